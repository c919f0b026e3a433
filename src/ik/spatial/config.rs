//! The spatial resolution's settings: the recruitment bands (15° and 30° by default), the
//! behind-the-character zone and the near distance ([`SpatialConfig`]), and the constants
//! the solver compares against, prepared from them once per call ([`Prepared`]).

use std::cell::Cell;

use glam::Vec4;

use crate::error::{ensure_all_finite, Error, Result};
use crate::ik::lanes::sin_cos_quarter;
use crate::math::lanes::Floats;

/// Angles that decide which groups of joints a gaze rotation recruits (radians).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RecruitmentBands {
    /// Up to this angle only the eyes move; beyond it the eyes keep this much of the
    /// rotation for themselves. Default 15° (the central foveal area's half-width).
    pub eyes_only: f32,
    /// Up to this angle the spine does not move; beyond it the eyes, head and cervicals
    /// keep this much for themselves. Default 30° (the central vision area's half-width).
    pub eyes_head_and_neck: f32,
}

impl Default for RecruitmentBands {
    fn default() -> Self {
        RecruitmentBands {
            eyes_only: 15f32.to_radians(),
            eyes_head_and_neck: 30f32.to_radians(),
        }
    }
}

/// Settings of the spatial resolution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpatialConfig {
    /// Which groups a rotation recruits.
    pub bands: RecruitmentBands,
    /// Half-width (radians, about the head's up axis) of the zone behind the character
    /// where the remembered [`TurnSide`] wins over the shortest rotation. Default 30°.
    ///
    /// [`TurnSide`]: crate::ik::TurnSide
    pub behind_hysteresis: f32,
    /// How far short of straight behind (radians) a target on the other side within the
    /// hysteresis zone is aimed at. Default 10°. At most `behind_hysteresis`.
    pub behind_clearance: f32,
    /// Below this distance from the eye (metres) the gaze rotation fades out, reaching zero
    /// at the eye itself. Default 0.25 m.
    pub near_distance: f32,
}

impl Default for SpatialConfig {
    fn default() -> Self {
        SpatialConfig {
            bands: RecruitmentBands::default(),
            behind_hysteresis: 30f32.to_radians(),
            behind_clearance: 10f32.to_radians(),
            near_distance: 0.25,
        }
    }
}

impl SpatialConfig {
    /// Checks the ranges: `0 ≤ eyes_only ≤ eyes_head_and_neck ≤ π`,
    /// `0 ≤ behind_clearance ≤ behind_hysteresis < 90°`, `near_distance ≥ 0`, all finite.
    pub fn validate(&self) -> Result<()> {
        ensure_all_finite(
            &[
                self.bands.eyes_only,
                self.bands.eyes_head_and_neck,
                self.behind_hysteresis,
                self.behind_clearance,
                self.near_distance,
            ],
            "spatial config",
        )?;
        let bands = self.bands;
        if bands.eyes_only < 0.0
            || bands.eyes_head_and_neck < bands.eyes_only
            || bands.eyes_head_and_neck > std::f32::consts::PI
        {
            return Err(Error::InvalidArgument(format!(
                "recruitment bands {} and {} must satisfy 0 ≤ eyes_only ≤ eyes_head_and_neck ≤ π",
                bands.eyes_only, bands.eyes_head_and_neck
            )));
        }
        if self.behind_clearance < 0.0
            || self.behind_hysteresis < self.behind_clearance
            || self.behind_hysteresis >= std::f32::consts::FRAC_PI_2
        {
            return Err(Error::InvalidArgument(format!(
                "behind_clearance {} and behind_hysteresis {} must satisfy 0 ≤ clearance ≤ \
                 hysteresis < π/2",
                self.behind_clearance, self.behind_hysteresis
            )));
        }
        if self.near_distance < 0.0 {
            return Err(Error::InvalidArgument(format!(
                "near_distance is {}, must be ≥ 0",
                self.near_distance
            )));
        }
        Ok(())
    }
}
/// The settings turned into the constants the solver compares against. The behind-zone
/// constants need trigonometry, so they are computed only when a target is behind.
#[derive(Debug, Clone)]
pub(crate) struct Prepared {
    behind_hysteresis: f32,
    behind_clearance: f32,
    pub(super) near_distance: f32,
    /// cos and sin of half of each band (the angles reserved for the groups above).
    pub(super) eyes_only_half: (f32, f32),
    pub(super) eyes_head_and_neck_half: (f32, f32),
    zone: Cell<Option<Zone>>,
}

/// cos and sin of half of `angle ∈ [0, π]`.
#[inline]
fn half_angle(angle: f32) -> (f32, f32) {
    let (sin, cos) = sin_cos_quarter(Floats::<Vec4>::splat(0.5 * angle));
    (cos.lane(0), sin.lane(0))
}

/// Constants of the zone behind the character.
#[derive(Debug, Clone, Copy)]
pub(super) struct Zone {
    pub(super) tan_hysteresis: f32,
    pub(super) tan_clearance: f32,
    pub(super) cos_clearance: f32,
    pub(super) sin_clearance: f32,
}

impl Prepared {
    pub(crate) fn new(config: &SpatialConfig) -> Prepared {
        Prepared {
            behind_hysteresis: config.behind_hysteresis,
            behind_clearance: config.behind_clearance,
            near_distance: config.near_distance,
            eyes_only_half: half_angle(config.bands.eyes_only),
            eyes_head_and_neck_half: half_angle(config.bands.eyes_head_and_neck),
            zone: Cell::new(None),
        }
    }

    #[inline]
    pub(super) fn zone(&self) -> Zone {
        if let Some(zone) = self.zone.get() {
            return zone;
        }
        let (sin_clearance, cos_clearance) = self.behind_clearance.sin_cos();
        let zone = Zone {
            tan_hysteresis: self.behind_hysteresis.tan(),
            tan_clearance: sin_clearance / cos_clearance,
            cos_clearance,
            sin_clearance,
        };
        self.zone.set(Some(zone));
        zone
    }
}
