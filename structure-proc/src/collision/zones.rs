//! Rigid impact zones, the fail-safe (Provot 1997; Bridson, Fedkiw &
//! Anderson 2002, §7.4; the dissertation §2.5): nodes still colliding after
//! the impulse passes are merged into zones, and each zone moves over the
//! step as one rigid body with the linear and angular momentum of its
//! nodes. Zones grow until no collision is left.
//!
//! The zone's motion is the linearised rigid one, dxᵢ = dx_c + ω × rᵢ with
//! rᵢ from the zone's centre of mass at the step's start: an affine map of
//! the start positions at every moment s of the step, I + s[ω]×, whose
//! determinant 1 + s²|ω|² never vanishes: a zone's own features, apart at
//! the start, stay apart. A
//! zone with a node that cannot move (fixed, or carried by a rigid body)
//! moves with those nodes' mean displacement instead: it takes the
//! support's motion, and the support takes the momentum.

use super::geometry::V3;
use nalgebra::Matrix3;

/// Disjoint sets of nodes (union by size, path halving).
#[derive(Debug, Clone)]
pub struct Zones {
    parent: Vec<usize>,
    size: Vec<usize>,
}

impl Zones {
    pub fn new(nodes: usize) -> Zones {
        Zones {
            parent: (0..nodes).collect(),
            size: vec![1; nodes],
        }
    }

    pub fn root(&mut self, mut n: usize) -> usize {
        while self.parent[n] != n {
            self.parent[n] = self.parent[self.parent[n]];
            n = self.parent[n];
        }
        n
    }

    /// Put a and b in one zone; true if they were apart.
    pub fn join(&mut self, a: usize, b: usize) -> bool {
        let (mut a, mut b) = (self.root(a), self.root(b));
        if a == b {
            return false;
        }
        if self.size[a] < self.size[b] {
            std::mem::swap(&mut a, &mut b);
        }
        self.parent[b] = a;
        self.size[a] += self.size[b];
        true
    }

    /// The zones of more than one node, each as its nodes in ascending order.
    pub fn groups(&mut self) -> Vec<Vec<usize>> {
        let mut by_root: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
        for n in 0..self.parent.len() {
            let r = self.root(n);
            if self.size[r] > 1 {
                by_root.entry(r).or_default().push(n);
            }
        }
        by_root.into_values().collect()
    }
}

/// Move the nodes of `zone` as one rigid body over the step: from the start
/// positions `x`, displacements `dx` (both xyz per node) and masses.
pub fn rigidify(zone: &[usize], x: &[f64], dx: &mut [f64], mass: &[f64], inv_mass: &[f64]) {
    let at = |a: &[f64], n: usize| V3::new(a[3 * n], a[3 * n + 1], a[3 * n + 2]);
    let held: Vec<usize> = zone
        .iter()
        .copied()
        .filter(|&n| inv_mass[n] == 0.0)
        .collect();
    let set = |dx: &mut [f64], n: usize, d: V3| {
        for c in 0..3 {
            dx[3 * n + c] = d[c];
        }
    };
    if !held.is_empty() {
        let d = held.iter().map(|&n| at(dx, n)).sum::<V3>() / held.len() as f64;
        for &n in zone.iter().filter(|&&n| inv_mass[n] > 0.0) {
            set(dx, n, d);
        }
        return;
    }
    let total: f64 = zone.iter().map(|&n| mass[n]).sum();
    let centre = zone.iter().map(|&n| at(x, n) * mass[n]).sum::<V3>() / total;
    let shift = zone.iter().map(|&n| at(dx, n) * mass[n]).sum::<V3>() / total;
    let mut spin = V3::zeros();
    let mut inertia = Matrix3::zeros();
    for &n in zone {
        let r = at(x, n) - centre;
        spin += r.cross(&(at(dx, n) - shift)) * mass[n];
        inertia += (Matrix3::identity() * r.norm_squared() - r * r.transpose()) * mass[n];
    }
    // Nodes on a line have no inertia about it: the pseudo-inverse leaves
    // that turn out, as it has no momentum either.
    let omega = inertia
        .pseudo_inverse(1e-12 * inertia.norm())
        .map(|inv| inv * spin)
        .unwrap_or_else(|_| V3::zeros());
    for &n in zone {
        let r = at(x, n) - centre;
        set(dx, n, shift + omega.cross(&r));
    }
}
