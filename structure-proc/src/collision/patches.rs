//! Patches of the surface for the layered contact model (`layered.rs`):
//! the primitives cut into small pieces that hang together on the mesh,
//! so that the nodes of a patch move nearly as one over a step and a box
//! over their motions bounds every pair the patch takes part in.
//!
//! A patch is grown breadth-first over primitives that share a node, from
//! the lowest-numbered primitive not yet taken, up to [`PATCH_SIZE`]
//! primitives of one class (the fabric's triangles, the bodies' triangles,
//! the strings' segments): it depends on the mesh alone, never on the
//! positions, so a run and its restart cut the same patches. Two patches
//! make a group; the group of a candidate pair is that of the primitives
//! that brought it (`candidates.rs`), whose nodes its two features are.

use super::surface::Surface;
use super::sweep::Aabb;
use std::collections::VecDeque;

/// Primitives in a patch: about a 3 × 3 cell piece of a triangle mesh, or
/// sixteen segments of a string. Fewer make more groups to bound; more
/// make looser bounds on a patch that bends.
pub const PATCH_SIZE: usize = 16;

/// The surface's patches and the nodes of each.
#[derive(Debug, Clone, Default)]
pub struct Patches {
    /// Nodes of patch k: `nodes[start[k]..start[k + 1]]`, every node of
    /// every primitive in it, each once.
    nodes: Vec<u32>,
    start: Vec<usize>,
    /// Primitives of patch k, in order: `members[member_start[k]..member_start[k + 1]]`.
    members: Vec<u32>,
    member_start: Vec<usize>,
    /// Each node's triangles, lowest first: `triangles[tri_start[n]..tri_start[n + 1]]`.
    triangles: Vec<u32>,
    tri_start: Vec<usize>,
}

impl Patches {
    /// The patches of `surface`, over `nodes` nodes and body points.
    pub fn new(surface: &Surface, nodes: usize) -> Patches {
        let (prims, prim_start) = by_node(surface, nodes, |_| true);
        let class = |p: usize| (surface.is_triangle(p), surface.is_body(p));
        let mut of_primitive = vec![u32::MAX; surface.len()];
        let mut count = 0u32;
        let mut queue = VecDeque::new();
        for seed in 0..surface.len() {
            if of_primitive[seed] != u32::MAX {
                continue;
            }
            let mut taken = 0;
            of_primitive[seed] = count;
            queue.clear();
            queue.push_back(seed);
            'grow: while let Some(p) = queue.pop_front() {
                taken += 1;
                if taken == PATCH_SIZE {
                    break;
                }
                for &n in surface.vertices(p) {
                    for &q in &prims[prim_start[n]..prim_start[n + 1]] {
                        let q = q as usize;
                        if of_primitive[q] == u32::MAX && class(q) == class(p) {
                            of_primitive[q] = count;
                            queue.push_back(q);
                            if taken + queue.len() == PATCH_SIZE {
                                break 'grow;
                            }
                        }
                    }
                }
            }
            count += 1;
        }
        let mut of_patch: Vec<Vec<u32>> = vec![Vec::new(); count as usize];
        let mut prims: Vec<Vec<u32>> = vec![Vec::new(); count as usize];
        for (p, &k) in of_primitive.iter().enumerate() {
            let k = k as usize;
            of_patch[k].extend(surface.vertices(p).iter().map(|&n| n as u32));
            prims[k].push(p as u32);
        }
        let mut start = vec![0];
        let mut flat = Vec::new();
        for mut m in of_patch {
            m.sort_unstable();
            m.dedup();
            flat.extend(m);
            start.push(flat.len());
        }
        let member_start = std::iter::once(0)
            .chain(prims.iter().scan(0, |a, m| {
                *a += m.len();
                Some(*a)
            }))
            .collect();
        let (triangles, tri_start) = by_node(surface, nodes, |p| surface.is_triangle(p));
        Patches {
            nodes: flat,
            start,
            members: prims.concat(),
            member_start,
            triangles,
            tri_start,
        }
    }

    /// How many patches there are.
    pub fn len(&self) -> usize {
        self.start.len() - 1
    }

    /// The primitives of patch k, in order.
    pub fn primitives(&self, k: usize) -> impl Iterator<Item = usize> + '_ {
        self.members[self.member_start[k]..self.member_start[k + 1]]
            .iter()
            .map(|&p| p as usize)
    }

    /// Each patch's box over its nodes' values in `dx` (xyz per node):
    /// their positions, or their motions.
    pub fn boxes(&self, dx: &[f64]) -> Vec<Aabb> {
        (0..self.len())
            .map(|k| {
                let mut b = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
                for &n in &self.nodes[self.start[k]..self.start[k + 1]] {
                    let n = n as usize;
                    for c in 0..3 {
                        b.0[c] = b.0[c].min(dx[3 * n + c]);
                        b.1[c] = b.1[c].max(dx[3 * n + c]);
                    }
                }
                b
            })
            .collect()
    }

    /// The lowest-numbered triangle with node n, and those with both n
    /// and m: the primitive that owns a point, and an edge (`surface.rs`
    /// gives each to the first primitive that has it).
    pub fn first_triangle(&self, n: usize, m: Option<usize>) -> Option<usize> {
        let around = &self.triangles[self.tri_start[n]..self.tri_start[n + 1]];
        match m {
            None => around.first().map(|&t| t as usize),
            Some(m) => {
                let others = &self.triangles[self.tri_start[m]..self.tri_start[m + 1]];
                around
                    .iter()
                    .find(|t| others.contains(t))
                    .map(|&t| t as usize)
            }
        }
    }
}

