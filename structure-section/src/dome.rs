//! A pre-shaped start (issue 23, item 2): the flat canopy laid on a
//! spherical cap. Distances from the apex along the fabric (the gore seams)
//! keep their flat lengths, so a point at flat distance r from the axis
//! lands at polar angle r/R on a sphere of radius R, and the skirt, at
//! r = D₀/2, at the projected radius R·sin(D₀/2R). The hoops come out
//! shorter than their flat length, gathered as on a real inflated canopy,
//! whose projected diameter is 0.67–0.70 D₀ for flat circular canopies
//! (Knacke, *Parachute Recovery Systems Design Manual*, 1992, table 5-1).

use crate::parachute::CanopyGeometry;
use std::f64::consts::FRAC_PI_2;

impl CanopyGeometry {
    /// The radius R [m] of the sphere on which the canopy, laid with its
    /// seams at their flat lengths, is `projected` [m] across the skirt
    /// (for a cross, across the arm ends' middles): the root of
    /// sin(x)/x = projected/D₀ with x = D₀/2R. Refused where the canopy
    /// would reach past the sphere's equator and curl in, or is no narrower
    /// than flat.
    pub fn dome_radius(&self, projected: f64) -> Result<f64, String> {
        let half = 0.5 * self.diameter;
        // Farthest fabric reaches polar angle x·r_max/(D₀/2) ≤ π/2.
        let x_max = FRAC_PI_2 * half / self.skirt_radius();
        let narrowest = self.diameter * x_max.sin() / x_max;
        if !(projected.is_finite() && projected >= narrowest && projected < self.diameter) {
            return Err(format!(
                "preshaped_diameter = {projected} m must lie from {narrowest:.3} m (the canopy's \
                 edge on the sphere's equator) to under D₀ = {:.3} m (flat: leave it out)",
                self.diameter
            ));
        }
        let q = projected / self.diameter;
        // sin(x)/x falls from 1 at 0 to sin(x_max)/x_max: bisect.
        let (mut lo, mut hi) = (0.0, x_max);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if mid.sin() / mid > q {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Ok(half / (0.5 * (lo + hi)))
    }
}

#[cfg(test)]
mod tests {
    use crate::parachute::ParachuteModel;

    #[test]
    fn the_skirt_lands_at_the_asked_projected_diameter() {
        let g = ParachuteModel::C9.geometry().unwrap();
        for ratio in [0.64, 0.7, 0.9, 0.999] {
            let r = g.dome_radius(ratio * g.diameter).unwrap();
            let projected = 2.0 * r * (0.5 * g.diameter / r).sin();
            assert!((projected / g.diameter - ratio).abs() < 1e-12, "{ratio}");
        }
        // A hemisphere: D_p/D₀ = 2/π exactly, the narrowest allowed.
        let hemisphere = g.dome_radius(g.diameter * 2.0 / std::f64::consts::PI);
        let r = hemisphere.unwrap();
        assert!((r - g.diameter / std::f64::consts::PI).abs() < 1e-9 * r);
        assert!(g.dome_radius(0.6 * g.diameter).is_err());
        assert!(g.dome_radius(g.diameter).is_err());
        assert!(g.dome_radius(f64::NAN).is_err());
    }
}
