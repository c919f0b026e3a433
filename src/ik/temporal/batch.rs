//! The entry points of a gaze motion's update — one character, a batch of up to
//! [`BATCH_LANES`], or a batch the crowd has already checked — their checks, and the choice
//! of the lane width a batch runs at.

use glam::Vec4;

use super::config::GazeConfig;
use super::input::GazeInput;
use super::update::UpdateGroups;
use super::{GazeMotion, BATCH_LANES};
use crate::error::{ensure_all_finite, ensure_finite, Error, Result};
use crate::ik::chain::GazeChain;
use crate::ik::spatial::{self, Prepared};
use crate::math::random::Random;
use crate::math::wide::{run_widest, LaneJob};

impl GazeMotion {
    /// Advances the motion by `input.dt` and computes this frame's deltas.
    ///
    /// `random` is the character's own seeded stream (e.g.
    /// `stream(seed, Purpose::GazeTiming, character_index)`): it draws `t_d` when a target is
    /// dropped. Allocates nothing. To update a crowd, [`GazeMotion::update_batch`] does the
    /// same for several characters at once, faster.
    ///
    /// Errors (the motion is left unchanged): [`Error::InvalidArgument`] if `chain` has a
    /// different joint count than the one the motion was made for, `input.base` is not one
    /// rotation per joint, `dt < 0`, the interest ratio is ≤ 0, or `config` is out of range;
    /// [`Error::NonFinite`] for a NaN or infinite input.
    pub fn update(
        &mut self,
        chain: &GazeChain,
        config: &GazeConfig,
        input: &GazeInput<'_>,
        random: &mut Random,
    ) -> Result<()> {
        let [result] = GazeMotion::update_batch([self], [chain], config, [input], [random]);
        result
    }

    /// [`GazeMotion::update`] for `N` characters at once, `1 ≤ N ≤ BATCH_LANES` (each with its
    /// own chain, input and random stream): the same results as `N` separate calls, computed
    /// together, one character per SIMD lane, in lane groups of the processor's width (16
    /// with AVX-512F, 8 with AVX, else 4; four for `N ≤ 4`, one for `N = 1`) — a lane
    /// group costs about as much as one character.
    /// Each character's result is independent: one failing leaves only its motion unchanged.
    ///
    /// A crowd updates its characters in chunks of [`BATCH_LANES`] (and the last few with a
    /// smaller `N`).
    pub fn update_batch<const N: usize>(
        motions: [&mut GazeMotion; N],
        chains: [&GazeChain; N],
        config: &GazeConfig,
        inputs: [&GazeInput<'_>; N],
        randoms: [&mut Random; N],
    ) -> [Result<()>; N] {
        const {
            assert!(
                N >= 1 && N <= BATCH_LANES,
                "1 to BATCH_LANES characters per batch"
            )
        };
        if let Err(error) = config.validate() {
            return std::array::from_fn(|_| Err(error.clone()));
        }
        let results: [Result<()>; N] =
            std::array::from_fn(|lane| motions[lane].check(chains[lane], inputs[lane]));
        let ok: [bool; N] = std::array::from_fn(|lane| results[lane].is_ok());
        if ok.contains(&true) {
            Self::update_checked(motions, chains, config, inputs, randoms, &ok);
        }
        results
    }

    /// [`update_batch`](Self::update_batch) for inputs known to pass its checks: the
    /// crowd's, whose every part was checked when it came in (its configuration when the
    /// crowd was made, poses, positions and targets when they were set). Debug builds
    /// check them again.
    pub(crate) fn update_batch_prechecked<const N: usize>(
        motions: [&mut GazeMotion; N],
        chains: [&GazeChain; N],
        config: &GazeConfig,
        inputs: [&GazeInput<'_>; N],
        randoms: [&mut Random; N],
    ) {
        debug_assert!(config.validate().is_ok());
        debug_assert!((0..N).all(|lane| motions[lane].check(chains[lane], inputs[lane]).is_ok()));
        Self::update_checked(motions, chains, config, inputs, randoms, &[true; N]);
    }

    /// [`update_batch`](Self::update_batch) once its checks are done: `ok[lane]` says which
    /// characters passed them (the others are left as they are).
    fn update_checked<const N: usize>(
        motions: [&mut GazeMotion; N],
        chains: [&GazeChain; N],
        config: &GazeConfig,
        inputs: [&GazeInput<'_>; N],
        randoms: [&mut Random; N],
        ok: &[bool; N],
    ) {
        let prepared = Prepared::new(&config.spatial);
        let (mut motions, mut randoms) = (motions, randoms);
        let groups = UpdateGroups {
            motions: &mut motions,
            chains: &chains,
            config,
            inputs: &inputs,
            randoms: &mut randoms,
            ok,
            prepared: &prepared,
        };
        if N == 1 {
            // One character: the one-lane (scalar) form of the same code.
            groups.run::<f32>();
        } else if N <= 4 {
            // A few characters: four lanes fill them at less cost than wider ones (the same
            // bits at every width).
            groups.run::<Vec4>();
        } else {
            run_widest(groups);
        }
    }

    fn check(&self, chain: &GazeChain, input: &GazeInput<'_>) -> Result<()> {
        if chain.joint_count() != self.joint_count as usize {
            return Err(Error::InvalidArgument(format!(
                "this gaze motion was made for a chain of {} joints, not {}",
                self.joint_count,
                chain.joint_count()
            )));
        }
        if input.base.len() != chain.joint_count() {
            return Err(Error::InvalidArgument(format!(
                "base holds {} rotations, the chain has {} joints",
                input.base.len(),
                chain.joint_count()
            )));
        }
        spatial::check_pose(chain, &input.character, input.base, "base")?;
        ensure_finite(input.dt, "dt")?;
        if input.dt < 0.0 {
            return Err(Error::InvalidArgument(format!(
                "dt is {}, must be ≥ 0",
                input.dt
            )));
        }
        if let Some(request) = &input.request {
            ensure_all_finite(&request.head_target.to_array(), "head_target")?;
            ensure_all_finite(&request.eye_target.to_array(), "eye_target")?;
            ensure_finite(request.interest_ratio, "interest_ratio")?;
            if request.interest_ratio <= 0.0 {
                return Err(Error::InvalidArgument(format!(
                    "interest_ratio is {}, must be in (0, 1]",
                    request.interest_ratio
                )));
            }
        }
        Ok(())
    }
}
