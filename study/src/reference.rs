//! Reference systems with a known answer, each a [`System`] the integrators
//! advance exactly as they advance a canopy: the damped and undamped
//! oscillator of thesis appendix A, the undamped simple pendulum of the thesis
//! §2.5.1, and the spring pendulum of thesis §2.5.2.

use crate::elliptic::{complete_k, sn_cn_dn};
use rigid_section::STANDARD_GRAVITY;
use structure_proc::forces::{elastic_energy, Dynamics, Loads};
use structure_proc::network::Network;
use structure_proc::{Model, NodeKind, Spring, System};

/// A system, its initial state and its exact solution.
pub trait Reference: Sync {
    /// Name on the command line and in the reports.
    fn name(&self) -> &'static str;
    /// What the error measures and where the exact solution comes from.
    fn error_measure(&self) -> &'static str;
    /// Simulated time of one run [s].
    fn end_time(&self) -> f64 {
        10.0
    }
    /// The error is sampled every this many seconds; steps divide it.
    fn sample_interval(&self) -> f64 {
        0.5
    }
    /// The system and its state (x, v) at t = 0.
    fn start(&self) -> (Box<dyn System>, Vec<f64>, Vec<f64>);
    /// Error of the state (x, v) at time t, relative to the motion's scale.
    fn error(&self, t: f64, x: &[f64], v: &[f64]) -> f64;
}

/// Every reference system, in the order the help lists them.
pub fn all() -> Vec<Box<dyn Reference>> {
    vec![
        Box::new(Oscillator::damped()),
        Box::new(Oscillator::undamped()),
        Box::new(Pendulum::default()),
        Box::new(SpringPendulum::new()),
    ]
}

/// The reference system called `name`.
pub fn by_name(name: &str) -> Option<Box<dyn Reference>> {
    all().into_iter().find(|r| r.name() == name)
}

/// One degree of freedom q, the x coordinate of node 1, with generalised
/// force F(q, q̇) on a mass; node 0 is a fixed anchor so that Kang's method
/// finds the stiffness between a node pair, as on a spring network.
struct OneDof<F> {
    inv_mass: [f64; 2],
    /// F(q, q̇) and its derivatives ∂F/∂q, ∂F/∂q̇.
    law: F,
    couplings: [(usize, usize, f64); 1],
}

impl<F: Fn(f64, f64) -> [f64; 3] + Sync> System for OneDof<F> {
    fn nodes(&self) -> usize {
        2
    }
    fn inv_mass(&self) -> &[f64] {
        &self.inv_mass
    }
    fn force(&self, x: &[f64], v: &[f64], f: &mut [f64]) {
        f.fill(0.0);
        f[3] = (self.law)(x[3], v[3])[0];
    }
    fn jacobian_product(&self, x: &[f64], v: &[f64], a: f64, b: f64, p: &[f64], out: &mut [f64]) {
        let [_, dq, dv] = (self.law)(x[3], v[3]);
        out.fill(0.0);
        out[3] = -(a * dq + b * dv) * p[3];
    }
    fn couplings(&self) -> &[(usize, usize, f64)] {
        &self.couplings
    }
}

/// State (x, v) of a [`OneDof`] at q, q̇.
fn one_dof_state(q: f64, qdot: f64) -> (Vec<f64>, Vec<f64>) {
    let mut x = vec![0.0; 6];
    let mut v = vec![0.0; 6];
    x[3] = q;
    v[3] = qdot;
    (x, v)
}

/// m·q̈ = −k·q − c·q̇ with k = 3 N/m, m = 2 kg, q(0) = 2 m, q̇(0) = 0 (the thesis
/// appendix A); damped with c = 0.5 N·s/m (ratio 0.1), or undamped.
#[derive(Debug, Clone, Copy)]
pub struct Oscillator {
    /// Stiffness k [N/m].
    pub k: f64,
    /// Mass m [kg].
    pub m: f64,
    /// Initial displacement x₀ [m].
    pub x0: f64,
    /// Damping c [N·s/m].
    pub c: f64,
}

impl Oscillator {
    pub fn damped() -> Oscillator {
        Oscillator {
            k: 3.0,
            m: 2.0,
            x0: 2.0,
            c: 0.5,
        }
    }
    pub fn undamped() -> Oscillator {
        Oscillator {
            c: 0.0,
            ..Oscillator::damped()
        }
    }

