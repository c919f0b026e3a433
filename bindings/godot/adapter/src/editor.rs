//! What the editor shows about the addon's nodes, for both front ends: each node's
//! configuration warnings (the yellow triangle in the Scene dock) and a character's mapping
//! report (its inspector's `mapping_report`). Computed from the node as it is in the edited
//! scene: its skeleton (if its parent is one), its `bone_map`, the crowd it would join.

use crowdgaze::ik::GazeChain;

use crate::crowd::CharacterSettings;
use crate::settings::CrowdSettings;
use crate::skeleton::{BoundSkeleton, PoseConvention, SkeletonAccess};
use crate::xform::Xform;

/// The crowd a character or target would join, as the front end found it with
/// [`choose_crowd`](crate::choose_crowd).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CrowdFound {
    /// It joins a `CrowdGaze` node.
    Found,
    /// There is no `CrowdGaze` node in the tree (it joins the first that enters).
    NoneYet,
    /// Its `crowd` path or the tree is wrong: what to set.
    Wrong(String),
}

/// What the editor shows about a `CrowdGazeCharacter`: its mapping report and its
/// configuration warnings.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CharacterCheck {
    /// The library's mapping report of the skeleton (the chain, each chain bone's role and
    /// how it was found, the notes), or why there is no chain.
    pub report: String,
    /// One line per problem, each saying what to do; empty when all is well.
    pub warnings: Vec<String>,
}

/// The mapping report and configuration warnings of a `CrowdGazeCharacter`: `skeleton` is
/// its parent `Skeleton` (`None` if the parent is not one), `node` its transform relative to
/// the skeleton, `bone_map` and `impact` its settings as given, `crowd` the crowd it would
/// join.
pub fn check_character(
    skeleton: Option<&impl SkeletonAccess>,
    node: &Xform,
    bone_map: &str,
    impact: f64,
    crowd: &CrowdFound,
) -> CharacterCheck {
    let mut warnings = Vec::new();
    let report = match skeleton {
        None => {
            warnings.push(
                "Not under a Skeleton: make this node a child of the character's Skeleton."
                    .to_string(),
            );
            "no gaze chain: the node is not a child of a Skeleton".to_string()
        }
        Some(skeleton) => match CharacterSettings::new(bone_map, impact) {
            Err(error) => {
                warnings.push(format!("{error}: fix bone_map or impact in the inspector."));
                format!("no gaze chain: {error}")
            }
            Ok(settings) => {
                match BoundSkeleton::bind(
                    skeleton,
                    node,
                    &settings.bone_map,
                    PoseConvention::RestTimesPose,
                ) {
                    Err(error) => {
                        let text = error.to_string();
                        if text.contains("no head bone") {
                            warnings.push(format!(
                                "No head found: {text}. Name the head (and the other chain \
                                 bones) in bone_map, e.g. Skull=head."
                            ));
                        } else {
                            warnings.push(format!("The skeleton cannot be mapped: {text}."));
                        }
                        format!("no gaze chain: {text}")
                    }
                    Ok((bound, chain)) => {
                        // Parts left out by a bone map are left out on purpose.
                        if bone_map.trim().is_empty() {
                            warnings.extend(missing_parts(&chain));
                        }
                        bound.report
                    }
                }
            }
        },
    };
    if let Some(warning) = crowd_warning(crowd, "character") {
        warnings.push(warning);
    }
    CharacterCheck { report, warnings }
}

/// The warning for a chain found by name without spine, neck or eyes: the parts missing do
/// not turn. (The mapping's notes, in the report, say the same and more.)
fn missing_parts(chain: &GazeChain) -> Option<String> {
    let mut missing = Vec::new();
    if chain.spine_count() == 0 {
        missing.push("spine");
    }
    if chain.cervical_count() == 0 {
        missing.push("neck");
    }
    if !chain.has_eyes() {
        missing.push("eyes");
    }
    if missing.is_empty() {
        return None;
    }
    Some(format!(
        "The gaze chain has no {} bones ({} joints found): those parts do not turn. If the \
         skeleton has them under other names, map them in bone_map (roles spine, neck, \
         left_eye, right_eye); see mapping_report.",
        missing.join(", no "),
        chain.joint_count()
    ))
}

