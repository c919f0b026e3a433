//! Eyelids as rigs carry them: upper-lid bones found by name (the library's skeleton map
//! leaves lid bones out of the chain), blink blend shapes found by name (ARKit, VRM, plain
//! `blink`), and the angle a lid bone turns for the library's lid pitch and closure.

use crowdgaze::skeleton_map::{read_name, Side};

/// How far an upper lid turns down from open to closed, radians (35°: an upper lid covers
/// the cornea from about 10° above the pupil to below it).
pub const CLOSED_LID_ANGLE: f32 = 35.0 * std::f32::consts::PI / 180.0;

/// The angle (radians, positive down, about the head's lateral axis) an upper-lid bone
/// turns from its animated pose for the library's lid `pitch` (radians, positive up) and
/// `closure` (0 open, 1 closed), times `influence` (0 to 1).
pub fn lid_angle(pitch: f32, closure: f32, influence: f32) -> f32 {
    let closure = closure.clamp(0.0, 1.0);
    let open = -pitch;
    (open + (CLOSED_LID_ANGLE - open) * closure) * influence.clamp(0.0, 1.0)
}

/// Words that make a lid bone a lower one.
const LOWER: &[&str] = &["lower", "low", "bottom", "bot", "b", "down", "dn"];
/// Words that make a lid bone an upper one.
const UPPER: &[&str] = &["upper", "up", "top", "t"];

/// The upper-lid bones of a skeleton, left and right, by name: a bone whose name has the
/// word `eyelid` or `lid` (`eyelid_upper_l`, `LeftEyelid`, `UpperLid.L`, `lid.T.L`) and a
/// side, not a lower lid (`lower`, `bottom`, `.B`); a name saying `upper` wins over one
/// that says neither. Helper and control bones are left out.
pub fn find_upper_lids<'a>(names: impl IntoIterator<Item = &'a str>) -> [Option<usize>; 2] {
    // (bone, explicitly upper) for each side.
    let mut found: [Option<(usize, bool)>; 2] = [None, None];
    for (bone, name) in names.into_iter().enumerate() {
        let read = read_name(name);
        if read.helper {
            continue;
        }
        let has = |list: &[&str]| read.words.iter().any(|w| list.contains(&w.as_str()));
        let lid = read
            .words
            .iter()
            .any(|w| w == "lid" || w == "eyelid" || w == "eyelids");
        if !lid || has(LOWER) {
            continue;
        }
        let side = match read.side {
            Side::Left => 0,
            Side::Right => 1,
            Side::Centre => continue,
        };
        let upper = has(UPPER);
        match found[side] {
            Some((_, true)) => {}
            Some((_, false)) if !upper => {}
            _ => found[side] = Some((bone, upper)),
        }
    }
    [found[0].map(|f| f.0), found[1].map(|f| f.0)]
}

/// Blend shape names tried, in order, for each eye (left, right) and for both at once.
const LEFT_SHAPES: &[&str] = &[
    "eyeBlinkLeft",
    "eyeBlink_L",
    "Blink_L",
    "blink_l",
    "BlinkLeft",
];
const RIGHT_SHAPES: &[&str] = &[
    "eyeBlinkRight",
    "eyeBlink_R",
    "Blink_R",
    "blink_r",
    "BlinkRight",
];
const BOTH_SHAPES: &[&str] = &[
    "Blink",
    "blink",
    "eyesClosed",
    "EyesClosed",
    "Fcl_EYE_Close",
];

/// The blend shapes a mesh closes its eyes with: indices into its blend shape names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct BlinkShapes {
    /// The left eye's blink shape.
    pub left: Option<usize>,
    /// The right eye's blink shape.
    pub right: Option<usize>,
    /// One shape that closes both eyes (used when neither eye has its own).
    pub both: Option<usize>,
}

impl BlinkShapes {
    /// True if no shape was found.
    pub fn is_empty(&self) -> bool {
        self.left.is_none() && self.right.is_none() && self.both.is_none()
    }

    /// Each shape found with the value it takes for the eyes' closures (left, right):
    /// `(shape, value)` pairs, at most two.
    pub fn values(&self, left: f32, right: f32) -> impl Iterator<Item = (usize, f32)> {
        let both = if self.left.is_none() && self.right.is_none() {
            self.both.map(|shape| (shape, left.max(right)))
        } else {
            None
        };
        self.left
            .map(|shape| (shape, left))
            .into_iter()
            .chain(self.right.map(|shape| (shape, right)))
            .chain(both)
    }
}

/// A mesh's blink shapes as a character drives them each frame: their values, and none
/// once the influence has stayed 0 since the shapes were last set (the animation's then).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct BlinkWriter {
    /// The shapes.
    pub shapes: BlinkShapes,
    /// True once the shapes were set with an influence above 0.
    written: bool,
}

impl BlinkWriter {
    /// A writer for `shapes`, nothing set yet.
    pub fn new(shapes: BlinkShapes) -> Self {
        BlinkWriter {
            shapes,
            written: false,
        }
    }

    /// The `(shape, value)` pairs to set this frame: the eyes' closures times `weight` (the
    /// influence); at weight 0 they are set to 0 once, then left alone.
    pub fn frame(&mut self, left: f32, right: f32, weight: f32) -> [Option<(usize, f32)>; 2] {
        let mut out = [None, None];
        if weight <= 0.0 && !self.written {
            return out;
        }
        self.written = weight > 0.0;
        let weight = weight.clamp(0.0, 1.0);
        for (slot, pair) in out
            .iter_mut()
            .zip(self.shapes.values(left * weight, right * weight))
        {
            *slot = Some(pair);
        }
        out
    }
}

