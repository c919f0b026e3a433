//! The view blender: view-adaptive animation (Chaudhuri, Papagiannakis & Magnenat-Thalmann,
//! §3). Key animations `P^k(t)`, key cameras `v^k` on the unit sphere around the character
//! (moving with it), the view weights of equation 2 and the blended pose of equation 3:
//! `P(t) = BLEND_k(P^k(t), w^k)`, with DLB or DIB per joint.
//!
//! # Frames and units
//! The *character transform* is the rigid transform (rotation + translation) placing the
//! character in the world; key camera directions are given in the character's own frame.
//! The viewer's position is in the world. Positions may be in any length unit (the caller's:
//! metres, centimetres, ...), the same for both: only directions are used, so the unit only
//! matters for telling a viewer *at* the character's centre, which has no direction.
//!
//! # Weights (equation 2)
//! `v_c` is the viewer's direction in the character's frame, projected on the unit sphere.
//! With `D_c = D(v_c, v_c')` for each key camera `c` (geodesic: the angle between them;
//! chordal: `|v_c − v_c'|`, the straight line through the sphere), key `k` gets
//! `w_k = Σ_{c → k} D_c^−α / Σ_c D_c^−α` (summed over the cameras mapped to it; many cameras
//! may map to one key). A viewer within [`AT_KEY_CAMERA`] of a key camera gets that camera's
//! key alone (shared equally if several cameras are that close): no division by zero, and
//! continuous, since the other weights there are below `(10⁻⁶ / D)^α`.

use glam::{DVec3, Vec3};

use super::aligned_sum::dlb_by;
use super::clip::{FramePair, KeyClip};
use super::iterative::dib_joints;
use super::settings::{DibSettings, PoseOutcome};
use super::AsDualQuat;
use crate::alloc::{try_reserve, try_vec, Field};
use crate::error::{Error, Result};
use crate::math::dualquat::DualQuat;

/// Most key animations a blender can have (their weights and samples live on the stack
/// during `weights` and `evaluate`, which allocate nothing).
pub const MAX_KEYS: usize = 32;

/// Most joints a pose can have.
pub const MAX_JOINTS: usize = 1 << 16;

/// Distance (radians, geodesic; or chord length on the unit sphere) below which the viewer is
/// *on* a key camera and gets that camera's key alone.
pub const AT_KEY_CAMERA: f64 = 1e-6;

/// The viewer is at the character's centre, with no direction, when its distance from the
/// character's position is at most `AT_CENTRE · max(1, |viewer|, |position|)` (caller units):
/// an absolute 10⁻⁶ near the origin, relative far from it.
pub const AT_CENTRE: f64 = 1e-6;

/// Smallest exponent α of equation 2.
pub const MIN_ALPHA: f32 = 2.0;
/// Largest exponent α of equation 2.
pub const MAX_ALPHA: f32 = 4.0;

/// How the distance `D` between the viewer's direction and a key camera is measured on the
/// unit sphere.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ViewDistance {
    /// The great-circle angle, in radians (0 to π). The default: it is the distance on the
    /// sphere itself.
    #[default]
    Geodesic,
    /// The Euclidean chord `|v_c − v_k|` (0 to 2), the paper's cheaper approximation:
    /// `2 sin(geodesic / 2)`, the same near a camera, shorter far from it.
    Chordal,
}

impl ViewDistance {
    /// `D(a, b)` for unit vectors `a` and `b`.
    pub fn between(self, a: DVec3, b: DVec3) -> f64 {
        match self {
            // atan2 of |a × b| and a · b is accurate at every angle (acos is not near 0).
            ViewDistance::Geodesic => a.cross(b).length().atan2(a.dot(b)),
            ViewDistance::Chordal => (a - b).length(),
        }
    }
}

/// Which blend `BLEND_k` of equation 3 the view blender uses per joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BlendMethod {
    /// DLB, equation 4: closed form, the fastest. The default.
    #[default]
    Dlb,
    /// DIB, Algorithm 1: the exact screw-metric mean, iterated to `precision`.
    Dib,
}

