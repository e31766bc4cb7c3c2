//! The annulus canopy of thesis §2.2 and §3.2: a flat ring R_int ≤ r ≤ R_ext
//! with the outer rim fixed.
//!
//! The seed meshed it with distmesh (703 nodes, 1280 triangles). Here nodes sit
//! on concentric rings with a count proportional to the radius, so every
//! triangle has about the same size, and neighbouring rings are stitched by
//! merging their nodes in angle order. With the defaults (12 rings, 107 nodes
//! on the rim) that gives 705 nodes and 1292 triangles.

pub use crate::rings::MeshError;
use crate::rings::{ring_mesh, Ring};
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

pub fn annulus(
    r_in: f64,
    r_out: f64,
    rings: usize,
    outer_nodes: usize,
    z: f64,
) -> Result<AnnulusMesh, MeshError> {
    let rings: Vec<Ring> = (0..rings)
        .map(|i| {
            let radius = r_in + (r_out - r_in) * i as f64 / (rings - 1) as f64;
            let nodes = ((outer_nodes as f64 * radius / r_out).round() as usize).max(6);
            // Alternate rings are rotated by half a spacing so the strips stay well shaped.
            let phase = if i % 2 == 1 { PI / nodes as f64 } else { 0.0 };
            Ring {
                radius,
                nodes,
                phase,
            }
        })
        .collect();
    let mesh = ring_mesh(&rings, z, false)?;
    let last = mesh.ring_start[rings.len() - 1];
    Ok(AnnulusMesh {
        rim: (last..last + rings[rings.len() - 1].nodes).collect(),
        inner: (0..rings[0].nodes).collect(),
        points: mesh.points,
        triangles: mesh.triangles,
    })
}
