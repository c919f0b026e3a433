//! The gaze chain's C description: `cg_chain_desc`, its human default, and its checked
//! conversion to the core's [`GazeChain`].

use glam::Vec3;

use super::error::Result;
use super::types::{cg_axis, cg_quat, cg_vec3};
use super::{ffi_boundary, write_versioned, Versioned};
use crate::error::{ensure_all_finite, ensure_finite, Error};
use crate::ik::{ChainJoint, GazeChain, JointLimits, JointRole, MAX_CHAIN_JOINTS};
use crate::world::World;

/// Most joints a `cg_chain_desc` holds: 8 spine + 4 cervical + 1 head + 2 eyes.
pub const CG_MAX_CHAIN_JOINTS: usize = 15;

const _: () = assert!(CG_MAX_CHAIN_JOINTS == MAX_CHAIN_JOINTS);

/// What a joint of a gaze chain is. Stored as `uint32_t` in `cg_chain_joint.role`.
#[repr(u32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum cg_joint_role {
    /// A lumbar or thoracic vertebra.
    Spine = 0,
    /// A cervical vertebra (neck).
    Cervical = 1,
    /// The head (skull base).
    Head = 2,
    /// The character's left eye.
    LeftEye = 3,
    /// The character's right eye.
    RightEye = 4,
}

impl cg_joint_role {
    /// Converts a `uint32_t` from C, rejecting unknown values.
    fn parse(value: u32, what: &str) -> Result<JointRole> {
        Ok(match value {
            0 => JointRole::Spine,
            1 => JointRole::Cervical,
            2 => JointRole::Head,
            3 => JointRole::LeftEye,
            4 => JointRole::RightEye,
            other => {
                return Err(Error::InvalidArgument(format!(
                    "{what} is {other}, not a cg_joint_role"
                ))
                .into())
            }
        })
    }

    /// The C value of a [`JointRole`].
    fn from_role(role: JointRole) -> u32 {
        (match role {
            JointRole::Spine => cg_joint_role::Spine,
            JointRole::Cervical => cg_joint_role::Cervical,
            JointRole::Head => cg_joint_role::Head,
            JointRole::LeftEye => cg_joint_role::LeftEye,
            JointRole::RightEye => cg_joint_role::RightEye,
        }) as u32
    }
}

/// One joint of a gaze chain.
///
/// Limits apply to the gaze's *delta* rotation on top of the joint's base rotation, split
/// as swing · twist about `twist_axis`: the twist angle stays in [min_twist, max_twist] and
/// the swing angle (a cone's half-angle) at most max_swing. Radians.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct cg_chain_joint {
    /// What the joint is: a `cg_joint_role` value.
    pub role: u32,
    /// Position of the joint in its parent's local frame (the chain root for the first
    /// joint, the head for the eyes), in your length units; at most 1 km long.
    pub offset: cg_vec3,
    /// Rest local rotation relative to the parent (normalised on reading).
    pub rest: cg_quat,
    /// Twist axis in the joint's local frame (normalised on reading): the skeleton's up axis
    /// for spine, cervicals and head (twist = yaw), the eye's forward axis for the eyes
    /// (twist = torsion).
    pub twist_axis: cg_vec3,
    /// Largest swing angle, radians, in [0, π].
    pub max_swing: f32,
    /// Smallest twist angle, radians, ≥ −π.
    pub min_twist: f32,
    /// Largest twist angle, radians, in [min_twist, π].
    pub max_twist: f32,
}

