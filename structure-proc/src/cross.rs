//! Flat cross (cruciform) canopies, the T-11 of dissertation table 5.2: a central
//! square of side a = D₀/3 and four square arms, so the tip-to-tip span is D₀.
//! A square grid of `cells` cells per a covers the cross; each cell is split
//! into two triangles along alternating diagonals, so the mesh has no
//! preferred direction. The lines start at the arm ends, a quarter of them on
//! each, evenly spread from corner to corner.

use crate::parachute::CanopyMesh;
use crate::rings::MeshError;
use structure_section::parachute::CanopyGeometry;

/// The cross of `g` in the plane z = `z` with `cells` cells across an arm.
pub fn cross_canopy(g: &CanopyGeometry, cells: usize, z: f64) -> Result<CanopyMesh, MeshError> {
    let per_arm = g.gores as usize / 4;
    if cells == 0 || g.gores % 4 != 0 || !(2..=cells + 1).contains(&per_arm) {
        return Err(MeshError(format!(
            "a cross with {cells} cells per arm cannot carry {} lines (in fours, 2 to {} per arm end)",
            g.gores,
            cells + 1
        )));
    }
    let n = 3 * cells;
    let h = g.diameter / n as f64;
    let half = 0.5 * g.diameter;
    // Cell (i, j) belongs to the cross if it lies in the middle third across x or y.
    let inside = |i: usize, j: usize| i / cells == 1 || j / cells == 1;
    let cell_exists = |i: isize, j: isize| {
        (0..n as isize).contains(&i)
            && (0..n as isize).contains(&j)
            && inside(i as usize, j as usize)
    };
    let mut index = vec![usize::MAX; (n + 1) * (n + 1)];
    let mut points = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (ii, jj) = (i as isize, j as isize);
            if [(ii - 1, jj - 1), (ii, jj - 1), (ii - 1, jj), (ii, jj)]
                .iter()
                .any(|&(a, b)| cell_exists(a, b))
            {
                index[j * (n + 1) + i] = points.len() / 3;
                points.extend([i as f64 * h - half, j as f64 * h - half, z]);
            }
        }
    }
    let node = |i: usize, j: usize| index[j * (n + 1) + i];
    let mut triangles = Vec::new();
    for j in 0..n {
        for i in 0..n {
            if !inside(i, j) {
                continue;
            }
            let (a, b, c, d) = (
                node(i, j),
                node(i + 1, j),
                node(i + 1, j + 1),
                node(i, j + 1),
            );
            // Counter-clockwise seen from +z, as the circular canopies.
            if (i + j) % 2 == 0 {
                triangles.extend([[a, b, c], [a, c, d]]);
            } else {
                triangles.extend([[a, b, d], [b, c, d]]);
            }
        }
    }
    // Line k of an arm end sits at the grid node nearest k/(per_arm − 1) of its width.
    let along =
        |k: usize| cells + (k as f64 * cells as f64 / (per_arm - 1) as f64).round() as usize;
    let mut skirt = Vec::with_capacity(g.gores as usize);
    // Counter-clockwise: +x end (y rising), +y end (x falling), −x end, −y end.
    skirt.extend((0..per_arm).map(|k| node(n, along(k))));
    skirt.extend((0..per_arm).map(|k| node(n - along(k), n)));
    skirt.extend((0..per_arm).map(|k| node(0, n - along(k))));
    skirt.extend((0..per_arm).map(|k| node(along(k), 0)));
    // The node or nodes nearest the centre stand for the apex.
    let r2 = |p: &[f64]| p[0] * p[0] + p[1] * p[1];
    let nearest = points.chunks_exact(3).map(r2).fold(f64::INFINITY, f64::min);
    let vent = (0..points.len() / 3)
        .filter(|&p| r2(&points[3 * p..3 * p + 3]) <= nearest * (1.0 + 1e-12))
        .collect();
    Ok(CanopyMesh {
        points,
        triangles,
        seams: Vec::new(),
        skirt,
        vent,
        rings: Vec::new(),
    })
}
