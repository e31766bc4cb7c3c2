//! Marker points on a rigid body's surface, where the immersed boundary
//! (`immersed.rs`) holds the fluid to the body's motion and takes its load.
//! Geometry only: the shape comes from rigid-proc, the pose from the caller.
//!
//! A 3-D flow gets markers over the whole closed surface, each triangle of
//! a fine triangulation cut along its longest edge until no edge is longer
//! than the grid spacing (Uhlmann, J. Comput. Phys. 209, 448–476, 2005,
//! spaces markers about one cell apart). A 2-D flow (one cell thick along
//! an axis) sees the body's section by the box's mid-plane: markers along
//! the section's outline, each carrying its piece of outline times the
//! box's thickness.

use exchange::Shape;
use nalgebra::{Isometry3, Point3, Vector3};
use std::f64::consts::PI;

/// Most segments around a sphere or cylinder.
const MAX_SEGMENTS: u32 = 4096;

/// A point of a body's surface and the piece of surface it stands for.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Marker {
    /// Position [m].
    pub x: [f64; 3],
    /// Outward unit normal.
    pub normal: [f64; 3],
    /// Area [m²].
    pub area: f64,
}

/// A body's closed surface in its own frame.
#[derive(Debug, Clone)]
pub struct Surface {
    points: Vec<Point3<f64>>,
    triangles: Vec<[u32; 3]>,
}

impl Surface {
    /// The shape's surface, a sphere or cylinder drawn with segments no
    /// longer than half of `spacing` [m] (the polygon's perimeter is then
    /// within (π/n)²/6 of the circle's).
    pub fn of(shape: &Shape, spacing: f64) -> Surface {
        Surface::drawn(shape, spacing, shape.bounding_radius())
    }

    /// [`Surface::of`] with the segments no longer than half of `spacing`
    /// along the circles' own radius: the surface a 3-D flow's markers are
    /// cut from. A long cylinder's bounding sphere would cut its sides
    /// into slivers: ten times the markers at 1.8 × 0.4 m on 4 cm cells.
    pub fn for_markers(shape: &Shape, spacing: f64) -> Surface {
        Surface::drawn(shape, spacing, shape.drawn_radius())
    }

    fn drawn(shape: &Shape, spacing: f64, radius: f64) -> Surface {
        let around = 2.0 * PI * radius / (0.5 * spacing);
        let segments = (around.ceil() as u32).clamp(24, MAX_SEGMENTS);
        let (points, triangles) = shape.surface_with(segments);
        Surface { points, triangles }
    }

    /// Markers over the whole surface placed by `pose` (world ← own),
    /// every triangle cut until its edges are at most `spacing` [m].
    pub fn markers(&self, pose: &Isometry3<f64>, spacing: f64) -> Vec<Marker> {
        let mut out = Vec::new();
        for t in &self.triangles {
            let corners = t.map(|i| pose * self.points[i as usize]);
            pieces(corners, spacing, &mut |(_, m)| out.push(m));
        }
        out
    }

    /// Markers along the section of the placed surface by the plane
    /// x_axis = level, pieces at most `spacing` long, each with its length
    /// times `thickness` [m] as area.
    pub fn section(
        &self,
        pose: &Isometry3<f64>,
        axis: usize,
        level: f64,
        spacing: f64,
        thickness: f64,
    ) -> Vec<Marker> {
        let mut out = Vec::new();
        for s in self.segments(pose, axis, level) {
            let length = (s.ends[1] - s.ends[0]).norm();
            let pieces = (length / (spacing * (1.0 + EDGE_SLACK))).ceil().max(1.0) as usize;
            for k in 0..pieces {
                let at = s.ends[0] + (s.ends[1] - s.ends[0]) * ((k as f64 + 0.5) / pieces as f64);
                out.push(Marker {
                    x: at.coords.into(),
                    normal: s.normal.into(),
                    area: length / pieces as f64 * thickness,
                });
            }
        }
        out
    }

