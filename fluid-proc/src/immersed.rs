//! Rigid bodies immersed in the incompressible flow (seed 000 §2.4: the
//! parachutist or cargo as a finite body the air flows round), by direct
//! forcing on the MAC faces (Uhlmann, J. Comput. Phys. 209, 448–476, 2005,
//! §2.2; with the repeated forcing of Wang, Fan & Luo, Int. J. Numer. Meth.
//! Fluids 56, 2008):
//!
//! 1. interpolate each velocity component at the body's surface markers
//!    with Peskin's δ_h (`delta.rs`, seed 000 eq. 3.25 in reverse);
//! 2. the force per unit mass that brings it to the body's velocity in one
//!    step, F_k = (U_k − Ũ_k)/Δt, is spread back with the same δ_h
//!    (eq. 3.25), weighted by the marker's volume ΔV_k = ΔA_k·h;
//! 3. repeat, so that markers whose kernels overlap agree.
//!
//! The markers sit 0.3 h inside the surface (Breugem, J. Comput. Phys. 231,
//! 4469–4498, 2012, §3.4): the kernel smears the forcing over ±2h, which
//! makes a body act larger than it is, and the retraction undoes it.
//!
//! The force the fluid exerts on the body is minus what the forcing gave
//! the fluid, plus the change of momentum of the fluid the body carries
//! inside it (Uhlmann eq. 29): F = −ρ Σ_k F_k ΔV_k + ρ V dU/dt. For a body
//! at rest in a steady flow it is the integral of the fluid's stress over
//! the surface: the pressure force of seed 000 eq. (2.40) and the friction
//! that eq. leaves out. The torque about the centre is −ρ Σ (x_k − c) × F_k ΔV_k;
//! the inner fluid's share of it, ρ/ρ_body of the body's own change of
//! angular momentum, is left out.

use crate::delta::{stencil, WIDTH};
use crate::grid::{Bc, Grid};
use crate::mac::Faces;
use crate::surface::{enclosed_volume, Marker, Surface};
use nalgebra::Isometry3;

/// Forcing passes per step: the first brings each marker to its body's
/// velocity alone; the next ones remove what neighbouring markers' kernels
/// added (Wang et al. 2008 found a few enough).
pub const FORCING_PASSES: usize = 4;

/// How far inside the surface the markers sit, in grid spacings (Breugem
/// 2012 §3.4). Measured on the cylinder at Re = 20 with 15.6 cells across
/// it: c_D 5.8 % above Schäfer & Turek's without, 1.2 % with.
pub const RETRACTION: f64 = 0.3;

/// The markers of `surface` placed by `pose` (world ← own) in a box of
/// `grid` whose low corner is at `origin` [m], in the box's frame and
/// retracted (`RETRACTION`), and the volume the surface encloses inside
/// the flow [m³]. A 2-D flow (one cell thick along an axis) takes the
/// section by its mid-plane.
pub fn place_markers(
    surface: &Surface,
    pose: &Isometry3<f64>,
    grid: &Grid,
    origin: [f64; 3],
) -> (Vec<Marker>, f64) {
    let active: Vec<usize> = (0..3).filter(|&d| grid.n[d] > 1).collect();
    let spacing = active
        .iter()
        .map(|&d| grid.h[d])
        .fold(f64::INFINITY, f64::min);
    let placed = Isometry3::translation(-origin[0], -origin[1], -origin[2]) * pose;
    let (mut markers, dimensions) = match (0..3).find(|&d| grid.n[d] == 1) {
        Some(thin) => {
            let level = 0.5 * grid.h[thin];
            (
                surface.section(&placed, thin, level, spacing, grid.h[thin]),
                2,
            )
        }
        None => (surface.markers(&placed, spacing), 3),
    };
    let volume = enclosed_volume(&markers, placed.translation.vector.into(), dimensions);
    for m in &mut markers {
        for d in 0..3 {
            m.x[d] -= RETRACTION * spacing * m.normal[d];
        }
    }
    (markers, volume)
}

