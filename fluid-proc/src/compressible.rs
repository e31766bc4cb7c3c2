//! The compressible Euler equations of seed 000 eq. (2.23) on a box of
//! cells: characteristic WENO5 fluxes (`characteristic.rs`) along each
//! axis, dimension by dimension, and the third-order TVD Runge–Kutta method
//! of §3.2.1 (Shu & Osher, J. Comput. Phys. 77, 439–471, 1988, eq. 2.18):
//!
//!   U⁽¹⁾ = Uⁿ + Δt L(Uⁿ)
//!   U⁽²⁾ = ¾Uⁿ + ¼(U⁽¹⁾ + Δt L(U⁽¹⁾))
//!   Uⁿ⁺¹ = ⅓Uⁿ + ⅔(U⁽²⁾ + Δt L(U⁽²⁾))
//!
//! Each stage is a convex combination of forward-Euler steps, so the
//! scheme keeps whatever the spatial operator keeps under Δt's CFL limit.
//! The step is chosen from the fastest wave, Δt = CFL / max Σ_d (|u_d| + c)/h_d.
//!
//! Cells live with three ghost layers on every axis more than one cell
//! thick (`padded.rs`'s [`Layout`]); an axis one cell thick carries no
//! flux, which makes a 1-D tube or a 2-D flow.

use crate::characteristic::{line_fluxes, REACH};
use crate::gas::{Gas, Primitive, State};
use crate::padded::{Layout, GHOSTS};
use rayon::prelude::*;

/// What a side of the box does to the gas.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GasSide {
    /// A slip wall that reflects: the ghosts mirror the cells with the
    /// normal momentum reversed, so no mass, momentum along the wall or
    /// energy crosses it.
    Wall,
    /// A transmissive side: the ghosts repeat the last cell, so waves leave
    /// with little reflection.
    Outflow,
    /// Wraps to the opposite side.
    Periodic,
}

/// The box, its sides and the gas.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GasSetup {
    pub n: [usize; 3],
    /// Cell size per axis [m].
    pub h: [f64; 3],
    pub sides: [[GasSide; 2]; 3],
    pub gas: Gas,
    /// Courant number of a step, at the fastest wave.
    pub cfl: f64,
}

/// Why a step could not be taken.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GasError {
    #[error(
        "at t = {time} s cell {cell:?} has density {density} kg/m³ and pressure {pressure} Pa: \
         the gas state is no longer physical (a smaller [fluid] cfl may help, unless the \
         gas is opening a vacuum)"
    )]
    Unphysical {
        time: f64,
        cell: [usize; 3],
        density: f64,
        pressure: f64,
    },
}

/// What a call to [`Compressible::advance`] did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct AdvanceReport {
    pub steps: u64,
    /// The shortest step taken [s].
    pub min_dt: f64,
}

/// The gas on its cells, at `time`.
#[derive(Debug, Clone)]
pub struct Compressible {
    pub setup: GasSetup,
    lay: Layout,
    /// Conserved states with ghosts, at `lay`.
    u: Vec<State>,
    /// Uⁿ during a step, and the right-hand side L(U) of the cells.
    start: Vec<State>,
    rhs: Vec<State>,
    pub time: f64,
}

impl Compressible {
    /// The gas with `initial(cell)` in every cell.
    pub fn new(setup: GasSetup, initial: impl Fn([usize; 3]) -> Primitive) -> Compressible {
        let lay = Layout::cells(setup.n);
        let dims = lay.dims();
        let mut u = vec![[0.0; 5]; dims.iter().product()];
        for_cells(setup.n, |c, _| {
            u[lay.at(c.map(|x| x as isize))] = setup.gas.conserved(initial(c))
        });
        let cells = setup.n.iter().product();
        Compressible {
            setup,
            lay,
            start: u.clone(),
            u,
            rhs: vec![[0.0; 5]; cells],
            time: 0.0,
        }
    }

