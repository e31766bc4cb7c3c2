//! Impulses on a pair of features (the dissertation eqs. 3.28–3.30, after
//! Bridson, Fedkiw & Anderson 2002, §7).
//!
//! Everything is in displacements over the step, dx = v_ave·Δt, so that an
//! impulse J on the pair changes its relative displacement Σ wᵢ dxᵢ by
//! J·Δt·Σ wᵢ²/mᵢ. Node i moves by wᵢ·(J·Δt)/mᵢ: Σ mᵢ·Δdxᵢ = J·Δt·Σ wᵢ = 0,
//! so every impulse keeps the momentum of the nodes it acts on. For two
//! points (w = [1, −1]) the inelastic impulse is eq. 3.28's
//! m₁m₂vₙ/(m₁ + m₂).

use super::geometry::{Closest, Stencil, V3};

/// The pair's relative displacement Σ wᵢ dxᵢ over the step.
pub fn relative(st: &Stencil, w: &[f64; 4], dx: &[f64]) -> V3 {
    (0..4)
        .map(|i| {
            let n = st.nodes[i];
            V3::new(dx[3 * n], dx[3 * n + 1], dx[3 * n + 2]) * w[i]
        })
        .sum()
}

/// Σ wᵢ²/mᵢ: 1 / the pair's effective mass; 0 when no node can move.
pub fn inverse_mass(st: &Stencil, w: &[f64; 4], inv_mass: &[f64]) -> f64 {
    (0..4).map(|i| w[i] * w[i] * inv_mass[st.nodes[i]]).sum()
}

/// Change the pair's relative displacement by `change`, sharing it by the
/// weights and inverse masses; `k` is [`inverse_mass`]. Returns J·Δt =
/// `change`/k, J the impulse: node i takes wᵢ·J (none if it cannot move).
pub fn apply(
    st: &Stencil,
    w: &[f64; 4],
    inv_mass: &[f64],
    k: f64,
    change: V3,
    dx: &mut [f64],
) -> V3 {
    for (&n, &wi) in st.nodes.iter().zip(w) {
        let share = change * (wi * inv_mass[n] / k);
        for c in 0..3 {
            dx[3 * n + c] += share[c];
        }
    }
    change / k
}

/// The inner part of the layer, as a fraction of it ([`Repulsion::act`]):
/// a pair closer than this gets eq. 3.30's repulsion and is moved back out
/// to it; farther out, a pair's approach is only stopped. With 0.3 and
/// eq. 3.30's own rate a strip twisted on itself drifted to touching
/// (`structure-proc/tests/contact.rs`).
pub const PUSH_WITHIN: f64 = 0.5;

/// What the proximity pass needs of the scene.
#[derive(Debug, Clone, Copy)]
pub struct Repulsion {
    /// The layer kept between features [m].
    pub thickness: f64,
    /// k of eq. 3.30 [N/m].
    pub stiffness: f64,
    /// Coulomb's μ.
    pub friction: f64,
    /// The step Δt [s].
    pub dt: f64,
    /// Whether the impulse grows from nothing at the layer's edge to the
    /// whole of it at [`PUSH_WITHIN`] (the layered model), rather than
    /// stopping the approach anywhere in the layer: a pair that crosses
    /// the edge then changes the step's outcome by little, so that an
    /// implicitly coupled window's tries, which move pairs across it, can
    /// converge.
    pub ramped: bool,
}

