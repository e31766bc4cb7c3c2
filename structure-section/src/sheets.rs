//! `[structure.disk]` and `[[structure.cords]]`: a free circular cloth and
//! strings held at both ends, the pieces of the dissertation's collision
//! scenes (§4.3.2: "a flat circular cloth is right above a bunch of strings
//! which are straight and parallel, with their ends fixed").

use crate::Fabric;
use scenario::Checker;
use serde::{Deserialize, Serialize};

/// A flat circular cloth, free, its plane horizontal.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Disk {
    /// Across [m].
    pub diameter: f64,
    /// Node rings from the centre node to the rim: the mesh resolution
    /// (ring k has 6k nodes, so the triangles are near equilateral).
    pub rings: u32,
    /// The centre [m].
    #[serde(default)]
    pub centre: [f64; 3],
    pub fabric: Fabric,
    /// Springs [N/m] between the far vertices of adjacent triangles (the
    /// dissertation, end of §2.3).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bending_stiffness: Option<f64>,
}

/// Most rings a disk may have (6·400²/2 ≈ 480 000 nodes).
pub const MAX_RINGS: u32 = 400;

impl Disk {
    pub fn check(&self, c: &mut Checker) {
        c.within("disk", None, |c| {
            c.positive(&["diameter"], self.diameter, "m");
            if !(1..=MAX_RINGS).contains(&self.rings) {
                c.problem(
                    &["rings"],
                    format!("rings = {} must lie in 1..={MAX_RINGS}", self.rings),
                );
            }
            c.finite3(&["centre"], self.centre);
            self.fabric.check(c);
            if let Some(k) = self.bending_stiffness {
                c.positive(&["bending_stiffness"], k, "N/m");
            }
        });
    }
}

/// Straight strings from `from` to `to`, each `segments` springs, repeated
/// `count` times, each copy shifted by `spacing` from the one before.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Cords {
    /// First end [m].
    pub from: [f64; 3],
    /// Second end [m].
    pub to: [f64; 3],
    /// Springs along each string.
    pub segments: u32,
    /// Mass per length [kg/m], lumped to the nodes.
    pub linear_density: f64,
    /// E·A [N]: each segment's stiffness is E·A/l⁰.
    pub axial_stiffness: f64,
    /// How many parallel strings.
    #[serde(default = "one")]
    pub count: u32,
    /// From one string to the next [m].
    #[serde(default)]
    pub spacing: [f64; 3],
    /// Whether both ends are held in place (otherwise both are free).
    #[serde(default = "yes")]
    pub fixed_ends: bool,
}

fn one() -> u32 {
    1
}

fn yes() -> bool {
    true
}

impl Cords {
    pub fn check(&self, c: &mut Checker, i: usize) {
        c.within("cords", Some(i), |c| {
            c.finite3(&["from"], self.from);
            c.finite3(&["to"], self.to);
            if self.from == self.to {
                c.problem(&["to"], "a string needs two different ends".into());
            }
            if !(1..=100_000).contains(&self.segments) {
                c.problem(
                    &["segments"],
                    format!("segments = {} must lie in 1..=100000", self.segments),
                );
            }
            c.positive(&["linear_density"], self.linear_density, "kg/m");
            c.positive(&["axial_stiffness"], self.axial_stiffness, "N");
            if !(1..=10_000).contains(&self.count) {
                c.problem(
                    &["count"],
                    format!("count = {} must lie in 1..=10000", self.count),
                );
            }
            c.finite3(&["spacing"], self.spacing);
            if self.count > 1 && self.spacing == [0.0; 3] {
                c.problem(
                    &["spacing"],
                    "several strings need a spacing, or they lie on each other".into(),
                );
            }
        });
    }
}
