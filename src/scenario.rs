//! Deterministic demo scenes for tests, benchmarks, examples and the command-line tool:
//! the paper's street (people walking up and down, standing, sitting on benches, with
//! scene objects; optionally some of them standing in groups, talking in turns) and a
//! plaza of random walkers at a chosen density.
//!
//! A scenario moves its people itself ([`Scenario::advance`](crate::scenario::Scenario::advance)) and hands their states to a
//! crowd ([`Scenario::push`](crate::scenario::Scenario::push)); it is a driver for the library, not part of its models.

use glam::{Vec2, Vec3};

use crate::crowd::{CharacterDesc, Crowd, ExplicitTarget, ObjectDesc, TargetPriority};
use crate::error::Result;
use crate::ik::GazeChain;
use crate::math::random::{stream, Purpose, Random};
use crate::scene::EntityUpdate;
use crate::world::World;

/// What a person in a scenario does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Activity {
    /// Walks along the street (or plaza), turning back at the ends.
    Walking,
    /// Stands still.
    Standing,
    /// Sits on a bench (still, facing the street).
    Sitting,
}

/// One person of a scenario, on the ground plane (metres).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Person {
    /// Ground position (along forward, along side).
    pub position: Vec2,
    /// Ground velocity (m/s).
    pub velocity: Vec2,
    /// Heading (radians) when not walking.
    pub heading: f32,
    /// What the person does.
    pub activity: Activity,
}

/// A scene object of a scenario (shop window, bench, lamp, poster...).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Prop {
    /// Ground position.
    pub position: Vec2,
    /// Facing (radians).
    pub heading: f32,
    /// Height of its look-at point (m).
    pub look_at_height: f32,
    /// Impact factor.
    pub impact: f32,
}

/// A deterministic scene: people moving inside a rectangle, and props.
#[derive(Debug, Clone)]
pub struct Scenario {
    /// The people, in the order their characters are added.
    pub people: Vec<Person>,
    /// The props, in the order their objects are added.
    pub props: Vec<Prop>,
    /// Extent of the walkable rectangle along forward (metres, from 0).
    pub length: f32,
    /// Extent along side (metres, from 0).
    pub width: f32,
    random: Random,
    ids: Vec<u32>,
    /// Groups standing together and talking in turns ([`with_conversations`]).
    ///
    /// [`with_conversations`]: Self::with_conversations
    pub groups: Vec<TalkingGroup>,
    /// Whether each person talks now.
    talking: Vec<bool>,
    /// The gaze chains people take in turn ([`with_chains`](Self::with_chains)); empty: the
    /// crowd's human chain for everyone.
    chains: Vec<GazeChain>,
}

/// Turn-taking in a group of talkers: turns of 4–16 s, each by a member other than the
/// last speaker, with pauses of 0–1 s between them, drawn from the caller's stream.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TurnTaking {
    /// How many members take turns.
    members: usize,
    /// The member talking now, if any.
    speaker: Option<usize>,
    /// The last member who talked.
    last: usize,
    /// Seconds until the current turn or pause ends.
    left: f32,
}

impl TurnTaking {
    /// Turns among `members` (at least 2), starting after a pause of `pause` seconds.
    pub fn new(members: usize, pause: f32) -> TurnTaking {
        TurnTaking {
            members,
            speaker: None,
            last: usize::MAX,
            left: pause,
        }
    }

    /// The member talking now, if any.
    pub fn speaker(&self) -> Option<usize> {
        self.speaker
    }

    /// Moves on by `dt` seconds, drawing from `random`; returns who talks now.
    pub fn advance(&mut self, dt: f32, random: &mut Random) -> Option<usize> {
        self.left -= dt;
        if self.left <= 0.0 {
            if self.speaker.take().is_some() {
                self.left = random.range(0.0, 1.0);
            } else {
                let mut speaker = random.below(self.members as u32) as usize;
                if speaker == self.last {
                    speaker = (speaker + 1) % self.members;
                }
                self.speaker = Some(speaker);
                self.last = speaker;
                self.left = random.range(4.0, 16.0);
            }
        }
        self.speaker
    }
}

