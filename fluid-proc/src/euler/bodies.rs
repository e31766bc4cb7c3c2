//! Rigid bodies as moving, reflecting boundaries of the gas (dissertation
//! §4.1: rigid bodies in compressible flow), by ghost cells filled from
//! image points (Forrer & Jeltsch, J. Comput. Phys. 140, 259–277, 1998;
//! Mittal et al., J. Comput. Phys. 227, 4825–4852, 2008).
//!
//! Before every Runge–Kutta stage the bodies are placed at the stage's
//! time and each cell whose centre lies inside one is solid. A solid cell
//! within the WENO5 reach (three cells along an axis) of a gas cell is a
//! ghost: its state mirrors the gas at its image point, the point at
//! distance d = max(|φ|, 1.5 h) outside the wall along the normal,
//! interpolated (multi-linearly, over the corners of its stencil that are
//! not solid, so the values stay a convex mix): the same density and pressure (a
//! slip wall with no normal pressure gradient), the same tangential
//! velocity, and the normal velocity relative to the wall reversed. At
//! the face between a gas cell and a ghost the WENO5 flux then meets a
//! mirrored pair of states, whose Riemann problem moves the face at the
//! wall's normal speed: the gas sees a wall that moves with the body and
//! lets nothing through it. (Reversing only |φ|/d of it, which makes the
//! velocity vanish at the wall for a linear profile, made a weaker
//! piston: the gas lagged behind an impulsively started one and the
//! shock ran 2 % slow, on any grid.) The fluxes are the ordinary WENO5
//! fluxes, so the scheme, its order away from the body and its Δt are
//! those of the gas alone. Solid cells are not stepped: a ghost takes
//! its image's state again at every stage, and a deeper solid cell, which
//! no gas cell reads, keeps the state it had (its last as a ghost, or the
//! initial gas), the same on any number of ranks. A cell the body leaves
//! was a ghost the stage before and starts from that state.
//!
//! The price: the wall is not a face of the cells, so the gas's mass,
//! momentum and energy are conserved only to the method's error at the
//! wall, O(h) (cut cells, Monasse et al., J. Comput. Phys. 231,
//! 2977–2994, 2012, would conserve them exactly). The body's load is the
//! pressure on a closed tessellation of its surface, −∮p n dA, with p read
//! there from the gas and its ghosts; the load a window hands rigid-proc
//! is its mean over the window's stages, weighted as the TVD Runge–Kutta
//! step weighs them (Shu & Osher eq. 2.18: 1/6, 1/6, 2/3).

use crate::euler::gas::{Gas, Primitive, State};
use crate::euler::level_set::Placed;
use crate::layout::{Layout, GHOSTS};
use crate::surface::{Marker, Surface};
use exchange::Body;
use exchange::Shape;
use nalgebra::Vector3;

pub use crate::euler::body_motion::Kinematics;

/// The least distance of an image point from the wall, in cells: its
/// stencil then lies in the gas beside a wall along the grid, and mostly
/// so beside an inclined one.
const IMAGE_CELLS: f64 = 1.5;

/// One body in the gas: its shape, how it moves, and the impulse the gas
/// has given it since its load was last taken.
#[derive(Clone)]
pub struct GasBody {
    pub name: String,
    shape: Shape,
    surface: Surface,
    pub kinematics: Kinematics,
    /// ∫F dt [N·s] and ∫τ dt about the centre [N·m·s], and the time [s].
    impulse: [f64; 3],
    angular: [f64; 3],
    duration: f64,
}

impl std::fmt::Debug for GasBody {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GasBody")
            .field("name", &self.name)
            .field("kinematics", &self.kinematics)
            .finish_non_exhaustive()
    }
}

impl GasBody {
    /// rigid-proc's `body` in a box whose low corner is at `origin` [m],
    /// at time `t` [s]; None for a mass point (it has no surface).
    pub fn of(body: &Body, origin: [f64; 3], t: f64, spacing: f64) -> Option<GasBody> {
        let shape = body.shape.clone()?;
        let kinematics = Kinematics::of(body, origin, t);
        Some(GasBody::new(&body.name, shape, kinematics, spacing))
    }

    /// A body of `shape` moving as `kinematics`; its surface drawn at
    /// `spacing` [m] (the box's finest cell).
    pub fn new(name: &str, shape: Shape, kinematics: Kinematics, spacing: f64) -> GasBody {
        GasBody {
            name: name.into(),
            surface: Surface::of(&shape, spacing),
            shape,
            kinematics,
            impulse: [0.0; 3],
            angular: [0.0; 3],
            duration: 0.0,
        }
    }

