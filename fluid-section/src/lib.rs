//! `[fluid]`: the flow model fluid-proc runs:
//! - `porous-free-stream`: the Darcy–Forchheimer (Ergun) load of the thesis
//!   eqs. (6)–(10) in a uniform stream, whose keys [`PorousLoad`] also gives
//!   to `[structure.porous]`;
//! - `incompressible`: the Navier–Stokes solver of dissertation §3.2.2 on a box
//!   of cells (`flow.rs`: `[fluid.box]`, `[fluid.sides]`), with the canopy
//!   in it, porous with the fabric keys of [`FluidSection::fabric`];
//! - `euler`: the compressible Euler solver of dissertation §3.2.1 on the same
//!   box (`gas.rs`: `gamma`, `cfl`, `[[fluid.regions]]`).

use flow::{FlowBox, FlowSides};
use frame::FrameSpec;
use gas::{GasRegion, AIR_GAMMA, DEFAULT_CFL};
pub use porous_load::{PorousLoad, AIR_DENSITY, AIR_VISCOSITY};
pub use scenario::section::Device;
use scenario::Checker;
use serde::{Deserialize, Serialize};

pub mod flow;
pub mod frame;
pub mod gas;
pub mod grading;
mod porous_load;
mod scene;

pub use scene::{Scene, POROSITY_WITHOUT_CANOPY};

fn is_cpu(d: &Device) -> bool {
    *d == Device::Cpu
}

/// Which keys of `[fluid]` each model takes, and which of those it needs.
const MODEL_KEYS: [(FluidModel, &[&str], &[&str]); 3] = [
    (
        FluidModel::PorousFreeStream,
        &[
            "density",
            "viscosity",
            "free_stream",
            "porosity",
            "diameter",
            "thickness",
        ],
        &["free_stream", "porosity", "diameter", "thickness"],
    ),
    (
        FluidModel::Incompressible,
        &[
            "density",
            "viscosity",
            "box",
            "sides",
            "initial_velocity",
            "probes",
            "frame",
            "porosity",
            "diameter",
            "thickness",
            "device",
        ],
        &["box"],
    ),
    (
        FluidModel::Euler,
        &["box", "sides", "gamma", "cfl", "regions"],
        &["box", "regions"],
    ),
];

#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum FluidModel {
    /// Uniform free stream through a porous canopy, no flow field (thesis §2.1).
    #[default]
    PorousFreeStream,
    /// Incompressible Navier–Stokes on a box of cells (dissertation §3.2.2).
    Incompressible,
    /// Compressible Euler equations of an ideal gas (dissertation §3.2.1).
    Euler,
}

impl FluidModel {
    pub fn name(self) -> &'static str {
        match self {
            FluidModel::PorousFreeStream => "porous-free-stream",
            FluidModel::Incompressible => "incompressible",
            FluidModel::Euler => "euler",
        }
    }
}

/// The porous free-stream model's keys sit in `[fluid]` itself, so they
/// mirror [`PorousLoad`]'s: serde's `flatten` would share the declaration but
/// cannot be combined with `deny_unknown_fields`, and loses the line of a
/// mistyped value. [`FluidSection::porous_load`] is the one bridge. Which
/// keys a model needs is checked here, after parsing.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FluidSection {
    #[serde(default)]
    pub model: FluidModel,
    /// Density ρ [kg/m³] (porous-free-stream, incompressible); ISA air at
    /// sea level when left out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<f64>,
    /// Dynamic viscosity μ [Pa·s] (porous-free-stream, incompressible);
    /// ISA air when left out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub viscosity: Option<f64>,
    /// Free-stream velocity of the air [m/s] (porous-free-stream).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub free_stream: Option<[f64; 3]>,
    /// Fabric porosity ε (0 < ε < 1), thesis eqs. (7)–(9) (porous-free-stream;
    /// optional for incompressible, with `diameter` and `thickness`: a porous canopy).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub porosity: Option<f64>,
    /// Characteristic (Ergun) diameter D [m], thesis eqs. (7)–(8) (porous-free-stream;
    /// incompressible, with `porosity`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub diameter: Option<f64>,
    /// Fabric thickness e [m], thesis eq. (6) (porous-free-stream;
    /// incompressible, with `porosity`).
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
    /// Named points whose pressure and velocity are monitors
    /// (`[[fluid.probes]]`, incompressible).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub probes: Option<Vec<flow::Probe>>,
    /// A box that follows the parachute (`[fluid.frame]`, incompressible).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frame: Option<FrameSpec>,
    /// Where the steps run: "cpu", or "gpu" through wgpu (the fluid-gpu
    /// crate): the incompressible model on a uniform box on one rank, with
    /// the canopy and the bodies in it, the state kept there from step to
    /// step; what the device does not cover yet, the check refuses.
    #[serde(default, skip_serializing_if = "is_cpu")]
    pub device: Device,
    /// Ratio of specific heats γ (euler); air's 1.4 when left out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gamma: Option<f64>,
    /// Courant number of a step at the fastest wave (euler); 0.6 when left out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cfl: Option<f64>,
    /// The gas at the start, region by region (euler).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub regions: Option<Vec<GasRegion>>,
}