/// A group of a scenario's people standing together and talking in turns ([`TurnTaking`],
/// seeded).
#[derive(Debug, Clone, PartialEq)]
pub struct TalkingGroup {
    /// The members, as indices into [`Scenario::people`].
    pub members: Vec<usize>,
    /// Who talks when (indices into `members`).
    pub turns: TurnTaking,
    /// The group's conversation id in the crowd, after [`Scenario::populate`].
    pub conversation: Option<u32>,
}

impl Scenario {
    /// The paper's second example: `people` characters on a 120 m × 14 m street, about 75%
    /// walking up or down it at 0.9–1.6 m/s, 15% standing, 10% sitting on benches, and
    /// `props` objects (shop windows, benches, lamps, posters) along both sides.
    pub fn street(people: usize, props: usize, seed: u64) -> Scenario {
        let mut random = stream(seed, Purpose::Scene, 0);
        let (length, width) = (120.0, 14.0);
        let mut prop_list = Vec::with_capacity(props);
        for i in 0..props {
            let side = i % 2;
            let x =
                (i / 2) as f32 * length / (props / 2 + 1).max(1) as f32 + random.range(0.0, 2.0);
            let y = if side == 0 { 0.3 } else { width - 0.3 };
            let heading = if side == 0 {
                std::f32::consts::FRAC_PI_2
            } else {
                -std::f32::consts::FRAC_PI_2
            };
            let (look_at_height, impact) = match i % 4 {
                0 => (1.5, random.range(0.6, 1.0)), // shop window
                1 => (0.5, random.range(0.3, 0.6)), // bench
                2 => (3.5, random.range(0.2, 0.5)), // lamp
                _ => (2.0, random.range(0.5, 0.9)), // poster
            };
            prop_list.push(Prop {
                position: Vec2::new(x, y),
                heading,
                look_at_height,
                impact,
            });
        }
        let mut people_list = Vec::with_capacity(people);
        for _ in 0..people {
            let roll = random.next_f32();
            let position = Vec2::new(random.range(0.0, length), random.range(1.5, width - 1.5));
            let person = if roll < 0.75 {
                let direction = if random.next_f32() < 0.5 { 1.0 } else { -1.0 };
                let speed = random.range(0.9, 1.6);
                Person {
                    position,
                    velocity: Vec2::new(direction * speed, random.range(-0.1, 0.1)),
                    heading: if direction > 0.0 {
                        0.0
                    } else {
                        std::f32::consts::PI
                    },
                    activity: Activity::Walking,
                }
            } else if roll < 0.9 {
                Person {
                    position,
                    velocity: Vec2::ZERO,
                    heading: random.range(-std::f32::consts::PI, std::f32::consts::PI),
                    activity: Activity::Standing,
                }
            } else {
                let side = random.next_f32() < 0.5;
                Person {
                    position: Vec2::new(position.x, if side { 1.0 } else { width - 1.0 }),
                    velocity: Vec2::ZERO,
                    heading: if side {
                        std::f32::consts::FRAC_PI_2
                    } else {
                        -std::f32::consts::FRAC_PI_2
                    },
                    activity: Activity::Sitting,
                }
            };
            people_list.push(person);
        }
        Scenario {
            people: people_list,
            props: prop_list,
            length,
            width,
            random,
            ids: Vec::new(),
            groups: Vec::new(),
            talking: vec![false; people],
            chains: Vec::new(),
        }
    }

