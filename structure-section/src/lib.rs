//! `[structure]`: the spring-mass canopy and strings (thesis §2.1, §3.2).

pub use collision::Collision;
use fluid_section::PorousLoad;
pub use integrator::{
    AdaptiveParams, HhtParams, Integrator, LinearSolver, NewmarkParams, NewtonParams, Scheme,
};
pub use parachute::{
    Cloth, ClothHold, ClothPlane, LineBreak, LineChange, Parachute, ParachuteModel,
};
use rigid_section::{default_gravity, AttachmentSpec, RigidSection};
pub use scenario::section::Device;
use scenario::Checker;
use serde::{Deserialize, Serialize};

pub mod canopy_in_flow;
pub mod collision;
mod dome;
pub mod integrator;
pub mod pack;
pub mod parachute;
mod scene;
pub mod sheets;

pub use pack::Pleats;
pub use scene::Scene;
pub use sheets::{Cords, Disk};

#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StructureSection {
    /// Structure sub-steps n_s per coupling window: Δt_s = Δt_f / n_s,
    /// with Δt_f the `[coupling] window`. With rigid bodies it is a
    /// multiple of `[coupling] impulse_substeps`; `coupler check` prints
    /// how many the integrator needs to be stable (dissertation eq. 3.7).
    #[serde(default = "one")]
    pub substeps: u32,
    #[serde(default)]
    pub integrator: Integrator,
    /// Where the steps run: the CPU, or a GPU through wgpu (`structure-gpu`):
    /// the explicit schemes (euler-cromer, velocity-verlet, rk4), the state
    /// kept there between sub-steps.
    #[serde(default)]
    pub device: Device,
    /// β, γ for `integrator = "newmark"`.
    #[serde(default)]
    pub newmark: NewmarkParams,
    /// α for `integrator = "hht"`.
    #[serde(default)]
    pub hht: HhtParams,
    /// Newton and conjugate-gradient settings of the implicit schemes.
    #[serde(default)]
    pub newton: NewtonParams,
    /// The error tolerance for `integrator = "dormand-prince"`.
    #[serde(default)]
    pub adaptive: AdaptiveParams,
    /// Gravitational acceleration [m/s²].
    #[serde(default = "default_gravity")]
    pub gravity: [f64; 3],
    #[serde(default)]
    pub damping: Damping,
    /// Viscous damping coefficient c [N·s/m] of dissertation eq. (2.38), for `damping = "viscous"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping_coefficient: Option<f64>,
    /// The annulus canopy of thesis §2.2 / §3.2, outer rim fixed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub annulus: Option<Annulus>,
    /// A parachute canopy with suspension lines (dissertation §4.2).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub parachute: Option<Parachute>,
    /// A rectangular cloth.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cloth: Option<Cloth>,
    /// A free circular cloth.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub disk: Option<Disk>,
    /// Straight strings held at both ends, alone or in parallel bundles.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub cords: Vec<Cords>,
    /// Strings from a fixed anchor to an attachment point on a rigid body.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub strings: Vec<StringSpec>,
    /// Named mass points of a hand-built spring network (e.g. the spring pendulum).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub points: Vec<PointSpec>,
    /// Hookean springs between named points.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub springs: Vec<SpringSpec>,
    /// The Darcy–Forchheimer load of a free stream through the canopy
    /// (thesis eqs. 6–10), applied by the structure solver itself: the
    /// porous scenes without a fluid process.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub porous: Option<PorousLoad>,
    /// Free nodes against the rigid bodies' shapes (dissertation §2.5, §3.4).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub collision: Option<Collision>,
}

fn one() -> u32 {
    1
}

/// The integrators `device = "gpu"` runs.
pub const GPU_INTEGRATORS: [Integrator; 3] = [
    Integrator::EulerCromer,
    Integrator::VelocityVerlet,
    Integrator::Rk4,
];

#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum Damping {
    #[default]
    None,
    /// Viscous force k_ij·Δt_s·(v_j − v_i) along every spring, thesis eq. (68).
    RelativeVelocity,
    /// Dashpot c·V⁽ⁱⁿᵗ⁾ of dissertation eq. (2.38), V⁽ⁱⁿᵗ⁾ taken as the rate of change
    /// of each spring's length, with c = `damping_coefficient`.
    Viscous,
}

