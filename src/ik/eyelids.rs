//! Living eyes: spontaneous blinks at each character's own rate, gaze-evoked blinks at the
//! start of large gaze shifts, and upper lids that follow the eyes' pitch. A model of its
//! own, in 8 bytes of state per character ([`BlinkState`]), every draw from the character's
//! seed, so a character blinks the same way in every run.
//!
//! **Rate.** Adults at rest blink about 17 times a minute (Bentivoglio et al. 1997,
//! *Movement Disorders* 12(6): 17/min at rest, 26 in conversation, 4.5 reading), with
//! large differences between people. Each character draws its own rate once, uniformly in
//! `mean_rate · [1 − rate_spread, 1 + rate_spread]` ([`BlinkSettings`]).
//!
//! **Intervals.** Blinks are not regular: the time from one blink's start to the next's is
//! drawn from a gamma distribution of shape 3 with the character's mean interval
//! `60 / rate` seconds (at least [`MIN_OPEN`] after the blink's end).
//! Our choice, for three properties of blinking we want and an exponential (Poisson)
//! process lacks: intervals are right-skewed (a long pause now and then), very short ones
//! are rare (a blink is seldom followed at once by another), and their spread is
//! moderate (a coefficient of variation of `1/√3 ≈ 0.58`).
//!
//! **Shape.** A blink lasts 150 to 350 ms, drawn uniformly for each blink (the 100–400 ms
//! of the literature, without its extremes). The lid closes in the first third and opens
//! in the other two: the down phase of a blink is faster than its up phase (Evinger,
//! Manning & Sibony 1991, *IOVS* 32). Each phase follows a smoothstep, so the closure
//! ([`BlinkState::closure`], 0 open, 1 closed) starts and ends at rest.
//!
//! **Gaze-evoked blinks.** A blink accompanies most large gaze shifts, starting with them:
//! Evinger et al. 1994 (*Exp. Brain Res.* 100, "Not looking while leaping") found the lid
//! closing muscle active with 97 % of saccadic gaze shifts larger than 33°. A shift of
//! amplitude `A` starts a blink with probability 0 up to `evoked_min_amplitude` (10°, our
//! choice: small shifts rarely come with a blink), rising linearly to `evoked_probability`
//! (0.97) at `evoked_full_amplitude` (33°), and that above.
//!
//! **Lids.** Each upper lid's pitch follows its eye's: during fixation the eye and the lid
//! take essentially equal vertical positions (Becker & Fuchs 1988, *J. Neurophysiol.* 60),
//! so the lid pitches `lid_gain` (1) times the eye's, looking down lowers the lids; the
//! blink's closure comes on top of it.

use glam::Quat;

use crate::error::{ensure_all_finite, Error, Result};
use crate::ik::GazeChain;
use crate::math::random::{stream, Purpose, Random};

/// The shortest and longest blink, seconds.
pub const BLINK_DURATION: (f32, f32) = (0.15, 0.35);

/// The shortest time the eyes stay open between two blinks, seconds (a drawn interval
/// shorter than the blink and this is stretched to them).
pub const MIN_OPEN: f32 = 0.1;

/// The share of a blink during which the lid closes (the rest it opens).
pub const CLOSING_SHARE: f32 = 1.0 / 3.0;

/// The longest time a step replays blink by blink, seconds: a longer step starts the
/// character's blinking afresh ([`BlinkState::advance`]), so that a step of any length costs
/// at most `CATCH_UP_HORIZON / MIN_OPEN` (600) draws per character.
pub const CATCH_UP_HORIZON: f32 = 60.0;

/// Shape of the gamma distribution of the intervals between blinks.
const INTERVAL_SHAPE: u32 = 3;

/// The index of a character's blink stream that draws its rate and first interval (the
/// blinks use the indices from 0 up).
const RATE_DRAWS: u64 = u64::MAX;

/// How a crowd's characters blink. Rates in blinks per minute, angles in radians.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlinkSettings {
    /// Mean spontaneous blink rate of the crowd's characters, blinks per minute, in
    /// [0, 120]; 0: no spontaneous blinks. Default 17 (Bentivoglio et al. 1997, at rest).
    pub mean_rate: f32,
    /// Spread of the characters' own rates: each draws `mean_rate · (1 + rate_spread · u)`,
    /// `u` uniform in [−1, 1]. In [0, 1). Default 0.5.
    pub rate_spread: f32,
    /// Gaze shifts up to this amplitude start no blink, radians. Default 10°.
    pub evoked_min_amplitude: f32,
    /// Gaze shifts from this amplitude on start a blink with `evoked_probability`, radians
    /// (above `evoked_min_amplitude`). Default 33° (Evinger et al. 1994).
    pub evoked_full_amplitude: f32,
    /// The probability that a large gaze shift starts a blink, in [0, 1]; 0: no
    /// gaze-evoked blinks. Default 0.97 (Evinger et al. 1994).
    pub evoked_probability: f32,
    /// Upper lid pitch per radian of eye pitch, in [0, 2]. Default 1 (Becker & Fuchs 1988).
    pub lid_gain: f32,
}

