//! Conversation gaze: where each member of a group of people standing together and talking
//! looks, glance by glance — at the speaker, at a listener, at another member, or away.
//! A model of its own, in plain per-group state ([`Conversation`]), every draw from the
//! crowd's seed and the member's id, so a conversation looks the same in every run.
//!
//! **Roles.** Each step a member is the *speaker* (its entity is flagged talking), a
//! *listener* (another member talks: the one who started last, the group's speaker), or
//! *idle* (no one talks).
//!
//! **Glances.** A member's gaze alternates between glances at someone (the speaker for a
//! listener, a listener for the speaker, another member when idle) and glances away. Each
//! lasts a gamma-distributed time (shape 2: few very short glances) whose mean depends on
//! the role: listeners look at the speaker 75 % of the time, in glances of 6 s on average,
//! speakers at a listener 41 % of the time, in glances of 1.8 s.
//! The shares are Argyle & Ingham's (1972, *Semiotica* 6: listener → speaker 75 %, speaker
//! → listener 41 % of the time; Argyle & Cook 1976, *Gaze and Mutual Gaze*); with the two
//! gazes independent, mutual gaze is their product, 31 %, as those studies measured. The
//! glance lengths are our choice, so that the glances at a partner average about 3 s and
//! mutual glances, which end when either look ends, about 1.2 s (Argyle & Cook's figures).
//! Idle members look at one another half of the time, in glances of 2.5 s (our choice).
//!
//! **Turns.** A change of role ends the current glance at once. A listener whose speaker
//! changes looks at the new one. A member who starts talking first looks away for
//! [`ConversationSettings::turn_start_aversion`] seconds (1 s): speakers look away as they
//! begin an utterance (Kendon 1967, *Acta Psychologica* 26).
//!
//! Where "away" is — the member's own attention model's target, or a point beside the
//! group — is the crowd's business; this model only says when.

use crate::error::{ensure_all_finite, Error, Result};
use crate::math::random::{stream, Purpose, Random};

/// Most members of one conversation.
pub const MAX_MEMBERS: usize = 8;

/// [`MemberGaze::target`] of a member looking away.
pub const AWAY: u8 = u8::MAX;

/// No member (a group without a speaker).
pub const NOBODY: u8 = u8::MAX;

/// Shape of the gamma distribution of glance lengths.
const GLANCE_SHAPE: u32 = 2;

/// The most glances of one member a step replays: a longer step (a pause) starts the
/// member's glance afresh after them, so a step of any length costs a bounded time.
const MAX_GLANCES_PER_STEP: u32 = 64;

/// How members of conversations look at each other. Times in seconds, shares in [0, 1].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConversationSettings {
    /// Share of the time a listener looks at the speaker, in (0, 1). Default 0.75 (Argyle
    /// & Ingham 1972).
    pub listener_share: f32,
    /// Mean length of a listener's glance at the speaker, s (> 0). Default 6.
    pub listener_glance: f32,
    /// Share of the time the speaker looks at a listener, in (0, 1). Default 0.41 (Argyle
    /// & Ingham 1972).
    pub speaker_share: f32,
    /// Mean length of the speaker's glance at a listener, s (> 0). Default 1.8.
    pub speaker_glance: f32,
    /// Share of the time a member looks at another while no one talks, in (0, 1).
    /// Default 0.5.
    pub idle_share: f32,
    /// Mean length of a glance at another member while no one talks, s (> 0). Default 2.5.
    pub idle_glance: f32,
    /// A member who starts talking first looks away this long, s (0: not at all).
    /// Default 1 (Kendon 1967).
    pub turn_start_aversion: f32,
}

impl Default for ConversationSettings {
    fn default() -> Self {
        ConversationSettings {
            listener_share: 0.75,
            listener_glance: 6.0,
            speaker_share: 0.41,
            speaker_glance: 1.8,
            idle_share: 0.5,
            idle_glance: 2.5,
            turn_start_aversion: 1.0,
        }
    }
}

