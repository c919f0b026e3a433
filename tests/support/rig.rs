//! A Mixamo skeleton for the `cg_rig` tests and benchmarks: 65 bones (`mixamorig:` names,
//! hips, three spine bones, neck, head, eyes, arms with five four-bone fingers, legs),
//! centimetres, Y up, facing +Z, with rotated rest rotations as imported FBX rigs have.
//! Self-contained: the bad-input test includes it by path.

#![allow(dead_code)]

use crowdgaze::ffi::rig::*;
use crowdgaze::ffi::types::{cg_quat, cg_vec3};
use glam::{Quat, Vec3};
use std::ffi::CString;
use std::os::raw::c_char;

/// A skeleton at rest, with the arrays `cg_rig_desc` points into.
pub struct Skeleton {
    pub names: Vec<CString>,
    pub name_pointers: Vec<*const c_char>,
    pub parents: Vec<i32>,
    pub translations: Vec<cg_vec3>,
    pub rotations: Vec<cg_quat>,
}

/// Index of the bone called `name` (without the `mixamorig:` prefix).
pub fn bone(skeleton: &Skeleton, name: &str) -> usize {
    let full = format!("mixamorig:{name}");
    skeleton
        .names
        .iter()
        .position(|n| n.to_str().unwrap() == full)
        .unwrap_or_else(|| panic!("no bone {name}"))
}

pub fn quat(q: Quat) -> cg_quat {
    cg_quat {
        x: q.x,
        y: q.y,
        z: q.z,
        w: q.w,
    }
}

pub fn glam_quat(q: cg_quat) -> Quat {
    Quat::from_xyzw(q.x, q.y, q.z, q.w)
}

impl Skeleton {
    /// Builds the skeleton from bones given as (name, parent name, rest position relative
    /// to the character, rest global rotation), parents first.
    fn from_globals(bones: &[(String, Option<String>, Vec3, Quat)]) -> Skeleton {
        let mut skeleton = Skeleton {
            names: Vec::new(),
            name_pointers: Vec::new(),
            parents: Vec::new(),
            translations: Vec::new(),
            rotations: Vec::new(),
        };
        for (index, (name, parent, position, rotation)) in bones.iter().enumerate() {
            let parent = parent.as_ref().map(|p| {
                bones[..index]
                    .iter()
                    .position(|b| &b.0 == p)
                    .unwrap_or_else(|| panic!("parent {p} of {name} not before it"))
            });
            let (local_t, local_r) = match parent {
                None => (*position, *rotation),
                Some(p) => {
                    let (_, _, parent_position, parent_rotation) = &bones[p];
                    (
                        parent_rotation.conjugate() * (*position - *parent_position),
                        (parent_rotation.conjugate() * *rotation).normalize(),
                    )
                }
            };
            skeleton.names.push(CString::new(name.as_str()).unwrap());
            skeleton.parents.push(parent.map_or(-1, |p| p as i32));
            skeleton.translations.push(cg_vec3 {
                x: local_t.x,
                y: local_t.y,
                z: local_t.z,
            });
            skeleton.rotations.push(quat(local_r));
        }
        skeleton.name_pointers = skeleton.names.iter().map(|n| n.as_ptr()).collect();
        skeleton
    }