/// The warning for a character's or target's crowd, if any.
fn crowd_warning(crowd: &CrowdFound, what: &str) -> Option<String> {
    match crowd {
        CrowdFound::Found => None,
        CrowdFound::NoneYet => Some(format!(
            "No CrowdGaze node in this scene: add one (or the {what} joins the only CrowdGaze \
             in the tree when the game runs)."
        )),
        CrowdFound::Wrong(text) => Some(format!("{text}.")),
    }
}

/// The configuration warnings of a `GazeTarget`: its settings as given and the crowd it
/// would join.
pub fn check_target(look_at_height: f64, impact: f64, crowd: &CrowdFound) -> Vec<String> {
    let mut warnings = Vec::new();
    if !(look_at_height as f32).is_finite() {
        warnings.push(format!(
            "look_at_height = {look_at_height}: set a finite height in metres."
        ));
    }
    if !(impact.is_finite() && (0.0..=1e6).contains(&impact)) {
        warnings.push(format!("impact = {impact}: set it from 0 to 1000000."));
    }
    warnings.extend(crowd_warning(crowd, "target"));
    warnings
}

/// The configuration warnings of a `CrowdGaze` node: its settings, checked as when it
/// enters the tree.
pub fn check_crowd(settings: &CrowdSettings) -> Vec<String> {
    match settings.config() {
        Ok(_) => Vec::new(),
        Err(error) => vec![format!("{error}: no crowd would be created.")],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tests::{rig_skeleton, FakeSkeleton};

    /// The adapter tests' standing human (Hips, Spine, Chest, Neck, Head, LeftEye,
    /// RightEye, LeftUpLeg, RightUpLeg; rests rotated as importers do).
    fn human() -> FakeSkeleton {
        FakeSkeleton::human(PoseConvention::RestTimesPose, Xform::IDENTITY, 1.0)
    }

    #[test]
    fn a_whole_chain_in_a_crowd_has_no_warning_and_a_report() {
        let check = check_character(
            Some(&human()),
            &Xform::IDENTITY,
            "",
            1.0,
            &CrowdFound::Found,
        );
        assert_eq!(check.warnings, Vec::<String>::new());
        assert!(
            check
                .report
                .starts_with("gaze chain of 6 joints: 2 spine, 1 neck, head, 2 eyes"),
            "{}",
            check.report
        );
        assert!(
            check.report.contains("'LeftEye' (by name)"),
            "{}",
            check.report
        );
    }

    #[test]
    fn each_problem_is_one_warning_saying_what_to_do() {
        let none: Option<&FakeSkeleton> = None;
        let check = check_character(none, &Xform::IDENTITY, "", 1.0, &CrowdFound::NoneYet);
        assert_eq!(check.warnings.len(), 2, "{:?}", check.warnings);
        assert!(check.warnings[0].starts_with("Not under a Skeleton"));
        assert!(check.warnings[1].starts_with("No CrowdGaze node in this scene"));
        assert!(check.report.starts_with("no gaze chain"));

        let mut headless = human();
        headless.names[4] = "Skull".into();
        let check = check_character(
            Some(&headless),
            &Xform::IDENTITY,
            "",
            1.0,
            &CrowdFound::Found,
        );
        assert_eq!(check.warnings.len(), 1, "{:?}", check.warnings);
        assert!(
            check.warnings[0].starts_with("No head found: ")
                && check.warnings[0].contains("'Skull'")
                && check.warnings[0].contains("bone_map"),
            "{:?}",
            check.warnings
        );
        // Mapped by hand, the same skeleton is fine.
        let check = check_character(
            Some(&headless),
            &Xform::IDENTITY,
            "Skull=head",
            1.0,
            &CrowdFound::Found,
        );
        assert_eq!(check.warnings, Vec::<String>::new());
        assert!(
            check.report.contains("'Skull' (override)"),
            "{}",
            check.report
        );

        // No eyes, no neck: the parts that do not turn.
        let mut neckless = human();
        neckless.names[3] = "Tail".into();
        neckless.parents[4] = Some(2);
        neckless.names[5] = "Blob1".into();
        neckless.names[6] = "Blob2".into();
        let check = check_character(
            Some(&neckless),
            &Xform::IDENTITY,
            "",
            1.0,
            &CrowdFound::Wrong("crowd = 'Lamp' names a Spatial, not a CrowdGaze".into()),
        );
        assert_eq!(check.warnings.len(), 2, "{:?}", check.warnings);
        assert!(
            check.warnings[0].starts_with("The gaze chain has no neck, no eyes bones"),
            "{:?}",
            check.warnings
        );
        assert_eq!(
            check.warnings[1],
            "crowd = 'Lamp' names a Spatial, not a CrowdGaze."
        );
        assert!(
            check.report.contains("note: no neck bone"),
            "{}",
            check.report
        );
        // Left out by the bone map: on purpose, no warning.
        let check = check_character(
            Some(&human()),
            &Xform::IDENTITY,
            "LeftEye=none,RightEye=none",
            1.0,
            &CrowdFound::Found,
        );
        assert_eq!(check.warnings, Vec::<String>::new());
        assert!(check.report.contains("4 joints"), "{}", check.report);

        // A bad bone map, a bad impact.
        let check = check_character(
            Some(&human()),
            &Xform::IDENTITY,
            "Head=brain",
            1.0,
            &CrowdFound::Found,
        );
        assert!(check.warnings[0].contains("'brain' is not a role"));
        let check = check_character(
            Some(&human()),
            &Xform::IDENTITY,
            "",
            f64::NAN,
            &CrowdFound::Found,
        );
        assert!(
            check.warnings[0].contains("impact = NaN"),
            "{:?}",
            check.warnings
        );

        // Mirrored.
        let mut mirrored = human();
        mirrored.global = Xform {
            basis: glam::Mat3::from_diagonal(glam::Vec3::new(-1.0, 1.0, 1.0)),
            origin: glam::Vec3::ZERO,
        };
        let check = check_character(
            Some(&mirrored),
            &Xform::IDENTITY,
            "",
            1.0,
            &CrowdFound::Found,
        );
        assert!(
            check.warnings[0].starts_with("The skeleton cannot be mapped")
                && check.warnings[0].contains("mirrored"),
            "{:?}",
            check.warnings
        );
    }

    #[test]
    fn eyes_under_a_facial_bone_are_mapped_and_noted_in_the_report() {
        // Character Creator 4: the eyes hang from CC_Base_FacialBone under the head.
        let rig = include_str!("../../../../tests/data/rigs/cc4.rig");
        let facial = rig_skeleton(rig, PoseConvention::RestTimesPose, Xform::IDENTITY);
        let check = check_character(Some(&facial), &Xform::IDENTITY, "", 1.0, &CrowdFound::Found);
        assert!(check.report.contains("2 eyes"), "{}", check.report);
        assert!(
            check.report.contains(
                "note: eye 'CC_Base_L_Eye' hangs from the head through 'CC_Base_FacialBone'"
            ),
            "{}",
            check.report
        );
        assert_eq!(check.warnings, Vec::<String>::new());
    }

    #[test]
    fn targets_and_crowds_warn_about_their_settings() {
        assert!(check_target(0.0, 1.0, &CrowdFound::Found).is_empty());
        let warnings = check_target(f64::INFINITY, -1.0, &CrowdFound::NoneYet);
        assert_eq!(warnings.len(), 3, "{warnings:?}");
        assert!(warnings[0].contains("look_at_height = inf"));
        assert!(warnings[1].contains("impact = -1"));
        assert!(warnings[2].contains("the target joins"));
        assert!(check_crowd(&CrowdSettings::default()).is_empty());
        let bad = CrowdSettings {
            max_characters: -5,
            ..CrowdSettings::default()
        };
        let warnings = check_crowd(&bad);
        assert_eq!(warnings.len(), 1);
        assert!(warnings[0].contains("max_characters = -5"), "{warnings:?}");
    }
}