    /// The conserved state of every cell, x fastest.
    pub fn cells(&self) -> Vec<State> {
        let mut out = Vec::with_capacity(self.rhs.len());
        for_cells(self.setup.n, |c, _| out.push(self.u[self.at(c)]));
        out
    }

    pub fn primitives(&self) -> Vec<Primitive> {
        let gas = self.setup.gas;
        self.cells().iter().map(|s| gas.primitive(s)).collect()
    }

    /// Σ U·V over the cells: mass [kg], momentum [kg·m/s] and energy [J].
    pub fn totals(&self) -> State {
        let volume: f64 = self.setup.h.iter().product();
        let mut sum = [0.0; 5];
        for s in self.cells() {
            for (t, v) in sum.iter_mut().zip(s) {
                *t += v * volume;
            }
        }
        sum
    }

    /// The longest stable step: CFL / max over cells of Σ_d (|u_d| + c)/h_d.
    pub fn stable_dt(&self) -> f64 {
        let s = &self.setup;
        let active: Vec<usize> = (0..3).filter(|&d| s.n[d] > 1).collect();
        let rate = self
            .cells()
            .iter()
            .map(|u| {
                let c = s.gas.sound_speed(u);
                active
                    .iter()
                    .map(|&d| ((u[1 + d] / u[0]).abs() + c) / s.h[d])
                    .sum::<f64>()
            })
            .fold(0.0, f64::max);
        if rate > 0.0 {
            s.cfl / rate
        } else {
            f64::INFINITY
        }
    }

    /// Advances by `duration` [s] in stable steps, the last one shortened
    /// to land on the end.
    pub fn advance(&mut self, duration: f64) -> Result<AdvanceReport, GasError> {
        let end = self.time + duration;
        let mut report = AdvanceReport {
            steps: 0,
            min_dt: f64::INFINITY,
        };
        while end - self.time > 1e-12 * duration {
            let dt = self.stable_dt();
            let last = dt >= end - self.time;
            let dt = if last { end - self.time } else { dt };
            self.step(dt)?;
            if last {
                self.time = end;
            }
            report.steps += 1;
            report.min_dt = report.min_dt.min(dt);
        }
        Ok(report)
    }

    /// One TVD Runge–Kutta step of `dt` (Shu & Osher eq. 2.18).
    pub fn step(&mut self, dt: f64) -> Result<(), GasError> {
        self.start.clone_from(&self.u);
        // (weight of Uⁿ, weight of the forward-Euler step) per stage.
        for (a, b) in [(0.0, 1.0), (0.75, 0.25), (1.0 / 3.0, 2.0 / 3.0)] {
            self.fill_ghosts();
            self.right_hand_side();
            let (lay, n) = (self.lay, self.setup.n);
            for_cells(n, |c, i| {
                let p = lay.at(c.map(|x| x as isize));
                for v in 0..5 {
                    let euler = self.u[p][v] + dt * self.rhs[i][v];
                    self.u[p][v] = a * self.start[p][v] + b * euler;
                }
            });
        }
        self.time += dt;
        self.check()
    }

    fn at(&self, c: [usize; 3]) -> usize {
        self.lay.at(c.map(|x| x as isize))
    }

    /// Every cell must keep a positive, finite density and pressure.
    fn check(&self) -> Result<(), GasError> {
        let gas = self.setup.gas;
        let mut bad = None;
        for_cells(self.setup.n, |c, _| {
            let s = &self.u[self.at(c)];
            let p = gas.pressure(s);
            let ok = s[0] > 0.0 && p > 0.0 && s.iter().all(|v| v.is_finite());
            if !ok && bad.is_none() {
                bad = Some(GasError::Unphysical {
                    time: self.time,
                    cell: c,
                    density: s[0],
                    pressure: p,
                });
            }
        });
        bad.map_or(Ok(()), Err)
    }

