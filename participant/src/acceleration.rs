//! Acceleration of a fixed-point iteration over a coupling window: the
//! writer of the accelerated fields has sent x̃_k, the solvers have answered
//! with x_k = H(x̃_k), and the next value sent is x̃_{k+1} = x̃_k + ω_k r_k,
//! r_k = x_k − x̃_k, computed in place over the loaned shared-memory
//! samples (`Segments`) so that no field is copied into a message.
//!
//! Aitken's ω (Irons & Tuck 1969; Küttler & Wall 2008, eq. 44) is the
//! secant step along the last two residuals,
//! ω_k = −ω_{k−1} · r_{k−1}·(r_k − r_{k−1}) / ‖r_k − r_{k−1}‖².
//! IQN-ILS (`iqn_ils.rs`) replaces ω by a least-squares model of the
//! inverse Jacobian built from the tries of this and the last windows.

use crate::iqn_ils::{Columns, Limits, Scale};
use crate::joint::Share;
use crate::scheme::Acceleration;

/// The writer's iteration state over one window.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct Accelerator {
    kind: Acceleration,
    /// x̃_k: what was last sent, all accelerated fields end to end.
    sent: Vec<f64>,
    /// r_{k−1} (Aitken, IQN-ILS).
    last_residual: Vec<f64>,
    /// x_{k−1}, the solvers' last answer (IQN-ILS).
    last_answer: Vec<f64>,
    omega: f64,
    /// Tries of this window so far.
    k: u32,
    /// IQN-ILS's columns, and the windows begun.
    columns: Columns,
    window: u64,
    /// Columns the last relaxation used (0: a plain ω).
    pub columns_used: usize,
    /// Parallel scheme: each field's weight in the joint inner product,
    /// set at a window's first try.
    #[serde(default)]
    scale: Scale,
    /// Parallel scheme: this try's answer and residual between
    /// [`Accelerator::share`] and [`Accelerator::relax_joint`].
    #[serde(skip)]
    pending: Option<(Vec<f64>, Vec<f64>)>,
    /// The writer's output index and length of each field in `sent`, in
    /// order: what a restarted run sends again of the fields its solver
    /// does not write at `Resume`.
    #[serde(default)]
    layout: Vec<(usize, usize)>,
    /// IQN-ILS: ω on the residual's part its columns do not explain
    /// ([`Columns::step_from`]). A setting, not state: never in a
    /// checkpoint, so a restarted run takes the scenario's.
    #[serde(skip, default = "whole")]
    complement: f64,
}

fn whole() -> f64 {
    1.0
}

/// Norms of one field's residual and value, ‖r‖₂ and ‖x‖₂.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Norms {
    pub residual: f64,
    pub value: f64,
}

impl Accelerator {
    /// `complement`: IQN-ILS's ω off its columns' span (1 for the others).
    pub fn new(kind: Acceleration, complement: f64) -> Accelerator {
        Accelerator {
            kind,
            sent: Vec::new(),
            last_residual: Vec::new(),
            last_answer: Vec::new(),
            omega: 0.0,
            k: 0,
            columns: Columns::default(),
            window: 0,
            columns_used: 0,
            scale: Scale::default(),
            pending: None,
            layout: Vec::new(),
            complement,
        }
    }

    /// This state, read from a checkpoint, with the settings of `now`.
    pub fn resumed_with(self, now: &Accelerator) -> Accelerator {
        Accelerator {
            complement: now.complement,
            ..self
        }
    }

    /// The output index and length of each field sent, in order.
    pub fn set_layout(&mut self, layout: Vec<(usize, usize)>) {
        self.layout = layout;
    }

    /// The part of the value last sent that is output `output`'s.
    pub fn sent_part(&self, output: usize) -> Option<&[f64]> {
        let mut at = 0;
        for &(i, len) in &self.layout {
            if i == output {
                return self.sent.get(at..at + len);
            }
            at += len;
        }
        None
    }

    /// A new window begins: its first value is relaxed with the initial ω,
    /// or by IQN-ILS with the columns of the windows before.
    pub fn start_window(&mut self) {
        self.k = 0;
        self.window += 1;
    }

