//! The ideal gas of the compressible Euler equations, dissertation eqs.
//! (2.20)–(2.24): the conserved state U = (ρ, ρu, ρv, ρw, E), the
//! equation of state p = (γ − 1)ρe (eq. 2.21), the flux along an axis
//! (F, G, H of eq. 2.24), and the eigen-decomposition A = RΛL of the flux
//! Jacobian (eqs. 3.11–3.16) that the characteristic WENO5 scheme projects
//! onto.
//!
//! The seed writes R for the 1-D system (eq. 3.13); in 3-D the flux along
//! axis d has the same acoustic pair u_d ∓ c and three fields moving at
//! u_d: the entropy wave and two shear waves (Toro, *Riemann Solvers and
//! Numerical Methods for Fluid Dynamics*, 3rd ed., §3.2.3). The vectors
//! are written for d = x; another axis permutes the momentum components
//! first ([`Gas::rotated`]), so one set of formulas serves all three.

/// A conserved state (ρ, ρu, ρv, ρw, E).
pub type State = [f64; 5];

/// An ideal gas with ratio of specific heats γ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gas {
    pub gamma: f64,
}

/// Density, velocity and pressure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Primitive {
    pub density: f64,
    pub velocity: [f64; 3],
    pub pressure: f64,
}

impl Gas {
    /// The conserved state of a primitive one: E = p/(γ − 1) + ½ρ|u|² (eq. 2.21).
    pub fn conserved(&self, w: Primitive) -> State {
        let [u, v, z] = w.velocity;
        let rho = w.density;
        let kinetic = 0.5 * rho * (u * u + v * v + z * z);
        [
            rho,
            rho * u,
            rho * v,
            rho * z,
            w.pressure / (self.gamma - 1.0) + kinetic,
        ]
    }

    pub fn primitive(&self, s: &State) -> Primitive {
        let rho = s[0];
        let velocity = [s[1] / rho, s[2] / rho, s[3] / rho];
        Primitive {
            density: rho,
            velocity,
            pressure: self.pressure(s),
        }
    }

    /// p = (γ − 1)(E − ½|m|²/ρ), eq. (2.21).
    #[inline(always)]
    pub fn pressure(&self, s: &State) -> f64 {
        let m2 = s[1] * s[1] + s[2] * s[2] + s[3] * s[3];
        (self.gamma - 1.0) * (s[4] - 0.5 * m2 / s[0])
    }

    /// Speed of sound c = √(γp/ρ).
    #[inline(always)]
    pub fn sound_speed(&self, s: &State) -> f64 {
        (self.gamma * self.pressure(s) / s[0]).sqrt()
    }

    /// The state with the momentum along `axis` moved first: (ρ, m_d,
    /// m_{d+1}, m_{d+2}, E). [`Gas::unrotated`] undoes it.
    #[inline(always)]
    pub fn rotated(s: &State, axis: usize) -> State {
        [
            s[0],
            s[1 + axis],
            s[1 + (axis + 1) % 3],
            s[1 + (axis + 2) % 3],
            s[4],
        ]
    }

    #[inline(always)]
    pub fn unrotated(r: &State, axis: usize) -> State {
        let mut s = [r[0], 0.0, 0.0, 0.0, r[4]];
        s[1 + axis] = r[1];
        s[1 + (axis + 1) % 3] = r[2];
        s[1 + (axis + 2) % 3] = r[3];
        s
    }

    /// The flux along x of a state (F of eq. 2.24); of a rotated state, the
    /// rotated flux along its axis.
    #[inline(always)]
    pub fn flux(&self, s: &State) -> State {
        let u = s[1] / s[0];
        let p = self.pressure(s);
        [s[1], s[1] * u + p, s[2] * u, s[3] * u, (s[4] + p) * u]
    }

    /// The eigenvalues of the x flux Jacobian at `s`: u − c, u, u, u, u + c
    /// (eq. 3.12 with the two shear waves).
    #[inline(always)]
    pub fn eigenvalues(&self, s: &State) -> [f64; 5] {
        let u = s[1] / s[0];
        let c = self.sound_speed(s);
        [u - c, u, u, u, u + c]
    }

    /// The Roe average of two states (Roe 1981; Toro §11.2): the state at
    /// which the eigenvectors between cells are taken, exact for a single
    /// shock or contact.
    pub fn roe_average(&self, a: &State, b: &State) -> Eigen {
        let (ra, rb) = (a[0].sqrt(), b[0].sqrt());
        let mean = |qa: f64, qb: f64| (ra * qa + rb * qb) / (ra + rb);
        let velocity = [1, 2, 3].map(|i| mean(a[i] / a[0], b[i] / b[0]));
        let enthalpy = mean(
            (a[4] + self.pressure(a)) / a[0],
            (b[4] + self.pressure(b)) / b[0],
        );
        Eigen::new(self.gamma, velocity, enthalpy)
    }
}