/// A character's gaze chain: up to 8 spine, up to 4 cervical, exactly 1 head and 0 or 2 eye
/// joints, listed bottom to top in `joints[0 .. joint_count]`: spine…, cervical…, head,
/// left eye, right eye. Each body joint's parent is the previous joint (the chain root for
/// the first); the eyes' parent is the head.
///
/// Expressed in the world's axes for a character at heading 0; the character's world
/// transform is translation(position) · rotation(heading about the up axis).
/// Set `struct_size = sizeof(cg_chain_desc)`, then fill it with `cg_chain_desc_init_human`
/// (and adjust) or field by field.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct cg_chain_desc {
    /// Size of this struct in bytes: set it to `sizeof(cg_chain_desc)` before every call
    /// taking the struct, `cg_chain_desc_init_human` included.
    pub struct_size: u32,
    /// Number of joints used in `joints`, 1 to `CG_MAX_CHAIN_JOINTS`.
    pub joint_count: u32,
    /// The joints, bottom to top; entries past `joint_count` are ignored.
    pub joints: [cg_chain_joint; CG_MAX_CHAIN_JOINTS],
    /// The direction the eyes look at rest, in the head's local frame (normalised on
    /// reading).
    pub eye_forward: cg_vec3,
    /// The head's up direction in its local frame, perpendicular to `eye_forward`.
    pub eye_up: cg_vec3,
    /// Position of the chain root (the pelvis) relative to the character's position, in the
    /// character's frame, in your length units; at most 1 km long.
    pub root_offset: cg_vec3,
}

impl cg_chain_desc {
    /// The C description of a core chain in units of which `units_per_metre` make a metre:
    /// the inverse of [`cg_chain_desc::to_core`] (lengths multiplied where it divides).
    pub(crate) fn from_core_in_units(chain: &GazeChain, units_per_metre: f32) -> cg_chain_desc {
        let mut desc = cg_chain_desc::from_core(chain);
        let scale = |v: cg_vec3| cg_vec3 {
            x: v.x * units_per_metre,
            y: v.y * units_per_metre,
            z: v.z * units_per_metre,
        };
        for joint in &mut desc.joints[..chain.joint_count()] {
            joint.offset = scale(joint.offset);
        }
        desc.root_offset = scale(desc.root_offset);
        desc
    }

    /// The C description of a core chain, lengths in metres.
    fn from_core(chain: &GazeChain) -> cg_chain_desc {
        let mut joints = [cg_chain_joint {
            role: 0,
            offset: cg_vec3::default(),
            rest: cg_quat::IDENTITY,
            twist_axis: cg_vec3::default(),
            max_swing: 0.0,
            min_twist: 0.0,
            max_twist: 0.0,
        }; CG_MAX_CHAIN_JOINTS];
        for (slot, joint) in joints.iter_mut().zip(chain.joints()) {
            *slot = cg_chain_joint {
                role: cg_joint_role::from_role(joint.role),
                offset: joint.offset.into(),
                rest: joint.rest.into(),
                twist_axis: joint.limits.twist_axis().into(),
                max_swing: joint.limits.max_swing(),
                min_twist: joint.limits.min_twist(),
                max_twist: joint.limits.max_twist(),
            };
        }
        cg_chain_desc {
            struct_size: std::mem::size_of::<cg_chain_desc>() as u32,
            joint_count: chain.joint_count() as u32,
            joints,
            eye_forward: chain.eye_forward().into(),
            eye_up: chain.eye_up().into(),
            root_offset: chain.root_offset().into(),
        }
    }