impl ConversationSettings {
    /// Checks the ranges: everything finite ([`Error::NonFinite`]); shares in (0, 1),
    /// glances in (0, 600] s, `turn_start_aversion` in [0, 60] s
    /// ([`Error::InvalidArgument`]).
    pub fn validate(&self) -> Result<()> {
        let all = [
            self.listener_share,
            self.listener_glance,
            self.speaker_share,
            self.speaker_glance,
            self.idle_share,
            self.idle_glance,
            self.turn_start_aversion,
        ];
        ensure_all_finite(&all, "conversation settings")?;
        let bad = |what: &str| Err(Error::InvalidArgument(format!("conversation: {what}")));
        for (share, name) in [
            (self.listener_share, "listener_share"),
            (self.speaker_share, "speaker_share"),
            (self.idle_share, "idle_share"),
        ] {
            if !(share > 0.0 && share < 1.0) {
                return bad(&format!("{name} is {share}, must be in (0, 1)"));
            }
        }
        for (glance, name) in [
            (self.listener_glance, "listener_glance"),
            (self.speaker_glance, "speaker_glance"),
            (self.idle_glance, "idle_glance"),
        ] {
            if !(glance > 0.0 && glance <= 600.0) {
                return bad(&format!("{name} is {glance} s, must be in (0, 600]"));
            }
        }
        if !(0.0..=60.0).contains(&self.turn_start_aversion) {
            return bad("turn_start_aversion must be in [0, 60] s");
        }
        Ok(())
    }

    /// The share of the time a member in `role` looks at someone.
    fn share(&self, role: Role) -> f32 {
        match role {
            Role::Listener => self.listener_share,
            Role::Speaker => self.speaker_share,
            Role::Idle => self.idle_share,
        }
    }

    /// Mean lengths of a glance at someone and of a glance away, s, for `role`.
    fn glances(&self, role: Role) -> (f32, f32) {
        let at = match role {
            Role::Listener => self.listener_glance,
            Role::Speaker => self.speaker_glance,
            Role::Idle => self.idle_glance,
        };
        let share = self.share(role);
        (at, at * (1.0 - share) / share)
    }
}

/// A member's part in the conversation this step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Role {
    /// No one talks.
    #[default]
    Idle,
    /// Another member talks.
    Listener,
    /// This member talks.
    Speaker,
}

/// One member's gaze in its conversation.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MemberGaze {
    /// The member looked at (an index into the group), or [`AWAY`].
    pub target: u8,
    /// The role the current glance was chosen for.
    role: Role,
    /// Seconds until the current glance ends.
    left: f32,
    /// Draws from the member's stream so far (the current glance's stream index).
    pub draws: u32,
}

/// A group of characters standing together: its members (character ids), each one's gaze,
/// and its speaker.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Conversation {
    /// The members' character ids; the first `count` are used.
    pub members: [u32; MAX_MEMBERS],
    /// Each member's gaze.
    pub gaze: [MemberGaze; MAX_MEMBERS],
    /// How many members.
    pub count: u8,
    /// The member whose words the listeners follow, or [`NOBODY`].
    pub speaker: u8,
}

impl Conversation {
    /// A new conversation of `members` (2 to [`MAX_MEMBERS`] ids), every member starting
    /// a glance as if its role had just changed.
    pub fn new(members: &[u32]) -> Conversation {
        debug_assert!((2..=MAX_MEMBERS).contains(&members.len()));
        let mut ids = [0; MAX_MEMBERS];
        ids[..members.len()].copy_from_slice(members);
        Conversation {
            members: ids,
            gaze: [MemberGaze {
                target: AWAY,
                role: Role::Idle,
                left: 0.0,
                draws: 0,
            }; MAX_MEMBERS],
            count: members.len() as u8,
            speaker: NOBODY,
        }
    }

    /// The members' ids.
    pub fn member_ids(&self) -> &[u32] {
        &self.members[..usize::from(self.count)]
    }

    /// Removes member `index`, moving the last one into its place (its gaze too); every
    /// reference to either by index follows. Returns the id of the member now at `index`,
    /// if one moved there.
    pub fn remove(&mut self, index: usize) -> Option<u32> {
        let last = usize::from(self.count) - 1;
        let renumber = |member: u8| -> u8 {
            match usize::from(member) {
                m if m == index => NOBODY,
                m if m == last => index as u8,
                _ => member,
            }
        };
        self.members[index] = self.members[last];
        self.gaze[index] = self.gaze[last];
        self.count -= 1;
        self.speaker = renumber(self.speaker);
        for gaze in &mut self.gaze[..usize::from(self.count)] {
            if gaze.target != AWAY {
                let target = renumber(gaze.target);
                if target == NOBODY {
                    gaze.left = 0.0; // looked at the member who left: choose again
                }
                gaze.target = target;
            }
        }
        (index < usize::from(self.count)).then(|| self.members[index])
    }

