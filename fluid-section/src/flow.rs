//! The keys of the incompressible flow model (`[fluid] model =
//! "incompressible"`, dissertation §3.2.2): the box of cells `[fluid.box]` and
//! what each of its sides does to the flow, `[fluid.sides]`.

use crate::grading::Core;
use scenario::Checker;
use serde::{Deserialize, Serialize};

/// Most cells a flow box may have (guards memory against typos: 10⁸ cells
/// take about 10 GB).
pub const MAX_CELLS: f64 = 1e8;

/// Largest Courant number Σ_a|u_a|·Δt/h_a a flow step takes. The explicit
/// advection of dissertation eq. (3.18) (WENO5, second-order Adams–Bashforth)
/// was measured to stay stable in a nearly inviscid periodic flow up to
/// about 0.6, along an axis and diagonally; 0.5 keeps a margin.
pub const MAX_COURANT: f64 = 0.5;

/// Fewest cells along an axis that is not one cell thick.
pub const MIN_CELLS: u32 = 4;

/// Fewest cells a rank's slab may have along the axis the box is split
/// along: the three cells a WENO5 stencil reaches past a face, so that a
/// halo comes from the two neighbouring ranks alone.
pub const HALO_CELLS: u32 = 3;

/// Fewest cells a rank's slab of the gas may have when bodies stand in
/// it, on cells of equal spacings: the reach of a ghost cell's image point
/// (fluid-proc's `euler/bodies.rs`): a ghost lies at most 3 cells inside the
/// wall (within WENO5's reach of a gas cell), its image point as far again
/// outside (at least 1.5 cells), and the image's stencil one cell further.
pub const BODY_HALO_CELLS: u32 = 7;

/// [`BODY_HALO_CELLS`] for cells of spacings `h` [m], split along `axis`:
/// the ghost's depth and the image's distance count in the longest
/// spacing h_max of the axes that vary (`active`), so they reach
/// 6·h_max/h_axis cells along the slab's axis, and the stencil one more.
pub fn body_halo_cells(h: [f64; 3], active: [bool; 3], axis: usize) -> u32 {
    let longest = (0..3)
        .filter(|&d| active[d])
        .map(|d| h[d])
        .fold(0.0, f64::max);
    // Equal spacings give exactly 6: the slack keeps round-off from adding a plane.
    let reach = (6.0 * longest / h[axis] - 1e-9).ceil() as u32;
    (reach + 1).max(BODY_HALO_CELLS)
}

/// `[fluid.box]`: a grid of cells over an axis-aligned box: uniform, of
/// `cells` cells, or graded from a fine core (`[fluid.box.core]`,
/// `grading.rs`), whose counts follow from it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(from = "BoxKeys", into = "BoxKeys")]
pub struct FlowBox {
    /// Lowest corner [m].
    pub lower: [f64; 3],
    /// Highest corner [m].
    pub upper: [f64; 3],
    /// Cells along x, y, z (a graded box's from its core).
    pub cells: [u32; 3],
    /// The fine core of a graded box.
    pub core: Option<Core>,
    /// Whether `cells` was given (which a graded box refuses).
    cells_given: bool,
}

/// `[fluid.box]`: a grid of cells over an axis-aligned box: uniform, of
/// `cells` cells, or graded from a fine core whose cells grow toward the
/// sides (`[fluid.box.core]`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
struct BoxKeys {
    /// Lowest corner [m].
    lower: [f64; 3],
    /// Highest corner [m].
    upper: [f64; 3],
    /// Cells along x, y, z of a uniform box; one cell along z makes a 2-D
    /// flow. Left out with a `[fluid.box.core]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    cells: Option<[u32; 3]>,
    /// A fine core, the cells growing from it toward the sides.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    core: Option<Core>,
}

impl From<BoxKeys> for FlowBox {
    fn from(k: BoxKeys) -> FlowBox {
        let mut b = FlowBox {
            lower: k.lower,
            upper: k.upper,
            cells: k.cells.unwrap_or([0; 3]),
            core: k.core,
            cells_given: k.cells.is_some(),
        };
        if let (None, Some(_)) = (k.cells, k.core) {
            b.cells = [0, 1, 2].map(|d| b.widths(d).map_or(0, |w| w.len() as u32));
        }
        b
    }
}

impl From<FlowBox> for BoxKeys {
    fn from(b: FlowBox) -> BoxKeys {
        BoxKeys {
            lower: b.lower,
            upper: b.upper,
            cells: (b.core.is_none() || b.cells_given).then_some(b.cells),
            core: b.core,
        }
    }
}

impl schemars::JsonSchema for FlowBox {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        BoxKeys::schema_name()
    }

    fn json_schema(generator: &mut schemars::SchemaGenerator) -> schemars::Schema {
        BoxKeys::json_schema(generator)
    }
}

impl FlowBox {
    /// Cell size per axis [m]: a graded axis's finest (its core's).
    pub fn spacing(&self) -> [f64; 3] {
        [0, 1, 2].map(|d| match self.widths(d) {
            Some(w) => w.iter().copied().fold(f64::INFINITY, f64::min),
            None => (self.upper[d] - self.lower[d]) / self.cells[d] as f64,
        })
    }

