//! BVH (Biovision hierarchy) motion files: a small reader and writer.
//!
//! The reader keeps everything needed to write the file back with the same hierarchy and
//! channel orders: joint names, offsets, each joint's channel list in its own order (the
//! rotation order differs between joints in some files), end sites, and the motion as one
//! row of numbers per frame. Rotations are in degrees; a joint's rotation is the product of
//! its rotation channels in the order listed (`Xrotation Yrotation Zrotation` is
//! `Rx · Ry · Rz`), as every BVH reader does.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{anyhow, bail, Context, Result};
use glam::{DQuat, DVec3, EulerRot};

/// One channel of a joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Channel {
    /// Translation along X.
    XPosition,
    /// Translation along Y.
    YPosition,
    /// Translation along Z.
    ZPosition,
    /// Rotation about X (degrees).
    XRotation,
    /// Rotation about Y (degrees).
    YRotation,
    /// Rotation about Z (degrees).
    ZRotation,
}

impl Channel {
    fn parse(text: &str) -> Option<Channel> {
        Some(match text.to_ascii_lowercase().as_str() {
            "xposition" => Channel::XPosition,
            "yposition" => Channel::YPosition,
            "zposition" => Channel::ZPosition,
            "xrotation" => Channel::XRotation,
            "yrotation" => Channel::YRotation,
            "zrotation" => Channel::ZRotation,
            _ => return None,
        })
    }

    /// The channel's name as written in files.
    pub fn name(self) -> &'static str {
        match self {
            Channel::XPosition => "Xposition",
            Channel::YPosition => "Yposition",
            Channel::ZPosition => "Zposition",
            Channel::XRotation => "Xrotation",
            Channel::YRotation => "Yrotation",
            Channel::ZRotation => "Zrotation",
        }
    }

    /// The rotation axis of a rotation channel.
    pub fn rotation_axis(self) -> Option<DVec3> {
        match self {
            Channel::XRotation => Some(DVec3::X),
            Channel::YRotation => Some(DVec3::Y),
            Channel::ZRotation => Some(DVec3::Z),
            _ => None,
        }
    }

    /// The translation axis of a position channel.
    pub fn position_axis(self) -> Option<usize> {
        match self {
            Channel::XPosition => Some(0),
            Channel::YPosition => Some(1),
            Channel::ZPosition => Some(2),
            _ => None,
        }
    }
}

/// A joint of the hierarchy.
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    /// Its name.
    pub name: String,
    /// Index of its parent joint (`None` for a root).
    pub parent: Option<usize>,
    /// Offset from the parent, in the parent's frame (file units).
    pub offset: DVec3,
    /// Its channels, in file order.
    pub channels: Vec<Channel>,
    /// Index of its first channel in a frame's row.
    pub first_channel: usize,
    /// The offset of its end site, if it has one.
    pub end_site: Option<DVec3>,
}

impl Joint {
    /// Its rotation at `frame` (a row of channel values), as a unit quaternion.
    pub fn rotation(&self, frame: &[f64]) -> DQuat {
        let mut rotation = DQuat::IDENTITY;
        for (k, channel) in self.channels.iter().enumerate() {
            if let Some(axis) = channel.rotation_axis() {
                let angle = frame[self.first_channel + k].to_radians();
                rotation *= DQuat::from_axis_angle(axis, angle);
            }
        }
        rotation
    }

    /// Its translation channels at `frame` (`None` without position channels).
    pub fn translation(&self, frame: &[f64]) -> Option<DVec3> {
        let mut value = DVec3::ZERO;
        let mut any = false;
        for (k, channel) in self.channels.iter().enumerate() {
            if let Some(axis) = channel.position_axis() {
                value[axis] = frame[self.first_channel + k];
                any = true;
            }
        }
        any.then_some(value)
    }

