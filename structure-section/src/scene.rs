//! What a structure program reads of a scenario, checked as one: the
//! coupling part, `[structure]`, and of its partners' tables what the
//! structure depends on: the bodies of `[rigid]` its strings hold and its
//! nodes collide with, and the flow of `[fluid]` its canopy stands in.

use crate::{canopy_in_flow, StructureSection};
use fluid_section::FluidSection;
use rigid_section::RigidSection;
use scenario::{section, Checker, Scenario, ScenarioError};
use std::path::Path;

/// The scenario as a structure program reads it.
#[derive(Debug, Clone)]
pub struct Scene {
    pub scenario: Scenario,
    pub structure: StructureSection,
    /// `[rigid]`, when participant `rigid` is listed.
    pub rigid: Option<RigidSection>,
    /// `[fluid]`, when participant `fluid` is listed.
    pub fluid: Option<FluidSection>,
}

impl Scene {
    /// Reads and checks the scenario text from `path` for `program`, as
    /// `--check` and a run both do. A partner's table with a problem gives
    /// the same message its own program gives (the coupler prints it once).
    pub fn load(path: &Path, text: &str, program: &str) -> Result<Scene, ScenarioError> {
        let scenario = Scenario::parse(path, text)?;
        let structure = section::read::<StructureSection>(path, text, "structure")?
            .ok_or_else(|| section::missing(path, "structure", program))?;
        let listed = |name| scenario.participants.lists(name);
        let rigid = match listed("rigid") {
            true => RigidSection::load(path, text)?,
            false => None,
        };
        let fluid = match listed("fluid") {
            true => section::read::<FluidSection>(path, text, "fluid")?,
            false => None,
        };
        if let Some(f) = &fluid {
            section::checked(path, text, |c| f.check(c))?;
        }
        let scene = Scene {
            scenario,
            structure,
            rigid,
            fluid,
        };
        section::checked(path, text, |c| scene.check(c, program))?;
        Ok(scene)
    }

    /// [`Scene::load`] of the file at `path`.
    pub fn load_file(path: &Path, program: &str) -> Result<Scene, ScenarioError> {
        Scene::load(path, &scenario::read_text(path)?, program)
    }

    fn check(&self, c: &mut Checker, program: &str) {
        let s = &self.structure;
        // Which participant loads the canopy comes before the section's own keys.
        if s.porous.is_some() && self.scenario.participants.lists("fluid") {
            c.problem(
                &["structure", "porous"],
                "[structure.porous] makes the structure apply the porous load itself, but \
                 participant `fluid` loads the canopy too: keep one of them"
                    .into(),
            );
        }
        s.check(c, self.rigid.as_ref());
        let n_i = self.scenario.coupling.impulse_substeps;
        if n_i > 0 && !s.substeps.is_multiple_of(n_i) {
            c.problem(
                &["structure", "substeps"],
                format!(
                    "substeps = {} is not a multiple of [coupling] impulse_substeps = {n_i}: \
                     each impulse exchange comes after a whole number of structure sub-steps",
                    s.substeps
                ),
            );
        }
        if let Some(f) = &self.fluid {
            canopy_in_flow::check(c, f, s);
        }
        self.scenario.check_one_process(c, "structure", program);
    }
}