impl Repulsion {
    /// The proximity impulse on a pair closer than the layer at the step's
    /// start (`near`, with its separation there): an inelastic part that
    /// stops the approach, the repulsion of eq. 3.30,
    /// I = min(Δt·k·d, m(0.1·d/Δt − vₙ)) for the overlap d, and Coulomb
    /// friction on the tangential motion, at most μ times the normal
    /// change (Bridson et al. 2002, §7.2).
    ///
    /// The repulsion is held to what keeps the energy. In the layer's
    /// outer part a pair's approach is only stopped (resting contact
    /// lives there; it is pushed only as far as other pairs' pushes moved
    /// it in). Closer than [`PUSH_WITHIN`] of the layer, the pair's
    /// velocity takes eq. 3.30's repulsion up to the approach just
    /// stopped, so that it parts no faster than it came, and its
    /// positions only are moved back out to [`PUSH_WITHIN`] of the layer,
    /// in `push`, a displacement that enters x^{n+1} but not v^{n+1} (the
    /// "split impulse" of Bullet Physics, Coumans; Catto 2006), so that
    /// pairs pressed together never drift to touching. Every impulse then
    /// keeps or lowers the kinetic energy of the step's average motion: one
    /// that changes the pair's relative displacement from r to r + c
    /// changes it by (|r + c|² − |r|²)/(2·Σwᵢ²/mᵢ·Δt²) ([`apply`] shares c
    /// by wᵢ/mᵢ), and here |r + c| ≤ |r| (the normal part ends at most as
    /// fast as it began, friction only shortens the tangential part), in
    /// any order. Whole, eq. 3.30 pushes resting layers apart at up to
    /// 0.1·d/Δt (metres a second for a millimetre's overlap), an energy in
    /// no account; a bounce in resting contact (the approach given back)
    /// raises the potential energy the step's end sees by about m·g·|Δx|
    /// each step. With either, `cloth-strings`' energy rose in hundreds of
    /// its windows (by up to 10⁻⁵ J), as the order of the impulses had it.
    /// Returns J·Δt of the velocity's part (zero if only `push` moved), if
    /// it acted ([`apply`]).
    pub fn act(
        &self,
        st: &Stencil,
        near: &Closest,
        inv_mass: &[f64],
        dx: &mut [f64],
        push: &mut [f64],
    ) -> Option<V3> {
        let k = inverse_mass(st, &near.w, inv_mass);
        if k == 0.0 {
            return None;
        }
        let rel = relative(st, &near.w, dx);
        let distance = near.distance();
        let n = match near.separation.try_normalize(1e-300) {
            Some(n) if distance > 1e-12 * self.thickness => n,
            // Touching: the normal that opposes the approach.
            _ => match rel.try_normalize(1e-300) {
                Some(r) => -r,
                None => return None,
            },
        };
        let d = self.thickness - distance;
        let dn = rel.dot(&n);
        let approach = (-dn).max(0.0);
        // The share of the impulse: 0 at the layer's edge, 1 from
        // PUSH_WITHIN in, when ramped; else all of it.
        let share = if self.ramped {
            (d / ((1.0 - PUSH_WITHIN) * self.thickness)).min(1.0)
        } else {
            1.0
        };
        let inelastic = share * approach;
        let after = dn + inelastic + relative(st, &near.w, push).dot(&n);
        // Eq. 3.30 in displacements: Δt·I/m = min(Δt²·k·d/m, 0.1·d − Δt·vₙ).
        let elastic = if after < 0.1 * d {
            (self.dt * self.dt * self.stiffness * d * k).min(0.1 * d - after)
        } else {
            0.0
        };
        let deep = distance < PUSH_WITHIN * self.thickness;
        let kept = if self.ramped {
            share * elastic.min(approach)
        } else if deep {
            elastic.min(inelastic)
        } else {
            0.0
        };
        // Deeper than PUSH_WITHIN of the layer: moved back out to it at
        // once, positions only.
        let out = PUSH_WITHIN * self.thickness - distance - after;
        let pushed = out > kept;
        if pushed {
            apply(st, &near.w, inv_mass, k, n * (out - kept), push);
        }
        let normal = inelastic + kept;
        if normal <= 0.0 {
            return pushed.then(V3::zeros);
        }
        let tangential = rel - n * dn;
        let slip = tangential.norm();
        let friction = if slip > 0.0 {
            tangential * (-(self.friction * normal).min(slip) / slip)
        } else {
            V3::zeros()
        };
        Some(apply(st, &near.w, inv_mass, k, n * normal + friction, dx))
    }
}

