//! The keys of the compressible Euler model (`[fluid] model = "euler"`,
//! dissertation eqs. 2.20–2.24): the ratio of specific heats, the Courant
//! number of a step, and the initial state region by region
//! (`[[fluid.regions]]`). The box and its sides are the flow keys of
//! `flow.rs`.

use super::flow::{FlowBox, SideSpec, SIDE_KEYS};
use scenario::Checker;
use serde::{Deserialize, Serialize};

/// Ratio of specific heats of air, κ = 1.4 (ISA, ISO 2533:1975): a
/// diatomic ideal gas, γ = 7/5.
pub const AIR_GAMMA: f64 = 1.4;

/// Courant number of a step at the fastest wave, Σ_d (|u_d| + c)Δt/h_d.
/// Jiang & Shu (J. Comput. Phys. 126, 1996, §4) ran WENO5 with third-order
/// TVD Runge–Kutta at 0.6; the scheme's linear limit is about 1.4 in 1-D.
pub const DEFAULT_CFL: f64 = 0.6;

/// Largest Courant number accepted: above 1 a wave crosses a cell in one
/// stage, which no scene needs.
pub const MAX_CFL: f64 = 1.0;

/// One `[[fluid.regions]]` entry: the gas in the cells whose centres lie
/// in [lower, upper). A later region overrides an earlier one; the first
/// must cover the whole box.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GasRegion {
    /// Lowest corner [m]; the box's when left out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lower: Option<[f64; 3]>,
    /// Highest corner [m] (exclusive); the box's when left out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub upper: Option<[f64; 3]>,
    /// Density ρ [kg/m³].
    pub density: f64,
    /// Velocity [m/s].
    #[serde(default)]
    pub velocity: [f64; 3],
    /// Pressure p [Pa].
    pub pressure: f64,
    /// A sinusoid added to the density.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density_wave: Option<DensityWave>,
}

/// The gas a `state` side holds beyond the box: `x_low = { state =
/// { density = 5.4, velocity = [2.2222, 0.0, 0.0], pressure = 10.3333 } }`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GasState {
    /// Density ρ [kg/m³].
    pub density: f64,
    /// Velocity [m/s].
    pub velocity: [f64; 3],
    /// Pressure p [Pa].
    pub pressure: f64,
}

/// ρ(x) = density + amplitude·sin(k·x), as in Shu & Osher's problem.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DensityWave {
    /// Amplitude [kg/m³], below the region's density so ρ stays positive.
    pub amplitude: f64,
    /// Wave vector k [rad/m].
    pub wavenumber: [f64; 3],
}

impl GasRegion {
    /// Whether the point `x` lies in the region.
    pub fn contains(&self, x: [f64; 3]) -> bool {
        (0..3).all(|d| {
            self.lower.is_none_or(|l| x[d] >= l[d]) && self.upper.is_none_or(|u| x[d] < u[d])
        })
    }

    /// The density at `x` [kg/m³].
    pub fn density_at(&self, x: [f64; 3]) -> f64 {
        self.density
            + self.density_wave.map_or(0.0, |w| {
                w.amplitude * (0..3).map(|d| w.wavenumber[d] * x[d]).sum::<f64>().sin()
            })
    }

