//! A packed start (issue 46, item 1): the canopy at line stretch as a long
//! narrow bundle, its flat pattern gathered into a pack of a given
//! diameter 2a. The middle of the canopy, as wide as the pack, lies flat
//! across its top; from there each gore seam runs straight down the
//! bundle's side at its flat length to the skirt, so a point at flat
//! distance r > a from the axis lies about r − a below the top. Each ring of the
//! flat pattern keeps its length by folding: a ring no wider than the
//! pack is a circle of its own radius; a wider one runs in and out of
//! the pack in pleats whose folds lie along the axis, P of them around,
//! every wall straight from a fold at the pack's radius a in to a fold at
//! the fold radius ρ and out again. A ring is then star-shaped about the
//! axis (its polar angle only grows), so it cannot cross itself, and two
//! rings lie at different heights.

use crate::parachute::{CanopyGeometry, CanopyShape};
use std::f64::consts::PI;

/// The deepest fold at the skirt, as a part of the pack's radius: the
/// inner folds stay a quarter of the radius off the axis, so that they
/// do not crowd it and the walls of neighbouring pleats stay apart.
pub const DEEPEST_FOLD: f64 = 0.75;

/// More pleats around than this is a pack too narrow to mesh.
pub const MOST_PLEATS: u32 = 4096;

/// The folds of a packed canopy.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pleats {
    /// Pleats in each gore; a gore's seams are outer folds.
    pub per_gore: u32,
    /// Pleats around, P: `per_gore` times the gores.
    pub count: u32,
    /// The pack's radius a [m]: where the outer folds lie.
    pub radius: f64,
}

impl CanopyGeometry {
    /// The fewest pleats per gore that pack the canopy into `diameter` [m]
    /// with the skirt's folds reaching in no deeper than [`DEEPEST_FOLD`]
    /// of the pack's radius. Refused for a cross, and for a pack no
    /// narrower than the canopy or needing more than [`MOST_PLEATS`].
    pub fn pleats(&self, diameter: f64) -> Result<Pleats, String> {
        let radius = 0.5 * diameter;
        let skirt = 0.5 * self.diameter;
        if self.shape == CanopyShape::Cross {
            return Err("a packed start is made for circular canopies, not a cross".into());
        }
        if !(diameter.is_finite() && diameter > 0.0 && radius < skirt) {
            return Err(format!(
                "pack_diameter = {diameter} m must lie above 0 and under D₀ = {:.3} m",
                self.diameter
            ));
        }
        let gores = self.gores.max(1);
        let mut per_gore = 1;
        while per_gore * gores <= MOST_PLEATS {
            let pleats = Pleats {
                per_gore,
                count: per_gore * gores,
                radius,
            };
            // A skirt's pleat has two walls of half its share of the ring.
            let wall = PI * skirt / pleats.count as f64;
            if pleats.fold_radius(wall) >= (1.0 - DEEPEST_FOLD) * radius {
                return Ok(pleats);
            }
            per_gore += 1;
        }
        Err(format!(
            "pack_diameter = {diameter} m needs more than {MOST_PLEATS} pleats around \
             the {:.3} m canopy: widen the pack",
            self.diameter
        ))
    }
}

impl Pleats {
    /// The fold radius ρ of a pleat whose walls are `wall` long [m]: from
    /// an outer fold at (a, 0) to an inner one at (ρ, π/P) in polar
    /// coordinates, wall² = a² + ρ² − 2aρ cos(π/P), the root inside.
    /// NaN where the wall is too long to fold inside the pack.
    pub fn fold_radius(&self, wall: f64) -> f64 {
        let half = PI / self.count as f64;
        let a = self.radius;
        a * half.cos() - (wall * wall - (a * half.sin()).powi(2)).sqrt()
    }

