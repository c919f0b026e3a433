//! The offline plan (the paper's own pipeline): attention planned over the recorded frames,
//! each character's exact percentile threshold and its constraints, then replayed by the
//! steps.

use super::Crowd;
use crate::attention::plan::{Constraint, Plan};
use crate::error::{Error, Result};

impl Crowd {
    /// Plans attention offline over the recorded frames (see the module docs). Requires
    /// `max_recorded_states > 0` and at least one recorded frame. The plan holds about
    /// 8 bytes per recorded frame and character (25 while planning): when that does not
    /// fit in memory this fails with [`Error::OutOfMemory`] and changes nothing.
    pub fn plan(&mut self) -> Result<()> {
        self.ensure_online("plan again")?;
        if self.shared.recording.frame_count() == 0 {
            return Err(Error::WrongState(
                "nothing recorded: set max_recorded_states and push frames before planning".into(),
            ));
        }
        let shared = &mut *self.shared;
        let plan = Plan::build(
            &shared.recording,
            &mut shared.scene,
            &mut shared.neighbours,
            &shared.scorer,
            &shared.characters.params,
            &shared.config.interest,
        )?;
        shared.plan = Some(plan);
        Ok(())
    }

    /// Leaves planned mode and forgets the recording; pushing frames works again.
    pub fn clear_plan(&mut self) {
        self.shared.plan = None;
        self.shared.recording.clear();
    }

    /// True while stepping follows a plan.
    pub fn is_planned(&self) -> bool {
        self.shared.plan.is_some()
    }

    /// A character's planned constraints (entity, `t_b`, `t_e`), in time order.
    pub fn constraints(&self, character_id: u32) -> Result<&[Constraint]> {
        let character = self.shared.scene.character_index(character_id)?;
        let plan = self
            .shared
            .plan
            .as_ref()
            .ok_or_else(|| Error::WrongState("no plan: call plan() first".into()))?;
        Ok(plan.constraints(character))
    }

    /// A character's planned threshold `A` (the exact percentile).
    pub fn planned_threshold(&self, character_id: u32) -> Result<f32> {
        let character = self.shared.scene.character_index(character_id)?;
        let plan = self
            .shared
            .plan
            .as_ref()
            .ok_or_else(|| Error::WrongState("no plan: call plan() first".into()))?;
        Ok(plan.threshold(character))
    }
}
