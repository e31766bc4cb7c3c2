//! Build the model a scenario's `[structure]` section describes.

use crate::annulus::{annulus, MeshError};
use crate::cross::cross_canopy;
use crate::designer::ParachuteParts;
use crate::dome::{confluence_depth, lay_on_dome};
use crate::forces::damping::{Damper, Law};
use crate::forces::delingette::{lame, TriangleSprings};
use crate::lines::add_line;
use crate::model::{Attachment, Model, NodeKind, Spring};
use crate::network::Network;
use crate::pack::pack_canopy;
use crate::parachute::{circular_canopy, CanopyMesh};
use crate::rectangle::{rectangle, Edge};
use crate::reefing::add_reefing_line;
use rigid_section::{BodySpec, RigidSection};
use std::collections::BTreeSet;
use structure_section::parachute::CanopyShape;
use structure_section::StructureSection;
use structure_section::{Cloth, ClothHold, ClothPlane, Parachute};
use structure_section::{Damping, Elasticity};

/// The model for `[structure]`, with structure step `dt` = Δt_s. The parachute's
/// confluence and the strings attach to the bodies of `[rigid]`, numbered as
/// [`StructureSection::attachments`] lists them.
pub fn build_model(
    s: &StructureSection,
    rigid: Option<&RigidSection>,
    dt: f64,
) -> Result<Model, MeshError> {
    let net = Network {
        damping: match s.damping {
            Damping::None => None,
            Damping::RelativeVelocity => Some(Law::RelativeVelocity),
            Damping::Viscous => Some(Law::Axial),
        },
        gravity: s.gravity,
        porous: s.porous.as_ref().map(|l| porous::Porous::new(&l.params())),
        ..Default::default()
    };
    let mut m = Model {
        net,
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
        add_surface(
            &mut m,
            mesh.points,
            mesh.triangles,
            a.fabric.areal_density,
            a.fabric.elasticity(),
        )?;
        hold(&mut m, &mesh.rim);
        m.vent = mesh.inner;
        m.canopy_height = a.height;
    }
    if let Some(p) = &s.parachute {
        add_parachute(&mut m, p, rigid)?;
    }
    if let Some(c) = &s.cloth {
        add_cloth(&mut m, c)?;
    }
    if let Some(d) = &s.disk {
        let mesh = crate::sheets::disk_mesh(d)?;
        add_sheet(
            &mut m,
            mesh.points,
            mesh.triangles,
            &d.fabric,
            d.bending_stiffness,
        )?;
    }
    add_network(&mut m, s)?;
    for c in &s.cords {
        crate::sheets::add_cords(&mut m, c);
    }
    add_strings(&mut m, &s.strings, rigid);
    add_dampers(&mut m, s, dt);
    m.prepare();
    Ok(m)
}

