//! The incompressible flow split among ranks (`part.rs`) gives the same
//! fields as on one rank, here with ranks as threads of one process (the
//! `Threads` communicator below), so that the decomposition is tested by
//! `cargo test` with no MPI installed; `tests/tests/mpi.rs` runs the same
//! on MPI through the coupler.
//!
//! The flow is the 3-D Taylor–Green vortex (Taylor & Green, Proc. R. Soc.
//! A 158, 499–521, 1937: u = sin x cos y cos z, v = −cos x sin y cos z,
//! w = 0 at t = 0) in a periodic box, so the slab axis z wraps round: on
//! two ranks each rank's neighbours below and above are the same rank.
//! Every cell is computed from the same values as on one rank; only the
//! dot products of the solves, sums over the ranks, change by round-off.

use fluid_proc::comm::Comm;
use fluid_proc::grid::Grid;
use fluid_proc::incompressible::{FlowSetup, Incompressible};
use fluid_proc::part::Part;
use fluid_proc::side::{bcs, Side};
use std::collections::{HashMap, VecDeque};
use std::f64::consts::PI;
use std::sync::{Arc, Condvar, Mutex};

/// Messages in flight between thread ranks: (from, to, tag) → queue.
#[derive(Debug, Default)]
struct Mailbox {
    queues: Mutex<HashMap<(usize, usize, i32), VecDeque<Vec<f64>>>>,
    arrived: Condvar,
}

/// One rank of a group of threads; sends never block.
#[derive(Debug)]
struct Threads {
    rank: usize,
    ranks: usize,
    mail: Arc<Mailbox>,
}

/// Tags of the collectives (point-to-point tags are small and positive).
const REDUCE: i32 = -1;
const RESULT: i32 = -2;
const GATHER: i32 = -3;

impl Threads {
    fn send(&self, to: usize, tag: i32, data: &[f64]) {
        let mut q = self.mail.queues.lock().unwrap();
        q.entry((self.rank, to, tag))
            .or_default()
            .push_back(data.to_vec());
        self.mail.arrived.notify_all();
    }

    fn receive(&self, from: usize, tag: i32) -> Vec<f64> {
        let mut q = self.mail.queues.lock().unwrap();
        loop {
            if let Some(m) = q
                .get_mut(&(from, self.rank, tag))
                .and_then(|q| q.pop_front())
            {
                return m;
            }
            q = self.mail.arrived.wait(q).unwrap();
        }
    }

    /// Rank 0 combines every rank's `x` in rank order; all get the result.
    fn reduce(&self, x: &mut [f64], combine: fn(f64, f64) -> f64) {
        if self.rank == 0 {
            for r in 1..self.ranks {
                for (a, b) in x.iter_mut().zip(self.receive(r, REDUCE)) {
                    *a = combine(*a, b);
                }
            }
            (1..self.ranks).for_each(|r| self.send(r, RESULT, x));
        } else {
            self.send(0, REDUCE, x);
            x.copy_from_slice(&self.receive(0, RESULT));
        }
    }
}

impl Comm for Threads {
    fn rank(&self) -> usize {
        self.rank
    }
    fn ranks(&self) -> usize {
        self.ranks
    }
    fn shift(&self, to: Option<(usize, &[f64])>, from: Option<(usize, &mut [f64])>, tag: i32) {
        if let Some((d, x)) = to {
            self.send(d, tag, x);
        }
        if let Some((s, x)) = from {
            x.copy_from_slice(&self.receive(s, tag));
        }
    }
    fn min(&self, x: f64) -> f64 {
        let mut v = [x];
        self.reduce(&mut v, f64::min);
        v[0]
    }
    fn sum(&self, x: &mut [f64]) {
        self.reduce(x, |a, b| a + b);
    }
    fn gather(&self, local: &[f64]) -> Option<Vec<Vec<f64>>> {
        if self.rank != 0 {
            self.send(0, GATHER, local);
            return None;
        }
        let mut parts = vec![local.to_vec()];
        parts.extend((1..self.ranks).map(|r| self.receive(r, GATHER)));
        Some(parts)
    }
    fn broadcast(&self, x: &mut [f64]) {
        if self.rank == 0 {
            (1..self.ranks).for_each(|r| self.send(r, RESULT, x));
        } else {
            x.copy_from_slice(&self.receive(0, RESULT));
        }
    }
    fn broadcast_text(&self, _: &mut String) {
        unreachable!("the flow broadcasts no text")
    }
}