impl FluidSection {
    /// What the porous free-stream model needs: the same keys, read as one
    /// load (None when one of them is missing, which `check` refuses for
    /// that model).
    pub fn porous_load(&self) -> Option<PorousLoad> {
        let free_stream = self.free_stream?;
        Some(PorousLoad {
            free_stream,
            ..self.fabric()?
        })
    }

    /// The fabric's keys (porosity, diameter, thickness) with the air's
    /// density and viscosity, in still air: the incompressible model's
    /// porous canopy takes its law from them and the air's velocity from
    /// its flow field. None unless all three are given.
    pub fn fabric(&self) -> Option<PorousLoad> {
        Some(PorousLoad {
            free_stream: [0.0; 3],
            density: self.density(),
            viscosity: self.viscosity(),
            porosity: self.porosity?,
            diameter: self.diameter?,
            thickness: self.thickness?,
        })
    }

    /// Density ρ [kg/m³] of the porous and incompressible models.
    pub fn density(&self) -> f64 {
        self.density.unwrap_or(AIR_DENSITY)
    }

    /// Dynamic viscosity μ [Pa·s] of the porous and incompressible models.
    pub fn viscosity(&self) -> f64 {
        self.viscosity.unwrap_or(AIR_VISCOSITY)
    }

    /// Ratio of specific heats γ of the euler model.
    pub fn gamma(&self) -> f64 {
        self.gamma.unwrap_or(AIR_GAMMA)
    }

    /// Courant number of an euler step.
    pub fn cfl(&self) -> f64 {
        self.cfl.unwrap_or(DEFAULT_CFL)
    }

    /// Every side of the flow box, defaults filled in.
    pub fn resolved_sides(&self) -> Option<[[flow::SideSpec; 2]; 3]> {
        let b = self.flow_box?;
        Some(self.sides.unwrap_or_default().resolved(b.cells))
    }

    /// The Courant number Σ_a|u_a|·Δt/h_a an incompressible flow step of
    /// `dt` starts with, at the fastest of the side and initial velocities
    /// relative to the box, which moves at `frame` [m/s] when it follows
    /// the parachute (None for another model: the euler model chooses its
    /// own steps).
    pub fn start_courant(&self, dt: f64, frame: [f64; 3]) -> Option<f64> {
        if self.model != FluidModel::Incompressible {
            return None;
        }
        let h = self.flow_box?.spacing();
        let courant = |v: [f64; 3]| {
            (0..3)
                .map(|a| (v[a] - frame[a]).abs() * dt / h[a])
                .sum::<f64>()
        };
        Some(self.given_velocities().map(courant).fold(0.0, f64::max))
    }

    /// The velocities the flow box's air is given [m/s]: the sides' and the
    /// initial velocity.
    pub fn given_velocities(&self) -> impl Iterator<Item = [f64; 3]> {
        let sides = self.resolved_sides();
        let from_sides: Vec<[f64; 3]> = sides
            .as_ref()
            .map_or(Vec::new(), |s| FlowSides::velocities(s).collect());
        from_sides.into_iter().chain(self.initial_velocity)
    }

