//! The compressible Euler equations of dissertation eq. (2.23) on a box of
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
//! thick (`layout.rs`'s [`Layout`]; more along the slab's axis when
//! bodies stand in the gas, `halo.rs`); an axis one cell
//! thick carries no flux, which makes a 1-D tube or a 2-D flow. On several
//! ranks each holds a slab of the box (`comm.rs`), and the ghosts at a side
//! it shares with another rank are that rank's cells: the same values one
//! rank alone reads, so the fields do not depend on the number of ranks.
//! Rigid bodies are walls of the gas (`bodies.rs`, `walls.rs`).
//!
//! The rest of the model, in this folder: the ideal gas and its
//! characteristic fields (`gas.rs`), the exact Riemann solution the
//! solver is checked against (`riemann.rs`), the signed distance to the
//! bodies' surfaces (`level_set.rs`) and how bodies move through a window
//! (`body_motion.rs`), the scenario's gas (`setup.rs`), and the model in
//! the run loop (`run.rs`).

pub mod bodies;
pub mod body_motion;
pub mod characteristic;
pub mod gas;
mod halo;
pub mod level_set;
pub mod riemann;
pub mod run;
pub mod setup;
mod walls;

use crate::comm::{Comm, Single, Slab};
use crate::euler::characteristic::{line_fluxes, REACH};
use crate::euler::gas::{Gas, Primitive, State};

#[cfg(doc)]
use crate::euler::bodies::Kinematics;
use crate::euler::bodies::{GasBody, Solids};
use crate::layout::{Layout, GHOSTS};
use rayon::prelude::*;
use std::sync::Arc;

/// What a side of the box does to the gas.
#[derive(Debug, Clone, Copy, PartialEq)]
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
    /// The ghosts hold this state: a supersonic inflow, every
    /// characteristic entering the box (a subsonic one would be given more
    /// than it takes, and reflect).
    State(Primitive),
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

/// What the gas saves at a window's start (implicit coupling) and writes
/// at a run checkpoint, one per rank.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct GasCheckpoint {
    u: Vec<State>,
    time: f64,
    inflow: State,
    /// Each body's motion ([`Kinematics::to_values`]).
    bodies: Vec<[f64; 17]>,
}

/// The gas on its cells (this rank's slab of them), at `time`.
#[derive(Debug, Clone)]
pub struct Compressible {
    /// The whole box.
    pub setup: GasSetup,
    comm: Arc<dyn Comm>,
    slab: Slab,
    /// This rank's cells per axis.
    n: [usize; 3],
    lay: Layout,
    /// Conserved states with ghosts, at `lay`.
    u: Vec<State>,
    /// Uⁿ during a step, and the right-hand side L(U) of the cells.
    start: Vec<State>,
    rhs: Vec<State>,
    pub time: f64,
    /// What the fluxes have carried in through the box's sides on this
    /// rank since the start: mass [kg], momentum [kg·m/s], energy [J].
    inflow: State,
    /// Rigid bodies in the gas (`bodies.rs`), and the cells inside
    /// them as last placed.
    pub bodies: Vec<GasBody>,
    solids: Solids,
}

impl Compressible {
    /// The gas with `initial(cell)` in every cell, on one rank.
    pub fn new(setup: GasSetup, initial: impl Fn([usize; 3]) -> Primitive) -> Compressible {
        Compressible::on(setup, Arc::new(Single), initial)
    }

    /// This rank's slab of the gas with `initial(cell)` in every cell (`cell`
    /// counted in the whole box). Each slab needs at least [`GHOSTS`] cells,
    /// so that its halo comes from its two neighbours alone.
    pub fn on(
        setup: GasSetup,
        comm: Arc<dyn Comm>,
        initial: impl Fn([usize; 3]) -> Primitive,
    ) -> Compressible {
        let slab = Slab::of(setup.n, comm.ranks(), comm.rank());
        let n = slab.cells();
        assert!(
            comm.ranks() == 1 || n[slab.axis] >= GHOSTS,
            "a slab of {} cells is thinner than the halo",
            n[slab.axis]
        );
        let lay = Layout::cells(n);
        let dims = lay.dims();
        let mut u = vec![[0.0; 5]; dims.iter().product()];
        for_cells(n, |c, _| {
            u[lay.at(c.map(|x| x as isize))] = setup.gas.conserved(initial(slab.global(c)))
        });
        let cells = n.iter().product();
        Compressible {
            setup,
            comm,
            slab,
            n,
            lay,
            start: u.clone(),
            u,
            rhs: vec![[0.0; 5]; cells],
            time: 0.0,
            inflow: [0.0; 5],
            bodies: Vec::new(),
            solids: Solids::default(),
        }
    }

