//! `[coupling] scheme` and `[coupling.implicit]`: whether windows are taken
//! again until the interface converges, and how (the participant library's
//! `scheme.rs` and PROTOCOL.md, "Implicit coupling").

use crate::check::Checker;
use exchange::fields::{
    self, ATTACHMENT_STATE, BODY_LOADS, BODY_STATES, CANOPY_POSITIONS, CANOPY_PRESSURE,
    CANOPY_VELOCITIES,
};
use serde::{Deserialize, Serialize};

/// The interface fields accelerated by default: those the fluid reads at
/// a window's start, written by the structure and the rigid bodies at its
/// end.
pub const DEFAULT_ACCELERATED: [&str; 3] = [CANOPY_POSITIONS, CANOPY_VELOCITIES, BODY_STATES];
/// Accelerated by default too under the parallel scheme, where the
/// structure and the rigid bodies read them at a window's start from the
/// fluid's last try: the fluid's answers.
pub const PARALLEL_ACCELERATED: [&str; 2] = [CANOPY_PRESSURE, BODY_LOADS];
/// Accelerated by default too when the structure and the bodies iterate
/// each window (`CouplingSection::bodies_iterate`): the attachment points
/// the structure reads at a window's start, written at its end.
pub const BODIES_ITERATE_ACCELERATED: &str = ATTACHMENT_STATE;
/// Default convergence limit ‖r‖₂ ≤ relative·‖x‖₂ per accelerated field.
pub const DEFAULT_RELATIVE: f64 = 1e-5;
/// Default ω: constant relaxation's, Aitken's first, IQN-ILS's before it
/// has a column.
pub const DEFAULT_RELAXATION: f64 = 0.1;
/// Default most tries per window.
pub const DEFAULT_MAX_ITERATIONS: u32 = 50;
/// IQN-ILS defaults: windows whose columns are reused, most columns, and
/// the QR2 filter's limit (Haelterman et al. 2016).
pub const DEFAULT_REUSED_WINDOWS: u32 = 8;
pub const DEFAULT_MAX_COLUMNS: u32 = 50;
pub const DEFAULT_FILTER: f64 = 1e-2;
/// Most tries per window a scenario may ask for.
pub const MAX_ITERATIONS: f64 = 10_000.0;

#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "lowercase")]
pub enum SchemeName {
    #[default]
    Explicit,
    /// Serial implicit: each window again until the interface converges,
    /// the fluid first, then the structure and the bodies.
    Implicit,
    /// Parallel implicit (Mehl, Uekermann et al. 2016): each try of a
    /// window computed by every participant at once, each from the
    /// others' last values, the quasi-Newton update acting on all the
    /// exchanged fields together.
    #[serde(rename = "parallel-implicit")]
    ParallelImplicit,
}

impl SchemeName {
    /// Whether windows are taken again until the interface converges.
    pub fn is_implicit(self) -> bool {
        self != SchemeName::Explicit
    }
}

#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "lowercase")]
pub enum AccelerationName {
    Constant,
    Aitken,
    #[default]
    #[serde(rename = "iqn-ils")]
    IqnIls,
}

#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum OnMax {
    /// Stop the run, naming the window, field and residual.
    #[default]
    Stop,
    /// Go on to the next window with a warning.
    GoOn,
}

/// `[coupling.implicit]`.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ImplicitSection {
    #[serde(default)]
    pub acceleration: AccelerationName,
    /// ω of constant relaxation; Aitken's first ω in each window.
    #[serde(default = "relaxation")]
    pub relaxation: f64,
    /// The fields relaxed and measured (by their protocol names); see
    /// [`ImplicitSection::accelerated`] for the default.
    #[serde(default)]
    pub accelerate: Option<Vec<String>>,
    /// Convergence: ‖r‖₂ ≤ relative·‖x‖₂ or ‖r‖₂ ≤ absolute, per field;
    /// with neither given, relative = [`DEFAULT_RELATIVE`].
    #[serde(default)]
    pub relative: Option<f64>,
    #[serde(default)]
    pub absolute: Option<f64>,
    /// Limits of single fields, in place of `relative` and `absolute`.
    #[serde(default)]
    pub field: Vec<FieldLimits>,
    #[serde(default = "one")]
    pub min_iterations: u32,
    #[serde(default = "max_iterations")]
    pub max_iterations: u32,
    #[serde(default)]
    pub on_max: OnMax,
    /// IQN-ILS: windows whose columns are reused besides the current one.
    #[serde(default = "reused_windows")]
    pub reused_windows: u32,
    /// IQN-ILS: most columns kept.
    #[serde(default = "max_columns")]
    pub max_columns: u32,
    /// IQN-ILS: the QR2 filter's limit, a column dropped when its part
    /// independent of the newer ones is below this fraction of its norm.
    #[serde(default = "filter")]
    pub filter: f64,
    /// IQN-ILS: ω on the part of each residual its columns do not explain
    /// (1: taken whole, as preCICE does). Strong added mass (a light
    /// fabric in dense air) wants about 1/(1 + μ), μ the air's mass over
    /// the cloth's in the modes the columns miss.
    #[serde(default = "complement_relaxation")]
    pub complement_relaxation: f64,
}

