//! Rows: the rig (its desc, create, the const readers, and each frame's conversions).
//!
//! Inputs are the Mixamo skeleton of `skeleton.rs` (65 bones, centimetres), broken one way
//! per case; the arrays a call reads and writes in place are checked unchanged after a
//! failure besides the fixture's snapshot (which reads the fixture's rig).

use crate::{
    blend::{or_null, or_null_mut},
    corruption::{bad_output_sizes, change, inside, non_finite, struct_sizes, Corruption},
    fixture::{Harness, Setup},
    set_sentinel_error,
    skeleton::Skeleton,
    table::Table,
    values::{bytes_of, floats, last_error, BAD_FLOATS, ZERO_QUAT},
    INVALID, NON_FINITE, NULL_ARG,
};
use crowdgaze::ffi::chain::cg_chain_desc;
use crowdgaze::ffi::rig::*;
use crowdgaze::ffi::status::cg_status;
use crowdgaze::ffi::types::{cg_quat, cg_vec3};
use std::ffi::c_char;
use std::mem::{offset_of, size_of};
use std::ptr::{null, null_mut};

/// The arguments of `cg_rig_create`: the desc and the arrays it points to, owned.
#[derive(Clone)]
struct RigInput {
    desc: cg_rig_desc,
    /// Each NUL-terminated.
    names: Vec<Vec<u8>>,
    parents: Vec<i32>,
    translations: Vec<cg_vec3>,
    rotations: Vec<cg_quat>,
    /// NUL-terminated, or none.
    bone_map: Option<Vec<u8>>,
    /// Pass as NULL: `bone_names`, `parents`, `rest_translations`, the name of bone 3.
    nulls: [bool; 4],
}

fn rig_input(_: &Harness) -> RigInput {
    let skeleton = Skeleton::mixamo();
    RigInput {
        desc: skeleton.desc(1.0),
        names: skeleton
            .names
            .iter()
            .map(|n| n.as_bytes_with_nul().to_vec())
            .collect(),
        parents: skeleton.parents.clone(),
        translations: skeleton.translations.clone(),
        rotations: skeleton.rotations.clone(),
        bone_map: None,
        nulls: [false; 4],
    }
}

impl RigInput {
    fn create(&mut self, h: &mut Harness) -> cg_status {
        let out: *mut *mut cg_rig = &mut h.out.rig;
        self.create_into(out)
    }

    fn create_into(&mut self, out: *mut *mut cg_rig) -> cg_status {
        let mut names: Vec<*const c_char> = self.names.iter().map(|n| n.as_ptr().cast()).collect();
        if self.nulls[3] {
            names[3] = null();
        }
        let mut desc = self.desc;
        desc.bone_names = or_null(names.as_ptr(), self.nulls[0]);
        desc.parents = or_null(self.parents.as_ptr(), self.nulls[1]);
        desc.rest_translations = or_null(self.translations.as_ptr(), self.nulls[2]);
        desc.rest_rotations = self.rotations.as_ptr();
        desc.bone_map = self.bone_map.as_ref().map_or(null(), |m| m.as_ptr().cast());
        unsafe { cg_rig_create(&desc, out) }
    }

    fn name(&mut self, bone: usize, name: &[u8]) {
        self.names[bone] = [name, b"\0"].concat();
    }

    fn map(&mut self, map: &str) {
        self.bone_map = Some([map.as_bytes(), b"\0"].concat());
    }
}

/// NaN and infinities in each component of the rest translation and rotation of `bones`.
fn non_finite_bones(bones: &[usize]) -> Vec<Corruption<RigInput>> {
    let mut out = Vec::new();
    for &bone in bones {
        for (component, label) in ["x", "y", "z", "w"].iter().enumerate() {
            for (bad, value) in BAD_FLOATS {
                if component < 3 {
                    out.push(change(
                        format!("rest_translations[{bone}].{label} = {bad}"),
                        NON_FINITE,
                        move |r: &mut RigInput| {
                            let t = &mut r.translations[bone];
                            *[&mut t.x, &mut t.y, &mut t.z][component] = value;
                        },
                    ));
                }
                out.push(change(
                    format!("rest_rotations[{bone}].{label} = {bad}"),
                    NON_FINITE,
                    move |r: &mut RigInput| {
                        let q = &mut r.rotations[bone];
                        *[&mut q.x, &mut q.y, &mut q.z, &mut q.w][component] = value;
                    },
                ));
            }
        }
    }
    out
}

