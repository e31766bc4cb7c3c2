//! Rigid bodies immersed in the incompressible flow (dissertation §2.4: the
//! parachutist or cargo as a finite body the air flows round), by direct
//! forcing on the MAC faces (Uhlmann, J. Comput. Phys. 209, 448–476, 2005,
//! §2.2; with the repeated forcing of Wang, Fan & Luo, Int. J. Numer. Meth.
//! Fluids 56, 2008):
//!
//! 1. interpolate each velocity component at the body's surface markers
//!    with Peskin's δ_h (`delta.rs`, dissertation eq. 3.25 in reverse);
//! 2. the force per unit mass that brings it to the body's velocity in one
//!    step, F_k = (U_k − Ũ_k)/Δt, is spread back with the same δ_h
//!    (eq. 3.25), weighted by the marker's volume ΔV_k = ΔA_k·h;
//! 3. repeat, so that markers whose kernels overlap agree.
//!
//! Spacings: a marker's volume ΔV_k = ΔA_k·h takes h as the geometric mean
//! of the spacings across the flow's axes (the thin axis of a 2-D flow left
//! out); markers are cut and retracted by the finest spacing.
//!
//! The markers sit 0.3 h inside the surface (Breugem, J. Comput. Phys. 231,
//! 4469–4498, 2012, §3.4): the kernel smears the forcing over ±2h, which
//! makes a body act larger than it is, and the retraction undoes it.
//!
//! The force the fluid exerts on the body is minus what the forcing gave
//! the fluid, plus the change of momentum of the fluid the body carries
//! inside it (Uhlmann eq. 29): F = −ρ Σ_k F_k ΔV_k + ρ V dU/dt. For a body
//! at rest in a steady flow it is the integral of the fluid's stress over
//! the surface: the pressure force of dissertation eq. (2.40) and the friction
//! that eq. leaves out. The torque about the centre is −ρ Σ (x_k − c) × F_k ΔV_k;
//! the inner fluid's share of it, ρ/ρ_body of the body's own change of
//! angular momentum, is left out.

use crate::comm::Slab;
use crate::incompressible::delta::{stencil, WIDTH};
use crate::incompressible::faces::Faces;
use crate::incompressible::grid::{Bc, Grid};
use crate::incompressible::part::Part;
use crate::surface::{enclosed_volume, Marker, Surface};
use nalgebra::Isometry3;

/// Forcing passes per step: the first brings each marker to its body's
/// velocity alone; the next ones remove what neighbouring markers' kernels
/// added (Wang et al. 2008 found a few enough).
pub const FORCING_PASSES: usize = 4;