/// How a generated fabric resists stretching: exactly one of the three.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Elasticity {
    /// Uniform spring stiffness k [N/m] (thesis §3.2).
    Uniform(f64),
    /// k = A·E/l⁰ per edge (thesis eq. 71).
    Fibre(Fibre),
    /// Delingette triangular springs (dissertation eqs. 2.29–2.37).
    Membrane(Membrane),
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Fibre {
    /// Cross-section area A [m²].
    pub area: f64,
    /// Young's modulus E [Pa].
    pub young_modulus: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Membrane {
    /// Young's modulus E [Pa].
    pub young_modulus: f64,
    /// Poisson ratio ν, in [0, 0.5).
    pub poisson_ratio: f64,
    /// Fabric thickness [m].
    pub thickness: f64,
}

#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Annulus {
    /// Inner (vent) radius R_int [m].
    pub inner_radius: f64,
    /// Outer radius R_ext [m]; the rim nodes are fixed (thesis §2.2).
    pub outer_radius: f64,
    /// Number of node rings from R_int to R_ext.
    #[serde(default = "default_rings")]
    pub rings: u32,
    /// Nodes on the outer ring; inner rings get proportionally fewer.
    #[serde(default = "default_outer_nodes")]
    pub outer_nodes: u32,
    /// The fabric: mass per area and elasticity.
    pub fabric: Fabric,
    /// Height of the flat canopy plane [m].
    #[serde(default)]
    pub height: f64,
}

/// `fabric = { … }` of a generated surface: mass per area and exactly one of
/// three elasticities.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Fabric {
    /// Mass per area [kg/m²], lumped to the nodes.
    pub areal_density: f64,
    /// Uniform spring stiffness k [N/m] (thesis §3.2) …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness: Option<f64>,
    /// … or fibres with k = A·E/l⁰ (thesis eq. 71) …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fibre: Option<Fibre>,
    /// … or a Delingette membrane (dissertation eqs. 2.29–2.37).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub membrane: Option<Membrane>,
}

impl Fabric {
    /// The one elasticity given; `check` has made sure there is exactly one.
    pub fn elasticity(&self) -> Elasticity {
        match (self.stiffness, self.fibre, self.membrane) {
            (Some(k), _, _) => Elasticity::Uniform(k),
            (_, Some(f), _) => Elasticity::Fibre(f),
            (_, _, Some(m)) => Elasticity::Membrane(m),
            _ => Elasticity::Uniform(f64::NAN),
        }
    }

    pub fn check(&self, c: &mut Checker) {
        c.within("fabric", None, |c| {
            c.positive(&["areal_density"], self.areal_density, "kg/m²");
            check_elasticity(
                c,
                self.stiffness,
                self.fibre.as_ref(),
                self.membrane.as_ref(),
            );
        });
    }
}

fn check_elasticity(c: &mut Checker, k: Option<f64>, f: Option<&Fibre>, m: Option<&Membrane>) {
    let given = k.is_some() as u8 + f.is_some() as u8 + m.is_some() as u8;
    if given != 1 {
        c.problem(
            &["stiffness"],
            "give exactly one of stiffness (N/m), fibre = { area, young_modulus } or \
             membrane = { young_modulus, poisson_ratio, thickness }"
                .into(),
        );
    }
    if let Some(k) = k {
        c.positive(&["stiffness"], k, "N/m");
    }
    if let Some(f) = f {
        c.within("fibre", None, |c| {
            c.positive(&["area"], f.area, "m²");
            c.positive(&["young_modulus"], f.young_modulus, "Pa");
        });
    }
    if let Some(m) = m {
        c.within("membrane", None, |c| {
            c.positive(&["young_modulus"], m.young_modulus, "Pa");
            c.positive(&["thickness"], m.thickness, "m");
            if !(m.poisson_ratio.is_finite() && (0.0..0.5).contains(&m.poisson_ratio)) {
                c.problem(
                    &["poisson_ratio"],
                    format!("poisson_ratio = {} must lie in [0, 0.5)", m.poisson_ratio),
                );
            }
        });
    }
}

fn default_rings() -> u32 {
    12
}
fn default_outer_nodes() -> u32 {
    107
}

#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StringSpec {
    /// Fixed end [m].
    pub anchor: [f64; 3],
    /// Name of the rigid body the other end is attached to …
    pub body: String,
    /// … at this point of the body's own frame [m] (default its origin).
    #[serde(default)]
    pub body_point: [f64; 3],
    /// Axial stiffness k [N/m].
    pub stiffness: f64,
    /// Rest length l⁰ [m].
    pub rest_length: f64,
    /// Compressive tolerance eps of thesis eq. (3) [m]: no force until stretched beyond it.
    #[serde(default)]
    pub compressive_tolerance: f64,
}

