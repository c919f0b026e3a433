//! Unit tests of the parent module.

use super::*;

fn values(lanes: usize, offset: f32) -> Vec<f32> {
    (0..lanes)
        .map(|i| (i as f32 * 0.37 + offset).sin() * 3.0)
        .collect()
}

/// Every operation of a wide type equals the scalar operation in each lane.
fn lane_wise<W: Wide>() {
    let (a, b) = (values(W::LANES, 0.1), values(W::LANES, 1.3));
    let (wa, wb) = (W::from_fn(|i| a[i]), W::from_fn(|i| b[i]));
    let check = |w: W, f: &dyn Fn(f32, f32) -> f32| {
        for i in 0..W::LANES {
            assert_eq!(w.lane(i).to_bits(), f(a[i], b[i]).to_bits(), "lane {i}");
        }
    };
    check(wa + wb, &|x, y| x + y);
    check(wa - wb, &|x, y| x - y);
    check(wa * wb, &|x, y| x * y);
    check(wa * 2.5, &|x, _| x * 2.5);
    check(wa + 2.5, &|x, _| x + 2.5);
    check(wa - 2.5, &|x, _| x - 2.5);
    check(wa / wb, &|x, y| x / y);
    check(-wa, &|x, _| -x);
    check(wa.max(wb), &|x, y| if x > y { x } else { y });
    check((wa * wa).sqrt(), &|x, _| (x * x).sqrt());
    check(wb.recip(), &|_, y| 1.0 / y);
    check(W::splat(0.25), &|_, _| 0.25);
    let less = wa.cmplt(wb);
    check(W::select(less, wa, wb), &|x, y| if x < y { x } else { y });
    check(W::select(!less, wa, wb), &|x, y| if x < y { y } else { x });
    for i in 0..W::LANES {
        assert_eq!(W::test(less, i), a[i] < b[i]);
        assert_eq!(W::test(wa.cmple(wb), i), a[i] <= b[i]);
        assert_eq!(W::test(wa.cmpgt(wb), i), a[i] > b[i]);
        assert_eq!(W::test(wa.cmpge(wb), i), a[i] >= b[i]);
        assert!(!W::test(less & !less, i));
        assert!(W::test(less | !less, i));
    }
    let none = W::mask_from_fn(|_| false);
    let last = W::mask_from_fn(|i| i == W::LANES - 1);
    assert!(!W::any(none) && W::any(last) && (W::LANES == 1 || !W::all(last)));
    assert!(W::all(!none));
    check(W::load(&a), &|x, _| x);
    check(wa.min(wb), &|x, y| x.min(y));
    check(wa.abs(), &|x, _| x.abs());
    for i in 0..W::LANES {
        assert!(W::test(wa.cmpeq(wa), i));
        assert_eq!(W::test(wa.cmpeq(wb), i), a[i] == b[i]);
        assert!(W::test(W::mask_splat(true), i) && !W::test(W::mask_splat(false), i));
    }
    check(clamp(wa, -1.0, 1.0), &|x, _| x.clamp(-1.0, 1.0));
    assert_eq!(wa.reduce_max(), a.iter().copied().fold(f32::MIN, f32::max));
    for i in 0..W::LANES {
        assert_eq!(W::lane_numbers().lane(i), i as f32);
    }
    for top in 0..W::LANES {
        // The largest value in each lane in turn.
        let lifted = W::select(W::mask_from_fn(|i| i == top), W::splat(9.0), wb);
        assert_eq!(lifted.reduce_max(), 9.0, "lane {top}");
    }
    let mut stored = vec![f32::NAN; W::LANES + 1];
    wa.store(&mut stored);
    assert_eq!(&stored[..W::LANES], &a[..]);
    assert!(stored[W::LANES].is_nan(), "wrote past LANES floats");
    let wholes: Vec<f32> = (0..W::LANES)
        .map(|i| ((i * 17) % 254) as f32 - 126.0)
        .collect();
    let powers = W::load(&wholes).exp2_whole();
    for (i, whole) in wholes.iter().enumerate() {
        assert_eq!(powers.lane(i), 2f32.powi(*whole as i32), "2^{whole}");
    }
    // Integers carried as float bits (NaN patterns among them) move unchanged.
    let index_bits: Vec<f32> = (0..W::LANES)
        .map(|i| f32::from_bits((u32::MAX - 1).wrapping_add(i as u32)))
        .collect();
    let indices = W::load(&index_bits);
    for i in 0..W::LANES {
        assert_eq!(
            indices.lane(i).to_bits(),
            (u32::MAX - 1).wrapping_add(i as u32)
        );
        assert!(!W::test(W::first_lanes(i), i));
        assert!(W::test(W::first_lanes(i + 1), i));
        assert!(W::all(W::first_lanes(W::LANES + i)));
    }
    // Compress every mask of the first lanes' patterns (all of them up to 8 lanes).
    for pattern in 0..(1u32 << W::LANES.min(8)) {
        let bits = pattern | (pattern << 8) & ((1u64 << W::LANES) - 1) as u32;
        let mask = W::mask_from_fn(|i| bits >> i & 1 != 0);
        assert_eq!(W::bitmask(mask), bits);
        let mut out = vec![f32::NAN; W::LANES + 1];
        indices.compress_store(mask, &mut out);
        let kept: Vec<u32> = (0..W::LANES as u32)
            .filter(|i| bits >> i & 1 != 0)
            .map(|i| (u32::MAX - 1).wrapping_add(i))
            .collect();
        let stored: Vec<u32> = out[..kept.len()].iter().map(|x| x.to_bits()).collect();
        assert_eq!(stored, kept, "mask {bits:b}");
        assert!(out[W::LANES].is_nan(), "wrote past LANES floats");
    }
    let columns: Vec<[f32; 8]> = (0..W::LANES)
        .map(|i| std::array::from_fn(|c| (i * 8 + c) as f32))
        .collect();
    let rows = W::transpose_in(|i| columns[i]);
    for (c, row) in rows.iter().enumerate() {
        for (i, column) in columns.iter().enumerate() {
            assert_eq!(row.lane(i), column[c]);
        }
    }
    let mut seen = vec![[0.0; 8]; W::LANES];
    W::transpose_out(rows, |i, column| seen[i] = column);
    assert_eq!(seen, columns);
}

#[test]
fn every_width_is_lane_wise_ieee() {
    for_every_width!(lane_wise());
}

#[test]
fn the_widest_width_the_processor_has_is_used() {
    #[cfg(target_arch = "x86_64")]
    let popcnt = std::is_x86_feature_detected!("popcnt");
    #[cfg(target_arch = "x86_64")]
    let expected = if popcnt && std::is_x86_feature_detected!("avx512f") {
        16
    } else if popcnt && std::is_x86_feature_detected!("avx") {
        8
    } else {
        4
    };
    #[cfg(not(target_arch = "x86_64"))]
    let expected = 4;
    assert_eq!(widest_lanes(), expected);
    assert_eq!(crate::blend::simd_lanes(), expected);
}