    /// The mean force [N] and torque about the centre [N·m] since the last
    /// call (zero before any step), on this rank's part of the surface.
    pub fn take_load(&mut self) -> ([f64; 3], [f64; 3]) {
        let d = self.duration;
        let mean = |v: [f64; 3]| v.map(|x| if d > 0.0 { x / d } else { 0.0 });
        let out = (mean(self.impulse), mean(self.angular));
        self.impulse = [0.0; 3];
        self.angular = [0.0; 3];
        self.duration = 0.0;
        out
    }

    /// Whether the gas sees the body at time `t`: in a 2-D box, whether
    /// its section by the mid-plane has an outline.
    pub fn is_seen(&self, cells: &Cells, t: f64) -> bool {
        let (pose, _) = self.kinematics.at(t);
        match Placed::new(&self.shape, &self.surface, &pose, cells.thin) {
            Placed::Section { segments, .. } => !segments.is_empty(),
            Placed::Solid { .. } => true,
        }
    }

    /// The closed tessellation of the surface at time `t` (a 2-D box's
    /// section, its pieces one box thick) and the centre then.
    fn markers(&self, cells: &Cells, t: f64) -> (Vec<Marker>, Vector3<f64>) {
        let (pose, mut centre) = self.kinematics.at(t);
        if let Some((axis, level)) = cells.thin {
            // The section's torque about the centre's point in its plane: a
            // centre off the mid-plane would add a spurious arm.
            centre[axis] = level;
        }
        let spacing = cells.finest();
        let markers = match cells.thin {
            Some((axis, level)) => {
                let thickness = cells.h[axis];
                self.surface.section(&pose, axis, level, spacing, thickness)
            }
            None => self.surface.markers(&pose, spacing),
        };
        (markers, centre)
    }

    /// Adds `weight` × the load at time `t` to the impulse: −p n A at
    /// every marker this rank holds, p read from the gas and its ghosts.
    /// The surface outside the box meets no gas and takes no load (a
    /// piston wider than its channel is pushed on its face alone).
    fn add_load(&mut self, cells: &Cells, u: &[State], gas: &Gas, t: f64, weight: f64) {
        let (markers, centre) = self.markers(cells, t);
        let (mut f, mut tau) = (Vector3::zeros(), Vector3::zeros());
        for m in markers.iter().filter(|m| cells.holds(m.x)) {
            let mut p = 0.0;
            for (at, w) in cells.stencil(m.x).into_iter().flatten() {
                p += w * gas.pressure(&u[at]);
            }
            let force = Vector3::from(m.normal) * (-p * m.area);
            f += force;
            tau += (Vector3::from(m.x) - centre).cross(&force);
        }
        for d in 0..3 {
            self.impulse[d] += weight * f[d];
            self.angular[d] += weight * tau[d];
        }
        self.duration += weight;
    }
}

/// This rank's cells as the bodies see them.
#[derive(Debug, Clone, Copy)]
pub struct Cells {
    /// The cells holding values along each axis, ghosts included: [low,
    /// high) in local cells.
    pub reach: [[isize; 2]; 3],
    /// The cells told apart as gas or solid: this rank's, and the halo
    /// planes from the ranks beside it.
    pub classified: [[isize; 2]; 3],
    pub lay: Layout,
    /// This rank's cells per axis, and the whole box's.
    pub n: [usize; 3],
    pub whole: [usize; 3],
    /// The global index of this rank's first cell.
    pub offset: [usize; 3],
    /// Cell size per axis [m].
    pub h: [f64; 3],
    /// A 2-D box's thin axis and the level of its mid-plane [m].
    pub thin: Option<(usize, f64)>,
}

/// Up to 2³ cells (padded indices) and their weights.
type Stencil = [Option<(usize, f64)>; 8];

impl Cells {
    fn active(&self, d: usize) -> bool {
        self.whole[d] > 1
    }

    /// The smallest cell size along the axes that vary [m].
    pub fn finest(&self) -> f64 {
        (0..3)
            .filter(|&d| self.active(d))
            .map(|d| self.h[d])
            .fold(f64::INFINITY, f64::min)
    }

    fn coarsest(&self) -> f64 {
        (0..3)
            .filter(|&d| self.active(d))
            .map(|d| self.h[d])
            .fold(0.0, f64::max)
    }

    /// The centre of local cell `c` in the box's frame [m].
    fn centre(&self, c: [isize; 3]) -> [f64; 3] {
        [0, 1, 2].map(|d| (c[d] + self.offset[d] as isize) as f64 * self.h[d] + 0.5 * self.h[d])
    }

    /// `x` moved into the box's span of cell centres along each axis that
    /// varies (an image point beyond a side reads the side's cells).
    fn clamped(&self, x: Vector3<f64>) -> [f64; 3] {
        [0, 1, 2].map(|d| match self.active(d) {
            true => x[d].clamp(0.5 * self.h[d], (self.whole[d] as f64 - 0.5) * self.h[d]),
            false => x[d],
        })
    }