/// The inelastic collision impulse (eq. 3.28 for the pair's weights): the
/// pair's approach along `n` over the step is stopped. The part of the
/// approach that the positions-only `push` makes is taken out of `push`
/// too, so that it never becomes a velocity ([`Repulsion::act`]). Returns
/// J·Δt of the velocity's part if it acted ([`apply`]).
pub fn stop(
    st: &Stencil,
    w: &[f64; 4],
    n: &V3,
    inv_mass: &[f64],
    dx: &mut [f64],
    push: &mut [f64],
) -> Option<V3> {
    let k = inverse_mass(st, w, inv_mass);
    let dn = relative(st, w, dx).dot(n);
    if k == 0.0 || dn >= 0.0 {
        return None;
    }
    let pushed = (-relative(st, w, push).dot(n)).clamp(0.0, -dn);
    if pushed > 0.0 {
        apply(st, w, inv_mass, k, n * pushed, push);
    }
    let whole = apply(st, w, inv_mass, k, n * -dn, dx);
    Some(whole * ((-dn - pushed) / -dn))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::geometry::Kind;

    /// What the repulsion leaves of the approach of a node falling at 1 m/s
    /// onto a fixed triangle below it, started `distance` above it [m/s
    /// along the normal, after the step's impulse]; the pass pushes only
    /// pairs within the layer.
    fn speed_after(r: &Repulsion, distance: f64) -> f64 {
        if distance >= r.thickness {
            return -1.0;
        }
        let st = Stencil {
            kind: Kind::PointTriangle,
            nodes: [0, 1, 2, 3],
        };
        let near = Closest {
            w: [1.0, -1.0 / 3.0, -1.0 / 3.0, -1.0 / 3.0],
            separation: V3::new(0.0, 0.0, distance),
        };
        let inv_mass = [1e3, 0.0, 0.0, 0.0];
        let mut dx = vec![0.0; 12];
        dx[2] = -r.dt;
        let mut push = vec![0.0; 12];
        r.act(&st, &near, &inv_mass, &mut dx, &mut push);
        dx[2] / r.dt
    }

    /// The layered model's ramped repulsion changes a step's outcome
    /// continuously as a pair crosses the layer's edge and its inner half
    /// (a window's tries move pairs across both): 10⁻⁹ of the layer either
    /// side of each moves the speed after by under 10⁻⁶ of the approach,
    /// while Bridson's stops the whole approach at the edge. At the edge
    /// itself the ramped impulse is nothing, and from the inner half in it
    /// stops the approach whole, as Bridson's does.
    #[test]
    fn the_ramped_repulsion_is_continuous_across_the_layer() {
        let layer = 1e-3;
        let ramped = Repulsion {
            thickness: layer,
            stiffness: 10.0,
            friction: 0.0,
            dt: 1e-4,
            ramped: true,
        };
        let whole = Repulsion {
            ramped: false,
            ..ramped
        };
        let eps = 1e-9 * layer;
        for edge in [layer, PUSH_WITHIN * layer] {
            let jump = speed_after(&ramped, edge - eps) - speed_after(&ramped, edge + eps);
            assert!(jump.abs() < 1e-6, "{jump} m/s across {edge} m");
        }
        assert!((speed_after(&ramped, layer - eps) + 1.0).abs() < 1e-6);
        assert!(
            speed_after(&ramped, 0.6 * layer) > -1.0 && speed_after(&ramped, 0.6 * layer) < 0.0
        );
        assert!(speed_after(&ramped, 0.5 * layer - eps) >= 0.0);
        let jump = speed_after(&whole, layer - eps) - speed_after(&whole, layer + eps);
        assert!(
            jump > 0.99,
            "Bridson's stops the approach at the edge: {jump}"
        );
    }
}