    /// The 65-bone Mixamo skeleton, centimetres, Y up, facing +Z.
    pub fn mixamo() -> Skeleton {
        let mut bones: Vec<(String, Option<String>, Vec3, Quat)> = Vec::new();
        let mut add = |name: &str, parent: Option<&str>, p: [f32; 3], r: Quat| {
            bones.push((
                format!("mixamorig:{name}"),
                parent.map(|p| format!("mixamorig:{p}")),
                Vec3::from(p),
                r,
            ));
        };
        // Imported rigs have bones whose rest frames are turned: a slight forward tilt
        // along the spine, and arms rolled about their length.
        let tilt = |degrees: f32| Quat::from_rotation_x(degrees.to_radians());
        add("Hips", None, [0.0, 100.0, 0.0], tilt(-3.0));
        add("Spine", Some("Hips"), [0.0, 110.0, 1.0], tilt(4.0));
        add("Spine1", Some("Spine"), [0.0, 122.0, 1.5], tilt(6.0));
        add("Spine2", Some("Spine1"), [0.0, 135.0, 1.0], tilt(2.0));
        add("Neck", Some("Spine2"), [0.0, 150.0, 0.0], tilt(-10.0));
        add("Head", Some("Neck"), [0.0, 160.0, 1.5], tilt(5.0));
        add("HeadTop_End", Some("Head"), [0.0, 178.0, 2.0], tilt(5.0));
        add("LeftEye", Some("Head"), [3.2, 165.0, 9.0], Quat::IDENTITY);
        add("RightEye", Some("Head"), [-3.2, 165.0, 9.0], Quat::IDENTITY);
        for (side, sign) in [("Left", 1.0f32), ("Right", -1.0f32)] {
            let arm = Quat::from_rotation_z(sign * -90f32.to_radians());
            let s = |x: f32| sign * x;
            add(
                &format!("{side}Shoulder"),
                Some("Spine2"),
                [s(6.0), 145.0, 0.0],
                arm,
            );
            add(
                &format!("{side}Arm"),
                Some(&format!("{side}Shoulder")),
                [s(16.0), 145.0, 0.0],
                arm,
            );
            add(
                &format!("{side}ForeArm"),
                Some(&format!("{side}Arm")),
                [s(44.0), 145.0, 0.0],
                arm * Quat::from_rotation_y(0.2),
            );
            add(
                &format!("{side}Hand"),
                Some(&format!("{side}ForeArm")),
                [s(70.0), 145.0, 0.0],
                arm,
            );
            for (finger, z) in [
                ("Thumb", 3.0),
                ("Index", 2.0),
                ("Middle", 0.0),
                ("Ring", -1.5),
                ("Pinky", -3.0),
            ] {
                let mut parent = format!("{side}Hand");
                for k in 1..=4 {
                    let name = format!("{side}Hand{finger}{k}");
                    let x = 78.0 + 2.5 * k as f32;
                    add(&name, Some(&parent), [s(x), 145.0, z], arm);
                    parent = name;
                }
            }
        }
        for (side, sign) in [("Left", 1.0f32), ("Right", -1.0f32)] {
            let down = Quat::from_rotation_x(180f32.to_radians());
            add(
                &format!("{side}UpLeg"),
                Some("Hips"),
                [sign * 9.0, 95.0, 0.0],
                down,
            );
            add(
                &format!("{side}Leg"),
                Some(&format!("{side}UpLeg")),
                [sign * 9.0, 52.0, 0.5],
                down,
            );
            add(
                &format!("{side}Foot"),
                Some(&format!("{side}Leg")),
                [sign * 9.0, 8.0, -1.0],
                down * Quat::from_rotation_x(-1.0),
            );
            add(
                &format!("{side}ToeBase"),
                Some(&format!("{side}Foot")),
                [sign * 9.0, 2.0, 12.0],
                down * Quat::from_rotation_x(-1.5),
            );
        }
        let skeleton = Skeleton::from_globals(&bones);
        assert_eq!(skeleton.names.len(), 65);
        skeleton
    }

    /// A `cg_rig_desc` over this skeleton (centimetres, axes detected), for a crowd of
    /// `crowd_units_per_metre`, Y up, +Z forward.
    pub fn desc(&self, crowd_units_per_metre: f32) -> cg_rig_desc {
        let mut desc = std::mem::MaybeUninit::<cg_rig_desc>::uninit();
        // SAFETY: a versioned struct starts with its `uint32_t struct_size`, set before the
        // call that fills the rest.
        let mut desc = unsafe {
            desc.as_mut_ptr()
                .cast::<u32>()
                .write(std::mem::size_of::<cg_rig_desc>() as u32);
            assert_eq!(
                cg_rig_desc_init(desc.as_mut_ptr()),
                crowdgaze::ffi::status::cg_status::Ok
            );
            desc.assume_init()
        };
        desc.bone_count = self.names.len() as u32;
        desc.bone_names = self.name_pointers.as_ptr();
        desc.parents = self.parents.as_ptr();
        desc.rest_translations = self.translations.as_ptr();
        desc.rest_rotations = self.rotations.as_ptr();
        desc.units_per_metre = 100.0;
        desc.crowd_units_per_metre = crowd_units_per_metre;
        desc
    }

    /// The rig of this skeleton for a crowd of `crowd_units_per_metre`.
    pub fn rig(&self, crowd_units_per_metre: f32) -> Rig {
        let desc = self.desc(crowd_units_per_metre);
        let mut rig = std::ptr::null_mut();
        // SAFETY: the desc points into this skeleton's live arrays.
        let status = unsafe { cg_rig_create(&desc, &mut rig) };
        assert_eq!(
            status,
            crowdgaze::ffi::status::cg_status::Ok,
            "cg_rig_create: {}",
            crowdgaze::ffi::last_error::last_error_message()
        );
        Rig(rig)
    }

    /// The engine's bone rotations of a frame: the rest pose with the spine, neck and head
    /// swayed by `phase` (radians) and the arms moved.
    pub fn animated(&self, phase: f32) -> Vec<cg_quat> {
        let mut rotations = self.rotations.clone();
        for name in ["Spine", "Spine1", "Neck", "Head", "LeftArm", "RightForeArm"] {
            let index = bone(self, name);
            let sway = Quat::from_euler(
                glam::EulerRot::YXZ,
                0.15 * phase.sin(),
                0.05 * (1.3 * phase).cos(),
                0.04 * phase.sin(),
            );
            rotations[index] = quat((glam_quat(rotations[index]) * sway).normalize());
        }
        rotations
    }
}

/// A rig, destroyed when dropped.
pub struct Rig(pub *mut cg_rig);

// SAFETY: a rig is immutable; its const calls are thread-safe (the header's contract).
unsafe impl Send for Rig {}
// SAFETY: as above.
unsafe impl Sync for Rig {}

impl Rig {
    /// The handle, which the caller now destroys.
    pub fn into_raw(self) -> *mut cg_rig {
        let rig = self.0;
        std::mem::forget(self);
        rig
    }
}

impl Drop for Rig {
    fn drop(&mut self) {
        // SAFETY: a live rig, destroyed once.
        unsafe { cg_rig_destroy(self.0) };
    }
}
