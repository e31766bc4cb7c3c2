//! A whole scenario as the tests edit it: the coupling part and the
//! sections of canopy's own three participants, each read by the crate
//! that owns it, written back as one file.

use fluid_section::FluidSection;
use rigid_section::RigidSection;
pub use scenario::ParticipantSpec;
use scenario::{section, CouplingSection, Participants, RunSection};
use serde::Serialize;
use std::path::Path;
use structure_section::{Parachute, StructureSection};

#[derive(Debug, Clone, Serialize)]
pub struct Scenario {
    pub run: RunSection,
    pub coupling: CouplingSection,
    pub participants: Participants,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fluid: Option<FluidSection>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub structure: Option<StructureSection>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rigid: Option<RigidSection>,
}

impl Scenario {
    /// Reads the file at `path`: its coupling part checked, each section
    /// parsed (their programs check them when a test runs the scene).
    pub fn load(path: &Path) -> Result<Scenario, scenario::ScenarioError> {
        let text = scenario::read_text(path)?;
        let base = scenario::Scenario::parse(path, &text)?;
        Ok(Scenario {
            run: base.run,
            coupling: base.coupling,
            participants: base.participants,
            fluid: section::read(path, &text, "fluid")?,
            structure: section::read(path, &text, "structure")?,
            rigid: RigidSection::load(path, &text)?,
        })
    }

    /// The scene's `[structure]`, to change (panics without one).
    pub fn structure_mut(&mut self) -> &mut StructureSection {
        self.structure.as_mut().expect("a [structure] section")
    }

    /// The scene's `[structure.parachute]` (panics without one).
    pub fn parachute(&self) -> &Parachute {
        let s = self.structure.as_ref().expect("a [structure] section");
        s.parachute.as_ref().expect("a [structure.parachute]")
    }

    /// The same, to change.
    pub fn parachute_mut(&mut self) -> &mut Parachute {
        let s = self.structure.as_mut().expect("a [structure] section");
        s.parachute.as_mut().expect("a [structure.parachute]")
    }

    /// The coupling part alone, with its clock.
    pub fn base(&self) -> scenario::Scenario {
        scenario::Scenario {
            run: self.run.clone(),
            coupling: self.coupling.clone(),
            participants: self.participants.clone(),
            sections: Vec::new(),
        }
    }

    /// The scenario as a file.
    pub fn to_toml(&self) -> String {
        toml::to_string_pretty(self).expect("a scenario always serialises")
    }
}
