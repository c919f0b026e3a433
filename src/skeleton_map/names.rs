//! Bone names as importers and rigs write them, read into a role: the namespace, rig prefix
//! (`mixamorig`, `CC_Base_`, `J_Bip_C_`, `DEF-`, `FACIAL_`...), side (`Left`, `L_`, `_l`,
//! `.L`, `left_`, Daz's `lEye`) and case are set aside, the rest split into words
//! (`abdomenLower` → `abdomen lower`, `spine_01` → `spine 1`), and the words name the role.
//!
//! Which rigs' names this reads, and where each is published: `docs/your-character.md`.

use super::BoneRole;

/// Which side of the character a bone is on, as its name says.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Side {
    /// No side in the name.
    Centre,
    /// The character's left.
    Left,
    /// The character's right.
    Right,
}

/// A bone name read: its side, its words (lowercase letters) and the number it ends with.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReadName {
    /// The side the name gives.
    pub side: Side,
    /// The words, lowercase, without the side, the prefix and the number.
    pub words: Vec<String>,
    /// The number in the name (`spine_03` → 3, `Spine` → none).
    pub number: Option<u32>,
    /// True for a Blender Rigify deform bone (`DEF-` prefix).
    pub rigify_deform: bool,
    /// True for a control, mechanism or helper bone that never takes gaze (Rigify `ORG-`,
    /// `MCH-`, `CTRL`, `IK`, end sites, twist and roll helpers of the limbs...).
    pub helper: bool,
}

/// Rig prefixes set aside, lowercase, longest first where one starts another. A side letter
/// right after them (`J_Bip_L_`, `CC_Base_L_`) is read as the side.
const PREFIXES: &[&str] = &[
    "mixamorig",
    "cc_base_",
    "j_bip_",
    "j_adj_",
    "j_sec_",
    "j_opt_",
    "valvebiped.bip01_",
    "bip01_",
    "bip01 ",
    "bip001_",
    "bip001 ",
    "facial_",
    "def-",
    "def_",
];

/// Prefixes of bones that never take gaze: Rigify's original, mechanism and control bones,
/// and the usual control-rig prefixes.
const HELPER_PREFIXES: &[&str] = &["org-", "mch-", "ctrl_", "ctrl-", "ik_", "ik-", "vb "];

/// Words that make a bone a helper whatever else its name says.
const HELPER_WORDS: &[&str] = &[
    "end", "top", "nub", "tip", "site", "target", "ik", "ctrl", "control", "helper", "socket",
    "dummy", "null", "parent", "aim", "look", "lookat", "offset", "attach", "ref", "goal",
];

/// Spine words: lumbar and thoracic bones.
const SPINE_WORDS: &[&str] = &[
    "spine", "chest", "abdomen", "waist", "torso", "back", "thorax", "lumbar", "thoracic", "belly",
    "stomach",
];

/// Words of the body's root (where legs and spine meet).
const ROOT_WORDS: &[&str] = &["hips", "hip", "pelvis", "root", "cog"];

/// Eye words that make a bone part of the eye's surroundings, not the eye.
const NOT_EYE_WORDS: &[&str] = &[
    "lid",
    "lids",
    "eyelid",
    "brow",
    "brows",
    "eyebrow",
    "lash",
    "lashes",
    "eyelash",
    "blink",
    "corner",
    "squint",
    "wide",
    "cheek",
    "socket",
    "ring",
    "sclera",
    "pupil",
    "iris",
    "cornea",
    "highlight",
    "water",
    "tear",
    "lower",
    "upper",
    "inner",
    "outer",
    "in",
    "out",
    "up",
    "down",
];

/// Splits a name into lowercase words at separators, case changes and digits; digits make
/// a word of their own.
fn split_words(name: &str) -> Vec<String> {
    let mut words: Vec<String> = Vec::new();
    let mut current = String::new();
    let mut previous: Option<char> = None;
    let flush = |current: &mut String, words: &mut Vec<String>| {
        if !current.is_empty() {
            words.push(std::mem::take(current).to_lowercase());
        }
    };
    let chars: Vec<char> = name.chars().collect();
    for (i, &c) in chars.iter().enumerate() {
        if !c.is_alphanumeric() {
            flush(&mut current, &mut words);
            previous = None;
            continue;
        }
        if let Some(p) = previous {
            let next = chars.get(i + 1).copied();
            let boundary = (p.is_lowercase() && c.is_uppercase())
                || (p.is_ascii_digit() != c.is_ascii_digit())
                // `HTMLParser`: a capital followed by a lowercase letter after capitals.
                || (p.is_uppercase() && c.is_uppercase() && next.is_some_and(char::is_lowercase));
            if boundary {
                flush(&mut current, &mut words);
            }
        }
        current.push(c);
        previous = Some(c);
    }
    flush(&mut current, &mut words);
    words
}

