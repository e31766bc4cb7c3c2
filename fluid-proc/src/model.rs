//! A flow model as the run loop (`run.rs`) drives it: what every rank does
//! together for each order (`Model`), and what rank 0 alone reads from
//! and answers to the other participants around it (`Lead`).
//!
//! The split follows the ranks (`ranks.rs`): rank 0 alone speaks to the
//! coupler, so everything that touches a field is in [`Lead`], called on
//! rank 0 only; everything that sums, swaps or steps over the box is in
//! [`Model`], called on every rank with the same order. A model on one
//! rank is the same code with a `Single` communicator. The porous
//! free-stream model (`porous.rs`), the incompressible flow
//! (`incompressible/run.rs`) and the Euler gas (`euler/run.rs`) implement
//! both.

use crate::comm::Comm;
use crate::driver::Error;
use fluid_section::Scene;
use participant::vtu::Image;
use participant::{Advance, Declaration, Monitor, Participant};
use std::sync::Arc;

/// One window's advance, as every rank is told it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Window {
    /// The window's length [s].
    pub dt: f64,
    /// Equal steps to take it in, where the model takes the coupler's (the
    /// Euler gas picks its own from its fastest wave).
    pub substeps: u32,
    /// Whether this advance ends the window: monitors are due.
    pub window_end: bool,
}

/// A flow model's state on one rank and what it does for each order. Every
/// rank calls each method together, with the same arguments; a failure
/// (an `Err` with its message) fails on every rank together.
pub trait Model: Sized {
    /// What an advance hands rank 0's [`Lead::answer`] (the loads, the
    /// pressure it reads the canopy's jumps from, its monitors).
    type Advanced;
    /// What the start hands rank 0's [`Lead::start`] (its first monitors).
    type Started;
    /// What a checkpoint of this rank's part holds: the state at a
    /// window's start, which implicit coupling takes again, and what a run
    /// checkpoint writes (`rank_checkpoint.rs`).
    type Saved: serde::Serialize + serde::de::DeserializeOwned + Default;
    /// Whether the model has a field: cells it writes as `fluid.pvd` and a
    /// state it keeps in run checkpoints. The porous free-stream model has
    /// neither: its jumps depend on the window's inputs alone.
    const FIELD: bool;

    /// This rank's part of the scene's flow at its start.
    fn on(scene: &Scene, comm: Arc<dyn Comm>) -> Result<Self, String>;

    /// Before the first window: the model's first monitors.
    fn start(&mut self) -> Self::Started;

    /// One advance of the window; with it, the steps it took.
    fn advance(&mut self, window: Window) -> Result<(Self::Advanced, u64), String>;

    /// A window begins that implicit coupling may take again; its start is
    /// saved next.
    fn new_window(&mut self) {}

    /// Save this rank's state into `into`.
    fn save(&self, into: &mut Self::Saved);

    /// Return to the state `from` holds; why not, when it holds another
    /// part of the flow than this rank's.
    fn restore(&mut self, from: &Self::Saved) -> Result<(), String>;

    /// The box's cells, gathered on rank 0 (None elsewhere, and where the
    /// model has no cells).
    fn cells(&mut self) -> Option<Cells>;
}

/// What rank 0 reads from the other participants before a model's advance
/// and answers them after it: the canopy's and the bodies' places in, the
/// pressure jumps and loads out, with the monitors that go with them.
pub trait Lead: Sized {
    type Model: Model;

    /// What rank 0 keeps beside rank 0's `model` at the start.
    fn new(scene: &Scene, model: &mut Self::Model) -> Result<Self, String>;

    /// What the model exchanges and monitors (the run loop adds that it
    /// restarts).
    fn declaration(&self, model: &Self::Model) -> Declaration;

    /// A window begins that may be taken again (implicit coupling).
    fn new_window(&mut self) {}

    /// Before the first window: the first monitors, with the answers a
    /// parallel scheme's readers take their first try from.
    fn start(
        &mut self,
        p: &mut Participant,
        model: &mut Self::Model,
        started: <Self::Model as Model>::Started,
    ) -> Result<Vec<Monitor>, Error>;

    /// Before an advance: what the model reads from the others.
    fn place(
        &mut self,
        p: &mut Participant,
        model: &mut Self::Model,
        a: &Advance,
    ) -> Result<(), Error>;

    /// After an advance: its answers to the others, and its monitors at a
    /// window's end.
    fn answer(
        &mut self,
        p: &mut Participant,
        model: &mut Self::Model,
        advanced: <Self::Model as Model>::Advanced,
        a: &Advance,
    ) -> Result<Vec<Monitor>, Error>;
}

/// A box's cell fields, gathered on rank 0 for the output: `cells` along
/// x, y, z from `origin` [m], `spacing` [m] apart (a graded box: its faces
/// along each axis, world coordinates [m]), each field with its name and
/// its values per cell (x fastest).
pub struct Cells {
    pub origin: [f64; 3],
    pub spacing: [f64; 3],
    pub cells: [usize; 3],
    pub faces: Option<[Vec<f64>; 3]>,
    pub fields: Vec<(&'static str, usize, Vec<f64>)>,
}

impl Cells {
    /// The cells as the `.vti` writer takes them.
    pub fn image(&self) -> Image<'_> {
        Image {
            origin: self.origin,
            spacing: self.spacing,
            cells: self.cells,
            faces: self.faces.as_ref(),
            cell_data: self
                .fields
                .iter()
                .map(|(name, n, values)| (*name, *n, &values[..]))
                .collect(),
        }
    }
}