    /// The outline of the placed surface's section by the plane x_axis =
    /// level: one segment per triangle that crosses it, with the
    /// triangle's outward normal in the plane.
    pub fn segments(&self, pose: &Isometry3<f64>, axis: usize, level: f64) -> Vec<Segment> {
        let mut out = Vec::new();
        for t in &self.triangles {
            let p = t.map(|i| pose * self.points[i as usize]);
            // A vertex on the plane counts as above it, so that every
            // crossing edge is found once by each of its two triangles' cuts.
            let above = p.map(|q| q[axis] >= level);
            if above.iter().all(|&a| a) || above.iter().all(|&a| !a) {
                continue;
            }
            let cut = |i: usize, j: usize| {
                let s = (level - p[i][axis]) / (p[j][axis] - p[i][axis]);
                p[i] + (p[j] - p[i]) * s
            };
            let ends: Vec<Point3<f64>> = [(0, 1), (1, 2), (2, 0)]
                .iter()
                .filter(|&&(i, j)| above[i] != above[j])
                .map(|&(i, j)| cut(i, j))
                .collect();
            let mut normal = (p[1] - p[0]).cross(&(p[2] - p[0]));
            normal[axis] = 0.0;
            if let (Some(n), [e0, e1]) = (normal.try_normalize(1e-300), ends.as_slice()) {
                out.push(Segment {
                    ends: [*e0, *e1],
                    normal: n,
                });
            }
        }
        out
    }
}

/// A piece of a section's outline and its outward normal in the plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    pub ends: [Point3<f64>; 2],
    pub normal: Vector3<f64>,
}

/// The volume the markers enclose [m³], by the divergence theorem about
/// `centre`: V = (1/k) Σ (x − centre)·n A over markers in k dimensions
/// (k = 2 for a section, whose normals lie in its plane).
pub fn enclosed_volume(markers: &[Marker], centre: [f64; 3], dimensions: usize) -> f64 {
    let sum: f64 = markers
        .iter()
        .map(|m| {
            (0..3)
                .map(|d| (m.x[d] - centre[d]) * m.normal[d])
                .sum::<f64>()
                * m.area
        })
        .sum();
    sum / dimensions as f64
}

/// A piece of a triangle: its centroid's barycentric coordinates in the
/// whole triangle, and the marker it makes.
pub type Piece = ([f64; 3], Marker);

/// How far past `spacing` an edge (or a section's segment) may be and stay
/// whole, relative. A mesh laid out one cell apart (a cloth of the box's
/// spacing) has edges of exactly `spacing`, which round-off in the vertices' positions would
/// otherwise cut or not from one window to the next, and from one run to
/// another (the same run on 1 and 2 ranks).
const EDGE_SLACK: f64 = 1e-6;

/// Cuts triangle abc along its longest edge until every edge is at most
/// `spacing` (`EDGE_SLACK`), and calls `f` with each piece's centroid (as barycentric
/// coordinates in abc) and its marker (normal by the vertex order).
pub fn pieces([a, b, c]: [Point3<f64>; 3], spacing: f64, f: &mut impl FnMut(Piece)) {
    pieces_as(
        [a, b, c],
        &mut Cuts::Choose {
            spacing,
            into: None,
        },
        f,
    );
}

/// How a triangle is cut: chosen from its edges' lengths (and recorded, in
/// depth-first order: the edge cut, or [`WHOLE`]), or as recorded before.
/// Implicit coupling places the canopy again at each try of a window, at
/// positions a little apart; cut by their lengths, a triangle whose edge
/// lies near `spacing` would be cut one way in one try and another way in
/// the next, a jump in the forcing that stalls the iteration. Cut as in the
/// window's first try, the markers move smoothly with the vertices.
pub enum Cuts<'a> {
    Choose {
        spacing: f64,
        into: Option<&'a mut Vec<u8>>,
    },
    Replay {
        from: &'a [u8],
        at: usize,
    },
}

/// A recorded piece left whole.
pub const WHOLE: u8 = 3;

/// [`pieces`], cut as `cuts` says.
pub fn pieces_as([a, b, c]: [Point3<f64>; 3], cuts: &mut Cuts, f: &mut impl FnMut(Piece)) {
    let corners = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    split([a, b, c], corners, cuts, f);
}

