//! What rigid-proc reads of a scenario, checked as one.

use crate::{attachments, AttachmentSpec, RigidSection};
use scenario::{section, Scenario, ScenarioError};
use std::path::Path;

/// What rigid-proc reads of a scenario: the coupling part, `[rigid]`, and
/// where the structure's strings attach to the bodies.
#[derive(Debug, Clone)]
pub struct Scene {
    pub scenario: Scenario,
    pub rigid: RigidSection,
    pub attachments: Vec<AttachmentSpec>,
}

impl Scene {
    /// Reads and checks the scenario text from `path`, as `--check` and a
    /// run both do.
    pub fn load(path: &Path, text: &str) -> Result<Scene, ScenarioError> {
        let scenario = Scenario::parse(path, text)?;
        section::checked(path, text, |c| {
            scenario.check_one_process(c, "rigid", "rigid-proc")
        })?;
        let rigid = RigidSection::load(path, text)?
            .ok_or_else(|| section::missing(path, "rigid", "rigid-proc"))?;
        let attachments = attachments(path, text)?;
        Ok(Scene {
            scenario,
            rigid,
            attachments,
        })
    }
}
