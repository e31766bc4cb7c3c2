//! The run's clock: its windows, the steps each participant takes in them,
//! and when output is due (docs/PROTOCOL.md, "The schedule").
//!
//! Every participant follows this schedule itself, and the coupler follows
//! the same one to supervise, so the coupler relays no step: a participant
//! starts a step when the fields it reads for it have arrived. One FSI
//! window is one fluid step Δt_f; a participant that steps per impulse
//! sub-step takes n_i steps of Δt_f/n_i in each window when it has an
//! impulse partner, so that the two alternate.

use serde::{Deserialize, Serialize};

/// The run's time parameters, from the scenario's `[run]` and `[coupling]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Timing {
    /// Simulated start time [s].
    pub start_time: f64,
    /// Simulated end time [s]; the last window is shortened to end there.
    pub end_time: f64,
    /// FSI window Δt_f [s].
    pub window: f64,
    /// Simulated time between outputs [s]; 0 writes the first and last state only.
    pub output_interval: f64,
    /// Impulse exchanges n_i per window (`[coupling] impulse_substeps`).
    /// The sub-steps each participant takes a window are its own, in its
    /// declared [`Cadence`].
    pub impulse_substeps: u32,
    /// Seconds a participant may wait for a field (or the coupler for an answer).
    pub timeout: f64,
    /// Simulated time between run checkpoints [s] (`[run]
    /// checkpoint_interval`); 0 writes none.
    #[serde(default)]
    pub checkpoint_interval: f64,
}

impl Timing {
    /// Number of windows from start to end (the last one may be shortened).
    pub fn windows(&self) -> u64 {
        let span = self.end_time - self.start_time;
        (span / self.window - 1e-9).ceil().max(1.0) as u64
    }

    /// Start time and length of window `w`; the last window ends exactly at `end_time`.
    pub fn window_span(&self, w: u64) -> (f64, f64) {
        let t = self.start_time + w as f64 * self.window;
        (t, self.window.min(self.end_time - t))
    }
}

/// How often a participant steps, as it declares it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Cadence {
    /// One `Advance` per window of `substeps` internal sub-steps (the fluid: 1).
    PerWindow { substeps: u32 },
    /// One `Advance` per impulse sub-step, `substeps_per_window / n_i`
    /// internal sub-steps each, when another participant steps per impulse
    /// sub-step too (the structure: n_s; rigid bodies: n_i). Alone, it
    /// steps like `PerWindow` with all of them.
    PerImpulse { substeps_per_window: u32 },
}

/// One step of the schedule, as a participant is told to take it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Advance {
    /// Index of the coupling (FSI) window, from 0.
    pub window: u64,
    /// Simulated time at the start of this step [s].
    pub time: f64,
    /// Length of this step [s].
    pub dt: f64,
    /// How many internal sub-steps of `dt / substeps` to take.
    pub substeps: u32,
    /// True on the first step of a window (of each try at it): read what
    /// comes once a window.
    pub window_start: bool,
    /// True on the last step of a window: report monitors and publish window-end fields.
    pub window_end: bool,
    /// Which try at the window this is, from 0: implicit coupling repeats a
    /// window from its checkpoint until the interface converges.
    pub iteration: u32,
}

/// What a participant does next, in schedule order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Command {
    /// Publish the initial values of your output fields; report monitors.
    Initialize,
    Advance(Advance),
    /// Implicit coupling: save the state at this window's start, so that the
    /// window can be taken again from it (`RestoreCheckpoint`).
    SaveCheckpoint,
    /// Implicit coupling: the interface has not converged; return to the
    /// state saved at this window's start, then take the window again.
    RestoreCheckpoint,
    /// Write output number `index` (simulated time `time`) into the run directory.
    Output {
        index: u64,
        time: f64,
    },
    /// Run checkpoints (`[run] checkpoint_interval`): write what the run
    /// needs to go on from the end of `window` into
    /// `Participant::state_file(window)`. Only to a participant that
    /// declares `.restarts()`.
    WriteCheckpoint {
        window: u64,
    },
    /// A restarted run (`coupler run --restart`), in place of `Initialize`:
    /// read back what `WriteCheckpoint { window }` wrote, then publish the
    /// output fields as at `Initialize`. The run goes on with the next window.
    Resume {
        window: u64,
    },
    /// The run is over: call `finish`.
    Stop,
}

/// Multiples of an interval of simulated time reached so far. The next
/// one is computed from their count rather than added up, so no interval,
/// however small against the time, can stall it.
#[derive(Debug, Clone)]
struct Interval {
    start: f64,
    interval: f64,
    /// Multiples passed: the next is at start + (passed + 1)·interval.
    passed: u64,
}