    /// Puts about `share` (0 to 1) of the people in groups of two and three (alternately)
    /// standing together on the pavements, facing each other, talking in turns (seeded by
    /// `seed`); [`populate`](Self::populate) makes each group a conversation of the crowd
    /// and [`push`](Self::push) flags who talks.
    pub fn with_conversations(mut self, share: f32, seed: u64) -> Scenario {
        let mut random = stream(seed, Purpose::Scene, 2);
        let wanted = (share.clamp(0.0, 1.0) * self.people.len() as f32).round() as usize;
        let mut next = 0;
        let mut size = 2;
        while next + size <= wanted.min(self.people.len()) {
            let centre = Vec2::new(
                random.range(2.0, (self.length - 2.0).max(2.0)),
                if random.next_f32() < 0.5 {
                    2.2
                } else {
                    self.width - 2.2
                },
            );
            let turn = random.range(0.0, std::f32::consts::TAU);
            let members: Vec<usize> = (next..next + size).collect();
            for (k, &member) in members.iter().enumerate() {
                let angle = turn + std::f32::consts::TAU * k as f32 / size as f32;
                let position = centre + 0.7 * Vec2::from_angle(angle);
                let to_centre = centre - position;
                self.people[member] = Person {
                    position,
                    velocity: Vec2::ZERO,
                    heading: to_centre.y.atan2(to_centre.x),
                    activity: Activity::Standing,
                };
            }
            self.groups.push(TalkingGroup {
                turns: TurnTaking::new(members.len(), random.range(0.0, 2.0)),
                members,
                conversation: None,
            });
            next += size;
            size = 5 - size; // 2, 3, 2, 3, ...
        }
        self.random = random;
        self
    }

    /// `people` random walkers in a square plaza at `density` people per m² (1.0–1.6 m/s,
    /// random directions), no props. Used to measure cost against crowd size at a fixed
    /// density.
    pub fn plaza(people: usize, density: f32, seed: u64) -> Scenario {
        let mut random = stream(seed, Purpose::Scene, 1);
        let side = (people as f32 / density).sqrt().max(1.0);
        let people_list = (0..people)
            .map(|_| {
                let direction =
                    Vec2::from_angle(random.range(-std::f32::consts::PI, std::f32::consts::PI));
                Person {
                    position: Vec2::new(random.range(0.0, side), random.range(0.0, side)),
                    velocity: direction * random.range(1.0, 1.6),
                    heading: 0.0,
                    activity: Activity::Walking,
                }
            })
            .collect();
        Scenario {
            people: people_list,
            props: Vec::new(),
            length: side,
            width: side,
            random,
            ids: Vec::new(),
            groups: Vec::new(),
            talking: vec![false; people],
            chains: Vec::new(),
        }
    }

    fn to_world(world: &World, ground: Vec2) -> Vec3 {
        world.forward * ground.x + world.side * ground.y
    }

    /// Gives person `i` the gaze chain `chains[i % chains.len()]` (in the crowd's axes) when
    /// [`populate`](Self::populate) adds them: a crowd of mixed rigs. No chains (the
    /// default): everyone gets the crowd's human chain.
    pub fn with_chains(mut self, chains: Vec<GazeChain>) -> Scenario {
        self.chains = chains;
        self
    }

    /// Adds every person as a character and every prop as an object to `crowd`.
    pub fn populate(&mut self, crowd: &mut Crowd) -> Result<()> {
        let world = crowd.config().world;
        self.ids.clear();
        for person in &self.people {
            let chain = match self.chains.len() {
                0 => None,
                kinds => Some(self.chains[self.ids.len() % kinds]),
            };
            let id = crowd.add_character(&CharacterDesc {
                position: Self::to_world(&world, person.position),
                heading: person.heading,
                chain,
                ..CharacterDesc::default()
            })?;
            self.ids.push(id);
        }
        for prop in &self.props {
            crowd.add_object(&ObjectDesc {
                position: Self::to_world(&world, prop.position),
                heading: prop.heading,
                look_at_height: prop.look_at_height,
                impact: prop.impact,
            })?;
        }
        for group in &mut self.groups {
            let members: Vec<u32> = group.members.iter().map(|&m| self.ids[m]).collect();
            group.conversation = Some(crowd.set_conversation(&members)?);
        }
        Ok(())
    }

    /// Whether person `i` talks now.
    pub fn talking(&self, i: usize) -> bool {
        self.talking[i]
    }

    /// The group person `i` stands in, if any (an index into [`groups`](Self::groups)).
    pub fn group_of(&self, i: usize) -> Option<usize> {
        self.groups
            .iter()
            .position(|group| group.members.contains(&i))
    }

