//! The crowd: owns every character and object, and the state of attention and gaze for each.

use crate::error::{Error, Result};
use crate::world::World;

/// Largest capacity accepted for characters or objects (keeps index arithmetic in `u32`).
pub const MAX_CAPACITY: u32 = 1 << 24;

/// How a crowd is set up. Capacities are fixed for the crowd's lifetime: every buffer is
/// sized from them at creation, so stepping never allocates.
#[derive(Debug, Clone, PartialEq)]
pub struct CrowdConfig {
    /// Seed of every random choice (per-character weights, attention percentage,
    /// deactivation times). Same inputs and seed give bit-identical outputs.
    pub seed: u64,
    /// Most characters (entities that look) the crowd can hold at once.
    pub max_characters: u32,
    /// Most scene objects (entities that are only looked at) the crowd can hold at once.
    pub max_objects: u32,
    /// Axes and length unit of the caller's world.
    pub world: World,
}

impl Default for CrowdConfig {
    fn default() -> Self {
        CrowdConfig {
            seed: 0x6372_6f77_6467_617a, // "crowdgaz"
            max_characters: 1024,
            max_objects: 256,
            world: World::default(),
        }
    }
}

impl CrowdConfig {
    /// Checks every field against its documented range.
    pub fn validate(&self) -> Result<()> {
        if self.max_characters == 0 || self.max_characters > MAX_CAPACITY {
            return Err(Error::InvalidArgument(format!(
                "max_characters is {}, must be 1..={MAX_CAPACITY}",
                self.max_characters
            )));
        }
        if self.max_objects > MAX_CAPACITY {
            return Err(Error::InvalidArgument(format!(
                "max_objects is {}, must be 0..={MAX_CAPACITY}",
                self.max_objects
            )));
        }
        Ok(())
    }
}

/// A crowd of characters and the objects they may look at.
///
/// Not safe for concurrent mutation; shared (`&Crowd`) reads may run concurrently.
#[derive(Debug)]
pub struct Crowd {
    config: CrowdConfig,
}

impl Crowd {
    /// Creates an empty crowd, sizing every buffer from `config`.
    pub fn new(config: CrowdConfig) -> Result<Crowd> {
        config.validate()?;
        Ok(Crowd { config })
    }

    /// The configuration the crowd was created with.
    pub fn config(&self) -> &CrowdConfig {
        &self.config
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn capacities_are_checked() {
        assert!(Crowd::new(CrowdConfig::default()).is_ok());
        let none = CrowdConfig {
            max_characters: 0,
            ..CrowdConfig::default()
        };
        assert!(matches!(Crowd::new(none), Err(Error::InvalidArgument(_))));
        let huge = CrowdConfig {
            max_objects: MAX_CAPACITY + 1,
            ..CrowdConfig::default()
        };
        assert!(matches!(Crowd::new(huge), Err(Error::InvalidArgument(_))));
    }
}
