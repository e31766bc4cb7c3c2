//! Counting intersections of a structure at one moment: triangle pairs that
//! cross, segments through triangles, segments through segments. The tests
//! read every output frame with it; it shares nothing with the collision
//! pass but the surface (parry's BVH and GJK tests, not our tree and
//! cubic), so it can catch what the pass misses.

use super::surface::Surface;
use nalgebra::{Isometry3, Point3};
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy};
use parry3d_f64::query;
use parry3d_f64::query::details::closest_points_segment_segment_with_locations_nD;
use parry3d_f64::shape::{Segment, SegmentPointLocation, Triangle};

/// Intersections found, by the kinds of the two primitives.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Intersections {
    pub triangle_triangle: usize,
    pub segment_triangle: usize,
    pub segment_segment: usize,
}

impl Intersections {
    pub fn total(&self) -> usize {
        self.triangle_triangle + self.segment_triangle + self.segment_segment
    }
}

/// Segments closer than this are crossing [m]: round-off at scene sizes of metres.
const CROSSING: f64 = 1e-12;

/// The intersections of `surface` with its nodes at `x` (xyz per node).
/// Primitives that share a node are not compared.
pub fn intersections(surface: &Surface, x: &[f64]) -> Intersections {
    let p = |n: usize| Point3::new(x[3 * n], x[3 * n + 1], x[3 * n + 2]);
    let leaves: Vec<Aabb> = (0..surface.len())
        .map(|k| Aabb::from_points(surface.vertices(k).iter().map(|&n| p(n))))
        .collect();
    let bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &leaves);
    let mut found = Intersections::default();
    let id = Isometry3::identity();
    let pairs: std::collections::BTreeSet<(usize, usize)> = bvh
        .leaf_pairs(&bvh, |l, r| l.intersects(r))
        .map(|(a, b)| ((a.min(b)) as usize, (a.max(b)) as usize))
        .filter(|(a, b)| a != b)
        .collect();
    for (a, b) in pairs {
        if surface
            .vertices(a)
            .iter()
            .any(|n| surface.vertices(b).contains(n))
        {
            continue;
        }
        let (ta, tb) = (surface.is_triangle(a), surface.is_triangle(b));
        let tri = |k: usize| {
            let [i, j, l] = surface.nodes[k];
            Triangle::new(p(i), p(j), p(l))
        };
        let seg = |k: usize| {
            let v = surface.vertices(k);
            Segment::new(p(v[0]), p(v[1]))
        };
        match (ta, tb) {
            (true, true) => {
                if query::intersection_test(&id, &tri(a), &id, &tri(b)).unwrap_or(false) {
                    found.triangle_triangle += 1;
                }
            }
            (true, false) | (false, true) => {
                let (t, s) = if ta { (a, b) } else { (b, a) };
                if query::intersection_test(&id, &tri(t), &id, &seg(s)).unwrap_or(false) {
                    found.segment_triangle += 1;
                }
            }
            (false, false) => {
                let (sa, sb) = (seg(a), seg(b));
                let (la, lb) = closest_points_segment_segment_with_locations_nD(
                    (&sa.a, &sa.b),
                    (&sb.a, &sb.b),
                );
                let on = |s: &Segment, l: SegmentPointLocation| match l {
                    SegmentPointLocation::OnVertex(0) => s.a,
                    SegmentPointLocation::OnVertex(_) => s.b,
                    SegmentPointLocation::OnEdge([u, v]) => {
                        Point3::from(s.a.coords * u + s.b.coords * v)
                    }
                };
                if (on(&sa, la) - on(&sb, lb)).norm() < CROSSING {
                    found.segment_segment += 1;
                }
            }
        }
    }
    found
}

/// How many of `triangles` (over the nodes at `x`, xyz per node) cross
/// the shape `shape` posed by `pose` (parry's GJK test).
pub fn triangles_through(
    shape: &dyn parry3d_f64::shape::Shape,
    pose: &Isometry3<f64>,
    x: &[f64],
    triangles: &[[usize; 3]],
) -> usize {
    let p = |n: usize| Point3::new(x[3 * n], x[3 * n + 1], x[3 * n + 2]);
    triangles
        .iter()
        .filter(|t| {
            let tri = Triangle::new(p(t[0]), p(t[1]), p(t[2]));
            query::intersection_test(pose, shape, &Isometry3::identity(), &tri).unwrap_or(false)
        })
        .count()
}