    /// Thesis eqs. (77)–(81) with v₀ = 0: x(t) = A·e^{−ct/2m}·sin(ωt + φ), and ẋ.
    pub fn exact(&self, t: f64) -> (f64, f64) {
        let Oscillator { k, m, x0, c } = *self;
        let w = (4.0 * m * k - c * c).sqrt() / (2.0 * m); // (77)
        let b = c * x0 / (2.0 * m * w); // (78)
        let a = (x0 * x0 + b * b).sqrt(); // (79)
        let phi = x0.atan2(b); // (80)
        let s = c / (2.0 * m);
        let e = (-s * t).exp();
        let (sin, cos) = (w * t + phi).sin_cos();
        (a * e * sin, a * e * (w * cos - s * sin)) // (81)
    }
}

impl Reference for Oscillator {
    fn name(&self) -> &'static str {
        if self.c == 0.0 {
            "oscillator"
        } else {
            "damped-oscillator"
        }
    }
    fn error_measure(&self) -> &'static str {
        "largest (|x − x_e| + |v − v_e|/ω₀)/x₀ over the samples; exact x_e of thesis appendix A, eqs. (77)–(81)"
    }
    fn start(&self) -> (Box<dyn System>, Vec<f64>, Vec<f64>) {
        let Oscillator { k, m, x0, c } = *self;
        let sys = OneDof {
            inv_mass: [0.0, 1.0 / m],
            law: move |q: f64, qd: f64| [-k * q - c * qd, -k, -c],
            couplings: [(0, 1, k)],
        };
        let (x, v) = one_dof_state(x0, 0.0);
        (Box::new(sys), x, v)
    }
    fn error(&self, t: f64, x: &[f64], v: &[f64]) -> f64 {
        let (xe, ve) = self.exact(t);
        ((x[3] - xe).abs() + (v[3] - ve).abs() / (self.k / self.m).sqrt()) / self.x0
    }
}

/// The undamped simple pendulum of thesis eqs. (58)–(61) with c = 0:
/// θ̈ = −(g/L)·sin θ, L = 1 m, released from rest at θ₀ = 1 rad. Its exact
/// motion is θ = 2·asin(k·sn(K(k) − ω₀t | k²)), k = sin(θ₀/2), ω₀ = √(g/L),
/// with period 4K(k)/ω₀ (the complete elliptic integral).
pub struct Pendulum {
    pub length: f64,
    pub theta0: f64,
}

impl Default for Pendulum {
    fn default() -> Self {
        Pendulum {
            length: 1.0,
            theta0: 1.0,
        }
    }
}

impl Pendulum {
    fn omega0(&self) -> f64 {
        (STANDARD_GRAVITY / self.length).sqrt()
    }

    /// Exact period [s].
    pub fn period(&self) -> f64 {
        4.0 * complete_k((self.theta0 / 2.0).sin().powi(2)) / self.omega0()
    }

    /// Exact θ(t) and θ̇(t) = −2kω₀·cn(K − ω₀t).
    pub fn exact(&self, t: f64) -> (f64, f64) {
        let k = (self.theta0 / 2.0).sin();
        let m = k * k;
        let (sn, cn, _) = sn_cn_dn(complete_k(m) - self.omega0() * t, m);
        (2.0 * (k * sn).asin(), -2.0 * k * self.omega0() * cn)
    }
}

impl Reference for Pendulum {
    fn name(&self) -> &'static str {
        "pendulum"
    }
    fn error_measure(&self) -> &'static str {
        "largest (|θ − θ_e| + |θ̇ − θ̇_e|/ω₀)/θ₀ over the samples; exact θ_e from Jacobi's sn, period 4K(k)/ω₀"
    }
    fn start(&self) -> (Box<dyn System>, Vec<f64>, Vec<f64>) {
        let g_l = STANDARD_GRAVITY / self.length;
        let sys = OneDof {
            inv_mass: [0.0, 1.0],
            law: move |q: f64, _| [-g_l * q.sin(), -g_l * q.cos(), 0.0],
            couplings: [(0, 1, g_l)],
        };
        let (x, v) = one_dof_state(self.theta0, 0.0);
        (Box::new(sys), x, v)
    }
    fn error(&self, t: f64, x: &[f64], v: &[f64]) -> f64 {
        let (q, qd) = self.exact(t);
        ((x[3] - q).abs() + (v[3] - qd).abs() / self.omega0()) / self.theta0
    }
}

/// The spring pendulum of thesis §2.5.2, eqs. (62)–(64), as
/// `scenarios/spring-pendulum.toml` sets it: a 1 kg bob between anchors at
/// y = ±1 m on two springs of K = 100 N/m and rest length 0.8 m, released from
/// rest at (0.3, 0.2) m. With no damping its energy is conserved.
pub struct SpringPendulum {
    /// The model at t = 0.
    model: Model,
    /// Its energy E₀ [J].
    e0: f64,
}

/// A spring-mass [`Model`] that owns its loads, so it can be boxed as a [`System`].
pub(crate) struct Owned(pub Model);

