//! Flat meshes of concentric node rings, stitched ring to ring in angle order:
//! the annulus canopy and the circular parachute canopies are both made of them.

use crate::forces::area_normal2;
use std::f64::consts::PI;

#[derive(Debug, thiserror::Error)]
#[error("mesh: {0}")]
pub struct MeshError(pub String);

/// One ring: `nodes` nodes at `radius`, the first at angle `phase`.
#[derive(Debug, Clone, Copy)]
pub struct Ring {
    pub radius: f64,
    pub nodes: usize,
    pub phase: f64,
}

pub struct RingMesh {
    /// xyz per node: an optional centre node, then ring after ring.
    pub points: Vec<f64>,
    /// Counter-clockwise seen from +z.
    pub triangles: Vec<[usize; 3]>,
    /// First node of each ring.
    pub ring_start: Vec<usize>,
}

impl Ring {
    fn angle(&self, k: usize) -> f64 {
        self.phase + 2.0 * PI * k as f64 / self.nodes as f64
    }
}

/// Mesh `rings` (radii increasing) in the plane z = `z`; with `centre`, a node at
/// the origin is fanned to the first ring.
pub fn ring_mesh(rings: &[Ring], z: f64, centre: bool) -> Result<RingMesh, MeshError> {
    let mut points = Vec::new();
    if centre {
        points.extend_from_slice(&[0.0, 0.0, z]);
    }
    let mut ring_start = Vec::new();
    for ring in rings {
        ring_start.push(points.len() / 3);
        for k in 0..ring.nodes {
            let th = ring.angle(k);
            points.extend_from_slice(&[ring.radius * th.cos(), ring.radius * th.sin(), z]);
        }
    }
    let mut triangles = Vec::new();
    if centre {
        let (s, n) = (ring_start[0], rings[0].nodes);
        triangles.extend((0..n).map(|k| [0, s + k, s + (k + 1) % n]));
    }
    for i in 0..rings.len() - 1 {
        let (a, b) = (&rings[i], &rings[i + 1]);
        let (sa, sb) = (ring_start[i], ring_start[i + 1]);
        let (mut ia, mut ib) = (0usize, 0usize);
        while ia < a.nodes || ib < b.nodes {
            let a0 = sa + ia % a.nodes;
            let b0 = sb + ib % b.nodes;
            let tri = if ib == b.nodes || (ia < a.nodes && a.angle(ia + 1) <= b.angle(ib + 1)) {
                ia += 1;
                [a0, sa + ia % a.nodes, b0]
            } else {
                ib += 1;
                [a0, sb + ib % b.nodes, b0]
            };
            triangles.push(tri);
        }
    }
    let outer = rings.last().map_or(1.0, |r| r.radius);
    for tri in &mut triangles {
        let n = area_normal2(&points, tri);
        if n[2] < 0.0 {
            tri.swap(1, 2);
        }
        let area = 0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        if area <= 1e-12 * outer * outer {
            return Err(MeshError(format!(
                "degenerate triangle {tri:?} (area {area:e} m²)"
            )));
        }
    }
    Ok(RingMesh {
        points,
        triangles,
        ring_start,
    })
}
