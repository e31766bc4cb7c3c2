//! The porous load of a fabric in a uniform stream (thesis eqs. 6–10): the
//! keys `[structure.porous]` gives a structure that applies it itself, and
//! that fluid-proc's porous free-stream model reads from `[fluid]`.

use scenario::Checker;
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

/// The Darcy–Forchheimer (Ergun) load of a uniform stream through a porous
/// fabric, thesis eqs. (6)–(10). `[fluid]` gives these keys to fluid-proc's
/// porous free-stream model; `[structure.porous]` gives the same keys to a
/// structure solver that applies the load itself, with no fluid process.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
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
    /// Fabric porosity ε (0 < ε < 1), thesis eqs. (7)–(9).
    pub porosity: f64,
    /// Characteristic (Ergun) diameter D [m], thesis eqs. (7)–(8).
    pub diameter: f64,
    /// Fabric thickness e [m], thesis eq. (6).
    pub thickness: f64,
}

impl PorousLoad {
    /// The law's parameters, as the `porous` crate takes them.
    pub fn params(&self) -> porous::Params {
        porous::Params {
            free_stream: self.free_stream,
            density: self.density,
            viscosity: self.viscosity,
            porosity: self.porosity,
            diameter: self.diameter,
            thickness: self.thickness,
        }
    }

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