    /// The box graded from `core`, its cells following from it.
    pub fn with_core(self, core: Core) -> FlowBox {
        let keys = BoxKeys {
            cells: None,
            core: Some(core),
            ..BoxKeys::from(self)
        };
        FlowBox::from(keys)
    }

    /// The widths of the cells along axis d of a graded box [m] (None on a
    /// uniform box, or where the core does not fit).
    pub fn widths(&self, d: usize) -> Option<Vec<f64>> {
        self.core?.widths(self.lower, self.upper, d)
    }

    pub fn check(&self, c: &mut Checker) {
        c.within("box", None, |c| {
            c.finite3(&["lower"], self.lower);
            c.finite3(&["upper"], self.upper);
            if (0..3).any(|d| self.upper[d] <= self.lower[d]) {
                c.problem(
                    &["upper"],
                    format!(
                        "upper = {:?} must lie above lower = {:?} along every axis",
                        self.upper, self.lower
                    ),
                );
            }
            match (self.core, self.cells_given) {
                (Some(core), given) => {
                    core.check(c, self.lower, self.upper);
                    if given {
                        c.problem(
                            &["cells"],
                            "cells follow from [fluid.box.core] (its spacing and growth): \
                             leave cells out, or the core"
                                .into(),
                        );
                    }
                }
                (None, false) => c.problem(
                    &["lower"],
                    "the box needs its cells: `cells = [nx, ny, nz]`, or a fine core \
                     [fluid.box.core] they grow from"
                        .into(),
                ),
                (None, true) => {}
            }
            // A core that does not fit is refused above, and has no cells.
            let unfit = self.core.is_some() && (0..3).any(|d| self.widths(d).is_none());
            if !unfit && self.cells.iter().any(|&n| n == 0 || (2..MIN_CELLS).contains(&n)) {
                c.problem(
                    &["cells"],
                    format!(
                        "cells = {:?}: each axis needs 1 cell (a 2-D flow) or at least {MIN_CELLS}, \
                         as the WENO5 stencils reach three faces beyond each face",
                        self.cells
                    ),
                );
            }
            let total: f64 = self.cells.iter().map(|&n| n as f64).product();
            c.at_most(&["cells"], total, MAX_CELLS);
        });
    }
}

/// What one side does to the flow.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum SideSpec {
    /// A no-slip wall at rest.
    Wall,
    /// The velocity on the side [m/s]: a moving wall (a lid) or, with a
    /// normal component, an inflow (`inflow` is the same).
    #[serde(alias = "inflow")]
    Velocity([f64; 3]),
    /// A channel inflow: this peak velocity [m/s] times 4s(1 − s) across
    /// each of the side's directions that is not periodic, s running from 0
    /// to 1 between the walls (Poiseuille's profile; Schäfer & Turek 1996).
    Parabolic([f64; 3]),
    /// An outflow at p = 0.
    Outflow,
    /// Wraps to the opposite side, which must be periodic too.
    Periodic,
    /// Gas held at this state beyond the side (`model = "euler"`): a
    /// supersonic inflow, where every characteristic enters the box, so
    /// the state outside decides the flux alone.
    State(crate::gas::GasState),
}

impl SideSpec {
    /// The velocity the side gives (a parabolic side's peak) [m/s].
    pub fn velocity(&self) -> Option<[f64; 3]> {
        match self {
            SideSpec::Velocity(v) | SideSpec::Parabolic(v) => Some(*v),
            _ => None,
        }
    }
}

/// `[fluid.sides]`: one entry per side. A side left out is a wall, or
/// periodic on an axis one cell thick (the z of a 2-D flow).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FlowSides {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x_low: Option<SideSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x_high: Option<SideSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub y_low: Option<SideSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub y_high: Option<SideSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub z_low: Option<SideSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub z_high: Option<SideSpec>,
}

/// Key names of the sides, `[axis][low, high]`.
pub const SIDE_KEYS: [[&str; 2]; 3] = [
    ["x_low", "x_high"],
    ["y_low", "y_high"],
    ["z_low", "z_high"],
];

impl FlowSides {
    fn given(&self) -> [[Option<SideSpec>; 2]; 3] {
        [
            [self.x_low, self.x_high],
            [self.y_low, self.y_high],
            [self.z_low, self.z_high],
        ]
    }

