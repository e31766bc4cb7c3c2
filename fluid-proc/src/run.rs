//! The one run loop of every flow model (`model.rs`), on one rank or
//! several (`ranks.rs` says how they work together): rank 0 [`lead`]s,
//! turning each command of the schedule into an [`Order`] that every rank
//! obeys together, and the other ranks [`follow`] its orders. Rank 0 alone
//! reads and answers the other participants (the model's [`Lead`]) and
//! writes the cells it gathers as `fluid.pvd`.

use crate::comm::Comm;
use crate::driver::Error;
use crate::model::{Cells, Lead, Model, Window};
use crate::rank_checkpoint::{self, Place};
use crate::ranks::{Order, Stopped};
use fluid_section::Scene;
use participant::vtu::Series;
use participant::{Command, Joining, Participant};
use std::sync::Arc;

/// A model on this rank, its checkpoint, the ranks' communicator and
/// where its run checkpoints go (rank 0 tells the others).
struct Ranked<M: Model> {
    model: M,
    /// The window's start (implicit coupling), or the state a run
    /// checkpoint wrote or read: saving into it again reuses its buffers.
    saved: M::Saved,
    comm: Arc<dyn Comm>,
    place: Place,
}

/// What obeying an order gave; only rank 0's is used.
enum Done<M: Model> {
    Started(M::Started),
    Cells(Option<Cells>),
    /// What the advance gave, and the steps it took.
    Advanced(M::Advanced, u64),
    Checkpoint,
    Stop,
}

impl<M: Model> Ranked<M> {
    /// Obeys `order` on this rank (every rank calls it with the same
    /// order); a failure fails on every rank together, with its message.
    fn obey(&mut self, order: Order) -> Result<Done<M>, String> {
        let m = &mut self.model;
        Ok(match order {
            Order::Monitors => Done::Started(m.start()),
            Order::Output { .. } => Done::Cells(m.cells()),
            Order::Advance {
                dt,
                substeps,
                window_end,
            } => {
                let window = Window {
                    dt,
                    substeps,
                    window_end,
                };
                let (advanced, steps) = m.advance(window)?;
                Done::Advanced(advanced, steps)
            }
            Order::Checkpoint { restore: false } => {
                m.new_window();
                m.save(&mut self.saved);
                Done::Checkpoint
            }
            Order::Checkpoint { restore: true } => {
                m.restore(&self.saved)?;
                Done::Checkpoint
            }
            Order::RunCheckpoint { window, resume } => {
                if M::FIELD {
                    self.run_checkpoint(window, resume)?;
                }
                Done::Checkpoint
            }
            Order::Stop => Done::Stop,
        })
    }

    /// Writes this rank's part of the run checkpoint of `window`, or reads
    /// it back (`resume`).
    fn run_checkpoint(&mut self, window: u64, resume: bool) -> Result<(), String> {
        let (comm, place) = (self.comm.as_ref(), &self.place);
        match resume {
            false => {
                self.model.save(&mut self.saved);
                rank_checkpoint::write_part(comm, place, window, &self.saved)
            }
            true => {
                let m = &mut self.model;
                rank_checkpoint::read_part(comm, place, window, |c: M::Saved| m.restore(&c))
            }
        }
    }
}

/// Rank 0 (or the only rank): declares what the model exchanges, runs the
/// schedule and finishes.
pub fn lead<L: Lead>(joining: Joining, scene: &Scene, comm: Arc<dyn Comm>) -> Result<(), Stopped> {
    let c = comm.as_ref();
    let stop = |e| Stopped::before_order(c, e);
    let mut model = L::Model::on(scene, comm.clone()).map_err(stop)?;
    let mut lead = L::new(scene, &mut model).map_err(stop)?;
    let declared = lead.declaration(&model).restarts();
    let mut p = joining
        .declare(declared)
        .map_err(|e| Stopped::before_order(c, e))?;
    let mut ranked = Ranked {
        model,
        saved: Default::default(),
        place: Place::of(&p),
        comm: comm.clone(),
    };
    let steps = p.reporting(|p| schedule(p, &mut ranked, &mut lead))?;
    p.finish(steps)?;
    Ok(())
}

/// The schedule's commands, turned into orders every rank obeys; the
/// steps taken.
fn schedule<L: Lead>(
    p: &mut Participant,
    r: &mut Ranked<L::Model>,
    lead: &mut L,
) -> Result<u64, Stopped> {
    let comm = r.comm.clone();
    let c = comm.as_ref();
    let mut series = Series::new(p.run_dir(), "fluid");
    let mut steps = 0u64;
    loop {
        let command = p.next_command().map_err(|e| Stopped::before_order(c, e))?;
        if command == Command::SaveCheckpoint {
            lead.new_window();
        }
        if let Command::Advance(a) = command {
            if let Err(e) = lead.place(p, &mut r.model, &a) {
                return Err(Stopped::before_order(c, fail(p, e.to_string())));
            }
        }
        let done = r
            .obey(Order::of(&command).share(c))
            .map_err(|msg| Stopped {
                error: fail(p, msg),
                together: true,
            })?;
        match (command, done) {
            (_, Done::Stop) => break,
            (Command::WriteCheckpoint { window }, Done::Checkpoint) => {
                if L::Model::FIELD {
                    rank_checkpoint::write_lead(p, window, &series, steps)?;
                }
                p.done(Vec::new())?
            }
            (Command::Resume { window }, Done::Checkpoint) => {
                if L::Model::FIELD {
                    steps = rank_checkpoint::read_lead(p, window, &mut series)?;
                }
                p.done(Vec::new())?
            }
            (_, Done::Checkpoint) => p.done(Vec::new())?,
            (_, Done::Started(started)) => {
                let m = lead.start(p, &mut r.model, started)?;
                p.done(m)?
            }
            (Command::Output { index, time }, Done::Cells(cells)) => {
                if L::Model::FIELD {
                    let cells = cells.ok_or("rank 0 gathers the cells")?;
                    series.write_image(index, time, &cells.image())?;
                }
                p.done(Vec::new())?
            }
            (Command::Advance(a), Done::Advanced(advanced, n)) => {
                steps += n;
                let m = lead.answer(p, &mut r.model, advanced, &a)?;
                p.done(m)?
            }
            _ => unreachable!("each order comes from its command"),
        }
    }
    Ok(steps)
}

/// Tells the coupler the run failed with `msg` and gives it back as the
/// error to stop on (the coupler's own error if even telling it failed).
pub fn fail(p: &mut Participant, msg: String) -> Error {
    match p.fail(msg.clone()) {
        Ok(()) => msg.into(),
        Err(e) => e.into(),
    }
}

/// A rank other than 0: obeys rank 0's orders until it stops, or until a
/// step fails (rank 0 meets the same failure and reports it).
#[cfg_attr(not(feature = "mpi"), allow(dead_code))]
pub fn follow<M: Model>(scene: &Scene, comm: Arc<dyn Comm>) -> Result<(), Error> {
    let mut r = Ranked {
        model: M::on(scene, comm.clone())?,
        saved: Default::default(),
        comm,
        place: Place::default(),
    };
    loop {
        let order = Order::Stop.share(r.comm.as_ref());
        match r.obey(order) {
            Ok(Done::Stop) | Err(_) => return Ok(()),
            Ok(_) => {}
        }
    }
}