/// The flow on `n` cells of [0, 2π]³ after `steps` steps, on `ranks`
/// thread ranks: the whole box's cell velocities and pressures (from rank
/// 0's gather) and the kinetic energy. Periodic but for the z sides, `z`.
fn taylor_green(n: [usize; 3], z: Side, ranks: usize, steps: usize) -> (Vec<f64>, Vec<f64>, f64) {
    let mail = Arc::new(Mailbox::default());
    let threads: Vec<_> = (0..ranks)
        .map(|rank| {
            let mail = mail.clone();
            std::thread::spawn(move || {
                let comm = Arc::new(Threads { rank, ranks, mail });
                run(n, z, comm, steps)
            })
        })
        .collect();
    let mut results: Vec<_> = threads.into_iter().map(|t| t.join().unwrap()).collect();
    results.swap_remove(0).expect("rank 0 gathers the fields")
}

fn run(
    n: [usize; 3],
    z: Side,
    comm: Arc<Threads>,
    steps: usize,
) -> Option<(Vec<f64>, Vec<f64>, f64)> {
    let h = n.map(|n| 2.0 * PI / n as f64);
    let sides = [[Side::Periodic; 2], [Side::Periodic; 2], [z; 2]];
    let setup = FlowSetup {
        grid: Grid {
            n,
            h,
            bc: bcs(&sides),
        },
        sides,
        density: 1.0,
        nu: 0.05,
    };
    let part = Part::on(comm, n, sides);
    let slab = part.slab;
    let mut flow = Incompressible::on(setup, part);
    for d in 0..2 {
        let mut m = slab.cells();
        m[d] += 1;
        for (f, u) in flow.u.u[d].iter_mut().enumerate() {
            let local = [f % m[0], (f / m[0]) % m[1], f / (m[0] * m[1])];
            let at = slab.global(local);
            // Faces normal to d at i·h along d, at cell centres elsewhere.
            let x = [0, 1, 2].map(|a| (at[a] as f64 + if a == d { 0.0 } else { 0.5 }) * h[a]);
            let (s, c) = ([x[0].sin(), x[1].sin()], [x[0].cos(), x[1].cos()]);
            *u = if d == 0 { s[0] * c[1] } else { -c[0] * s[1] } * x[2].cos();
        }
    }
    flow.impose_sides();
    for _ in 0..steps {
        flow.step(0.4 * h[0]).unwrap();
    }
    let energy = flow.kinetic_energy();
    let velocity = flow.part.gather(&flow.cell_velocity());
    let pressure = flow.part.gather(&flow.pressure());
    Some((velocity?, pressure?, energy))
}

/// Round-off of the fields from the order of the dot products' terms:
/// 2·10⁻¹⁶ of the largest value measured. Colouring the slabs by their own
/// cells instead of the box's (a bug, tried) puts them 3·10⁻¹² off, as the
/// solves stop at a relative residual of 10⁻⁸ along another path.
const ROUND_OFF: f64 = 1e-13;

fn assert_same(one: &(Vec<f64>, Vec<f64>, f64), many: &(Vec<f64>, Vec<f64>, f64), ranks: usize) {
    for (name, a, b) in [("velocity", &one.0, &many.0), ("pressure", &one.1, &many.1)] {
        assert_eq!(a.len(), b.len());
        let scale = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(scale > 0.1, "{name} is not trivial: {scale}");
        let worst = a
            .iter()
            .zip(b)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(
            worst <= ROUND_OFF * scale,
            "{name} on {ranks} ranks is {worst:e} off one rank's (largest {scale})"
        );
    }
    assert!(
        (one.2 - many.2).abs() <= ROUND_OFF * one.2,
        "energy {} against {}",
        many.2,
        one.2
    );
}

#[test]
fn a_periodic_3d_vortex_gives_the_same_flow_on_1_2_and_3_ranks() {
    // 12 cells along z: slabs of 6 on two ranks (whose coarse levels stop
    // halving at 3, where rank 0 gathers the multigrid's rest) and of 4 on
    // three.
    let n = [16, 16, 12];
    let one = taylor_green(n, Side::Periodic, 1, 8);
    for ranks in [2, 3] {
        assert_same(&one, &taylor_green(n, Side::Periodic, ranks, 8), ranks);
    }
}

#[test]
fn slabs_starting_at_odd_cells_keep_the_red_black_colours() {
    // 9 cells along z between walls on three ranks: z never halves, so
    // every level but the gathered last is smoothed in slabs starting at
    // cells 3 and 6, whose colours must follow the whole box's.
    let n = [16, 16, 9];
    let one = taylor_green(n, Side::WALL, 1, 6);
    assert_same(&one, &taylor_green(n, Side::WALL, 3, 6), 3);
}

#[test]
fn slabs_that_cannot_halve_gather_the_finest_level() {
    // 10 cells along z on two ranks: the slabs (5 cells each) cannot halve,
    // so rank 0 gathers the finest level and runs the whole cycle.
    let n = [8, 8, 10];
    let one = taylor_green(n, Side::Periodic, 1, 6);
    assert_same(&one, &taylor_green(n, Side::Periodic, 2, 6), 2);
}