/// One body in the flow: its markers at its present pose (in the box's
/// frame, the box's low corner at the origin), how it moves, and what the
/// forcing has given the fluid since its load was last taken.
#[derive(Debug, Clone, Default)]
pub struct ImmersedBody {
    pub markers: Vec<Marker>,
    /// Centre of mass [m].
    pub centre: [f64; 3],
    /// Velocity of the centre [m/s].
    pub velocity: [f64; 3],
    /// Angular velocity [rad/s].
    pub spin: [f64; 3],
    /// Volume the markers enclose inside the flow [m³].
    pub volume: f64,
    /// Σ F_k ΔV_k Δt over the steps since the load was taken [m⁴/s], and
    /// Σ (x_k − c) × F_k ΔV_k Δt [m⁵/s].
    impulse: [f64; 3],
    angular: [f64; 3],
    /// The body's change of velocity and the time since the load was taken.
    dv: [f64; 3],
    duration: f64,
}

impl ImmersedBody {
    /// Puts the body at a new pose, keeping what it has given the fluid so
    /// far (a body's first placement is not a change of velocity).
    pub fn place(
        &mut self,
        markers: Vec<Marker>,
        centre: [f64; 3],
        velocity: [f64; 3],
        spin: [f64; 3],
        volume: f64,
    ) {
        if !self.markers.is_empty() {
            let old = self.velocity;
            for ((dv, v), o) in self.dv.iter_mut().zip(velocity).zip(old) {
                *dv += v - o;
            }
        }
        *self = ImmersedBody {
            markers,
            centre,
            velocity,
            spin,
            volume,
            ..*self
        };
    }

    /// The body's velocity at point x: U + ω × (x − c) [m/s].
    pub fn velocity_at(&self, x: [f64; 3]) -> [f64; 3] {
        let r = [0, 1, 2].map(|d| x[d] - self.centre[d]);
        let w = self.spin;
        [
            self.velocity[0] + w[1] * r[2] - w[2] * r[1],
            self.velocity[1] + w[2] * r[0] - w[0] * r[2],
            self.velocity[2] + w[0] * r[1] - w[1] * r[0],
        ]
    }

    /// The fluid's mean force [N] and torque about the centre [N·m] on the
    /// body since the last call, for a fluid of this density [kg/m³]; zero
    /// before any step.
    pub fn take_load(&mut self, density: f64) -> ([f64; 3], [f64; 3]) {
        let t = self.duration;
        let load = if t > 0.0 {
            (
                [0, 1, 2].map(|d| density * (self.volume * self.dv[d] - self.impulse[d]) / t),
                self.angular.map(|a| -density * a / t),
            )
        } else {
            ([0.0; 3], [0.0; 3])
        };
        self.impulse = [0.0; 3];
        self.angular = [0.0; 3];
        self.dv = [0.0; 3];
        self.duration = 0.0;
        load
    }
}

/// The faces of component `c` a point's kernel reaches and their weights:
/// along each axis WIDTH lattice places (faces along c at i·h, cells
/// elsewhere at (i + ½)·h), wrapped round a periodic axis; a place outside
/// the box, or a side face, gets no weight.
struct Reach {
    index: [[usize; WIDTH]; 3],
    weight: [[f64; WIDTH]; 3],
}

impl Reach {
    fn new(grid: &Grid, c: usize, x: [f64; 3]) -> Reach {
        let mut index = [[0; WIDTH]; 3];
        let mut weight = [[0.0; WIDTH]; 3];
        for d in 0..3 {
            let n = grid.n[d] as i64;
            let shift = if d == c { 0.0 } else { 0.5 };
            let (first, w) = stencil(x[d] / grid.h[d] - shift);
            for j in 0..WIDTH {
                let i = first + j as i64;
                let periodic = grid.bc[d][0] == Bc::Periodic;
                let (lo, hi) = if d == c { (1, n - 1) } else { (0, n - 1) };
                if periodic {
                    index[d][j] = i.rem_euclid(n) as usize;
                    weight[d][j] = w[j];
                } else if (lo..=hi).contains(&i) {
                    index[d][j] = i as usize;
                    weight[d][j] = w[j];
                }
            }
        }
        Reach { index, weight }
    }

