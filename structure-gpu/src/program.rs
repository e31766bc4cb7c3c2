//! Each explicit scheme as a list of the kernels' passes, in the order of
//! structure-proc's integrators (`euler_cromer.rs`, `velocity_verlet.rs`,
//! `rk4.rs`), so the device does the CPU's arithmetic step for step.

/// The explicit schemes the device runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scheme {
    /// Thesis eqs. (15)–(16).
    EulerCromer,
    /// Thesis eqs. (37)–(40), v_{n+1} in the damping force predicted by Euler.
    VelocityVerlet,
    /// Thesis eqs. (42)–(51); the dissertation's GPU scheme (§5).
    Rk4,
}

/// The device's vectors, 3 reals a node each.
pub(crate) mod vector {
    pub const X: u32 = 0;
    pub const V: u32 = 1;
    pub const F1: u32 = 2;
    pub const F2: u32 = 3;
    pub const F3: u32 = 4;
    pub const F4: u32 = 5;
    pub const V2: u32 = 6;
    pub const V3: u32 = 7;
    pub const V4: u32 = 8;
    pub const XS: u32 = 9;
}
use vector::*;

/// One pass of a step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Pass {
    /// Element forces at positions `x`, velocities `v`, into the slots.
    Slots { x: u32, v: u32 },
    /// out ← m·g + the slots, node by node.
    Gather { out: u32 },
    /// out ← a + c·b, divided by the node's mass where `scaled`; where
    /// 1/m = 0 a kick that `reacts` adds c·b to the reaction instead (the
    /// impulse on held and attached nodes).
    Combine {
        out: u32,
        a: u32,
        b: u32,
        c: Coef,
        scaled: bool,
        reacts: bool,
    },
}

/// A multiple of the step, `times`·h/`over`, rounded as the CPU's
/// integrators round it (RK4's w·h/6).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Coef {
    pub times: f64,
    pub over: f64,
}

impl Coef {
    pub fn of(self, h: f64) -> f64 {
        self.times * h / self.over
    }
}

/// times·h.
const fn h(times: f64) -> Coef {
    Coef { times, over: 1.0 }
}

/// v ← v + c·f/m, the impulse c·f on nodes with 1/m = 0 to the reaction
/// (the CPU's `kick`).
fn kick(v: u32, f: u32, c: Coef) -> Pass {
    Pass::Combine {
        out: v,
        a: v,
        b: f,
        c,
        scaled: true,
        reacts: true,
    }
}

/// out ← v + c·f/m, a trial velocity (the CPU's `kicked`).
fn kicked(out: u32, v: u32, f: u32, c: Coef) -> Pass {
    Pass::Combine {
        out,
        a: v,
        b: f,
        c,
        scaled: true,
        reacts: false,
    }
}

/// out ← x + c·v.
fn drift(out: u32, x: u32, v: u32, c: Coef) -> Pass {
    Pass::Combine {
        out,
        a: x,
        b: v,
        c,
        scaled: false,
        reacts: false,
    }
}

/// The force at (x, v) into `out`.
fn force(x: u32, v: u32, out: u32) -> [Pass; 2] {
    [Pass::Slots { x, v }, Pass::Gather { out }]
}

impl Scheme {
    /// How many vectors a step uses: one past the highest it names. The
    /// reaction follows them.
    pub(crate) fn vectors(self) -> u32 {
        let named = |p: &Pass| match *p {
            Pass::Slots { x, v } => x.max(v),
            Pass::Gather { out } => out,
            Pass::Combine { out, a, b, .. } => out.max(a).max(b),
        };
        self.passes().iter().map(named).max().unwrap_or(V) + 1
    }

    /// One step's passes.
    pub(crate) fn passes(self) -> Vec<Pass> {
        let mut p = Vec::new();
        match self {
            Scheme::EulerCromer => {
                p.extend(force(X, V, F1));
                p.push(kick(V, F1, h(1.0))); // (15)
                p.push(drift(X, X, V, h(1.0))); // (16)
            }
            Scheme::VelocityVerlet => {
                // F1 = f0, F2 = f1, V2 = the predictor for (39).
                p.extend(force(X, V, F1));
                p.push(kicked(V2, V, F1, h(1.0)));
                p.push(kick(V, F1, h(0.5))); // (37)
                p.push(drift(X, X, V, h(1.0))); // (38)
                p.extend(force(X, V2, F2)); // (39)
                p.push(kick(V, F2, h(0.5))); // (40)
            }
            Scheme::Rk4 => {
                p.extend(force(X, V, F1)); // (42)–(43)
                p.push(drift(XS, X, V, h(0.5)));
                p.push(kicked(V2, V, F1, h(0.5)));
                p.extend(force(XS, V2, F2)); // (44)–(45)
                p.push(drift(XS, X, V2, h(0.5)));
                p.push(kicked(V3, V, F2, h(0.5)));
                p.extend(force(XS, V3, F3)); // (46)–(47)
                p.push(drift(XS, X, V3, h(1.0)));
                p.push(kicked(V4, V, F3, h(1.0)));
                p.extend(force(XS, V4, F4)); // (48)–(49)
                                             // (51) then (50), with the CPU's weights w·h/6.
                for (vk, w) in [(V, 1.0), (V2, 2.0), (V3, 2.0), (V4, 1.0)] {
                    p.push(drift(
                        X,
                        X,
                        vk,
                        Coef {
                            times: w,
                            over: 6.0,
                        },
                    ));
                }
                for (f, w) in [(F1, 1.0), (F2, 2.0), (F3, 2.0), (F4, 1.0)] {
                    p.push(kick(
                        V,
                        f,
                        Coef {
                            times: w,
                            over: 6.0,
                        },
                    ));
                }
            }
        }
        p
    }
}