/// The right eigenvectors R (as columns) and left eigenvectors L = R⁻¹ (as
/// rows) of the x flux Jacobian, eqs. (3.13)–(3.16) in 3-D.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Eigen {
    pub right: [[f64; 5]; 5],
    pub left: [[f64; 5]; 5],
}

impl Eigen {
    /// At velocity (u, v, w) and total specific enthalpy H = (E + p)/ρ (eq. 3.14).
    pub fn new(gamma: f64, velocity: [f64; 3], enthalpy: f64) -> Eigen {
        let [u, v, w] = velocity;
        let q2 = u * u + v * v + w * w;
        let h = enthalpy;
        let c2 = (gamma - 1.0) * (h - 0.5 * q2);
        let c = c2.sqrt();
        // Columns r1 … r5 (eq. 3.13 with the shear waves r3, r4), stored by rows.
        let right = [
            [1.0, 1.0, 0.0, 0.0, 1.0],
            [u - c, u, 0.0, 0.0, u + c],
            [v, v, 1.0, 0.0, v],
            [w, w, 0.0, 1.0, w],
            [h - u * c, 0.5 * q2, v, w, h + u * c],
        ];
        let b = (gamma - 1.0) / c2;
        let left = [
            [
                0.5 * (0.5 * b * q2 + u / c),
                -0.5 * (b * u + 1.0 / c),
                -0.5 * b * v,
                -0.5 * b * w,
                0.5 * b,
            ],
            [1.0 - 0.5 * b * q2, b * u, b * v, b * w, -b],
            [-v, 0.0, 1.0, 0.0, 0.0],
            [-w, 0.0, 0.0, 1.0, 0.0],
            [
                0.5 * (0.5 * b * q2 - u / c),
                -0.5 * (b * u - 1.0 / c),
                -0.5 * b * v,
                -0.5 * b * w,
                0.5 * b,
            ],
        ];
        Eigen { right, left }
    }

    /// Characteristic variables L·s.
    #[inline(always)]
    pub fn to_characteristic(&self, s: &State) -> State {
        self.left.map(|row| dot(&row, s))
    }

    /// Conserved variables R·w.
    #[inline(always)]
    pub fn from_characteristic(&self, w: &State) -> State {
        self.right.map(|row| dot(&row, w))
    }
}

#[inline(always)]
fn dot(a: &[f64; 5], b: &[f64; 5]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3] + a[4] * b[4]
}

#[cfg(test)]
mod tests {
    use super::*;

    const AIR: Gas = Gas { gamma: 1.4 };

    fn state() -> State {
        AIR.conserved(Primitive {
            density: 1.3,
            velocity: [0.7, -0.4, 0.25],
            pressure: 2.1,
        })
    }

    #[test]
    fn left_eigenvectors_invert_the_right_ones() {
        let s = state();
        let e = AIR.roe_average(&s, &s);
        for i in 0..5 {
            for j in 0..5 {
                let lr: f64 = (0..5).map(|k| e.left[i][k] * e.right[k][j]).sum();
                let id = if i == j { 1.0 } else { 0.0 };
                assert!((lr - id).abs() < 1e-13, "(LR)[{i}][{j}] = {lr}");
            }
        }
    }

    #[test]
    fn the_eigenvectors_diagonalise_the_flux_jacobian() {
        // A = RΛL (eq. 3.16): A·r_k = λ_k r_k, with A by central differences
        // of the flux, to the differences' truncation error.
        let s = state();
        let e = AIR.roe_average(&s, &s);
        let lambda = AIR.eigenvalues(&s);
        let eps = 1e-6;
        for (k, l) in lambda.iter().enumerate() {
            let r: State = [0, 1, 2, 3, 4].map(|i| e.right[i][k]);
            let plus = AIR.flux(&[0, 1, 2, 3, 4].map(|i| s[i] + eps * r[i]));
            let minus = AIR.flux(&[0, 1, 2, 3, 4].map(|i| s[i] - eps * r[i]));
            for i in 0..5 {
                let ar = (plus[i] - minus[i]) / (2.0 * eps);
                assert!(
                    (ar - l * r[i]).abs() < 1e-8,
                    "A r_{k} [{i}] = {ar}, λ r = {}",
                    l * r[i]
                );
            }
        }
    }

    #[test]
    fn rotation_round_trips_and_primitives_round_trip() {
        let s = state();
        for axis in 0..3 {
            assert_eq!(Gas::unrotated(&Gas::rotated(&s, axis), axis), s);
        }
        let w = AIR.primitive(&s);
        let back = AIR.conserved(w);
        for i in 0..5 {
            assert!((back[i] - s[i]).abs() < 1e-14);
        }
        assert!((w.pressure - 2.1).abs() < 1e-14);
    }
}
