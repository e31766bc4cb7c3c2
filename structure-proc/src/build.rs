//! Build the model a scenario's `[structure]` section describes.

use crate::annulus::{annulus, MeshError};
use crate::forces::damping::{Damper, Law};
use crate::forces::delingette::{lame, TriangleSprings};
use crate::model::{Attachment, Model, NodeKind, Spring};
use coupler::scenario::structure::{Damping, Elasticity};
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
        damping: match s.damping {
            Damping::None => None,
            Damping::RelativeVelocity => Some(Law::RelativeVelocity),
            Damping::Viscous => Some(Law::Axial),
        },
        gravity: s.gravity,
        dt,
        ..Default::default()
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
        lump_areal_mass(&mut m, &mesh.triangles, a.areal_density);
        add_fabric(&mut m, &mesh.triangles, a.elasticity())?;
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
    add_network(&mut m, s)?;
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
    add_dampers(&mut m, s, dt);
    m.prepare();
    Ok(m)
}

/// Lump a third of every triangle's fabric mass to each vertex.
fn lump_areal_mass(m: &mut Model, triangles: &[[usize; 3]], areal_density: f64) {
    for tri in triangles {
        let n2 = crate::forces::area_normal2(&m.x, tri);
        let area = 0.5 * (n2[0] * n2[0] + n2[1] * n2[1] + n2[2] * n2[2]).sqrt();
        for &node in tri {
            m.mass[node] += areal_density * area / 3.0;
        }
    }
}

/// Springs on the edges of `triangles` (uniform k, or k = A·E/l⁰ of seed 003
/// eq. 71), or Delingette triangular springs (seed 000 eqs. 2.29–2.32).
fn add_fabric(m: &mut Model, triangles: &[[usize; 3]], e: Elasticity) -> Result<(), MeshError> {
    if let Elasticity::Membrane(mb) = e {
        let (lambda, mu) = lame(mb.young_modulus, mb.poisson_ratio, mb.thickness);
        for tri in triangles {
            let t = TriangleSprings::new(&m.x, *tri, lambda, mu)
                .map_err(|d| MeshError(d.to_string()))?;
            m.membrane.push(t);
        }
        return Ok(());
    }
    let mut edges = BTreeSet::new();
    for tri in triangles {
        for k in 0..3 {
            let (i, j) = (tri[k], tri[(k + 1) % 3]);
            edges.insert((i.min(j), i.max(j)));
        }
    }
    for (i, j) in edges {
        let rest = distance(&m.x, i, j);
        let k = match e {
            Elasticity::Uniform(k) => k,
            Elasticity::Fibre(f) => f.area * f.young_modulus / rest,
            Elasticity::Membrane(_) => unreachable!(),
        };
        m.springs.push(Spring {
            i,
            j,
            k,
            rest,
            tension_only: false,
            eps: 0.0,
        });
    }
    Ok(())
}

/// `[[structure.points]]` and `[[structure.springs]]`: a hand-built network.
fn add_network(m: &mut Model, s: &StructureSection) -> Result<(), MeshError> {
    let first = m.nodes();
    for p in &s.points {
        let n = m.nodes();
        push_node(
            m,
            p.position,
            if p.fixed {
                NodeKind::Fixed
            } else {
                NodeKind::Free
            },
        );
        m.points.push((p.name.clone(), n));
        if !p.fixed {
            m.mass[n] = p.mass;
            m.v[3 * n..3 * n + 3].copy_from_slice(&p.velocity);
        }
    }
    let index = |name: &str| first + s.points.iter().position(|p| p.name == name).unwrap_or(0);
    for sp in &s.springs {
        let (i, j) = (index(&sp.ends[0]), index(&sp.ends[1]));
        let rest = sp.rest_length.unwrap_or_else(|| distance(&m.x, i, j));
        if rest <= 0.0 {
            return Err(MeshError(format!(
                "spring {} – {} has zero rest length: its ends start at the same place",
                sp.ends[0], sp.ends[1]
            )));
        }
        m.springs.push(Spring {
            i,
            j,
            k: sp.stiffness,
            rest,
            tension_only: false,
            eps: 0.0,
        });
    }
    Ok(())
}

/// One damper per spring, string and membrane edge: c = k·Δt_s for seed 003
/// eq. (68), c = damping_coefficient for seed 000 eq. (2.38).
fn add_dampers(m: &mut Model, s: &StructureSection, dt: f64) {
    let coefficient = |k: f64| match s.damping {
        Damping::RelativeVelocity => k * dt,
        _ => s.damping_coefficient.unwrap_or(0.0),
    };
    if s.damping == Damping::None {
        return;
    }
    let mut dampers: Vec<Damper> = m
        .springs
        .iter()
        .map(|sp| Damper {
            i: sp.i,
            j: sp.j,
            c: coefficient(sp.k),
            slack_below: if sp.tension_only {
                sp.rest + sp.eps
            } else {
                0.0
            },
        })
        .collect();
    // A membrane edge shared by two triangles gets one damper with k̃ of eq. (2.37).
    let mut edges = std::collections::BTreeMap::new();
    for t in &m.membrane {
        for (i, j, k) in t.edge_stiffness() {
            *edges.entry((i.min(j), i.max(j))).or_insert(0.0) += k;
        }
    }
    dampers.extend(edges.into_iter().map(|((i, j), k)| Damper {
        i,
        j,
        c: coefficient(k),
        slack_below: 0.0,
    }));
    m.dampers = dampers;
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
