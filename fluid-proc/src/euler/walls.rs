//! Rigid bodies in the gas (part of `mod.rs`; the method is
//! `bodies.rs`): this rank's cells as the bodies see them, the bodies
//! placed at each Runge–Kutta stage's time and at a step's end, their
//! ghosts filled and their loads taken, their motion kept in checkpoints.

use super::Compressible;
use crate::euler::bodies::{add_loads, Cells, Kinematics, Solids};
use crate::layout::GHOSTS;

impl Compressible {
    /// This rank's cells as the bodies see them.
    pub fn grid(&self) -> Cells {
        let thin = (0..3)
            .find(|&d| self.setup.n[d] == 1)
            .map(|d| (d, 0.5 * self.setup.h[d]));
        // The planes other ranks fill along each axis (none at a side of
        // the box), told gas from solid as their owners tell them; ghost
        // planes hold values that far, and GHOSTS deep beyond a side.
        let halo = |d: usize| {
            let g = self.lay.g[d] as isize;
            self.shared_sides(d).map(|s| s.map_or(0, |_| g))
        };
        let classified = [0, 1, 2].map(|d| [-halo(d)[0], self.n[d] as isize + halo(d)[1]]);
        let reach = [0, 1, 2].map(|d| {
            let side = self.lay.g[d].min(GHOSTS) as isize;
            let [low, high] = classified[d];
            [low.min(-side), high.max(self.n[d] as isize + side)]
        });
        Cells {
            reach,
            classified,
            lay: self.lay,
            n: self.n,
            whole: self.setup.n,
            offset: self.slab.global([0; 3]),
            h: self.setup.h,
            thin,
        }
    }

    /// Places the bodies at the present time and fills the cells inside
    /// them: call it after changing [`Compressible::bodies`].
    pub fn place_bodies(&mut self) {
        self.place_at(self.time);
        self.fill_ghosts();
        self.fill_bodies();
    }

    /// Tells this rank's solid cells at time `t` [s].
    fn place_at(&mut self, t: f64) {
        self.solids = Solids::find(&self.bodies, &self.grid(), t);
    }

    /// After a step: the bodies where they are at its end, so that the
    /// sums, the output's mask and the next Δt see the gas cells of now.
    pub(super) fn settle_bodies(&mut self) {
        if self.bodies.iter().any(|b| !b.kinematics.at_rest()) {
            self.place_at(self.time);
        }
    }

    /// Sets each body's motion from now on (in the order of
    /// [`Compressible::bodies`]), the bodies placed where it starts.
    pub fn move_bodies(&mut self, kinematics: &[Kinematics]) {
        for (b, k) in self.bodies.iter_mut().zip(kinematics) {
            b.kinematics = *k;
        }
        self.place_at(self.time);
    }

    /// Each body's motion, 17 values (see [`Kinematics::to_values`]), for a
    /// checkpoint.
    pub(super) fn body_motions(&self) -> Vec<[f64; 17]> {
        self.bodies
            .iter()
            .map(|b| b.kinematics.to_values())
            .collect()
    }

    /// The bodies moving as `motions` (from [`Compressible::body_motions`])
    /// say, placed at the present time.
    pub(super) fn restore_bodies(&mut self, motions: &[[f64; 17]]) {
        for (b, m) in self.bodies.iter_mut().zip(motions) {
            b.kinematics = Kinematics::from_values(m);
        }
        self.place_at(self.time);
    }

    /// Whether each cell of this rank (x fastest) lies inside a body.
    pub fn inside(&self) -> Vec<bool> {
        let count = self.n.iter().product();
        match self.solids.inside.len() == count {
            true => self.solids.inside.clone(),
            false => vec![false; count],
        }
    }

    /// The bodies at stage time `t`: placed there (unless they are
    /// already, or all stand still where they were placed), their ghosts
    /// filled, the box's ghosts filled again from them, and their loads
    /// taken `weight` [s] of.
    pub(super) fn stage_bodies(&mut self, t: f64, weight: f64) {
        let still = self.bodies.iter().all(|b| b.kinematics.at_rest());
        let placed = self.solids.placed_at;
        if !(placed == Some(t) || (still && placed.is_some())) {
            self.place_at(t);
        }
        let cells = self.grid();
        self.fill_bodies();
        let gas = self.setup.gas;
        add_loads(&mut self.bodies, &cells, &self.u, &gas, t, weight);
    }

    /// The solid cells from the gas around them, then the box's ghosts
    /// again (a side or another rank may mirror or read a solid cell):
    /// on every rank together, ghosts of its own or not, since the halo
    /// exchange is collective.
    pub(super) fn fill_bodies(&mut self) {
        self.solids.fill(&mut self.u, &self.setup.gas);
        self.fill_ghosts();
    }
}