    /// How many values were last sent.
    pub fn sent_len(&self) -> usize {
        self.sent.len()
    }

    /// Remember `values` (the fields end to end) as sent, unrelaxed: the
    /// initial values, or a window's converged answer.
    pub fn sent_as_is(&mut self, values: &mut [&mut [f64]]) {
        // The next relaxation starts afresh, with the initial ω.
        self.k = 0;
        self.sent.clear();
        for v in values.iter() {
            self.sent.extend_from_slice(v);
        }
    }

    /// The residual's and the value's norms per field of `values` (the
    /// solvers' answers x_k, end to end as sent).
    pub fn norms(&self, values: &[&mut [f64]]) -> Vec<Norms> {
        let mut at = 0;
        values
            .iter()
            .map(|v| {
                let sent = &self.sent[at..at + v.len()];
                at += v.len();
                let r2: f64 = v.iter().zip(sent).map(|(x, s)| (x - s) * (x - s)).sum();
                let x2: f64 = v.iter().map(|x| x * x).sum();
                Norms {
                    residual: r2.sqrt(),
                    value: x2.sqrt(),
                }
            })
            .collect()
    }

    /// Relax `values` (x_k in, x̃_{k+1} out, in place) and remember them as
    /// sent.
    pub fn relax(&mut self, values: &mut [&mut [f64]]) {
        if let Acceleration::IqnIls { .. } = self.kind {
            return self.quasi_newton(values);
        }
        self.columns_used = 0;
        let omega = self.omega_for(values);
        let mut at = 0;
        for v in values.iter_mut() {
            for (x, s) in v.iter_mut().zip(&mut self.sent[at..]) {
                *x = *s + omega * (*x - *s);
                *s = *x;
            }
            at += v.len();
        }
        self.omega = omega;
        self.k += 1;
    }

    /// IQN-ILS: x̃_{k+1} = x_k + W c, or x̃_k + ω₀ r_k with no column yet.
    fn quasi_newton(&mut self, values: &mut [&mut [f64]]) {
        let Acceleration::IqnIls {
            initial,
            reused_windows,
            max_columns,
            filter,
        } = self.kind
        else {
            unreachable!("called for IQN-ILS")
        };
        let limits = Limits {
            reused_windows,
            max_columns,
            filter,
        };
        let (x, r) = self.answer(values);
        self.push_column(&x, &r, limits);
        let next: Vec<f64> = match self.columns.step(&r, filter, self.complement) {
            Some((step, used)) => {
                self.columns_used = used;
                x.iter().zip(&step).map(|(x, s)| x + s).collect()
            }
            None => {
                self.columns_used = 0;
                self.plain_step(&r, initial)
            }
        };
        self.send_next(values, next, x, r);
    }

    /// x_k, the fields end to end, and r_k = x_k − x̃_k.
    fn answer(&self, values: &[&mut [f64]]) -> (Vec<f64>, Vec<f64>) {
        let x: Vec<f64> = values.iter().flat_map(|v| v.iter().copied()).collect();
        let r: Vec<f64> = x.iter().zip(&self.sent).map(|(x, s)| x - s).collect();
        (x, r)
    }

    /// IQN-ILS: from a window's second try on, the column (ΔR, ΔX).
    fn push_column(&mut self, x: &[f64], r: &[f64], limits: Limits) {
        self.columns.fit(x.len());
        if self.k > 0 && self.last_answer.len() == x.len() {
            let dr = r.iter().zip(&self.last_residual).map(|(a, b)| a - b);
            let dx = x.iter().zip(&self.last_answer).map(|(a, b)| a - b);
            self.columns
                .push(dr.collect(), dx.collect(), self.window, limits);
        }
    }

    /// x̃_k + ω r_k.
    fn plain_step(&self, r: &[f64], omega: f64) -> Vec<f64> {
        self.sent
            .iter()
            .zip(r)
            .map(|(s, r)| s + omega * r)
            .collect()
    }