    /// Checks the description and converts it to the core's chain, dividing lengths
    /// (offsets, root offset) by `units_per_metre`. Call it on a struct read with
    /// `read_versioned` (which checks `struct_size`).
    ///
    /// Errors: [`Error::InvalidArgument`] (joint count, unknown role, order of roles,
    /// zero-length axis or rotation, limits out of range, units_per_metre ≤ 0),
    /// [`Error::NonFinite`] (any NaN or infinite float).
    // Borrowed although `Copy`: the description is 884 bytes.
    #[allow(clippy::wrong_self_convention)]
    pub(crate) fn to_core(&self, units_per_metre: f32) -> Result<GazeChain> {
        ensure_finite(units_per_metre, "units_per_metre")?;
        if units_per_metre <= 0.0 {
            return Err(Error::InvalidArgument(format!(
                "units_per_metre is {units_per_metre}, must be > 0"
            ))
            .into());
        }
        let count = self.joint_count as usize;
        if count == 0 || count > CG_MAX_CHAIN_JOINTS {
            return Err(Error::InvalidArgument(format!(
                "cg_chain_desc.joint_count is {count}, must be 1..={CG_MAX_CHAIN_JOINTS}"
            ))
            .into());
        }
        let placeholder = ChainJoint::new(
            JointRole::Head,
            Vec3::ZERO,
            glam::Quat::IDENTITY,
            JointLimits::free(Vec3::Y),
        );
        let mut joints = [placeholder; CG_MAX_CHAIN_JOINTS];
        for (index, (joint, desc)) in joints.iter_mut().zip(&self.joints[..count]).enumerate() {
            let what = |field: &str| format!("joints[{index}].{field}");
            let role = cg_joint_role::parse(desc.role, &what("role"))?;
            let offset = desc.offset.to_finite(&what("offset"))? / units_per_metre;
            let rest = desc.rest.to_unit(&what("rest"))?;
            let twist_axis = desc.twist_axis.to_finite(&what("twist_axis"))?;
            if twist_axis.length() <= 1e-6 {
                return Err(Error::InvalidArgument(format!(
                    "{} has zero length",
                    what("twist_axis")
                ))
                .into());
            }
            ensure_all_finite(
                &[desc.max_swing, desc.min_twist, desc.max_twist],
                &what("limits"),
            )?;
            *joint = ChainJoint::new(
                role,
                offset,
                rest,
                JointLimits::new(twist_axis, desc.max_swing, desc.min_twist, desc.max_twist),
            );
        }
        let eye_forward = self.eye_forward.to_finite("eye_forward")?;
        let eye_up = self.eye_up.to_finite("eye_up")?;
        let root_offset = self.root_offset.to_finite("root_offset")? / units_per_metre;
        Ok(GazeChain::new(
            &joints[..count],
            eye_forward,
            eye_up,
            root_offset,
        )?)
    }
}

impl Versioned for cg_chain_desc {
    const SIZES: &'static [usize] = &[std::mem::size_of::<cg_chain_desc>()];
    const NAME: &'static str = "cg_chain_desc";

    fn defaults() -> Self {
        cg_chain_desc::from_core(&GazeChain::human(Vec3::Y, Vec3::Z))
    }
}

/// Fills `desc` with the gaze chain of an adult human (Grillon & Thalmann's 5 spine,
/// 2 cervical, 1 head and 2 eye joints) for a skeleton whose up axis is `up_axis` and which
/// faces `forward_axis` (both `cg_axis` values, perpendicular; the character's left is
/// up × forward). Set `desc->struct_size = sizeof(cg_chain_desc)` first: only that many
/// bytes are written, and `struct_size` keeps its value. The caller owns `desc`.
///
/// Lengths are in **metres**: the pelvis (chain root) 0.95 above the character's position,
/// eyes at 1.62, 64 mm apart. If your crowd's `units_per_metre` is not 1, multiply every
/// `joints[i].offset` and `root_offset` by it. Rest rotations are identity. Limits: each spine
/// joint ±8° of yaw and a 5° swing cone, each cervical ±25° and 20°, the head ±20° and 25°,
/// the eyes a 35° cone and no torsion.
///
/// `*desc` is written only on success. Errors: `CG_STATUS_NULL_ARGUMENT` (desc NULL),
/// `CG_STATUS_INVALID_ARGUMENT` (an axis not a `cg_axis`, or the two not perpendicular),
/// `CG_STATUS_BAD_STRUCT_SIZE` (`struct_size` not a size the library knows, 0 or an unset
/// field included). Thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_chain_desc_init_human(
    desc: *mut cg_chain_desc,
    up_axis: u32,
    forward_axis: u32,
) -> super::cg_status {
    ffi_boundary!({
        let world = World::new(
            cg_axis::parse(up_axis, "up_axis")?,
            cg_axis::parse(forward_axis, "forward_axis")?,
            1.0,
        )?;
        let human = cg_chain_desc::from_core(&GazeChain::human(world.up, world.forward));
        // SAFETY: the caller passes a cg_chain_desc it owns, of at least its struct_size
        // bytes (or NULL).
        unsafe { write_versioned(desc, human, "desc") }
    })
}

