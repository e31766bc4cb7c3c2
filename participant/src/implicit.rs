//! A participant's side of implicit coupling: the accelerated fields it
//! writes are held in their loaned shared memory until its try at the
//! window is done, then measured against what it sent before, relaxed in
//! place unless they converged (`acceleration.rs`; under the parallel
//! scheme together with the other writers', `joint.rs`) and sent; its word
//! on the try goes to the others (`verdict.rs`).

use crate::acceleration::{Accelerator, Norms};
use crate::channel::FieldLoan;
use crate::declaration::Declaration;
use crate::error::ExchangeError;
use crate::fields::Outputs;
use crate::joint::Share;
use crate::monitors::Monitor;
use crate::presence::Presence;
use crate::scheme::{Implicit, Measured, COLUMNS, RESIDUAL, TRIES};

/// The field on which participant `name` sends its share of a parallel
/// scheme's joint relaxation to the other writers (`joint.rs`).
pub fn share_field(name: &str) -> String {
    format!("implicit.share.{name}")
}

/// `declaration` of participant `me` of the run's `names`, with what
/// implicit coupling adds: its monitors, and under the parallel scheme,
/// when it writes an accelerated field, its share of the joint relaxation
/// written and the other writers' read.
pub fn with_implicit(
    declaration: Declaration,
    settings: &Implicit,
    me: &str,
    names: &[String],
) -> Declaration {
    let written: Vec<String> = settings
        .fields
        .iter()
        .filter(|m| declaration.writes.iter().any(|w| w.name == m.field))
        .map(|m| format!("{RESIDUAL}{}", m.field))
        .collect();
    let mut monitors = Vec::new();
    if names.first().is_some_and(|n| n == me) {
        monitors.push(TRIES.to_string());
    }
    let writer = !written.is_empty();
    if writer {
        monitors.extend(written);
        monitors.push(COLUMNS.to_string());
    }
    let mut declaration = declaration.monitors(monitors).units(|m| match m {
        TRIES => "tries",
        COLUMNS => "columns",
        // ‖r‖₂/‖x‖₂ of a field: a ratio.
        m if m.starts_with(RESIDUAL) => "1",
        _ => "",
    });
    if settings.parallel && writer {
        declaration = declaration.writes_items_of(&share_field(me), 1);
        for other in names.iter().filter(|n| *n != me) {
            declaration = declaration.reads_if_written(&share_field(other));
        }
    }
    declaration
}

pub struct Tries {
    pub settings: Implicit,
    /// This participant's accelerated outputs, by index, with their limits.
    accelerated: Vec<(usize, Measured)>,
    accelerator: Accelerator,
    /// Filled and not yet sent, by output index.
    held: Vec<(usize, FieldLoan)>,
    /// The last try's norms per accelerated field.
    pub last: Vec<(String, Norms)>,
    /// Whether the last try's fields all converged.
    pub converged: bool,
}

impl Tries {
    pub fn new(settings: Implicit, outputs: &Outputs) -> Tries {
        let accelerated = settings
            .fields
            .iter()
            .filter_map(|m| outputs.find(&m.field).map(|i| (i, m.clone())))
            .collect();
        Tries {
            accelerator: Accelerator::new(settings.acceleration, settings.complement),
            settings,
            accelerated,
            held: Vec::new(),
            last: Vec::new(),
            converged: true,
        }
    }

    /// The worst of this participant's unconverged fields on the last try:
    /// its index among the measured, ‖r‖₂, ‖x‖₂.
    pub fn worst(&self) -> Option<(usize, f64, f64)> {
        let s = &self.settings;
        let at = |field: &String| s.fields.iter().position(|m| m.field == *field);
        let measured = self
            .last
            .iter()
            .filter_map(|(field, n)| {
                let i = at(field)?;
                let unconverged = !s.fields[i].converged(n.residual, n.value);
                unconverged.then_some((i, n.residual, n.value))
            })
            .max_by(|a, b| (a.1 / a.2).total_cmp(&(b.1 / b.2)));
        // Unconverged with every field within its limits: the try had
        // nothing to be measured against (`measure`), its norms zero.
        measured.or_else(|| match self.converged {
            true => None,
            false => self
                .last
                .iter()
                .find_map(|(field, n)| Some((at(field)?, n.residual, n.value))),
        })
    }

