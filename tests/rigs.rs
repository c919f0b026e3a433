//! The rigs people ship, each from its published hierarchy (`tests/data/rigs/*.rig`, sources
//! in each file and in its README): every one maps with the default rules and no override
//! to the chain its `expect` line gives — root, spine, neck, head and eyes — facing the way
//! its `up` and `forward` lines say, found from the rest pose alone — also mirrored, as
//! Unreal's left-handed numbers give it; and each frame's conversions go round on it.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crowdgaze::skeleton_map::{map_skeleton, parse_axis, BoneMap, RestBone, SkeletonOptions};
use crowdgaze::world::Axis;
use glam::{Quat, Vec3};

/// A rig read from its file.
struct Rig {
    file: String,
    names: Vec<String>,
    parents: Vec<Option<usize>>,
    translations: Vec<Vec3>,
    rotations: Vec<Quat>,
    units_per_metre: f32,
    up: Axis,
    forward: Axis,
    /// `root`, `spine`, `neck`, `head`, `eyes` → bone names.
    expect: HashMap<String, Vec<String>>,
}

fn rig_files() -> Vec<PathBuf> {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/rigs");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&folder)
        .unwrap_or_else(|e| panic!("{}: {e}", folder.display()))
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|e| e == "rig"))
        .collect();
    files.sort();
    files
}

fn read_rig(path: &Path) -> Rig {
    let file = path.file_name().unwrap().to_string_lossy().into_owned();
    let text = std::fs::read_to_string(path).unwrap();
    let mut rig = Rig {
        file: file.clone(),
        names: Vec::new(),
        parents: Vec::new(),
        translations: Vec::new(),
        rotations: Vec::new(),
        units_per_metre: 1.0,
        up: Axis::PositiveY,
        forward: Axis::PositiveZ,
        expect: HashMap::new(),
    };
    let mut index: HashMap<String, usize> = HashMap::new();
    for line in text.lines() {
        let line = line.trim();
        if let Some(value) = line.strip_prefix("# units_per_metre:") {
            rig.units_per_metre = value.trim().parse().unwrap();
        } else if let Some(value) = line.strip_prefix("# up:") {
            let axis = value.split_whitespace().next().unwrap();
            rig.up = parse_axis(axis).unwrap_or_else(|| panic!("{file}: up {axis}"));
        } else if let Some(value) = line.strip_prefix("# forward:") {
            let axis = value.split_whitespace().next().unwrap();
            rig.forward = parse_axis(axis).unwrap_or_else(|| panic!("{file}: forward {axis}"));
        } else if let Some(value) = line.strip_prefix("# expect") {
            for pair in value.split_whitespace() {
                let (key, bones) = pair.split_once('=').unwrap();
                let bones = match bones {
                    "none" => Vec::new(),
                    list => list.split(',').map(str::to_string).collect(),
                };
                rig.expect.insert(key.to_string(), bones);
            }
        } else if let Some(value) = line.strip_prefix("bone ") {
            let fields: Vec<&str> = value.split_whitespace().collect();
            assert!(fields.len() == 5 || fields.len() == 9, "{file}: {line}");
            let parent = match fields[1] {
                "-" => None,
                name => Some(
                    *index
                        .get(name)
                        .unwrap_or_else(|| panic!("{file}: parent {name} before {line}")),
                ),
            };
            let number = |i: usize| -> f32 { fields[i].parse().unwrap() };
            index.insert(fields[0].to_string(), rig.names.len());
            rig.names.push(fields[0].to_string());
            rig.parents.push(parent);
            rig.translations
                .push(Vec3::new(number(2), number(3), number(4)));
            rig.rotations.push(if fields.len() == 9 {
                Quat::from_xyzw(number(5), number(6), number(7), number(8)).normalize()
            } else {
                Quat::IDENTITY
            });
        }
    }
    assert!(!rig.names.is_empty(), "{file}: no bones");
    for key in ["root", "spine", "neck", "head", "eyes"] {
        assert!(rig.expect.contains_key(key), "{file}: expect has no {key}");
    }
    rig
}