impl Default for BlinkSettings {
    fn default() -> Self {
        BlinkSettings {
            mean_rate: 17.0,
            rate_spread: 0.5,
            evoked_min_amplitude: 10f32.to_radians(),
            evoked_full_amplitude: 33f32.to_radians(),
            evoked_probability: 0.97,
            lid_gain: 1.0,
        }
    }
}

impl BlinkSettings {
    /// Checks the ranges: everything finite ([`Error::NonFinite`]); `mean_rate` in
    /// [0, 120], `rate_spread` in [0, 1), `0 ≤ evoked_min_amplitude < evoked_full_amplitude
    /// ≤ π`, `evoked_probability` in [0, 1], `lid_gain` in [0, 2]
    /// ([`Error::InvalidArgument`]).
    pub fn validate(&self) -> Result<()> {
        ensure_all_finite(
            &[
                self.mean_rate,
                self.rate_spread,
                self.evoked_min_amplitude,
                self.evoked_full_amplitude,
                self.evoked_probability,
                self.lid_gain,
            ],
            "blink settings",
        )?;
        let bad = |what: &str| Err(Error::InvalidArgument(format!("blink settings: {what}")));
        if !(0.0..=120.0).contains(&self.mean_rate) {
            return bad("mean_rate must be in [0, 120] blinks per minute");
        }
        if !(0.0..1.0).contains(&self.rate_spread) {
            return bad("rate_spread must be in [0, 1)");
        }
        if !(0.0 <= self.evoked_min_amplitude
            && self.evoked_min_amplitude < self.evoked_full_amplitude
            && self.evoked_full_amplitude <= std::f32::consts::PI)
        {
            return bad("need 0 ≤ evoked_min_amplitude < evoked_full_amplitude ≤ π");
        }
        if !(0.0..=1.0).contains(&self.evoked_probability) {
            return bad("evoked_probability must be in [0, 1]");
        }
        if !(0.0..=2.0).contains(&self.lid_gain) {
            return bad("lid_gain must be in [0, 2]");
        }
        Ok(())
    }

    /// True if these settings blink never: no spontaneous blinks (`mean_rate` 0) and no
    /// gaze-evoked ones (`evoked_probability` 0). A crowd then skips blinking altogether.
    pub fn never_blink(&self) -> bool {
        self.mean_rate == 0.0 && self.evoked_probability == 0.0
    }

    /// The probability that a gaze shift of `amplitude` radians starts a blink.
    pub fn evoked_probability_at(&self, amplitude: f32) -> f32 {
        let ramp = (amplitude - self.evoked_min_amplitude)
            / (self.evoked_full_amplitude - self.evoked_min_amplitude);
        self.evoked_probability * ramp.clamp(0.0, 1.0)
    }

    /// A character's own blink rate, blinks per minute, from its seed.
    pub fn rate_of(&self, seed: u64) -> f32 {
        let mut draws = stream(seed, Purpose::Blinks, RATE_DRAWS);
        self.mean_rate * (1.0 + self.rate_spread * draws.range(-1.0, 1.0))
    }

    /// An upper lid's pitch for an eye pitched `eye_pitch` radians (positive up), before
    /// the blink's closure.
    pub fn lid_pitch(&self, eye_pitch: f32) -> f32 {
        self.lid_gain * eye_pitch
    }
}

/// The seed of a character's blinks (the `seed` of [`BlinkState`]'s calls): from the
/// crowd's seed and the character's id, so that it survives removals and reorders.
pub fn character_seed(crowd_seed: u64, character_id: u32) -> u64 {
    stream(crowd_seed, Purpose::Blinks, u64::from(character_id)).next_u64()
}

/// Each eye's pitch in the head's frame, radians, positive towards the head's up
/// ([`GazeChain::eye_up`]): the direction the eye's local rotation `base · delta` gives its
/// rest gaze ([`GazeChain::eye_forward`]), as the gaze IK turns it. `[0, 0]` for a chain
/// without eyes. `base(joint)` is the base rotation of chain joint `joint`, `deltas` the
/// chain's deltas.
pub fn eye_pitches(chain: &GazeChain, base: impl Fn(usize) -> Quat, deltas: &[Quat]) -> [f32; 2] {
    let Some(eyes) = chain.eye_indices() else {
        return [0.0; 2];
    };
    eyes.map(|index| {
        let rest = chain.joints()[index].rest;
        let local_forward = rest.conjugate() * chain.eye_forward();
        let direction = (base(index) * deltas[index]) * local_forward;
        direction
            .normalize_or_zero()
            .dot(chain.eye_up())
            .clamp(-1.0, 1.0)
            .asin()
    })
}

/// The character's `draws`-th blink stream and its first draw, the blink's duration
/// (seconds). The stream then draws the interval to the next blink (from this one's
/// start), then the gaze-evoked decision.
fn blink_stream(seed: u64, draws: u32) -> (Random, f32) {
    let mut random = stream(seed, Purpose::Blinks, u64::from(draws));
    let duration = random.range(BLINK_DURATION.0, BLINK_DURATION.1);
    (random, duration)
}

