//! The runtime dispatch: which width the processor supports, and a [`LaneJob`] run at that
//! width, compiled for its instruction set (and, for tests, a function run at every width).

use super::Wide;
#[cfg(target_arch = "x86_64")]
use super::{avx::F8, avx512::F16};
use glam::Vec4;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Work written once for any lane width: [`run_widest`] runs it at the widest width the
/// processor offers, compiled for that instruction set.
pub(crate) trait LaneJob {
    /// What the job returns.
    type Output;
    /// The job at width `W`. Implementations mark it `#[inline(always)]`, and everything it
    /// calls too, so that it is compiled inside the instruction-set-specific caller (a call
    /// left out of line is compiled without AVX and is slow).
    fn run<W: Wide>(self) -> Self::Output;
}

/// Runs `job` with 16 lanes where the processor has AVX-512F, 8 with AVX, else 4 (glam's
/// `Vec4`: SSE2 on x86-64, NEON on AArch64, plain floats elsewhere). Results are the same bits
/// at every width. The wide forms are also compiled with POPCNT (every processor with AVX
/// has it): counting a mask's lanes is then one instruction rather than fifteen, and a
/// search's batch length waits on that count.
/// No wider than [`set_max_simd_lanes`] allows.
#[inline]
pub(crate) fn run_widest<J: LaneJob>(job: J) -> J::Output {
    let max_lanes = MAX_LANES.load(Ordering::Relaxed);
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("popcnt") {
        if max_lanes >= 16 && std::is_x86_feature_detected!("avx512f") {
            // SAFETY: the processor has AVX-512F and POPCNT, checked just above.
            return unsafe { run_avx512(job) };
        }
        if max_lanes >= 8 && std::is_x86_feature_detected!("avx") {
            // SAFETY: the processor has AVX and POPCNT, checked just above.
            return unsafe { run_avx(job) };
        }
    }
    if max_lanes < 4 {
        return job.run::<f32>();
    }
    job.run::<Vec4>()
}

/// The widest lanes [`run_widest`] may use (see [`set_max_simd_lanes`]).
static MAX_LANES: AtomicUsize = AtomicUsize::new(usize::MAX);

/// Limits the SIMD width of every later step in this process to at most `lanes` lanes: 16
/// (AVX-512F, the default where the processor has it), 8 (AVX), 4 (SSE2 or NEON) or 1 (plain
/// floats, for any smaller value). Results are the same bits at every width: this exists to
/// check that, and to rule the wide paths out when debugging. Safe to call at any time from
/// any thread; a step under way may use either width for its remaining batches.
pub fn set_max_simd_lanes(lanes: usize) {
    MAX_LANES.store(lanes, Ordering::Relaxed);
}

/// How many lanes [`run_widest`] runs with on this processor.
pub(crate) fn widest_lanes() -> usize {
    struct Lanes;
    impl LaneJob for Lanes {
        type Output = usize;
        #[inline(always)]
        fn run<W: Wide>(self) -> usize {
            W::LANES
        }
    }
    run_widest(Lanes)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,popcnt")]
fn run_avx512<J: LaneJob>(job: J) -> J::Output {
    job.run::<F16>()
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,popcnt")]
fn run_avx<J: LaneJob>(job: J) -> J::Output {
    job.run::<F8>()
}

/// Runs a generic test function `f::<W>()` for every width this processor can run (the wider
/// ones only where the processor has AVX or AVX-512F, as under valgrind it may not).
#[cfg(test)]
macro_rules! for_every_width {
    ($f:ident ( $($arg:expr),* )) => {{
        $f::<f32>($($arg),*);
        $f::<glam::Vec4>($($arg),*);
        #[cfg(target_arch = "x86_64")]
        {
            if std::is_x86_feature_detected!("avx") {
                $f::<$crate::math::wide::F8>($($arg),*);
            }
            if std::is_x86_feature_detected!("avx512f") {
                $f::<$crate::math::wide::F16>($($arg),*);
            }
        }
    }};
}
#[cfg(test)]
pub(crate) use for_every_width;
