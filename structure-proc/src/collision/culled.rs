//! The triangles of the regions the tree skipped as smooth, watched while
//! the candidates are held. The tree skips a connected region whose normals
//! all point at least [`FACING_MARGIN`] into one hemisphere (`tree.rs`);
//! the pairs within it are never found, so the held candidates stay valid
//! only while that remains so. Each triangle is allowed the turn that
//! keeps its normal that far inside its region's hemisphere (the normal's
//! angle above the hemisphere's edge at the search, less the margin), so
//! a test of the region anew would still skip it; a triangle that may have
//! turned more has the candidates found anew.

use super::geometry::V3;
use super::surface::Surface;
use super::tree::{Tree, FACING_MARGIN, NO_REGION};

/// A triangle of a skipped region as it stood at the search: its nodes,
/// its edges e₁, e₂ from its first node, and the square of how far those
/// edges may change before its normal may have turned by its allowance α.
/// With its edges changed by Δe₁, Δe₂, its normal e₁ × e₂ changed by at
/// most |Δe₁||e₂| + |e₁||Δe₂| + |Δe₁||Δe₂| ≤ d(|e₁| + |e₂|) + d²,
/// d = max |Δeᵢ|, and it turned by less than α while that stays below
/// sin α·|e₁ × e₂|. A triangle moving without turning (a falling cloth)
/// has Δe = 0.
#[derive(Debug, Clone)]
pub struct Culled {
    nodes: [u32; 3],
    e1: V3,
    e2: V3,
    reach2: f64,
}

impl Culled {
    /// The triangle of `nodes` standing at `x`, allowed to turn by the
    /// angle whose sine is `allowed`.
    fn new(nodes: [usize; 3], x: &[f64], allowed: f64) -> Culled {
        let (e1, e2) = edges(nodes, x);
        let b = e1.norm() + e2.norm();
        let t = allowed * e1.cross(&e2).norm();
        let reach = 0.5 * ((b * b + 4.0 * t).sqrt() - b);
        Culled {
            nodes: nodes.map(|n| n as u32),
            e1,
            e2,
            reach2: reach * reach,
        }
    }

    /// Whether its normal may have turned by its allowance with its nodes
    /// at `x` or at `x + dx` (its edges change linearly in between).
    pub fn may_have_turned(&self, x: &[f64], dx: &[f64]) -> bool {
        let [a, b, c] = self.nodes.map(|n| 3 * n as usize);
        let mut most: f64 = 0.0;
        for s in [0.0, 1.0] {
            let (mut d1, mut d2) = (0.0, 0.0);
            for k in 0..3 {
                let p = |i: usize| x[i + k] + s * dx[i + k];
                let f1 = p(b) - p(a) - self.e1[k];
                let f2 = p(c) - p(a) - self.e2[k];
                d1 += f1 * f1;
                d2 += f2 * f2;
            }
            most = most.max(d1).max(d2);
        }
        most >= self.reach2
    }
}

/// A triangle's edges from its first node at `x`.
fn edges(nodes: [usize; 3], x: &[f64]) -> (V3, V3) {
    let at = |n: usize| V3::new(x[3 * n], x[3 * n + 1], x[3 * n + 2]);
    (at(nodes[1]) - at(nodes[0]), at(nodes[2]) - at(nodes[0]))
}

/// The triangles of `s` in the regions of `tree` (`region`, from
/// [`Tree::regions`]) standing at `x`, each with its allowance: its
/// region's hemisphere is the one of the region's directions nearest the
/// region's summed normal, and its normal n̂ points into it by the angle
/// asin(n̂·d̂), more than the margin (the tree tested it so).
pub fn culled(tree: &Tree, s: &Surface, region: &[usize], x: &[f64]) -> Vec<Culled> {
    // Each skipped triangle with its normal at `x`, computed once.
    let normals: Vec<(usize, V3)> = (0..region.len())
        .filter(|&p| region[p] != NO_REGION)
        .map(|p| {
            let (e1, e2) = edges(s.nodes[p], x);
            (p, e1.cross(&e2))
        })
        .collect();
    let mut summed = std::collections::BTreeMap::<usize, V3>::new();
    for (p, n) in &normals {
        *summed.entry(region[*p]).or_insert_with(V3::zeros) += n;
    }
    let hemisphere: std::collections::BTreeMap<usize, V3> = summed
        .into_iter()
        .map(|(r, sum)| {
            let along = |d: &V3| d.dot(&sum);
            let best = tree
                .directions(r)
                .max_by(|a, b| along(a).total_cmp(&along(b)));
            (r, best.expect("a skipped region faces a direction"))
        })
        .collect();
    let allowed = |n: &V3, d: &V3| {
        let inside = n.try_normalize(1e-300).map_or(0.0, |n| n.dot(d));
        (inside.clamp(-1.0, 1.0).asin() - FACING_MARGIN)
            .max(0.0)
            .sin()
    };
    normals
        .iter()
        .map(|(p, n)| Culled::new(s.nodes[*p], x, allowed(n, &hemisphere[&region[*p]])))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A triangle allowed 30° is flagged once turned by 30° about any of
    /// its edges or its normal's tilt axes, and never while it only
    /// translates.
    #[test]
    fn a_turn_by_the_allowance_is_caught_and_a_translation_is_not() {
        let x = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.2, 0.7, 0.0];
        let allowed = 30f64.to_radians();
        let t = Culled::new([0, 1, 2], &x, allowed.sin());
        let still = [0.0; 9];
        let shift: Vec<f64> = (0..9).map(|i| [0.3, -2.0, 5.0][i % 3]).collect();
        assert!(!t.may_have_turned(&x, &still));
        assert!(!t.may_have_turned(&x, &shift));
        for axis in [
            V3::x(),
            V3::y(),
            V3::new(1.0, 1.0, 0.0),
            V3::new(0.2, 0.7, 0.0),
        ] {
            let r = nalgebra::Rotation3::new(axis.normalize() * allowed);
            let turned: Vec<f64> = x
                .chunks(3)
                .flat_map(|p| {
                    let q = r * V3::new(p[0], p[1], p[2]);
                    [q.x - p[0], q.y - p[1], q.z - p[2]]
                })
                .collect();
            assert!(t.may_have_turned(&x, &turned), "turned about {axis:?}");
            let moved: Vec<f64> = x.iter().zip(&turned).map(|(a, b)| a + b).collect();
            assert!(
                t.may_have_turned(&moved, &still),
                "turned about {axis:?}, at the start"
            );
        }
    }
}
