//! `[structure]`: the spring-mass canopy and strings (seed 003 §2.1, §3.2).

use super::check::Checker;
use super::rigid::RigidSection;
use serde::{Deserialize, Serialize};

/// Standard acceleration of gravity [m/s²] (3rd CGPM, 1901).
pub const STANDARD_GRAVITY: f64 = 9.80665;

pub fn default_gravity() -> [f64; 3] {
    [0.0, 0.0, -STANDARD_GRAVITY]
}

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StructureSection {
    #[serde(default)]
    pub integrator: Integrator,
    /// Gravitational acceleration [m/s²].
    #[serde(default = "default_gravity")]
    pub gravity: [f64; 3],
    #[serde(default)]
    pub damping: Damping,
    /// The annulus canopy of seed 003 §2.2 / §3.2, outer rim fixed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub annulus: Option<Annulus>,
    /// Strings from a fixed anchor to an attachment point on a rigid body.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub strings: Vec<StringSpec>,
}

#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Integrator {
    /// Velocity Verlet (seed 003 §2.4.7).
    #[default]
    VelocityVerlet,
    /// Euler–Cromer / symplectic Euler (seed 003 eqs. 15–16).
    EulerCromer,
}

#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Damping {
    #[default]
    None,
    /// Viscous force k_ij·Δt_s·(v_j − v_i) along every spring, seed 003 eq. (68).
    RelativeVelocity,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Annulus {
    /// Inner (vent) radius R_int [m].
    pub inner_radius: f64,
    /// Outer radius R_ext [m]; the rim nodes are fixed (seed 003 §2.2).
    pub outer_radius: f64,
    /// Number of node rings from R_int to R_ext.
    #[serde(default = "default_rings")]
    pub rings: u32,
    /// Nodes on the outer ring; inner rings get proportionally fewer.
    #[serde(default = "default_outer_nodes")]
    pub outer_nodes: u32,
    /// Uniform spring stiffness k [N/m] (seed 003 §3.2).
    pub stiffness: f64,
    /// Fabric mass per area [kg/m²], lumped to the nodes.
    pub areal_density: f64,
    /// Height of the flat canopy plane [m].
    #[serde(default)]
    pub height: f64,
}

fn default_rings() -> u32 {
    12
}
fn default_outer_nodes() -> u32 {
    107
}

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StringSpec {
    /// Fixed end [m].
    pub anchor: [f64; 3],
    /// Name of the rigid body the other end is attached to (at its centre of mass).
    pub body: String,
    /// Axial stiffness k [N/m].
    pub stiffness: f64,
    /// Rest length l⁰ [m].
    pub rest_length: f64,
    /// Compressive tolerance eps of seed 003 eq. (3) [m]: no force until stretched beyond it.
    #[serde(default)]
    pub compressive_tolerance: f64,
}

impl StructureSection {
    pub fn check(&self, c: &mut Checker, rigid: Option<&RigidSection>) {
        c.within("structure", None, |c| {
            c.finite3(&["gravity"], self.gravity);
            if self.annulus.is_none() && self.strings.is_empty() {
                c.problem(&[], "has nothing to simulate: give [structure.annulus] or [[structure.strings]]".into());
            }
            if let Some(a) = &self.annulus {
                c.within("annulus", None, |c| {
                    c.positive(&["inner_radius"], a.inner_radius, "m");
                    c.positive(&["outer_radius"], a.outer_radius, "m");
                    if a.outer_radius <= a.inner_radius {
                        c.problem(&["outer_radius"], format!(
                            "outer_radius = {} must exceed inner_radius = {}", a.outer_radius, a.inner_radius));
                    }
                    c.at_most(&["rings"], a.rings as f64, 1000.0);
                    c.at_most(&["outer_nodes"], a.outer_nodes as f64, 1e5);
                    if a.rings < 2 {
                        c.problem(&["rings"], format!("rings = {} must be at least 2", a.rings));
                    }
                    if a.outer_nodes < 6 {
                        c.problem(&["outer_nodes"], format!("outer_nodes = {} must be at least 6", a.outer_nodes));
                    }
                    c.positive(&["stiffness"], a.stiffness, "N/m");
                    c.positive(&["areal_density"], a.areal_density, "kg/m²");
                    c.finite(&["height"], a.height);
                });
            }
            for (i, s) in self.strings.iter().enumerate() {
                c.within("strings", Some(i), |c| {
                    c.finite3(&["anchor"], s.anchor);
                    c.positive(&["stiffness"], s.stiffness, "N/m");
                    c.positive(&["rest_length"], s.rest_length, "m");
                    c.finite_nonneg(&["compressive_tolerance"], s.compressive_tolerance);
                    match rigid {
                        None => c.problem(&["body"], format!(
                            "string attaches to body `{}` but the scene has no rigid participant", s.body)),
                        Some(r) if !r.bodies.iter().any(|b| b.name == s.body) => c.problem(&["body"], format!(
                            "no rigid body is named `{}` (bodies: {})", s.body,
                            r.bodies.iter().map(|b| b.name.as_str()).collect::<Vec<_>>().join(", "))),
                        Some(_) => {}
                    }
                });
            }
        });
    }
}