impl Interval {
    fn new(start: f64, interval: f64) -> Interval {
        Interval {
            start,
            interval,
            passed: 0,
        }
    }

    /// Whether `t` reached the next multiple (never, for an interval of 0);
    /// if so, every multiple up to `t` counts as passed.
    fn reached(&mut self, t: f64) -> bool {
        if self.interval <= 0.0 {
            return false;
        }
        // A small tolerance keeps round-off in t from skipping one: a
        // billionth of the interval, or far from 0 s, where the clock's
        // steps are coarser than that, a few of them (a window spans at
        // least 2^20, scenario::MIN_CLOCK_STEPS_PER_WINDOW).
        let clock_step = t.abs().next_up() - t.abs();
        let tol = (1e-9 * self.interval).max(16.0 * clock_step);
        let next = self.start + (self.passed + 1) as f64 * self.interval;
        if t < next - tol {
            return false;
        }
        let k = ((t + tol - self.start) / self.interval).floor();
        self.passed = self.passed.max(k.max(0.0) as u64);
        true
    }
}

/// When output is due: at the start, at every `output_interval` of
/// simulated time (at the first window end that reaches it) and at the end.
#[derive(Debug, Clone)]
pub struct Outputs {
    every: Interval,
    /// Outputs written so far.
    index: u64,
}

impl Outputs {
    pub fn new(timing: &Timing) -> Outputs {
        Outputs {
            every: Interval::new(timing.start_time, timing.output_interval),
            index: 0,
        }
    }

    /// Whether output is due at time `t` (`last`: the run's end); if so,
    /// its index, and the schedule moves on.
    pub fn due(&mut self, t: f64, last: bool) -> Option<u64> {
        let reached = self.every.reached(t);
        if !(self.index == 0 || last || reached) {
            return None;
        }
        self.index += 1;
        Some(self.index - 1)
    }
}

/// One participant's commands, from `Initialize` to `Stop`.
#[derive(Debug, Clone)]
pub struct Plan {
    timing: Timing,
    windows: u64,
    /// Advances per window, and internal sub-steps per advance.
    per_window: u32,
    substeps: u32,
    outputs: Outputs,
    /// When run checkpoints are due (`checkpoint_interval`).
    checkpoints: Interval,
    /// Whether windows are repeated until the interface converges.
    implicit: bool,
    /// The try at the current window, from 0.
    iteration: u32,
    /// The command after the next one to hand out, as a position.
    at: Position,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Position {
    Initialize,
    FirstOutput,
    /// Implicit coupling only: save, or restore, before the window's first advance.
    Checkpoint {
        window: u64,
        restore: bool,
    },
    Advance {
        window: u64,
        k: u32,
    },
    /// Implicit coupling only: the window is over; whether to take it again
    /// is for [`Plan::decide`] to say.
    Verdict {
        window: u64,
    },
    Output {
        window: u64,
    },
    /// A run checkpoint at the window's end, if due.
    WriteCheckpoint {
        window: u64,
    },
    /// A restarted run's first command.
    Resume {
        window: u64,
    },
    Stop,
    Over,
}

impl Plan {
    /// `partnered`: whether another participant steps per impulse sub-step.
    pub fn new(timing: &Timing, cadence: Cadence, partnered: bool) -> Plan {
        let n_i = timing.impulse_substeps.max(1);
        let (per_window, substeps) = match cadence {
            Cadence::PerWindow { substeps } => (1, substeps),
            Cadence::PerImpulse {
                substeps_per_window,
            } if partnered => (n_i, substeps_per_window / n_i),
            Cadence::PerImpulse {
                substeps_per_window,
            } => (1, substeps_per_window),
        };
        Plan {
            timing: *timing,
            windows: timing.windows(),
            per_window,
            substeps: substeps.max(1),
            outputs: Outputs::new(timing),
            checkpoints: Interval::new(timing.start_time, timing.checkpoint_interval),
            implicit: false,
            iteration: 0,
            at: Position::Initialize,
        }
    }

    /// The same schedule with every window repeated from its checkpoint
    /// until [`decide`](Self::decide) lets it go on.
    pub fn implicit(mut self) -> Plan {
        self.implicit = true;
        self
    }

    /// The same schedule resumed after the end of `window`, as a restarted
    /// run takes it: `Resume`, then the next window. The outputs and run
    /// checkpoints of the windows before are counted as the full schedule
    /// would have, so their numbers and times go on alike.
    pub fn resumed_after(mut self, window: u64) -> Plan {
        let _ = self.outputs.due(self.timing.start_time, false);
        for w in 0..=window.min(self.windows.saturating_sub(1)) {
            let (t, dt) = self.timing.window_span(w);
            let _ = self.outputs.due(t + dt, w + 1 == self.windows);
            let _ = self.checkpoints.reached(t + dt);
        }
        self.at = Position::Resume { window };
        self
    }