    fn index(&self, c: [usize; 3]) -> usize {
        c[0] + self.n[0] * (c[1] + self.n[1] * c[2])
    }

    /// Whether `x` lies in the box, in a cell of this rank's (along an
    /// axis that varies): each marker is counted on one rank.
    fn holds(&self, x: [f64; 3]) -> bool {
        (0..3).filter(|&d| self.active(d)).all(|d| {
            let global = (x[d] / self.h[d]).floor();
            let local = global - self.offset[d] as f64;
            (0.0..self.whole[d] as f64).contains(&global)
                && (0.0..self.n[d] as f64).contains(&local)
        })
    }

    /// The cells around `x` with multi-linear weights; corners beyond the
    /// cells holding values ([`Cells::reach`]) are left out (None).
    fn stencil(&self, x: [f64; 3]) -> Stencil {
        let mut base = [0isize; 3];
        let mut frac = [0.0; 3];
        for d in (0..3).filter(|&d| self.active(d)) {
            let s = x[d] / self.h[d] - 0.5 - self.offset[d] as f64;
            base[d] = s.floor() as isize;
            frac[d] = s - s.floor();
        }
        let mut out = [None; 8];
        for (k, slot) in out.iter_mut().enumerate() {
            let mut c = [0isize; 3];
            let mut w = 1.0;
            let mut inside = true;
            for d in 0..3 {
                let up = (k >> d) & 1 == 1;
                if !self.active(d) {
                    if up {
                        w = 0.0;
                    }
                    continue;
                }
                c[d] = base[d] + up as isize;
                w *= if up { frac[d] } else { 1.0 - frac[d] };
                inside &= (self.reach[d][0]..self.reach[d][1]).contains(&c[d]);
            }
            if w > 0.0 && inside {
                *slot = Some((self.lay.at(c), w));
            }
        }
        out
    }
}

/// A solid cell the gas reads: where its state comes from.
#[derive(Debug, Clone, Copy)]
struct Ghost {
    /// Padded index.
    at: usize,
    /// The image point's stencil over gas cells, weights summing to 1.
    image: Stencil,
    normal: Vector3<f64>,
    /// The wall's velocity at the closest point [m/s].
    wall: Vector3<f64>,
}

/// The solid cells of this rank at one time: which they are, and what
/// fills the ghosts among them.
#[derive(Debug, Clone, Default)]
pub struct Solids {
    /// Per cell of this rank (x fastest): whether its centre is inside a body.
    pub inside: Vec<bool>,
    ghosts: Vec<Ghost>,
    /// Per cell of this rank: whether it is solid and no gas cell reads it.
    pub deep: Vec<bool>,
    /// The time the bodies were placed at [s]; None before they are.
    pub placed_at: Option<f64>,
}

/// What a padded cell is, as [`Solids::find`] classifies it.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    /// Beyond a side of the box: a ghost of the side's condition.
    Beyond,
    Gas,
    Solid,
}

impl Solids {
    /// The bodies placed at time `t`, over this rank's `cells` and the
    /// halo planes other ranks' cells fill (so that every rank tells gas
    /// from solid there as the rank owning them does).
    pub fn find(bodies: &[GasBody], cells: &Cells, t: f64) -> Solids {
        let lay = cells.lay;
        let mut kind = vec![Kind::Beyond; lay.dims().iter().product()];
        let known = cells.classified;
        lay.for_box(known, |_, at| kind[at] = Kind::Gas);
        // (local cell, body, closest point, centre) of this rank's solid cells.
        let mut solid = Vec::new();
        for (b, body) in bodies.iter().enumerate() {
            let (pose, centre) = body.kinematics.at(t);
            let placed = Placed::new(&body.shape, &body.surface, &pose, cells.thin);
            let [lo, hi] = placed.bounds();
            let range = [0, 1, 2].map(|d| {
                let to_cell = |x: f64| x / cells.h[d] - 0.5 - cells.offset[d] as f64;
                let first = (to_cell(lo[d]).ceil() as isize).max(known[d][0]);
                let last = (to_cell(hi[d]).floor() as isize + 1).min(known[d][1]);
                [first, last.max(first)]
            });
            lay.for_box(range, |c, at| {
                if kind[at] == Kind::Solid {
                    return;
                }
                let closest = placed.closest(cells.centre(c));
                if closest.phi < 0.0 {
                    kind[at] = Kind::Solid;
                    let own = (0..3).all(|d| (0..cells.n[d] as isize).contains(&c[d]));
                    if own {
                        solid.push((c.map(|x| x as usize), b, closest, centre));
                    }
                }
            });
        }
        let count = cells.n.iter().product();
        let mut inside = vec![false; count];
        let mut deep = vec![false; count];
        let mut ghosts = Vec::new();
        let least = IMAGE_CELLS * cells.coarsest();
        for (c, b, closest, centre) in solid {
            let i = cells.index(c);
            inside[i] = true;
            if !reads_gas(&kind, cells, c) {
                deep[i] = true;
                continue;
            }
            let normal = Vector3::from(closest.normal);
            let point = Vector3::from(closest.point);
            let d = closest.phi.abs().max(least);
            let image = cells.clamped(point + normal * d);
            let at = lay.at(c.map(|x| x as isize));
            ghosts.push(Ghost {
                at,
                image: gas_stencil(cells, &kind, image, at),
                normal,
                wall: bodies[b].kinematics.velocity_at(&centre, &point),
            });
        }
        Solids {
            inside,
            ghosts,
            deep,
            placed_at: Some(t),
        }
    }

