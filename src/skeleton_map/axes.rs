//! A skeleton's axes: the signed coordinate axis nearest to a direction, axis names, the
//! direction a skeleton faces from its rest pose (left and right bone pairs, else the eyes
//! in front of the head, else the toes in front of the feet), and the turn from one pair of
//! up and forward axes to another.

use glam::{Mat3, Quat, Vec3};

use super::names::{read_name, Side};
use super::{FacingFrom, RestBone};
use crate::error::{Error, Result};
use crate::world::Axis;

/// The signed coordinate axis nearest to `v`.
pub fn nearest_axis(v: Vec3) -> Axis {
    let a = v.abs();
    if a.x >= a.y && a.x >= a.z {
        if v.x >= 0.0 {
            Axis::PositiveX
        } else {
            Axis::NegativeX
        }
    } else if a.y >= a.z {
        if v.y >= 0.0 {
            Axis::PositiveY
        } else {
            Axis::NegativeY
        }
    } else if v.z >= 0.0 {
        Axis::PositiveZ
    } else {
        Axis::NegativeZ
    }
}

/// Parses an axis name: `x`, `+x`, `-x`, `y`, ... (case-insensitive).
pub fn parse_axis(text: &str) -> Option<Axis> {
    Some(match text.trim().to_ascii_lowercase().as_str() {
        "x" | "+x" => Axis::PositiveX,
        "-x" => Axis::NegativeX,
        "y" | "+y" => Axis::PositiveY,
        "-y" => Axis::NegativeY,
        "z" | "+z" => Axis::PositiveZ,
        "-z" => Axis::NegativeZ,
        _ => return None,
    })
}

/// `v` without its part along `up`.
fn on_ground(v: Vec3, up: Vec3) -> Vec3 {
    v - up * v.dot(up)
}

/// A name's words and number, which a left bone and its right twin share.
type PairKey = (Vec<String>, Option<u32>);

