//! Ingesting a frame: the entities' positions, headings and velocities from the engine,
//! checked, into the scene (and the recording, for the offline plan).

use super::Crowd;
use crate::error::{Error, Result};
use crate::scene::EntityUpdate;

impl Crowd {
    /// Time of the last pushed frame (−∞ before the first).
    pub fn time(&self) -> f64 {
        self.shared.time
    }

    /// Ingests one frame of entity states at time `time` (seconds, not earlier than the
    /// previous frame). Entities not listed keep their last state. With recording on, the
    /// states are also recorded for [`plan`](Self::plan). Fails without changing anything
    /// on an unknown id, a non-finite value, an earlier time, a full recording, or while a
    /// plan is active.
    pub fn push_frame(&mut self, time: f64, updates: &[EntityUpdate]) -> Result<()> {
        self.push_frame_with(time, updates.len(), |i| Ok(updates[i]))
    }

    /// [`push_frame`](Self::push_frame) for states produced on the fly: `state(i)` for
    /// `i < count` converts the caller's i-th state (it is called twice per state: once to
    /// check them all, once to apply). Lets a caller hand over its own layout without a
    /// buffer.
    pub fn push_frame_with<E: From<Error>>(
        &mut self,
        time: f64,
        count: usize,
        state: impl Fn(usize) -> std::result::Result<EntityUpdate, E>,
    ) -> std::result::Result<(), E> {
        if !time.is_finite() {
            return Err(Error::NonFinite(format!("frame time is {time}")).into());
        }
        if time < self.shared.time {
            return Err(Error::InvalidArgument(format!(
                "frame time {time} is earlier than the previous frame's {}",
                self.shared.time
            ))
            .into());
        }
        self.ensure_online("push a frame")?;
        for i in 0..count {
            self.shared.scene.check_update(&state(i)?)?;
        }
        if self.shared.recording.is_enabled() {
            self.shared
                .recording
                .record_with(time, count, |i| state(i).ok())?;
        }
        for i in 0..count {
            if let Ok(update) = state(i) {
                self.shared.scene.apply_one(time, &update);
            }
        }
        self.shared.time = time;
        Ok(())
    }
}