/// How far any node moving within box `a` can come closer to any moving
/// within box `b`: the largest length of a difference of two points of
/// the boxes.
#[inline]
pub fn approach(a: &Aabb, b: &Aabb) -> f64 {
    (0..3)
        .map(|c| {
            let most = (a.1[c] - b.0[c]).abs().max((b.1[c] - a.0[c]).abs());
            most * most
        })
        .sum::<f64>()
        .sqrt()
}

/// Each node's primitives that `keep` keeps, lowest first, as a list and
/// its starts.
fn by_node(
    surface: &Surface,
    nodes: usize,
    keep: impl Fn(usize) -> bool,
) -> (Vec<u32>, Vec<usize>) {
    let mut count = vec![0usize; nodes + 1];
    for p in (0..surface.len()).filter(|&p| keep(p)) {
        for &n in surface.vertices(p) {
            count[n + 1] += 1;
        }
    }
    for n in 0..nodes {
        count[n + 1] += count[n];
    }
    let mut fill = count.clone();
    let mut list = vec![0u32; count[nodes]];
    for p in (0..surface.len()).filter(|&p| keep(p)) {
        for &n in surface.vertices(p) {
            list[fill[n]] = p as u32;
            fill[n] += 1;
        }
    }
    (list, count)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::network::Network;

    #[test]
    fn a_cloth_is_cut_into_connected_patches_of_sixteen_triangles() {
        let n = 21;
        let m = crate::rectangle::rectangle(1.0, 1.0, n, n, [0.0; 3]);
        let net = Network {
            mass: vec![1.0; n * n],
            inv_mass: vec![1.0; n * n],
            triangles: m.triangles.clone(),
            canopy_nodes: n * n,
            ..Network::default()
        };
        let s = Surface::of(&net);
        let p = Patches::new(&s, n * n);
        let sizes: Vec<usize> = (0..p.len()).map(|k| p.primitives(k).count()).collect();
        // Every primitive in one patch, none above the size; most full.
        let mut all: Vec<usize> = (0..p.len()).flat_map(|k| p.primitives(k)).collect();
        all.sort_unstable();
        assert_eq!(all, (0..s.len()).collect::<Vec<_>>());
        assert!(sizes.iter().all(|&z| (1..=PATCH_SIZE).contains(&z)));
        let full = sizes.iter().filter(|&&z| z == PATCH_SIZE).count();
        assert!(full * 10 >= p.len() * 7, "{full} of {} full", p.len());
        // A patch is compact: its nodes span a few cells, not a row.
        let cell = 1.0 / (n - 1) as f64;
        for k in 0..p.len() {
            let b = p.boxes(&m.points);
            let span = (b[k].1[0] - b[k].0[0]).max(b[k].1[1] - b[k].0[1]);
            assert!(span <= 6.0 * cell + 1e-12, "patch {k} spans {span}");
        }
        // The owner of a point and of an edge is the lowest triangle with it.
        let t0 = s.nodes[0];
        assert_eq!(p.first_triangle(t0[0], None), Some(0));
        assert_eq!(p.first_triangle(t0[0], Some(t0[1])), Some(0));
    }
}