/// A key camera `v^k`: a unit direction from the character, in the character's frame, and
/// the key animation it selects.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KeyCamera {
    /// Unit direction from the character's centre towards the camera, character frame.
    pub direction: DVec3,
    /// Index of the key animation this camera maps to.
    pub key: usize,
}

/// Settings of a view blender, fixed at creation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewBlenderConfig {
    /// Joints per pose, 1 to [`MAX_JOINTS`].
    pub joint_count: usize,
    /// Key animations `K`, 1 to [`MAX_KEYS`].
    pub key_count: usize,
    /// Exponent α of equation 2, in [2, 4]: lower spreads each key camera's influence wider,
    /// higher focuses it near the camera. Default 2.
    pub alpha: f32,
    /// How `D` is measured. Default geodesic.
    pub distance: ViewDistance,
    /// DLB or DIB per joint. Default DLB.
    pub method: BlendMethod,
    /// DIB's precision `p` (see [`DibSettings`]; in the caller's length unit for the
    /// translations). Default 1e−6.
    pub precision: f32,
    /// DIB's most updates per joint (see [`DibSettings`]). Default 16.
    pub max_iterations: u32,
}

impl ViewBlenderConfig {
    /// A config for `joint_count` joints and `key_count` keys, other fields at their defaults.
    pub fn new(joint_count: usize, key_count: usize) -> ViewBlenderConfig {
        let dib = DibSettings::default();
        ViewBlenderConfig {
            joint_count,
            key_count,
            alpha: MIN_ALPHA,
            distance: ViewDistance::default(),
            method: BlendMethod::default(),
            precision: dib.precision,
            max_iterations: dib.max_iterations,
        }
    }

    /// DIB's settings from this config.
    pub fn dib_settings(&self) -> DibSettings {
        DibSettings {
            precision: self.precision,
            max_iterations: self.max_iterations,
        }
    }

    /// Checks every field against its documented range.
    ///
    /// Errors: [`Error::InvalidArgument`] (a count or α out of range, precision `≤ 0`,
    /// too many iterations), [`Error::NonFinite`] (α or precision NaN or infinite).
    pub fn validate(&self) -> Result<()> {
        if self.joint_count == 0 || self.joint_count > MAX_JOINTS {
            return Err(Error::InvalidArgument(format!(
                "joint_count is {}, must be 1..={MAX_JOINTS}",
                self.joint_count
            )));
        }
        if self.key_count == 0 || self.key_count > MAX_KEYS {
            return Err(Error::InvalidArgument(format!(
                "key_count is {}, must be 1..={MAX_KEYS}",
                self.key_count
            )));
        }
        if !self.alpha.is_finite() {
            return Err(Error::NonFinite(format!("alpha is {}", self.alpha)));
        }
        if !(MIN_ALPHA..=MAX_ALPHA).contains(&self.alpha) {
            return Err(Error::InvalidArgument(format!(
                "alpha is {}, must be in [{MIN_ALPHA}, {MAX_ALPHA}]",
                self.alpha
            )));
        }
        self.dib_settings().validate()
    }
}

/// Blends key animations by where the viewer stands (see the module docs).
///
/// Built with [`ViewBlender::new`], given a clip or pose for every key
/// ([`ViewBlender::set_key_clip`], [`ViewBlender::set_key_pose`]) and key cameras
/// ([`ViewBlender::add_camera`]); then [`ViewBlender::weights`] and [`ViewBlender::evaluate`]
/// take `&self`, allocate nothing and may run concurrently.
#[derive(Debug, Clone)]
pub struct ViewBlender {
    config: ViewBlenderConfig,
    key_clips: Vec<Option<KeyClip>>,
    key_cameras: Vec<KeyCamera>,
}

impl ViewBlender {
    /// A blender with no clips and no cameras yet.
    ///
    /// Errors: see [`ViewBlenderConfig::validate`].
    pub fn new(config: ViewBlenderConfig) -> Result<ViewBlender> {
        config.validate()?;
        Ok(ViewBlender {
            config,
            key_clips: try_vec(
                config.key_count,
                None,
                &Field("key_count", config.key_count as u64),
            )?,
            key_cameras: Vec::new(),
        })
    }

    /// The settings the blender was created with.
    pub fn config(&self) -> &ViewBlenderConfig {
        &self.config
    }

