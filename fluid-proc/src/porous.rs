//! The porous free-stream model: a uniform stream passes through the fabric as
//! through a porous medium, and the Darcy–Forchheimer (Ergun) law gives the
//! pressure jump across every canopy triangle (seed 003 eqs. 6–10). No flow
//! field is solved.

use coupler::scenario::FluidSection;

pub struct Porous {
    /// Free-stream velocity of the air [m/s].
    pub free_stream: [f64; 3],
    /// Darcy coefficient A(ε, μ) [Pa·s/m²], seed 003 eq. (7).
    pub a: f64,
    /// Forchheimer coefficient B(ε, μ) [Pa·s²/m³], seed 003 eq. (8).
    pub b: f64,
    pub porosity: f64,
    pub thickness: f64,
}

impl Porous {
    pub fn new(s: &FluidSection) -> Porous {
        let (eps, d, mu, rho) = (s.porosity, s.diameter, s.viscosity, s.density);
        Porous {
            free_stream: s.free_stream,
            a: mu * 150.0 * (1.0 - eps).powi(2) / (d * d * eps * eps),
            b: rho * 1.75 * (1.0 - eps) / (d * eps * eps),
            porosity: eps,
            thickness: s.thickness,
        }
    }

    /// Signed pressure jump ΔP (eq. 6) for a Forchheimer velocity v_f along the normal.
    /// The sign follows v_f, so the load pushes the fabric along the flow through it.
    pub fn jump(&self, v_f: f64) -> f64 {
        self.thickness * (self.a * v_f + self.b * v_f * v_f.abs())
    }

    /// Pressure jump on every triangle (`triangles`: 3 vertex indices each;
    /// `x`, `v`: xyz per vertex). The load on a triangle is `out[t] · area · n`,
    /// with n the unit normal of its vertex order.
    pub fn pressure(&self, triangles: &[[usize; 3]], x: &[f64], v: &[f64], out: &mut [f64]) {
        for (tri, o) in triangles.iter().zip(out.iter_mut()) {
            let p = |k: usize, c: usize| x[3 * tri[k] + c];
            let e1 = [p(1, 0) - p(0, 0), p(1, 1) - p(0, 1), p(1, 2) - p(0, 2)];
            let e2 = [p(2, 0) - p(0, 0), p(2, 1) - p(0, 1), p(2, 2) - p(0, 2)];
            let n = [
                e1[1] * e2[2] - e1[2] * e2[1],
                e1[2] * e2[0] - e1[0] * e2[2],
                e1[0] * e2[1] - e1[1] * e2[0],
            ];
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            if len == 0.0 {
                *o = 0.0;
                continue;
            }
            // Eq. (10): the seepage velocity is the normal part of the air's velocity
            // relative to the triangle (its vertices' mean velocity).
            let mut v_normal = 0.0;
            for c in 0..3 {
                let v_centre = (v[3 * tri[0] + c] + v[3 * tri[1] + c] + v[3 * tri[2] + c]) / 3.0;
                v_normal += n[c] / len * (self.free_stream[c] - v_centre);
            }
            *o = self.jump(self.porosity * v_normal); // eq. (9): v_f = ε·v_pore
        }
    }
}

/// Triangles from the flat index field the structure sends once.
pub fn triangles_from_field(field: &[f64]) -> Vec<[usize; 3]> {
    field
        .chunks_exact(3)
        .map(|t| [t[0] as usize, t[1] as usize, t[2] as usize])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use coupler::scenario::fluid::FluidModel;

    fn section(v: f64) -> FluidSection {
        FluidSection {
            model: FluidModel::PorousFreeStream,
            free_stream: [0.0, 0.0, v],
            density: 1.2,
            viscosity: 1.8e-5,
            porosity: 0.4,
            diameter: 2e-3,
            thickness: 1e-4,
        }
    }

    #[test]
    fn jump_follows_the_ergun_law() {
        // Seed 003 eqs. (6)–(9) evaluated by hand for ε = 0.4, D = 2 mm, μ = 1.8e-5, ρ = 1.2.
        let p = Porous::new(&section(10.0));
        let a = 1.8e-5 * 150.0 * 0.36 / (4e-6 * 0.16);
        let b = 1.2 * 1.75 * 0.6 / (2e-3 * 0.16);
        assert!((p.a / a - 1.0).abs() < 1e-14 && (p.b / b - 1.0).abs() < 1e-14);
        // A flat triangle facing +z in a +z stream of 10 m/s: v_f = ε·10 = 4 m/s.
        let tri = [[0, 1, 2]];
        let x = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
        let mut out = [0.0];
        p.pressure(&tri, &x, &[0.0; 9], &mut out);
        let expected = 1e-4 * (a * 4.0 + b * 16.0);
        assert!(
            (out[0] / expected - 1.0).abs() < 1e-14,
            "{} vs {expected}",
            out[0]
        );
        // Reversed vertex order flips the normal and so the sign of the jump;
        // a triangle moving with the air sees no seepage and no load.
        p.pressure(&[[0, 2, 1]], &x, &[0.0; 9], &mut out);
        assert!((out[0] + expected).abs() < 1e-12 * expected);
        let v = [0.0, 0.0, 10.0, 0.0, 0.0, 10.0, 0.0, 0.0, 10.0];
        p.pressure(&tri, &x, &v, &mut out);
        assert_eq!(out[0], 0.0);
    }

    #[test]
    fn only_the_normal_component_seeps_through() {
        // Seed 003 eq. (10): a stream along the fabric exerts no load.
        let mut s = section(0.0);
        s.free_stream = [30.0, -20.0, 0.0];
        let p = Porous::new(&s);
        let x = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
        let mut out = [1.0];
        p.pressure(&[[0, 1, 2]], &x, &[0.0; 9], &mut out);
        assert_eq!(out[0], 0.0);
    }
}
