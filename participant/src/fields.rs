//! A participant's field ports: the fields it writes, each with the peers
//! that read it, and the fields it reads, each with its writer.
//!
//! Every value written is read once, in order, by each reader: the
//! writer numbers its values and a reader checks the numbers, so a value
//! lost or read twice is an error rather than a silent wrong answer.

use crate::channel::{self, ChannelError, FieldIn, FieldLoan, FieldOut, FieldSample, Ipc};
use crate::declaration::{Read, Write};
use crate::error::ExchangeError;
use crate::names;
use crate::presence::Presence;
use crate::wire::Source;
use iceoryx2::node::Node;
use std::time::Duration;

/// Where the time of a write went.
#[derive(Default)]
pub struct Written {
    /// In the solver's `fill`: its own work.
    pub computed: Duration,
    /// From the value's time stamp on (sending it, waking readers): a
    /// reader that waits for it counts this as its value's latency.
    pub in_flight: Duration,
}

pub struct Output {
    pub name: String,
    per_item: u32,
    items: Option<u64>,
    /// None when no participant reads it: writing it is then skipped.
    publisher: Option<FieldOut>,
    /// Number of the next value written.
    seq: u64,
    /// The readers, by participant index.
    readers: Vec<usize>,
}

pub struct Outputs {
    list: Vec<Output>,
    /// The run's participants, by index.
    names: Vec<String>,
}

impl Outputs {
    /// `names`: the run's participants; `patience`: how long a full reader
    /// may hold a write back.
    pub fn open(
        node: &Node<Ipc>,
        run: &str,
        names: &[String],
        writes: &[Write],
        readers: &[Vec<String>],
        patience: Duration,
    ) -> Result<Outputs, ChannelError> {
        let mut list = Vec::new();
        for (w, names_) in writes.iter().zip(readers) {
            let indices = names_
                .iter()
                .filter_map(|r| names.iter().position(|n| n == r))
                .collect();
            let len_hint = w.items.map_or(1024, |n| n as usize * w.per_item as usize);
            let publisher = match names_.is_empty() {
                true => None,
                false => Some(channel::field_out(
                    node,
                    &names::field(run, &w.name),
                    names_.len(),
                    len_hint,
                    patience,
                )?),
            };
            list.push(Output {
                name: w.name.clone(),
                per_item: w.per_item,
                items: w.items,
                publisher,
                seq: 0,
                readers: indices,
            });
        }
        Ok(Outputs {
            list,
            names: names.to_vec(),
        })
    }

    pub fn find(&self, name: &str) -> Option<usize> {
        self.list.iter().position(|o| o.name == name)
    }

    /// Every participant that reads a field written here, by index.
    pub fn readers(&self) -> impl Iterator<Item = usize> + '_ {
        self.list.iter().flat_map(|o| o.readers.iter().copied())
    }

    pub fn has_readers(&self, i: usize) -> bool {
        self.list[i].publisher.is_some()
    }

    /// Publish `len` values of output `i`, computed by `fill` into the
    /// loaned shared memory; then wake the readers that sleep.
    pub fn write(
        &mut self,
        i: usize,
        len: usize,
        fill: impl FnOnce(&mut [f64]),
        presence: &Presence,
    ) -> Result<Written, ExchangeError> {
        let Some((sample, computed)) = self.fill(i, len, fill)? else {
            return Ok(Written::default());
        };
        let stamped = std::time::Instant::now();
        self.send(i, sample, presence)?;
        Ok(Written {
            computed,
            in_flight: stamped.elapsed(),
        })
    }

    /// `len` values of output `i` computed by `fill` into loaned shared
    /// memory, not yet sent, and the time `fill` took; None when nobody
    /// reads it.
    pub fn fill(
        &mut self,
        i: usize,
        len: usize,
        fill: impl FnOnce(&mut [f64]),
    ) -> Result<Option<(FieldLoan, Duration)>, ExchangeError> {
        let out = &mut self.list[i];
        check_length(out, len)?;
        let Some(publisher) = &out.publisher else {
            return Ok(None);
        };
        let sample = publisher
            .loan_slice_uninit(len)
            .map_err(channel::ipc_err("loan field"))?;
        // SAFETY: the payload lies in a shared-memory segment the OS zero-filled
        // when it was mapped and which since holds only f64 values, so every
        // element is an initialised f64; `fill` overwrites all of them.
        let mut sample = unsafe { sample.assume_init() };
        let computing = std::time::Instant::now();
        fill(sample.payload_mut());
        Ok(Some((sample, computing.elapsed())))
    }

    /// Send a filled `sample` of output `i`, numbered and stamped now; then
    /// wake the readers that sleep.
    pub fn send(
        &mut self,
        i: usize,
        mut sample: FieldLoan,
        presence: &Presence,
    ) -> Result<(), ExchangeError> {
        let out = &mut self.list[i];
        *sample.user_header_mut() = [out.seq, channel::monotonic_ns()];
        if sample.send().is_err() {
            return Err(ExchangeError::Unread {
                field: out.name.clone(),
                readers: out.readers.iter().map(|&r| self.names[r].clone()).collect(),
            });
        }
        out.seq += 1;
        presence.wake_sleeping(&out.readers)?;
        Ok(())
    }
}

