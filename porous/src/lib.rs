//! The porous free-stream load: a uniform stream passes through the fabric as
//! through a porous medium, and the Darcy–Forchheimer (Ergun) law gives the
//! pressure jump across every canopy triangle (thesis eqs. 6–10). No flow
//! field is solved.
//!
//! One law for every process that applies it: fluid-proc's porous free-stream
//! model sends the jumps to the structure, and a structure solver with
//! `[structure.porous]` evaluates them itself at every force evaluation.

/// The law's parameters: the air's stream and properties, and the fabric's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Params {
    /// Free-stream velocity of the air [m/s].
    pub free_stream: [f64; 3],
    /// Air density ρ [kg/m³].
    pub density: f64,
    /// Air dynamic viscosity μ [Pa·s].
    pub viscosity: f64,
    /// Fabric porosity ε (0 < ε < 1), thesis eqs. (7)–(9).
    pub porosity: f64,
    /// Characteristic (Ergun) diameter D [m], thesis eqs. (7)–(8).
    pub diameter: f64,
    /// Fabric thickness e [m], thesis eq. (6).
    pub thickness: f64,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Porous {
    /// Free-stream velocity of the air [m/s].
    pub free_stream: [f64; 3],
    /// Darcy coefficient A(ε, μ) [Pa·s/m²], thesis eq. (7).
    pub a: f64,
    /// Forchheimer coefficient B(ε, μ) [Pa·s²/m³], thesis eq. (8).
    pub b: f64,
    pub porosity: f64,
    pub thickness: f64,
}

impl Porous {
    pub fn new(s: &Params) -> Porous {
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

    /// Pressure jump on triangle `tri` of a surface at positions `x` moving
    /// with velocities `v` (xyz per vertex). Its load is `jump · area · n`,
    /// with n the unit normal of the vertex order.
    pub fn triangle_jump(&self, x: &[f64], v: &[f64], tri: &[usize; 3]) -> f64 {
        self.seepage(x, v, tri)
            .map_or(0.0, |s| self.jump(s.forchheimer))
    }

    /// How the load on `tri` resists the triangle's motion through the air:
    /// the load on each vertex changes with each vertex's velocity by
    /// −c·n·nᵀ, and this returns (c [N·s/m], n). From eqs. (6), (9), (10):
    /// c = e·ε·(A + 2B·|v_f|)·area/9, the load's third on each vertex taking a
    /// third of each vertex's velocity. Implicit schemes need it where the
    /// stream damps the canopy strongly.
    pub fn triangle_damping(&self, x: &[f64], v: &[f64], tri: &[usize; 3]) -> (f64, [f64; 3]) {
        match self.seepage(x, v, tri) {
            None => (0.0, [0.0; 3]),
            Some(s) => {
                let slope = self.thickness * (self.a + 2.0 * self.b * s.forchheimer.abs());
                (slope * self.porosity * s.area / 9.0, s.normal)
            }
        }
    }

    /// The air's flow through `tri`; None for a degenerate triangle.
    fn seepage(&self, x: &[f64], v: &[f64], tri: &[usize; 3]) -> Option<Seepage> {
        let n = area_normal2(x, tri);
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        if len == 0.0 {
            return None;
        }
        let normal = n.map(|c| c / len);
        // Eq. (10): the seepage velocity is the normal part of the air's velocity
        // relative to the triangle (its vertices' mean velocity).
        let mut v_normal = 0.0;
        for c in 0..3 {
            let v_centre = (v[3 * tri[0] + c] + v[3 * tri[1] + c] + v[3 * tri[2] + c]) / 3.0;
            v_normal += normal[c] * (self.free_stream[c] - v_centre);
        }
        Some(Seepage {
            normal,
            area: 0.5 * len,
            forchheimer: self.porosity * v_normal, // eq. (9): v_f = ε·v_pore
        })
    }

    /// [`triangle_jump`](Self::triangle_jump) of every triangle into `out`.
    pub fn pressure(&self, triangles: &[[usize; 3]], x: &[f64], v: &[f64], out: &mut [f64]) {
        for (tri, o) in triangles.iter().zip(out.iter_mut()) {
            *o = self.triangle_jump(x, v, tri);
        }
    }
}

/// A triangle's unit normal, its area [m²] and the Forchheimer velocity v_f
/// of the air through it along the normal [m/s].
struct Seepage {
    normal: [f64; 3],
    area: f64,
    forchheimer: f64,
}

/// (x1 − x0) × (x2 − x0) of triangle `tri` (xyz per vertex in `x`): twice the
/// area times the unit normal of the vertex order.
#[inline]
pub fn area_normal2(x: &[f64], tri: &[usize; 3]) -> [f64; 3] {
    let p = |k: usize, c: usize| x[3 * tri[k] + c];
    let e1 = [p(1, 0) - p(0, 0), p(1, 1) - p(0, 1), p(1, 2) - p(0, 2)];
    let e2 = [p(2, 0) - p(0, 0), p(2, 1) - p(0, 1), p(2, 2) - p(0, 2)];
    [
        e1[1] * e2[2] - e1[2] * e2[1],
        e1[2] * e2[0] - e1[0] * e2[2],
        e1[0] * e2[1] - e1[1] * e2[0],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn section(v: f64) -> Params {
        Params {
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
        // Thesis eqs. (6)–(9) evaluated by hand for ε = 0.4, D = 2 mm, μ = 1.8e-5, ρ = 1.2.
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
        // Thesis eq. (10): a stream along the fabric exerts no load.
        let mut s = section(0.0);
        s.free_stream = [30.0, -20.0, 0.0];
        let p = Porous::new(&s);
        let x = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
        let mut out = [1.0];
        p.pressure(&[[0, 1, 2]], &x, &[0.0; 9], &mut out);
        assert_eq!(out[0], 0.0);
    }
}