/// `[[coupling.implicit.field]]`: one accelerated field's own limits.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FieldLimits {
    pub name: String,
    #[serde(default)]
    pub relative: Option<f64>,
    #[serde(default)]
    pub absolute: Option<f64>,
}

impl FieldLimits {
    fn check(&self, c: &mut Checker, accelerated: &[String]) {
        if !accelerated.contains(&self.name) {
            c.problem(
                &["name"],
                format!(
                    "field `{}` is not accelerated (accelerate = {accelerated:?}), so it takes \
                     no limits",
                    self.name
                ),
            );
        }
        if let Some(r) = self.relative {
            c.positive(&["relative"], r, "");
        }
        if let Some(a) = self.absolute {
            c.positive(&["absolute"], a, "");
        }
    }
}

impl Default for ImplicitSection {
    fn default() -> Self {
        ImplicitSection {
            acceleration: AccelerationName::default(),
            relaxation: DEFAULT_RELAXATION,
            accelerate: None,
            relative: None,
            absolute: None,
            field: Vec::new(),
            min_iterations: 1,
            max_iterations: DEFAULT_MAX_ITERATIONS,
            on_max: OnMax::default(),
            reused_windows: DEFAULT_REUSED_WINDOWS,
            max_columns: DEFAULT_MAX_COLUMNS,
            filter: DEFAULT_FILTER,
            complement_relaxation: 1.0,
        }
    }
}

impl ImplicitSection {
    /// The accelerated fields: `accelerate`, else [`DEFAULT_ACCELERATED`],
    /// with [`BODIES_ITERATE_ACCELERATED`] when `bodies_iterate` and
    /// [`PARALLEL_ACCELERATED`] when `parallel`.
    pub fn accelerated(&self, bodies_iterate: bool, parallel: bool) -> Vec<String> {
        if let Some(given) = &self.accelerate {
            return given.clone();
        }
        let mut fields: Vec<String> = DEFAULT_ACCELERATED.iter().map(|s| s.to_string()).collect();
        if bodies_iterate {
            fields.push(BODIES_ITERATE_ACCELERATED.to_string());
        }
        if parallel {
            fields.extend(PARALLEL_ACCELERATED.iter().map(|s| s.to_string()));
        }
        fields
    }

    /// The relative and absolute limits of accelerated field `name`: its
    /// own, else the section's, else the default relative limit.
    pub fn limits(&self, name: &str) -> (Option<f64>, Option<f64>) {
        let own = self.field.iter().find(|f| f.name == name);
        let given = own.map_or((self.relative, self.absolute), |f| (f.relative, f.absolute));
        match given {
            (None, None) => (Some(DEFAULT_RELATIVE), None),
            limits => limits,
        }
    }