/// A named mass point of a hand-built network.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PointSpec {
    pub name: String,
    /// Initial position [m].
    pub position: [f64; 3],
    /// Initial velocity [m/s].
    #[serde(default)]
    pub velocity: [f64; 3],
    /// Mass [kg]; ignored for fixed points.
    #[serde(default)]
    pub mass: f64,
    /// Held in place.
    #[serde(default)]
    pub fixed: bool,
}

/// A Hookean spring between two named points (thesis eq. 67).
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SpringSpec {
    pub ends: [String; 2],
    /// Stiffness k [N/m].
    pub stiffness: f64,
    /// Rest length l⁰ [m]; the initial distance of the ends if left out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rest_length: Option<f64>,
}

impl StructureSection {
    /// The structure's step Δt_s = Δt_f / n_s [s] in a coupling `window` Δt_f [s].
    pub fn dt(&self, window: f64) -> f64 {
        window / self.substeps as f64
    }

    /// The rigid body of every attachment point, in the order structure
    /// solvers number them and exchange their state and impulses: the
    /// parachute's confluence first, then the strings of `[[structure.strings]]`.
    pub fn attachments(&self) -> Vec<AttachmentSpec> {
        let confluence = self.parachute.iter().filter_map(|p| {
            p.body.clone().map(|body| AttachmentSpec {
                body,
                point: p.body_point,
            })
        });
        confluence
            .chain(self.strings.iter().map(|st| AttachmentSpec {
                body: st.body.clone(),
                point: st.body_point,
            }))
            .collect()
    }

    /// The integrator with its parameters resolved.
    pub fn scheme(&self) -> Scheme {
        Scheme::resolve(
            self.integrator,
            self.newmark,
            self.hht,
            self.newton,
            self.adaptive,
        )
    }

    /// What `device = "gpu"` does not run (the adapter itself is the
    /// structure program's to find, in its `--check` answer).
    fn check_device(&self, c: &mut Checker) {
        if self.device != Device::Gpu {
            return;
        }
        if !GPU_INTEGRATORS.contains(&self.integrator) {
            let names: Vec<_> = GPU_INTEGRATORS.iter().map(|i| i.name()).collect();
            c.problem(
                &["device"],
                format!(
                    "device = \"gpu\" runs integrator = {}, not \"{}\"",
                    names.join(", "),
                    self.integrator.name()
                ),
            );
        }
        if self.collision.is_some() {
            c.problem(
                &["device"],
                "device = \"gpu\" does not run [structure.collision] yet: use device = \"cpu\""
                    .into(),
            );
        }
    }

    pub fn check(&self, c: &mut Checker, rigid: Option<&RigidSection>) {
        c.within("structure", None, |c| {
            c.nonzero(&["substeps"], self.substeps as f64);
            c.at_most(&["substeps"], self.substeps as f64, scenario::MAX_SUBSTEPS);
            c.finite3(&["gravity"], self.gravity);
            let surfaces = self.annulus.is_some() as u8
                + self.parachute.is_some() as u8
                + self.cloth.is_some() as u8
                + self.disk.is_some() as u8;
            if surfaces == 0 && self.strings.is_empty() && self.points.is_empty() && self.cords.is_empty() {
                c.problem(&[], "has nothing to simulate: give [structure.annulus], [structure.parachute], [structure.cloth], [structure.disk], [[structure.strings]], [[structure.cords]] or [[structure.points]]".into());
            }
            if let Some(p) = &self.porous {
                c.within("porous", None, |c| p.check(c));
                if surfaces == 0 {
                    c.problem(&["porous"], "a porous load needs a canopy surface: give [structure.annulus], [structure.parachute], [structure.cloth] or [structure.disk]".into());
                }
            }
            if surfaces > 1 {
                let key = if self.disk.is_some() { "disk" } else { "cloth" };
                c.problem(&[key], "give at most one of [structure.annulus], [structure.parachute], [structure.cloth] and [structure.disk]".into());
            }
            if let Some(d) = &self.disk {
                d.check(c);
            }
            for (i, cord) in self.cords.iter().enumerate() {
                cord.check(c, i);
            }
            if let Some(p) = &self.parachute {
                p.check(c, |b| body_problem(rigid, b));
            }
            if let Some(cl) = &self.cloth {
                cl.check(c);
            }
            if let Some(k) = &self.collision {
                k.check(c, rigid);
            }
            self.check_device(c);
            integrator::check_params(c, &self.newmark, &self.hht, &self.newton, &self.adaptive);
            match (self.damping, self.damping_coefficient) {
                (Damping::Viscous, None) => c.problem(&["damping_coefficient"],
                    "damping = \"viscous\" needs damping_coefficient = c (N·s/m, dissertation eq. 2.38)".into()),
                (Damping::Viscous, Some(d)) => c.finite_nonneg(&["damping_coefficient"], d),
                (_, Some(_)) => c.problem(&["damping_coefficient"],
                    "damping_coefficient is used only with damping = \"viscous\"".into()),
                _ => {}
            }
            self.check_network(c);
            self.check_annulus(c);
            for (i, s) in self.strings.iter().enumerate() {
                c.within("strings", Some(i), |c| {
                    c.finite3(&["anchor"], s.anchor);
                    c.positive(&["stiffness"], s.stiffness, "N/m");
                    c.positive(&["rest_length"], s.rest_length, "m");
                    c.finite_nonneg(&["compressive_tolerance"], s.compressive_tolerance);
                    c.finite3(&["body_point"], s.body_point);
                    if let Some(msg) = body_problem(rigid, &s.body) {
                        c.problem(&["body"], msg);
                    }
                });
            }
        });
    }

