//! The stability sweep: every chosen integrator on a linear spring network
//! over a grid of stiffness k and step h, each run called stable or unstable
//! by a stated rule, and the largest stable step found by bisection beside
//! the theory: ω_max of dissertation eq. (3.7) and the scheme's interval ω·h ≤ y*.

use crate::accuracy::scheme;
use crate::reference::{mechanical_energy, Owned};
use structure_proc::network::Network;
use structure_proc::stability::{self, Interval};
use structure_proc::{Model, NodeKind, Spring, System};
use structure_section::Integrator;

/// The rule: a run is unstable when a value turns non-finite, or when its
/// energy after [`STEPS`] steps exceeds this factor times its initial energy.
/// The network is undamped, so a stable scheme keeps its energy bounded. The
/// energy is judged at the end, not at its peak: stable schemes may swing
/// far on the way — velocity Verlet's energy oscillates by up to 1/(1 − y²/4)
/// near its limit, and HHT-α overshoots for a few steps when ω·h ≫ 1 (Hilber
/// & Hughes 1978) before its dissipation takes over.
pub const GROWTH: f64 = 100.0;
/// Steps each run takes.
pub const STEPS: u64 = 1000;
/// Bisection halvings of the log-step between the last stable and the first
/// unstable grid step; 8 resolve a quarter decade to 0.2 %.
pub const BISECTIONS: u32 = 8;

/// Amplitude of the initial mode, as a fraction of the spacing: small enough
/// that the energy can grow by [`GROWTH`] before springs approach zero length,
/// where their force stops being linear.
pub const AMPLITUDE: f64 = 1e-3;

/// A fixed–fixed chain of `free` equal masses joined by `free + 1` equal
/// springs along x, started at rest in its highest mode: under axial motion the
/// spring forces of thesis eq. (67) are exactly linear, and the motion stays
/// in that mode, whose frequency 2√(k/m)·sin(nπ/(2(n+1))) is the network's ω_max.
#[derive(Debug, Clone, Copy)]
pub struct Chain {
    /// Free nodes n; odd, so the middle node carries the mode.
    pub free: usize,
    /// Mass of each free node [kg].
    pub mass: f64,
    /// Rest length of each spring [m].
    pub spacing: f64,
}

impl Default for Chain {
    fn default() -> Self {
        Chain {
            free: 9,
            mass: 0.01,
            spacing: 0.1,
        }
    }
}

impl Chain {
    /// The network with spring stiffness `k` [N/m], at rest in its highest mode.
    pub fn model(&self, k: f64) -> Model {
        let n = self.free;
        let nodes = n + 2;
        let mut x = vec![0.0; 3 * nodes];
        for i in 0..nodes {
            let mode = (n as f64 * i as f64 * std::f64::consts::PI / (n as f64 + 1.0)).sin();
            x[3 * i] = i as f64 * self.spacing + AMPLITUDE * self.spacing * mode;
        }
        let mut kind = vec![NodeKind::Free; nodes];
        kind[0] = NodeKind::Fixed;
        kind[nodes - 1] = NodeKind::Fixed;
        let mut mass = vec![self.mass; nodes];
        mass[0] = 0.0;
        mass[nodes - 1] = 0.0;
        let springs = (0..nodes - 1)
            .map(|i| Spring {
                i,
                j: i + 1,
                k,
                rest: self.spacing,
                tension_only: false,
                eps: 0.0,
            })
            .collect();
        let mut m = Model {
            x,
            v: vec![0.0; 3 * nodes],
            net: Network {
                mass,
                kind,
                springs,
                ..Default::default()
            },
            ..Default::default()
        };
        m.prepare();
        m
    }

    /// ω_max bound of dissertation eq. (3.7) at stiffness `k`, as canopy computes it.
    pub fn omega_max(&self, k: f64) -> f64 {
        let m = self.model(k);
        stability::omega_max(&m.inv_mass, &m.couplings)
    }

    /// The exact highest frequency of the chain at stiffness `k`.
    pub fn exact_omega_max(&self, k: f64) -> f64 {
        let n = self.free as f64;
        2.0 * (k / self.mass).sqrt() * (n * std::f64::consts::PI / (2.0 * (n + 1.0))).sin()
    }
}

#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    /// Energy within [`GROWTH`]·E₀ after [`STEPS`] steps; the ratio E/E₀ then.
    Stable(f64),
    /// Non-finite at the step given, or the energy ratio beyond [`GROWTH`] at the end.
    Unstable { step: u64, ratio: f64 },
    /// The step itself failed (Newton iterations that did not converge).
    Failed(String),
}

impl Outcome {
    pub fn label(&self) -> String {
        match self {
            Outcome::Stable(_) => "stable".into(),
            Outcome::Unstable { step, ratio } if ratio.is_finite() => {
                format!("unstable: energy {ratio:.3e} E0 after {step} steps")
            }
            Outcome::Unstable { step, .. } => format!("unstable: non-finite at step {step}"),
            Outcome::Failed(why) => format!("failed: {why}"),
        }
    }
}

