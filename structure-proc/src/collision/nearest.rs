//! The nearest points of a point and a triangle, and of two segments, as
//! the weights the narrow phase uses (Ericson, *Real-Time Collision
//! Detection*, 2005, §5.1.5 and §5.1.9). They run for every candidate pair
//! of every step, so they are written out in f64 with no allocation and
//! no generic dispatch; `intersections.rs` keeps parry's versions as the
//! independent check.

use super::geometry::V3;

/// The barycentric coordinates (α, β, γ) of the point of the triangle
/// abc nearest to p, by Voronoi regions (Ericson §5.1.5). A degenerate
/// (zero-area) triangle that leaves no region gives its nearest vertex.
#[inline]
pub fn point_triangle(p: &V3, a: &V3, b: &V3, c: &V3) -> [f64; 3] {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(&ap), ac.dot(&ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return [1.0, 0.0, 0.0];
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(&bp), ac.dot(&bp));
    if d3 >= 0.0 && d4 <= d3 {
        return [0.0, 1.0, 0.0];
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return [1.0 - v, v, 0.0];
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(&cp), ac.dot(&cp));
    if d6 >= 0.0 && d5 <= d6 {
        return [0.0, 0.0, 1.0];
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return [1.0 - w, 0.0, w];
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return [0.0, 1.0 - w, w];
    }
    let sum = va + vb + vc;
    if sum > 0.0 && sum.is_finite() {
        let (v, w) = (vb / sum, vc / sum);
        return [1.0 - v - w, v, w];
    }
    let d = [ap, bp, cp].map(|e| e.norm_squared());
    let k = (0..3).min_by(|&i, &j| d[i].total_cmp(&d[j])).unwrap_or(0);
    let mut w = [0.0; 3];
    w[k] = 1.0;
    w
}

/// Parameters (s, t) in [0, 1]² of the nearest points p₁ + s(q₁ − p₁) and
/// p₂ + t(q₂ − p₂) of two segments (Ericson §5.1.9): the lines' nearest
/// points clamped to the first segment, the second's nearest to that, and
/// the first's again if the second clamped. Parallel segments (a
/// vanishing determinant relative to the lengths) start from s = 0.
#[inline]
pub fn segment_segment(p1: &V3, q1: &V3, p2: &V3, q2: &V3) -> (f64, f64) {
    let (d1, d2, r) = (q1 - p1, q2 - p2, p1 - p2);
    let (a, e, f) = (d1.norm_squared(), d2.norm_squared(), d2.dot(&r));
    if a == 0.0 && e == 0.0 {
        return (0.0, 0.0);
    }
    if a == 0.0 {
        return (0.0, (f / e).clamp(0.0, 1.0));
    }
    let c = d1.dot(&r);
    if e == 0.0 {
        return ((-c / a).clamp(0.0, 1.0), 0.0);
    }
    let b = d1.dot(&d2);
    let det = a * e - b * b;
    let mut s = if det > 1e-14 * a * e {
        ((b * f - c * e) / det).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let mut t = (b * s + f) / e;
    if t < 0.0 {
        t = 0.0;
        s = (-c / a).clamp(0.0, 1.0);
    } else if t > 1.0 {
        t = 1.0;
        s = ((b - c) / a).clamp(0.0, 1.0);
    }
    (s, t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Point3;
    use parry3d_f64::query::details::closest_points_segment_segment_with_locations_nD;
    use parry3d_f64::query::PointQuery;
    use parry3d_f64::shape::Triangle;

    /// A fixed pseudo-random sequence in [−1, 1).
    fn points(seed: u64, n: usize) -> Vec<V3> {
        let mut s = seed;
        let mut next = move || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        };
        (0..n).map(|_| V3::new(next(), next(), next())).collect()
    }

    #[test]
    fn point_triangle_agrees_with_parry_to_round_off() {
        let v = points(7, 4 * 20_000);
        for q in v.chunks(4) {
            let w = point_triangle(&q[0], &q[1], &q[2], &q[3]);
            let on = q[1] * w[0] + q[2] * w[1] + q[3] * w[2];
            let tri = Triangle::new(q[1].into(), q[2].into(), q[3].into());
            let want = tri.distance_to_local_point(&Point3::from(q[0]), false);
            assert!(
                w.iter().all(|&x| (-1e-15..=1.0 + 1e-15).contains(&x)),
                "{w:?}"
            );
            assert!(((q[0] - on).norm() - want).abs() < 1e-12, "{q:?}");
        }
    }

    #[test]
    fn segment_segment_agrees_with_parry_to_round_off() {
        let mut v = points(11, 4 * 20_000);
        // Parallel and collinear pairs too.
        for q in v.chunks_mut(4).take(2_000) {
            q[3] = q[2] + (q[1] - q[0]) * 0.7;
        }
        for q in v.chunks(4) {
            let (s, t) = segment_segment(&q[0], &q[1], &q[2], &q[3]);
            let d = (q[0] + (q[1] - q[0]) * s - q[2] - (q[3] - q[2]) * t).norm();
            let pts = [q[0], q[1], q[2], q[3]].map(Point3::from);
            let (a, b) = closest_points_segment_segment_with_locations_nD(
                (&pts[0], &pts[1]),
                (&pts[2], &pts[3]),
            );
            let at = |p: &Point3<f64>, q: &Point3<f64>, l| match l {
                parry3d_f64::shape::SegmentPointLocation::OnVertex(0) => *p,
                parry3d_f64::shape::SegmentPointLocation::OnVertex(_) => *q,
                parry3d_f64::shape::SegmentPointLocation::OnEdge([u, w]) => {
                    Point3::from(p.coords * u + q.coords * w)
                }
            };
            let want = (at(&pts[0], &pts[1], a) - at(&pts[2], &pts[3], b)).norm();
            assert!((d - want).abs() < 1e-12, "{d} against {want} for {q:?}");
        }
    }
}
