//! `[fluid]`: the flow model fluid-proc runs. For now the porous free-stream
//! model: the Darcy–Forchheimer (Ergun) load of seed 003 eqs. (6)–(10), whose
//! keys [`PorousLoad`] also gives to `[structure.porous]`.

use super::check::Checker;
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
}

/// The porous free-stream model's keys sit in `[fluid]` itself, so they
/// mirror [`PorousLoad`]'s: serde's `flatten` would share the declaration but
/// cannot be combined with `deny_unknown_fields`, and loses the line of a
/// mistyped value. [`FluidSection::porous_load`] is the one bridge.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FluidSection {
    #[serde(default)]
    pub model: FluidModel,
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

impl FluidSection {
    /// What the porous free-stream model needs: the same keys, read as one load.
    pub fn porous_load(&self) -> PorousLoad {
        PorousLoad {
            free_stream: self.free_stream,
            density: self.density,
            viscosity: self.viscosity,
            porosity: self.porosity,
            diameter: self.diameter,
            thickness: self.thickness,
        }
    }

    pub fn check(&self, c: &mut Checker) {
        c.within("fluid", None, |c| self.porous_load().check(c));
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