    pub fn check(&self, c: &mut Checker) {
        c.within("fluid", None, |c| {
            self.check_model_keys(c);
            self.check_fabric(c);
            c.positive(&["density"], self.density(), "kg/m³");
            c.positive(&["viscosity"], self.viscosity(), "Pa·s");
            if self.model == FluidModel::Euler {
                gas::check(
                    c,
                    self.regions.as_deref(),
                    self.flow_box.as_ref(),
                    self.resolved_sides(),
                    self.gamma(),
                    self.cfl(),
                );
            } else if let Some(sides) = self.resolved_sides() {
                gas::check_no_state_sides(c, sides, self.model.name());
            }
            if let Some(b) = &self.flow_box {
                b.check(c);
                self.sides.unwrap_or_default().check(c, b);
            }
            if let Some(v) = self.initial_velocity {
                c.finite3(&["initial_velocity"], v);
            }
            if let (Some(probes), Some(b)) = (&self.probes, &self.flow_box) {
                flow::Probe::check_all(probes, c, b);
            }
            if let Some(frame) = &self.frame {
                frame.check(c, self.resolved_sides());
            }
            self.check_device(c);
        });
    }

    /// What `device = "gpu"` does not cover yet in the section itself (the
    /// partners' part: `scene.rs`; the adapter: fluid-proc's `--check`).
    fn check_device(&self, c: &mut Checker) {
        if self.device != Device::Gpu {
            return;
        }
        if self.flow_box.is_some_and(|b| b.core.is_some()) {
            c.problem(
                &["device"],
                "device = \"gpu\" does not run a graded box ([fluid.box.core]) yet: use \
                 device = \"cpu\""
                    .into(),
            );
        }
    }

    /// Every key given is one the model takes, and the model's needed
    /// keys are given.
    fn check_model_keys(&self, c: &mut Checker) {
        let model = self.model.name();
        let given = [
            ("density", self.density.is_some()),
            ("viscosity", self.viscosity.is_some()),
            ("free_stream", self.free_stream.is_some()),
            ("porosity", self.porosity.is_some()),
            ("diameter", self.diameter.is_some()),
            ("thickness", self.thickness.is_some()),
            ("box", self.flow_box.is_some()),
            ("sides", self.sides.is_some()),
            ("initial_velocity", self.initial_velocity.is_some()),
            ("probes", self.probes.is_some()),
            ("frame", self.frame.is_some()),
            ("device", self.device != Device::Cpu),
            ("gamma", self.gamma.is_some()),
            ("cfl", self.cfl.is_some()),
            ("regions", self.regions.is_some()),
        ];
        let (_, takes, needs) = MODEL_KEYS
            .iter()
            .find(|(m, _, _)| *m == self.model)
            .expect("every model has its keys");
        if let Some((key, _)) = given.iter().find(|(k, g)| *g && !takes.contains(k)) {
            c.problem(&[key], format!("{key} is not a key of model = \"{model}\""));
        }
        if let Some(key) = needs
            .iter()
            .find(|k| given.iter().any(|(g, on)| g == *k && !on))
        {
            c.problem(
                &["model"],
                format!("model = \"{model}\" needs the key `{key}` in [fluid]"),
            );
        }
    }

    /// The fabric's three keys come together and hold valid values.
    fn check_fabric(&self, c: &mut Checker) {
        let fabric = [self.porosity, self.diameter, self.thickness];
        let some = fabric.iter().filter(|k| k.is_some()).count();
        if self.model == FluidModel::Incompressible && (1..3).contains(&some) {
            let keys = ["porosity", "diameter", "thickness"];
            let at = |given: bool| {
                keys[fabric
                    .iter()
                    .position(|k| k.is_some() == given)
                    .unwrap_or(0)]
            };
            let missing = at(false);
            c.problem(
                &[at(true)],
                format!(
                    "porosity, diameter and thickness make the canopy's fabric porous \
                         together: give `{missing}` too, or none of them for a closed fabric"
                ),
            );
        }
        if let Some(load) = self.porous_load().or(self.fabric()) {
            load.check(c);
        }
    }
}
