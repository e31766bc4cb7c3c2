//! The exact solution of the Riemann problem for the 1-D Euler equations of
//! an ideal gas (Toro, *Riemann Solvers and Numerical Methods for Fluid
//! Dynamics*, 3rd ed., ch. 4): the star pressure from Newton's method on
//! the pressure function (Toro eqs. 4.5–4.7, 4.37) and the solution at any
//! x/t (§4.5). It is the reference Sod's shock tube is checked against.

use crate::euler::gas::{Gas, Primitive};

/// The two states either side of the jump, along x.
#[derive(Debug, Clone, Copy)]
pub struct Riemann {
    pub gas: Gas,
    pub left: Primitive,
    pub right: Primitive,
}

/// Pressure and velocity between the two nonlinear waves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Star {
    pub pressure: f64,
    pub velocity: f64,
}

/// Newton's iteration stops at this relative change of p* (Toro uses 1e-6;
/// the solution is a reference, so it goes to round-off).
const TOLERANCE: f64 = 1e-14;

impl Riemann {
    /// p* and u* (Toro §4.3.1).
    ///
    /// # Panics
    /// If the two rarefactions would open a vacuum (Toro eq. 4.40), which the
    /// scenes do not set up.
    pub fn star(&self) -> Star {
        let (l, r) = (&self.left, &self.right);
        let (cl, cr) = (self.sound(l), self.sound(r));
        let du = r.velocity[0] - l.velocity[0];
        let g = self.gas.gamma;
        assert!(
            2.0 * (cl + cr) / (g - 1.0) > du,
            "the states open a vacuum between them"
        );
        // Primitive-variable guess (Toro eq. 4.47), kept positive.
        let guess =
            0.5 * (l.pressure + r.pressure) - 0.125 * du * (l.density + r.density) * (cl + cr);
        let mut p = guess.max(1e-8 * (l.pressure + r.pressure));
        for _ in 0..100 {
            let (fl, dl) = self.pressure_function(p, l);
            let (fr, dr) = self.pressure_function(p, r);
            let next = (p - (fl + fr + du) / (dl + dr)).max(0.5 * p);
            let change = (next - p).abs() / (0.5 * (next + p));
            p = next;
            if change < TOLERANCE {
                break;
            }
        }
        let (fl, _) = self.pressure_function(p, l);
        let (fr, _) = self.pressure_function(p, r);
        Star {
            pressure: p,
            velocity: 0.5 * (l.velocity[0] + r.velocity[0]) + 0.5 * (fr - fl),
        }
    }

    /// The solution at x/t = `s` (Toro §4.5, Fig. 4.14); tangential
    /// velocities are carried by the contact.
    pub fn sample(&self, star: Star, s: f64) -> Primitive {
        let g = self.gas.gamma;
        let (ps, us) = (star.pressure, star.velocity);
        // Mirror the right half onto the left: x → −x, u → −u.
        let (side, sign, s) = if s <= us {
            (&self.left, 1.0, s)
        } else {
            (&self.right, -1.0, -s)
        };
        let (rho, u, p) = (side.density, sign * side.velocity[0], side.pressure);
        let us = sign * us;
        let c = self.sound(side);
        let with = |density: f64, u: f64, pressure: f64| {
            let mut velocity = side.velocity;
            velocity[0] = sign * u;
            Primitive {
                density,
                velocity,
                pressure,
            }
        };
        let gm = (g - 1.0) / (g + 1.0);
        if ps > p {
            // A shock (Toro eqs. 4.50, 4.52).
            let speed = u - c * ((g + 1.0) / (2.0 * g) * ps / p + (g - 1.0) / (2.0 * g)).sqrt();
            if s <= speed {
                with(rho, u, p)
            } else {
                with(rho * (ps / p + gm) / (gm * ps / p + 1.0), us, ps)
            }
        } else {
            // A rarefaction (Toro eqs. 4.53–4.56).
            let star_c = c * (ps / p).powf((g - 1.0) / (2.0 * g));
            let (head, tail) = (u - c, us - star_c);
            if s <= head {
                with(rho, u, p)
            } else if s >= tail {
                with(rho * (ps / p).powf(1.0 / g), us, ps)
            } else {
                let k = 2.0 / (g + 1.0) + gm / c * (u - s);
                with(
                    rho * k.powf(2.0 / (g - 1.0)),
                    2.0 / (g + 1.0) * (c + 0.5 * (g - 1.0) * u + s),
                    p * k.powf(2.0 * g / (g - 1.0)),
                )
            }
        }
    }

    fn sound(&self, w: &Primitive) -> f64 {
        (self.gas.gamma * w.pressure / w.density).sqrt()
    }

    /// f_K(p) and its derivative (Toro eqs. 4.6, 4.7, 4.37).
    fn pressure_function(&self, p: f64, k: &Primitive) -> (f64, f64) {
        let g = self.gas.gamma;
        let (rho, pk) = (k.density, k.pressure);
        if p > pk {
            let a = 2.0 / ((g + 1.0) * rho);
            let b = (g - 1.0) / (g + 1.0) * pk;
            let root = (a / (p + b)).sqrt();
            ((p - pk) * root, root * (1.0 - 0.5 * (p - pk) / (p + b)))
        } else {
            let c = self.sound(k);
            let ratio = p / pk;
            (
                2.0 * c / (g - 1.0) * (ratio.powf((g - 1.0) / (2.0 * g)) - 1.0),
                ratio.powf(-(g + 1.0) / (2.0 * g)) / (rho * c),
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state(density: f64, u: f64, pressure: f64) -> Primitive {
        Primitive {
            density,
            velocity: [u, 0.0, 0.0],
            pressure,
        }
    }

    /// Toro Table 4.3 (γ = 1.4): the star states of his tests 1–3 to the
    /// five digits printed there.
    #[test]
    fn star_states_match_toros_table() {
        let gas = Gas { gamma: 1.4 };
        let cases = [
            // Test 1 (Sod's problem).
            (
                state(1.0, 0.0, 1.0),
                state(0.125, 0.0, 0.1),
                0.30313,
                0.92745,
            ),
            // Test 2 (123 problem).
            (
                state(1.0, -2.0, 0.4),
                state(1.0, 2.0, 0.4),
                0.00189,
                0.00000,
            ),
            // Test 3 (left half of the blast wave).
            (
                state(1.0, 0.0, 1000.0),
                state(1.0, 0.0, 0.01),
                460.894,
                19.5975,
            ),
        ];
        for (left, right, p, u) in cases {
            let star = Riemann { gas, left, right }.star();
            assert!((star.pressure - p).abs() <= 0.5e-5 * p.max(1.0), "{star:?}");
            assert!(
                (star.velocity - u).abs() <= 0.5e-5 * u.abs().max(1.0),
                "{star:?}"
            );
        }
    }

    #[test]
    fn the_solution_is_continuous_across_the_rarefaction_edges() {
        // Sod's rarefaction: the fan meets the left state at its head and
        // the star state at its tail.
        let gas = Gas { gamma: 1.4 };
        let r = Riemann {
            gas,
            left: state(1.0, 0.0, 1.0),
            right: state(0.125, 0.0, 0.1),
        };
        let star = r.star();
        let c = 1.4f64.sqrt();
        let head = r.sample(star, -c + 1e-12);
        assert!((head.density - 1.0).abs() < 1e-9);
        let star_c = c * (star.pressure).powf(0.4 / 2.8);
        let tail = r.sample(star, star.velocity - star_c - 1e-12);
        assert!((tail.pressure - star.pressure).abs() < 1e-9);
        assert!((tail.velocity[0] - star.velocity).abs() < 1e-9);
    }
}