    /// Where node `k` of a ring of `nodes` nodes at flat radius `r` lies
    /// across the pack [m]: on a circle of radius r where the ring fits in
    /// the pack, else on its pleats. A pleated ring has an even number of
    /// nodes in each pleat (`nodes` a multiple of 2P), the first on an
    /// outer fold and the middle one on the inner fold; each wall is the
    /// flat ring's chords end to end, so every edge keeps its length.
    pub fn place(&self, r: f64, nodes: usize, k: usize) -> [f64; 2] {
        let turn = 2.0 * PI / nodes as f64;
        if r <= self.radius {
            let angle = turn * k as f64;
            return [r * angle.cos(), r * angle.sin()];
        }
        let per_pleat = nodes / self.count as usize;
        let half = per_pleat / 2;
        let chord = 2.0 * r * (0.5 * turn).sin();
        let fold = self.fold_radius(half as f64 * chord);
        let (pleat, at) = (k / per_pleat, k % per_pleat);
        let step = 2.0 * PI / self.count as f64;
        let polar = |rho: f64, angle: f64| [rho * angle.cos(), rho * angle.sin()];
        let outer = polar(self.radius, step * pleat as f64);
        let inner = polar(fold, step * (pleat as f64 + 0.5));
        let next = polar(self.radius, step * (pleat + 1) as f64);
        let (from, to, s) = match at <= half {
            true => (outer, inner, at as f64 / half as f64),
            false => (inner, next, (at - half) as f64 / half as f64),
        };
        [
            from[0] + s * (to[0] - from[0]),
            from[1] + s * (to[1] - from[1]),
        ]
    }

    /// The nodes of a ring at flat radius `r` that would have `flat`
    /// nodes unpacked: as many where it fits in the pack, else the nearest
    /// multiple of 2P, at least 2P.
    pub fn ring_nodes(&self, r: f64, flat: usize) -> usize {
        if r <= self.radius {
            return flat;
        }
        let two_p = 2 * self.count as usize;
        ((flat as f64 / two_p as f64).round() as usize).max(1) * two_p
    }
}

#[cfg(test)]
mod tests {
    use crate::parachute::ParachuteModel;

    fn c9() -> crate::parachute::CanopyGeometry {
        ParachuteModel::C9.geometry().unwrap()
    }

    /// Each edge of a pleated ring is the flat ring's chord 2r·sin(π/n),
    /// and the first node of every gore (a seam) lies on the pack's radius.
    #[test]
    fn a_pleated_ring_keeps_its_edges_and_puts_seams_outside() {
        let g = c9();
        let pleats = g.pleats(0.4).unwrap();
        let r = 0.5 * g.diameter;
        let n = pleats.ring_nodes(r, 4 * g.gores as usize);
        assert_eq!(n % (2 * pleats.count as usize), 0);
        let chord = 2.0 * r * (std::f64::consts::PI / n as f64).sin();
        for k in 0..n {
            let [x0, y0] = pleats.place(r, n, k);
            let [x1, y1] = pleats.place(r, n, (k + 1) % n);
            assert!(
                ((x1 - x0).hypot(y1 - y0) - chord).abs() < 1e-12 * r,
                "edge {k}"
            );
            let reach = x0.hypot(y0);
            assert!(
                reach <= pleats.radius * (1.0 + 1e-12),
                "node {k} outside the pack"
            );
        }
        for seam in (0..n).step_by(n / g.gores as usize) {
            let [x, y] = pleats.place(r, n, seam);
            assert!((x.hypot(y) - pleats.radius).abs() < 1e-12);
        }
    }

    /// The fewest pleats: one fewer would fold the skirt deeper than
    /// DEEPEST_FOLD of the radius; the folds chosen stay inside it.
    #[test]
    fn the_fewest_pleats_that_keep_the_folds_off_the_axis() {
        let g = c9();
        let p = g.pleats(0.4).unwrap();
        let skirt = 0.5 * g.diameter;
        let least = (1.0 - super::DEEPEST_FOLD) * p.radius;
        let wall = |count: u32| std::f64::consts::PI * skirt / count as f64;
        assert!(p.fold_radius(wall(p.count)) >= least);
        let fewer = super::Pleats {
            count: p.count - g.gores,
            ..p
        };
        // Deeper than allowed, or NaN: the wall does not fold inside the pack.
        let deeper = fewer.fold_radius(wall(fewer.count));
        assert!(deeper.is_nan() || deeper < least, "{deeper}");
    }

    #[test]
    fn packs_no_narrower_than_the_canopy_or_of_a_cross_are_refused() {
        let g = c9();
        assert!(g.pleats(g.diameter).is_err());
        assert!(g.pleats(0.0).is_err());
        assert!(g.pleats(1e-4).unwrap_err().contains("widen the pack"));
        let cross = ParachuteModel::T11.geometry().unwrap();
        assert!(cross.pleats(0.5).unwrap_err().contains("circular"));
    }
}