/// One run of `integrator` with step `dt` on `chain` at stiffness `k`.
pub fn probe(chain: &Chain, integrator: Integrator, k: f64, dt: f64) -> Outcome {
    let model = chain.model(k);
    let e0 = mechanical_energy(&model, &model.x, &model.v);
    let (mut x, mut v) = (model.x.clone(), model.v.clone());
    let sys = Owned(model);
    let mut stepper = structure_proc::integrator(scheme(integrator));
    for step in 1..=STEPS {
        if let Err(e) = stepper.step(&sys as &dyn System, dt, &mut x, &mut v) {
            return Outcome::Failed(e.to_string());
        }
        if x.iter().chain(&v).any(|q| !q.is_finite()) {
            return Outcome::Unstable {
                step,
                ratio: f64::INFINITY,
            };
        }
    }
    let ratio = mechanical_energy(&sys.0, &x, &v) / e0;
    if ratio <= GROWTH {
        Outcome::Stable(ratio)
    } else {
        Outcome::Unstable { step: STEPS, ratio }
    }
}

/// One cell of the map.
#[derive(Debug, Clone)]
pub struct Cell {
    pub integrator: Integrator,
    pub k: f64,
    pub dt: f64,
    /// ω_max·h with ω_max from eq. (3.7).
    pub omega_h: f64,
    pub outcome: Outcome,
}

/// `count` values from `lo` to `hi`, equally spaced in log.
pub fn log_grid(lo: f64, hi: f64, count: usize) -> Vec<f64> {
    if count < 2 {
        return vec![lo];
    }
    let r = (hi / lo).ln() / (count - 1) as f64;
    (0..count).map(|i| lo * (r * i as f64).exp()).collect()
}

/// Every integrator at every (k, dt) of the grid; `progress` hears of each
/// integrator as it finishes.
pub fn map(
    chain: &Chain,
    integrators: &[Integrator],
    ks: &[f64],
    dts: &[f64],
    mut progress: impl FnMut(Integrator, &[Cell]),
) -> Vec<Cell> {
    let mut cells = Vec::new();
    for &i in integrators {
        let start = cells.len();
        for &k in ks {
            let w = chain.omega_max(k);
            for &dt in dts {
                cells.push(Cell {
                    integrator: i,
                    k,
                    dt,
                    omega_h: w * dt,
                    outcome: probe(chain, i, k, dt),
                });
            }
        }
        progress(i, &cells[start..]);
    }
    cells
}

/// The largest stable step of one integrator at one stiffness, measured and predicted.
#[derive(Debug, Clone)]
pub struct Limit {
    pub integrator: Integrator,
    pub k: f64,
    /// ω_max of eq. (3.7) at this k [rad/s].
    pub omega_max: f64,
    /// Largest stable step found [s]; None when every grid step was stable,
    /// 0 when even the smallest was not.
    pub measured: Option<f64>,
    /// y*/ω_max [s] with ω_max of eq. (3.7); None for unconditional stability.
    pub predicted: Option<f64>,
}

/// ω·h at which the rule calls `integrator` unstable, in theory: the end of
/// its stability interval; for an empty interval, where the amplification of
/// the undamped mode, |R(iy)|^(2·STEPS), reaches [`GROWTH`] — explicit Euler
/// |R|² = 1 + y², explicit midpoint and Heun |R|² = 1 + y⁴/4 (their modes'
/// amplification is a scaled rotation, so energy grows exactly as |R|²ⁿ).
pub fn predicted_omega_h(integrator: Integrator) -> Option<f64> {
    let per_step = GROWTH.powf(1.0 / STEPS as f64) - 1.0; // |R|² − 1 at the limit
    match stability::interval(scheme(integrator)) {
        Interval::Unconditional => None,
        Interval::Bounded(y) => Some(y),
        Interval::Empty => match integrator {
            Integrator::ExplicitEuler => Some(per_step.sqrt()),
            Integrator::EulerRichardson | Integrator::ImprovedEuler => {
                Some((4.0 * per_step).powf(0.25))
            }
            _ => None,
        },
    }
}

/// For each integrator and stiffness of `cells`: the first unstable grid step
/// above the last stable one, refined by [`BISECTIONS`] geometric bisections.
pub fn limits(chain: &Chain, cells: &[Cell]) -> Vec<Limit> {
    let mut out: Vec<Limit> = Vec::new();
    for c in cells {
        if out
            .iter()
            .any(|l| l.integrator == c.integrator && l.k == c.k)
        {
            continue;
        }
        let mut column: Vec<&Cell> = cells
            .iter()
            .filter(|d| d.integrator == c.integrator && d.k == c.k)
            .collect();
        column.sort_by(|a, b| a.dt.total_cmp(&b.dt));
        let first_bad = column
            .iter()
            .position(|d| !matches!(d.outcome, Outcome::Stable(_)));
        let measured = match first_bad {
            None => None,
            Some(0) => Some(0.0),
            Some(b) => {
                let (mut lo, mut hi) = (column[b - 1].dt, column[b].dt);
                for _ in 0..BISECTIONS {
                    let mid = (lo * hi).sqrt();
                    if matches!(probe(chain, c.integrator, c.k, mid), Outcome::Stable(_)) {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                Some(lo)
            }
        };
        let omega_max = chain.omega_max(c.k);
        out.push(Limit {
            integrator: c.integrator,
            k: c.k,
            omega_max,
            measured,
            predicted: predicted_omega_h(c.integrator).map(|y| y / omega_max),
        });
    }
    out
}
