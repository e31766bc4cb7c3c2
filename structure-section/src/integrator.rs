//! `[structure] integrator = "…"` and the parameters of the schemes that have any
//! (thesis §2.4).

use scenario::Checker;
use serde::{Deserialize, Serialize};

/// The time integrator of the structure, one key in the scenario.
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum Integrator {
    /// Explicit (forward) Euler, thesis §2.4.1.
    ExplicitEuler,
    /// Euler–Cromer / symplectic Euler, thesis eqs. (15)–(16).
    EulerCromer,
    /// Euler–Richardson (midpoint), thesis eqs. (17)–(22).
    EulerRichardson,
    /// Improved explicit Euler (Heun), thesis eqs. (23)–(24).
    ImprovedEuler,
    /// Newmark with β, γ from `[structure.newmark]`, thesis eqs. (25)–(26).
    Newmark,
    /// Newmark's average-acceleration preset, β = 1/4, γ = 1/2.
    NewmarkAverageAcceleration,
    /// Newmark's linear-acceleration preset, β = 1/6, γ = 1/2.
    NewmarkLinearAcceleration,
    /// Velocity Verlet, thesis eqs. (37)–(40).
    #[default]
    VelocityVerlet,
    /// Hilber–Hughes–Taylor α, thesis §2.4.7, α from `[structure.hht]`.
    Hht,
    /// Classical fourth-order Runge–Kutta, thesis eqs. (42)–(51).
    Rk4,
    /// Kang's fast approximated implicit method, thesis eqs. (52)–(57).
    Kang,
    /// Backward Euler with Newton iterations and conjugate gradients (Baraff & Witkin 1998).
    BackwardEuler,
    /// Adaptive Dormand–Prince 5(4), tolerance from `[structure.adaptive]`
    /// (beyond the dissertation and the thesis: Dormand & Prince 1980).
    DormandPrince,
}

impl Integrator {
    pub const ALL: [Integrator; 13] = [
        Integrator::ExplicitEuler,
        Integrator::EulerCromer,
        Integrator::EulerRichardson,
        Integrator::ImprovedEuler,
        Integrator::Newmark,
        Integrator::NewmarkAverageAcceleration,
        Integrator::NewmarkLinearAcceleration,
        Integrator::VelocityVerlet,
        Integrator::Hht,
        Integrator::Rk4,
        Integrator::Kang,
        Integrator::BackwardEuler,
        Integrator::DormandPrince,
    ];

    /// The scenario spelling, e.g. `"velocity-verlet"`.
    pub fn name(self) -> &'static str {
        match self {
            Integrator::ExplicitEuler => "explicit-euler",
            Integrator::EulerCromer => "euler-cromer",
            Integrator::EulerRichardson => "euler-richardson",
            Integrator::ImprovedEuler => "improved-euler",
            Integrator::Newmark => "newmark",
            Integrator::NewmarkAverageAcceleration => "newmark-average-acceleration",
            Integrator::NewmarkLinearAcceleration => "newmark-linear-acceleration",
            Integrator::VelocityVerlet => "velocity-verlet",
            Integrator::Hht => "hht",
            Integrator::Rk4 => "rk4",
            Integrator::Kang => "kang",
            Integrator::BackwardEuler => "backward-euler",
            Integrator::DormandPrince => "dormand-prince",
        }
    }

    /// Whether the scheme chooses its own internal steps by error control.
    pub fn is_adaptive(self) -> bool {
        self == Integrator::DormandPrince
    }

    /// Whether the scheme solves a nonlinear system with Newton iterations.
    pub fn is_implicit(self) -> bool {
        matches!(
            self,
            Integrator::Newmark
                | Integrator::NewmarkAverageAcceleration
                | Integrator::NewmarkLinearAcceleration
                | Integrator::Hht
                | Integrator::BackwardEuler
        )
    }
}

/// `[structure.newmark]`: β and γ of thesis eqs. (25)–(26) for `integrator = "newmark"`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NewmarkParams {
    #[serde(default = "quarter")]
    pub beta: f64,
    #[serde(default = "half")]
    pub gamma: f64,
}

impl Default for NewmarkParams {
    fn default() -> Self {
        NewmarkParams {
            beta: 0.25,
            gamma: 0.5,
        }
    }
}

/// `[structure.hht]`: Hilber–Hughes–Taylor α ∈ [−1/3, 0]; β = (1 − α)²/4 and
/// γ = 1/2 − α follow from it (Hilber, Hughes & Taylor 1977).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct HhtParams {
    #[serde(default = "default_alpha")]
    pub alpha: f64,
}

impl Default for HhtParams {
    fn default() -> Self {
        HhtParams {
            alpha: default_alpha(),
        }
    }
}

/// `[structure.adaptive]`: the error tolerance of `integrator = "dormand-prince"`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AdaptiveParams {
    /// Largest local error per internal step, relative to 1 + |value| of each
    /// position [m] and velocity [m/s].
    #[serde(default = "default_adaptive_tolerance")]
    pub tolerance: f64,
}

impl Default for AdaptiveParams {
    fn default() -> Self {
        AdaptiveParams {
            tolerance: default_adaptive_tolerance(),
        }
    }
}

fn default_adaptive_tolerance() -> f64 {
    1e-6
}

/// `[structure.newton]`: the nonlinear solve of the implicit schemes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NewtonParams {
    /// Stop when the correction of the acceleration is this small relative to it.
    #[serde(default = "default_tolerance")]
    pub tolerance: f64,
    #[serde(default = "default_iterations")]
    pub max_iterations: u32,
    /// Relative residual at which each conjugate-gradient solve stops.
    #[serde(default = "default_cg_tolerance")]
    pub cg_tolerance: f64,
    #[serde(default = "default_cg_iterations")]
    pub max_cg_iterations: u32,
    /// How each Newton step's linear system is solved.
    #[serde(default)]
    pub linear_solver: LinearSolver,
}