    pub fn check(&self, c: &mut Checker, bodies_iterate: bool, parallel: bool) {
        let accelerated = self.accelerated(bodies_iterate, parallel);
        let at = |key: &'static str| ["coupling", "implicit", key];
        let w = self.relaxation;
        if !(w.is_finite() && w > 0.0 && w <= 2.0) {
            c.problem(
                &at("relaxation"),
                format!("relaxation = {w} must lie in (0, 2]: ω ≤ 0 never moves, ω > 2 overshoots"),
            );
        }
        if let Some(r) = self.relative {
            c.positive(&at("relative"), r, "");
        }
        if let Some(a) = self.absolute {
            c.positive(&at("absolute"), a, "");
        }
        c.nonzero(&at("min_iterations"), self.min_iterations as f64);
        c.nonzero(&at("max_iterations"), self.max_iterations as f64);
        c.at_most(
            &at("max_iterations"),
            self.max_iterations as f64,
            MAX_ITERATIONS,
        );
        if self.min_iterations > self.max_iterations {
            c.problem(
                &at("min_iterations"),
                format!(
                    "min_iterations = {} is above max_iterations = {}",
                    self.min_iterations, self.max_iterations
                ),
            );
        }
        c.nonzero(&at("max_columns"), self.max_columns as f64);
        c.at_most(&at("max_columns"), self.max_columns as f64, MAX_ITERATIONS);
        c.at_most(
            &at("reused_windows"),
            self.reused_windows as f64,
            MAX_ITERATIONS,
        );
        if !(self.filter.is_finite() && self.filter > 0.0 && self.filter < 1.0) {
            c.problem(
                &at("filter"),
                format!("filter = {} must lie in (0, 1)", self.filter),
            );
        }
        let w = self.complement_relaxation;
        if !(w.is_finite() && w > 0.0 && w <= 1.0) {
            c.problem(
                &at("complement_relaxation"),
                format!(
                    "complement_relaxation = {w} must lie in (0, 1]: 1 takes the unexplained \
                     residual whole, below 1 damps it"
                ),
            );
        }
        for (i, f) in self.field.iter().enumerate() {
            c.within("coupling", None, |c| {
                c.within("implicit", None, |c| {
                    c.within("field", Some(i), |c| f.check(c, &accelerated))
                })
            });
        }
        check_accelerated(c, &accelerated, bodies_iterate);
    }
}

/// `accelerate`: fields implicit coupling can relax once a window, and at
/// least one.
fn check_accelerated(c: &mut Checker, accelerated: &[String], bodies_iterate: bool) {
    let at = ["coupling", "implicit", "accelerate"];
    let per_impulse = accelerated
        .iter()
        .find(|f| fields::PER_IMPULSE.contains(&f.as_str()));
    if let (false, Some(field)) = (bodies_iterate, per_impulse) {
        c.problem(
            &at,
            format!(
                "`{field}` is exchanged at every impulse sub-step, and implicit coupling \
                 relaxes a field once a window: set [coupling] impulse_substeps = 1, or \
                 take it out of accelerate"
            ),
        );
    }
    if accelerated.is_empty() {
        c.problem(
            &at,
            "accelerate lists no field: implicit coupling needs a field to converge".into(),
        );
    }
}

fn relaxation() -> f64 {
    DEFAULT_RELAXATION
}
fn one() -> u32 {
    1
}
fn max_iterations() -> u32 {
    DEFAULT_MAX_ITERATIONS
}
fn reused_windows() -> u32 {
    DEFAULT_REUSED_WINDOWS
}
fn max_columns() -> u32 {
    DEFAULT_MAX_COLUMNS
}
fn filter() -> f64 {
    DEFAULT_FILTER
}
fn complement_relaxation() -> f64 {
    1.0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A field's own limits replace the section's; a field without any
    /// takes the default relative limit.
    #[test]
    fn a_field_takes_its_own_limits_else_the_sections_else_the_default() {
        let mut s = ImplicitSection {
            absolute: Some(1e-8),
            field: vec![FieldLimits {
                name: CANOPY_VELOCITIES.into(),
                relative: Some(1e-4),
                absolute: None,
            }],
            ..Default::default()
        };
        assert_eq!(s.limits(CANOPY_VELOCITIES), (Some(1e-4), None));
        assert_eq!(s.limits(CANOPY_POSITIONS), (None, Some(1e-8)));
        s.absolute = None;
        assert_eq!(s.limits(CANOPY_POSITIONS), (Some(DEFAULT_RELATIVE), None));
    }

    /// The default list closes the structure–body loop when it is iterated;
    /// a given list is taken as it is.
    #[test]
    fn attachment_state_joins_the_default_when_the_bodies_iterate() {
        let mut s = ImplicitSection::default();
        assert_eq!(s.accelerated(false, false), DEFAULT_ACCELERATED);
        assert_eq!(
            s.accelerated(true, false).last().map(String::as_str),
            Some(BODIES_ITERATE_ACCELERATED)
        );
        // The parallel scheme relaxes the fluid's answers too.
        let parallel = s.accelerated(false, true);
        assert_eq!(parallel[DEFAULT_ACCELERATED.len()..], PARALLEL_ACCELERATED);
        s.accelerate = Some(vec![BODY_STATES.into()]);
        assert_eq!(s.accelerated(true, true), [BODY_STATES]);
    }
}
