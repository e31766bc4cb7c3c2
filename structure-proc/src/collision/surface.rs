//! What collides in the structure: the fabric's triangles and the strings'
//! segments (the dissertation §3.4: "a string is represented by a group of
//! connected edges"), and which elementary tests a pair of them needs.
//!
//! A triangle pair needs fifteen tests (each point of one against the other,
//! each edge of one against each edge of the other), a segment–triangle pair
//! five, a segment pair one. Neighbouring triangles share points and edges,
//! so every point and every edge is owned by one primitive, the first that
//! has it, and a primitive pair tests only what its two members own: each
//! elementary test is then made once, whichever primitive pair brings it.
//! Features that share a node are never tested (they touch by construction).

use super::geometry::{Kind, Stencil};
use crate::network::Network;

/// The fabric's triangles, then the strings' segments, as primitives.
#[derive(Debug, Clone, Default)]
pub struct Surface {
    /// Nodes of primitive p: three for a triangle (p < `triangles`), two
    /// for a segment (the third entry repeats the second).
    pub nodes: Vec<[usize; 3]>,
    /// How many of the primitives are triangles.
    pub triangles: usize,
    /// The bodies' triangles are the primitives from here to `triangles`.
    bodies_from: usize,
    /// Points each primitive owns: `points[point_start[p]..point_start[p + 1]]`.
    points: Vec<usize>,
    point_start: Vec<usize>,
    /// Edges each primitive owns, in the same layout.
    edges: Vec<[usize; 2]>,
    edge_start: Vec<usize>,
}

/// The strings' segments of `net`: springs with an end beyond the canopy's
/// nodes (suspension lines, hand-built strings), each node pair once; a
/// broken spring (k = 0) is none.
pub fn segments(net: &Network) -> impl Iterator<Item = (usize, usize)> + '_ {
    let mut seen = std::collections::HashSet::new();
    net.springs.iter().filter_map(move |s| {
        let key = (s.i.min(s.j), s.i.max(s.j));
        let string = s.i >= net.canopy_nodes || s.j >= net.canopy_nodes;
        (string && s.k > 0.0 && s.i != s.j && seen.insert(key)).then_some((s.i, s.j))
    })
}

impl Surface {
    /// The network's canopy triangles and the springs that are strings (an
    /// end beyond the canopy's nodes: suspension lines, hand-built strings);
    /// a broken spring (k = 0) is no longer a segment.
    pub fn of(net: &Network) -> Surface {
        Surface::with_fixed(net, &[])
    }

    /// [`Surface::of`] with `fixed` triangles too, over nodes numbered
    /// after the network's: the surfaces of static bodies.
    pub fn with_fixed(net: &Network, fixed: &[[usize; 3]]) -> Surface {
        let mut nodes: Vec<[usize; 3]> = net.triangles.clone();
        nodes.extend_from_slice(fixed);
        let triangles = nodes.len();
        nodes.extend(segments(net).map(|(i, j)| [i, j, j]));
        let mut surface = Surface {
            nodes,
            triangles,
            bodies_from: net.triangles.len(),
            ..Surface::default()
        };
        let fixed_nodes = fixed.iter().flatten().map(|&n| n + 1).max().unwrap_or(0);
        surface.own(net.nodes().max(fixed_nodes));
        surface
    }

    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    pub fn is_triangle(&self, p: usize) -> bool {
        p < self.triangles
    }

    /// Whether primitive p is a body's: two of them never need a test (no
    /// impulse moves a body's points).
    pub fn is_body(&self, p: usize) -> bool {
        (self.bodies_from..self.triangles).contains(&p)
    }

    /// The nodes of primitive p: three or two.
    pub fn vertices(&self, p: usize) -> &[usize] {
        let n = if self.is_triangle(p) { 3 } else { 2 };
        &self.nodes[p][..n]
    }

    /// Give every point and edge to the first primitive that has it.
    fn own(&mut self, node_count: usize) {
        let mut point_taken = vec![false; node_count];
        let mut edge_taken = std::collections::HashSet::new();
        self.point_start.push(0);
        self.edge_start.push(0);
        for p in 0..self.len() {
            let v: Vec<usize> = self.vertices(p).to_vec();
            for &n in &v {
                if !point_taken[n] {
                    point_taken[n] = true;
                    self.points.push(n);
                }
            }
            let pairs: &[(usize, usize)] = if v.len() == 3 {
                &[(0, 1), (1, 2), (2, 0)]
            } else {
                &[(0, 1)]
            };
            for &(a, b) in pairs {
                if edge_taken.insert((v[a].min(v[b]), v[a].max(v[b]))) {
                    self.edges.push([v[a], v[b]]);
                }
            }
            self.point_start.push(self.points.len());
            self.edge_start.push(self.edges.len());
        }
    }

    fn owned_points(&self, p: usize) -> &[usize] {
        &self.points[self.point_start[p]..self.point_start[p + 1]]
    }

    fn owned_edges(&self, p: usize) -> &[[usize; 2]] {
        &self.edges[self.edge_start[p]..self.edge_start[p + 1]]
    }

    /// The elementary tests the primitive pair p, q (p ≠ q) brings, each
    /// given to `visit`.
    #[inline]
    pub fn each_stencil(&self, p: usize, q: usize, mut visit: impl FnMut(Stencil)) {
        for (a, b) in [(p, q), (q, p)] {
            if !self.is_triangle(b) {
                continue;
            }
            let [t0, t1, t2] = self.nodes[b];
            for &n in self.owned_points(a) {
                if n != t0 && n != t1 && n != t2 {
                    visit(Stencil {
                        kind: Kind::PointTriangle,
                        nodes: [n, t0, t1, t2],
                    });
                }
            }
        }
        for &[a0, a1] in self.owned_edges(p) {
            for &[b0, b1] in self.owned_edges(q) {
                if a0 != b0 && a0 != b1 && a1 != b0 && a1 != b1 {
                    visit(Stencil {
                        kind: Kind::EdgeEdge,
                        nodes: [a0, a1, b0, b1],
                    });
                }
            }
        }
    }
}
