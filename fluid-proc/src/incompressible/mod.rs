//! The incompressible Navier–Stokes solver of dissertation §3.2.2: the
//! pressure-increment projection method of eqs. (3.18)–(3.20) on the MAC grid
//! (Brown, Cortez & Minion, J. Comput. Phys. 168, 464–499, 2001, the
//! method's reference [5] there), second order in time:
//!
//! 1. u* from (u* − uⁿ)/Δt + ∇q = −[(u·∇)u]^{n+½} + ν∇²(u* + uⁿ)/2 with
//!    q = p^{n−½}: the advection term (`advection.rs`, WENO5) extrapolated
//!    to n + ½ by Adams–Bashforth, the viscous term Crank–Nicolson
//!    (`viscosity.rs`), one component at a time (`component.rs`);
//!    Bodies in the flow then force u* to their motion (`immersed.rs`);
//! 2. u^{n+1} = u* − Δt∇φ with ∇·u^{n+1} = 0 (`projection.rs`, `poisson.rs`);
//! 3. p^{n+½} = q + φ − (νΔt/2)∇²φ.
//!
//! Step 1 reads the window's start alone: under implicit coupling a
//! window's later tries take the first try's (`prediction.rs`).
//!
//! Pressures here are kinematic (p/ρ, m²/s²); `pressure` gives pascals.
//! The side velocities are held fixed in time, but in a box that follows
//! the parachute (`frame.rs`), and u* takes them as its boundary values.
//!
//! Split among ranks, each holds its slab of the box (`part.rs`): `u`, `q`
//! and the fields it returns are the slab's, and the sums and extrema it
//! returns are the whole box's.

// The box and its sides: cells and pressure sides (`grid.rs`), the cells'
// widths along each axis, uniform or graded (`axis.rs`), velocity sides
// (`side.rs`), the scenario's flow (`setup.rs`), the slab of it on each
// rank (`part.rs`) and the face velocities with the ghost layers that
// carry the sides (`faces.rs`, `padded.rs`).
pub mod axis;
pub mod faces;
pub mod grid;
pub mod padded;
pub mod part;
pub mod setup;
pub mod side;
// The step: WENO5 advection, the Crank–Nicolson viscous solve (the lengths
// their stencils read, `metric.rs`), the pressure operator and its
// multigrid-preconditioned solve, the
// projection; every loop on the pool's threads, the same to the bit on
// any number of them (`rows.rs`).
pub mod advection;
mod component;
pub mod laplacian;
pub mod metric;
pub mod multigrid;
pub mod poisson;
pub mod prediction;
pub mod projection;
pub mod rows;
pub mod viscosity;
// A window's checkpoint, and a box that follows the parachute.
pub mod checkpoint;
pub mod frame;
// Bodies and the canopy in the flow: markers held by direct forcing with
// Peskin's δ, the pressure force of eq. 2.40, the canopy's jump read
// through the local index coating, and where rank 0 places them.
pub mod canopy;
pub mod clearance;
pub mod coating;
pub mod delta;
pub mod flow_bodies;
pub mod flow_canopy;
pub mod immersed;
pub mod pressure_force;
// Probes and profiles read off the cells.
pub mod probe;
pub mod profile;
// The model in the run loop (`run.rs` of the crate).
pub mod run;
// The step on a GPU (`[fluid] device = "gpu"`), and what crosses back.
pub mod device;
pub mod device_fetch;

use crate::incompressible::checkpoint::History;
use crate::incompressible::component::{adams_bashforth, by_component, ChangeInputs, Work};
use crate::incompressible::faces::{for_each_cell_faces, Faces};
use crate::incompressible::frame::Frame;
use crate::incompressible::grid::Grid;
use crate::incompressible::immersed::{force, Air, ImmersedBody};
use crate::incompressible::padded::Padded;
use crate::incompressible::part::{Halo, Part};
use crate::incompressible::poisson::{Poisson, SolveError};
use crate::incompressible::prediction::Prediction;
use crate::incompressible::projection::project;
use crate::incompressible::side::{bcs, Sides};
use crate::incompressible::viscosity::ViscousError;
use fluid_section::flow::MAX_COURANT;

/// Relative residual of the pressure solve.
pub const PRESSURE_TOLERANCE: f64 = 1e-8;
/// Relative residual of the viscous solve.
pub const VISCOUS_TOLERANCE: f64 = 1e-8;

