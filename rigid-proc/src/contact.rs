//! Rigid–rigid contact with a coefficient of restitution (dissertation §3.4).
//!
//! parry finds the contact patches; each patch gets one impulse along its
//! normal at the patch's centroid. For two bodies meeting head on, the
//! impulse is the dissertation's inelastic part I_in = m₁m₂vₙ/(m₁+m₂) (eq. 3.28) plus
//! the elastic part C_R·I_in (eq. 3.31); off the line of centres the general
//! rigid-body form adds the rotational terms, j = −(1+C_R)vₙ / (1/m_a + 1/m_b
//! + n·[(I_a⁻¹(r_a×n))×r_a + (I_b⁻¹(r_b×n))×r_b]), which reduces to it there.
//!
//! Contacts are found at the start of each impulse sub-step and resolved
//! there when the gap would close within the sub-step at the present
//! approach speed, so bodies never pass through each other; an impact is
//! taken up to one sub-step early, a position error of at most vₙ·h.

use exchange::Body;
use nalgebra::Vector3;
use parry3d_f64::query::{ContactManifold, DefaultQueryDispatcher, PersistentQueryDispatcher};

/// Passes over the contacts of one sub-step, for impulses that set other
/// contacts approaching again.
const SWEEPS: usize = 16;

/// One contact patch between bodies `a` and `b`.
#[derive(Debug, Clone, PartialEq)]
pub struct Contact {
    pub a: usize,
    pub b: usize,
    /// Centroid of the patch [m].
    pub point: Vector3<f64>,
    /// Unit normal from `a` towards `b`.
    pub normal: Vector3<f64>,
    /// Separation [m], negative when they overlap.
    pub gap: f64,
}

/// The contact patches between shaped bodies that may touch within `h`.
pub fn detect(bodies: &[Body], h: f64) -> Vec<Contact> {
    let dispatcher = DefaultQueryDispatcher;
    let mut found = Vec::new();
    for a in 0..bodies.len() {
        for b in a + 1..bodies.len() {
            let (ba, bb) = (&bodies[a], &bodies[b]);
            let (Some(sa), Some(sb)) = (&ba.shape, &bb.shape) else {
                continue;
            };
            if ba.inv_mass() == 0.0 && bb.inv_mass() == 0.0 {
                continue;
            }
            let reach = |body: &Body, r: f64| body.state.v.norm() + body.state.w.norm() * r;
            let prediction =
                (reach(ba, sa.bounding_radius()) + reach(bb, sb.bounding_radius())) * h;
            let (pa, pb) = (ba.shape_pose(), bb.shape_pose());
            let mut manifolds: Vec<ContactManifold<(), ()>> = Vec::new();
            let pos12 = pa.inv_mul(&pb);
            if dispatcher
                .contact_manifolds(
                    &pos12,
                    &*sa.shape,
                    &*sb.shape,
                    prediction,
                    &mut manifolds,
                    &mut None,
                )
                .is_err()
            {
                continue;
            }
            for m in manifolds.iter().filter(|m| !m.points.is_empty()) {
                let sub1 = pa * m.subshape_pos1.unwrap_or_default();
                let sub2 = pb * m.subshape_pos2.unwrap_or_default();
                let n = (sub1 * m.local_n1).normalize();
                let mut point = Vector3::zeros();
                let mut gap = f64::INFINITY;
                for p in &m.points {
                    point += ((sub1 * p.local_p1).coords + (sub2 * p.local_p2).coords) / 2.0;
                    gap = gap.min(p.dist);
                }
                found.push(Contact {
                    a,
                    b,
                    point: point / m.points.len() as f64,
                    normal: n,
                    gap,
                });
            }
        }
    }
    found
}

/// Apply the restitution impulses of the contacts that close within `h`;
/// `restitution(a, b)` gives each pair's C_R. Returns the impulses applied.
pub fn resolve(
    bodies: &mut [Body],
    contacts: &[Contact],
    restitution: impl Fn(usize, usize) -> f64,
    h: f64,
) -> usize {
    let mut applied = 0;
    for _ in 0..SWEEPS {
        let mut any = false;
        for c in contacts {
            let (a, b) = (&bodies[c.a], &bodies[c.b]);
            let vn = (b.velocity_at(&c.point) - a.velocity_at(&c.point)).dot(&c.normal);
            // Separating, or still apart at the end of the sub-step.
            if vn >= 0.0 || c.gap + vn * h > 0.0 {
                continue;
            }
            let n = c.normal;
            let k = a.inv_effective_mass(&c.point, &n) + b.inv_effective_mass(&c.point, &n);
            if k <= 0.0 {
                continue;
            }
            let j = n * (-(1.0 + restitution(c.a, c.b)) * vn / k);
            bodies[c.a].apply_impulse(&c.point, &-j);
            bodies[c.b].apply_impulse(&c.point, &j);
            applied += 1;
            any = true;
        }
        if !any {
            break;
        }
    }
    applied
}