    /// The ghosts of every axis more than one cell thick, axis by axis over
    /// the whole range of the others (edges and corners too).
    fn fill_ghosts(&mut self) {
        let lay = self.lay;
        let g = GHOSTS as isize;
        for a in 0..3 {
            if lay.g[a] == 0 {
                continue;
            }
            let (s, m) = (lay.stride[a] as isize, lay.m[a] as isize);
            let sides = self.setup.sides[a];
            let u = &mut self.u;
            lay.for_each_line(a, |base| {
                let ix = |k: isize| (base as isize + k * s) as usize;
                if sides == [GasSide::Periodic; 2] {
                    for k in 1..=g {
                        u[ix(-k)] = u[ix(m - k)];
                        u[ix(m - 1 + k)] = u[ix(k - 1)];
                    }
                    return;
                }
                for (side, up) in [(sides[0], false), (sides[1], true)] {
                    let (edge, dir) = if up { (m - 1, 1) } else { (0, -1) };
                    for k in 1..=g {
                        let ghost = match side {
                            GasSide::Wall => {
                                let mut v = u[ix(edge - dir * (k - 1))];
                                v[1 + a] = -v[1 + a];
                                v
                            }
                            GasSide::Outflow => u[ix(edge)],
                            // A periodic side facing another kind is
                            // refused by the scenario check.
                            GasSide::Periodic => u[ix(edge)],
                        };
                        u[ix(edge + dir * k)] = ghost;
                    }
                }
            });
        }
    }

    /// rhs = L(U) = −Σ_d (F_{i+½} − F_{i−½})/h_d, line by line along each
    /// axis, the lines in parallel.
    fn right_hand_side(&mut self) {
        self.rhs.iter_mut().for_each(|r| *r = [0.0; 5]);
        let (lay, setup) = (self.lay, self.setup);
        let n = setup.n;
        for d in (0..3).filter(|&d| n[d] > 1) {
            let (b, e) = ((d + 1) % 3, (d + 2) % 3);
            let lines: Vec<[usize; 2]> = (0..n[e])
                .flat_map(|ie| (0..n[b]).map(move |ib| [ib, ie]))
                .collect();
            let u = &self.u;
            let inv_h = 1.0 / setup.h[d];
            let changes: Vec<Vec<State>> = lines
                .par_iter()
                .map_init(
                    || (Vec::new(), vec![[0.0; 5]; n[d] + 1]),
                    |(line, faces), &[ib, ie]| {
                        line.clear();
                        for k in -(REACH as isize)..(n[d] + REACH) as isize {
                            let mut c = [0isize; 3];
                            c[d] = k;
                            c[b] = ib as isize;
                            c[e] = ie as isize;
                            line.push(Gas::rotated(&u[lay.at(c)], d));
                        }
                        line_fluxes(&setup.gas, line, faces);
                        faces
                            .windows(2)
                            .map(|f| {
                                let dif = [0, 1, 2, 3, 4].map(|v| (f[0][v] - f[1][v]) * inv_h);
                                Gas::unrotated(&dif, d)
                            })
                            .collect()
                    },
                )
                .collect();
            for (&[ib, ie], change) in lines.iter().zip(changes) {
                for (k, dv) in change.iter().enumerate() {
                    let mut c = [0usize; 3];
                    c[d] = k;
                    c[b] = ib;
                    c[e] = ie;
                    let r = &mut self.rhs[c[0] + n[0] * (c[1] + n[1] * c[2])];
                    for v in 0..5 {
                        r[v] += dv[v];
                    }
                }
            }
        }
    }
}

/// Calls `f(cell, index)` for every cell, x fastest.
fn for_cells(n: [usize; 3], mut f: impl FnMut([usize; 3], usize)) {
    let mut i = 0;
    for k in 0..n[2] {
        for j in 0..n[1] {
            for x in 0..n[0] {
                f([x, j, k], i);
                i += 1;
            }
        }
    }
}