    /// The window whose end awaits a verdict, and the try at it that just
    /// ended: the schedule goes on only after [`decide`](Self::decide).
    pub fn verdict_due(&self) -> Option<(u64, u32)> {
        match self.at {
            Position::Verdict { window } => Some((window, self.iteration)),
            _ => None,
        }
    }

    /// The verdict on the window that just ended: take it again from its
    /// checkpoint (`repeat`), or go on.
    pub fn decide(&mut self, repeat: bool) {
        let Position::Verdict { window } = self.at else {
            return;
        };
        self.at = match repeat {
            true => {
                self.iteration += 1;
                Position::Checkpoint {
                    window,
                    restore: true,
                }
            }
            false => Position::Output { window },
        };
    }

    /// Where a window starts: at its checkpoint when implicit.
    fn window_start(&mut self, window: u64) -> Position {
        self.iteration = 0;
        match self.implicit {
            true => Position::Checkpoint {
                window,
                restore: false,
            },
            false => Position::Advance { window, k: 0 },
        }
    }

    fn advance(&self, window: u64, k: u32) -> Advance {
        let (t, dt) = self.timing.window_span(window);
        if self.per_window == 1 {
            return Advance {
                window,
                time: t,
                dt,
                substeps: self.substeps,
                window_start: true,
                window_end: true,
                iteration: self.iteration,
            };
        }
        let dt_i = dt / self.per_window as f64;
        Advance {
            window,
            time: t + k as f64 * dt_i,
            dt: dt_i,
            substeps: self.substeps,
            window_start: k == 0,
            window_end: k + 1 == self.per_window,
            iteration: self.iteration,
        }
    }
}

impl Iterator for Plan {
    type Item = Command;