    /// The Euler order of its three rotation channels, if it has exactly three distinct
    /// ones (intrinsic, in file order).
    pub fn euler_order(&self) -> Option<EulerRot> {
        let axes: Vec<Channel> = self
            .channels
            .iter()
            .copied()
            .filter(|c| c.rotation_axis().is_some())
            .collect();
        use Channel::{XRotation as X, YRotation as Y, ZRotation as Z};
        Some(match axes.as_slice() {
            [X, Y, Z] => EulerRot::XYZ,
            [X, Z, Y] => EulerRot::XZY,
            [Y, X, Z] => EulerRot::YXZ,
            [Y, Z, X] => EulerRot::YZX,
            [Z, X, Y] => EulerRot::ZXY,
            [Z, Y, X] => EulerRot::ZYX,
            _ => return None,
        })
    }

    /// Writes `rotation` into `frame`'s rotation channels, each angle chosen within 180° of
    /// `near` (the same channels of a reference frame), so that curves stay continuous.
    pub fn set_rotation(&self, frame: &mut [f64], rotation: DQuat, near: &[f64]) -> Result<()> {
        let order = self.euler_order().ok_or_else(|| {
            anyhow!(
                "joint {} has no three distinct rotation channels: its rotation cannot be changed",
                self.name
            )
        })?;
        let (a, b, c) = rotation.to_euler(order);
        let mut angles = [a, b, c].into_iter();
        for (k, channel) in self.channels.iter().enumerate() {
            if channel.rotation_axis().is_some() {
                let index = self.first_channel + k;
                let angle = angles.next().unwrap_or(0.0).to_degrees();
                let reference = near[index];
                let turns = ((reference - angle) / 360.0).round();
                frame[index] = angle + 360.0 * turns;
            }
        }
        Ok(())
    }
}

/// A BVH file: hierarchy and motion.
#[derive(Debug, Clone, PartialEq)]
pub struct Bvh {
    /// Joints, parents before children (file order).
    pub joints: Vec<Joint>,
    /// Channels per frame.
    pub channel_count: usize,
    /// Seconds per frame.
    pub frame_time: f64,
    /// One row of `channel_count` values per frame.
    pub frames: Vec<Vec<f64>>,
}

struct Tokens<'a> {
    path: &'a Path,
    words: Vec<(&'a str, usize)>,
    next: usize,
}

impl<'a> Tokens<'a> {
    fn line(&self) -> usize {
        self.words
            .get(self.next)
            .or(self.words.last())
            .map_or(1, |w| w.1)
    }

    fn error(&self, message: impl std::fmt::Display) -> anyhow::Error {
        anyhow!("{}:{}: {message}", self.path.display(), self.line())
    }

    fn word(&mut self, what: &str) -> Result<&'a str> {
        let word = self
            .words
            .get(self.next)
            .map(|w| w.0)
            .ok_or_else(|| self.error(format!("unexpected end of file, expected {what}")))?;
        self.next += 1;
        Ok(word)
    }

    fn expect(&mut self, wanted: &str) -> Result<()> {
        let line = self.line();
        let word = self.word(&format!("'{wanted}'"))?;
        if !word.eq_ignore_ascii_case(wanted) {
            bail!(
                "{}:{line}: expected '{wanted}', found '{word}'",
                self.path.display()
            );
        }
        Ok(())
    }

    fn number(&mut self, what: &str) -> Result<f64> {
        let line = self.line();
        let word = self.word(what)?;
        let value: f64 = word.parse().map_err(|_| {
            anyhow!(
                "{}:{line}: {what}: '{word}' is not a number",
                self.path.display()
            )
        })?;
        if !value.is_finite() {
            bail!("{}:{line}: {what} is {word}", self.path.display());
        }
        Ok(value)
    }

    fn vector(&mut self, what: &str) -> Result<DVec3> {
        Ok(DVec3::new(
            self.number(what)?,
            self.number(what)?,
            self.number(what)?,
        ))
    }
}

