//! The annulus canopy of seed 003 §2.2 and §3.2: a flat ring R_int ≤ r ≤ R_ext
//! with the outer rim fixed.
//!
//! The seed meshed it with distmesh (703 nodes, 1280 triangles). Here nodes sit
//! on concentric rings with a count proportional to the radius, so every
//! triangle has about the same size, and neighbouring rings are stitched by
//! merging their nodes in angle order. With the defaults (12 rings, 107 nodes
//! on the rim) that gives 705 nodes and 1292 triangles.

use std::f64::consts::PI;

pub struct AnnulusMesh {
    /// xyz per node.
    pub points: Vec<f64>,
    /// Counter-clockwise seen from +z, so every normal points along +z.
    pub triangles: Vec<[usize; 3]>,
    /// Nodes on the outer rim.
    pub rim: Vec<usize>,
    /// Nodes on the inner (vent) edge.
    pub inner: Vec<usize>,
}

#[derive(Debug, thiserror::Error)]
#[error("annulus mesh: {0}")]
pub struct MeshError(pub String);

pub fn annulus(
    r_in: f64,
    r_out: f64,
    rings: usize,
    outer_nodes: usize,
    z: f64,
) -> Result<AnnulusMesh, MeshError> {
    let mut points = Vec::new();
    let mut ring_start = Vec::new();
    let mut ring_len = Vec::new();
    let mut ring_phase = Vec::new();
    for i in 0..rings {
        let r = r_in + (r_out - r_in) * i as f64 / (rings - 1) as f64;
        let n = ((outer_nodes as f64 * r / r_out).round() as usize).max(6);
        // Alternate rings are rotated by half a spacing so the strips stay well shaped.
        let phase = if i % 2 == 1 { PI / n as f64 } else { 0.0 };
        ring_start.push(points.len() / 3);
        ring_len.push(n);
        ring_phase.push(phase);
        for k in 0..n {
            let th = phase + 2.0 * PI * k as f64 / n as f64;
            points.extend_from_slice(&[r * th.cos(), r * th.sin(), z]);
        }
    }
    let mut triangles = Vec::new();
    for i in 0..rings - 1 {
        let (sa, na, pa) = (ring_start[i], ring_len[i], ring_phase[i]);
        let (sb, nb, pb) = (ring_start[i + 1], ring_len[i + 1], ring_phase[i + 1]);
        let ang = |phase: f64, n: usize, k: usize| phase + 2.0 * PI * k as f64 / n as f64;
        let (mut ia, mut ib) = (0usize, 0usize);
        while ia < na || ib < nb {
            let next_a = ang(pa, na, ia + 1);
            let next_b = ang(pb, nb, ib + 1);
            let a0 = sa + ia % na;
            let b0 = sb + ib % nb;
            let tri = if ib == nb || (ia < na && next_a <= next_b) {
                ia += 1;
                [a0, sa + ia % na, b0]
            } else {
                ib += 1;
                [a0, sb + ib % nb, b0]
            };
            triangles.push(tri);
        }
    }
    for tri in &mut triangles {
        let n = crate::forces::area_normal2(&points, tri);
        if n[2] < 0.0 {
            tri.swap(1, 2);
        }
        let area = 0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        if area <= 1e-12 * r_out * r_out {
            return Err(MeshError(format!(
                "degenerate triangle {tri:?} (area {area:e} m²)"
            )));
        }
    }
    let last = rings - 1;
    Ok(AnnulusMesh {
        rim: (ring_start[last]..ring_start[last] + ring_len[last]).collect(),
        inner: (0..ring_len[0]).collect(),
        points,
        triangles,
    })
}