impl Cuts<'_> {
    /// The edge to cut next (0: ab, 1: bc, 2: ca), or [`WHOLE`].
    fn next(&mut self, edges: [f64; 3]) -> u8 {
        match self {
            Cuts::Choose { spacing, into } => {
                let longest = (0..3)
                    .max_by(|&i, &j| edges[i].total_cmp(&edges[j]))
                    .unwrap_or(0);
                let cut = match edges[longest] > *spacing * (1.0 + EDGE_SLACK) {
                    true => longest as u8,
                    false => WHOLE,
                };
                if let Some(into) = into {
                    into.push(cut);
                }
                cut
            }
            Cuts::Replay { from, at } => {
                *at += 1;
                from.get(*at - 1).copied().unwrap_or(WHOLE)
            }
        }
    }
}

fn split(p: [Point3<f64>; 3], w: [[f64; 3]; 3], cuts: &mut Cuts, f: &mut impl FnMut(Piece)) {
    let [a, b, c] = p;
    let edges = [(b - a).norm(), (c - b).norm(), (a - c).norm()];
    let cut = cuts.next(edges);
    if cut != WHOLE {
        // Rotate so the cut edge is the first, then cut it at its middle.
        let (i, j, k) = (cut as usize, (cut as usize + 1) % 3, (cut as usize + 2) % 3);
        let m = Point3::from((p[i].coords + p[j].coords) * 0.5);
        let wm = [0, 1, 2].map(|d| 0.5 * (w[i][d] + w[j][d]));
        split([p[i], m, p[k]], [w[i], wm, w[k]], cuts, f);
        split([m, p[j], p[k]], [wm, w[j], w[k]], cuts, f);
        return;
    }
    let cross: Vector3<f64> = (b - a).cross(&(c - a));
    if let Some(n) = cross.try_normalize(1e-300) {
        let centroid = [0, 1, 2].map(|d| (w[0][d] + w[1][d] + w[2][d]) / 3.0);
        f((
            centroid,
            Marker {
                x: ((a.coords + b.coords + c.coords) / 3.0).into(),
                normal: n.into(),
                area: 0.5 * cross.norm(),
            },
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rigid_section::ShapeSpec;

    fn shape(spec: ShapeSpec) -> Shape {
        spec.shape().unwrap()
    }

    /// The markers of a sphere of radius 1 cover its area 4π and enclose
    /// its volume 4π/3, to the polygon's error (π/n)²/6 ≈ 2e-4 at the
    /// segments a spacing of 0.1 gives.
    #[test]
    fn sphere_markers_carry_its_area_and_volume() {
        let s = Surface::of(&shape(ShapeSpec::Sphere { radius: 1.0 }), 0.1);
        let m = s.markers(&Isometry3::translation(2.0, 0.0, 0.0), 0.1);
        let area: f64 = m.iter().map(|m| m.area).sum();
        let volume = enclosed_volume(&m, [2.0, 0.0, 0.0], 3);
        assert!((area / (4.0 * PI) - 1.0).abs() < 2e-3, "area {area}");
        assert!(
            (volume / (4.0 * PI / 3.0) - 1.0).abs() < 3e-3,
            "volume {volume}"
        );
        // Outward: the normal points away from the centre.
        assert!(m.iter().all(|m| (m.x[0] - 2.0) * m.normal[0]
            + m.x[1] * m.normal[1]
            + m.x[2] * m.normal[2]
            > 0.0));
        assert!(m.iter().all(|m| m.area.sqrt() < 0.1));
    }

    /// The section of a cylinder (radius 0.05, along z) by a plane across
    /// its axis is its circle: perimeter 2πr times the thickness, area πr².
    #[test]
    fn cylinder_section_is_its_circle() {
        let r = 0.05;
        let s = Surface::of(
            &shape(ShapeSpec::Cylinder {
                radius: r,
                height: 1.0,
            }),
            0.005,
        );
        let pose = Isometry3::translation(0.2, 0.2, 0.0);
        let m = s.section(&pose, 2, 0.01, 0.005, 0.02);
        let perimeter: f64 = m.iter().map(|m| m.area).sum::<f64>() / 0.02;
        let area = enclosed_volume(&m, [0.2, 0.2, 0.0], 2) / 0.02;
        assert!(
            (perimeter / (2.0 * PI * r) - 1.0).abs() < 1e-4,
            "{perimeter}"
        );
        assert!((area / (PI * r * r) - 1.0).abs() < 1e-4, "{area}");
        assert!(m
            .iter()
            .all(|m| m.normal[2] == 0.0 && (m.x[2] - 0.01).abs() < 1e-12));
    }
}
