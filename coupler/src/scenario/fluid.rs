//! `[fluid]`: the flow model fluid-proc runs:
//! - `porous-free-stream`: the Darcy–Forchheimer (Ergun) load of seed 003
//!   eqs. (6)–(10) in a uniform stream, whose keys [`PorousLoad`] also gives
//!   to `[structure.porous]`;
//! - `incompressible`: the Navier–Stokes solver of seed 000 §3.2.2 on a box
//!   of cells (`flow.rs`: `[fluid.box]`, `[fluid.sides]`).

use super::check::Checker;
use super::flow::{FlowBox, FlowSides};
use serde::{Deserialize, Serialize};

/// Density of air at sea level, ISA (ISO 2533:1975) [kg/m³].
pub const AIR_DENSITY: f64 = 1.225;
/// Dynamic viscosity of air at 15 °C, ISA (ISO 2533:1975) [Pa·s].
pub const AIR_VISCOSITY: f64 = 1.7894e-5;

fn air_density() -> f64 {
    AIR_DENSITY
}
fn air_viscosity() -> f64 {
    AIR_VISCOSITY
}

#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FluidModel {
    /// Uniform free stream through a porous canopy, no flow field (seed 003 §2.1).
    #[default]
    PorousFreeStream,
    /// Incompressible Navier–Stokes on a box of cells (seed 000 §3.2.2).
    Incompressible,
}

impl FluidModel {
    pub fn name(self) -> &'static str {
        match self {
            FluidModel::PorousFreeStream => "porous-free-stream",
            FluidModel::Incompressible => "incompressible",
        }
    }
}

/// The porous free-stream model's keys sit in `[fluid]` itself, so they
/// mirror [`PorousLoad`]'s: serde's `flatten` would share the declaration but
/// cannot be combined with `deny_unknown_fields`, and loses the line of a
/// mistyped value. [`FluidSection::porous_load`] is the one bridge. Which
/// keys a model needs is checked here, after parsing.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FluidSection {
    #[serde(default)]
    pub model: FluidModel,
    /// Density ρ [kg/m³].
    #[serde(default = "air_density")]
    pub density: f64,
    /// Dynamic viscosity μ [Pa·s].
    #[serde(default = "air_viscosity")]
    pub viscosity: f64,
    /// Free-stream velocity of the air [m/s] (porous-free-stream).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub free_stream: Option<[f64; 3]>,
    /// Fabric porosity ε (0 < ε < 1), seed 003 eqs. (7)–(9) (porous-free-stream).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub porosity: Option<f64>,
    /// Characteristic (Ergun) diameter D [m], seed 003 eqs. (7)–(8) (porous-free-stream).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub diameter: Option<f64>,
    /// Fabric thickness e [m], seed 003 eq. (6) (porous-free-stream).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thickness: Option<f64>,
    /// The box of cells (incompressible).
    #[serde(rename = "box", default, skip_serializing_if = "Option::is_none")]
    pub flow_box: Option<FlowBox>,
    /// What each side of the box does (incompressible); every side a wall
    /// when left out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sides: Option<FlowSides>,
    /// Velocity of the fluid at the start [m/s] (incompressible).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub initial_velocity: Option<[f64; 3]>,
}

impl FluidSection {
    /// What the porous free-stream model needs: the same keys, read as one
    /// load (None when one of them is missing, which `check` refuses for
    /// that model).
    pub fn porous_load(&self) -> Option<PorousLoad> {
        Some(PorousLoad {
            free_stream: self.free_stream?,
            density: self.density,
            viscosity: self.viscosity,
            porosity: self.porosity?,
            diameter: self.diameter?,
            thickness: self.thickness?,
        })
    }

    /// Every side of the flow box, defaults filled in.
    pub fn resolved_sides(&self) -> Option<[[super::flow::SideSpec; 2]; 3]> {
        let b = self.flow_box?;
        Some(self.sides.unwrap_or_default().resolved(b.cells))
    }

