//! Build the model a scenario's `[structure]` section describes.

use crate::annulus::{annulus, MeshError};
use crate::model::{Attachment, Model, NodeKind, Spring};
use coupler::scenario::{RigidSection, StructureSection};
use std::collections::BTreeSet;

/// The model for `[structure]`, with structure step `dt` = Δt_s. Strings attach
/// to the bodies of `[rigid]`, in the order of `[[structure.strings]]`.
pub fn build_model(
    s: &StructureSection,
    rigid: Option<&RigidSection>,
    dt: f64,
) -> Result<Model, MeshError> {
    let mut m = Model {
        x: Vec::new(),
        v: Vec::new(),
        mass: Vec::new(),
        kind: Vec::new(),
        springs: Vec::new(),
        triangles: Vec::new(),
        canopy_nodes: 0,
        vent: Vec::new(),
        canopy_height: 0.0,
        attachments: Vec::new(),
        gravity: s.gravity,
        damping: s.damping,
        dt,
        damping_dt: dt,
    };
    if let Some(a) = &s.annulus {
        let mesh = annulus(
            a.inner_radius,
            a.outer_radius,
            a.rings as usize,
            a.outer_nodes as usize,
            a.height,
        )?;
        let n = mesh.points.len() / 3;
        m.x = mesh.points;
        m.v = vec![0.0; 3 * n];
        m.mass = vec![0.0; n];
        m.kind = vec![NodeKind::Free; n];
        for &r in &mesh.rim {
            m.kind[r] = NodeKind::Fixed;
        }
        // Lump a third of every triangle's fabric mass to each vertex.
        let mut edges = BTreeSet::new();
        for tri in &mesh.triangles {
            let n2 = crate::forces::area_normal2(&m.x, tri);
            let area = 0.5 * (n2[0] * n2[0] + n2[1] * n2[1] + n2[2] * n2[2]).sqrt();
            for k in 0..3 {
                m.mass[tri[k]] += a.areal_density * area / 3.0;
                let (i, j) = (tri[k], tri[(k + 1) % 3]);
                edges.insert((i.min(j), i.max(j)));
            }
        }
        for (i, j) in edges {
            let rest = distance(&m.x, i, j);
            m.springs.push(Spring {
                i,
                j,
                k: a.stiffness,
                rest,
                tension_only: false,
                eps: 0.0,
            });
        }
        for (n, kind) in m.kind.iter().enumerate() {
            if *kind == NodeKind::Fixed {
                m.mass[n] = 0.0;
            }
        }
        m.triangles = mesh.triangles;
        m.vent = mesh.inner;
        m.canopy_height = a.height;
        m.canopy_nodes = n;
    }
    for st in &s.strings {
        // A massless string: fixed anchor node and a node attached to the body.
        let anchor = m.nodes();
        push_node(&mut m, st.anchor, NodeKind::Fixed);
        let body = rigid
            .and_then(|r| r.bodies.iter().find(|b| b.name == st.body))
            .map(|b| b.position)
            .unwrap_or(st.anchor);
        let end = m.nodes();
        let attachment = m.attachments.len();
        push_node(&mut m, body, NodeKind::Attached(attachment));
        m.attachments.push(Attachment {
            node: end,
            x0: body,
            ..Default::default()
        });
        m.springs.push(Spring {
            i: anchor,
            j: end,
            k: st.stiffness,
            rest: st.rest_length,
            tension_only: true,
            eps: st.compressive_tolerance,
        });
    }
    Ok(m)
}

fn push_node(m: &mut Model, x: [f64; 3], kind: NodeKind) {
    m.x.extend_from_slice(&x);
    m.v.extend_from_slice(&[0.0; 3]);
    m.mass.push(0.0);
    m.kind.push(kind);
}

fn distance(x: &[f64], i: usize, j: usize) -> f64 {
    (0..3)
        .map(|c| (x[3 * j + c] - x[3 * i + c]).powi(2))
        .sum::<f64>()
        .sqrt()
}