fn check_length(out: &Output, len: usize) -> Result<(), ExchangeError> {
    let per = out.per_item as usize;
    let (ok, declared) = match out.items {
        Some(n) => (
            len == n as usize * per,
            format!("{n} items of {per} values"),
        ),
        None => (len.is_multiple_of(per), format!("items of {per} values")),
    };
    match ok {
        true => Ok(()),
        false => Err(ExchangeError::Length {
            field: out.name.clone(),
            declared,
            written: len,
        }),
    }
}

pub struct Input {
    pub name: String,
    /// Its writer; None when nobody writes it (an optional read).
    pub source: Option<Source>,
    /// The writer's participant index.
    pub writer: usize,
    subscriber: Option<FieldIn>,
    /// Number of the next value due.
    expect: u64,
    /// How long the last wait for it took.
    pub last_wait: Duration,
}

pub struct Inputs {
    pub list: Vec<Input>,
}

impl Inputs {
    pub fn open(
        node: &Node<Ipc>,
        run: &str,
        names: &[String],
        reads: &[Read],
        sources: &[Option<Source>],
    ) -> Result<Inputs, ChannelError> {
        let mut list = Vec::new();
        for (r, source) in reads.iter().zip(sources) {
            let subscriber = match source {
                Some(s) => Some(channel::field_in(
                    node,
                    &names::field(run, &r.name),
                    s.readers as usize,
                )?),
                None => None,
            };
            let writer = source
                .as_ref()
                .and_then(|s| names.iter().position(|n| *n == s.writer))
                .unwrap_or(usize::MAX);
            list.push(Input {
                name: r.name.clone(),
                source: source.clone(),
                writer,
                subscriber,
                expect: 0,
                last_wait: Duration::ZERO,
            });
        }
        Ok(Inputs { list })
    }

    pub fn find(&self, name: &str) -> Option<usize> {
        self.list.iter().position(|i| i.name == name)
    }
}

impl Input {
    pub fn is_connected(&self) -> bool {
        self.subscriber.is_some()
    }

    /// The next value if it has arrived.
    pub fn poll(&self) -> Result<Option<FieldSample>, ChannelError> {
        match &self.subscriber {
            Some(s) => s.receive().map_err(channel::ipc_err("receive field")),
            None => Ok(None),
        }
    }

    /// Check that `sample` is the value due, and count it; returns when it
    /// was sent.
    pub fn accept(&mut self, sample: &FieldSample) -> Result<u64, ExchangeError> {
        let [got, sent] = *sample.user_header();
        if got != self.expect {
            return Err(ExchangeError::OutOfOrder {
                field: self.name.clone(),
                expected: self.expect,
                got,
            });
        }
        self.expect += 1;
        Ok(sent)
    }
}