type Named = (&'static str, fn(&mut RigInput));

fn create_corruptions() -> Vec<Corruption<RigInput>> {
    type R = RigInput;
    type D = cg_rig_desc;
    let mut out = inside(struct_sizes::<D>(), "desc.", |r: &mut R| &mut r.desc);
    out.extend(inside(
        non_finite(&floats!(D: units_per_metre, crowd_units_per_metre)),
        "desc.",
        |r: &mut R| &mut r.desc,
    ));
    // The hips (first), the head and the last bone.
    out.extend(non_finite_bones(&[0, 5, 64]));
    let nulls: [Named; 3] = [
        ("bone_names NULL", |r| r.nulls[0] = true),
        ("parents NULL", |r| r.nulls[1] = true),
        ("rest_translations NULL", |r| r.nulls[2] = true),
    ];
    out.extend(nulls.map(|(what, apply)| change(what, NULL_ARG, apply)));
    let invalid: [Named; 41] = [
        ("bone_count 0", |r| r.desc.bone_count = 0),
        ("bone_count 65537 (CG_MAX_RIG_BONES + 1)", |r| {
            r.desc.bone_count = 65537
        }),
        ("bone_count UINT32_MAX", |r| r.desc.bone_count = u32::MAX),
        ("the name of bone 3 NULL", |r| r.nulls[3] = true),
        ("an empty name", |r| r.name(7, b"")),
        ("a name of spaces", |r| r.name(7, b"   ")),
        ("a name of 1025 bytes", |r| r.name(20, &[b'x'; 1025])),
        ("a name of 100000 bytes", |r| r.name(20, &[b'x'; 100_000])),
        ("a name that is not UTF-8", |r| r.name(20, b"Left\xffHand")),
        ("a name cut inside a UTF-8 sequence", |r| {
            r.name(20, "Kopf\u{e9}".as_bytes().split_last().unwrap().1)
        }),
        ("two bones of one name", |r| {
            r.names[12] = r.names[11].clone()
        }),
        ("a parent that is the bone itself", |r| r.parents[4] = 4),
        ("a parent after its child", |r| r.parents[4] = 10),
        ("parent -2", |r| r.parents[4] = -2),
        ("parent INT32_MIN", |r| r.parents[4] = i32::MIN),
        ("parent 65 (bone_count)", |r| r.parents[64] = 65),
        ("a zero rest rotation", |r| r.rotations[5] = ZERO_QUAT),
        ("units_per_metre 0", |r| r.desc.units_per_metre = 0.0),
        ("units_per_metre -100", |r| r.desc.units_per_metre = -100.0),
        ("units_per_metre 1e7", |r| r.desc.units_per_metre = 1e7),
        ("units_per_metre 1e-3 (a bone over 1 km)", |r| {
            r.desc.units_per_metre = 1e-3
        }),
        ("crowd_units_per_metre 0", |r| {
            r.desc.crowd_units_per_metre = 0.0
        }),
        ("crowd_units_per_metre 1e7", |r| {
            r.desc.crowd_units_per_metre = 1e7
        }),
        ("up 6", |r| r.desc.up = 6),
        ("forward 0x7FFFFFFF", |r| r.desc.forward = 0x7FFF_FFFF),
        ("up = forward", |r| (r.desc.up, r.desc.forward) = (2, 2)),
        ("forward = -up", |r| (r.desc.up, r.desc.forward) = (2, 3)),
        ("crowd_up CG_RIG_AXIS_DETECT", |r| {
            r.desc.crowd_up = CG_RIG_AXIS_DETECT
        }),
        ("crowd_forward 6", |r| r.desc.crowd_forward = 6),
        ("crowd_up = crowd_forward", |r| r.desc.crowd_forward = 2),
        ("bone_map 'Spine' (no role)", |r| r.map("Spine")),
        ("bone_map 'Spine=elbow'", |r| r.map("Spine=elbow")),
        ("bone_map '=head'", |r| r.map("=head")),
        ("bone_map naming no bone", |r| r.map("Jaw=head")),
        ("bone_map naming a bone twice", |r| {
            r.map("Spine=spine,spine=neck")
        }),
        ("bone_map not UTF-8", |r| {
            r.bone_map = Some(b"Spine=\xff\0".to_vec())
        }),
        ("bone_map stopping the chain at Spine1", |r| {
            r.map("mixamorig:Spine1=none")
        }),
        ("bone_map leaving one eye", |r| r.map("RightEye=none")),
        ("bone_map taking the head away", |r| r.map("Head=none")),
        ("bone_map making two heads", |r| {
            r.map("HeadTop_End=head,LeftEye=none,RightEye=none")
        }),
        ("bone_map putting a neck bone below spine bones", |r| {
            r.map("Spine=neck")
        }),
    ];
    out.extend(invalid.map(|(what, apply)| change(what, INVALID, apply)));
    out
}

/// A skeleton with nothing showing where it faces (no side, eyes or toes), or whose head is
/// level with its root.
fn bare_skeleton(flat: bool) -> RigInput {
    let names: Vec<Vec<u8>> = ["Hips", "Spine", "Neck", "Head"]
        .iter()
        .map(|n| [n.as_bytes(), b"\0"].concat())
        .collect();
    let rise = if flat { 0.0 } else { 0.2 };
    let mut input = rig_input_of(names, vec![-1, 0, 1, 2]);
    input.translations = vec![
        cg_vec3 {
            x: 0.0,
            y: 1.0,
            z: 0.0,
        },
        cg_vec3 {
            x: 0.0,
            y: rise,
            z: 0.1,
        },
        cg_vec3 {
            x: 0.0,
            y: rise,
            z: 0.1,
        },
        cg_vec3 {
            x: 0.0,
            y: rise,
            z: 0.1,
        },
    ];
    input
}

fn rig_input_of(names: Vec<Vec<u8>>, parents: Vec<i32>) -> RigInput {
    let count = names.len();
    let mut desc = Skeleton::mixamo().desc(1.0);
    desc.bone_count = count as u32;
    desc.units_per_metre = 1.0;
    RigInput {
        desc,
        names,
        parents,
        translations: vec![cg_vec3::default(); count],
        rotations: vec![cg_quat::IDENTITY; count],
        bone_map: None,
        nulls: [false; 4],
    }
}

/// The arguments of `cg_rig_base_pose` and `cg_rig_write_joints`: the posed bones, the
/// joints of the chain, the counts.
#[derive(Clone)]
struct PoseInput {
    bones: Vec<cg_quat>,
    bone_count: usize,
    joints: [cg_quat; 7],
    /// Joints given (`write_joints`) or room for them (`base_pose`).
    joint_count: usize,
    /// Pass as NULL: the rig, the bones, the joints (or the output).
    nulls: [bool; 3],
}

fn pose_input(_: &Harness) -> PoseInput {
    let skeleton = Skeleton::mixamo();
    PoseInput {
        bones: skeleton.animated(1.3),
        bone_count: 65,
        joints: std::array::from_fn(|k| {
            let angle = 0.05 * (k as f32 + 1.0);
            cg_quat {
                x: 0.0,
                y: angle.sin(),
                z: 0.0,
                w: angle.cos(),
            }
        }),
        joint_count: 7,
        nulls: [false; 3],
    }
}

impl PoseInput {
    fn rig(&self, h: &Harness) -> *const cg_rig {
        or_null(h.rig, self.nulls[0])
    }
}

/// NaN and infinities in each component of `array[index]` of the inputs `pick` names, and
/// a zero rotation there.
fn bad_rotations(
    array: &'static str,
    indices: &[usize],
    pick: fn(&mut PoseInput) -> &mut [cg_quat],
) -> Vec<Corruption<PoseInput>> {
    let mut out = Vec::new();
    for &index in indices {
        for (component, label) in ["x", "y", "z", "w"].iter().enumerate() {
            for (bad, value) in BAD_FLOATS {
                out.push(change(
                    format!("{array}[{index}].{label} = {bad}"),
                    NON_FINITE,
                    move |p: &mut PoseInput| {
                        let q = &mut pick(p)[index];
                        *[&mut q.x, &mut q.y, &mut q.z, &mut q.w][component] = value;
                    },
                ));
            }
        }
        out.push(change(
            format!("{array}[{index}] zero"),
            INVALID,
            move |p: &mut PoseInput| pick(p)[index] = ZERO_QUAT,
        ));
    }
    out
}

fn pose_corruptions(joints_name: &'static str) -> Vec<Corruption<PoseInput>> {
    type P = PoseInput;
    let mut out = vec![
        change("rig NULL", NULL_ARG, |p: &mut P| p.nulls[0] = true),
        change("bone_rotations NULL", NULL_ARG, |p: &mut P| {
            p.nulls[1] = true
        }),
        change(format!("{joints_name} NULL"), NULL_ARG, |p: &mut P| {
            p.nulls[2] = true
        }),
        change("bone_count 64 (the rig has 65)", INVALID, |p: &mut P| {
            p.bone_count = 64
        }),
        change("bone_count 66 (the rig has 65)", INVALID, |p: &mut P| {
            p.bone_count = 66
        }),
        change("(bone_rotations NULL, 0)", INVALID, |p: &mut P| {
            (p.nulls[1], p.bone_count) = (true, 0)
        }),
        change("bone_count SIZE_MAX", INVALID, |p: &mut P| {
            p.bone_count = usize::MAX
        }),
        change("joints 6 (the chain has 7)", INVALID, |p: &mut P| {
            p.joint_count = 6
        }),
        change(format!("({joints_name} NULL, 0)"), INVALID, |p: &mut P| {
            (p.nulls[2], p.joint_count) = (true, 0)
        }),
    ];
    // The hips (folded into the first joint) and the head; a finger is read by no joint
    // (tests/ffi_rig.rs: anything there is accepted and left as it is).
    let pick: fn(&mut P) -> &mut [cg_quat] = |p| &mut p.bones;
    out.extend(bad_rotations("bone_rotations", &[0, 5], pick));
    out
}

/// The bytes of rotations (NaN equal to itself).
fn bits(rotations: &[cg_quat]) -> Vec<u8> {
    bytes_of(rotations).to_vec()
}

pub(crate) fn rows_rig(t: &mut Table) {
    t.case("cg_rig_desc_init", "desc NULL", NULL_ARG, |_| unsafe {
        cg_rig_desc_init(null_mut())
    });
    bad_output_sizes(
        t,
        "cg_rig_desc_init",
        size_of::<cg_rig_desc>(),
        |_, out| unsafe { cg_rig_desc_init(out) },
    );

    let f = "cg_rig_create";
    t.case(f, "desc NULL", NULL_ARG, |h| unsafe {
        cg_rig_create(null(), &mut h.out.rig)
    });
    t.case(f, "out_rig NULL", NULL_ARG, |h| {
        rig_input(h).create_into(null_mut())
    });
    t.corrupt(Setup::Online, f, create_corruptions(), rig_input, |h, r| {
        r.create(h)
    });
    t.case(f, "a facing the rest pose does not show", INVALID, |h| {
        bare_skeleton(false).create(h)
    });
    t.case(f, "the head level with the root at rest", INVALID, |h| {
        let mut input = bare_skeleton(true);
        input.desc.forward = 4;
        input.create(h)
    });

    let f = "cg_rig_chain";
    t.case(f, "rig NULL", NULL_ARG, |h| unsafe {
        cg_rig_chain(null(), &mut h.out.chain)
    });
    t.case(f, "out_chain NULL", NULL_ARG, |h| unsafe {
        cg_rig_chain(h.rig, null_mut())
    });
    bad_output_sizes(t, f, size_of::<cg_chain_desc>(), |h, out| unsafe {
        cg_rig_chain(h.rig, out)
    });

    type Count = unsafe extern "C" fn(*const cg_rig, *mut u32) -> cg_status;
    let counts: [(&'static str, Count); 2] = [
        ("cg_rig_bone_count", cg_rig_bone_count),
        ("cg_rig_joint_count", cg_rig_joint_count),
    ];
    for (f, count) in counts {
        t.case(f, "rig NULL", NULL_ARG, move |h| unsafe {
            count(null(), &mut h.out.id)
        });
        t.case(f, "out_count NULL", NULL_ARG, move |h| unsafe {
            count(h.rig, null_mut())
        });
    }

    type List = unsafe extern "C" fn(*const cg_rig, *mut u32, usize) -> cg_status;
    let lists: [(&'static str, &'static str, usize, List); 2] = [
        ("cg_rig_chain_bones", "joints", 7, cg_rig_chain_bones),
        ("cg_rig_bone_roles", "bones", 65, cg_rig_bone_roles),
    ];
    for (f, of, needed, list) in lists {
        t.case(f, "rig NULL", NULL_ARG, move |h| unsafe {
            list(null(), h.out.bones.as_mut_ptr(), needed)
        });
        t.case(f, "output NULL with a length", NULL_ARG, move |h| unsafe {
            list(h.rig, null_mut(), needed)
        });
        t.case(
            f,
            format!("out_len {} (the rig has {needed} {of})", needed - 1),
            INVALID,
            move |h| unsafe { list(h.rig, h.out.bones.as_mut_ptr(), needed - 1) },
        );
        t.case(f, "(NULL, 0)", INVALID, move |h| unsafe {
            list(h.rig, null_mut(), 0)
        });
        t.case(f, "output misaligned", INVALID, move |h| unsafe {
            let misaligned = h.out.bones.as_mut_ptr().cast::<u8>().add(1).cast::<u32>();
            list(h.rig, misaligned, needed)
        });
    }

    let f = "cg_rig_base_pose";
    t.corrupt(
        Setup::Online,
        f,
        pose_corruptions("out_base"),
        pose_input,
        |h, p| {
            let before = bits(&p.bones);
            let bones = or_null(p.bones.as_ptr(), p.nulls[1]);
            let out = or_null_mut(h.out.quats.as_mut_ptr(), p.nulls[2]);
            let status =
                unsafe { cg_rig_base_pose(p.rig(h), bones, p.bone_count, out, p.joint_count) };
            if before != bits(&p.bones) {
                h.note("changed bone_rotations");
            }
            status
        },
    );

    let f = "cg_rig_write_joints";
    let mut write = pose_corruptions("joints");
    write.push(change(
        "joints 8 (the chain has 7)",
        INVALID,
        |p: &mut PoseInput| p.joint_count = 8,
    ));
    let pick: fn(&mut PoseInput) -> &mut [cg_quat] = |p| &mut p.joints;
    write.extend(bad_rotations("joints", &[0, 4, 6], pick));
    t.corrupt(Setup::Online, f, write, pose_input, |h, p| {
        let mut joints = [cg_quat::IDENTITY; 8];
        joints[..7].copy_from_slice(&p.joints);
        let before = bits(&p.bones);
        let joints = or_null(joints.as_ptr(), p.nulls[2]);
        let bones = or_null_mut(p.bones.as_mut_ptr(), p.nulls[1]);
        let status =
            unsafe { cg_rig_write_joints(p.rig(h), joints, p.joint_count, bones, p.bone_count) };
        if before != bits(&p.bones) {
            h.note("wrote into bone_rotations");
        }
        status
    });

    t.no_failure_modes(
        "cg_rig_destroy",
        "returns nothing; NULL is accepted and ignored",
        || {
            let before = set_sentinel_error();
            unsafe { cg_rig_destroy(null_mut()) };
            assert_eq!(last_error(), before);
        },
    );
    t.no_failure_modes(
        "cg_rig_report",
        "returns a length; a NULL rig gives 0, a NULL or short buffer is documented",
        check_report,
    );
}

/// `cg_rig_report` with a NULL rig, a NULL buffer, a zero length, a one-byte buffer and a
/// short one: the full length always comes back, at most `len - 1` bytes and a NUL are
/// written.
fn check_report() {
    let skeleton = Skeleton::mixamo();
    let rig = skeleton.rig(1.0);
    let length = unsafe { cg_rig_report(rig.0, null_mut(), 0) };
    assert!(length > 100, "{length}");
    let mut buf = [0x5Au8; 64];
    let pointer = buf.as_mut_ptr().cast::<c_char>();
    assert_eq!(unsafe { cg_rig_report(null(), pointer, 64) }, 0);
    assert!(buf.iter().all(|&b| b == 0x5A), "a NULL rig wrote");
    assert_eq!(unsafe { cg_rig_report(rig.0, pointer, 0) }, length);
    assert!(buf.iter().all(|&b| b == 0x5A), "len 0 wrote");
    assert_eq!(unsafe { cg_rig_report(rig.0, pointer, 1) }, length);
    assert_eq!(buf[0], 0, "len 1 writes the NUL alone");
    assert!(buf[1..].iter().all(|&b| b == 0x5A));
    assert_eq!(unsafe { cg_rig_report(rig.0, pointer, 6) }, length);
    assert_eq!(&buf[..6], b"gaze \0");
    assert!(buf[6..].iter().all(|&b| b == 0x5A), "wrote past len");
}