impl Rig {
    /// The rig mirrored across its sagittal plane (left and right swapped in space, not in
    /// name): what a left-handed engine's raw numbers look like in a right-handed reading.
    fn mirrored(&self) -> Rig {
        let left = self.up.vector().cross(self.forward.vector());
        let mirror = |v: Vec3| v - 2.0 * v.dot(left) * left;
        Rig {
            file: format!("{} mirrored", self.file),
            names: self.names.clone(),
            parents: self.parents.clone(),
            translations: self.translations.iter().map(|&t| mirror(t)).collect(),
            rotations: self
                .rotations
                .iter()
                .map(|q| {
                    let axis = -mirror(Vec3::new(q.x, q.y, q.z));
                    Quat::from_xyzw(axis.x, axis.y, axis.z, q.w)
                })
                .collect(),
            units_per_metre: self.units_per_metre,
            up: self.up,
            forward: self.forward,
            expect: self.expect.clone(),
        }
    }

    fn bones(&self) -> Vec<RestBone<'_>> {
        (0..self.names.len())
            .map(|i| RestBone {
                name: &self.names[i],
                parent: self.parents[i],
                translation: self.translations[i],
                rotation: self.rotations[i],
            })
            .collect()
    }

    fn names_of(&self, bones: &[usize]) -> Vec<String> {
        bones.iter().map(|&b| self.names[b].clone()).collect()
    }
}

#[test]
fn every_published_rig_maps_with_the_default_rules() {
    let files = rig_files();
    assert!(files.len() >= 17, "{} rig files", files.len());
    let mut failures = Vec::new();
    let rigs = files.iter().map(|path| read_rig(path));
    for rig in rigs.flat_map(|rig| [rig.mirrored(), rig]) {
        let bones = rig.bones();
        let options = SkeletonOptions {
            units_per_metre: rig.units_per_metre,
            ..SkeletonOptions::default()
        };
        let mapped = match map_skeleton(&bones, &BoneMap::default(), &options) {
            Ok(mapped) => mapped,
            Err(error) => {
                failures.push(format!("{}: {error}", rig.file));
                continue;
            }
        };
        let chain = &mapped.chain;
        let spine = chain.spine_count();
        let neck = chain.cervical_count();
        let body = chain.body_count();
        let got: HashMap<&str, Vec<String>> = HashMap::from([
            ("root", vec![rig.names[mapped.root].clone()]),
            ("spine", rig.names_of(&mapped.bones[..spine])),
            ("neck", rig.names_of(&mapped.bones[spine..spine + neck])),
            ("head", rig.names_of(&mapped.bones[body - 1..body])),
            ("eyes", rig.names_of(&mapped.bones[body..])),
        ]);
        for (key, want) in &rig.expect {
            if got.get(key.as_str()) != Some(want) {
                failures.push(format!(
                    "{}: {key} is {:?}, the rig's published chain says {want:?}\n{}",
                    rig.file,
                    got.get(key.as_str()),
                    mapped.report()
                ));
            }
        }
        if (mapped.up, mapped.forward) != (rig.up, rig.forward) {
            failures.push(format!(
                "{}: detected up {:?} forward {:?}, the rig is up {:?} forward {:?}",
                rig.file, mapped.up, mapped.forward, rig.up, rig.forward
            ));
        }
        // The rest pose's locals give the chain's rest; a pose written back reads back.
        let mut base = vec![Quat::IDENTITY; mapped.joint_count()];
        mapped.base_pose(&rig.rotations, &mut base).unwrap();
        for (k, joint) in chain.joints().iter().enumerate() {
            assert!(
                base[k].abs_diff_eq(joint.rest, 1e-4),
                "{}: joint {k}",
                rig.file
            );
        }
        let joints: Vec<Quat> = (0..mapped.joint_count())
            .map(|k| Quat::from_rotation_y(0.1 * k as f32) * base[k])
            .collect();
        let mut locals = rig.rotations.clone();
        mapped.write_joints(&joints, &mut locals).unwrap();
        mapped.base_pose(&locals, &mut base).unwrap();
        for (k, (got, want)) in base.iter().zip(&joints).enumerate() {
            assert!(got.abs_diff_eq(*want, 1e-4), "{}: joint {k} back", rig.file);
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}
