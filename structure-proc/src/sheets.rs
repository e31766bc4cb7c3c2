//! The free circular cloth of `[structure.disk]` and the strings of
//! `[[structure.cords]]` (the dissertation's collision scenes, §4.3.2–4.3.3).

use crate::model::{Model, NodeKind, Spring};
use crate::rings::{ring_mesh, MeshError, Ring, RingMesh};
use std::f64::consts::PI;
use structure_section::{Cords, Disk};

/// The disk's mesh: a centre node and `rings` rings of 6k nodes at equal
/// spacing, each turned by half a spacing from the one inside, so the
/// triangles are near equilateral.
pub fn disk_mesh(d: &Disk) -> Result<RingMesh, MeshError> {
    let n = d.rings as usize;
    let rings: Vec<Ring> = (1..=n)
        .map(|k| Ring {
            radius: 0.5 * d.diameter * k as f64 / n as f64,
            nodes: 6 * k,
            phase: if k % 2 == 0 { PI / (6 * k) as f64 } else { 0.0 },
        })
        .collect();
    let mut mesh = ring_mesh(&rings, 0.0, true)?;
    for p in mesh.points.chunks_exact_mut(3) {
        for (x, c) in p.iter_mut().zip(d.centre) {
            *x += c;
        }
    }
    Ok(mesh)
}

/// Add each string of `cords`: `segments` springs of stiffness E·A/l⁰,
/// its mass lumped to the nodes (half a segment's at each end), its ends
/// held when asked. Strings carry tension only (thesis eq. 3).
pub fn add_cords(m: &mut Model, cords: &Cords) {
    let n = cords.segments as usize;
    let length = (0..3)
        .map(|c| (cords.to[c] - cords.from[c]).powi(2))
        .sum::<f64>()
        .sqrt();
    let rest = length / n as f64;
    let node_mass = cords.linear_density * rest;
    for s in 0..cords.count as usize {
        let first = m.nodes();
        for k in 0..=n {
            let u = k as f64 / n as f64;
            let end = k == 0 || k == n;
            for c in 0..3 {
                let x =
                    cords.from[c] + u * (cords.to[c] - cords.from[c]) + s as f64 * cords.spacing[c];
                m.x.push(x);
            }
            m.v.extend_from_slice(&[0.0; 3]);
            let held = end && cords.fixed_ends;
            m.kind.push(if held {
                NodeKind::Fixed
            } else {
                NodeKind::Free
            });
            m.mass.push(match (held, end) {
                (true, _) => 0.0,
                (false, true) => 0.5 * node_mass,
                (false, false) => node_mass,
            });
        }
        for k in 0..n {
            m.springs.push(Spring {
                i: first + k,
                j: first + k + 1,
                k: cords.axial_stiffness / rest,
                rest,
                tension_only: true,
                eps: 0.0,
            });
        }
    }
}