/// The side word at the start or the end of `words`, taken out.
fn take_side(words: &mut Vec<String>) -> Side {
    let side_of = |word: &str| match word {
        "left" | "l" | "lf" | "lft" => Side::Left,
        "right" | "r" | "rt" | "rgt" => Side::Right,
        _ => Side::Centre,
    };
    if words.len() > 1 {
        let first = side_of(&words[0]);
        if first != Side::Centre {
            words.remove(0);
            return first;
        }
        let last = side_of(&words[words.len() - 1]);
        if last != Side::Centre {
            words.pop();
            return last;
        }
    }
    Side::Centre
}

/// Reads a bone name (see the [module docs](self)).
pub fn read_name(name: &str) -> ReadName {
    // A namespace (`mixamorig:`, a Maya `|` path) ends at its last separator.
    let short = name.rsplit([':', '|']).next().unwrap_or(name).trim();
    let lower = short.to_lowercase();
    let helper = HELPER_PREFIXES.iter().any(|p| lower.starts_with(p));
    let rigify_deform = lower.starts_with("def-") || lower.starts_with("def_");
    let mut rest = short;
    for prefix in PREFIXES {
        if lower.starts_with(prefix) && lower.len() > prefix.len() {
            rest = &short[prefix.len()..];
            break;
        }
    }
    // A side letter between a prefix and the name (`J_Bip_L_UpperArm`, `CC_Base_R_Eye`,
    // `FACIAL_L_Eye`), or Daz's lowercase side before a capital (`lEye`, `rShldrBend`).
    let mut side = Side::Centre;
    let bytes = rest.as_bytes();
    if bytes.len() > 2 && matches!(bytes[1], b'_' | b'-' | b'.' | b' ') {
        side = match bytes[0] {
            b'L' | b'l' => Side::Left,
            b'R' | b'r' => Side::Right,
            b'C' | b'c' | b'M' | b'm' => Side::Centre,
            _ => Side::Centre,
        };
        if matches!(bytes[0], b'L' | b'l' | b'R' | b'r' | b'C' | b'c') {
            rest = &rest[2..];
        }
    } else if bytes.len() > 1 && matches!(bytes[0], b'l' | b'r') && bytes[1].is_ascii_uppercase() {
        side = if bytes[0] == b'l' {
            Side::Left
        } else {
            Side::Right
        };
        rest = &rest[1..];
    }
    let mut words = split_words(rest);
    if side == Side::Centre {
        side = take_side(&mut words);
    }
    // The number: the last all-digit word (`spine_03`, `Spine1`, `spine.004`, `neck2`).
    let mut number = None;
    if let Some(position) = words
        .iter()
        .rposition(|w| w.chars().all(|c| c.is_ascii_digit()))
    {
        number = words[position].parse().ok();
        words.remove(position);
    }
    words.retain(|w| !w.chars().all(|c| c.is_ascii_digit()));
    let helper = helper || words.iter().any(|w| HELPER_WORDS.contains(&w.as_str()));
    ReadName {
        side,
        words,
        number,
        rigify_deform,
        helper,
    }
}

impl ReadName {
    fn has(&self, word: &str) -> bool {
        self.words.iter().any(|w| w == word)
    }

    fn first(&self) -> &str {
        self.words.first().map_or("", String::as_str)
    }

    /// The role these words name, by the default rules.
    pub fn role(&self) -> BoneRole {
        if self.helper || self.words.is_empty() {
            return BoneRole::None;
        }
        if self.rigify_deform && self.words == ["spine"] {
            // Rigify's deform spine: `DEF-spine` is the hips, `.001`–`.003` the torso,
            // `.004`–`.005` the neck, `.006` the head.
            return match self.number {
                None => BoneRole::Root,
                Some(1..=3) => BoneRole::Spine,
                Some(4..=5) => BoneRole::Neck,
                Some(6) => BoneRole::Head,
                Some(_) => BoneRole::None,
            };
        }
        let first = self.first();
        let one_word = self.words.len() == 1;
        // Eyes: a side, and the word eye (or eyeball), nothing of the lids or brows.
        let eye_word = self
            .words
            .iter()
            .any(|w| w == "eye" || w == "eyeball" || w == "eyes");
        if eye_word
            && !self
                .words
                .iter()
                .any(|w| NOT_EYE_WORDS.contains(&w.as_str()))
        {
            return match self.side {
                Side::Left => BoneRole::LeftEye,
                Side::Right => BoneRole::RightEye,
                Side::Centre => BoneRole::None,
            };
        }
        if self.side != Side::Centre {
            return BoneRole::None;
        }
        if first == "head" && (one_word || self.words[1..].iter().all(|w| w == "bone")) {
            return BoneRole::Head;
        }
        if first == "neck" || first == "cervical" {
            let rest_ok = self.words[1..]
                .iter()
                .all(|w| matches!(w.as_str(), "lower" | "upper" | "twist" | "mid" | "base"));
            return if rest_ok {
                BoneRole::Neck
            } else {
                BoneRole::None
            };
        }
        let spine_like = self.words.iter().all(|w| {
            SPINE_WORDS.contains(&w.as_str())
                || matches!(w.as_str(), "lower" | "upper" | "mid" | "middle")
        }) && self.words.iter().any(|w| SPINE_WORDS.contains(&w.as_str()));
        if spine_like {
            return BoneRole::Spine;
        }
        if self
            .words
            .iter()
            .all(|w| ROOT_WORDS.contains(&w.as_str()) || w == "bone")
        {
            return BoneRole::Root;
        }
        BoneRole::None
    }