    /// The key cameras, in the order they were added.
    pub fn key_cameras(&self) -> &[KeyCamera] {
        &self.key_cameras
    }

    /// The clip of key `key`, if set.
    pub fn key_clip(&self, key: usize) -> Option<&KeyClip> {
        self.key_clips.get(key).and_then(Option::as_ref)
    }

    /// Sets (or replaces) key animation `key`.
    ///
    /// Errors: [`Error::InvalidArgument`] if `key ≥ key_count` or the clip's joint count is
    /// not the blender's. Nothing changes on error.
    pub fn set_key_clip(&mut self, key: usize, clip: KeyClip) -> Result<()> {
        self.check_key(key)?;
        if clip.joint_count() != self.config.joint_count {
            return Err(Error::InvalidArgument(format!(
                "the clip has {} joints, the blender {}",
                clip.joint_count(),
                self.config.joint_count
            )));
        }
        self.key_clips[key] = Some(clip);
        Ok(())
    }

    /// Sets key `key` to a static pose of `joint_count` transforms.
    ///
    /// Errors: as [`ViewBlender::set_key_clip`] and [`KeyClip::pose`].
    pub fn set_key_pose<Q: AsDualQuat>(&mut self, key: usize, pose: &[Q]) -> Result<()> {
        self.check_key(key)?;
        if pose.len() != self.config.joint_count {
            return Err(Error::InvalidArgument(format!(
                "the pose has {} joints, the blender {}",
                pose.len(),
                self.config.joint_count
            )));
        }
        self.set_key_clip(key, KeyClip::pose(pose)?)
    }

    /// Adds a key camera in direction `direction` (character frame, any non-zero length)
    /// mapped to key `key`, and returns its index. Several cameras may map to one key.
    ///
    /// Errors: [`Error::InvalidArgument`] (`key ≥ key_count`, a zero direction),
    /// [`Error::NonFinite`] (a NaN or infinite component), [`Error::OutOfMemory`].
    pub fn add_camera(&mut self, direction: Vec3, key: usize) -> Result<usize> {
        self.check_key(key)?;
        if !direction.is_finite() {
            return Err(Error::NonFinite(format!("camera direction is {direction}")));
        }
        let direction = direction.as_dvec3();
        let length = direction.length();
        if length <= 1e-12 {
            return Err(Error::InvalidArgument(
                "camera direction has zero length".into(),
            ));
        }
        let cameras = Field("key cameras", self.key_cameras.len() as u64 + 1);
        try_reserve(&mut self.key_cameras, 1, &cameras)?;
        self.key_cameras.push(KeyCamera {
            direction: direction / length,
            key,
        });
        Ok(self.key_cameras.len() - 1)
    }

    fn check_key(&self, key: usize) -> Result<()> {
        if key >= self.config.key_count {
            return Err(Error::InvalidArgument(format!(
                "key {key} does not exist, the blender has {} keys",
                self.config.key_count
            )));
        }
        Ok(())
    }

    /// `v_c`: the unit direction from the character to the viewer, in the character's frame.
    ///
    /// `character` is the character's rigid transform in the world (normalised here);
    /// `viewer` the viewer's world position, same unit.
    ///
    /// Errors: [`Error::NonFinite`] (a NaN or infinite input), [`Error::InvalidArgument`]
    /// (the character transform has a zero rotation, or the viewer is at the character's
    /// centre, see [`AT_CENTRE`]).
    pub fn viewer_direction(character: DualQuat, viewer: Vec3) -> Result<DVec3> {
        if !character.is_finite() {
            return Err(Error::NonFinite("character transform is not finite".into()));
        }
        if !viewer.is_finite() {
            return Err(Error::NonFinite(format!("viewer position is {viewer}")));
        }
        let character = character.as_f64().try_normalize().ok_or_else(|| {
            Error::InvalidArgument("character transform has a zero rotation".into())
        })?;
        let position = character.translation();
        let viewer = viewer.as_dvec3();
        let offset = viewer - position;
        let distance = offset.length();
        let scale = 1.0f64.max(viewer.length()).max(position.length());
        if distance <= AT_CENTRE * scale {
            return Err(Error::InvalidArgument(format!(
                "the viewer is at the character's centre (distance {distance:.3e}): \
                 it has no direction"
            )));
        }
        Ok(character.real.conjugate() * (offset / distance))
    }