    /// The largest velocities the sides give [m/s] (a parabolic side's peak).
    pub fn velocities(sides: &[[SideSpec; 2]; 3]) -> impl Iterator<Item = [f64; 3]> + '_ {
        sides.iter().flatten().filter_map(|s| s.velocity())
    }

    /// Every side, with the defaults for those left out.
    pub fn resolved(&self, cells: [u32; 3]) -> [[SideSpec; 2]; 3] {
        let given = self.given();
        [0, 1, 2].map(|d| {
            let default = if cells[d] == 1 {
                SideSpec::Periodic
            } else {
                SideSpec::Wall
            };
            given[d].map(|s| s.unwrap_or(default))
        })
    }

    pub fn check(&self, c: &mut Checker, flow_box: &FlowBox) {
        let sides = self.resolved(flow_box.cells);
        c.within("sides", None, |c| {
            for d in 0..3 {
                for s in 0..2 {
                    if let Some(v) = sides[d][s].velocity() {
                        c.finite3(&[SIDE_KEYS[d][s]], v);
                    }
                }
                let periodic = sides[d].map(|s| s == SideSpec::Periodic);
                if periodic[0] != periodic[1] {
                    c.problem(
                        &[SIDE_KEYS[d][periodic[1] as usize]],
                        format!(
                            "{} is periodic but {} is not: periodic sides come in pairs",
                            SIDE_KEYS[d][periodic[1] as usize],
                            SIDE_KEYS[d][periodic[0] as usize]
                        ),
                    );
                }
                // A 2-D flow has no velocity along its thin axis.
                let moves_along_thin = |s: usize, a: usize| {
                    flow_box.cells[a] == 1
                        && sides[d][s].velocity().is_some_and(|v| v[a] != 0.0)
                };
                for s in 0..2 {
                    if let Some(a) = (0..3).find(|&a| moves_along_thin(s, a)) {
                        c.problem(
                            &[SIDE_KEYS[d][s]],
                            format!(
                                "{} moves along {}, but the box is one cell thick there (a 2-D flow has no velocity along it)",
                                SIDE_KEYS[d][s],
                                ["x", "y", "z"][a]
                            ),
                        );
                    }
                }
                if flow_box.cells[d] == 1 && !periodic[0] {
                    c.problem(
                        &[SIDE_KEYS[d][0]],
                        format!(
                            "the box is one cell thick along {}, so its sides there must be periodic (a 2-D flow)",
                            ["x", "y", "z"][d]
                        ),
                    );
                }
            }
            // With no outflow the fluid has nowhere to go: the flux through
            // the sides must balance, or no divergence-free field obeys them.
            let outflow = sides.iter().flatten().any(|s| *s == SideSpec::Outflow);
            if !outflow {
                let (net, scale) = net_inflow(&sides, flow_box);
                if net.abs() > 1e-9 * scale.max(f64::MIN_POSITIVE) {
                    c.problem(
                        &[],
                        format!(
                            "the sides let {net:.6e} m³/s more in than out and none is an outflow: \
                             make one side `outflow`, or balance the inflows"
                        ),
                    );
                }
            }
        });
    }
}

/// Net volume flux into the box through its sides [m³/s], and the sum of
/// the absolute fluxes (its scale).
fn net_inflow(sides: &[[SideSpec; 2]; 3], b: &FlowBox) -> (f64, f64) {
    let size = [0, 1, 2].map(|d| b.upper[d] - b.lower[d]);
    let (mut net, mut scale) = (0.0, 0.0);
    for d in 0..3 {
        let area = size[(d + 1) % 3] * size[(d + 2) % 3];
        for (s, sign) in [(0, 1.0), (1, -1.0)] {
            if let Some(v) = sides[d][s].velocity() {
                // The mean of 4s(1 − s) over the n cell centres
                // s = (i + ½)/n, as the side's faces take it: 2/3 + 1/(3n²).
                let mut mean = v[d];
                if let SideSpec::Parabolic(_) = sides[d][s] {
                    for t in [(d + 1) % 3, (d + 2) % 3] {
                        if sides[t][0] != SideSpec::Periodic {
                            let n = b.cells[t] as f64;
                            mean *= 2.0 / 3.0 + 1.0 / (3.0 * n * n);
                        }
                    }
                }
                net += sign * mean * area;
                scale += (mean * area).abs();
            }
        }
    }
    (net, scale)
}

/// `[[fluid.probes]]`: a named point whose pressure and velocity the flow
/// reports as monitors (`probe_<name>_pressure`, `probe_<name>_velocity_x`…).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Probe {
    pub name: String,
    /// Where [m], world axes; inside the box.
    pub point: [f64; 3],
}

impl Probe {
    /// Names plain and distinct, points inside `flow_box`.
    pub fn check_all(probes: &[Probe], c: &mut Checker, flow_box: &FlowBox) {
        for (i, p) in probes.iter().enumerate() {
            c.within("probes", Some(i), |c| {
                c.plain_name(&["name"], &p.name, true);
                if probes[..i].iter().any(|q| q.name == p.name) {
                    c.problem(
                        &["name"],
                        format!("a probe named `{}` is given twice", p.name),
                    );
                }
                c.finite3(&["point"], p.point);
                let inside =
                    (0..3).all(|d| (flow_box.lower[d]..=flow_box.upper[d]).contains(&p.point[d]));
                if !inside {
                    c.problem(
                        &["point"],
                        format!(
                            "point = {:?} lies outside the box, from {:?} to {:?}",
                            p.point, flow_box.lower, flow_box.upper
                        ),
                    );
                }
            });
        }
    }
}
