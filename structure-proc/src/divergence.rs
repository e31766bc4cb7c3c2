//! Divergence detection, run after every coupling step: a non-finite
//! position or velocity, or a node faster than [`SPEED_FACTOR`] times the
//! scene's speed scale — kinetic energy 10⁴ times what the scene can supply
//! to it. An unstable integration grows geometrically, so it crosses that
//! bound within a few steps of leaving the physics; a stable one stays far
//! below it. The message names the node and the quantity; the driver adds
//! the simulated time.

use crate::Model;
use structure_section::Scene;

/// A node may move at most this many times the scene's speed scale.
pub const SPEED_FACTOR: f64 = 100.0;
/// The smallest speed scale [m/s], for scenes that start at rest with no
/// gravity and no stream (a released spring pendulum moves at ~1 m/s).
pub const MIN_SPEED_SCALE: f64 = 1.0;

/// The speed scale of a scene and what set it.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct Watch {
    /// Speed scale [m/s].
    pub scale: f64,
    /// Where the scale comes from, for the message.
    pub source: String,
}

impl Watch {
    /// The largest of: the fastest node at the start, the speed the initial
    /// elastic energy would give the lightest free node, √(2E/m_min), the
    /// free stream (of `[fluid]` or `[structure.porous]`), the flow box's
    /// sides and initial velocity, the speed that gravity
    /// gives in the whole run, |g|·(t_end − t₀), and [`MIN_SPEED_SCALE`].
    pub fn new(m: &Model, scene: &Scene) -> Watch {
        let mut w = Watch {
            scale: MIN_SPEED_SCALE,
            source: "the floor of 1 m/s".into(),
        };
        let fastest = (0..m.nodes()).map(|n| speed(&m.v, n)).fold(0.0, f64::max);
        w.raise(fastest, "the fastest node at the start");
        let stream = |u: [f64; 3]| u.iter().map(|c| c * c).sum::<f64>().sqrt();
        if let Some(u) = scene.fluid.as_ref().and_then(|f| f.free_stream) {
            w.raise(stream(u), "the free stream");
        }
        for u in scene.fluid.iter().flat_map(|f| f.given_velocities()) {
            w.raise(stream(u), "the flow's fastest side or initial velocity");
        }
        if let Some(p) = &m.porous {
            w.raise(stream(p.free_stream), "the free stream");
        }
        // Energy stored in the springs at the start, all given to the lightest
        // free node: the fastest it could move on that energy alone.
        let lightest = (0..m.nodes())
            .filter(|&n| m.inv_mass[n] > 0.0)
            .map(|n| m.mass[n])
            .fold(f64::INFINITY, f64::min);
        let stored = crate::forces::elastic_energy(m, &m.x);
        w.raise(
            (2.0 * stored / lightest).sqrt(),
            "the elastic energy at the start on the lightest node",
        );
        let g = stream(m.gravity);
        w.raise(
            g * (scene.scenario.run.end_time - scene.scenario.run.start_time),
            "the speed of a free fall over the run",
        );
        w
    }

    /// Raise the scale to `speed` if it is larger (a rigid body's speed, say).
    pub fn raise(&mut self, speed: f64, source: &str) {
        if speed.is_finite() && speed > self.scale {
            self.scale = speed;
            self.source = source.to_string();
        }
    }

    /// The speed bound [m/s].
    pub fn bound(&self) -> f64 {
        SPEED_FACTOR * self.scale
    }

    /// The first node whose state is non-finite or too fast, as a message.
    pub fn check(&self, m: &Model) -> Option<String> {
        if let Some((node, what)) = m.first_non_finite() {
            return Some(format!("{} has a non-finite {what}", label(m, node)));
        }
        let bound = self.bound();
        let (node, fastest) = (0..m.nodes())
            .map(|n| (n, speed(&m.v, n)))
            .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
        (fastest > bound).then(|| {
            format!(
                "{} moves at {fastest:.3e} m/s, beyond the bound {bound:.3e} m/s \
                 ({SPEED_FACTOR} × the speed scale {:.3e} m/s, {})",
                label(m, node),
                self.scale,
                self.source
            )
        })
    }
}

/// "node 12", or "node 2 (`bob`)" for a named point.
fn label(m: &Model, node: usize) -> String {
    match m.points.iter().find(|(_, n)| *n == node) {
        Some((name, _)) => format!("node {node} (`{name}`)"),
        None => format!("node {node}"),
    }
}

fn speed(v: &[f64], n: usize) -> f64 {
    (v[3 * n].powi(2) + v[3 * n + 1].powi(2) + v[3 * n + 2].powi(2)).sqrt()
}
