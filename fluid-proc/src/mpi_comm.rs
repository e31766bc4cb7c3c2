//! [`Comm`] on MPI (rsmpi), for fluid-proc started under `mpirun`
//! (feature `mpi`).

use crate::comm::Comm;
use mpi::collective::SystemOperation;
use mpi::point_to_point as p2p;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;

/// The ranks of `MPI_COMM_WORLD`.
pub struct MpiComm {
    world: SimpleCommunicator,
}

impl std::fmt::Debug for MpiComm {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "MpiComm(rank {} of {})", self.rank(), self.ranks())
    }
}

impl MpiComm {
    /// The world of an initialised MPI universe (kept alive by the caller).
    pub fn new(universe: &mpi::environment::Universe) -> MpiComm {
        MpiComm {
            world: universe.world(),
        }
    }

    /// Stops every rank: for an error met on one rank alone.
    pub fn abort(&self, code: i32) -> ! {
        self.world.abort(code)
    }
}

// SAFETY of Send and Sync: the communicator is used from the thread that
// owns it; rayon's workers never touch it (the solver calls its Comm only
// between parallel loops).
unsafe impl Send for MpiComm {}
unsafe impl Sync for MpiComm {}

impl Comm for MpiComm {
    fn rank(&self) -> usize {
        self.world.rank() as usize
    }

    fn ranks(&self) -> usize {
        self.world.size() as usize
    }

    fn shift(&self, to: Option<(usize, &[f64])>, from: Option<(usize, &mut [f64])>, tag: i32) {
        let at = |r: usize| self.world.process_at_rank(r as i32);
        match (to, from) {
            (Some((d, send)), Some((s, recv))) => {
                p2p::send_receive_into_with_tags(send, &at(d), tag, recv, &at(s), tag);
            }
            (Some((d, send)), None) => at(d).send_with_tag(send, tag),
            (None, Some((s, recv))) => {
                at(s).receive_into_with_tag(recv, tag);
            }
            (None, None) => {}
        }
    }

    fn min(&self, x: f64) -> f64 {
        let mut out = x;
        self.world
            .all_reduce_into(&x, &mut out, SystemOperation::min());
        out
    }

    fn sum(&self, x: &mut [f64]) {
        let local = x.to_vec();
        self.world
            .all_reduce_into(&local[..], x, SystemOperation::sum());
    }

    fn gather(&self, local: &[f64]) -> Option<Vec<Vec<f64>>> {
        // Counts first, then each rank's values, point to point to rank 0.
        let root = self.world.process_at_rank(0);
        if self.rank() != 0 {
            root.send_with_tag(&(local.len() as u64), 2);
            root.send_with_tag(local, 3);
            return None;
        }
        let mut parts = vec![local.to_vec()];
        for r in 1..self.ranks() {
            let from = self.world.process_at_rank(r as i32);
            let mut count = 0u64;
            from.receive_into_with_tag(&mut count, 2);
            let mut part = vec![0.0; count as usize];
            from.receive_into_with_tag(&mut part[..], 3);
            parts.push(part);
        }
        Some(parts)
    }

    fn broadcast(&self, x: &mut [f64]) {
        self.world.process_at_rank(0).broadcast_into(x);
    }

    fn broadcast_text(&self, text: &mut String) {
        let root = self.world.process_at_rank(0);
        let mut len = text.len() as u64;
        root.broadcast_into(&mut len);
        let mut bytes = std::mem::take(text).into_bytes();
        bytes.resize(len as usize, 0);
        root.broadcast_into(&mut bytes[..]);
        *text = String::from_utf8_lossy(&bytes).into_owned();
    }
}