    /// Calls `f(face, weight)` for the faces reached (face numbering of
    /// `Faces::u[c]`, whose row along c has n_c + 1 faces).
    fn for_each(&self, m: [usize; 3], mut f: impl FnMut(usize, f64)) {
        for k in 0..WIDTH {
            let wk = self.weight[2][k];
            if wk == 0.0 {
                continue;
            }
            for j in 0..WIDTH {
                let wj = wk * self.weight[1][j];
                if wj == 0.0 {
                    continue;
                }
                let row = m[0] * (self.index[1][j] + m[1] * self.index[2][k]);
                for i in 0..WIDTH {
                    let w = wj * self.weight[0][i];
                    if w != 0.0 {
                        f(row + self.index[0][i], w);
                    }
                }
            }
        }
    }
}

/// Holds the face velocities `u` to the bodies' motion at their markers
/// over a step of `dt`, recording on each body what the forcing gave the
/// fluid. The periodic repeat faces (face n of a periodic axis) are left
/// for the caller to make equal again.
pub fn force(grid: &Grid, u: &mut Faces, dt: f64, bodies: &mut [ImmersedBody]) {
    let active: Vec<usize> = (0..3).filter(|&d| grid.n[d] > 1).collect();
    // ΔV_k = ΔA_k·h with h the mean spacing across the flow's own axes.
    let spacing = active
        .iter()
        .map(|&d| grid.h[d])
        .product::<f64>()
        .powf(1.0 / active.len() as f64);
    let cell: f64 = grid.h.iter().product();
    for &c in &active {
        let mut m = grid.n;
        m[c] += 1;
        let reach: Vec<Vec<Reach>> = bodies
            .iter()
            .map(|b| b.markers.iter().map(|k| Reach::new(grid, c, k.x)).collect())
            .collect();
        let target: Vec<Vec<f64>> = bodies
            .iter()
            .map(|b| b.markers.iter().map(|k| b.velocity_at(k.x)[c]).collect())
            .collect();
        let mut push = vec![Vec::new(); bodies.len()];
        for _ in 0..FORCING_PASSES {
            // Every marker reads the same field, then all spread (Uhlmann's
            // explicit forcing), so the order of the markers does not matter.
            for (b, body) in bodies.iter().enumerate() {
                push[b].clear();
                for (k, r) in reach[b].iter().enumerate() {
                    let mut seen = 0.0;
                    r.for_each(m, |f, w| seen += w * u.u[c][f]);
                    // F_k ΔV_k Δt: the momentum per unit density the marker adds.
                    push[b].push((target[b][k] - seen) * body.markers[k].area * spacing);
                }
            }
            for (b, body) in bodies.iter_mut().enumerate() {
                for (k, r) in reach[b].iter().enumerate() {
                    let p = push[b][k];
                    r.for_each(m, |f, w| u.u[c][f] += p * w / cell);
                    body.impulse[c] += p;
                    let x = body.markers[k].x;
                    // Along a 2-D flow's thin axis nothing varies, so the
                    // forcing there has no moment arm.
                    let arm = [0, 1, 2].map(|d| match grid.n[d] {
                        1 => 0.0,
                        _ => x[d] - body.centre[d],
                    });
                    // arm × p e_c has components arm_{c+2}·p along c + 1
                    // and −arm_{c+1}·p along c + 2.
                    let (a, b2) = ((c + 1) % 3, (c + 2) % 3);
                    body.angular[a] += arm[b2] * p;
                    body.angular[b2] -= arm[a] * p;
                }
            }
        }
    }
    for body in bodies.iter_mut() {
        body.duration += dt;
    }
}
