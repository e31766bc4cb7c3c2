//! What every participant of a run is doing, on a blackboard flag each one
//! keeps: computing, spinning or asleep; for a wait, whether it is expected
//! to be short, how long (as a power of two), and whom it waits for; and
//! how many cores it holds.
//!
//! The schedule is staggered: one participant computes while the others
//! wait for it. A waiting participant spins (it sees its value within a
//! fraction of a microsecond, with no system call on either side) when its
//! wait is expected short and the run's busy processes leave it a core.
//! When they do not, the waiter expecting the shortest wait keeps spinning
//! and the others sleep on their wake events: in a window of the
//! structure trading impulses with the rigid bodies every sub-step, the
//! rigid bodies spin and the fluid, which waits for the window's end,
//! sleeps. A sleeper is woken when it should spin after all: by its writer
//! starting to compute, or by another participant falling asleep and
//! freeing a core. A writer wakes a sleeping reader when its value is out;
//! a spinning reader costs it nothing.
//!
//! Other work on the machine counts: the cores a run has are the
//! machine's less those the kernel sees busy with tasks not of this run
//! (`load.rs`), so beside a user's busy process on two cores nobody spins.

use crate::channel::{self, Board, ChannelError, FlagIn, FlagOut, Ipc};
use crate::load::Load;
use crate::names;
use iceoryx2::node::Node;
use iceoryx2::port::notifier::Notifier;
use std::cell::Cell;
use std::sync::atomic::{fence, Ordering};
use std::time::{Duration, Instant};

/// How long a participant this one has woken counts as awake while its
/// flag still says asleep: the wakee raises its flag only once it runs, and
/// beside other work it runs on this participant's core (a sync wake-up
/// puts it there), so a waker that took its asleep flag at its word would
/// spin on the core the wakee waits for.
const WOKEN_AWAKE: Duration = Duration::from_millis(1);

/// How often a waiter shows on its flag that it is alive ([`Own::beat`]).
const BEAT_EVERY: Duration = Duration::from_millis(50);
/// A waiter whose flag has not beaten for this long (or a third of the
/// coupling timeout, if shorter) is stopped in its wait, not waiting: its
/// flag still names whom it waited for, though that one may have answered
/// long since. A sleeper beats every `BLOCK_SLICE` (10 ms); a second
/// leaves room for a machine loaded far past its cores.
const STALE: Duration = Duration::from_secs(1);

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum State {
    Computing,
    Spinning,
    Asleep,
}

/// One participant's flag, decoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Seen {
    pub state: State,
    /// Whether the wait it is in is expected to be short.
    pub short: bool,
    /// How long it is expected to be: ⌈log₂⌉ of its last length in µs.
    pub expected: u8,
    /// The participant it waits for, by index.
    pub waiting_for: Option<usize>,
    /// Cores it holds while awake (its MPI ranks).
    pub ranks: u64,
    /// When it last showed it is alive, in [`now_ms`].
    pub beat: u32,
}

/// Milliseconds on the machine's monotonic clock, which every process on
/// it shares, modulo 2³² (differences taken wrapping).
pub fn now_ms() -> u32 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime only writes the timespec it is given.
    unsafe { libc::clock_gettime(libc::CLOCK_MONOTONIC, &mut t) };
    (t.tv_sec as u64 * 1000 + t.tv_nsec as u64 / 1_000_000) as u32
}

/// A wait's expected length as a flag holds it: ⌈log₂⌉ of µs, at most 31.
pub fn expected(last: std::time::Duration) -> u8 {
    let us = last.as_micros().min(u32::MAX as u128) as u32;
    (32 - us.leading_zeros()).min(31) as u8
}

impl Seen {
    fn encode(self) -> u64 {
        let state = match self.state {
            State::Computing => 0,
            State::Spinning => 1,
            State::Asleep => 2,
        };
        let waiting = self.waiting_for.map_or(0, |w| w as u64 + 1);
        state
            | (self.short as u64) << 2
            | (self.expected as u64 & 31) << 3
            | (self.ranks & 0xffff) << 8
            | (waiting & 0xff) << 24
            | (self.beat as u64) << 32
    }