    /// The Courant number Σ_a|u_a|·Δt/h_a a flow step of `dt` starts with,
    /// at the fastest of the side and initial velocities (None for a model
    /// with no cells).
    pub fn start_courant(&self, dt: f64) -> Option<f64> {
        let h = self.flow_box?.spacing();
        let sides = self.resolved_sides()?;
        let courant = |v: [f64; 3]| (0..3).map(|a| v[a].abs() * dt / h[a]).sum::<f64>();
        Some(
            FlowSides::velocities(&sides)
                .chain(self.initial_velocity)
                .map(courant)
                .fold(0.0, f64::max),
        )
    }

    pub fn check(&self, c: &mut Checker) {
        c.within("fluid", None, |c| {
            let model = self.model.name();
            let porous_keys = [
                ("free_stream", self.free_stream.is_some()),
                ("porosity", self.porosity.is_some()),
                ("diameter", self.diameter.is_some()),
                ("thickness", self.thickness.is_some()),
            ];
            let flow_keys = [
                ("box", self.flow_box.is_some()),
                ("sides", self.sides.is_some()),
                ("initial_velocity", self.initial_velocity.is_some()),
            ];
            let (needed, foreign): (&[(&str, bool)], &[(&str, bool)]) = match self.model {
                FluidModel::PorousFreeStream => (&porous_keys, &flow_keys),
                FluidModel::Incompressible => (&flow_keys[..1], &porous_keys),
            };
            if let Some((key, _)) = foreign.iter().find(|(_, given)| *given) {
                c.problem(&[key], format!("{key} is not a key of model = \"{model}\""));
            }
            if let Some((key, _)) = needed.iter().find(|(_, given)| !*given) {
                c.problem(
                    &["model"],
                    format!("model = \"{model}\" needs the key `{key}` in [fluid]"),
                );
            }
            if let Some(load) = self.porous_load() {
                load.check(c);
            }
            c.positive(&["density"], self.density, "kg/m³");
            c.positive(&["viscosity"], self.viscosity, "Pa·s");
            if let Some(b) = &self.flow_box {
                b.check(c);
                self.sides.unwrap_or_default().check(c, b);
            }
            if let Some(v) = self.initial_velocity {
                c.finite3(&["initial_velocity"], v);
            }
        });
    }
}

/// The Darcy–Forchheimer (Ergun) load of a uniform stream through a porous
/// fabric, seed 003 eqs. (6)–(10). `[fluid]` gives these keys to fluid-proc's
/// porous free-stream model; `[structure.porous]` gives the same keys to a
/// structure solver that applies the load itself, with no fluid process.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PorousLoad {
    /// Free-stream velocity of the air [m/s].
    pub free_stream: [f64; 3],
    /// Air density ρ [kg/m³].
    #[serde(default = "air_density")]
    pub density: f64,
    /// Air dynamic viscosity μ [Pa·s].
    #[serde(default = "air_viscosity")]
    pub viscosity: f64,
    /// Fabric porosity ε (0 < ε < 1), seed 003 eqs. (7)–(9).
    pub porosity: f64,
    /// Characteristic (Ergun) diameter D [m], seed 003 eqs. (7)–(8).
    pub diameter: f64,
    /// Fabric thickness e [m], seed 003 eq. (6).
    pub thickness: f64,
}

impl PorousLoad {
    /// Checks the keys relative to the table `c` is in.
    pub fn check(&self, c: &mut Checker) {
        c.finite3(&["free_stream"], self.free_stream);
        c.positive(&["density"], self.density, "kg/m³");
        c.positive(&["viscosity"], self.viscosity, "Pa·s");
        c.fraction(&["porosity"], self.porosity);
        c.positive(&["diameter"], self.diameter, "m");
        c.positive(&["thickness"], self.thickness, "m");
    }
}