impl System for Owned {
    fn nodes(&self) -> usize {
        self.0.nodes()
    }
    fn inv_mass(&self) -> &[f64] {
        &self.0.inv_mass
    }
    fn force(&self, x: &[f64], v: &[f64], f: &mut [f64]) {
        self.dynamics(|d| d.force(x, v, f));
    }
    fn jacobian_product(&self, x: &[f64], v: &[f64], a: f64, b: f64, p: &[f64], out: &mut [f64]) {
        self.dynamics(|d| d.jacobian_product(x, v, a, b, p, out));
    }
    fn couplings(&self) -> &[(usize, usize, f64)] {
        &self.0.couplings
    }
}

impl Owned {
    fn dynamics(&self, f: impl FnOnce(&Dynamics)) {
        f(&Dynamics {
            net: &self.0.net,
            loads: &Loads::default(),
        })
    }
}

impl Default for SpringPendulum {
    fn default() -> Self {
        SpringPendulum::new()
    }
}

impl SpringPendulum {
    pub fn new() -> SpringPendulum {
        let model = Self::model();
        let e0 = mechanical_energy(&model, &model.x, &model.v);
        SpringPendulum { model, e0 }
    }

    fn model() -> Model {
        let spring = |i, j| Spring {
            i,
            j,
            k: 100.0,
            rest: 0.8,
            tension_only: false,
            eps: 0.0,
        };
        let mut m = Model {
            x: vec![0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.3, 0.2, 0.0],
            v: vec![0.0; 9],
            net: Network {
                mass: vec![0.0, 0.0, 1.0],
                kind: vec![NodeKind::Fixed, NodeKind::Fixed, NodeKind::Free],
                springs: vec![spring(0, 2), spring(1, 2)],
                ..Default::default()
            },
            ..Default::default()
        };
        m.prepare();
        m
    }
}

/// Kinetic plus elastic energy [J] of `m` at the state (x, v).
pub(crate) fn mechanical_energy(m: &Model, x: &[f64], v: &[f64]) -> f64 {
    let kinetic: f64 = (0..m.nodes())
        .map(|n| 0.5 * m.mass[n] * (0..3).map(|c| v[3 * n + c].powi(2)).sum::<f64>())
        .sum();
    kinetic + elastic_energy(m, x)
}

impl Reference for SpringPendulum {
    fn name(&self) -> &'static str {
        "spring-pendulum"
    }
    fn error_measure(&self) -> &'static str {
        "largest |E − E₀|/E₀ over the samples: the energy of eq. (62) is conserved"
    }
    fn start(&self) -> (Box<dyn System>, Vec<f64>, Vec<f64>) {
        let m = self.model.clone();
        let (x, v) = (m.x.clone(), m.v.clone());
        (Box::new(Owned(m)), x, v)
    }
    fn error(&self, _t: f64, x: &[f64], v: &[f64]) -> f64 {
        (mechanical_energy(&self.model, x, v) / self.e0 - 1.0).abs()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pendulum_period_matches_the_tabulated_large_amplitude_factor() {
        // T/T₀ at θ₀ = 90° is 1.18034060… (e.g. Nelson & Olsson, Am. J. Phys. 54, 112 (1986)).
        let p = Pendulum {
            length: 1.0,
            theta0: std::f64::consts::FRAC_PI_2,
        };
        let t0 = 2.0 * std::f64::consts::PI / p.omega0();
        assert!((p.period() / t0 - 1.180_340_6).abs() < 1e-7);
        // The exact motion starts at θ₀ at rest and comes back after one period.
        let (q, qd) = p.exact(0.0);
        assert!((q - p.theta0).abs() < 1e-12 && qd.abs() < 1e-7);
        let (q, _) = p.exact(p.period());
        assert!((q - p.theta0).abs() < 1e-9);
        // Half a period later it is at −θ₀.
        let (q, _) = p.exact(p.period() / 2.0);
        assert!((q + p.theta0).abs() < 1e-9);
    }

    #[test]
    fn exact_solutions_satisfy_their_equations_of_motion() {
        // Central second differences of x_e against the force law.
        let h = 1e-4;
        let osc = Oscillator::damped();
        for t in [0.3, 2.0, 7.7] {
            let (x, v) = osc.exact(t);
            let acc = (osc.exact(t + h).0 - 2.0 * x + osc.exact(t - h).0) / (h * h);
            assert!((osc.m * acc + osc.k * x + osc.c * v).abs() < 1e-6);
        }
        let p = Pendulum::default();
        for t in [0.3, 2.0, 7.7] {
            let (q, _) = p.exact(t);
            let acc = (p.exact(t + h).0 - 2.0 * q + p.exact(t - h).0) / (h * h);
            assert!((acc + STANDARD_GRAVITY * q.sin()).abs() < 1e-5);
        }
    }
}