    /// Advances the conversation by `dt` seconds. `talking[i]` says whether member `i`
    /// talks this step; `seed` is the crowd's.
    pub fn advance(
        &mut self,
        settings: &ConversationSettings,
        seed: u64,
        dt: f32,
        talking: &[bool; MAX_MEMBERS],
    ) {
        let count = usize::from(self.count);
        // The speaker goes on while it talks; else the first member who talks, if any.
        if self.speaker == NOBODY || !talking[usize::from(self.speaker)] {
            self.speaker = (0..count)
                .find(|&member| talking[member])
                .map_or(NOBODY, |member| member as u8);
        }
        for (member, &talks) in talking.iter().enumerate().take(count) {
            let role = if talks {
                Role::Speaker
            } else if self.speaker != NOBODY {
                Role::Listener
            } else {
                Role::Idle
            };
            let gaze = self.gaze[member];
            let lost_speaker =
                role == Role::Listener && gaze.target != AWAY && gaze.target != self.speaker;
            if role != gaze.role || lost_speaker {
                self.start_glance(settings, seed, member, role, true);
            } else {
                self.gaze[member].left -= dt;
                // A long step may end several glances: up to `MAX_GLANCES_PER_STEP` are
                // replayed; after more (a pause), the member starts a glance afresh.
                let mut replayed = 0;
                while self.gaze[member].left <= 0.0 {
                    let overshoot = self.gaze[member].left;
                    self.start_glance(settings, seed, member, role, false);
                    replayed += 1;
                    if replayed == MAX_GLANCES_PER_STEP {
                        break;
                    }
                    self.gaze[member].left += overshoot;
                }
            }
        }
    }

    /// Starts member `member`'s next glance in `role`: after a change of role, the role's
    /// first glance (`changed`); else the other kind than the current one (at someone
    /// after away, away after at someone).
    fn start_glance(
        &mut self,
        settings: &ConversationSettings,
        seed: u64,
        member: usize,
        role: Role,
        changed: bool,
    ) {
        let id = self.members[member];
        let gaze = &mut self.gaze[member];
        gaze.draws = gaze.draws.wrapping_add(1);
        let mut random = member_stream(seed, id, gaze.draws);
        let (at_mean, away_mean) = settings.glances(role);
        let look_at_someone = match (role, changed) {
            // A new speaker looks away first (Kendon 1967).
            (Role::Speaker, true) if settings.turn_start_aversion > 0.0 => false,
            // Else a new role starts where its glances would be at any moment: at someone
            // with the role's share.
            (_, true) => random.next_f32() < settings.share(role),
            (_, false) => gaze.target == AWAY,
        };
        gaze.role = role;
        if !look_at_someone {
            gaze.target = AWAY;
            gaze.left = if role == Role::Speaker && changed {
                settings.turn_start_aversion
            } else {
                gamma(&mut random, away_mean)
            };
            return;
        }
        let count = usize::from(self.count);
        gaze.target = match role {
            Role::Listener => self.speaker,
            // Any other member, uniformly.
            _ => {
                let pick = random.below(count as u32 - 1) as usize;
                (if pick >= member { pick + 1 } else { pick }) as u8
            }
        };
        gaze.left = gamma(&mut random, at_mean);
    }
}

/// Member `id`'s stream for its `draws`-th glance.
fn member_stream(seed: u64, id: u32, draws: u32) -> Random {
    stream(
        seed,
        Purpose::Conversation,
        u64::from(id) << 32 | u64::from(draws),
    )
}

/// The away glance's direction offsets for member `id`'s `draws`-th glance: a yaw of
/// 20–40° to either side and a pitch of 5–15° down, radians.
pub fn away_offsets(seed: u64, id: u32, draws: u32) -> (f32, f32) {
    let mut random = member_stream(seed, id, draws);
    random.next_u64(); // the glance's own draws come first
    random.next_u64();
    random.next_u64();
    let side = if random.next_f32() < 0.5 { -1.0 } else { 1.0 };
    let yaw = side * random.range(20f32.to_radians(), 40f32.to_radians());
    let pitch = -random.range(5f32.to_radians(), 15f32.to_radians());
    (yaw, pitch)
}

/// A gamma-distributed time of shape [`GLANCE_SHAPE`] and mean `mean` seconds.
fn gamma(random: &mut Random, mean: f32) -> f32 {
    let product: f32 = (0..GLANCE_SHAPE).map(|_| 1.0 - random.next_f32()).product();
    (-product.ln() * mean / GLANCE_SHAPE as f32).max(1e-3)
}

#[cfg(test)]
mod tests;