/// How far inside the surface the markers sit, in grid spacings (Breugem
/// 2012 §3.4). Measured on the cylinder at Re = 20 with 15.6 cells across
/// it: c_D 5.8 % above Schäfer & Turek's without, 1.3 % with.
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
    let spacing = grid.spacing_range().0;
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
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct ImmersedBody {
    pub markers: Vec<Marker>,
    /// The velocity each marker moves with [m/s].
    pub targets: Vec<[f64; 3]>,
    /// A porous sheet's law, Δp = a·w + b·w|w| [Pa] for the air's velocity
    /// w through it along the markers' normals relative to the sheet
    /// (`canopy::porous_law`); None for a body or a closed fabric.
    pub porous: Option<[f64; 2]>,
    /// An open sheet (`place_sheet`): the air slips along it.
    sheet: bool,
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
            targets: Vec::new(),
            ..*self
        };
        self.targets = self.markers.iter().map(|m| self.velocity_at(m.x)).collect();
    }

    /// Puts an open surface (a canopy) in the flow: markers moving with
    /// the given velocities, and no fluid inside. The air slips along it.
    pub fn place_sheet(&mut self, markers: Vec<Marker>, targets: Vec<[f64; 3]>) {
        self.markers = markers;
        self.targets = targets;
        self.sheet = true;
    }

    /// Whether the body is an open sheet (`place_sheet`).
    pub fn is_sheet(&self) -> bool {
        self.sheet
    }

    /// Notes a step of `dt` [s] of forcing (the device's `force`, whose
    /// pushes come back at the window's end, `device.rs`).
    pub(crate) fn forced_for(&mut self, dt: f64) {
        self.duration += dt;
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

    /// Appends where the body is and how it moves (not what it has given
    /// the fluid) to `out`, as numbers for a broadcast ([`Self::decode`]).
    pub fn encode(&self, out: &mut Vec<f64>) {
        debug_assert_eq!(self.markers.len(), self.targets.len());
        let [a, b] = self.porous.unwrap_or([f64::NAN; 2]);
        out.extend([self.markers.len() as f64, a, b, self.sheet as u8 as f64]);
        out.extend(self.centre.iter().chain(&self.velocity).chain(&self.spin));
        out.push(self.volume);
        for (k, v) in self.markers.iter().zip(&self.targets) {
            out.extend(k.x.iter().chain(&k.normal).chain([&k.area]).chain(v));
        }
    }

    /// A body as [`Self::encode`] wrote it, taken from the front of `x`.
    pub fn decode(x: &mut impl Iterator<Item = f64>) -> ImmersedBody {
        let [n, a, b, sheet] = take(x);
        let [centre, velocity, spin] = [take(x), take(x), take(x)];
        let [volume] = take(x);
        let (markers, targets) = (0..n as usize)
            .map(|_| {
                let (at, normal, [area]) = (take(x), take(x), take(x));
                (
                    Marker {
                        x: at,
                        normal,
                        area,
                    },
                    take(x),
                )
            })
            .unzip();
        ImmersedBody {
            markers,
            targets,
            porous: (!a.is_nan()).then_some([a, b]),
            sheet: sheet != 0.0,
            centre,
            velocity,
            spin,
            volume,
            ..ImmersedBody::default()
        }
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

/// The next N numbers of an encoded body.
fn take<const N: usize>(x: &mut impl Iterator<Item = f64>) -> [f64; N] {
    std::array::from_fn(|_| x.next().expect("an encoded body is whole"))
}

/// The faces of component `c` a point's kernel reaches and their weights:
/// along each axis WIDTH lattice places (faces along c at i·h, cells
/// elsewhere at (i + ½)·h), wrapped round a periodic axis; a place outside
/// the box, or a side face, gets no weight. Split among ranks, only the
/// places of this rank's `slab` keep their weight, numbered from its low
/// side: its cells [lo, hi) along the slab axis, and for the slab axis's
/// own component the faces [lo, hi), the face at hi being the rank
/// above's (`part.rs`).
struct Reach {
    index: [[usize; WIDTH]; 3],
    weight: [[f64; WIDTH]; 3],
}

impl Reach {
    fn new(grid: &Grid, slab: &Slab, c: usize, x: [f64; 3]) -> Reach {
        let mut index = [[0; WIDTH]; 3];
        let mut weight = [[0.0; WIDTH]; 3];
        for d in 0..3 {
            let n = grid.n[d] as i64;
            let shift = if d == c { 0.0 } else { 0.5 };
            let (first, w) = stencil(grid.axes[d].coordinate(x[d]) - shift);
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
        let a = slab.axis;
        for j in 0..WIDTH {
            if (slab.lo..slab.hi).contains(&index[a][j]) {
                index[a][j] -= slab.lo;
            } else {
                weight[a][j] = 0.0;
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

/// How much of a sheet's own spread force its markers read back, per unit
/// of force per area and spacing: Peskin's Σφ² = 3/8 along the normal
/// (`delta.rs`), the kernel summing to one along the sheet.
const SELF_WEIGHT: f64 = 3.0 / 8.0;

/// Each active component's reach from a marker.
type Reaches = [Option<Reach>; 3];

fn interpolate(u: &Faces, m: &[[usize; 3]; 3], r: &Reaches) -> [f64; 3] {
    let mut v = [0.0; 3];
    for c in 0..3 {
        if let Some(r) = &r[c] {
            r.for_each(m[c], |f, w| v[c] += w * u.u[c][f]);
        }
    }
    v
}

/// The porous sheets' pushes, from the air `air` at their markers: the
/// Ergun drag (thesis eqs. 6–10) on the air crossing each marker, implicit
/// in the crossing speed (κ = Δt·weight/(ρ·h)), over the step Δt in air of
/// density ρ.
fn porous_pushes(
    bodies: &[&mut ImmersedBody],
    air: &[Vec<[f64; 3]>],
    kappa: f64,
    [dt, density]: [f64; 2],
    pushes: &mut [Vec<[f64; 3]>],
) {
    for (b, body) in bodies.iter().enumerate() {
        let Some([a, bb]) = body.porous else { continue };
        for ((k, air), v) in body.markers.iter().zip(&air[b]).zip(&body.targets) {
            let n = k.normal;
            let seen: f64 = (0..3).map(|d| (air[d] - v[d]) * n[d]).sum();
            let linear = 1.0 + kappa * a;
            let root = (linear * linear + 4.0 * kappa * bb * seen.abs()).sqrt();
            let w = 2.0 * seen / (linear + root);
            let drop = a * w + bb * w * w.abs();
            pushes[b].push(n.map(|n| -dt * drop * n * k.area / density));
        }
    }
}

/// The other bodies' pushes (one forcing pass): the momentum per unit
/// density, F_k ΔV_k Δt, that brings the air at each marker to the marker's
/// velocity; across a closed sheet only along its normal.
fn solid_pushes(
    bodies: &[&mut ImmersedBody],
    air: &[Vec<[f64; 3]>],
    spacing: f64,
    pushes: &mut [Vec<[f64; 3]>],
) {
    for (b, body) in bodies.iter().enumerate() {
        pushes[b].clear();
        if body.porous.is_some() {
            continue;
        }
        for ((k, air), v) in body.markers.iter().zip(&air[b]).zip(&body.targets) {
            let mut e = [0, 1, 2].map(|d| v[d] - air[d]);
            if body.sheet {
                let across: f64 = (0..3).map(|d| e[d] * k.normal[d]).sum();
                e = k.normal.map(|n| across * n);
            }
            pushes[b].push(e.map(|e| e * k.area * spacing));
        }
    }
}

/// The air's velocity over the ground [m/s] at each marker of the bodies
/// `pick` chooses (none at the others'), the faces moving at `frame`.
/// Split among ranks, each interpolates from its own faces and the shares
/// are summed over the ranks, so that every rank sees the whole kernel's
/// and computes the same forcing.
fn air_at(
    u: &Faces,
    m: &[[usize; 3]; 3],
    reach: &[Vec<Reaches>],
    pick: impl Fn(usize) -> bool,
    part: &Part,
    frame: [f64; 3],
) -> Vec<Vec<[f64; 3]>> {
    let mut air: Vec<Vec<[f64; 3]>> = reach
        .iter()
        .enumerate()
        .map(|(b, r)| match pick(b) {
            true => r.iter().map(|r| interpolate(u, m, r)).collect(),
            false => Vec::new(),
        })
        .collect();
    if part.split() {
        let mut shares: Vec<f64> = air.iter().flatten().flatten().copied().collect();
        part.comm.sum(&mut shares);
        for (v, s) in air.iter_mut().flatten().zip(shares.chunks_exact(3)) {
            v.copy_from_slice(s);
        }
    }
    // Over the ground, as the markers' targets are.
    if frame != [0.0; 3] {
        for v in air.iter_mut().flatten() {
            (0..3).for_each(|d| v[d] += frame[d]);
        }
    }
    air
}

impl ImmersedBody {
    /// Notes momentum per unit density `push` [m⁴/s] given to the fluid at
    /// x, and its moment about the centre.
    pub(crate) fn record(&mut self, grid: &Grid, x: [f64; 3], push: [f64; 3]) {
        // Along a 2-D flow's thin axis nothing varies, so the forcing there
        // has no moment arm.
        let r = [0, 1, 2].map(|d| match grid.n[d] {
            1 => 0.0,
            _ => x[d] - self.centre[d],
        });
        for d in 0..3 {
            self.impulse[d] += push[d];
            self.angular[d] +=
                r[(d + 1) % 3] * push[(d + 2) % 3] - r[(d + 2) % 3] * push[(d + 1) % 3];
        }
    }
}

/// The air a forcing step acts on: the step `dt` [s], the density [kg/m³],
/// and the velocity over the ground [m/s] of the box its faces move with
/// (`frame.rs`; zero for a fixed box), which the markers' targets are not.
#[derive(Debug, Clone, Copy)]
pub struct Air {
    pub dt: f64,
    pub density: f64,
    pub frame: [f64; 3],
}

/// Holds the face velocities `u` to the bodies' motion at their markers
/// over a step of `dt` in a fluid of `density` [kg/m³], recording on each
/// body what the forcing gave the fluid. The periodic repeat faces (face n
/// of a periodic axis) are left for the caller to make equal again.
///
/// `grid` is the whole box and `u` this rank's `part` of it. Split among
/// ranks, every rank holds every body's markers, forces its own faces and
/// records the whole forcing (`air_at`); the faces a slab shares with the
/// rank below are the caller's to copy down, as the periodic repeats.
///
/// A sheet (`ImmersedBody::place_sheet`) is a fabric, whose load is the
/// pressure jump across it, a normal force: by Newton's third law the air
/// gets only a normal force back, and slips along the sheet. A closed sheet
/// holds the air's normal velocity to its own. Across a porous sheet
/// (`ImmersedBody::porous`) the fabric's drag −Δp(w)·ΔA·n is spread once
/// (eq. 3.25), w
/// the air's relative normal velocity after the drag acts, from
/// w + κ(a·w + b·w|w|) = w̃ with w̃ before it and κ = Δt·(3/8)/(ρh), the
/// sheet's response to its own force (implicit, so a stiff fabric is no
/// limit on the step; the spread force is Δp(w) whatever κ is).
pub fn force(grid: &Grid, part: &Part, u: &mut Faces, air: Air, bodies: &mut [&mut ImmersedBody]) {
    let Air { dt, density, frame } = air;
    let active: Vec<usize> = (0..3).filter(|&d| grid.n[d] > 1).collect();
    // ΔV_k = ΔA_k·h with h the mean spacing across the flow's own axes.
    let spacing = active
        .iter()
        .map(|&d| grid.h[d])
        .product::<f64>()
        .powf(1.0 / active.len() as f64);
    let cell: f64 = grid.h.iter().product();
    let m = [0, 1, 2].map(|c| {
        let mut m = part.slab.cells();
        m[c] += 1;
        m
    });
    let reach: Vec<Vec<Reaches>> = bodies
        .iter()
        .map(|b| {
            b.markers
                .iter()
                .map(|k| {
                    [0, 1, 2].map(|c| (grid.n[c] > 1).then(|| Reach::new(grid, &part.slab, c, k.x)))
                })
                .collect()
        })
        .collect();
    let spread = |u: &mut Faces, r: &Reaches, push: [f64; 3]| {
        for c in 0..3 {
            if let Some(r) = &r[c] {
                r.for_each(m[c], |f, w| u.u[c][f] += push[c] * w / cell);
            }
        }
    };
    let kappa = dt * SELF_WEIGHT / (density * spacing);
    // Every marker reads the same field, then all spread (Uhlmann's
    // explicit forcing), so the order of the markers does not matter.
    let mut pushes: Vec<Vec<[f64; 3]>> = vec![Vec::new(); bodies.len()];
    let air = air_at(u, &m, &reach, |b| bodies[b].porous.is_some(), part, frame);
    porous_pushes(bodies, &air, kappa, [dt, density], &mut pushes);
    let apply = |pushes: &[Vec<[f64; 3]>], u: &mut Faces, bodies: &mut [&mut ImmersedBody]| {
        for (b, body) in bodies.iter_mut().enumerate() {
            for (k, push) in pushes[b].iter().enumerate() {
                let push = [0, 1, 2].map(|c| if grid.n[c] > 1 { push[c] } else { 0.0 });
                spread(u, &reach[b][k], push);
                let x = body.markers[k].x;
                body.record(grid, x, push);
            }
        }
    };
    apply(&pushes, u, bodies);
    for _ in 0..FORCING_PASSES {
        // Across a porous sheet the drag did the work: only the others
        // are forced again.
        let air = air_at(u, &m, &reach, |b| bodies[b].porous.is_none(), part, frame);
        solid_pushes(bodies, &air, spacing, &mut pushes);
        apply(&pushes, u, bodies);
    }
    for body in bodies.iter_mut() {
        body.duration += dt;
    }
}