    /// The character ids of the people, in order (after [`populate`](Self::populate)).
    pub fn character_ids(&self) -> &[u32] {
        &self.ids
    }

    /// The world point at ground coordinates `ground` (metres along forward and side, as
    /// [`Person::position`]) and `height` metres above the ground, in `world`'s axes.
    pub fn world_point(world: &World, ground: Vec2, height: f32) -> Vec3 {
        Self::to_world(world, ground) + world.up * height
    }

    /// Makes person `i` stop where it is, turn to face `point` (world, metres) and stare at
    /// it: it stands from now on ([`Activity::Standing`]) and has `point` as an overriding
    /// explicit gaze target in `crowd` (after [`populate`](Self::populate)) until the
    /// caller clears it. A scripted stimulus, e.g. for gaze following: the scenario only
    /// moves people; where the others look is the crowd's business.
    pub fn stop_and_look(&mut self, crowd: &mut Crowd, i: usize, point: Vec3) -> Result<()> {
        let world = crowd.config().world;
        let person = &mut self.people[i];
        let to_point = world.ground(point) - person.position;
        person.activity = Activity::Standing;
        person.velocity = Vec2::ZERO;
        if to_point.length_squared() > 1e-6 {
            person.heading = to_point.y.atan2(to_point.x);
        }
        crowd.set_gaze_target(
            self.ids[i],
            ExplicitTarget::Point(point),
            TargetPriority::Override,
        )
    }

    /// Moves every walker by `dt` seconds; walkers turn back at the ends and drift a
    /// little sideways, staying inside the rectangle. Groups go on with their turns.
    pub fn advance(&mut self, dt: f32) {
        for group in &mut self.groups {
            let before = group.turns.speaker();
            let now = group.turns.advance(dt, &mut self.random);
            if before != now {
                if let Some(member) = before {
                    self.talking[group.members[member]] = false;
                }
                if let Some(member) = now {
                    self.talking[group.members[member]] = true;
                }
            }
        }
        for person in &mut self.people {
            if person.activity != Activity::Walking {
                continue;
            }
            person.position += person.velocity * dt;
            if person.position.x < 0.0 || person.position.x > self.length {
                person.velocity.x = -person.velocity.x;
                person.position.x = person.position.x.clamp(0.0, self.length);
            }
            if person.position.y < 1.0 || person.position.y > self.width - 1.0 {
                person.velocity.y = -person.velocity.y;
                person.position.y = person.position.y.clamp(1.0, self.width - 1.0);
            }
            // A gentle random drift of the sideways speed keeps the crowd varied.
            person.velocity.y =
                (person.velocity.y + self.random.range(-0.02, 0.02)).clamp(-0.3, 0.3);
        }
    }

    /// The entity update of person `i` (position, heading from motion for walkers).
    pub fn update(&self, world: &World, i: usize) -> EntityUpdate {
        let person = &self.people[i];
        EntityUpdate {
            id: self.ids[i],
            position: Self::to_world(world, person.position),
            heading: person.heading,
            heading_from_motion: person.activity == Activity::Walking,
            velocity: None,
            talking: self.talking[i],
        }
    }

    /// Plays `frames` frames of `dt` seconds: moves the people, pushes their states (times
    /// continuing after the crowd's last frame), steps the crowd, then calls `each`.
    pub fn play(
        &mut self,
        crowd: &mut Crowd,
        frames: usize,
        dt: f32,
        mut each: impl FnMut(&Crowd),
    ) -> Result<()> {
        let start = crowd.time().max(0.0);
        for frame in 0..frames {
            self.advance(dt);
            self.push(crowd, start + (frame + 1) as f64 * f64::from(dt))?;
            crowd.step(dt)?;
            each(crowd);
        }
        Ok(())
    }

