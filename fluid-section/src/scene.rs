//! What fluid-proc reads of a scenario, checked as one: the coupling part,
//! `[fluid]`, and the bodies of `[rigid]` that stand in the flow; and the
//! checks that need the coupling part (ranks, the window's Courant number,
//! which partners each model can take).

use crate::flow::{body_halo_cells, SideSpec, HALO_CELLS, MAX_COURANT, SIDE_KEYS};
use crate::frame::FrameSpec;
use crate::{FluidModel, FluidSection};
use rigid_section::RigidSection;
use scenario::{section, Checker, Scenario, ScenarioError};
use std::path::Path;

/// The message for fabric keys with no canopy to carry them; the structure
/// gives the same one when it is listed but sends no canopy surface.
pub const POROSITY_WITHOUT_CANOPY: &str = "porosity, diameter and thickness describe the \
     canopy's fabric, but no participant `structure` sends a canopy surface \
     ([structure.annulus], [structure.parachute] or [structure.cloth]): give one, or leave the \
     keys out";

/// The scenario as fluid-proc reads it.
#[derive(Debug, Clone)]
pub struct Scene {
    pub scenario: Scenario,
    pub fluid: FluidSection,
    /// `[rigid]`, when participant `rigid` is listed: its shaped bodies
    /// are immersed boundaries of the incompressible flow and walls of the
    /// gas.
    pub rigid: Option<RigidSection>,
}

impl Scene {
    /// Reads and checks the scenario text from `path`, as `--check` and a
    /// run both do.
    pub fn load(path: &Path, text: &str) -> Result<Scene, ScenarioError> {
        let scenario = Scenario::parse(path, text)?;
        let fluid = section::read::<FluidSection>(path, text, "fluid")?
            .ok_or_else(|| section::missing(path, "fluid", "fluid-proc"))?;
        section::checked(path, text, |c| fluid.check(c))?;
        let rigid = match scenario.participants.lists("rigid") {
            true => RigidSection::load(path, text)?,
            false => None,
        };
        section::checked(path, text, |c| {
            check_partners(c, &scenario, &fluid, rigid.as_ref())
        })?;
        Ok(Scene {
            scenario,
            fluid,
            rigid,
        })
    }

    /// The velocity [m/s] over the ground the flow box starts with when it
    /// follows the parachute (`[fluid.frame]`), None for a fixed box.
    pub fn frame_start(&self) -> Option<[f64; 3]> {
        let frame = self.fluid.frame.as_ref()?;
        Some(frame.start_velocity(followed(frame, self.rigid.as_ref())?))
    }

    /// [`Scene::load`] of the file at `path`.
    pub fn load_file(path: &Path) -> Result<Scene, ScenarioError> {
        Scene::load(path, &scenario::read_text(path)?)
    }
}

/// The checks of `[fluid]` against the coupling part and `[rigid]`.
fn check_partners(
    c: &mut Checker,
    scenario: &Scenario,
    s: &FluidSection,
    rigid: Option<&RigidSection>,
) {
    let listed = |name| scenario.participants.lists(name);
    // The incompressible flow takes the canopy and rigid bodies (immersed
    // boundaries); the gas takes rigid bodies (ghost cells), not the canopy yet.
    if s.model == FluidModel::Euler && listed("structure") {
        c.problem(
            &["fluid", "model"],
            "model = \"euler\" is not coupled to a structure yet: use model = \
             \"incompressible\" or \"porous-free-stream\" for such a scene"
                .into(),
        );
    }
    if s.model == FluidModel::Euler {
        check_gas_bodies(c, s, rigid);
    }
    if s.model == FluidModel::Incompressible && s.porosity.is_some() && !listed("structure") {
        c.problem(&["fluid", "porosity"], POROSITY_WITHOUT_CANOPY.into());
    }
    let ranks = scenario.participants.get("fluid").map_or(1, |f| f.ranks());
    if ranks > 1 {
        let walls = s.model == FluidModel::Euler
            && rigid.is_some_and(|r| r.bodies.iter().any(|b| b.shape.is_some()));
        check_ranks(c, s, ranks, walls);
    }
    check_device(c, s, ranks);
    let frame = check_frame(c, scenario, s, rigid);
    let window = scenario.coupling.window;
    let courant = s.start_courant(window, frame).unwrap_or(0.0);
    if courant > MAX_COURANT {
        c.problem(
            &["coupling", "window"],
            format!(
                "window = {window} s is one flow step, and at the sides' speed it crosses \
                 {courant:.3} cells (the Courant number): more than {MAX_COURANT} is unstable, \
                 so shorten it"
            ),
        );
    }
}

/// What `device = "gpu"` does not run yet among the partners: the flow
/// on several ranks.
fn check_device(c: &mut Checker, s: &FluidSection, ranks: u32) {
    if s.device == crate::Device::Gpu && ranks > 1 {
        c.problem(
            &["fluid", "device"],
            "device = \"gpu\" does not run the flow on several ranks yet: use device = \"cpu\""
                .into(),
        );
    }
}

