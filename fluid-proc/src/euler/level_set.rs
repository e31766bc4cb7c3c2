//! The signed distance φ to a placed rigid body's surface and the outward
//! normal at its closest point: the level set the gas's ghost cells read
//! (`bodies.rs`), negative inside the body. Geometry only: the pose
//! comes from the caller.
//!
//! A 3-D box asks parry for the closest point of the shape itself (sphere,
//! cuboid, cylinder or closed mesh). A 2-D box (one cell thick along an
//! axis) sees the body's section by its mid-plane, as the incompressible
//! flow does (`surface.rs`): φ is the distance to the nearest segment of
//! that outline in the plane, inside by the even–odd crossing rule.

use crate::surface::{Segment, Surface};
use exchange::Shape;
use nalgebra::{Isometry3, Point3, Vector3};

/// The closest point of a body's surface to a point x.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Closest {
    /// Signed distance from the surface [m]: negative inside the body.
    pub phi: f64,
    /// The surface's closest point [m].
    pub point: [f64; 3],
    /// The outward unit normal there (along x − point outside, against
    /// it inside).
    pub normal: [f64; 3],
}

/// A body's surface at one pose, ready for distance queries.
pub enum Placed {
    /// A 3-D box: the shape, world ← shape frame.
    Solid { shape: Shape, pose: Isometry3<f64> },
    /// A 2-D box: the section's outline in the plane across `thin`.
    Section {
        segments: Vec<Segment>,
        thin: usize,
        level: f64,
    },
}

impl Placed {
    /// `shape` (whose surface is `surface`) placed by `pose` (world ← own
    /// frame); `thin` is the axis a 2-D box is one cell thick along and
    /// the level of its mid-plane [m].
    pub fn new(
        shape: &Shape,
        surface: &Surface,
        pose: &Isometry3<f64>,
        thin: Option<(usize, f64)>,
    ) -> Placed {
        match thin {
            None => Placed::Solid {
                shape: shape.clone(),
                pose: pose * shape.placement,
            },
            Some((thin, level)) => Placed::Section {
                segments: surface.segments(pose, thin, level),
                thin,
                level,
            },
        }
    }

    /// The corners of a box that holds the surface [m] (a section's spans
    /// its mid-plane alone along the thin axis).
    pub fn bounds(&self) -> [[f64; 3]; 2] {
        match self {
            Placed::Solid { shape, pose } => {
                let b = shape.shape.compute_aabb(pose);
                [b.mins.coords.into(), b.maxs.coords.into()]
            }
            Placed::Section {
                segments,
                thin,
                level,
            } => {
                let mut lo = [f64::INFINITY; 3];
                let mut hi = [f64::NEG_INFINITY; 3];
                for p in segments.iter().flat_map(|s| s.ends) {
                    for d in 0..3 {
                        lo[d] = lo[d].min(p[d]);
                        hi[d] = hi[d].max(p[d]);
                    }
                }
                (lo[*thin], hi[*thin]) = (*level, *level);
                [lo, hi]
            }
        }
    }

    /// The closest surface point to `x` (on the mid-plane of a section).
    pub fn closest(&self, x: [f64; 3]) -> Closest {
        match self {
            Placed::Solid { shape, pose } => solid_closest(shape, pose, x),
            Placed::Section { segments, thin, .. } => section_closest(segments, *thin, x),
        }
    }
}

fn solid_closest(shape: &Shape, pose: &Isometry3<f64>, x: [f64; 3]) -> Closest {
    let at = Point3::from(x);
    let (projection, feature) = shape
        .shape
        .project_local_point_and_get_feature(&pose.inverse_transform_point(&at));
    let point = pose * projection.point;
    let away = at - point;
    let distance = away.norm();
    let sign = if projection.is_inside { -1.0 } else { 1.0 };
    // On the surface itself the direction is lost: the feature's normal.
    let normal = match away.try_normalize(1e-14 * (1.0 + point.coords.norm())) {
        Some(n) => n * sign,
        None => shape
            .shape
            .feature_normal_at_point(feature, &projection.point)
            .map_or(Vector3::z(), |n| pose.rotation * n.into_inner()),
    };
    Closest {
        phi: sign * distance,
        point: point.coords.into(),
        normal: normal.into(),
    }
}

