//! Flat circular parachute canopies (dissertation §4.2: C-9, T-10, G-11, …): a disc of
//! nominal diameter D₀, optionally with a vent, divided into gores. Rings of nodes
//! run from the vent (or a centre node) to the skirt; every ring has a multiple
//! of the gore count of nodes, so the gore seams, the radial lines between gores,
//! are chains of mesh edges, and each suspension line starts at a seam on the skirt.

use crate::rings::{ring_mesh, MeshError, Ring};
use structure_section::parachute::CanopyGeometry;
use structure_section::Pleats;

pub struct CanopyMesh {
    pub points: Vec<f64>,
    pub triangles: Vec<[usize; 3]>,
    /// Edges along the gore seams.
    pub seams: Vec<(usize, usize)>,
    /// Skirt node of each line, counter-clockwise from +x.
    pub skirt: Vec<usize>,
    /// The vent edge, or the centre node.
    pub vent: Vec<usize>,
    /// Each node ring's first node and layout (none for a cross).
    pub rings: Vec<(usize, Ring)>,
}

/// The canopy of `g` in the plane z = `z` with `rings` node rings; a
/// canopy to be packed into `pleats` has each ring wider than the pack
/// meshed with a whole number of node pairs in every pleat.
pub fn circular_canopy(
    g: &CanopyGeometry,
    rings: usize,
    z: f64,
    pleats: Option<&Pleats>,
) -> Result<CanopyMesh, MeshError> {
    let (radius, vent) = (0.5 * g.diameter, 0.5 * g.vent);
    let gores = g.gores as usize;
    let centre = vent == 0.0;
    // With a vent, the first ring is its edge; without, rings start one spacing out.
    let spacing = if centre {
        radius / rings as f64
    } else {
        (radius - vent) / (rings - 1) as f64
    };
    let radii: Vec<f64> = (0..rings)
        .map(|i| {
            if centre {
                spacing * (i + 1) as f64
            } else {
                vent + spacing * i as f64
            }
        })
        .collect();
    // Nodes per gore on the skirt so that the skirt spacing is about the radial one.
    let per_gore = (2.0 * std::f64::consts::PI * radius / (gores as f64 * spacing))
        .round()
        .max(1.0);
    let layout: Vec<Ring> = radii
        .iter()
        .map(|&r| {
            let flat = gores * ((per_gore * r / radius).round() as usize).max(1);
            Ring {
                radius: r,
                nodes: pleats.map_or(flat, |p| p.ring_nodes(r, flat)),
                phase: 0.0,
            }
        })
        .collect();
    let mesh = ring_mesh(&layout, z, centre)?;
    // Seam node k of ring i sits at angle 2πk/gores.
    let seam_node = |i: usize, k: usize| mesh.ring_start[i] + k * layout[i].nodes / gores;
    let mut seams = Vec::new();
    for k in 0..gores {
        if centre {
            seams.push((0, seam_node(0, k)));
        }
        for i in 0..rings - 1 {
            seams.push((seam_node(i, k), seam_node(i + 1, k)));
        }
    }
    let skirt = (0..gores).map(|k| seam_node(rings - 1, k)).collect();
    let vent_nodes = if centre {
        vec![0]
    } else {
        (0..layout[0].nodes)
            .map(|k| mesh.ring_start[0] + k)
            .collect()
    };
    Ok(CanopyMesh {
        points: mesh.points,
        triangles: mesh.triangles,
        seams,
        skirt,
        vent: vent_nodes,
        rings: mesh.ring_start.into_iter().zip(layout).collect(),
    })
}