impl Bvh {
    /// Reads a BVH file.
    pub fn read(path: &Path) -> Result<Bvh> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("{}: cannot read", path.display()))?;
        Bvh::parse(&text, path)
    }

    /// Parses BVH text (`path` only names the file in errors).
    pub fn parse(text: &str, path: &Path) -> Result<Bvh> {
        let lines: Vec<&str> = text.lines().collect();
        // The hierarchy is read as words; the motion as lines.
        let motion_line = lines
            .iter()
            .position(|l| l.trim().eq_ignore_ascii_case("MOTION"))
            .ok_or_else(|| anyhow!("{}: no MOTION section", path.display()))?;
        let words = lines[..motion_line]
            .iter()
            .enumerate()
            .flat_map(|(i, line)| line.split_whitespace().map(move |w| (w, i + 1)))
            .collect();
        let mut tokens = Tokens {
            path,
            words,
            next: 0,
        };
        tokens.expect("HIERARCHY")?;
        let mut joints = Vec::new();
        let mut channel_count = 0;
        while tokens.next < tokens.words.len() {
            tokens.expect("ROOT")?;
            parse_joint(&mut tokens, None, &mut joints, &mut channel_count)?;
        }
        if joints.is_empty() {
            bail!("{}:{}: no ROOT joint", path.display(), motion_line + 1);
        }

        // Motion: "Frames: N", "Frame Time: t", then N rows.
        let mut rest = lines
            .iter()
            .enumerate()
            .skip(motion_line + 1)
            .filter(|(_, l)| !l.trim().is_empty());
        let header = |entry: Option<(usize, &&str)>, name: &str| -> Result<(usize, String)> {
            let (i, line) = entry.ok_or_else(|| {
                anyhow!(
                    "{}: unexpected end of file, expected '{name}'",
                    path.display()
                )
            })?;
            let trimmed = line.trim();
            let value = trimmed
                .strip_prefix(name)
                .or_else(|| {
                    trimmed
                        .to_ascii_lowercase()
                        .starts_with(&name.to_ascii_lowercase())
                        .then(|| &trimmed[name.len()..])
                })
                .ok_or_else(|| {
                    anyhow!(
                        "{}:{}: expected '{name}', found '{trimmed}'",
                        path.display(),
                        i + 1
                    )
                })?;
            Ok((i + 1, value.trim().to_string()))
        };
        let (line, value) = header(rest.next(), "Frames:")?;
        let frame_count: usize = value.parse().map_err(|_| {
            anyhow!(
                "{}:{line}: Frames: '{value}' is not a frame count",
                path.display()
            )
        })?;
        let (line, value) = header(rest.next(), "Frame Time:")?;
        let frame_time: f64 = value.parse().map_err(|_| {
            anyhow!(
                "{}:{line}: Frame Time: '{value}' is not a number",
                path.display()
            )
        })?;
        if !(frame_time.is_finite() && frame_time > 0.0) {
            bail!(
                "{}:{line}: Frame Time is {value}, must be positive",
                path.display()
            );
        }
        let mut frames = Vec::with_capacity(frame_count);
        for (i, line) in rest {
            let mut row = Vec::with_capacity(channel_count);
            for word in line.split_whitespace() {
                let value: f64 = word.parse().map_err(|_| {
                    anyhow!(
                        "{}:{}: motion value '{word}' is not a number",
                        path.display(),
                        i + 1
                    )
                })?;
                if !value.is_finite() {
                    bail!("{}:{}: motion value is {word}", path.display(), i + 1);
                }
                row.push(value);
            }
            if row.len() != channel_count {
                bail!(
                    "{}:{}: {} motion values, the hierarchy has {channel_count} channels",
                    path.display(),
                    i + 1,
                    row.len()
                );
            }
            frames.push(row);
        }
        if frames.len() != frame_count {
            bail!(
                "{}:{}: {} frames of motion, the header says {frame_count}",
                path.display(),
                lines.len(),
                frames.len()
            );
        }
        Ok(Bvh {
            joints,
            channel_count,
            frame_time,
            frames,
        })
    }

    /// Index of the joint named `name` (case-insensitive).
    pub fn joint(&self, name: &str) -> Option<usize> {
        self.joints
            .iter()
            .position(|j| j.name.eq_ignore_ascii_case(name))
    }

    /// The file as text: the same hierarchy, channel orders and layout conventions
    /// (tab-indented), values with 6 decimals.
    pub fn to_text(&self) -> String {
        let mut out = String::with_capacity(
            64 * self.joints.len() + 12 * self.channel_count * self.frames.len(),
        );
        out.push_str("HIERARCHY\n");
        self.write_joint(&mut out, 0, 0);
        for (index, joint) in self.joints.iter().enumerate().skip(1) {
            if joint.parent.is_none() {
                self.write_joint(&mut out, index, 0);
            }
        }
        out.push_str("MOTION\n");
        let _ = writeln!(out, "Frames: {}", self.frames.len());
        let _ = writeln!(out, "Frame Time: {}", format_number(self.frame_time, 7));
        for row in &self.frames {
            let mut first = true;
            for value in row {
                if !first {
                    out.push(' ');
                }
                first = false;
                out.push_str(&format_number(*value, 6));
            }
            out.push('\n');
        }
        out
    }

    fn write_joint(&self, out: &mut String, index: usize, depth: usize) {
        let joint = &self.joints[index];
        let indent = "\t".repeat(depth);
        let keyword = if joint.parent.is_none() {
            "ROOT"
        } else {
            "JOINT"
        };
        let _ = writeln!(out, "{indent}{keyword} {}", joint.name);
        let _ = writeln!(out, "{indent}{{");
        let _ = writeln!(out, "{indent}\tOFFSET {}", format_vector(joint.offset));
        let names: Vec<&str> = joint.channels.iter().map(|c| c.name()).collect();
        let _ = writeln!(
            out,
            "{indent}\tCHANNELS {} {}",
            joint.channels.len(),
            names.join(" ")
        );
        for (child, candidate) in self.joints.iter().enumerate() {
            if candidate.parent == Some(index) {
                self.write_joint(out, child, depth + 1);
            }
        }
        if let Some(end) = joint.end_site {
            let _ = writeln!(out, "{indent}\tEnd Site");
            let _ = writeln!(out, "{indent}\t{{");
            let _ = writeln!(out, "{indent}\t\tOFFSET {}", format_vector(end));
            let _ = writeln!(out, "{indent}\t}}");
        }
        let _ = writeln!(out, "{indent}}}");
    }
}

