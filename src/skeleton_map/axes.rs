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

/// The direction a skeleton faces at rest, and how it was found: `left × up`, left from the
/// left and right bone pairs; else the way from the head to the eyes; else from the feet to
/// the toes. Fails with [`Error::InvalidArgument`] asking for the forward axis if none of
/// them shows it.
pub(super) fn detect_forward(
    bones: &[RestBone<'_>],
    globals: &[(Quat, Vec3)],
    up_axis: Axis,
    eyes: Option<[usize; 2]>,
    head: usize,
) -> Result<(Axis, FacingFrom)> {
    let up = up_axis.vector();
    let left = on_ground(left_from_pairs(bones, globals), up);
    let scale = globals
        .iter()
        .map(|(_, p)| p.length())
        .fold(0.0f32, f32::max)
        .max(1e-6);
    if left.length() > 1e-4 * scale {
        return Ok((nearest_axis(left.cross(up)), FacingFrom::SidePairs));
    }
    if let Some([left_eye, right_eye]) = eyes {
        let middle = 0.5 * (globals[left_eye].1 + globals[right_eye].1);
        let ahead = on_ground(middle - globals[head].1, up);
        if ahead.length() > 1e-4 * scale {
            return Ok((nearest_axis(ahead), FacingFrom::Eyes));
        }
    }
    if let (Some(toes), Some(feet)) = (
        mean_of(bones, globals, &["toe", "toes", "toebase", "ball"]),
        mean_of(bones, globals, &["foot", "ankle"]),
    ) {
        let ahead = on_ground(toes - feet, up);
        if ahead.length() > 1e-4 * scale {
            return Ok((nearest_axis(ahead), FacingFrom::Toes));
        }
    }
    Err(Error::InvalidArgument(
        "cannot tell which way the skeleton faces: no bones named as left and right pairs, \
         no eyes in front of the head, no toes in front of the feet; give the forward axis \
         (the direction the character faces at rest)"
            .into(),
    ))
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