    /// Write `next` into `values` and remember it as sent, with the try's
    /// answer and residual.
    fn send_next(&mut self, values: &mut [&mut [f64]], next: Vec<f64>, x: Vec<f64>, r: Vec<f64>) {
        let mut at = 0;
        for v in values.iter_mut() {
            v.copy_from_slice(&next[at..at + v.len()]);
            at += v.len();
        }
        self.sent = next;
        (self.last_residual, self.last_answer) = (r, x);
        self.k += 1;
    }

    /// Parallel scheme, a try's first half: this writer's share of the
    /// joint relaxation of answers `values` (`joint.rs`), in the inner
    /// product scaled by the window's first answer; the answer is kept
    /// for [`Accelerator::relax_joint`].
    pub fn share(&mut self, values: &[&mut [f64]], converged: bool, comparable: bool) -> Share {
        let (x, r) = self.answer(values);
        if self.k == 0 {
            self.scale = Scale::of(values);
        }
        let mut share = Share {
            converged,
            comparable,
            ..Share::default()
        };
        match self.kind {
            Acceleration::IqnIls {
                reused_windows,
                max_columns,
                filter,
                ..
            } => {
                let limits = Limits {
                    reused_windows,
                    max_columns,
                    filter,
                };
                self.columns.rescale(&self.scale);
                self.push_column(&x, &r, limits);
                share.columns = self.columns.count();
                share.gram = self.columns.gram();
                share.against = self.columns.against(&r);
            }
            Acceleration::Aitken { .. } if self.k > 0 && self.last_residual.len() == r.len() => {
                let d: Vec<f64> = r
                    .iter()
                    .zip(&self.last_residual)
                    .map(|(a, b)| a - b)
                    .collect();
                share.num = self.scale.dot(&self.last_residual, &d);
                share.den = self.scale.dot(&d, &d);
            }
            _ => {}
        }
        self.pending = Some((x, r));
        share
    }

    /// Parallel scheme, a try's second half: relax `values` by the sum of
    /// every writer's share, `total` (the same on every writer), and
    /// remember them as sent.
    pub fn relax_joint(&mut self, values: &mut [&mut [f64]], total: &Share) {
        let (x, r) = self.pending.take().expect("a share before its relaxation");
        self.columns_used = 0;
        let next = match self.kind {
            Acceleration::Constant { omega } => self.plain_step(&r, omega),
            Acceleration::Aitken { initial } => {
                self.omega = match self.k {
                    0 => initial,
                    _ => total.aitken(self.omega),
                };
                self.plain_step(&r, self.omega)
            }
            Acceleration::IqnIls {
                initial, filter, ..
            } => match total.coefficients(filter) {
                Some((kept, c)) => {
                    self.columns_used = kept.len();
                    let step = self.columns.step_from(&kept, &c, &r, self.complement);
                    x.iter().zip(&step).map(|(x, s)| x + s).collect()
                }
                None => self.plain_step(&r, initial),
            },
        };
        self.send_next(values, next, x, r);
    }