    fn decode(v: u64) -> Seen {
        Seen {
            state: match v & 3 {
                0 => State::Computing,
                1 => State::Spinning,
                _ => State::Asleep,
            },
            short: v & 4 != 0,
            expected: ((v >> 3) & 31) as u8,
            waiting_for: match (v >> 24) & 0xff {
                0 => None,
                w => Some(w as usize - 1),
            },
            ranks: (v >> 8) & 0xffff,
            beat: (v >> 32) as u32,
        }
    }

    /// Whether it waits but has not beaten within `limit` ms of `now`.
    fn stopped(self, now: u32, limit: u32) -> bool {
        self.state != State::Computing && now.wrapping_sub(self.beat) > limit
    }

    /// Cores it holds now: all its ranks while awake; asleep, rank 0 gives
    /// its core back and the others (polling inside MPI) keep theirs.
    fn cores(self) -> u64 {
        match self.state {
            State::Asleep => self.ranks.saturating_sub(1),
            _ => self.ranks,
        }
    }

    /// Whether it waits with a better claim to spin than `other`: a
    /// shorter expected wait, or an equal one and a lower index.
    fn before(self, me: usize, other: Seen, index: usize) -> bool {
        (self.expected, me) < (other.expected, index)
    }
}

/// This participant's own flag, as it is created when connecting.
pub struct Own {
    flag: FlagOut,
    /// What `flag` holds now.
    shown: Cell<Seen>,
    /// Its word on its last try at a window (`verdict.rs`), and its worst
    /// unconverged field (`channel::TRY_KEYS`).
    word: FlagOut,
    worst: [FlagOut; 3],
    ranks: u64,
    _board: Board,
}

impl Own {
    pub fn create(
        node: &Node<Ipc>,
        run: &str,
        name: &str,
        ranks: usize,
    ) -> Result<Own, ChannelError> {
        let (board, [flag, word, w0, w1, w2]) = channel::own_flag(node, &names::asleep(run, name))?;
        let own = Own {
            flag,
            shown: Cell::new(Seen::decode(0)),
            word,
            worst: [w0, w1, w2],
            ranks: ranks.max(1) as u64,
            _board: board,
        };
        own.set(State::Computing, None);
        Ok(own)
    }

    pub fn set(&self, state: State, wait: Option<(bool, u8, usize)>) {
        let seen = Seen {
            state,
            short: wait.is_some_and(|w| w.0),
            expected: wait.map_or(0, |w| w.1),
            waiting_for: wait.map(|w| w.2),
            ranks: self.ranks,
            beat: now_ms(),
        };
        self.show(seen);
    }

    fn show(&self, seen: Seen) {
        self.shown.set(seen);
        self.flag.update_with_copy(seen.encode());
    }

    /// In a wait: show that this participant is alive, at most every
    /// [`BEAT_EVERY`], so that a chain of waits ends at one stopped in its
    /// wait ([`Presence::waits_after`]).
    pub fn beat(&self) {
        let shown = self.shown.get();
        let now = now_ms();
        if now.wrapping_sub(shown.beat) as u128 >= BEAT_EVERY.as_millis() {
            self.show(Seen { beat: now, ..shown });
        }
    }

    /// Post this participant's word on its last try at a window, after its
    /// worst unconverged field (`worst`: index among the measured, ‖r‖₂,
    /// ‖x‖₂), so that a participant reading the word reads it too.
    pub fn post_word(&self, word: u64, worst: Option<(usize, f64, f64)>) {
        let (i, r, x) = worst.map_or((0, 0.0, 0.0), |(i, r, x)| (i as u64 + 1, r, x));
        self.worst[0].update_with_copy(i);
        self.worst[1].update_with_copy(r.to_bits());
        self.worst[2].update_with_copy(x.to_bits());
        std::sync::atomic::fence(Ordering::SeqCst);
        self.word.update_with_copy(word);
    }