/// Each `[[structure.strings]]` entry: a massless string from a fixed
/// anchor node to a node attached to its rigid body.
fn add_strings(
    m: &mut Model,
    strings: &[structure_section::StringSpec],
    rigid: Option<&RigidSection>,
) {
    for st in strings {
        // A massless string: fixed anchor node and a node attached to the body.
        let anchor = m.nodes();
        push_node(m, st.anchor, NodeKind::Fixed);
        let body = rigid
            .and_then(|r| r.bodies.iter().find(|b| b.name == st.body))
            .map(|b| b.world_point(st.body_point))
            .unwrap_or(st.anchor);
        let end = m.nodes();
        let attachment = m.attachments.len();
        push_node(m, body, NodeKind::Attached(attachment));
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
}

/// The fabric surface: free nodes at `points`, its triangles, lumped masses and
/// elasticity. It must come first: the surface occupies nodes `0..canopy_nodes`.
fn add_surface(
    m: &mut Model,
    points: Vec<f64>,
    triangles: Vec<[usize; 3]>,
    areal_density: f64,
    e: Elasticity,
) -> Result<(), MeshError> {
    let n = points.len() / 3;
    m.x = points;
    m.v = vec![0.0; 3 * n];
    m.mass = vec![0.0; n];
    m.kind = vec![NodeKind::Free; n];
    lump_areal_mass(m, &triangles, areal_density);
    add_fabric(m, &triangles, e)?;
    m.triangles = triangles;
    m.canopy_nodes = n;
    Ok(())
}

/// Hold `nodes` in place (Dirichlet condition); they carry no mass.
fn hold(m: &mut Model, nodes: &[usize]) {
    for &n in nodes {
        m.kind[n] = NodeKind::Fixed;
        m.mass[n] = 0.0;
    }
}

/// A parachute (dissertation §4.2): canopy, gore seams, suspension lines to a
/// confluence that is a payload mass point or a rigid body's attachment point.
fn add_parachute(
    m: &mut Model,
    p: &Parachute,
    rigid: Option<&RigidSection>,
) -> Result<(), MeshError> {
    let g = p.geometry();
    let body = match &p.body {
        Some(name) => Some(
            rigid
                .and_then(|r| r.bodies.iter().find(|b| &b.name == name))
                .ok_or_else(|| {
                    MeshError(format!("the parachute's body `{name}` is not in [rigid]"))
                })?,
        ),
        None => None,
    };
    let (mut mesh, start, confluence, z) = place_canopy(p, body)?;
    // The fabric's and seams' rest state is the flat canopy's.
    add_surface(
        m,
        mesh.points,
        mesh.triangles,
        p.fabric.areal_density,
        p.fabric.elasticity(),
    )?;
    if let Some(k) = p.seam_stiffness {
        for &(i, j) in &mesh.seams {
            let rest = distance(&m.x, i, j);
            m.springs.push(Spring {
                i,
                j,
                k,
                rest,
                tension_only: false,
                eps: 0.0,
            });
        }
    }
    m.x.copy_from_slice(&start);
    m.vent = std::mem::take(&mut mesh.vent);
    m.canopy_height = z;
    let hub = add_confluence(m, p, confluence, body.is_some());
    add_suspension_lines(m, p, &mesh.skirt, hub);
    add_reefing_line(m, p, &mesh.skirt);
    // The start: released at this velocity, or held by the payload first.
    let velocity = p.velocity.or(body.map(|b| b.velocity)).unwrap_or([0.0; 3]);
    for v in m.v.chunks_exact_mut(3) {
        v.copy_from_slice(&velocity);
    }
    if let (Some(until), None) = (p.release_time, body) {
        m.hold_until(hub, m.mass[hub], until);
    }
    m.parachute = Some(ParachuteParts {
        hub,
        nominal_area: g.nominal_area(),
        nominal_diameter: g.diameter,
        air_density: None,
    });
    Ok(())
}

/// The canopy of `p` placed over its confluence: the flat mesh (the fabric's
/// rest state), where its nodes start (flat, pre-shaped on a spherical
/// cap, or packed at line stretch), the confluence (on `body`, or below `height` so that the lines
/// reach it) and the height of the canopy's top.
fn place_canopy(
    p: &Parachute,
    body: Option<&BodySpec>,
) -> Result<(CanopyMesh, Vec<f64>, [f64; 3], f64), MeshError> {
    let g = p.geometry();
    let pleats = p.pack_diameter.map(|d| g.pleats(d)).transpose();
    let pleats = pleats.map_err(MeshError)?;
    let mut mesh = match g.shape {
        CanopyShape::Circular => circular_canopy(&g, p.resolution as usize, 0.0, pleats.as_ref())?,
        CanopyShape::Cross => cross_canopy(&g, p.resolution as usize, 0.0)?,
    };
    let mut start = mesh.points.clone();
    // Lines of length L from the skirt meet on the axis this far below its top.
    let drop = match (p.preshaped_diameter, &pleats) {
        (None, None) => (g.line_length.powi(2) - g.skirt_radius().powi(2)).sqrt(),
        (Some(d), _) => {
            lay_on_dome(&mut start, g.dome_radius(d).map_err(MeshError)?);
            confluence_depth(&start, &mesh.skirt, g.line_length)
        }
        (None, Some(pleats)) => {
            pack_canopy(&mut start, &mesh.rings, pleats);
            confluence_depth(&start, &mesh.skirt, g.line_length)
        }
    };
    // Attached to a body, the canopy is placed above it; otherwise at `height`.
    let confluence = match body {
        Some(b) => b.world_point(p.body_point),
        None => [0.0, 0.0, p.height - drop],
    };
    let z = confluence[2] + drop;
    for points in [&mut mesh.points, &mut start] {
        for point in points.chunks_exact_mut(3) {
            point[0] += confluence[0];
            point[1] += confluence[1];
            point[2] += z;
        }
    }
    Ok((mesh, start, confluence, z))
}

/// The confluence node where the lines meet: attached to the body, or a
/// mass point of the payload's mass. Returns its node.
fn add_confluence(m: &mut Model, p: &Parachute, at: [f64; 3], on_body: bool) -> usize {
    let hub = m.nodes();
    match on_body {
        true => {
            push_node(m, at, NodeKind::Attached(m.attachments.len()));
            m.attachments.push(Attachment {
                node: hub,
                x0: at,
                ..Default::default()
            });
        }
        false => {
            push_node(m, at, NodeKind::Free);
            m.mass[hub] = p.payload_mass.unwrap_or(0.0);
        }
    }
    m.points.push(("confluence".into(), hub));
    hub
}

/// A suspension line from each skirt node to the confluence `hub`, with its
/// length change and break rule (dissertation §4.2.3).
fn add_suspension_lines(m: &mut Model, p: &Parachute, skirt: &[usize], hub: usize) {
    let g = p.geometry();
    for (index, &skirt) in skirt.iter().enumerate() {
        let change: f64 = p
            .line_changes
            .iter()
            .filter(|c| c.lines.contains(&(index as u32)))
            .map(|c| c.rest_length_change)
            .sum();
        let mut line = add_line(
            (&mut m.x, &mut m.v, &mut m.net),
            skirt,
            hub,
            p.line_segments as usize,
            g.line_length + change,
            p.line_axial_stiffness,
            p.line_density,
        );
        for b in p
            .line_breaks
            .iter()
            .filter(|b| b.lines.contains(&(index as u32)))
        {
            line.break_time = b.time.or(line.break_time);
            line.break_tension = b.tension.or(line.break_tension);
        }
        m.lines.push(line);
    }
}

/// A rectangular cloth with the chosen edges or corners held, and optional
/// bending springs between the far vertices of adjacent triangles (the dissertation, end of §2.3).
fn add_cloth(m: &mut Model, c: &Cloth) -> Result<(), MeshError> {
    let (nx, ny) = (c.nodes_x as usize, c.nodes_y as usize);
    let mut mesh = rectangle(c.width, c.depth, nx, ny, [0.0; 3]);
    for p in mesh.points.chunks_exact_mut(3) {
        let (u, w) = (p[0], p[1]);
        let local = match c.plane {
            ClothPlane::Horizontal => [u, w, 0.0],
            ClothPlane::Vertical => [u, 0.0, w],
        };
        for k in 0..3 {
            p[k] = c.origin[k] + local[k];
        }
    }
    let held: Vec<usize> = c
        .fixed
        .iter()
        .flat_map(|h| match h {
            ClothHold::EdgeX0 => mesh.edge(Edge::X0),
            ClothHold::EdgeX1 => mesh.edge(Edge::X1),
            ClothHold::EdgeY0 => mesh.edge(Edge::Y0),
            ClothHold::EdgeY1 => mesh.edge(Edge::Y1),
            ClothHold::CornerX0Y0 => vec![mesh.node(0, 0)],
            ClothHold::CornerX1Y0 => vec![mesh.node(nx - 1, 0)],
            ClothHold::CornerX0Y1 => vec![mesh.node(0, ny - 1)],
            ClothHold::CornerX1Y1 => vec![mesh.node(nx - 1, ny - 1)],
        })
        .collect();
    let triangles = std::mem::take(&mut mesh.triangles);
    add_sheet(m, mesh.points, triangles, &c.fabric, c.bending_stiffness)?;
    hold(m, &held);
    Ok(())
}

/// A free cloth at `points` with its `triangles` and fabric, and optional
/// bending springs between the far vertices of adjacent triangles (the
/// dissertation, end of §2.3).
fn add_sheet(
    m: &mut Model,
    points: Vec<f64>,
    triangles: Vec<[usize; 3]>,
    fabric: &structure_section::Fabric,
    bending_stiffness: Option<f64>,
) -> Result<(), MeshError> {
    if let Some(k) = bending_stiffness {
        for (i, j) in bending_pairs(&triangles) {
            let rest = distance(&points, i, j);
            m.springs.push(Spring {
                i,
                j,
                k,
                rest,
                tension_only: false,
                eps: 0.0,
            });
        }
    }
    add_surface(
        m,
        points,
        triangles,
        fabric.areal_density,
        fabric.elasticity(),
    )?;
    m.vent = Vec::new();
    Ok(())
}

/// For every edge shared by two triangles, the two vertices not on it.
fn bending_pairs(triangles: &[[usize; 3]]) -> Vec<(usize, usize)> {
    let mut far = std::collections::HashMap::new();
    let mut pairs = Vec::new();
    for t in triangles {
        for k in 0..3 {
            let (i, j, o) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
            if let Some(other) = far.insert((i.min(j), i.max(j)), o) {
                pairs.push((other, o));
            }
        }
    }
    pairs
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

/// Springs on the edges of `triangles` (uniform k, or k = A·E/l⁰ of the thesis
/// eq. 71), or Delingette triangular springs (dissertation eqs. 2.29–2.32).
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

/// One damper per spring, string and membrane edge: c = k·Δt_s for the thesis
/// eq. (68), c = damping_coefficient for dissertation eq. (2.38).
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