    /// This rank's gas cells: its cells less those inside bodies.
    fn own_gas(&self) -> impl Iterator<Item = &State> + '_ {
        let inside = &self.solids.inside;
        self.own()
            .enumerate()
            .filter(move |(i, _)| !inside.get(*i).copied().unwrap_or(false))
            .map(|(_, s)| s)
    }

    /// The conserved state of every cell of this rank, x fastest.
    pub fn cells(&self) -> Vec<State> {
        self.own().copied().collect()
    }

    /// This rank's cell states in place, x fastest (a row along x is
    /// contiguous in the padded layout), without copying them.
    fn own(&self) -> impl Iterator<Item = &State> + '_ {
        let n = self.n;
        (0..n[2]).flat_map(move |k| {
            (0..n[1]).flat_map(move |j| {
                let p = self.lay.at([0, j as isize, k as isize]);
                self.u[p..p + n[0]].iter()
            })
        })
    }

    /// The primitive state of every cell of this rank, x fastest.
    pub fn primitives(&self) -> Vec<Primitive> {
        let gas = self.setup.gas;
        self.own().map(|s| gas.primitive(s)).collect()
    }

    /// The primitive state of every cell of the box, x fastest, on rank 0
    /// (None on the others). Every rank must call it.
    pub fn gathered_primitives(&self) -> Option<Vec<Primitive>> {
        let local: Vec<f64> = self
            .primitives()
            .iter()
            .flat_map(|w| {
                [
                    w.density,
                    w.velocity[0],
                    w.velocity[1],
                    w.velocity[2],
                    w.pressure,
                ]
            })
            .collect();
        let all = self.gathered(&local, 5)?;
        Some(
            all.chunks_exact(5)
                .map(|v| Primitive {
                    density: v[0],
                    velocity: [v[1], v[2], v[3]],
                    pressure: v[4],
                })
                .collect(),
        )
    }

    /// 1 for each cell of the box inside a body, 0 for the gas, x fastest,
    /// on rank 0 (None on the others). Every rank must call it.
    pub fn gathered_inside(&self) -> Option<Vec<f64>> {
        let local: Vec<f64> = self.inside().iter().map(|&i| i as u8 as f64).collect();
        self.gathered(&local, 1)
    }

    /// `k` values per cell of this rank (x fastest), gathered for the whole
    /// box on rank 0 (None on the others).
    fn gathered(&self, local: &[f64], k: usize) -> Option<Vec<f64>> {
        let parts = self.comm.gather(local)?;
        let n = self.setup.n;
        let mut all = vec![0.0; k * n.iter().product::<usize>()];
        for (rank, part) in parts.iter().enumerate() {
            let slab = Slab::of(n, parts.len(), rank);
            for_cells(slab.cells(), |c, i| {
                let [x, y, z] = slab.global(c);
                let at = x + n[0] * (y + n[1] * z);
                all[k * at..k * at + k].copy_from_slice(&part[k * i..k * i + k]);
            });
        }
        Some(all)
    }

    /// Σ U·V over the box's gas cells (those outside bodies): mass [kg],
    /// momentum [kg·m/s] and energy [J], on every rank.
    pub fn totals(&self) -> State {
        let volume: f64 = self.setup.h.iter().product();
        let mut sum = [0.0; 5];
        for s in self.own_gas() {
            for (t, v) in sum.iter_mut().zip(s) {
                *t += v * volume;
            }
        }
        self.comm.sum(&mut sum);
        sum
    }

    /// What the fluxes have carried in through the box's sides since the
    /// start, through the faces of gas cells: mass [kg], momentum [kg·m/s]
    /// and energy [J], on every rank. With [`Compressible::totals`] it
    /// closes the budget: without bodies totals − inflow stays at its start
    /// to round-off.
    pub fn inflow(&self) -> State {
        let mut sum = self.inflow;
        self.comm.sum(&mut sum);
        sum
    }

    /// The lowest density and pressure over the box's gas cells, on every rank.
    pub fn lowest(&self) -> [f64; 2] {
        let gas = self.setup.gas;
        let mut low = [f64::INFINITY; 2];
        for s in self.own_gas() {
            low[0] = low[0].min(s[0]);
            low[1] = low[1].min(gas.pressure(s));
        }
        low.map(|x| self.comm.min(x))
    }

    /// The longest stable step: CFL / max over the box's cells and the
    /// states its `state` sides hold of Σ_d (|u_d| + c)/h_d, on every rank
    /// (the held gas enters the first cells at its own speed). Ghost cells
    /// count, their velocity holding the wall's; deep solid cells do not.
    pub fn stable_dt(&self) -> f64 {
        let s = &self.setup;
        let active: Vec<usize> = (0..3).filter(|&d| s.n[d] > 1).collect();
        let rate_of = |u: &State| {
            let c = s.gas.sound_speed(u);
            active
                .iter()
                .map(|&d| ((u[1 + d] / u[0]).abs() + c) / s.h[d])
                .sum::<f64>()
        };
        let held = s.sides.iter().flatten().filter_map(|side| match side {
            GasSide::State(w) => Some(s.gas.conserved(*w)),
            _ => None,
        });
        let rate = for_cells_at(self.n, self.lay)
            .enumerate()
            .filter(|&(i, _)| !self.solids.frozen(i))
            .map(|(_, p)| rate_of(&self.u[p]))
            .chain(held.map(|u| rate_of(&u)))
            .fold(0.0, f64::max);
        let dt = if rate > 0.0 {
            s.cfl / rate
        } else {
            f64::INFINITY
        };
        self.comm.min(dt)
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

    /// This rank's state: its conserved cells (with their ghosts, which
    /// every step fills again), the time and what has come in through the
    /// sides. Nothing else carries over from step to step: each step finds
    /// its own Δt, and places the bodies where their motion puts them.
    pub fn save(&self, into: &mut GasCheckpoint) {
        into.u.clone_from(&self.u);
        into.time = self.time;
        into.inflow = self.inflow;
        into.bodies = self.body_motions();
    }

    /// Return to the state `from` holds, if it holds this rank's cells
    /// (false: saved by a run on other cells or ranks, and nothing changes).
    pub fn restore(&mut self, from: &GasCheckpoint) -> bool {
        if from.u.len() != self.u.len() {
            return false;
        }
        self.u.clone_from(&from.u);
        self.time = from.time;
        self.inflow = from.inflow;
        self.restore_bodies(&from.bodies);
        true
    }

    /// One TVD Runge–Kutta step of `dt` (Shu & Osher eq. 2.18).
    pub fn step(&mut self, dt: f64) -> Result<(), GasError> {
        self.start.clone_from(&self.u);
        // Per stage: the weights of Uⁿ and of the forward-Euler step, the
        // stage's time after tⁿ, and its weight in Uⁿ⁺¹ − Uⁿ
        // (= Δt(L₀ + L₁ + 4L₂)/6).
        let stages = [
            (0.0, 1.0, 0.0, 1.0 / 6.0),
            (0.75, 0.25, dt, 1.0 / 6.0),
            (1.0 / 3.0, 2.0 / 3.0, 0.5 * dt, 2.0 / 3.0),
        ];
        for (a, b, after, share) in stages {
            self.fill_ghosts();
            if !self.bodies.is_empty() {
                self.stage_bodies(self.time + after, share * dt);
            }
            let entering = self.right_hand_side();
            for (total, v) in self.inflow.iter_mut().zip(entering) {
                *total += share * dt * v;
            }
            let (lay, n) = (self.lay, self.n);
            for_cells(n, |c, i| {
                // A solid cell is not stepped: a ghost takes its image's
                // state again at the next stage, a deeper one keeps its
                // own, and a cell the body leaves starts from that state.
                if self.solids.is_inside(i) {
                    return;
                }
                let p = lay.at(c.map(|x| x as isize));
                for v in 0..5 {
                    let euler = self.u[p][v] + dt * self.rhs[i][v];
                    self.u[p][v] = a * self.start[p][v] + b * euler;
                }
            });
        }
        self.time += dt;
        self.settle_bodies();
        self.check()
    }

    fn at(&self, c: [usize; 3]) -> usize {
        self.lay.at(c.map(|x| x as isize))
    }

    /// Every cell must keep a positive, finite density and pressure. The
    /// first bad cell of the box is reported, the same on every rank.
    fn check(&self) -> Result<(), GasError> {
        let gas = self.setup.gas;
        let n = self.setup.n;
        let mut bad = None;
        let inside = self.inside();
        for_cells(self.n, |c, i| {
            if inside[i] {
                return;
            }
            let s = &self.u[self.at(c)];
            let p = gas.pressure(s);
            let ok = s[0] > 0.0 && p > 0.0 && s.iter().all(|v| v.is_finite());
            if !ok && bad.is_none() {
                let [x, y, z] = self.slab.global(c);
                bad = Some(((x + n[0] * (y + n[1] * z)) as f64, [s[0], p]));
            }
        });
        // The lowest bad cell over the ranks, then its values from its owner.
        let first = self.comm.min(bad.map_or(f64::INFINITY, |b| b.0));
        if first.is_infinite() {
            return Ok(());
        }
        let mut values = match bad {
            Some((i, v)) if i == first => v,
            _ => [0.0; 2],
        };
        self.comm.sum(&mut values);
        let i = first as usize;
        Err(GasError::Unphysical {
            time: self.time,
            cell: [i % n[0], (i / n[0]) % n[1], i / (n[0] * n[1])],
            density: values[0],
            pressure: values[1],
        })
    }

    /// rhs = L(U) = −Σ_d (F_{i+½} − F_{i−½})/h_d, line by line along each
    /// axis, the lines in parallel. Returns what the fluxes carry in
    /// through the box's sides on this rank, per second.
    fn right_hand_side(&mut self) -> State {
        self.rhs.iter_mut().for_each(|r| *r = [0.0; 5]);
        let (lay, setup) = (self.lay, self.setup);
        let n = self.n;
        let mut entering = [0.0; 5];
        for d in (0..3).filter(|&d| n[d] > 1) {
            let area: f64 = (0..3).filter(|&o| o != d).map(|o| setup.h[o]).product();
            let sides = self.shared_sides(d).map(|s| s.is_none());
            let (b, e) = ((d + 1) % 3, (d + 2) % 3);
            let lines: Vec<[usize; 2]> = (0..n[e])
                .flat_map(|ie| (0..n[b]).map(move |ib| [ib, ie]))
                .collect();
            let u = &self.u;
            let inv_h = 1.0 / setup.h[d];
            let changes: Vec<(Vec<State>, [State; 2])> = lines
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
                        let change = faces
                            .windows(2)
                            .map(|f| {
                                let dif = [0, 1, 2, 3, 4].map(|v| (f[0][v] - f[1][v]) * inv_h);
                                Gas::unrotated(&dif, d)
                            })
                            .collect();
                        let ends = [faces[0], faces[n[d]]].map(|f| Gas::unrotated(&f, d));
                        (change, ends)
                    },
                )
                .collect();
            for (&[ib, ie], (change, ends)) in lines.iter().zip(changes) {
                // A side's face counts where gas lies behind it: a body
                // reaching out of the box holds solid cells there.
                let gas_at = |k: usize| {
                    let mut c = [0usize; 3];
                    (c[d], c[b], c[e]) = (k, ib, ie);
                    !self.solids.is_inside(c[0] + n[0] * (c[1] + n[1] * c[2]))
                };
                let open = [sides[0] && gas_at(0), sides[1] && gas_at(n[d] - 1)];
                for v in 0..5 {
                    let low = if open[0] { ends[0][v] } else { 0.0 };
                    let high = if open[1] { ends[1][v] } else { 0.0 };
                    entering[v] += (low - high) * area;
                }
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
        entering
    }
}

/// The padded index of every cell of `n` at `lay`, x fastest.
fn for_cells_at(n: [usize; 3], lay: Layout) -> impl Iterator<Item = usize> {
    (0..n[2]).flat_map(move |k| {
        (0..n[1]).flat_map(move |j| {
            let p = lay.at([0, j as isize, k as isize]);
            p..p + n[0]
        })
    })
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