/// Finds a mesh's blink shapes among its blend shape `names`. `overrides` (the node's
/// `eyelid_shapes`: empty, one name for both eyes, or `left,right`) replaces the
/// automatic choice (ARKit `eyeBlinkLeft`/`eyeBlinkRight`, VRM `Blink_L`/`Blink_R`/`Blink`,
/// `blink`). Errors name an override the mesh does not have, and list its shapes.
pub fn find_blink_shapes(names: &[String], overrides: &str) -> Result<BlinkShapes, String> {
    let find = |wanted: &str| names.iter().position(|n| n == wanted);
    let overrides = overrides.trim();
    if !overrides.is_empty() {
        let parts: Vec<&str> = overrides.split(',').map(str::trim).collect();
        let lookup = |name: &str| {
            find(name).ok_or_else(|| {
                format!(
                    "eyelid_shapes names '{name}', which the mesh does not have (its blend \
                     shapes: {}); give one name, or 'left,right'",
                    if names.is_empty() {
                        "none".to_string()
                    } else {
                        names.join(", ")
                    }
                )
            })
        };
        return match parts.as_slice() {
            [both] => Ok(BlinkShapes {
                both: Some(lookup(both)?),
                ..BlinkShapes::default()
            }),
            [left, right] => Ok(BlinkShapes {
                left: Some(lookup(left)?),
                right: Some(lookup(right)?),
                both: None,
            }),
            _ => Err(format!(
                "eyelid_shapes = '{overrides}': give one blend shape name, or 'left,right'"
            )),
        };
    }
    let first = |list: &[&str]| list.iter().find_map(|name| find(name));
    Ok(BlinkShapes {
        left: first(LEFT_SHAPES),
        right: first(RIGHT_SHAPES),
        both: first(BOTH_SHAPES),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lids(names: &[&str]) -> [Option<usize>; 2] {
        find_upper_lids(names.iter().copied())
    }

    #[test]
    fn upper_lid_bones_are_found_by_name() {
        assert_eq!(
            lids(&["Head", "eyelid_upper_l", "eyelid_upper_r"]),
            [Some(1), Some(2)]
        );
        assert_eq!(
            lids(&["Head", "LeftEyelid", "RightEyelid"]),
            [Some(1), Some(2)]
        );
        assert_eq!(lids(&["UpperLid.R", "UpperLid.L"]), [Some(1), Some(0)]);
        assert_eq!(
            lids(&["lid.B.L", "lid.T.L", "lid.T.R", "lid.B.R"]),
            [Some(1), Some(2)]
        );
        // Lower lids, eyes and centre bones are not upper lids; "upper" wins.
        assert_eq!(
            lids(&["eyelid_lower_l", "LeftEye", "Eyelid", "LowerLid.R"]),
            [None, None]
        );
        assert_eq!(lids(&["Eyelid_L", "Eyelid_Upper_L"]), [Some(1), None]);
        assert_eq!(lids(&["Eyelid_Upper_L", "Eyelid_L"]), [Some(0), None]);
        assert_eq!(lids(&["MCH-lid.T.L", "ORG-lid.T.R"]), [None, None]);
    }

    #[test]
    fn blink_shapes_are_found_or_named() {
        let names = |list: &[&str]| list.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let arkit = names(&["jawOpen", "eyeBlinkLeft", "eyeBlinkRight"]);
        let found = find_blink_shapes(&arkit, "").unwrap();
        assert_eq!(
            (found.left, found.right, found.both),
            (Some(1), Some(2), None)
        );
        let values: Vec<_> = found.values(0.25, 0.5).collect();
        assert_eq!(values, vec![(1, 0.25), (2, 0.5)]);
        let vrm = names(&["A", "Blink", "Blink_L", "Blink_R"]);
        let found = find_blink_shapes(&vrm, "").unwrap();
        assert_eq!((found.left, found.right), (Some(2), Some(3)));
        let plain = names(&["smile", "blink"]);
        let found = find_blink_shapes(&plain, "").unwrap();
        assert_eq!(found.values(0.5, 0.7).collect::<Vec<_>>(), vec![(1, 0.7)]);
        assert!(find_blink_shapes(&names(&["smile"]), "")
            .unwrap()
            .is_empty());
        let named = find_blink_shapes(&plain, "smile").unwrap();
        assert_eq!(named.both, Some(0));
        let text = find_blink_shapes(&plain, "wink").unwrap_err();
        assert!(
            text.contains("'wink'") && text.contains("smile, blink"),
            "{text}"
        );
        assert!(find_blink_shapes(&plain, "a,b,c").is_err());
    }

    #[test]
    fn a_blink_writer_sets_zero_once_then_leaves_the_shapes() {
        let shapes = BlinkShapes {
            left: Some(3),
            right: Some(4),
            both: None,
        };
        let mut writer = BlinkWriter::new(shapes);
        assert_eq!(writer.frame(1.0, 1.0, 0.0), [None, None]);
        assert_eq!(
            writer.frame(0.8, 0.6, 0.5),
            [Some((3, 0.4)), Some((4, 0.3))]
        );
        assert_eq!(
            writer.frame(0.8, 0.6, 0.0),
            [Some((3, 0.0)), Some((4, 0.0))]
        );
        assert_eq!(writer.frame(0.8, 0.6, 0.0), [None, None]);
    }

    #[test]
    fn lid_angle_follows_pitch_and_closes() {
        assert_eq!(lid_angle(0.1, 0.0, 1.0), -0.1);
        assert!((lid_angle(0.1, 1.0, 1.0) - CLOSED_LID_ANGLE).abs() < 1e-6);
        assert!((lid_angle(0.0, 1.0, 0.5) - CLOSED_LID_ANGLE / 2.0).abs() < 1e-6);
        assert_eq!(lid_angle(0.3, 1.0, 0.0), 0.0);
    }
}