/// Whether what `[fluid.frame]` follows takes part: the canopy a
/// structure sends, or a body of `[rigid]`. Returns the frame's velocity
/// at the start [m/s] (zero without a frame).
fn check_frame(
    c: &mut Checker,
    scenario: &Scenario,
    s: &FluidSection,
    rigid: Option<&RigidSection>,
) -> [f64; 3] {
    let Some(frame) = &s.frame else {
        return [0.0; 3];
    };
    let key = ["fluid", "frame", "follow"];
    if frame.follows_canopy() && !scenario.participants.lists("structure") {
        c.problem(
            &key,
            "follow = \"canopy\" needs a participant `structure` to send the canopy".into(),
        );
    }
    match followed(frame, rigid) {
        Some(initial) => frame.start_velocity(initial),
        None => {
            c.problem(
                &key,
                format!(
                    "follow = \"{}\" is neither \"canopy\" nor a body of [[rigid.bodies]] \
                     (with a participant `rigid`)",
                    frame.follow
                ),
            );
            [0.0; 3]
        }
    }
}

/// The initial velocity [m/s] of what `frame` follows: Some(None) for the
/// canopy (the structure's own), None when it names no body of `rigid`.
fn followed(frame: &FrameSpec, rigid: Option<&RigidSection>) -> Option<Option<[f64; 3]>> {
    if frame.follows_canopy() {
        return Some(None);
    }
    let bodies = rigid.map_or(&[][..], |r| &r.bodies[..]);
    let body = bodies.iter().find(|b| b.name == frame.follow)?;
    Some(Some(body.velocity))
}

/// A body with a shape stands in the gas as a wall, which a 1-D tube has
/// no room for: the box must vary along two axes at least. Its ghost
/// cells do not wrap round a periodic side.
fn check_gas_bodies(c: &mut Checker, s: &FluidSection, rigid: Option<&RigidSection>) {
    let (Some(b), Some(rigid), Some(sides)) = (s.flow_box, rigid, s.resolved_sides()) else {
        return;
    };
    let Some(i) = rigid.bodies.iter().position(|b| b.shape.is_some()) else {
        return;
    };
    let name = &rigid.bodies[i].name;
    if b.cells.iter().filter(|&&n| n > 1).count() < 2 {
        c.within("rigid", None, |c| {
            c.within("bodies", Some(i), |c| {
                c.problem(
                    &["shape"],
                    "a body with a shape is a wall in the gas, and this box is one cell \
                     thick along two axes (a 1-D tube): give it cells along two axes at \
                     least, or leave the shape out (a mass point stays out of the gas)"
                        .into(),
                )
            })
        });
        return;
    }
    let periodic = (0..3)
        .filter(|&d| b.cells[d] > 1)
        .find(|&d| sides[d][0] == SideSpec::Periodic);
    if let Some(d) = periodic {
        c.problem(
            &["fluid", "sides", SIDE_KEYS[d][0]],
            format!(
                "body `{name}` stands in the gas as a wall, whose ghost cells do not wrap \
                 round a periodic side yet: give the box walls, outflows or states here"
            ),
        );
    }
}

/// Whether the fluid can run on `ranks` ranks: a model split among ranks
/// (euler and incompressible), and slabs at least as thick as the
/// stencil's reach (the image points' with bodies in the gas, `walls`),
/// so that each rank's halo comes from its two neighbours.
fn check_ranks(c: &mut Checker, s: &FluidSection, ranks: u32, walls: bool) {
    let key = ["participants", "fluid", "ranks"];
    if s.model == FluidModel::PorousFreeStream {
        c.problem(
            &key,
            format!(
                "ranks = {ranks}: model = \"{}\" has no cells to split and runs on one rank",
                s.model.name()
            ),
        );
        return;
    }
    let Some(b) = s.flow_box else { return };
    let axis = if s.model == FluidModel::Euler {
        // The one with the most cells, the last of equals.
        (0..3).rev().max_by_key(|&d| (b.cells[d], d)).unwrap_or(0)
    } else {
        // The slowest in memory more than one cell thick (fluid-proc's part.rs).
        match (1..3).rev().find(|&d| b.cells[d] > 1) {
            Some(d) => d,
            None => {
                c.problem(
                    &key,
                    format!("ranks = {ranks}: the incompressible flow is split along y or z, and this box is one cell thick along both"),
                );
                return;
            }
        }
    };
    let active = b.cells.map(|n| n > 1);
    let least = match walls {
        true => body_halo_cells(b.spacing(), active, axis),
        false => HALO_CELLS,
    };
    if u64::from(b.cells[axis]) < u64::from(least) * u64::from(ranks) {
        let with = if walls { " (bodies in the gas)" } else { "" };
        c.problem(
            &key,
            format!(
                "ranks = {ranks} leaves fewer than {least} cells per rank{with} along {} ({} \
                 cells): use fewer ranks",
                ["x", "y", "z"][axis],
                b.cells[axis]
            ),
        );
    }
}
