//! Influence and its fades: how much of the gaze a character's bones take (0: the animation
//! alone, 1: the library's gaze), moving to a goal over a settable time. Each character
//! has one [`Fade`], and each crowd one that multiplies its characters'.

use crowdgaze::{Error, Result};

/// Longest fade time accepted, seconds (a day: beyond it a fade never visibly moves).
pub const MAX_FADE_TIME: f32 = 86_400.0;

/// An influence moving to its goal at a constant rate: `current` reaches `goal` in the fade
/// time given when the goal was set. Plain data: advancing it allocates nothing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fade {
    current: f32,
    goal: f32,
    /// Change per second (≥ 0; 0 with `current == goal`).
    rate: f32,
}

impl Default for Fade {
    /// Full influence, at rest.
    fn default() -> Self {
        Fade::FULL
    }
}

impl Fade {
    /// Full influence, at rest.
    pub const FULL: Fade = Fade {
        current: 1.0,
        goal: 1.0,
        rate: 0.0,
    };

    /// A fade at rest at `value` (clamped to 0..=1).
    pub fn at(value: f32) -> Fade {
        let value = if value.is_finite() {
            value.clamp(0.0, 1.0)
        } else {
            1.0
        };
        Fade {
            current: value,
            goal: value,
            rate: 0.0,
        }
    }

    /// Moves towards `goal` (0 to 1) from where it is now, arriving `seconds` from now
    /// (0: at once). A goal already set keeps its pace.
    pub fn set(&mut self, goal: f32, seconds: f32) {
        let goal = if goal.is_finite() {
            goal.clamp(0.0, 1.0)
        } else {
            self.goal
        };
        if goal == self.goal && self.rate > 0.0 {
            return;
        }
        self.goal = goal;
        let distance = (goal - self.current).abs();
        if !(seconds.is_finite() && seconds > 0.0) || distance == 0.0 {
            self.current = goal;
            self.rate = 0.0;
        } else {
            self.rate = distance / seconds;
        }
    }

    /// Lets `dt` seconds pass (negative and non-finite `dt` pass none).
    pub fn advance(&mut self, dt: f32) {
        if self.rate == 0.0 || dt.is_nan() || dt <= 0.0 {
            return;
        }
        let step = self.rate * dt.min(MAX_FADE_TIME);
        if (self.goal - self.current).abs() <= step {
            self.current = self.goal;
            self.rate = 0.0;
        } else if self.goal > self.current {
            self.current += step;
        } else {
            self.current -= step;
        }
    }

    /// The influence now, 0 to 1.
    pub fn value(&self) -> f32 {
        self.current
    }

    /// The influence it moves to, 0 to 1.
    pub fn goal(&self) -> f32 {
        self.goal
    }

    /// True while it moves.
    pub fn is_moving(&self) -> bool {
        self.rate > 0.0
    }
}

/// A node's `active`, `influence` and `influence_fade_time` as checked: the goal of its
/// [`Fade`] is `influence` while active, 0 while not.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Controls {
    /// Whether the node's gaze is applied at all.
    pub active: bool,
    /// How much of the gaze is applied while active, 0 to 1.
    pub influence: f32,
    /// Seconds a change of `active` or `influence` takes to show fully (0: at once).
    pub fade_time: f32,
}

impl Default for Controls {
    /// Active, full influence, a fade time of 0.5 s.
    fn default() -> Self {
        Controls {
            active: true,
            influence: 1.0,
            fade_time: 0.5,
        }
    }
}

impl Controls {
    /// The controls from the node's values as given. Errors name the property and its
    /// value: `influence` outside 0..=1 or not finite, `influence_fade_time` negative, not
    /// finite or over [`MAX_FADE_TIME`].
    pub fn new(active: bool, influence: f64, fade_time: f64) -> Result<Controls> {
        if !(influence.is_finite() && (0.0..=1.0).contains(&influence)) {
            return Err(Error::InvalidArgument(format!(
                "influence = {influence:?}: it must be from 0 to 1"
            )));
        }
        if !(fade_time.is_finite() && (0.0..=f64::from(MAX_FADE_TIME)).contains(&fade_time)) {
            return Err(Error::InvalidArgument(format!(
                "influence_fade_time = {fade_time:?}: it must be from 0 to {MAX_FADE_TIME} seconds"
            )));
        }
        Ok(Controls {
            active,
            influence: influence as f32,
            fade_time: fade_time as f32,
        })
    }

    /// The influence the fade moves to.
    pub fn goal(&self) -> f32 {
        if self.active {
            self.influence
        } else {
            0.0
        }
    }

    /// Sets `fade`'s goal from these controls.
    pub fn apply(&self, fade: &mut Fade) {
        fade.set(self.goal(), self.fade_time);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fade_arrives_in_its_time_and_stays() {
        let mut fade = Fade::FULL;
        fade.set(0.0, 0.5);
        assert!(fade.is_moving());
        fade.advance(0.25);
        assert!((fade.value() - 0.5).abs() < 1e-6, "{}", fade.value());
        fade.advance(0.25);
        assert_eq!(fade.value(), 0.0);
        assert!(!fade.is_moving());
        fade.advance(1.0);
        assert_eq!(fade.value(), 0.0);
        // Back in, from where it is, over the time given then.
        fade.set(0.5, 1.0);
        fade.advance(0.5);
        assert!((fade.value() - 0.25).abs() < 1e-6);
        fade.advance(10.0);
        assert_eq!(fade.value(), 0.5);
    }

    #[test]
    fn zero_time_is_immediate_and_bad_input_is_harmless() {
        let mut fade = Fade::FULL;
        fade.set(0.3, 0.0);
        assert_eq!(fade.value(), 0.3);
        fade.set(f32::NAN, 1.0);
        assert_eq!(fade.goal(), 0.3);
        fade.set(2.0, f32::INFINITY);
        assert_eq!(fade.value(), 1.0);
        fade.set(0.0, 1.0);
        fade.advance(f32::NAN);
        fade.advance(-1.0);
        assert_eq!(fade.value(), 1.0);
        fade.advance(f32::INFINITY);
        assert_eq!(fade.value(), 0.0);
        assert_eq!(Fade::at(f32::NAN).value(), 1.0);
        assert_eq!(Fade::at(-3.0).value(), 0.0);
    }

    #[test]
    fn setting_the_same_goal_keeps_the_pace() {
        let mut fade = Fade::FULL;
        fade.set(0.0, 1.0);
        fade.advance(0.5);
        fade.set(0.0, 1.0);
        fade.advance(0.5);
        assert_eq!(fade.value(), 0.0);
    }

    #[test]
    fn controls_check_and_name_their_properties() {
        let controls = Controls::new(false, 0.5, 2.0).unwrap();
        assert_eq!(controls.goal(), 0.0);
        let mut fade = Fade::FULL;
        controls.apply(&mut fade);
        fade.advance(1.0);
        assert!((fade.value() - 0.5).abs() < 1e-6);
        assert_eq!(Controls::new(true, 0.5, 0.0).unwrap().goal(), 0.5);
        let text = Controls::new(true, 1.5, 0.0).unwrap_err().to_string();
        assert!(text.contains("influence = 1.5"), "{text}");
        let text = Controls::new(true, f64::NAN, 0.0).unwrap_err().to_string();
        assert!(text.contains("influence = NaN"), "{text}");
        let text = Controls::new(true, 1.0, -1.0).unwrap_err().to_string();
        assert!(text.contains("influence_fade_time = -1"), "{text}");
        assert!(Controls::new(true, 1.0, 1e300).is_err());
    }
}