#[cfg(test)]
// The tests' C calls pass pointers to live locals: their safety comment, once.
#[allow(clippy::undocumented_unsafe_blocks)]
mod tests {
    use super::super::{cg_status, last_error, read_versioned};
    use super::*;
    use crate::ffi::error::FfiError;

    fn human_desc(up: cg_axis, forward: cg_axis) -> cg_chain_desc {
        // SAFETY: zero bytes are a valid cg_chain_desc (plain old data).
        let mut desc: cg_chain_desc = unsafe { std::mem::zeroed() };
        desc.struct_size = std::mem::size_of::<cg_chain_desc>() as u32;
        assert_eq!(
            unsafe { cg_chain_desc_init_human(&mut desc, up as u32, forward as u32) },
            cg_status::Ok
        );
        desc
    }

    #[test]
    fn the_human_description_round_trips() {
        for (up, forward, up_vector, forward_vector) in [
            (cg_axis::PositiveY, cg_axis::PositiveZ, Vec3::Y, Vec3::Z),
            (cg_axis::PositiveZ, cg_axis::NegativeY, Vec3::Z, Vec3::NEG_Y),
            (cg_axis::PositiveZ, cg_axis::PositiveX, Vec3::Z, Vec3::X),
        ] {
            let desc = human_desc(up, forward);
            assert_eq!(
                desc.struct_size as usize,
                std::mem::size_of::<cg_chain_desc>()
            );
            assert_eq!(desc.joint_count, 10);
            let core = desc.to_core(1.0).unwrap();
            assert_eq!(core, GazeChain::human(up_vector, forward_vector));
            // In centimetres: scale the lengths, get the same chain back.
            let mut centimetres = desc;
            for joint in &mut centimetres.joints[..10] {
                joint.offset =
                    (Vec3::new(joint.offset.x, joint.offset.y, joint.offset.z) * 100.0).into();
            }
            let root = centimetres.root_offset;
            centimetres.root_offset = (Vec3::new(root.x, root.y, root.z) * 100.0).into();
            let scaled = centimetres.to_core(100.0).unwrap();
            for (a, b) in scaled.joints().iter().zip(core.joints()) {
                assert!(a.offset.abs_diff_eq(b.offset, 1e-6));
            }
            assert!((scaled.look_at_height(up_vector) - 1.62).abs() < 1e-5);
        }
    }

    #[test]
    fn a_chain_in_units_reads_back_as_the_chain() {
        let mut joints = GazeChain::human(Vec3::Z, Vec3::NEG_Y).joints().to_vec();
        joints[1].rest = glam::Quat::from_rotation_x(0.3);
        joints[4].rest = glam::Quat::from_euler(glam::EulerRot::YXZ, 0.2, -0.1, 0.05);
        let chain =
            GazeChain::new(&joints, Vec3::NEG_Y, Vec3::Z, Vec3::new(0.01, 0.0, 0.93)).unwrap();
        // Equal to float rounding: reading divides lengths by the units and renormalises
        // the rotations.
        for units in [1.0, 100.0, 39.37, 1e-3, 1e6] {
            let read = cg_chain_desc::from_core_in_units(&chain, units)
                .to_core(units)
                .unwrap();
            for (a, b) in read.joints().iter().zip(chain.joints()) {
                assert!(a.offset.abs_diff_eq(b.offset, 1e-6), "{units}");
                assert!(a.rest.abs_diff_eq(b.rest, 1e-6), "{units}");
                assert_eq!((a.role, a.limits), (b.role, b.limits), "{units}");
            }
            let root = read.root_offset();
            assert!(root.abs_diff_eq(chain.root_offset(), 1e-6), "{units}");
        }
    }