    /// Leaving the run: holding no core, and waiting for no one, but for
    /// the one whose value it gave up waiting for, if it did.
    pub fn leave(&self) {
        let shown = self.shown.get();
        let seen = Seen {
            state: State::Asleep,
            short: false,
            expected: 0,
            waiting_for: shown
                .waiting_for
                .filter(|_| shown.state != State::Computing),
            ranks: 0,
            beat: now_ms(),
        };
        self.show(seen);
    }
}

struct Peer {
    flag: FlagIn,
    word: FlagIn,
    worst: [FlagIn; 3],
    wake: Notifier<Ipc>,
    _board: Board,
}

/// Every participant's flag, and a way to wake each.
pub struct Presence {
    own: Own,
    /// Index of this participant among the run's.
    me: usize,
    /// By participant index; None for this one.
    peers: Vec<Option<Peer>>,
    cores: u64,
    /// Cores other work on the machine holds.
    load: Load,
    /// By participant index: when this one last woke it, until its flag
    /// shows it awake ([`WOKEN_AWAKE`]).
    woken: Vec<Cell<Option<Instant>>>,
}

impl Presence {
    /// Open the other participants' flags; `names` are the run's
    /// participants, `me` this one's index among them.
    pub fn open(
        node: &Node<Ipc>,
        run: &str,
        names: &[String],
        me: usize,
        own: Own,
    ) -> Result<Presence, ChannelError> {
        let mut peers = Vec::new();
        for (i, name) in names.iter().enumerate() {
            if i == me {
                peers.push(None);
                continue;
            }
            let (board, [flag, word, w0, w1, w2]) =
                channel::peer_flag(node, &names::asleep(run, name))?;
            let wake = channel::notifier(node, &names::wake(run, name))?;
            peers.push(Some(Peer {
                flag,
                word,
                worst: [w0, w1, w2],
                wake,
                _board: board,
            }));
        }
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get()) as u64;
        Ok(Presence {
            own,
            me,
            woken: peers.iter().map(|_| Cell::new(None)).collect(),
            peers,
            cores,
            load: Load::new(),
        })
    }

    /// This participant's index among the run's.
    pub fn me(&self) -> usize {
        self.me
    }

    /// This participant's own flag.
    pub fn own(&self) -> &Own {
        &self.own
    }

    fn seen(&self, p: usize) -> Option<Seen> {
        let peer = self.peers.get(p)?.as_ref()?;
        Some(Seen::decode(*peer.flag.get()))
    }

    fn wake(&self, p: usize) -> Result<(), ChannelError> {
        if let Some(Some(peer)) = self.peers.get(p) {
            peer.wake.notify().map_err(channel::ipc_err("notify"))?;
            self.woken[p].set(Some(Instant::now()));
        }
        Ok(())
    }

    /// Participant `p`'s flag as the count of cores should take it: asleep
    /// but woken by this one under [`WOKEN_AWAKE`] ago, it computes.
    fn awake(&self, p: usize) -> Option<Seen> {
        let s = self.seen(p)?;
        let Some(at) = self.woken[p].get() else {
            return Some(s);
        };
        if s.state != State::Asleep || at.elapsed() >= WOKEN_AWAKE {
            self.woken[p].set(None);
            return Some(s);
        }
        Some(Seen {
            state: State::Computing,
            ..s
        })
    }

    /// Participant `p`'s word on its last try at a window (this one's own
    /// is not read here).
    pub fn word(&self, p: usize) -> Option<u64> {
        Some(*self.peers.get(p)?.as_ref()?.word.get())
    }

    /// Participant `p`'s worst unconverged field on its last try, as
    /// [`Own::post_word`] has it.
    pub fn worst(&self, p: usize) -> Option<(usize, f64, f64)> {
        let w = &self.peers.get(p)?.as_ref()?.worst;
        let i = (*w[0].get()).checked_sub(1)?;
        Some((
            i as usize,
            f64::from_bits(*w[1].get()),
            f64::from_bits(*w[2].get()),
        ))
    }

    /// Whom participant `from` waits for, as the flags show it now, and
    /// whom that one waits for, and so on: the chain of waits after
    /// `from`, ending at one that computes (or hangs), has left (but for
    /// one that gave up its wait: the chain goes on to whom it waited
    /// for), is stopped in its wait (its flag has not beaten for
    /// [`STALE`], or a third of `timeout`), or would close a circle. Its
    /// last is the one that holds the others up.
    pub fn waits_after(&self, from: usize, timeout: Duration) -> Vec<usize> {
        let limit = STALE.min(timeout / 3).as_millis() as u32;
        let now = now_ms();
        let mut chain: Vec<usize> = Vec::new();
        let mut at = from;
        while let Some(next) = self
            .seen(at)
            .filter(|s| s.state != State::Computing && (s.ranks == 0 || !s.stopped(now, limit)))
            .and_then(|s| s.waiting_for)
        {
            if next == from || next == self.me || chain.contains(&next) {
                break;
            }
            chain.push(next);
            at = next;
        }
        chain
    }

    /// Wake every participant that sleeps.
    pub fn wake_all_sleeping(&self) -> Result<(), ChannelError> {
        let all: Vec<usize> = (0..self.peers.len()).filter(|&p| p != self.me).collect();
        self.wake_sleeping(&all)
    }

    /// Whether participant `p` has left the run (its flag says so; a
    /// participant still in the run holds at least one rank).
    pub fn has_left(&self, p: usize) -> bool {
        self.seen(p).is_none_or(|s| s.ranks == 0)
    }

    /// Whether this machine has a core to spare at all.
    pub fn can_spin(&self) -> bool {
        self.cores >= 2
    }

    /// Every participant's flag but `except`'s (this one's own as `mine`).
    fn others(&self, except: usize, mine: Seen) -> impl Iterator<Item = (usize, Seen)> + '_ {
        (0..self.peers.len())
            .filter(move |&p| p != except)
            .filter_map(move |p| match p == self.me {
                true => Some((p, mine)),
                false => self.awake(p).map(|s| (p, s)),
            })
    }

    /// Cores the run has: the machine's, less those other work holds.
    fn run_cores(&self) -> u64 {
        let me = self.own.ranks;
        let ours = me
            + (0..self.peers.len())
                .filter_map(|p| self.awake(p))
                .map(|s| s.cores())
                .sum::<u64>();
        let others = self.load.others(std::time::Instant::now(), ours);
        self.cores.saturating_sub(others)
    }

    /// Whether other work holds some of the machine's cores now: then not
    /// even a short spin is free, since a spinner keeps its core from the
    /// participant it just woke (a sync wake-up puts that one on the
    /// waker's core).
    pub fn crowded(&self) -> bool {
        self.run_cores() < self.cores
    }

    /// Whether participant `p`, waiting as `w`, may spin while this one is
    /// `mine`: its wait is expected short, and the others' busy cores
    /// leave it room among the cores the run has, or, when they do not,
    /// the computing ones alone do and no spinner expects a shorter wait.
    fn may_spin_as(&self, p: usize, w: Seen, mine: Seen) -> bool {
        if !w.short || !self.can_spin() {
            return false;
        }
        let cores = self.run_cores();
        let busy: u64 = self.others(p, mine).map(|(_, s)| s.cores()).sum();
        if busy + w.ranks <= cores {
            return true;
        }
        let computing: u64 = self
            .others(p, mine)
            .filter(|(_, s)| s.state == State::Computing)
            .map(|(_, s)| s.cores())
            .sum();
        computing + w.ranks <= cores
            && self
                .others(p, mine)
                .filter(|(_, s)| s.state == State::Spinning)
                .all(|(q, s)| w.before(p, s, q))
    }

    /// Whether this participant, waiting (`short`, `expected`) for
    /// `writer`, may spin now.
    pub fn may_spin(&self, short: bool, expected: u8, writer: usize) -> bool {
        let w = self.as_waiting(State::Spinning, short, expected, writer);
        self.may_spin_as(self.me, w, w)
    }

    fn as_waiting(&self, state: State, short: bool, expected: u8, writer: usize) -> Seen {
        Seen {
            state,
            short,
            expected,
            waiting_for: Some(writer),
            ranks: self.own.ranks,
            beat: now_ms(),
        }
    }

    /// Waiting for `writer`: spinning, or (after a fence that pairs with
    /// the writer's) asleep.
    pub fn waiting(&self, state: State, short: bool, expected: u8, writer: usize) {
        self.own.set(state, Some((short, expected, writer)));
        fence(Ordering::SeqCst);
    }

    /// Wake the sleepers `pick` selects that may spin now, this participant
    /// being `mine`.
    fn wake_spinners(&self, mine: Seen, pick: impl Fn(Seen) -> bool) -> Result<(), ChannelError> {
        for p in 0..self.peers.len() {
            let Some(s) = self.seen(p) else { continue };
            if s.state == State::Asleep && s.ranks > 0 && pick(s) {
                let as_spinner = Seen {
                    state: State::Spinning,
                    ..s
                };
                if self.may_spin_as(p, as_spinner, mine) {
                    self.wake(p)?;
                }
            }
        }
        Ok(())
    }

    /// The value came: computing from now on. Whoever sleeps in a short
    /// wait for this participant and may spin now is woken.
    pub fn computing(&self) -> Result<(), ChannelError> {
        self.own.set(State::Computing, None);
        let mine = Seen {
            state: State::Computing,
            short: false,
            expected: 0,
            waiting_for: None,
            ranks: self.own.ranks,
            beat: now_ms(),
        };
        self.wake_spinners(mine, |s| s.waiting_for == Some(self.me))
    }

    /// This participant just fell asleep (waiting as given) and freed a
    /// core: wake those that may spin now.
    pub fn freed_core(&self, short: bool, expected: u8, writer: usize) -> Result<(), ChannelError> {
        let mine = self.as_waiting(State::Asleep, short, expected, writer);
        self.wake_spinners(mine, |_| true)
    }

    /// After a value went out to `readers`: wake those that sleep. The
    /// fence pairs with the one a reader passes after raising its flag
    /// (Dekker's pattern), so a reader falling asleep as the value goes out
    /// is woken or sees it.
    pub fn wake_sleeping(&self, readers: &[usize]) -> Result<(), ChannelError> {
        fence(Ordering::SeqCst);
        for &r in readers {
            if self.seen(r).is_some_and(|s| s.state == State::Asleep) {
                self.wake(r)?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flag_reads_back_as_written() {
        assert_eq!(expected(std::time::Duration::from_micros(300)), 9);
        for (state, short, expected, waiting_for, ranks, beat) in [
            (State::Asleep, true, 9, Some(0), 4, 0),
            (State::Computing, false, 0, None, 1, 17),
            (State::Spinning, true, 31, Some(7), 1, u32::MAX),
        ] {
            let seen = Seen {
                state,
                short,
                expected,
                waiting_for,
                ranks,
                beat,
            };
            assert_eq!(Seen::decode(seen.encode()), seen);
        }
    }

    #[test]
    fn a_waiter_that_stops_beating_reads_as_stopped_and_one_computing_never() {
        let waiting = Seen {
            state: State::Asleep,
            short: false,
            expected: 0,
            waiting_for: Some(1),
            ranks: 1,
            beat: u32::MAX - 100,
        };
        // 600 ms later across the clock's wrap: stopped past 500 ms only.
        let now = 499;
        assert!(waiting.stopped(now, 500));
        assert!(!waiting.stopped(now, 700));
        let computing = Seen {
            state: State::Computing,
            ..waiting
        };
        assert!(!computing.stopped(now, 500));
    }
}