    /// The view weights `w_k` of equation 2 for a viewer at `viewer` looking at the character
    /// placed by `character`, into `out` (`key_count` long; convex: `≥ 0`, summing to 1).
    /// Allocates nothing.
    ///
    /// Errors: those of [`ViewBlender::viewer_direction`]; [`Error::InvalidArgument`] if
    /// `out.len() != key_count`; [`Error::WrongState`] if there is no key camera. Nothing is
    /// written on error.
    pub fn weights(&self, character: DualQuat, viewer: Vec3, out: &mut [f32]) -> Result<()> {
        if out.len() != self.config.key_count {
            return Err(Error::InvalidArgument(format!(
                "weights output holds {}, the blender has {} keys",
                out.len(),
                self.config.key_count
            )));
        }
        let mut weights = [0.0f64; MAX_KEYS];
        self.weights_into(character, viewer, &mut weights)?;
        for (slot, weight) in out.iter_mut().zip(weights) {
            *slot = weight as f32;
        }
        Ok(())
    }

    /// Equation 2 into `weights[..key_count]` (the rest stay 0).
    fn weights_into(
        &self,
        character: DualQuat,
        viewer: Vec3,
        weights: &mut [f64; MAX_KEYS],
    ) -> Result<()> {
        let view = Self::viewer_direction(character, viewer)?;
        if self.key_cameras.is_empty() {
            return Err(Error::WrongState(
                "the view blender has no key camera: add one first".into(),
            ));
        }
        let distance = self.config.distance;
        let nearest = self
            .key_cameras
            .iter()
            .map(|camera| distance.between(view, camera.direction))
            .fold(f64::INFINITY, f64::min);
        if nearest < AT_KEY_CAMERA {
            // On a key camera: its key alone (shared if several cameras are that close).
            for camera in &self.key_cameras {
                if distance.between(view, camera.direction) < AT_KEY_CAMERA {
                    weights[camera.key] += 1.0;
                }
            }
        } else {
            // D^−α scaled by nearest^α, so the largest term is 1 and nothing overflows.
            let alpha = f64::from(self.config.alpha);
            for camera in &self.key_cameras {
                let d = distance.between(view, camera.direction);
                weights[camera.key] += (nearest / d).powf(alpha);
            }
        }
        let total: f64 = weights.iter().sum();
        for weight in weights.iter_mut() {
            *weight /= total;
        }
        Ok(())
    }