    #[test]
    fn init_checks_its_arguments_and_writes_only_on_success() {
        assert_eq!(
            unsafe { cg_chain_desc_init_human(std::ptr::null_mut(), 2, 4) },
            cg_status::NullArgument
        );
        let mut desc = human_desc(cg_axis::PositiveY, cg_axis::PositiveZ);
        let before = desc;
        desc.joint_count = 3;
        let snapshot = desc;
        assert_eq!(
            unsafe { cg_chain_desc_init_human(&mut desc, 2, 3) },
            cg_status::InvalidArgument
        );
        assert_eq!(desc, snapshot, "not perpendicular: unchanged");
        assert_eq!(
            unsafe { cg_chain_desc_init_human(&mut desc, 9, 4) },
            cg_status::InvalidArgument
        );
        assert!(last_error::last_error_message().contains("not a cg_axis"));
        assert_eq!(desc, snapshot);
        assert_eq!(
            unsafe { cg_chain_desc_init_human(&mut desc, 2, 4) },
            cg_status::Ok
        );
        assert_eq!(desc, before);
        // A struct_size this library does not know: nothing is written.
        for size in [0, 4, 880, 888, u32::MAX] {
            desc.joint_count = 3;
            desc.struct_size = size;
            let snapshot = desc;
            assert_eq!(
                unsafe { cg_chain_desc_init_human(&mut desc, 2, 4) },
                cg_status::BadStructSize
            );
            assert_eq!(desc, snapshot, "struct_size {size}: unchanged");
        }
    }

    #[test]
    fn bad_descriptions_are_rejected() {
        let good = human_desc(cg_axis::PositiveY, cg_axis::PositiveZ);
        let invalid = |desc: &cg_chain_desc| {
            matches!(
                desc.to_core(1.0),
                Err(FfiError::Core(Error::InvalidArgument(_)))
            )
        };
        let non_finite = |desc: &cg_chain_desc| {
            matches!(desc.to_core(1.0), Err(FfiError::Core(Error::NonFinite(_))))
        };
        assert!(matches!(
            good.to_core(0.0),
            Err(FfiError::Core(Error::InvalidArgument(_)))
        ));
        assert!(matches!(
            good.to_core(f32::NAN),
            Err(FfiError::Core(Error::NonFinite(_)))
        ));
        let mut desc = good;
        desc.joint_count = 0;
        assert!(invalid(&desc));
        desc.joint_count = 16;
        assert!(invalid(&desc));
        desc.joint_count = 9; // one eye
        assert!(invalid(&desc));
        desc.joint_count = 8; // no eyes: fine
        assert!(desc.to_core(1.0).is_ok());
        let mut desc = good;
        desc.joints[3].role = 7;
        assert!(invalid(&desc));
        desc.joints[3].role = cg_joint_role::Head as u32;
        assert!(invalid(&desc), "two heads");
        let mut desc = good;
        desc.joints[2].offset.y = f32::NAN;
        assert!(non_finite(&desc));
        let mut desc = good;
        desc.joints[2].rest.w = f32::INFINITY;
        assert!(non_finite(&desc));
        let mut desc = good;
        desc.joints[2].rest = cg_quat {
            x: 0.0,
            y: 0.0,
            z: 0.0,
            w: 0.0,
        };
        assert!(invalid(&desc));
        let mut desc = good;
        desc.joints[5].twist_axis = cg_vec3::default();
        assert!(invalid(&desc));
        let mut desc = good;
        desc.joints[5].max_swing = f32::NAN;
        assert!(non_finite(&desc));
        let mut desc = good;
        desc.joints[5].min_twist = 1.0;
        assert!(invalid(&desc), "min > max");
        let mut desc = good;
        desc.eye_forward = cg_vec3::default();
        assert!(invalid(&desc));
        let mut desc = good;
        desc.eye_up = desc.eye_forward;
        assert!(invalid(&desc));
        let mut desc = good;
        desc.root_offset.z = f32::NEG_INFINITY;
        assert!(non_finite(&desc));
        // A wrong struct_size is caught when reading it from C.
        let mut desc = good;
        desc.struct_size = 12;
        // SAFETY: desc is a valid, aligned cg_chain_desc.
        let read = unsafe { read_versioned(&desc) };
        assert!(matches!(read, Err(FfiError::BadStructSize(_))));
    }
}