fn section_closest(segments: &[Segment], thin: usize, x: [f64; 3]) -> Closest {
    let (a, b) = ((thin + 1) % 3, (thin + 2) % 3);
    let mut at = Point3::from(x);
    at[thin] = segments.first().map_or(x[thin], |s| s.ends[0][thin]);
    let mut best = (f64::INFINITY, at, Vector3::zeros());
    let mut crossings = 0;
    for s in segments {
        let [p, q] = s.ends;
        let along = q - p;
        let t = ((at - p).dot(&along) / along.norm_squared().max(1e-300)).clamp(0.0, 1.0);
        let c = p + along * t;
        let d = (at - c).norm();
        // Ties (a corner shared by two segments) sum their normals: the
        // sum points out of a corner however sharp.
        if d < best.0 - 1e-12 * d {
            best = (d, c, s.normal);
        } else if d <= best.0 + 1e-12 * d {
            best.2 += s.normal;
        }
        // A ray from x along +a crosses this segment (half-open in b).
        if (p[b] > at[b]) != (q[b] > at[b]) {
            let cross_a = p[a] + (at[b] - p[b]) / (q[b] - p[b]) * (q[a] - p[a]);
            if cross_a > at[a] {
                crossings += 1;
            }
        }
    }
    let (distance, point, normal) = best;
    let inside = crossings % 2 == 1;
    let sign = if inside { -1.0 } else { 1.0 };
    let away = at - point;
    let normal = match away.try_normalize(1e-14 * (1.0 + point.coords.norm())) {
        Some(n) => n * sign,
        None => normal.try_normalize(1e-300).unwrap_or(Vector3::zeros()),
    };
    Closest {
        phi: sign * distance,
        point: point.coords.into(),
        normal: normal.into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cylinder(r: f64) -> (Shape, Surface) {
        let shape = Shape::cylinder(r, 0.01);
        let surface = Surface::of(&shape, 1e-3);
        (shape, surface)
    }

    /// A circle's distance is |x − c| − r, to the polygon's sagitta
    /// s²/8r = 6.3·10⁻⁷ m for segments s of 0.5 mm on r = 0.05 m; the
    /// normal is radial to the angle a segment spans, s/r = 0.01 rad.
    #[test]
    fn a_cylinders_section_is_its_circle_to_the_polygons_sagitta() {
        let r = 0.05;
        let (shape, surface) = cylinder(r);
        let pose = Isometry3::translation(0.3, 0.2, 0.005);
        let placed = Placed::new(&shape, &surface, &pose, Some((2, 0.005)));
        for (x, y) in [
            (0.3, 0.2),
            (0.31, 0.21),
            (0.36, 0.2),
            (0.3, 0.26),
            (0.2, 0.1),
        ] {
            let c = placed.closest([x, y, 0.005]);
            let (dx, dy) = (x - 0.3, y - 0.2);
            let rho = (dx * dx + dy * dy).sqrt();
            assert!((c.phi - (rho - r)).abs() < 7e-7, "{x} {y}: {}", c.phi);
            if rho > 1e-3 {
                let radial = [dx / rho, dy / rho];
                assert!((c.normal[0] - radial[0]).abs() < 1e-2, "{c:?}");
                assert!((c.normal[1] - radial[1]).abs() < 1e-2, "{c:?}");
            }
        }
        let [lo, hi] = placed.bounds();
        assert!((lo[0] - 0.25).abs() < 1e-9 && (hi[1] - 0.25).abs() < 1e-9);
    }

    /// A cuboid's distance in 3-D (parry): outside along a face normal,
    /// inside to the nearest face.
    #[test]
    fn a_cuboids_distance_in_3d_is_to_its_nearest_face() {
        let shape = Shape::cuboid([0.2, 0.4, 0.6]);
        let surface = Surface::of(&shape, 0.05);
        let pose = Isometry3::translation(1.0, 1.0, 1.0);
        let placed = Placed::new(&shape, &surface, &pose, None);
        let c = placed.closest([1.3, 1.0, 1.0]);
        assert!((c.phi - 0.2).abs() < 1e-12 && (c.normal[0] - 1.0).abs() < 1e-12);
        let c = placed.closest([1.05, 1.0, 1.0]);
        assert!((c.phi + 0.05).abs() < 1e-12 && (c.normal[0] - 1.0).abs() < 1e-12);
    }

    /// Outside the sharp tip of a 15° wedge the sign is right, and the
    /// normal points out of the tip.
    #[test]
    fn a_sharp_corner_is_outside_beyond_its_tip() {
        let t = 15f64.to_radians().tan();
        let p = |x: f64, y: f64| Point3::new(x, y, 0.0);
        let n = |x: f64, y: f64| Vector3::new(x, y, 0.0).normalize();
        let segments = vec![
            Segment {
                ends: [p(0.0, 0.0), p(1.0, t)],
                normal: n(-t, 1.0),
            },
            Segment {
                ends: [p(1.0, t), p(1.0, -t)],
                normal: n(1.0, 0.0),
            },
            Segment {
                ends: [p(1.0, -t), p(0.0, 0.0)],
                normal: n(-t, -1.0),
            },
        ];
        let placed = Placed::Section {
            segments,
            thin: 2,
            level: 0.0,
        };
        let c = placed.closest([-0.1, 0.0, 0.0]);
        assert!((c.phi - 0.1).abs() < 1e-12 && c.normal[0] < -0.99, "{c:?}");
        let c = placed.closest([0.5, 0.0, 0.0]);
        assert!(c.phi < 0.0 && (c.phi + 0.5 * 15f64.to_radians().sin()).abs() < 1e-12);
        let c = placed.closest([0.5, 0.2, 0.0]);
        assert!(c.phi > 0.0);
    }
}
