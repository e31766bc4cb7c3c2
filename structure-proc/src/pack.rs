//! Laying a flat canopy into its pack at line stretch, the packed start
//! (`structure_section`'s `pack.rs` says why the folds cannot cross): the
//! middle of the canopy flat across the pack's top, the seams straight
//! down the axis from there, each ring pleated into the pack at its own
//! height.

use crate::rings::Ring;
use structure_section::Pleats;

/// Moves the flat canopy `points` (in the plane z = 0, its axis the z axis,
/// ring after ring as `rings` lays them out, each with its first node)
/// into the pack of `pleats`, across to where `Pleats::place` puts each
/// node in its ring, and down so that every seam keeps its flat length:
/// from one ring to the next at flat radii r and r + Δr, its nodes at
/// ρ = min(r, a) from the axis, the seam drops √(Δr² − Δρ²).
pub fn pack_canopy(points: &mut [f64], rings: &[(usize, Ring)], pleats: &Pleats) {
    let Some(&(first, ring)) = rings.first() else {
        return;
    };
    // A centre node comes before the first ring, at radius 0.
    let mut last = if first > 0 { 0.0 } else { ring.radius };
    let mut depth = 0.0;
    for &(start, ring) in rings {
        let reach = |r: f64| r.min(pleats.radius);
        let (dr, drho) = (ring.radius - last, reach(ring.radius) - reach(last));
        depth += (dr * dr - drho * drho).max(0.0).sqrt();
        last = ring.radius;
        for k in 0..ring.nodes {
            let [x, y] = pleats.place(ring.radius, ring.nodes, k);
            let p = &mut points[3 * (start + k)..3 * (start + k) + 3];
            p.copy_from_slice(&[x, y, -depth]);
        }
    }
}