/// `[structure.newton] linear_solver`.
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum LinearSolver {
    /// Conjugate gradients, matrix-free, preconditioned by the diagonal.
    Cg,
    /// A sparse Cholesky factorization of the assembled matrix (faer),
    /// kept as the preconditioner of conjugate gradients while they
    /// converge in a few iterations (`structure-proc/src/integrators/cholesky.rs`).
    #[default]
    Cholesky,
    /// Conjugate gradients preconditioned with smoothed-aggregation algebraic
    /// multigrid, whose cost grows like the node count
    /// (`structure-proc/src/integrators/multigrid.rs`).
    Multigrid,
}

impl Default for NewtonParams {
    fn default() -> Self {
        NewtonParams {
            tolerance: default_tolerance(),
            max_iterations: default_iterations(),
            cg_tolerance: default_cg_tolerance(),
            max_cg_iterations: default_cg_iterations(),
            linear_solver: LinearSolver::default(),
        }
    }
}

fn quarter() -> f64 {
    0.25
}
fn half() -> f64 {
    0.5
}
fn default_alpha() -> f64 {
    -0.1
}
fn default_tolerance() -> f64 {
    1e-10
}
fn default_iterations() -> u32 {
    30
}
fn default_cg_tolerance() -> f64 {
    // An inexact Newton method: each linear solve only needs to gain a few
    // digits, the Newton test on the correction sets the final accuracy.
    1e-4
}
fn default_cg_iterations() -> u32 {
    2000
}

/// The scheme with its parameters resolved, as the structure solver uses it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Scheme {
    ExplicitEuler,
    EulerCromer,
    EulerRichardson,
    ImprovedEuler,
    VelocityVerlet,
    Rk4,
    Kang,
    /// Newmark (α = 0) and HHT-α: M·a₊ = (1 + α)·F₊ − α·F.
    Newmark {
        beta: f64,
        gamma: f64,
        alpha: f64,
        newton: NewtonParams,
    },
    BackwardEuler {
        newton: NewtonParams,
    },
    DormandPrince {
        tolerance: f64,
    },
}

impl Scheme {
    pub fn resolve(
        i: Integrator,
        newmark: NewmarkParams,
        hht: HhtParams,
        newton: NewtonParams,
        adaptive: AdaptiveParams,
    ) -> Scheme {
        let nm = |beta, gamma, alpha| Scheme::Newmark {
            beta,
            gamma,
            alpha,
            newton,
        };
        match i {
            Integrator::ExplicitEuler => Scheme::ExplicitEuler,
            Integrator::EulerCromer => Scheme::EulerCromer,
            Integrator::EulerRichardson => Scheme::EulerRichardson,
            Integrator::ImprovedEuler => Scheme::ImprovedEuler,
            Integrator::VelocityVerlet => Scheme::VelocityVerlet,
            Integrator::Rk4 => Scheme::Rk4,
            Integrator::Kang => Scheme::Kang,
            Integrator::Newmark => nm(newmark.beta, newmark.gamma, 0.0),
            Integrator::NewmarkAverageAcceleration => nm(0.25, 0.5, 0.0),
            Integrator::NewmarkLinearAcceleration => nm(1.0 / 6.0, 0.5, 0.0),
            Integrator::Hht => {
                let a = hht.alpha;
                nm((1.0 - a).powi(2) / 4.0, 0.5 - a, a)
            }
            Integrator::BackwardEuler => Scheme::BackwardEuler { newton },
            Integrator::DormandPrince => Scheme::DormandPrince {
                tolerance: adaptive.tolerance,
            },
        }
    }
}

pub(crate) fn check_params(
    c: &mut Checker,
    newmark: &NewmarkParams,
    hht: &HhtParams,
    newton: &NewtonParams,
    adaptive: &AdaptiveParams,
) {
    c.within("adaptive", None, |c| {
        c.fraction(&["tolerance"], adaptive.tolerance)
    });
    c.within("newmark", None, |c| {
        if !(newmark.beta.is_finite() && (0.0..=0.5).contains(&newmark.beta)) {
            c.problem(
                &["beta"],
                format!("beta = {} must lie in [0, 0.5]", newmark.beta),
            );
        }
        if !(newmark.gamma.is_finite() && (0.5..=1.0).contains(&newmark.gamma)) {
            c.problem(
                &["gamma"],
                format!(
                    "gamma = {} must lie in [0.5, 1] (γ < 1/2 adds energy)",
                    newmark.gamma
                ),
            );
        }
    });
    c.within("hht", None, |c| {
        if !(hht.alpha.is_finite() && (-1.0 / 3.0..=0.0).contains(&hht.alpha)) {
            c.problem(
                &["alpha"],
                format!("alpha = {} must lie in [-1/3, 0]", hht.alpha),
            );
        }
    });
    c.within("newton", None, |c| {
        c.fraction(&["tolerance"], newton.tolerance);
        c.fraction(&["cg_tolerance"], newton.cg_tolerance);
        c.nonzero(&["max_iterations"], newton.max_iterations as f64);
        c.at_most(&["max_iterations"], newton.max_iterations as f64, 1e4);
        c.nonzero(&["max_cg_iterations"], newton.max_cg_iterations as f64);
        c.at_most(&["max_cg_iterations"], newton.max_cg_iterations as f64, 1e7);
    });
}
