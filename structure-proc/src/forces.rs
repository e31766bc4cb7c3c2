//! Forces on the nodes, each term with its energy where one exists.

use crate::model::{Model, NodeKind, Spring};
use coupler::scenario::structure::Damping;

#[inline]
fn sub(x: &[f64], i: usize, j: usize) -> [f64; 3] {
    [
        x[3 * j] - x[3 * i],
        x[3 * j + 1] - x[3 * i + 1],
        x[3 * j + 2] - x[3 * i + 2],
    ]
}

/// Stretch that produces force: l − l⁰ for a Hookean spring (seed 003 eq. 67);
/// max(l − l⁰ − eps, 0) for a string (seed 003 eq. 3).
#[inline]
fn active_stretch(s: &Spring, l: f64) -> f64 {
    if s.tension_only {
        (l - s.rest - s.eps).max(0.0)
    } else {
        l - s.rest
    }
}

/// Elastic energy ½ k δ² of one spring, δ its active stretch.
pub fn spring_energy(s: &Spring, x: &[f64]) -> f64 {
    let d = sub(x, s.i, s.j);
    let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    0.5 * s.k * active_stretch(s, l).powi(2)
}

/// Loads from other processes, held for one step and read in place.
#[derive(Debug, Clone, Copy, Default)]
pub struct Loads<'a> {
    /// Signed pressure jump per canopy triangle [Pa]; empty when no fluid takes part.
    pub pressure: &'a [f64],
}

/// Total force on every node at positions `x`, velocities `v`: springs
/// (eq. 67 / eq. 3), damping (eq. 68), gravity (eq. 5) and the fluid's pressure
/// jump on the canopy triangles. `f` is overwritten.
pub fn total_force(m: &Model, loads: &Loads, x: &[f64], v: &[f64], f: &mut [f64]) {
    for n in 0..m.nodes() {
        for c in 0..3 {
            f[3 * n + c] = m.mass[n] * m.gravity[c];
        }
    }
    for s in &m.springs {
        let d = sub(x, s.i, s.j);
        let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let t = s.k * active_stretch(s, l);
        if t != 0.0 && l > 0.0 {
            for c in 0..3 {
                let fc = t * d[c] / l;
                f[3 * s.i + c] += fc;
                f[3 * s.j + c] -= fc;
            }
        }
        // A slack string carries no force (eq. 3), viscous or elastic.
        let slack = s.tension_only && t == 0.0;
        if m.damping == Damping::RelativeVelocity && !slack {
            // Seed 003 eq. (68): F_v,i = Σ k_ij·Δt·(v_j − v_i).
            let c_ij = s.k * m.damping_dt;
            for c in 0..3 {
                let fc = c_ij * (v[3 * s.j + c] - v[3 * s.i + c]);
                f[3 * s.i + c] += fc;
                f[3 * s.j + c] -= fc;
            }
        }
    }
    for (tri, &p) in m.triangles.iter().zip(loads.pressure) {
        if p == 0.0 {
            continue;
        }
        // jump · area · n = ½ jump (e1 × e2), shared equally by the three vertices.
        let n2 = area_normal2(x, tri);
        for &node in tri {
            for c in 0..3 {
                f[3 * node + c] += p * n2[c] / 6.0;
            }
        }
    }
    for (n, kind) in m.kind.iter().enumerate() {
        if *kind == NodeKind::Fixed {
            f[3 * n..3 * n + 3].fill(0.0);
        }
    }
}

/// (x1 − x0) × (x2 − x0): twice the area times the unit normal.
#[inline]
pub fn area_normal2(x: &[f64], tri: &[usize; 3]) -> [f64; 3] {
    let a = sub(x, tri[0], tri[1]);
    let b = sub(x, tri[0], tri[2]);
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
