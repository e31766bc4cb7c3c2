//! Step 1 of the projection method (`mod.rs`), one velocity
//! component at a time: each component's work arrays, its change
//! δ = u* − uⁿ over the step from the window's start (advection by WENO5
//! and Adams–Bashforth, the Crank–Nicolson viscous solve, the last
//! pressure's gradient), and the components run side by side.

use crate::incompressible::advection::advection;
use crate::incompressible::grid::Grid;
use crate::incompressible::metric::Metric;
use crate::incompressible::padded::Padded;
use crate::incompressible::part::Halo;
use crate::incompressible::projection::gradients;
use crate::incompressible::rows;
use crate::incompressible::side::Sides;
use crate::incompressible::viscosity::{laplacian, Helmholtz, ViscousError};
use crate::incompressible::VISCOUS_TOLERANCE;
use rayon::prelude::*;

/// One advected component's work arrays.
pub(crate) struct Work {
    /// N = ∇·(u u_c) at n and n − 1.
    pub(crate) n: [Vec<f64>; 2],
    b: Vec<f64>,
    lap: Vec<f64>,
    flux: Vec<f64>,
    /// ∇q on the component's faces (unpadded, as in `Faces`).
    grad_q: Vec<f64>,
    /// δ = u* − uⁿ, kept as the next step's first guess.
    pub(crate) delta: Padded,
    /// The component's lengths along each axis (`metric.rs`).
    metric: Metric,
    helmholtz: Helmholtz,
}

impl Work {
    /// Zeroed work arrays of component `delta.c` on this rank's cells
    /// `grid`, δ starting from `delta`.
    pub(crate) fn new(delta: Padded, grid: &Grid) -> Work {
        let (len, c) = (delta.data.len(), delta.c);
        Work {
            n: [vec![0.0; len], vec![0.0; len]],
            b: vec![0.0; len],
            lap: vec![0.0; len],
            flux: vec![0.0; len],
            grad_q: vec![0.0; grid.n.iter().product::<usize>() / grid.n[c] * (grid.n[c] + 1)],
            helmholtz: Helmholtz::new(&delta),
            metric: Metric::of(grid, c, &delta.lay),
            delta,
        }
    }
}

/// What step 1 of the projection method reads of the window's start, for
/// each component's change.
pub(crate) struct ChangeInputs<'a> {
    pub(crate) grid: &'a Grid,
    pub(crate) sides: &'a Sides,
    pub(crate) padded: &'a [Option<Padded>; 3],
    pub(crate) q: &'a [f64],
    pub(crate) halo: &'a Halo,
    pub(crate) nu: f64,
    /// Adams–Bashforth's weights of Nⁿ and Nⁿ⁻¹.
    pub(crate) ab: [f64; 2],
    pub(crate) dt: f64,
}

impl ChangeInputs<'_> {
    /// Component `c`'s change δ into `w.delta`, with Nⁿ; the Helmholtz
    /// iterations.
    pub(crate) fn component(&self, c: usize, w: &mut Work) -> Result<usize, ViscousError> {
        let (grid, nu, dt, ab) = (self.grid, self.nu, self.dt, self.ab);
        let u = self.padded[c]
            .as_ref()
            .expect("a padded array for each worked component");
        w.n.rotate_right(1);
        advection(self.padded, c, &w.metric, &mut w.flux, &mut w.n[0]);
        laplacian(u, &w.metric, &mut w.lap);
        // The change over the step solves (I − αL)δ = Δt(−N^{n+½} − ∇q + νLuⁿ),
        // which is eq. (3.18) less (I − αL)uⁿ.
        gradients(grid, self.q, self.halo, c, &mut w.grad_q, |g, grad| {
            *g = grad
        });
        let lay = u.lay;
        let m = lay.m;
        let ([n0, n1], lap, grad_q) = (&w.n, &w.lap, &w.grad_q);
        rows::each(&lay, lay.unknown_box(), [&mut w.b], |row, [b]| {
            let [i0, j, k] = row.first.map(|x| x as usize);
            let face0 = i0 + m[0] * (j + m[1] * k);
            for i in 0..row.len {
                let p = row.at + i;
                let adv = ab[0] * n0[p] + ab[1] * n1[p];
                b[row.offset + i] = dt * (-adv - grad_q[face0 + i] + nu * lap[p]);
            }
        });
        let alpha = 0.5 * nu * dt;
        w.helmholtz.solve(
            self.sides,
            &w.metric,
            alpha,
            &w.b,
            &mut w.delta,
            VISCOUS_TOLERANCE,
        )
    }
}

/// `f(c, item)` for each component's item: `side_by_side`
/// (`Incompressible::side_by_side`) on the pool's threads, so that one
/// component's serial parts (its solve's sums, its ghosts) overlap another's
/// loops, else one after the other. Each call writes only its own item and
/// keeps its sums on one thread in the grid's order (`rows.rs`), so the bits
/// are the same either way.
pub(crate) fn by_component<T: Send, R: Send>(
    side_by_side: bool,
    items: &mut [T],
    f: impl Fn(usize, &mut T) -> R + Sync,
) -> Vec<R> {
    let f = |(c, item): (usize, &mut T)| f(c, item);
    match side_by_side {
        true => items.par_iter_mut().enumerate().map(f).collect(),
        false => items.iter_mut().enumerate().map(f).collect(),
    }
}

/// The weights of Nⁿ and N^{n−1} in the advection term N^{n+½} of a step
/// of `dt` after one of `last`: second-order Adams–Bashforth for the length
/// ratio r = Δt/Δt_old, (1 + r/2, −r/2); explicit Euler on the first step.
///
/// With WENO5 its stability needs a Courant number Σ_a|u_a|Δt/h_a below
/// about 0.6 in a nearly inviscid flow (MAX_COURANT keeps a margin):
/// third-order Adams–Bashforth, tried, is worse, as the upwind scheme's
/// damped eigenvalues fall outside its smaller region along the negative
/// real axis.
pub(crate) fn adams_bashforth(dt: f64, last: Option<f64>) -> [f64; 2] {
    match last {
        Some(old) => {
            let r = dt / old;
            [1.0 + 0.5 * r, -0.5 * r]
        }
        None => [1.0, 0.0],
    }
}