    /// This try's ω; keeps r_k for the next (Aitken).
    fn omega_for(&mut self, values: &[&mut [f64]]) -> f64 {
        match self.kind {
            Acceleration::Constant { omega } => omega,
            Acceleration::IqnIls { .. } => unreachable!("IQN-ILS has no ω"),
            Acceleration::Aitken { initial } => {
                let residual = values
                    .iter()
                    .flat_map(|v| v.iter())
                    .zip(&self.sent)
                    .map(|(x, s)| x - s);
                if self.k == 0 {
                    self.last_residual.clear();
                    self.last_residual.extend(residual);
                    return initial;
                }
                let (mut num, mut den) = (0.0, 0.0);
                for (r, last) in residual.zip(&mut self.last_residual) {
                    let d = r - *last;
                    num += *last * d;
                    den += d * d;
                    *last = r;
                }
                match den > 0.0 {
                    true => -self.omega * num / den,
                    false => self.omega,
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The added-mass iteration in one unknown: a light wall of mass m in
    /// fluid of added mass M under load f answers a guessed acceleration a
    /// with H(a) = (f − M a)/m. The fixed point is a* = f/(m + M); plain
    /// iteration diverges for M > m (Causin, Gerbeau & Nobile 2005), and a
    /// constant ω converges only below 2m/(m + M).
    fn h(a: f64) -> f64 {
        let (m, added, f) = (1.0, 4.0, 10.0);
        (f - added * a) / m
    }

    fn iterate(kind: Acceleration, tries: usize) -> Vec<f64> {
        let mut acc = Accelerator::new(kind, 1.0);
        let mut guess = [0.0];
        acc.sent_as_is(&mut [&mut guess[..]]);
        acc.start_window();
        let mut errors = Vec::new();
        for _ in 0..tries {
            let mut x = [h(guess[0])];
            acc.relax(&mut [&mut x[..]]);
            guess = x;
            errors.push((guess[0] - 2.0).abs());
        }
        errors
    }

    /// Aitken's secant step solves a linear scalar fixed point exactly at
    /// the second relaxed value; ω = 1 diverges; ω = 0.2 (= 1/(1 + M/m),
    /// the exact inverse) hits it at once.
    #[test]
    fn aitken_solves_the_added_mass_iteration_where_plain_iteration_diverges() {
        let plain = iterate(Acceleration::Constant { omega: 1.0 }, 4);
        assert!(plain[3] > 100.0, "{plain:?}");
        let exact = iterate(Acceleration::Constant { omega: 0.2 }, 1);
        assert!(exact[0] < 1e-14, "{exact:?}");
        let aitken = iterate(Acceleration::Aitken { initial: 0.1 }, 2);
        assert!(aitken[1] < 1e-12, "{aitken:?}");
        // One unknown: IQN-ILS's one column is the same secant.
        let iqn = iterate(
            Acceleration::IqnIls {
                initial: 0.1,
                reused_windows: 0,
                max_columns: 10,
                filter: 1e-2,
            },
            2,
        );
        assert!(iqn[1] < 1e-12, "{iqn:?}");
    }

    /// The added-mass iteration of a fabric in many modes, mode i of
    /// added-mass ratio μᵢ spread over [0, 8]: H(a)ᵢ = fᵢ − μᵢ aᵢ (unit
    /// cloth mass), fixed point aᵢ = fᵢ/(1 + μᵢ). IQN-ILS that keeps three
    /// columns cannot learn sixty modes; taking the rest whole (ω = 1) it
    /// amplifies those of μ > 1 and stalls, and with ω = 1/(1 + μ_max)
    /// off its columns every mode is damped and it converges
    /// ([`Columns::step_from`]).
    fn many_modes(complement: f64, tries: usize) -> f64 {
        let n = 60;
        let mu: Vec<f64> = (0..n).map(|i| 8.0 * i as f64 / (n - 1) as f64).collect();
        let f: Vec<f64> = (0..n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let exact: Vec<f64> = (0..n).map(|i| f[i] / (1.0 + mu[i])).collect();
        let kind = Acceleration::IqnIls {
            initial: 0.1,
            reused_windows: 0,
            max_columns: 3,
            filter: 1e-2,
        };
        let mut acc = Accelerator::new(kind, complement);
        let mut guess = vec![0.0; n];
        acc.sent_as_is(&mut [&mut guess[..]]);
        acc.start_window();
        for _ in 0..tries {
            let mut x: Vec<f64> = (0..n).map(|i| f[i] - mu[i] * guess[i]).collect();
            acc.relax(&mut [&mut x[..]]);
            guess = x;
        }
        let error: f64 = guess.iter().zip(&exact).map(|(g, e)| (g - e).powi(2)).sum();
        let size: f64 = exact.iter().map(|e| e * e).sum();
        (error / size).sqrt()
    }

    #[test]
    fn iqn_ils_relaxed_off_its_columns_converges_where_whole_steps_stall() {
        let whole = many_modes(1.0, 40);
        assert!(whole > 0.1, "relative error {whole:.2e} after 40 tries");
        let relaxed = many_modes(1.0 / 9.0, 40);
        assert!(
            relaxed < 1e-5,
            "relative error {relaxed:.2e} after 40 tries"
        );
    }
}
