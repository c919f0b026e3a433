//! The one-character entry points, [`solve`] and [`eye_rays`], and the checks of a pose and
//! character transform they and the gaze motion share.

use glam::{Quat, Vec3, Vec4};

use super::body::{solve_bodies, BodyLane, SpatialSolution};
use super::config::{Prepared, SpatialConfig};
use super::eyes::{eye_rays_unchecked, EyeFrames, EyeRays};
use super::frames::head_frame;
use super::TurnSide;
use crate::error::{ensure_all_finite, ensure_finite, Error, Result};
use crate::ik::chain::{GazeChain, MAX_BODY_JOINTS};
use crate::ik::CharacterTransform;
use crate::math::lanes::{Floats, MAX_LANES, Q4, V3};

/// Solves one posture: writes the delta rotation of every chain joint into
/// `deltas[..chain.joint_count()]` so that the body aims at `head_target` and the eyes
/// converge on `eye_target` (world positions, metres).
///
/// `base` holds the base local rotation of each chain joint (rest or animated pose, unit
/// quaternions); the final local rotation of joint `i` is `base[i] * deltas[i]`. `side` is
/// the character's remembered [`TurnSide`] (start with [`TurnSide::UNDECIDED`]).
///
/// Errors: [`Error::InvalidArgument`] if `base` or `deltas` is shorter than the chain or
/// `config` is out of range, [`Error::NonFinite`] for a NaN or infinite input.
#[allow(clippy::too_many_arguments)]
pub fn solve(
    chain: &GazeChain,
    config: &SpatialConfig,
    character: &CharacterTransform,
    base: &[Quat],
    head_target: Vec3,
    eye_target: Vec3,
    side: &mut TurnSide,
    deltas: &mut [Quat],
) -> Result<SpatialSolution> {
    config.validate()?;
    check_pose(chain, character, base, "base")?;
    if deltas.len() < chain.joint_count() {
        return Err(Error::InvalidArgument(format!(
            "deltas holds {} rotations, the chain has {} joints",
            deltas.len(),
            chain.joint_count()
        )));
    }
    ensure_all_finite(&head_target.to_array(), "head_target")?;
    ensure_all_finite(&eye_target.to_array(), "eye_target")?;
    let prepared = Prepared::new(config);
    // One character: the narrowest lanes do (every width gives the same bits).
    let mut goals = [Q4::<Vec4>::identity(); MAX_BODY_JOINTS];
    let mut lanes = [None; MAX_LANES];
    lanes[0] = Some(BodyLane {
        chain,
        character,
        base,
        head_target,
        side: *side,
    });
    let ([solved, ..], heads) = solve_bodies(&prepared, lanes, &mut goals);
    let (solution, new_side) = solved.ok_or_else(|| Error::Internal("empty solve".into()))?;
    *side = new_side;
    let body = chain.body_count();
    for (delta, goal) in deltas[..body].iter_mut().zip(&goals) {
        *delta = goal.lane(0);
    }
    if chain.has_eyes() {
        let chains = [chain; MAX_LANES];
        let bases = [base; MAX_LANES];
        let target = V3::splat(eye_target.into());
        let side_sign = Floats::splat(side.resolved());
        for eye in 0..2 {
            let frames = EyeFrames::new(&chains, &bases, &heads, eye);
            deltas[frames.index[0]] = frames.goal(&chains, &prepared, target, side_sign).lane(0);
        }
    }
    Ok(solution)
}

/// The eyes' world positions and gaze directions for the pose `base[i] * deltas[i]`.
///
/// Errors: as [`solve`].
pub fn eye_rays(
    chain: &GazeChain,
    character: &CharacterTransform,
    base: &[Quat],
    deltas: &[Quat],
) -> Result<EyeRays> {
    check_pose(chain, character, base, "base")?;
    check_pose(chain, character, deltas, "deltas")?;
    let head = head_frame(chain, character, base, deltas);
    Ok(eye_rays_unchecked(chain, &head, base, deltas))
}

/// Checks a slice of joint rotations against the chain, and the character transform.
pub(crate) fn check_pose(
    chain: &GazeChain,
    character: &CharacterTransform,
    rotations: &[Quat],
    what: &str,
) -> Result<()> {
    if rotations.len() < chain.joint_count() {
        return Err(Error::InvalidArgument(format!(
            "{what} holds {} rotations, the chain has {} joints",
            rotations.len(),
            chain.joint_count()
        )));
    }
    for rotation in &rotations[..chain.joint_count()] {
        if !rotation.is_finite() {
            return Err(Error::NonFinite(format!("{what} contains {rotation:?}")));
        }
    }
    ensure_all_finite(&character.position.to_array(), "character position")?;
    ensure_all_finite(&character.rotation.to_array(), "character rotation")?;
    ensure_finite(character.rotation.length() - 1.0, "character rotation")?;
    Ok(())
}