/// Why a flow step failed.
#[derive(Debug, thiserror::Error)]
pub enum FlowError {
    #[error(transparent)]
    Pressure(#[from] SolveError),
    #[error(transparent)]
    Viscous(#[from] ViscousError),
    #[error("the Courant number Σ|u_a|·Δt/h_a = {0:.3} is above {MAX_COURANT}: the flow step is too long for the explicit advection (shorten the coupling window)")]
    Courant(f64),
    #[error("the velocity is no longer finite")]
    NonFinite,
    #[error("on the device: {0}")]
    Device(String),
}

/// The box, its sides and the fluid.
#[derive(Debug, Clone)]
pub struct FlowSetup {
    pub grid: Grid,
    pub sides: Sides,
    /// Density ρ [kg/m³].
    pub density: f64,
    /// Kinematic viscosity ν = μ/ρ [m²/s].
    pub nu: f64,
}

/// What one step did.
#[derive(Debug, Clone, Copy, Default)]
pub struct StepReport {
    pub courant: f64,
    pub pressure_iterations: usize,
    /// Wall-clock time of the projection (divergence, solve, update) [s].
    /// On the device the whole step: its passes are queued together and
    /// the host sees only when the step's last submit is done.
    pub pressure_seconds: f64,
    pub viscous_iterations: usize,
    /// Whether the step took its window's kept prediction (`prediction.rs`).
    pub kept_prediction: bool,
}

pub struct Incompressible {
    /// The whole box.
    pub setup: FlowSetup,
    /// This rank's part of it, its cells as a grid, and its own sides.
    pub part: Part,
    local: Grid,
    pub(crate) sides: Sides,
    /// q's planes beyond the slab.
    halo: Halo,
    /// Face velocities uⁿ [m/s].
    pub u: Faces,
    /// Kinematic pressure p^{n−½}/ρ per cell [m²/s²].
    pub q: Vec<f64>,
    /// The last pressure correction φ, the next solve's first guess.
    phi: Vec<f64>,
    scratch: Vec<f64>,
    poisson: Poisson,
    padded: [Option<Padded>; 3],
    work: [Option<Work>; 3],
    /// The previous step's Δt (None before the first step).
    last_dt: Option<f64>,
    pub time: f64,
    /// Rigid bodies in the flow (`immersed.rs`), markers in the box's frame.
    pub bodies: Vec<ImmersedBody>,
    /// The canopy in the flow, an open surface (`canopy.rs`).
    pub canopy: Option<ImmersedBody>,
    /// How the box moves when it follows the parachute (`frame.rs`), and
    /// its sides as the ground sees them.
    pub frame: Option<Frame>,
    pub(crate) ground_sides: Sides,
    /// Under implicit coupling, the window's first prediction, for the
    /// window's later tries (`prediction.rs`); None: none kept.
    prediction: Option<Prediction>,
    /// Where the steps run on a GPU (`device.rs`).
    device: Option<device::OnDevice>,
}

impl Incompressible {
    /// A fluid at rest with the side velocities on the sides. The sides
    /// must pair up (periodic with periodic) and an axis one cell thick must
    /// be periodic, as the scenario check makes sure.
    pub fn new(setup: FlowSetup) -> Incompressible {
        let part = Part::whole(setup.grid.n, setup.sides);
        Incompressible::on(setup, part)
    }

    /// This rank's `part` of the flow.
    pub fn on(setup: FlowSetup, part: Part) -> Incompressible {
        let mut setup = setup;
        setup.grid.bc = bcs(&setup.sides);
        let global = setup.grid.clone();
        let grid = part.local_grid(&global);
        // From the whole box, so that every rank has the same components.
        let active = |c: usize| global.n[c] > 1;
        let padded = [0, 1, 2].map(|c| active(c).then(|| Padded::on(&part, &global, c)));
        let work = padded.clone().map(|p| p.map(|p| Work::new(p, &grid)));
        let mut flow = Incompressible {
            u: Faces::zeros(&grid),
            q: vec![0.0; grid.cells()],
            phi: vec![0.0; grid.cells()],
            scratch: vec![0.0; grid.cells()],
            poisson: Poisson::on(&global, &part, PRESSURE_TOLERANCE),
            sides: part.local_sides(),
            local: grid,
            part,
            halo: Halo::default(),
            padded,
            work,
            last_dt: None,
            time: 0.0,
            bodies: Vec::new(),
            canopy: None,
            frame: None,
            ground_sides: setup.sides,
            prediction: None,
            device: None,
            setup,
        };
        flow.impose_sides();
        flow
    }

    /// The step history and solver warm starts (`checkpoint.rs`).
    pub fn save_history(&self, into: &mut History) {
        if self.device_history(into) {
            return;
        }
        into.phi.clone_from(&self.phi);
        into.last_dt = self.last_dt;
        let work = self.work.iter().flatten();
        into.advection.resize(work.clone().count(), Vec::new());
        into.delta.resize(into.advection.len(), Vec::new());
        for (w, (n, d)) in work.zip(into.advection.iter_mut().zip(&mut into.delta)) {
            n.clone_from(&w.n[0]);
            d.clone_from(&w.delta.data);
        }
    }

    pub fn restore_history(&mut self, from: &History) {
        self.host_changed();
        self.phi.clone_from(&from.phi);
        self.last_dt = from.last_dt;
        let work = self.work.iter_mut().flatten();
        for (w, (n, d)) in work.zip(from.advection.iter().zip(&from.delta)) {
            w.n[0].clone_from(n);
            w.delta.data.clone_from(d);
        }
    }

    /// The whole box.
    pub fn grid(&self) -> &Grid {
        &self.setup.grid
    }

    /// This rank's cells (the whole box on one rank).
    pub fn local_grid(&self) -> &Grid {
        &self.local
    }

    /// Puts the side velocities on the side faces and makes periodic
    /// repeats (and the faces two ranks share) equal, after the caller set
    /// `u`.
    pub fn impose_sides(&mut self) {
        // From the current state: the device's, where it ran (the pressure
        // too, which the next upload sends back with the velocities).
        if let Err(e) = self.fetch_pressure().and_then(|_| self.fetch_velocities()) {
            eprintln!("fluid-proc: {e}");
        }
        self.host_changed();
        let (sides, side_by_side) = (&self.sides, self.side_by_side());
        let mut items: Vec<_> = self.padded.iter_mut().zip(&mut self.u.u).collect();
        by_component(side_by_side, &mut items, |_, (p, u)| {
            if let Some(p) = p {
                p.load_from(u);
                p.fill_ghosts(sides);
                p.store_into(u);
            }
        });
    }

    /// Whether the components' work goes side by side (`by_component`): on
    /// one rank, where a grid is large enough to split its rows among
    /// threads. Across MPI ranks a component's sums and ghost swaps are
    /// collective calls, which must come in the same order on every rank.
    fn side_by_side(&self) -> bool {
        !self.part.split() && rows::worth_threads(self.local.cells())
    }

    /// Rank 0's bodies and canopy, as it last placed them, on every rank:
    /// each rank forces its own faces from every marker (`immersed::force`).
    /// Nothing to do on one rank.
    pub fn share_bodies(&mut self) {
        let comm = self.part.comm.as_ref();
        if comm.ranks() == 1 {
            return;
        }
        let mut x = Vec::new();
        if comm.rank() == 0 {
            x.extend([self.bodies.len() as f64, self.canopy.is_some() as u8 as f64]);
            for b in self.bodies.iter().chain(&self.canopy) {
                b.encode(&mut x);
            }
        }
        let mut len = [x.len() as f64];
        comm.broadcast(&mut len);
        x.resize(len[0] as usize, 0.0);
        comm.broadcast(&mut x);
        if comm.rank() != 0 {
            let mut x = x.into_iter();
            let (bodies, canopy) = (x.next().unwrap_or(0.0), x.next().unwrap_or(0.0));
            self.bodies = (0..bodies as usize)
                .map(|_| ImmersedBody::decode(&mut x))
                .collect();
            self.canopy = (canopy != 0.0).then(|| ImmersedBody::decode(&mut x));
        }
    }

    /// Pressure p = ρq per cell at the last half step [Pa].
    pub fn pressure(&self) -> Vec<f64> {
        self.q.iter().map(|q| q * self.setup.density).collect()
    }

    /// Calls `f(cell, velocity)` for every cell, the velocity [m/s] being
    /// the mean of the cell's two faces along each axis.
    fn for_each_cell_velocity(&self, mut f: impl FnMut(usize, [f64; 3])) {
        let u = &self.u.u;
        for_each_cell_faces(self.local.n, |c, below, up| {
            f(
                c,
                [0, 1, 2].map(|d| 0.5 * (u[d][below[d]] + u[d][below[d] + up[d]])),
            );
        });
    }

    /// Velocity per cell [m/s], 3 per cell (x, y, z).
    pub fn cell_velocity(&self) -> Vec<f64> {
        let mut out = vec![0.0; 3 * self.local.cells()];
        self.for_each_cell_velocity(|c, v| out[3 * c..3 * c + 3].copy_from_slice(&v));
        out
    }

    /// Kinetic energy ½ρΣ|u|²V over the cells, from the cell velocities [J].
    pub fn kinetic_energy(&self) -> f64 {
        let (sum, volume) = self.cell_sums(1, |v, out| out[0] = v.iter().map(|x| x * x).sum());
        0.5 * self.setup.density * sum[0] * volume
    }

    /// Momentum ρΣuV over the cells, from the cell velocities [kg·m/s].
    pub fn momentum(&self) -> [f64; 3] {
        let (sum, volume) = self.cell_sums(3, |v, out| out.copy_from_slice(&v));
        [0, 1, 2].map(|d| self.setup.density * sum[d] * volume)
    }

    /// Σ_cells f(velocity)·V over the whole box, `k` sums at once, as the
    /// sums and a factor: on a uniform grid the plain sums and the one cell
    /// volume, on a graded one the sums weighed by each cell's and 1.
    fn cell_sums(&self, k: usize, f: impl Fn([f64; 3], &mut [f64])) -> (Vec<f64>, f64) {
        let mut sum = vec![0.0; k];
        let mut value = vec![0.0; k];
        let graded = self.local.is_graded();
        self.for_each_cell_velocity(|c, v| {
            f(v, &mut value);
            // x·1 is x to the bit: a uniform grid's sums stay plain.
            let weight = match graded {
                true => self.local.volume(self.local.coords(c)),
                false => 1.0,
            };
            for (s, x) in sum.iter_mut().zip(&value) {
                *s += x * weight;
            }
        });
        self.part.comm.sum(&mut sum);
        let volume: f64 = if graded {
            1.0
        } else {
            self.setup.grid.h.iter().product()
        };
        (sum, volume)
    }

    /// Largest |∇·u| over the cells [1/s].
    pub fn max_divergence(&mut self) -> f64 {
        crate::incompressible::faces::divergence(&self.local, &self.u, &mut self.scratch);
        self.part
            .max(self.scratch.iter().fold(0.0, |m, d| m.max(d.abs())))
    }

    /// Largest change of a face velocity from `before` over the box [m/s].
    pub fn max_change(&self, before: &Faces) -> f64 {
        self.part.max(self.u.max_difference(before))
    }

    /// The Courant number of a step of `dt`: max over the cells of
    /// Σ_a |u_a|·Δt/h_a (the cell velocities), which bounds how far the
    /// explicit advection reaches in one step whatever the flow's direction.
    pub fn courant(&self, dt: f64) -> f64 {
        let g = &self.local;
        let inv_w: [Vec<f64>; 3] = [0, 1, 2].map(|d| {
            (0..g.n[d])
                .map(|i| 1.0 / g.axes[d].width(i as isize))
                .collect()
        });
        let mut most: f64 = 0.0;
        self.for_each_cell_velocity(|c, v| {
            let x = g.coords(c);
            most = most.max((0..3).map(|a| v[a].abs() * inv_w[a][x[a]]).sum::<f64>());
        });
        self.part.max(most) * dt
    }

    /// Advances the flow by `dt` [s], `u` and `q` up to date after it
    /// (on a device too, `device.rs`).
    pub fn step(&mut self, dt: f64) -> Result<StepReport, FlowError> {
        let report = self.step_in_window(dt, false)?;
        self.fetch()?;
        Ok(report)
    }

    /// Implicit coupling: from now on, keep each window's first prediction
    /// for the window's later tries (`prediction.rs`).
    pub fn keep_predictions(&mut self) {
        self.prediction.get_or_insert_with(Prediction::default);
    }

    /// [`Incompressible::step`], `u` and `q` left on the device where the
    /// flow runs on one until [`Incompressible::fetch`]; `first`: the step is its window's first,
    /// whose prediction a later try of the window takes once
    /// [`Incompressible::keep_predictions`] was called.
    pub fn step_in_window(&mut self, dt: f64, first: bool) -> Result<StepReport, FlowError> {
        if self.device.is_some() {
            return self.step_on_device(dt, first);
        }
        let courant = self.courant(dt);
        if !courant.is_finite() {
            return Err(FlowError::NonFinite);
        }
        if courant > MAX_COURANT {
            return Err(FlowError::Courant(courant));
        }
        let (viscous_iterations, kept_prediction) = self.predict(dt, first)?;
        self.force_immersed(dt);
        if let (true, Some(p)) = (kept_prediction, &self.prediction) {
            p.guess(&mut self.phi);
        }
        let (pressure_iterations, pressure_seconds) = self.project(dt)?;
        if let (true, Some(p)) = (first, &mut self.prediction) {
            p.keep_correction(&self.phi);
        }
        self.last_dt = Some(dt);
        self.time += dt;
        Ok(StepReport {
            courant,
            pressure_iterations,
            pressure_seconds,
            viscous_iterations,
            kept_prediction,
        })
    }

    /// The predicted velocity u* of eq. (3.18): advection by Adams–Bashforth,
    /// viscosity by Crank–Nicolson (a Helmholtz solve per component), the
    /// last pressure's gradient; in a box that follows the parachute, the
    /// frame's acceleration. Returns the Helmholtz iterations, and whether
    /// the step took the change the window's first try computed: a
    /// window's `first` step does where it reads the same state
    /// (`prediction.rs`).
    fn predict(&mut self, dt: f64, first: bool) -> Result<(usize, bool), FlowError> {
        let (u, sides) = (&self.u, &self.sides);
        by_component(self.side_by_side(), &mut self.padded, |_, p| {
            if let Some(p) = p {
                p.load(u);
                p.fill_ghosts(sides);
            }
        });
        self.part.fill_halo(&self.q, &mut self.halo);
        let predicted = match (first, self.prediction.is_some()) {
            (true, true) => self.change_kept(dt)?,
            _ => (self.change(dt)?, false),
        };
        self.apply_change(dt);
        Ok(predicted)
    }

    /// The change δ = u* − uⁿ of each component over the step, before the
    /// frame's acceleration, into its work arrays, with Nⁿ.
    fn change(&mut self, dt: f64) -> Result<usize, FlowError> {
        let inputs = ChangeInputs {
            grid: &self.local,
            sides: &self.sides,
            padded: &self.padded,
            q: &self.q,
            halo: &self.halo,
            nu: self.setup.nu,
            ab: adams_bashforth(dt, self.last_dt),
            dt,
        };
        let done = by_component(self.side_by_side(), &mut self.work, |c, w| match w {
            Some(w) => inputs.component(c, w),
            None => Ok(0),
        });
        let mut viscous_iterations = 0;
        for d in done {
            viscous_iterations += d?;
        }
        Ok(viscous_iterations)
    }

    /// u* = uⁿ + δ less the frame's acceleration over the step.
    fn apply_change(&mut self, dt: f64) {
        // A box that follows the parachute accelerates: the air takes the
        // frame's body force −a·Δt, and the sides their velocities at the
        // step's end (`frame.rs`).
        let dv = self.move_frame(dt);
        let (sides, side_by_side) = (&self.sides, self.side_by_side());
        let mut items: Vec<_> = (self.padded.iter_mut().zip(&self.work))
            .zip(&mut self.u.u)
            .collect();
        by_component(side_by_side, &mut items, |c, ((u, w), faces)| {
            let (Some(u), Some(w)) = (u, w) else {
                return;
            };
            let lay = u.lay;
            let d = &w.delta.data;
            rows::each(&lay, lay.unknown_box(), [&mut u.data], |row, [u]| {
                for i in 0..row.len {
                    u[row.offset + i] += d[row.at + i] - dv[c];
                }
            });
            u.fill_ghosts(sides);
            u.store_into(faces);
        });
    }

    /// The bodies' and canopy's direct forcing on u*, before the projection,
    /// so that the projected field is divergence-free with them in it.
    fn force_immersed(&mut self, dt: f64) {
        // A body without markers (a mass point) is not in the flow.
        let mut forced: Vec<&mut ImmersedBody> = self
            .bodies
            .iter_mut()
            .chain(self.canopy.as_mut())
            .filter(|b| !b.markers.is_empty())
            .collect();
        if !forced.is_empty() {
            // The forcing acts on u* before the projection, so the projected
            // field is divergence-free with the bodies and canopy in it.
            let (global, density) = (&self.setup.grid, self.setup.density);
            let frame = self.frame.map_or([0.0; 3], |f| f.velocity);
            let air = Air { dt, density, frame };
            force(global, &self.part, &mut self.u, air, &mut forced);
            self.impose_sides();
        }
    }

    /// The projection and the pressure update of eq. (3.20); the Poisson
    /// iterations and their wall time.
    fn project(&mut self, dt: f64) -> Result<(usize, f64), FlowError> {
        let nu = self.setup.nu;
        let grid = &self.local;
        let clock = std::time::Instant::now();
        let pressure_iterations = project(
            grid,
            &mut self.poisson,
            &mut self.u,
            dt,
            &mut self.phi,
            &mut self.scratch,
        )?;
        let pressure_seconds = clock.elapsed().as_secs_f64();
        // Eq. (3.20) with A = −∇²: p^{n+½} = q + φ + (νΔt/2)Aφ.
        self.poisson.apply(&self.phi, &mut self.scratch);
        let alpha = 0.5 * nu * dt;
        for ((q, phi), a_phi) in self.q.iter_mut().zip(&self.phi).zip(&self.scratch) {
            *q += phi + alpha * a_phi;
        }
        Ok((pressure_iterations, pressure_seconds))
    }
}