    /// True if the name looks like an eye's, however the rules read it (for the check that
    /// no eye is left out).
    pub fn mentions_eye(&self) -> bool {
        !self.helper
            && self.has("eye")
            && !self
                .words
                .iter()
                .any(|w| NOT_EYE_WORDS.contains(&w.as_str()))
    }

    /// True if the name looks like a spine or neck bone's (for the check that the chain
    /// leaves none out).
    pub fn mentions_spine_or_neck(&self) -> bool {
        !self.helper
            && self.side == Side::Centre
            && self
                .words
                .iter()
                .any(|w| SPINE_WORDS.contains(&w.as_str()) || w == "neck" || w == "cervical")
    }

    /// The name's key for pairing left and right bones: its words and number.
    pub fn pair_key(&self) -> (Vec<String>, Option<u32>) {
        (self.words.clone(), self.number)
    }
}

/// The role of `name` by the default rules ([`read_name`], then [`ReadName::role`]).
pub fn default_role(name: &str) -> BoneRole {
    read_name(name).role()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_split_at_case_digits_and_separators() {
        assert_eq!(split_words("abdomenLower"), ["abdomen", "lower"]);
        assert_eq!(split_words("spine_01"), ["spine", "01"]);
        assert_eq!(split_words("Spine1"), ["spine", "1"]);
        assert_eq!(split_words("spine.004"), ["spine", "004"]);
        assert_eq!(split_words("HeadTop_End"), ["head", "top", "end"]);
        assert_eq!(split_words("NeckTwist01"), ["neck", "twist", "01"]);
        assert_eq!(split_words("UpperChest"), ["upper", "chest"]);
    }

    #[test]
    fn names_of_the_usual_rigs_read_as_their_roles() {
        use BoneRole::*;
        let cases = [
            ("mixamorig:Hips", Root),
            ("mixamorigSpine2", Spine),
            ("mixamorig_spine_1", Spine),
            ("mixamorig:HeadTop_End", None),
            ("mixamorig:LeftEye", LeftEye),
            ("left_eye", LeftEye),
            ("spine_05", Spine),
            ("neck_02", Neck),
            ("head", Head),
            ("FACIAL_L_Eye", LeftEye),
            ("FACIAL_R_Eye", RightEye),
            ("FACIAL_L_EyeParent", None),
            ("FACIAL_L_EyelidUpperA", None),
            ("abdomenLower", Spine),
            ("chestUpper", Spine),
            ("neckLower", Neck),
            ("lEye", LeftEye),
            ("rEye", RightEye),
            ("l_eye", LeftEye),
            ("spine4", Spine),
            ("neck2", Neck),
            ("left_eye_smplhf", LeftEye),
            ("J_Bip_C_Head", Head),
            ("J_Bip_C_UpperChest", Spine),
            ("J_Adj_L_FaceEye", LeftEye),
            ("J_Bip_L_UpperArm", None),
            ("CC_Base_Head", Head),
            ("CC_Base_NeckTwist01", Neck),
            ("CC_Base_Waist", Spine),
            ("CC_Base_L_Eye", LeftEye),
            ("CC_Base_FacialBone", None),
            ("DEF-spine", Root),
            ("DEF-spine.003", Spine),
            ("DEF-spine.004", Neck),
            ("DEF-spine.006", Head),
            ("DEF-eye.L", LeftEye),
            ("ORG-spine.006", None),
            ("Eye.R", RightEye),
            ("Eye_L", LeftEye),
            ("LowerBack", Spine),
            ("upperarm_twist_01_l", None),
            ("clavicle_l", None),
            ("LeftUpLeg", None),
            ("pelvis", Root),
            ("root", Root),
            ("jaw", None),
        ];
        for (name, role) in cases {
            assert_eq!(default_role(name), role, "{name}: {:?}", read_name(name));
        }
    }
}