    fn next(&mut self) -> Option<Command> {
        loop {
            let (command, next) = match self.at {
                Position::Initialize => (Some(Command::Initialize), Position::FirstOutput),
                Position::FirstOutput => {
                    let t = self.timing.start_time;
                    let index = self.outputs.due(t, false);
                    let first = self.window_start(0);
                    (index.map(|index| Command::Output { index, time: t }), first)
                }
                Position::Checkpoint { window, restore } => {
                    let command = match restore {
                        true => Command::RestoreCheckpoint,
                        false => Command::SaveCheckpoint,
                    };
                    (Some(command), Position::Advance { window, k: 0 })
                }
                Position::Advance { window, k } => {
                    let next = if k + 1 < self.per_window {
                        Position::Advance { window, k: k + 1 }
                    } else if self.implicit {
                        Position::Verdict { window }
                    } else {
                        Position::Output { window }
                    };
                    (Some(Command::Advance(self.advance(window, k))), next)
                }
                // Undecided: no command until `decide`.
                Position::Verdict { .. } => return None,
                Position::Output { window } => {
                    let (t, dt) = self.timing.window_span(window);
                    let last = window + 1 == self.windows;
                    let time = t + dt;
                    let index = self.outputs.due(time, last);
                    let next = if last {
                        Position::Stop
                    } else {
                        Position::WriteCheckpoint { window }
                    };
                    (index.map(|index| Command::Output { index, time }), next)
                }
                Position::WriteCheckpoint { window } => {
                    let (t, dt) = self.timing.window_span(window);
                    let due = self.checkpoints.reached(t + dt);
                    let command = due.then_some(Command::WriteCheckpoint { window });
                    (command, self.window_start(window + 1))
                }
                Position::Resume { window } => {
                    let next = match window + 1 >= self.windows {
                        true => Position::Stop,
                        false => self.window_start(window + 1),
                    };
                    (Some(Command::Resume { window }), next)
                }
                Position::Stop => (Some(Command::Stop), Position::Over),
                Position::Over => return None,
            };
            self.at = next;
            if command.is_some() {
                return command;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn timing(end_time: f64, output_interval: f64) -> Timing {
        Timing {
            start_time: 0.0,
            end_time,
            window: 1e-3,
            output_interval,
            impulse_substeps: 3,
            timeout: 1.0,
            checkpoint_interval: 0.0,
        }
    }

    fn advances(plan: Plan) -> Vec<Advance> {
        plan.filter_map(|c| match c {
            Command::Advance(a) => Some(a),
            _ => None,
        })
        .collect()
    }

    #[test]
    fn impulse_partners_alternate_every_impulse_sub_step() {
        let t = timing(0.01, 0.0);
        let cadence = Cadence::PerImpulse {
            substeps_per_window: 6,
        };
        let a = advances(Plan::new(&t, cadence, true));
        assert_eq!(a.len(), 30, "3 impulse sub-steps in each of 10 windows");
        assert!(a
            .iter()
            .all(|a| a.substeps == 2 && (a.dt - 1e-3 / 3.0).abs() < 1e-15));
        assert_eq!(a.iter().filter(|a| a.window_end).count(), 10);
        // Each window's first sub-step says so, and only it.
        assert!(a
            .iter()
            .enumerate()
            .all(|(i, a)| a.window_start == (i % 3 == 0)));
        assert_eq!(a[4].time, 1e-3 + 1e-3 / 3.0, "window 1, sub-step 1");
        // Alone, it takes all its sub-steps in one advance per window.
        let a = advances(Plan::new(&t, cadence, false));
        assert_eq!(a.len(), 10);
        assert!(a
            .iter()
            .all(|a| a.substeps == 6 && a.window_start && a.window_end));
    }

    /// A run resumed after a run checkpoint's window takes the rest of the
    /// schedule exactly as the whole run does: the same advances, outputs
    /// (numbers and times) and later checkpoints.
    #[test]
    fn a_resumed_plan_is_the_rest_of_the_whole_plan() {
        let mut t = timing(0.02, 0.003);
        t.checkpoint_interval = 0.005;
        let cadence = Cadence::PerWindow { substeps: 1 };
        let whole: Vec<Command> = Plan::new(&t, cadence, false).collect();
        let written: Vec<u64> = whole
            .iter()
            .filter_map(|c| match c {
                Command::WriteCheckpoint { window } => Some(*window),
                _ => None,
            })
            .collect();
        // At 5, 10 and 15 ms; none at the run's end.
        assert_eq!(written, [4, 9, 14]);
        for &window in &written {
            let at = whole
                .iter()
                .position(|c| *c == Command::WriteCheckpoint { window })
                .unwrap();
            let rest: Vec<Command> = Plan::new(&t, cadence, false)
                .resumed_after(window)
                .collect();
            assert_eq!(rest[0], Command::Resume { window });
            assert_eq!(rest[1..], whole[at + 1..]);
        }
    }

    /// Implicit: each window starts at its checkpoint, waits for a verdict
    /// at its end, and a repeat restores the checkpoint and counts the try.
    #[test]
    fn an_implicit_window_is_taken_again_until_it_is_let_go_on() {
        let t = timing(0.002, 0.0);
        let mut plan = Plan::new(&t, Cadence::PerWindow { substeps: 1 }, false).implicit();
        let mut seen = Vec::new();
        loop {
            if let Some((window, iteration)) = plan.verdict_due() {
                let repeat = iteration < [2, 0][window as usize];
                plan.decide(repeat);
                continue;
            }
            match plan.next() {
                Some(Command::Advance(a)) => seen.push(format!("A{}.{}", a.window, a.iteration)),
                Some(Command::SaveCheckpoint) => seen.push("S".into()),
                Some(Command::RestoreCheckpoint) => seen.push("R".into()),
                Some(Command::Output { index, .. }) => seen.push(format!("O{index}")),
                Some(c) => seen.push(format!("{c:?}")),
                None => break,
            }
        }
        let expected = "Initialize O0 S A0.0 R A0.1 R A0.2 S A1.0 O1 Stop";
        assert_eq!(seen.join(" "), expected);
    }

    #[test]
    fn the_last_window_ends_at_the_end_time() {
        let a = advances(Plan::new(
            &timing(0.0105, 0.0),
            Cadence::PerWindow { substeps: 1 },
            false,
        ));
        assert_eq!(a.len(), 11);
        let last = a[10];
        assert!((last.time + last.dt - 0.0105).abs() < 1e-15, "{last:?}");
    }

    fn output_times(t: &Timing) -> Vec<f64> {
        Plan::new(t, Cadence::PerWindow { substeps: 1 }, false)
            .filter_map(|c| match c {
                Command::Output { time, .. } => Some(time),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn outputs_come_at_the_start_every_interval_and_the_end() {
        let times = output_times(&timing(0.2, 0.05));
        let expected = [0.0, 0.05, 0.1, 0.15, 0.2];
        assert_eq!(times.len(), expected.len(), "{times:?}");
        assert!(times
            .iter()
            .zip(expected)
            .all(|(a, b)| (a - b).abs() < 1e-12));
        assert_eq!(output_times(&timing(0.2, 0.0)), vec![0.0, 0.2]);
    }

    #[test]
    fn an_interval_far_below_the_clock_resolution_cannot_stall_the_schedule() {
        // 1e-17 s added to t ≈ 0.05 does not change it: counting intervals
        // rather than adding them up, the schedule still moves on, and
        // writes at every window end.
        let times = output_times(&timing(0.05, 1e-17));
        assert_eq!(times.len(), 51);
    }
}