/// A gamma-distributed interval with mean `60 / rate` seconds (infinite for a rate of 0).
fn interval(random: &mut Random, rate: f32) -> f32 {
    if rate <= 0.0 {
        return f32::INFINITY;
    }
    let product: f32 = (0..INTERVAL_SHAPE)
        .map(|_| 1.0 - random.next_f32())
        .product();
    -product.ln() * (60.0 / rate) / INTERVAL_SHAPE as f32
}

/// The smoothstep `3x² − 2x³` of `x` in [0, 1].
fn smoothstep(x: f32) -> f32 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

/// One character's blinking: 8 bytes. Advance it every frame with
/// [`advance`](Self::advance); read its [`closure`](Self::closure).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlinkState {
    /// Above 0: seconds until the next spontaneous blink. At most 0: blinking, for
    /// `−clock` seconds so far.
    clock: f32,
    /// Blink streams used so far: the current (or next) blink draws from stream `draws`.
    draws: u32,
}

impl BlinkState {
    /// A character's blinking at its start: open eyes, the first blink at a random point
    /// of its first interval.
    pub fn new(settings: &BlinkSettings, seed: u64) -> BlinkState {
        let rate = settings.rate_of(seed);
        let mut draws = stream(seed, Purpose::Blinks, RATE_DRAWS);
        draws.next_f32(); // the rate's draw
        let first = interval(&mut draws, rate) * (1.0 - draws.next_f32());
        BlinkState {
            clock: first.max(f32::MIN_POSITIVE),
            draws: 0,
        }
    }

    /// True while the lids are in a blink.
    pub fn is_blinking(&self) -> bool {
        self.clock <= 0.0
    }

    /// Blinks started so far, spontaneous or gaze-evoked, and gaze-evoked draws that
    /// started none.
    pub fn draws(&self) -> u32 {
        self.draws
    }

    /// [`advance`](Self::advance) for a frame in which nothing happens — no gaze shift
    /// starts and no blink starts or ends — which is most frames; returns false (and
    /// changes nothing) for any other, which then needs `advance`. The same result as
    /// `advance` without its seed.
    #[inline]
    pub fn advance_quietly(&mut self, dt: f32, shift: Option<f32>) -> bool {
        let clock = self.clock - dt;
        if shift.is_some() || clock <= 0.0 {
            return false;
        }
        self.clock = clock;
        true
    }

    /// Moves the character's blinking on by `dt` seconds (≥ 0). `shift` is the amplitude
    /// (radians) of a gaze shift that starts in this frame, if one does: it may start a
    /// blink ([`BlinkSettings::evoked_probability_at`]) unless one is under way.
    pub fn advance(&mut self, settings: &BlinkSettings, seed: u64, dt: f32, shift: Option<f32>) {
        if let (Some(amplitude), false) = (shift, self.is_blinking()) {
            let chance = settings.evoked_probability_at(amplitude);
            if chance > 0.0 {
                let (mut random, _) = blink_stream(seed, self.draws);
                for _ in 0..INTERVAL_SHAPE {
                    random.next_u64(); // past the interval's draws
                }
                let evoked = random.next_f32() < chance;
                self.draws = self.draws.wrapping_add(1);
                if evoked {
                    self.clock = 0.0;
                }
            }
        }
        self.clock -= dt;
        if self.clock < -CATCH_UP_HORIZON {
            // Blinks over more than the horizon passed in this step (a pause, or a time
            // stamp passed as a step): start afresh, as a new character does, rather than
            // replay them one by one (in f32, past about 10⁸ s, replaying them would make
            // no progress at all).
            let (mut random, _) = blink_stream(seed, self.draws);
            let rate = settings.rate_of(seed);
            let first = interval(&mut random, rate) * (1.0 - random.next_f32());
            self.draws = self.draws.wrapping_add(1);
            self.clock = first.max(f32::MIN_POSITIVE);
            return;
        }
        // A blink that ended this frame: the next interval runs from its start. Each turn
        // moves the clock on by at least `MIN_OPEN`, so at most `CATCH_UP_HORIZON /
        // MIN_OPEN` turns.
        while self.is_blinking() {
            let (mut random, duration) = blink_stream(seed, self.draws);
            let elapsed = -self.clock;
            if elapsed < duration {
                break;
            }
            let next = interval(&mut random, settings.rate_of(seed));
            self.draws = self.draws.wrapping_add(1);
            self.clock = next.max(duration + MIN_OPEN) - elapsed;
        }
    }

    /// How closed the lids are: 0 open, 1 closed.
    pub fn closure(&self, seed: u64) -> f32 {
        if !self.is_blinking() {
            return 0.0;
        }
        let (_, duration) = blink_stream(seed, self.draws);
        let elapsed = -self.clock;
        let closing = CLOSING_SHARE * duration;
        if elapsed < closing {
            smoothstep(elapsed / closing)
        } else {
            1.0 - smoothstep((elapsed - closing) / (duration - closing))
        }
    }

    /// The current blink's duration, seconds, while one is under way.
    pub fn blink_duration(&self, seed: u64) -> Option<f32> {
        self.is_blinking().then(|| blink_stream(seed, self.draws).1)
    }
}

#[cfg(test)]
mod tests;