fn format_number(value: f64, decimals: usize) -> String {
    let text = format!("{value:.decimals$}");
    let text = if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    };
    if text == "-0" {
        "0".to_string()
    } else {
        text
    }
}

fn format_vector(v: DVec3) -> String {
    format!(
        "{} {} {}",
        format_number(v.x, 6),
        format_number(v.y, 6),
        format_number(v.z, 6)
    )
}

fn parse_joint(
    tokens: &mut Tokens,
    parent: Option<usize>,
    joints: &mut Vec<Joint>,
    channel_count: &mut usize,
) -> Result<()> {
    let name = tokens.word("a joint name")?.to_string();
    tokens.expect("{")?;
    tokens.expect("OFFSET")?;
    let offset = tokens.vector("OFFSET")?;
    tokens.expect("CHANNELS")?;
    let line = tokens.line();
    let count = tokens.number("the channel count")?;
    if count < 0.0 || count.fract() != 0.0 || count > 6.0 {
        bail!(
            "{}:{line}: CHANNELS {count}: a joint has 0 to 6 channels",
            tokens.path.display()
        );
    }
    let mut channels = Vec::with_capacity(count as usize);
    for _ in 0..count as usize {
        let line = tokens.line();
        let word = tokens.word("a channel name")?;
        channels.push(Channel::parse(word).ok_or_else(|| {
            anyhow!(
                "{}:{line}: unknown channel '{word}' (expected X/Y/Z position or rotation)",
                tokens.path.display()
            )
        })?);
    }
    let index = joints.len();
    joints.push(Joint {
        name,
        parent,
        offset,
        first_channel: *channel_count,
        channels,
        end_site: None,
    });
    *channel_count += count as usize;
    loop {
        let line = tokens.line();
        let word = tokens.word("JOINT, End Site or '}'")?;
        if word.eq_ignore_ascii_case("JOINT") {
            parse_joint(tokens, Some(index), joints, channel_count)?;
        } else if word.eq_ignore_ascii_case("End") {
            tokens.expect("Site")?;
            tokens.expect("{")?;
            tokens.expect("OFFSET")?;
            joints[index].end_site = Some(tokens.vector("OFFSET")?);
            tokens.expect("}")?;
        } else if word == "}" {
            return Ok(());
        } else {
            bail!(
                "{}:{line}: expected JOINT, End Site or '}}', found '{word}'",
                tokens.path.display()
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SMALL: &str = "HIERARCHY\nROOT Hips\n{\n\tOFFSET 0 0 0\n\tCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n\tJOINT Head\n\t{\n\t\tOFFSET 0 1.5 0\n\t\tCHANNELS 3 Yrotation Xrotation Zrotation\n\t\tEnd Site\n\t\t{\n\t\t\tOFFSET 0 1 0\n\t\t}\n\t}\n}\nMOTION\nFrames: 2\nFrame Time: 0.0333333\n1 2 3 10 20 30 40 50 60\n1.5 2 3 -10 -20 170 -40 -50 -60\n";

    #[test]
    fn reads_writes_and_reads_the_same() {
        let path = Path::new("small.bvh");
        let bvh = Bvh::parse(SMALL, path).unwrap();
        assert_eq!(bvh.joints.len(), 2);
        assert_eq!(bvh.channel_count, 9);
        assert_eq!(bvh.joints[1].euler_order(), Some(EulerRot::YXZ));
        assert_eq!(bvh.joints[0].euler_order(), Some(EulerRot::ZXY));
        let again = Bvh::parse(&bvh.to_text(), path).unwrap();
        assert_eq!(bvh, again);
    }

    #[test]
    fn rotations_follow_the_channel_order_and_convert_back() {
        let bvh = Bvh::parse(SMALL, Path::new("small.bvh")).unwrap();
        let head = &bvh.joints[1];
        let frame = &bvh.frames[0];
        let expected = DQuat::from_rotation_y(40f64.to_radians())
            * DQuat::from_rotation_x(50f64.to_radians())
            * DQuat::from_rotation_z(60f64.to_radians());
        assert!(head.rotation(frame).abs_diff_eq(expected, 1e-12));
        let mut out = frame.clone();
        head.set_rotation(&mut out, expected, frame).unwrap();
        for (a, b) in out.iter().zip(frame) {
            assert!((a - b).abs() < 1e-9, "{a} {b}");
        }
        // Angles stay near the reference even across ±180°.
        let root = &bvh.joints[0];
        let reference = &bvh.frames[1];
        let mut out = reference.clone();
        root.set_rotation(&mut out, root.rotation(reference), reference)
            .unwrap();
        let again = root.rotation(&out);
        assert!(again.dot(root.rotation(reference)).abs() > 1.0 - 1e-12);
        for k in 3..6 {
            assert!((out[k] - reference[k]).abs() < 180.0);
        }
    }

    #[test]
    fn bad_files_name_the_line() {
        let path = Path::new("bad.bvh");
        let error = Bvh::parse(&SMALL.replace("OFFSET 0 1.5 0", "OFFSET 0 x 0"), path)
            .unwrap_err()
            .to_string();
        assert!(error.starts_with("bad.bvh:8:"), "{error}");
        let error = Bvh::parse(&SMALL.replace("1.5 2 3", "1.5 2"), path)
            .unwrap_err()
            .to_string();
        assert!(error.starts_with("bad.bvh:20:"), "{error}");
    }
}