    /// Pushes every person's state to `crowd` at time `time` (no allocation).
    pub fn push(&self, crowd: &mut Crowd, time: f64) -> Result<()> {
        let world = crowd.config().world;
        crowd.push_frame_with(time, self.people.len(), |i| Ok(self.update(&world, i)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::crowd::CrowdConfig;

    #[test]
    fn groups_stand_together_and_talk_one_at_a_time() {
        let mut scenario = Scenario::street(60, 10, 3).with_conversations(1.0 / 3.0, 5);
        // 20 people in groups of 2, 3, 2, 3, ...: 2 + 3 + 2 + 3 + 2 + 3 + 2 = 17, then 3.
        let grouped: usize = scenario.groups.iter().map(|g| g.members.len()).sum();
        assert_eq!(grouped, 20);
        let mut crowd = Crowd::new(CrowdConfig::default()).unwrap();
        scenario.populate(&mut crowd).unwrap();
        let mut talked = [false; 60];
        for _ in 0..900 {
            scenario.advance(1.0 / 30.0);
            for group in &scenario.groups {
                let talking = group
                    .members
                    .iter()
                    .filter(|&&m| scenario.talking(m))
                    .count();
                assert!(talking <= 1);
                for &m in &group.members {
                    talked[m] |= scenario.talking(m);
                    assert_eq!(scenario.people[m].activity, Activity::Standing);
                }
            }
        }
        assert!(talked.iter().filter(|&&t| t).count() >= 10);
        for (g, group) in scenario.groups.iter().enumerate() {
            let id = scenario.character_ids()[group.members[0]];
            assert_eq!(crowd.conversation_of(id).unwrap(), group.conversation);
            assert_eq!(scenario.group_of(group.members[0]), Some(g));
        }
    }

    #[test]
    fn street_is_deterministic_and_has_the_papers_mix() {
        let a = Scenario::street(130, 60, 9);
        let b = Scenario::street(130, 60, 9);
        assert_eq!(a.people, b.people);
        assert_eq!(a.props.len(), 60);
        let walking = a
            .people
            .iter()
            .filter(|p| p.activity == Activity::Walking)
            .count();
        assert!((80..115).contains(&walking), "{walking}");
        assert_ne!(a.people, Scenario::street(130, 60, 10).people);
    }

    #[test]
    fn a_stopped_person_stands_facing_the_point_and_stares_at_it() {
        let mut scenario = Scenario::street(20, 4, 2);
        let mut crowd = Crowd::new(CrowdConfig::default()).unwrap();
        scenario.populate(&mut crowd).unwrap();
        let walker = (0..20)
            .find(|&i| scenario.people[i].activity == Activity::Walking)
            .unwrap();
        let world = crowd.config().world;
        let ground = scenario.people[walker].position + Vec2::new(0.0, 3.0);
        let point = Scenario::world_point(&world, ground, 10.0);
        assert!((world.height(point) - 10.0).abs() < 1e-5);
        scenario.stop_and_look(&mut crowd, walker, point).unwrap();
        let before = scenario.people[walker].position;
        scenario.play(&mut crowd, 30, 1.0 / 30.0, |_| {}).unwrap();
        let person = scenario.people[walker];
        assert_eq!(person.position, before);
        assert_eq!(person.activity, Activity::Standing);
        assert!((person.heading - std::f32::consts::FRAC_PI_2).abs() < 1e-5);
        let id = scenario.character_ids()[walker];
        let head = crowd.gaze_motion(id).unwrap().gaze_ray();
        let to_point = (point - head.0).normalize();
        assert!(head.1.dot(to_point) > 0.9, "{:?} vs {to_point:?}", head.1);
    }

    #[test]
    fn people_stay_on_the_street() {
        let mut scenario = Scenario::street(50, 10, 1);
        let mut crowd = Crowd::new(CrowdConfig::default()).unwrap();
        scenario.populate(&mut crowd).unwrap();
        for frame in 0..3000 {
            scenario.advance(1.0 / 30.0);
            scenario.push(&mut crowd, frame as f64 / 30.0).unwrap();
        }
        for person in &scenario.people {
            assert!((0.0..=120.0).contains(&person.position.x));
            assert!((0.0..=14.0).contains(&person.position.y));
        }
    }
}