    /// The blended pose `P(t)` (equation 3) into `out` (`joint_count` long): each key clip
    /// sampled at `time` seconds, then blended joint by joint with the view weights, by DLB
    /// or DIB as configured. Keys of weight 0 are skipped. Allocates nothing.
    ///
    /// With DIB, every joint is written even if some did not reach the precision; the
    /// outcome counts them (and [`PoseOutcome::into_result`] turns that into
    /// [`Error::NotConverged`]).
    ///
    /// Errors: those of [`ViewBlender::weights`]; [`Error::InvalidArgument`] if
    /// `out.len() != joint_count`; [`Error::NonFinite`] for a NaN or infinite time;
    /// [`Error::WrongState`] if a key has no clip or pose yet. Nothing is written on error.
    pub fn evaluate<O: From<DualQuat>>(
        &self,
        character: DualQuat,
        viewer: Vec3,
        time: f64,
        out: &mut [O],
    ) -> Result<PoseOutcome> {
        if out.len() != self.config.joint_count {
            return Err(Error::InvalidArgument(format!(
                "pose output holds {} joints, the blender has {}",
                out.len(),
                self.config.joint_count
            )));
        }
        if !time.is_finite() {
            return Err(Error::NonFinite(format!("time is {time}")));
        }
        if let Some(missing) = self.key_clips.iter().position(Option::is_none) {
            return Err(Error::WrongState(format!(
                "key {missing} has no clip or pose yet"
            )));
        }
        let mut weights = [0.0f64; MAX_KEYS];
        self.weights_into(character, viewer, &mut weights)?;

        // The keys that contribute, their weights and where `time` falls in their clips.
        let mut clips: [Option<&KeyClip>; MAX_KEYS] = [None; MAX_KEYS];
        let mut active_weights = [0.0f32; MAX_KEYS];
        let mut frames = [FramePair::default(); MAX_KEYS];
        let mut active = 0;
        for (clip, &weight) in self.key_clips.iter().zip(weights.iter()) {
            if let Some(clip) = clip.as_ref().filter(|_| weight > 0.0) {
                clips[active] = Some(clip);
                active_weights[active] = weight as f32;
                frames[active] = clip.frame_pair(time);
                active += 1;
            }
        }
        let active_weights = &active_weights[..active];
        let inverse_total = 1.0 / active_weights.iter().map(|&w| f64::from(w)).sum::<f64>();
        let settings = self.config.dib_settings();

        let sample = |k: usize, joint: usize| match clips[k] {
            Some(clip) => clip.joint_at(frames[k], joint),
            None => DualQuat::IDENTITY,
        };
        let mut outcome = PoseOutcome::default();
        match self.config.method {
            BlendMethod::Dlb => {
                for (joint, slot) in out.iter_mut().enumerate() {
                    outcome.joints += 1;
                    *slot = dlb_by(active_weights, |k| sample(k, joint)).into();
                }
            }
            BlendMethod::Dib => dib_joints(
                active_weights,
                inverse_total,
                &settings,
                self.config.joint_count,
                sample,
                |joint, joint_outcome| {
                    outcome.add(joint_outcome);
                    out[joint] = joint_outcome.blend.into();
                },
            ),
        }
        Ok(outcome)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;
    use std::f32::consts::FRAC_PI_2;

    fn blender(alpha: f32, distance: ViewDistance) -> ViewBlender {
        let mut config = ViewBlenderConfig::new(1, 3);
        config.alpha = alpha;
        config.distance = distance;
        let mut blender = ViewBlender::new(config).unwrap();
        blender.add_camera(Vec3::X, 0).unwrap();
        blender.add_camera(Vec3::Z, 1).unwrap();
        blender.add_camera(-Vec3::X, 2).unwrap();
        blender
    }

    #[test]
    fn distances() {
        let a = DVec3::X;
        let b = DVec3::Y;
        assert!((ViewDistance::Geodesic.between(a, b) - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        assert!((ViewDistance::Chordal.between(a, b) - 2f64.sqrt()).abs() < 1e-12);
        assert!(ViewDistance::Geodesic.between(a, a) == 0.0);
        assert!((ViewDistance::Geodesic.between(a, -a) - std::f64::consts::PI).abs() < 1e-12);
    }

    #[test]
    fn the_viewer_direction_is_in_the_character_frame() {
        // Character at (10, 0, 0), turned 90° about y: its +z faces world +x.
        let character = DualQuat::from_rotation_translation(
            Quat::from_rotation_y(FRAC_PI_2),
            Vec3::new(10.0, 0.0, 0.0),
        );
        let direction =
            ViewBlender::viewer_direction(character, Vec3::new(13.0, 0.0, 0.0)).unwrap();
        assert!((direction - DVec3::Z).length() < 1e-6, "{direction}");
        assert!(matches!(
            ViewBlender::viewer_direction(character, Vec3::new(10.0, 0.0, 0.0)),
            Err(Error::InvalidArgument(_))
        ));
    }

    #[test]
    fn weights_follow_equation_2() {
        let blender = blender(2.0, ViewDistance::Geodesic);
        let mut w = [0.0f32; 3];
        // Halfway between +x and +z: D = π/4, 3π/4... keys 0 and 1 equal, key 2 smaller.
        let viewer = Vec3::new(1.0, 0.0, 1.0);
        blender.weights(DualQuat::IDENTITY, viewer, &mut w).unwrap();
        let d = [
            std::f64::consts::FRAC_PI_4,
            std::f64::consts::FRAC_PI_4,
            3.0 * std::f64::consts::FRAC_PI_4,
        ];
        let inv: Vec<f64> = d.iter().map(|d| d.powi(-2)).collect();
        let total: f64 = inv.iter().sum();
        for k in 0..3 {
            assert!((f64::from(w[k]) - inv[k] / total).abs() < 1e-6, "{w:?}");
        }
        assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-6);
    }

    #[test]
    fn a_viewer_on_a_key_camera_gets_that_key_alone() {
        let blender = blender(3.0, ViewDistance::Chordal);
        let mut w = [0.0f32; 3];
        blender
            .weights(DualQuat::IDENTITY, Vec3::new(0.0, 0.0, 5.0), &mut w)
            .unwrap();
        assert_eq!(w, [0.0, 1.0, 0.0]);
    }

    #[test]
    fn configs_are_checked() {
        assert!(ViewBlender::new(ViewBlenderConfig::new(0, 3)).is_err());
        assert!(ViewBlender::new(ViewBlenderConfig::new(3, 0)).is_err());
        assert!(ViewBlender::new(ViewBlenderConfig::new(3, MAX_KEYS + 1)).is_err());
        let mut config = ViewBlenderConfig::new(3, 3);
        config.alpha = 1.0;
        assert!(matches!(
            ViewBlender::new(config),
            Err(Error::InvalidArgument(_))
        ));
        config.alpha = f32::NAN;
        assert!(matches!(ViewBlender::new(config), Err(Error::NonFinite(_))));
    }

    #[test]
    fn evaluate_needs_every_key_and_a_camera() {
        let mut config = ViewBlenderConfig::new(1, 2);
        config.method = BlendMethod::Dib;
        let mut blender = ViewBlender::new(config).unwrap();
        let mut out = [DualQuat::ZERO];
        blender.set_key_pose(0, &[DualQuat::IDENTITY]).unwrap();
        blender.add_camera(Vec3::Z, 0).unwrap();
        assert!(matches!(
            blender.evaluate(DualQuat::IDENTITY, Vec3::Z, 0.0, &mut out),
            Err(Error::WrongState(_))
        ));
        assert_eq!(out, [DualQuat::ZERO]);
        blender
            .set_key_pose(1, &[DualQuat::from_rotation(Quat::from_rotation_y(1.0))])
            .unwrap();
        // Only key 0 has a camera: key 1 never contributes.
        let outcome = blender
            .evaluate(DualQuat::IDENTITY, Vec3::X, 0.0, &mut out)
            .unwrap();
        assert!(outcome.converged());
        assert!((out[0] - DualQuat::IDENTITY).length() < 1e-6);
        assert!(blender.set_key_pose(2, &[DualQuat::IDENTITY]).is_err());
        assert!(blender.set_key_pose(0, &[DualQuat::IDENTITY; 2]).is_err());
        assert!(blender.add_camera(Vec3::ZERO, 0).is_err());
        assert!(blender.add_camera(Vec3::Z, 5).is_err());
    }

    #[test]
    fn allocations_that_fail_change_nothing() {
        use crate::alloc::fault::fail_after;
        fail_after(Some(0));
        let created = ViewBlender::new(ViewBlenderConfig::new(4, 2));
        fail_after(None);
        let message = created.unwrap_err().to_string();
        assert!(
            message.starts_with("out of memory: key_count = 2 needs "),
            "{message}"
        );
        let mut blender = ViewBlender::new(ViewBlenderConfig::new(4, 2)).unwrap();
        let before = format!("{blender:?}");
        type Call = dyn Fn(&mut ViewBlender) -> Result<()>;
        let calls: [&Call; 2] = [&|b| b.add_camera(Vec3::Z, 0).map(|_| ()), &|b| {
            b.set_key_pose(1, &[DualQuat::IDENTITY; 4])
        }];
        for (n, call) in calls.into_iter().enumerate() {
            fail_after(Some(0));
            let result = call(&mut blender);
            fail_after(None);
            assert!(
                matches!(result, Err(Error::OutOfMemory(_))),
                "{n}: {result:?}"
            );
            assert_eq!(format!("{blender:?}"), before);
        }
        let frames = [DualQuat::IDENTITY; 12];
        fail_after(Some(0));
        let clip = KeyClip::new(&frames, 4, 30.0, true);
        fail_after(None);
        let message = clip.unwrap_err().to_string();
        assert_eq!(
            message,
            "out of memory: a clip of 3 frames × 4 joints needs 384 bytes"
        );
    }
}
