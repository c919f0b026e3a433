//! Reordering flat arrays in place by a permutation, allocating nothing: how the crowd
//! keeps its entities and characters stored in spatial order (see
//! [`Scene::reorder`](super::Scene::reorder)).
//!
//! A permutation is given as `order`, the old index of each new position: after
//! [`Reorder::apply`], `values[i]` holds what `values[order[i]]` held before. Each array is
//! permuted by swaps along the permutation's cycles, at most one swap per element; which
//! positions are settled is a bit set sized at creation.

/// Scratch space for reordering arrays of up to a fixed length.
#[derive(Debug, Clone)]
pub struct Reorder {
    /// One bit per position: set once the position holds its new value.
    settled: Vec<u64>,
}

impl Reorder {
    /// Scratch space for arrays of up to `capacity` elements; `what` names the caller's
    /// numbers `capacity` comes from, for
    /// [`Error::OutOfMemory`](crate::error::Error::OutOfMemory).
    pub fn new(capacity: usize, what: &dyn std::fmt::Display) -> crate::error::Result<Reorder> {
        Ok(Reorder {
            settled: crate::alloc::try_vec(capacity.div_ceil(64), 0, what)?,
        })
    }

    /// Permutes `values` so that `values[i]` becomes the old `values[order[i]]`.
    ///
    /// `order` must be a permutation of `0..values.len()` and `values` at most the capacity
    /// long; otherwise this panics (an index out of range) or leaves `values` in some other
    /// order, never reading or writing out of bounds.
    pub fn apply<T>(&mut self, values: &mut [T], order: &[u32]) {
        assert!(
            order.len() == values.len() && values.len() <= self.settled.len() * 64,
            "an order of {} for {} values (room for {})",
            order.len(),
            values.len(),
            self.settled.len() * 64
        );
        let words = values.len().div_ceil(64);
        self.settled[..words].fill(0);
        for start in 0..values.len() {
            if self.is_settled(start) {
                continue;
            }
            // Walk the cycle through `start`: each position takes its value from the next
            // one, which then holds the value the walk carries on with.
            let mut position = start;
            loop {
                self.settle(position);
                let source = order[position] as usize;
                if source == start || self.is_settled(source) {
                    // Back at the start (or, for an `order` that is no permutation, at a
                    // settled position: stop rather than loop).
                    break;
                }
                values.swap(position, source);
                position = source;
            }
        }
    }

    /// Turns `order` (a permutation: the old index of each new position) into its inverse
    /// (the new position of each old index), in place.
    ///
    /// `order` must be a permutation of `0..order.len()` within the capacity: otherwise this
    /// panics or leaves some other values, never indexing out of bounds.
    pub fn invert(&mut self, order: &mut [u32]) {
        assert!(
            order.len() <= self.settled.len() * 64,
            "an order beyond the capacity"
        );
        self.settled[..order.len().div_ceil(64)].fill(0);
        for start in 0..order.len() {
            if self.is_settled(start) {
                continue;
            }
            // Along the cycle start → order[start] → …, each index learns the one before.
            let (mut previous, mut current) = (start, order[start] as usize);
            while current != start && current < order.len() && !self.is_settled(current) {
                let next = order[current] as usize;
                order[current] = previous as u32;
                self.settle(current);
                (previous, current) = (current, next);
            }
            order[start] = previous as u32;
            self.settle(start);
        }
    }

    /// True if `order` lists each of `0..order.len()` once (and fits the capacity).
    pub fn is_permutation(&mut self, order: &[u32]) -> bool {
        if order.len() > self.settled.len() * 64 {
            return false;
        }
        self.settled[..order.len().div_ceil(64)].fill(0);
        for &old in order {
            let old = old as usize;
            if old >= order.len() || self.is_settled(old) {
                return false;
            }
            self.settle(old);
        }
        true
    }

    fn is_settled(&self, position: usize) -> bool {
        self.settled[position / 64] & (1 << (position % 64)) != 0
    }

    fn settle(&mut self, position: usize) {
        self.settled[position / 64] |= 1 << (position % 64);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::Random;

    #[test]
    fn applies_every_permutation_of_four() {
        let mut reorder = Reorder::new(4, &"test").unwrap();
        let mut order = [0u32, 1, 2, 3];
        // Heap's algorithm over all 24 orders.
        fn visit(k: usize, order: &mut [u32; 4], reorder: &mut Reorder, seen: &mut usize) {
            if k == 1 {
                let mut values = ['a', 'b', 'c', 'd'];
                reorder.apply(&mut values, order);
                let expected = order.map(|old| ['a', 'b', 'c', 'd'][old as usize]);
                assert_eq!(values, expected, "order {order:?}");
                *seen += 1;
                return;
            }
            for i in 0..k {
                visit(k - 1, order, reorder, seen);
                if k.is_multiple_of(2) {
                    order.swap(i, k - 1);
                } else {
                    order.swap(0, k - 1);
                }
            }
        }
        let mut seen = 0;
        visit(4, &mut order, &mut reorder, &mut seen);
        assert_eq!(seen, 24);
    }

    #[test]
    fn applies_large_random_permutations_and_is_reusable() {
        let mut random = Random::new(11);
        let mut reorder = Reorder::new(1000, &"test").unwrap();
        for len in [0usize, 1, 63, 64, 65, 1000] {
            let mut order: Vec<u32> = (0..len as u32).collect();
            for i in (1..len).rev() {
                let j = random.below(i as u32 + 1) as usize;
                order.swap(i, j);
            }
            let mut values: Vec<u64> = (0..len as u64).map(|v| v * 7 + 3).collect();
            reorder.apply(&mut values, &order);
            for (value, &old) in values.iter().zip(&order) {
                assert_eq!(*value, old as u64 * 7 + 3);
            }
        }
    }

    #[test]
    fn an_order_that_is_no_permutation_ends_without_going_out_of_bounds() {
        let mut reorder = Reorder::new(3, &"test").unwrap();
        let mut values = [10, 20, 30];
        reorder.apply(&mut values, &[1, 2, 1]);
        let mut sorted = values;
        sorted.sort();
        assert_eq!(sorted, [10, 20, 30], "swaps only move values");
    }

    #[test]
    fn inverts_permutations_in_place() {
        let mut random = Random::new(5);
        let mut reorder = Reorder::new(300, &"test").unwrap();
        for len in [0usize, 1, 2, 64, 300] {
            let mut order: Vec<u32> = (0..len as u32).collect();
            for i in (1..len).rev() {
                order.swap(i, random.below(i as u32 + 1) as usize);
            }
            let mut inverse = order.clone();
            reorder.invert(&mut inverse);
            for (new, &old) in order.iter().enumerate() {
                assert_eq!(inverse[old as usize], new as u32);
            }
        }
    }

    #[test]
    fn tells_permutations_apart() {
        let mut reorder = Reorder::new(4, &"test").unwrap();
        assert!(reorder.is_permutation(&[2, 0, 3, 1]));
        assert!(reorder.is_permutation(&[]));
        assert!(!reorder.is_permutation(&[2, 0, 2, 1]));
        assert!(!reorder.is_permutation(&[0, 4]));
        let beyond: Vec<u32> = (0..65).collect();
        assert!(
            !reorder.is_permutation(&beyond),
            "beyond the capacity (rounded up to 64)"
        );
    }

    #[test]
    #[should_panic(expected = "an order of 2 for 3 values")]
    fn a_short_order_panics() {
        Reorder::new(3, &"test")
            .unwrap()
            .apply(&mut [1, 2, 3], &[0, 1]);
    }
}
