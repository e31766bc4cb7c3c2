//! A window's predicted velocity, kept for the window's later tries under
//! implicit coupling.
//!
//! Step 1 of the projection method (`mod.rs`), the predicted
//! change δ = u* − uⁿ from the advection term Nⁿ, the viscous solves and
//! the last pressure's gradient, reads the window's start alone. The
//! interface enters after it: the canopy's and bodies' markers in the
//! forcing, the canopy's velocity in the frame's acceleration, both in the
//! projection. A try after the first starts from the same state, so it can
//! take the first try's Nⁿ and δ instead of computing them again (the
//! advection and the three Helmholtz solves, about 40 % of a step on the
//! C-9). It does so only after checking, bit for bit, that it reads what
//! the first try read: the velocities, the pressure, the step history (the
//! last advection term and the solves' first guess), the two step lengths,
//! and the sides' values. A kept prediction therefore gives the very bits a
//! fresh one would.
//!
//! The pressure solve reads more than the window's start: the interface's
//! forcing changes u* from try to try, but less and less as the tries
//! converge. A later try's solve therefore starts from the last try's φ
//! (`Prediction::correction`) rather than the window's first guess and
//! stops at the same residual, 10⁻⁸ of ‖b‖: fewer iterations, the same flow
//! to the solve's tolerance; a window taken again from its checkpoint, its
//! tries in the same order, still gives the same bits.

use crate::incompressible::faces::Faces;
use crate::incompressible::side::Sides;
use crate::incompressible::{FlowError, Incompressible};

/// What step 1 reads beyond the constant grid and viscosity, in place.
pub struct State<'a> {
    pub dt: f64,
    pub last_dt: Option<f64>,
    pub sides: &'a Sides,
    pub u: &'a Faces,
    pub q: &'a [f64],
    /// Per component, the history it starts from: Nⁿ⁻¹ and the viscous
    /// solve's first guess (empty for a component not advanced).
    pub history: [(&'a [f64], &'a [f64]); 3],
}

/// A [`State`] kept: what a kept prediction was computed from.
#[derive(Debug, Clone)]
pub struct Inputs {
    dt: f64,
    last_dt: Option<f64>,
    sides: Sides,
    u: Faces,
    q: Vec<f64>,
    history: [(Vec<f64>, Vec<f64>); 3],
}

impl Inputs {
    /// A copy of `state`, taken before anything is computed from it.
    pub fn of(state: &State) -> Inputs {
        Inputs {
            dt: state.dt,
            last_dt: state.last_dt,
            sides: *state.sides,
            u: state.u.clone(),
            q: state.q.to_vec(),
            history: state.history.map(|(n, g)| (n.to_vec(), g.to_vec())),
        }
    }

    /// Whether `state` holds the same bits as `self`.
    fn same(&self, state: &State) -> bool {
        let history = |(a, b): (&(Vec<f64>, Vec<f64>), &(&[f64], &[f64]))| {
            same_bits(&a.0, b.0) && same_bits(&a.1, b.1)
        };
        // The cheap checks first; the first differing value ends a scan.
        self.dt.to_bits() == state.dt.to_bits()
            && self.last_dt.map(f64::to_bits) == state.last_dt.map(f64::to_bits)
            && self.sides == *state.sides
            && self.u.n == state.u.n
            && same_bits(&self.q, state.q)
            && (0..3).all(|c| same_bits(&self.u.u[c], &state.u.u[c]))
            && self.history.iter().zip(&state.history).all(history)
    }
}

/// The window's first prediction and what it was computed from.
#[derive(Debug, Clone, Default)]
pub struct Prediction {
    from: Option<Inputs>,
    /// Per component: Nⁿ and δ (padded, as `Work` holds them).
    pub kept: [(Vec<f64>, Vec<f64>); 3],
    pub viscous_iterations: usize,
    /// The last try's pressure correction φ of the window's first step:
    /// the next try's first guess (empty before the first try's).
    pub correction: Vec<f64>,
}

impl Prediction {
    /// Whether the kept prediction was computed from `state`.
    pub fn holds_for(&self, state: &State) -> bool {
        self.from.as_ref().is_some_and(|f| f.same(state))
    }

    /// Nothing kept: the next prediction is computed.
    pub fn forget(&mut self) {
        self.from = None;
    }

    /// `inputs` are what [`Prediction::kept`] and the iterations, which
    /// the caller has just filled, were computed from.
    pub fn computed_from(&mut self, inputs: Inputs) {
        self.from = Some(inputs);
    }

    /// A later try's first guess of the pressure correction: the last
    /// try's, into `phi` (left as it is before there is one).
    pub fn guess(&self, phi: &mut [f64]) {
        if self.correction.len() == phi.len() {
            phi.copy_from_slice(&self.correction);
        }
    }

    /// `phi`, solved in this try's first step: the next try's guess.
    pub fn keep_correction(&mut self, phi: &[f64]) {
        self.correction.clear();
        self.correction.extend_from_slice(phi);
    }
}

/// A flow's window prediction: what step 1 reads, and the change kept
/// or computed.
impl Incompressible {
    /// What step 1 reads, for a kept prediction's check.
    fn state(&self, dt: f64) -> State<'_> {
        let history = std::array::from_fn(|c| match &self.work[c] {
            Some(w) => (w.n[0].as_slice(), w.delta.data.as_slice()),
            None => (&[][..], &[][..]),
        });
        State {
            dt,
            last_dt: self.last_dt,
            sides: &self.sides,
            u: &self.u,
            q: &self.q,
            history,
        }
    }

    /// [`Incompressible::change`], or the kept one where it was computed
    /// from the same state (then true); a computed one is kept.
    pub(super) fn change_kept(&mut self, dt: f64) -> Result<(usize, bool), FlowError> {
        let mut prediction = self.prediction.take().unwrap_or_default();
        // Every rank takes its kept change or none does: the solves sum
        // over the ranks.
        let miss = !prediction.holds_for(&self.state(dt)) as u8 as f64;
        let result = match self.part.max(miss) == 0.0 {
            true => {
                for (w, (n, delta)) in self.work.iter_mut().zip(&prediction.kept) {
                    if let Some(w) = w {
                        w.n.rotate_right(1);
                        w.n[0].copy_from_slice(n);
                        w.delta.data.copy_from_slice(delta);
                    }
                }
                Ok((prediction.viscous_iterations, true))
            }
            false => {
                prediction.forget();
                let inputs = Inputs::of(&self.state(dt));
                let computed = self.change(dt);
                if let Ok(iterations) = computed {
                    for (w, kept) in self.work.iter().zip(&mut prediction.kept) {
                        if let Some(w) = w {
                            kept.0.clone_from(&w.n[0]);
                            kept.1.clone_from(&w.delta.data);
                        }
                    }
                    prediction.viscous_iterations = iterations;
                    prediction.computed_from(inputs);
                }
                computed.map(|iterations| (iterations, false))
            }
        };
        self.prediction = Some(prediction);
        result
    }
}

/// Whether `a` and `b` hold the same bits (−0 is not +0, a NaN is itself).
fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}
