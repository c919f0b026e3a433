//! Seeded random numbers: every random choice in crowdgaze comes from here, so the same seed
//! gives the same crowd whatever the thread count or call order.
//!
//! [`stream`] derives an independent generator from `(seed, purpose, index)` — e.g. one per
//! character for its weights — so a character's draws do not depend on the others'.
//! The generator is SplitMix64 (Steele, Lea & Flood 2014): tiny state, good enough
//! statistics for animation choices, and no dependency.

/// A SplitMix64 generator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Random {
    state: u64,
}

/// What a random stream is used for; mixed into the seed so streams never coincide.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u64)]
pub enum Purpose {
    /// A character's attention parameters (weights, attention percentage).
    CharacterParams = 1,
    /// A character's gaze timing draws (deactivation times).
    GazeTiming = 2,
    /// A character's saliency random picks.
    Saliency = 3,
    /// Scene generation in demos and tests.
    Scene = 4,
    /// The stock baseline's random glances.
    Baseline = 5,
    /// A character's blinks (rate, intervals, durations, gaze-evoked draws).
    Blinks = 6,
    /// A conversation member's glances (lengths, whom, where away).
    Conversation = 7,
}

/// The generator for `(seed, purpose, index)`.
pub fn stream(seed: u64, purpose: Purpose, index: u64) -> Random {
    let mut mixer = Random::new(seed ^ (purpose as u64).wrapping_mul(0xA076_1D64_78BD_642F));
    let first = mixer.next_u64();
    Random::new(first ^ index.wrapping_mul(0xE703_7ED1_A0B4_28DB))
}

impl Random {
    /// A generator starting from `seed`.
    pub fn new(seed: u64) -> Random {
        Random { state: seed }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A uniform float in [0, 1).
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
    }

    /// A uniform float in [low, high) (`low` if the range is empty).
    pub fn range(&mut self, low: f32, high: f32) -> f32 {
        if high <= low {
            return low;
        }
        low + (high - low) * self.next_f32()
    }

    /// A uniform integer in [0, n) (0 if n is 0).
    pub fn below(&mut self, n: u32) -> u32 {
        (((self.next_u64() >> 32) * u64::from(n)) >> 32) as u32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_seed_same_numbers_and_streams_differ() {
        let mut a = stream(7, Purpose::CharacterParams, 3);
        let mut b = stream(7, Purpose::CharacterParams, 3);
        let mut c = stream(7, Purpose::CharacterParams, 4);
        let mut d = stream(7, Purpose::GazeTiming, 3);
        let (x, y, z, w) = (a.next_u64(), b.next_u64(), c.next_u64(), d.next_u64());
        assert_eq!(x, y);
        assert_ne!(x, z);
        assert_ne!(x, w);
    }

    #[test]
    fn uniform_floats_cover_the_unit_interval() {
        let mut random = Random::new(1);
        let draws: Vec<f32> = (0..100_000).map(|_| random.next_f32()).collect();
        assert!(draws.iter().all(|v| (0.0..1.0).contains(v)));
        let mean = draws.iter().sum::<f32>() / draws.len() as f32;
        assert!((mean - 0.5).abs() < 0.005, "mean {mean}");
        let below: Vec<u32> = (0..10_000).map(|_| random.below(4)).collect();
        for k in 0..4 {
            let share = below.iter().filter(|v| **v == k).count() as f32 / 10_000.0;
            assert!((share - 0.25).abs() < 0.02, "{k}: {share}");
        }
    }
}
