//! Laying a flat canopy on a spherical cap, the pre-shaped start
//! (`structure_section`'s `dome_radius` finds the sphere).

/// Moves the flat canopy `points` (in the plane z = 0, its axis the z axis)
/// onto the sphere of `radius` whose top is the origin: a point at distance
/// r from the axis goes to polar angle r/R, so lengths along the radial
/// seams are kept and every point's depth below the apex is R(1 − cos r/R).
pub fn lay_on_dome(points: &mut [f64], radius: f64) {
    for p in points.chunks_exact_mut(3) {
        let r = p[0].hypot(p[1]);
        if r == 0.0 {
            continue;
        }
        let angle = r / radius;
        let scale = radius * angle.sin() / r;
        p[0] *= scale;
        p[1] *= scale;
        p[2] = -radius * (1.0 - angle.cos());
    }
}

/// How far below the canopy's top the suspension lines of `length` from
/// the `skirt` nodes meet on the axis, with the tightest line just taut:
/// min over the lines of depth + √(L² − ρ²), ρ the node's distance from
/// the axis.
pub fn confluence_depth(points: &[f64], skirt: &[usize], length: f64) -> f64 {
    skirt
        .iter()
        .map(|&n| {
            let p = &points[3 * n..3 * n + 3];
            let reach = p[0].hypot(p[1]);
            -p[2] + (length * length - reach * reach).sqrt()
        })
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seams_keep_their_length_and_points_lie_on_the_sphere() {
        let radius = 3.0;
        // A radial seam of ten equal pieces of 0.4 m, flat.
        let mut points: Vec<f64> = (0..=10)
            .flat_map(|i| {
                let r = 0.4 * i as f64;
                [0.6 * r, 0.8 * r, 0.0]
            })
            .collect();
        lay_on_dome(&mut points, radius);
        for p in points.chunks_exact(3) {
            let from_centre = (p[0] * p[0] + p[1] * p[1] + (p[2] + radius).powi(2)).sqrt();
            assert!((from_centre - radius).abs() < 1e-12);
        }
        // Arc length from the apex: R times the polar angle, 0.4 m per piece.
        for (i, p) in points.chunks_exact(3).enumerate() {
            let angle = (p[0].hypot(p[1])).atan2(p[2] + radius);
            assert!((radius * angle - 0.4 * i as f64).abs() < 1e-12);
        }
    }
}