    fn check(&self, c: &mut Checker, b: &FlowBox, first: bool) {
        if let Some(l) = self.lower {
            c.finite3(&["lower"], l);
        }
        if let Some(u) = self.upper {
            c.finite3(&["upper"], u);
        }
        if let (Some(l), Some(u)) = (self.lower, self.upper) {
            if (0..3).any(|d| u[d] <= l[d]) {
                c.problem(
                    &["upper"],
                    format!("upper = {u:?} must lie above lower = {l:?} along every axis"),
                );
            }
        }
        let lower_covers = (0..3).all(|d| self.lower.is_none_or(|l| l[d] <= b.lower[d]));
        let upper_covers = (0..3).all(|d| self.upper.is_none_or(|u| u[d] >= b.upper[d]));
        if first && !(lower_covers && upper_covers) {
            c.problem(
                &[if lower_covers { "upper" } else { "lower" }],
                "the first region must cover the whole box (leave out lower and upper), so that \
                 every cell has a gas; later regions override it"
                    .into(),
            );
        }
        c.positive(&["density"], self.density, "kg/m³");
        c.finite3(&["velocity"], self.velocity);
        c.positive(&["pressure"], self.pressure, "Pa");
        if let Some(w) = self.density_wave {
            c.within("density_wave", None, |c| {
                c.finite3(&["wavenumber"], w.wavenumber);
                if !(w.amplitude.is_finite() && w.amplitude.abs() < self.density) {
                    c.problem(
                        &["amplitude"],
                        format!(
                            "amplitude = {} must be smaller than the region's density {} kg/m³, \
                             or the density turns negative",
                            w.amplitude, self.density
                        ),
                    );
                }
            });
        }
    }
}

/// Checks `[fluid]`'s euler keys: the regions against the box, γ, the
/// Courant number, and sides a gas can have.
pub fn check(
    c: &mut Checker,
    regions: Option<&[GasRegion]>,
    b: Option<&FlowBox>,
    sides: Option<[[SideSpec; 2]; 3]>,
    gamma: f64,
    cfl: f64,
) {
    if !(gamma.is_finite() && gamma > 1.0) {
        c.problem(
            &["gamma"],
            format!("gamma = {gamma} must be > 1 (the ratio of specific heats cp/cv)"),
        );
    }
    if !(cfl.is_finite() && cfl > 0.0 && cfl <= MAX_CFL) {
        c.problem(&["cfl"], format!("cfl = {cfl} must lie in (0, {MAX_CFL}]"));
    }
    if let (Some(regions), Some(b)) = (regions, b) {
        if regions.is_empty() {
            c.problem(
                &["regions"],
                "lists no region: give at least one [[fluid.regions]] for the whole box".into(),
            );
        }
        for (i, r) in regions.iter().enumerate() {
            c.within("regions", Some(i), |c| r.check(c, b, i == 0));
        }
    }
    let Some(sides) = sides else { return };
    for d in 0..3 {
        for s in 0..2 {
            let key = SIDE_KEYS[d][s];
            if sides[d][s].velocity().is_some() {
                c.within("sides", None, |c| {
                    c.problem(
                        &[key],
                        format!(
                            "{key}: a side with a given velocity belongs to model = \"incompressible\"; \
                             a side of model = \"euler\" is \"wall\" (reflecting), \"outflow\" \
                             (transmissive), \"periodic\" or {{ state = {{ density, velocity, \
                             pressure }} }} (a supersonic inflow)"
                        ),
                    )
                });
            }
            if let SideSpec::State(state) = sides[d][s] {
                c.within("sides", None, |c| c.within(key, None, |c| state.check(c)));
            }
        }
    }
}

impl GasState {
    fn check(&self, c: &mut Checker) {
        c.within("state", None, |c| {
            c.positive(&["density"], self.density, "kg/m³");
            c.positive(&["pressure"], self.pressure, "Pa");
            c.finite3(&["velocity"], self.velocity);
        });
    }
}

/// A `state` side is the euler model's: the other models are refused it.
pub fn check_no_state_sides(c: &mut Checker, sides: [[SideSpec; 2]; 3], model: &str) {
    for d in 0..3 {
        for s in 0..2 {
            if let SideSpec::State(_) = sides[d][s] {
                let key = SIDE_KEYS[d][s];
                c.within("sides", None, |c| {
                    c.problem(
                        &[key],
                        format!(
                            "{key}: a side held at a gas state belongs to model = \"euler\"; \
                             model = \"{model}\" takes \"wall\", {{ velocity = [..] }}, \
                             {{ parabolic = [..] }}, \"outflow\" or \"periodic\""
                        ),
                    )
                });
            }
        }
    }
}
