//! The Jacobian a·K + b·C of the total force (K = −∂F/∂x, C = −∂F/∂v) as
//! 3×3 blocks between nodes, for solvers that factorize it: the same
//! matrix [`crate::System::jacobian_product`] applies, element by element
//! (each element's block sits beside its product in its own file).
//! Every element gives its blocks at any state, zero ones too, so the
//! pattern is the network's and a factorization's ordering can be kept.

use super::pressure::porous_damping_block;
use crate::network::Network;
use nalgebra::Matrix3;

/// (row node, column node, block): a·K + b·C = Σ blocks.
pub type Block = (usize, usize, Matrix3<f64>);

/// A two-node element's block S as [S −S; −S S] on (i, j).
fn pair(out: &mut Vec<Block>, i: usize, j: usize, s: Matrix3<f64>) {
    out.extend([(i, i, s), (j, j, s), (i, j, -s), (j, i, -s)]);
}

/// The blocks of a·K + b·C at positions `x`, velocities `v` into `out`
/// (cleared first): springs and strings, membrane edges, dampers, the
/// porous load's resistance to motion. Gravity and the fluid's jump do
/// not depend on the state here (as in the product).
pub fn blocks(m: &Network, x: &[f64], v: &[f64], a: f64, b: f64, out: &mut Vec<Block>) {
    out.clear();
    for s in &m.springs {
        pair(out, s.i, s.j, s.stiffness_block(x, a));
    }
    for t in &m.membrane {
        // Edge e runs from vertex EDGES[e].0 (sign +1) to EDGES[e].1 (−1):
        // the edges' blocks summed into the 9 vertex pairs of the triangle.
        let g = t.stiffness_blocks(x, a);
        let mut v = [[Matrix3::zeros(); 3]; 3];
        for (k, gk) in g.iter().enumerate() {
            for (f, &gkf) in gk.iter().enumerate() {
                for (p, sp) in [(k, 1.0), ((k + 1) % 3, -1.0)] {
                    for (q, sq) in [(f, 1.0), ((f + 1) % 3, -1.0)] {
                        v[p][q] += gkf * (sp * sq);
                    }
                }
            }
        }
        for (p, vp) in v.iter().enumerate() {
            out.extend(
                vp.iter()
                    .enumerate()
                    .map(|(q, &b)| (t.nodes[p], t.nodes[q], b)),
            );
        }
    }
    if let Some(law) = m.damping {
        for d in &m.dampers {
            pair(out, d.i, d.j, d.damping_block(law, x, b));
        }
    }
    if let Some(law) = &m.porous {
        for tri in &m.triangles {
            let s = porous_damping_block(law, x, v, tri, b);
            for &i in tri {
                out.extend(tri.iter().map(|&j| (i, j, s)));
            }
        }
    }
}