/// The character's left from the rest positions of bones whose names make a left and
/// right pair (the same words and number, opposite sides: `LeftArm`/`RightArm`,
/// `thigh_l`/`thigh_r`, `J_Bip_L_Hand`/`J_Bip_R_Hand`, `lShin`/`rShin`, `eye.L`/`eye.R`).
fn left_from_pairs(bones: &[RestBone<'_>], globals: &[(Quat, Vec3)]) -> Vec3 {
    use std::collections::HashMap;
    let mut lefts: HashMap<PairKey, usize> = HashMap::new();
    let mut rights: Vec<(usize, PairKey)> = Vec::new();
    for (index, bone) in bones.iter().enumerate() {
        let read = read_name(bone.name);
        match read.side {
            Side::Left => {
                lefts.entry(read.pair_key()).or_insert(index);
            }
            Side::Right => rights.push((index, read.pair_key())),
            Side::Centre => {}
        }
    }
    let mut left = Vec3::ZERO;
    for (right, key) in rights {
        if let Some(&index) = lefts.get(&key) {
            left += globals[index].1 - globals[right].1;
        }
    }
    left
}

/// The mean rest position of the bones whose name has one of `words`.
fn mean_of(bones: &[RestBone<'_>], globals: &[(Quat, Vec3)], words: &[&str]) -> Option<Vec3> {
    let (sum, count) = bones
        .iter()
        .enumerate()
        .filter(|(_, bone)| {
            let read = read_name(bone.name);
            !read.helper && read.words.iter().any(|w| words.contains(&w.as_str()))
        })
        .fold((Vec3::ZERO, 0), |(sum, count), (index, _)| {
            (sum + globals[index].1, count + 1)
        });
    (count > 0).then(|| sum / count as f32)
}

/// The direction a skeleton faces at rest, and how it was found: the way from the head to
/// the eyes; else from the feet to the toes; else `left × up`, left from the left and right
/// bone pairs. The eyes and toes come first: they show the facing in a mirrored
/// (left-handed) space too, such as Unreal's, where the side pairs would give it backwards.
/// Also says whether the side pairs point the other way (a mirrored space). Fails with
/// [`Error::InvalidArgument`] asking for the forward axis if none of them shows it, or if
/// the side pairs say the skeleton faces sideways of where its eyes or toes point.
pub(super) fn detect_forward(
    bones: &[RestBone<'_>],
    globals: &[(Quat, Vec3)],
    up_axis: Axis,
    eyes: Option<[usize; 2]>,
    head: usize,
) -> Result<(Axis, FacingFrom, bool)> {
    let up = up_axis.vector();
    let scale = globals
        .iter()
        .map(|(_, p)| p.length())
        .fold(0.0f32, f32::max)
        .max(1e-6);
    let shows = |v: Vec3| v.length() > 1e-4 * scale;
    let from_pairs = {
        let left = on_ground(left_from_pairs(bones, globals), up);
        shows(left).then(|| nearest_axis(left.cross(up)))
    };
    let from_eyes = eyes.and_then(|[left_eye, right_eye]| {
        let middle = 0.5 * (globals[left_eye].1 + globals[right_eye].1);
        let ahead = on_ground(middle - globals[head].1, up);
        shows(ahead).then(|| nearest_axis(ahead))
    });
    let from_toes = match (
        mean_of(bones, globals, &["toe", "toes", "toebase", "ball"]),
        mean_of(bones, globals, &["foot", "ankle"]),
    ) {
        (Some(toes), Some(feet)) => {
            let ahead = on_ground(toes - feet, up);
            shows(ahead).then(|| nearest_axis(ahead))
        }
        _ => None,
    };
    let geometric = from_eyes
        .map(|axis| (axis, FacingFrom::Eyes))
        .or(from_toes.map(|axis| (axis, FacingFrom::Toes)));
    match (geometric, from_pairs) {
        (Some((axis, how)), Some(pairs)) => {
            // The same, or mirrored (backwards): fine. Sideways: something is wrong.
            if pairs.vector().dot(axis.vector()) == 0.0 {
                return Err(Error::InvalidArgument(format!(
                    "the skeleton's left and right bones say it faces {pairs:?}, its {} say                      {axis:?}: give the forward axis",
                    if how == FacingFrom::Eyes { "eyes" } else { "toes" }
                )));
            }
            Ok((axis, how, pairs != axis))
        }
        (Some((axis, how)), None) => Ok((axis, how, false)),
        (None, Some(pairs)) => Ok((pairs, FacingFrom::SidePairs, false)),
        (None, None) => Err(Error::InvalidArgument(
            "cannot tell which way the skeleton faces: no eyes in front of the head, no toes \
             in front of the feet, no bones named as left and right pairs; give the forward \
             axis (the direction the character faces at rest)"
                .into(),
        )),
    }
}

/// The rotation that turns `from`'s up and forward onto `to`'s (both perpendicular pairs).
pub(super) fn turn_between(from: (Axis, Axis), to: (Axis, Axis)) -> Quat {
    let frame = |(up, forward): (Axis, Axis)| {
        let (up, forward) = (up.vector(), forward.vector());
        Mat3::from_cols(up, forward, up.cross(forward))
    };
    Quat::from_mat3(&(frame(to) * frame(from).transpose())).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn turns_take_one_pair_of_axes_onto_another() {
        let z_up = (Axis::PositiveZ, Axis::PositiveY);
        let y_up = (Axis::PositiveY, Axis::PositiveZ);
        let turn = turn_between(z_up, y_up);
        assert!((turn * Vec3::Z).abs_diff_eq(Vec3::Y, 1e-6));
        assert!((turn * Vec3::Y).abs_diff_eq(Vec3::Z, 1e-6));
        assert_eq!(turn_between(y_up, y_up), Quat::IDENTITY);
        assert_eq!(parse_axis("-Z"), Some(Axis::NegativeZ));
        assert_eq!(parse_axis("w"), None);
    }
}