    /// The implicit monitors' values for a window that took `tries`.
    pub fn monitors(&self, tries: u32, first: bool) -> Vec<Monitor> {
        let mut m = Vec::new();
        if first {
            m.push(Monitor::new(TRIES, tries as f64));
        }
        for (field, n) in &self.last {
            let relative = match n.value > 0.0 {
                true => n.residual / n.value,
                false => n.residual,
            };
            m.push(Monitor::new(format!("{RESIDUAL}{field}"), relative));
        }
        if !self.accelerated.is_empty() {
            m.push(Monitor::new(COLUMNS, self.accelerator.columns_used as f64));
        }
        m
    }

    /// The worst unconverged field of each participant in `unconverged`, with
    /// its residual and writer.
    pub fn unconverged_detail(
        &self,
        unconverged: &[usize],
        me: usize,
        names: &[String],
        presence: &Presence,
    ) -> String {
        let fields = &self.settings.fields;
        let parts: Vec<String> = unconverged
            .iter()
            .map(|&p| {
                let worst = match p == me {
                    true => self.worst(),
                    false => presence.worst(p),
                };
                let field = |i: usize| fields.get(i).map_or("?", |f| f.field.as_str());
                match worst {
                    // Unconverged with nothing to measure: a try that had
                    // nothing sent before it (`measure`).
                    Some((i, r, x)) if r == 0.0 && x == 0.0 => format!(
                        "field `{}` of `{}`: not measured, nothing was sent before this try \
                         (a field first written at a window's end needs a second try: \
                         max_iterations of 2 or more)",
                        field(i),
                        names[p]
                    ),
                    Some((i, r, x)) => format!(
                        "field `{}` of `{}`: residual {r:.3e} against a value of {x:.3e}",
                        field(i),
                        names[p]
                    ),
                    None => format!("a field of `{}`", names[p]),
                }
            })
            .collect();
        parts.join("; ")
    }

    pub fn is_accelerated(&self, output: usize) -> bool {
        self.accelerated.iter().any(|(i, _)| *i == output)
    }

    pub fn hold(&mut self, output: usize, sample: FieldLoan) {
        self.held.push((output, sample));
    }

    /// The acceleration state, for a run checkpoint.
    pub fn accelerator(&self) -> &Accelerator {
        &self.accelerator
    }

    /// A restarted run: the acceleration state as a run checkpoint kept it.
    pub fn resume(&mut self, accelerator: Accelerator) {
        self.accelerator = accelerator.resumed_with(&self.accelerator);
    }

    /// Send the held values and leave the acceleration state as it is: a
    /// restarted run's fields, as they were sent before its checkpoint.
    /// Under the parallel scheme the accelerated fields that the solver
    /// did not write again at `Resume` (a fluid's answers, computed at
    /// window ends only) go out as the acceleration state kept them.
    pub fn send_held(
        &mut self,
        outputs: &mut Outputs,
        presence: &Presence,
    ) -> Result<(), ExchangeError> {
        let unwritten: Vec<usize> = match self.settings.parallel {
            true => self
                .accelerated
                .iter()
                .map(|(i, _)| *i)
                .filter(|i| !self.held.iter().any(|(h, _)| h == i))
                .collect(),
            false => Vec::new(),
        };
        for i in unwritten {
            let Some(part) = self.accelerator.sent_part(i) else {
                continue;
            };
            let part = part.to_vec();
            if let Some((sample, _)) = outputs.fill(i, part.len(), |o| o.copy_from_slice(&part))? {
                self.held.push((i, sample));
            }
        }
        self.held.sort_by_key(|(i, _)| *i);
        self.send(outputs, presence)
    }

    /// A window begins.
    pub fn start_window(&mut self) {
        self.accelerator.start_window();
    }