    /// Whether cell `i` of this rank (x fastest) is inside a body.
    pub fn is_inside(&self, i: usize) -> bool {
        self.inside.get(i).copied().unwrap_or(false)
    }

    /// Whether cell `i` of this rank (x fastest) is frozen: solid, and
    /// read by no gas cell.
    pub fn frozen(&self, i: usize) -> bool {
        self.deep.get(i).copied().unwrap_or(false)
    }

    /// Fills the ghosts from their image points.
    pub fn fill(&self, u: &mut [State], gas: &Gas) {
        for g in &self.ghosts {
            u[g.at] = gas.conserved(image_state(g, u, gas));
        }
    }
}

/// Adds each body's load at time `t`, times `weight`, to its impulse.
pub fn add_loads(
    bodies: &mut [GasBody],
    cells: &Cells,
    u: &[State],
    gas: &Gas,
    t: f64,
    weight: f64,
) {
    for body in bodies {
        body.add_load(cells, u, gas, t, weight);
    }
}

/// Whether a gas cell of the box lies within the WENO5 reach of solid
/// cell `c` along an axis that varies.
fn reads_gas(kind: &[Kind], cells: &Cells, c: [usize; 3]) -> bool {
    let reach = GHOSTS as isize;
    (0..3).filter(|&d| cells.active(d)).any(|d| {
        (-reach..=reach).filter(|&k| k != 0).any(|k| {
            let mut o = c.map(|x| x as isize);
            o[d] += k;
            kind[cells.lay.at(o)] == Kind::Gas
        })
    })
}

/// `x`'s stencil over cells that are not solid (gas, or the ghosts of a
/// side of the box), renormalised; if every corner is solid (a body
/// thinner than the stencil), over all of them; if none holds a value (on
/// cells far longer across the slab's axis than along it, beyond the
/// halo), the ghost `at` itself, which then keeps its state.
fn gas_stencil(cells: &Cells, kind: &[Kind], x: [f64; 3], at: usize) -> Stencil {
    let all = cells.stencil(x);
    if all.iter().all(Option::is_none) {
        let mut own = [None; 8];
        own[0] = Some((at, 1.0));
        return own;
    }
    let mut gas = all;
    for slot in gas.iter_mut() {
        if slot.is_some_and(|(at, _)| kind[at] == Kind::Solid) {
            *slot = None;
        }
    }
    // Gas corners whose weights sum to almost nothing would amplify
    // round-off: below 10⁻⁶ the solid corners count too.
    let total: f64 = gas.iter().flatten().map(|s| s.1).sum();
    let (mut out, total) = match total > 1e-6 {
        true => (gas, total),
        false => (all, all.iter().flatten().map(|s| s.1).sum()),
    };
    for (_, w) in out.iter_mut().flatten() {
        *w /= total;
    }
    out
}

/// The ghost's primitive state from its image point's.
fn image_state(g: &Ghost, u: &[State], gas: &Gas) -> Primitive {
    let mut image = [0.0; 5];
    for (at, w) in g.image.into_iter().flatten() {
        let p = gas.primitive(&u[at]);
        let values = [
            p.density,
            p.velocity[0],
            p.velocity[1],
            p.velocity[2],
            p.pressure,
        ];
        for (s, v) in image.iter_mut().zip(values) {
            *s += w * v;
        }
    }
    let v = Vector3::new(image[1], image[2], image[3]);
    let relative = v - g.wall;
    let normal = relative.dot(&g.normal);
    // Tangential velocity kept, normal velocity relative to the wall reversed.
    let ghost = g.wall + relative - g.normal * (2.0 * normal);
    Primitive {
        density: image[0],
        velocity: ghost.into(),
        pressure: image[4],
    }
}