    /// `[structure.annulus]`: radii, rings and nodes that make a mesh.
    fn check_annulus(&self, c: &mut Checker) {
        if let Some(a) = &self.annulus {
            c.within("annulus", None, |c| {
                c.positive(&["inner_radius"], a.inner_radius, "m");
                c.positive(&["outer_radius"], a.outer_radius, "m");
                if a.outer_radius <= a.inner_radius {
                    c.problem(
                        &["outer_radius"],
                        format!(
                            "outer_radius = {} must exceed inner_radius = {}",
                            a.outer_radius, a.inner_radius
                        ),
                    );
                }
                c.at_most(&["rings"], a.rings as f64, 1000.0);
                c.at_most(&["outer_nodes"], a.outer_nodes as f64, 1e5);
                if a.rings < 2 {
                    c.problem(
                        &["rings"],
                        format!("rings = {} must be at least 2", a.rings),
                    );
                }
                if a.outer_nodes < 6 {
                    c.problem(
                        &["outer_nodes"],
                        format!("outer_nodes = {} must be at least 6", a.outer_nodes),
                    );
                }
                a.fabric.check(c);
                c.finite(&["height"], a.height);
            });
        }
    }

    fn check_network(&self, c: &mut Checker) {
        for (i, p) in self.points.iter().enumerate() {
            c.within("points", Some(i), |c| {
                c.plain_name(&["name"], &p.name, true);
                if self.points[..i].iter().any(|q| q.name == p.name) {
                    c.problem(
                        &["name"],
                        format!("a point named `{}` is already defined", p.name),
                    );
                }
                c.finite3(&["position"], p.position);
                c.finite3(&["velocity"], p.velocity);
                if p.fixed {
                    c.finite_nonneg(&["mass"], p.mass);
                } else {
                    c.positive(&["mass"], p.mass, "kg");
                }
            });
        }
        for (i, s) in self.springs.iter().enumerate() {
            c.within("springs", Some(i), |c| {
                for end in &s.ends {
                    if !self.points.iter().any(|p| &p.name == end) {
                        c.problem(&["ends"], format!("no point is named `{end}`"));
                    }
                }
                if s.ends[0] == s.ends[1] {
                    c.problem(&["ends"], "a spring needs two different points".into());
                }
                c.positive(&["stiffness"], s.stiffness, "N/m");
                if let Some(l) = s.rest_length {
                    c.positive(&["rest_length"], l, "m");
                }
            });
        }
    }
}

/// Why `body` is not a rigid body of the scene, if it is not.
fn body_problem(rigid: Option<&RigidSection>, body: &str) -> Option<String> {
    match rigid {
        None => Some(format!(
            "attaches to body `{body}` but the scene has no rigid participant"
        )),
        Some(r) if !r.bodies.iter().any(|b| b.name == body) => Some(format!(
            "no rigid body is named `{body}` (bodies: {})",
            r.bodies
                .iter()
                .map(|b| b.name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        )),
        Some(_) => None,
    }
}