    /// Send the held values as they are (the initial values). Under the
    /// parallel scheme every accelerated field read in this run must be
    /// among them.
    pub fn send_as_is(
        &mut self,
        outputs: &mut Outputs,
        presence: &Presence,
    ) -> Result<(), ExchangeError> {
        let missing = self
            .accelerated
            .iter()
            .find(|(i, _)| outputs.has_readers(*i) && !self.held.iter().any(|(h, _)| h == i));
        if let (true, Some((_, m))) = (self.settings.parallel, missing) {
            return Err(ExchangeError::NotPublishedAtStart(m.field.clone()));
        }
        self.held.sort_by_key(|(i, _)| *i);
        self.keep_layout();
        let mut values: Vec<&mut [f64]> =
            self.held.iter_mut().map(|(_, s)| s.payload_mut()).collect();
        self.accelerator.sent_as_is(&mut values);
        self.send(outputs, presence)
    }

    /// The try is over: measure the held values against those sent before,
    /// relax them unless they all converged, send them. Returns whether
    /// they converged.
    pub fn close_try(
        &mut self,
        outputs: &mut Outputs,
        presence: &Presence,
    ) -> Result<bool, ExchangeError> {
        let comparable = self.measure();
        let mut values: Vec<&mut [f64]> =
            self.held.iter_mut().map(|(_, s)| s.payload_mut()).collect();
        match self.converged || !comparable {
            true => self.accelerator.sent_as_is(&mut values),
            false => {
                self.accelerator.relax(&mut values);
            }
        }
        self.send(outputs, presence)?;
        Ok(self.converged)
    }

    /// Parallel scheme, the try is over: measure the held values and
    /// return this writer's share of their joint relaxation; with nothing
    /// held (no field of it read in this run), a share that counts for
    /// nothing.
    pub fn share_try(&mut self) -> Share {
        let comparable = self.measure();
        let values: Vec<&mut [f64]> = self.held.iter_mut().map(|(_, s)| s.payload_mut()).collect();
        match values.is_empty() {
            true => Share::idle(),
            false => self.accelerator.share(&values, self.converged, comparable),
        }
    }

    /// Parallel scheme: relax the held values by `total`, the sum of every
    /// writer's share, unless every writer's fields converged; send them.
    pub fn close_joint(
        &mut self,
        total: &Share,
        outputs: &mut Outputs,
        presence: &Presence,
    ) -> Result<(), ExchangeError> {
        let mut values: Vec<&mut [f64]> =
            self.held.iter_mut().map(|(_, s)| s.payload_mut()).collect();
        match total.converged || !total.comparable {
            true => self.accelerator.sent_as_is(&mut values),
            false => self.accelerator.relax_joint(&mut values, total),
        }
        self.send(outputs, presence)
    }

    /// Measure the held values (in output order) against those sent
    /// before: `last` and `converged`. Returns whether they were
    /// comparable (a value of the same layout was sent before).
    fn measure(&mut self) -> bool {
        self.held.sort_by_key(|(i, _)| *i);
        self.keep_layout();
        let values: Vec<&mut [f64]> = self.held.iter_mut().map(|(_, s)| s.payload_mut()).collect();
        let total: usize = values.iter().map(|v| v.len()).sum();
        let comparable = self.accelerator.sent_len() == total;
        let norms = match comparable {
            true => self.accelerator.norms(&values),
            // Nothing comparable was sent before: nothing to measure yet.
            false => vec![Norms::default(); values.len()],
        };
        self.last.clear();
        let mut converged = true;
        for ((i, _), n) in self.held.iter().zip(&norms) {
            let m = &self
                .accelerated
                .iter()
                .find(|(a, _)| a == i)
                .expect("held")
                .1;
            converged &= m.converged(n.residual, n.value);
            self.last.push((m.field.clone(), *n));
        }
        // A try that nothing was sent before (an accelerated field its
        // solver first writes at a window's end, under the serial scheme)
        // has not been measured: it is no converged window, and the next
        // try measures against it.
        self.converged = converged && comparable;
        comparable
    }

    /// The held fields' outputs and lengths, in the order they are sent.
    fn keep_layout(&mut self) {
        let layout = self.held.iter().map(|(i, s)| (*i, s.payload().len()));
        self.accelerator.set_layout(layout.collect());
    }

    fn send(&mut self, outputs: &mut Outputs, presence: &Presence) -> Result<(), ExchangeError> {
        for (i, sample) in self.held.drain(..) {
            outputs.send(i, sample, presence)?;
        }
        Ok(())
    }
}
