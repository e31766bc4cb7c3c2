//! What rigid-proc writes for ParaView: every body's centre of mass as a
//! vertex (`bodies.pvd`), and the surfaces of the bodies with a shape
//! (`body-surfaces.pvd`).

use crate::Bodies;
use participant::vtu::{CellKind, Piece, Series};

type Error = Box<dyn std::error::Error>;

/// Every body's surface (mass points as vertices) for ParaView.
pub fn write_surfaces(series: &mut Series, b: &Bodies, index: u64, time: f64) -> Result<(), Error> {
    let mut points = Vec::new();
    let mut velocity = Vec::new();
    let mut triangles = Vec::new();
    for body in &b.bodies {
        let Some(shape) = &body.shape else { continue };
        let pose = body.own_pose();
        let (local, tris) = shape.surface();
        let first = points.len() / 3;
        for p in &local {
            let w = (pose * p).coords;
            points.extend_from_slice(w.as_slice());
            velocity.extend_from_slice(body.velocity_at(&w).as_slice());
        }
        triangles.extend(tris.iter().flat_map(|t| t.map(|i| first + i as usize)));
    }
    series.write(
        index,
        time,
        &Piece {
            points: &points,
            kind: CellKind::Triangle,
            connectivity: &triangles,
            point_data: vec![("velocity", 3, &velocity)],
        },
    )?;
    Ok(())
}

/// Every body's centre of mass, as vertices.
pub fn write_points(series: &mut Series, b: &Bodies, index: u64, time: f64) -> Result<(), Error> {
    let points: Vec<f64> = b
        .bodies
        .iter()
        .flat_map(|b| b.state.x.iter().copied().collect::<Vec<_>>())
        .collect();
    let vel: Vec<f64> = b
        .bodies
        .iter()
        .flat_map(|b| b.state.v.iter().copied().collect::<Vec<_>>())
        .collect();
    let conn: Vec<usize> = (0..b.bodies.len()).collect();
    series.write(
        index,
        time,
        &Piece {
            points: &points,
            kind: CellKind::Vertex,
            connectivity: &conn,
            point_data: vec![("velocity", 3, &vel)],
        },
    )?;
    Ok(())
}
