//! The continuous test (the dissertation §2.5, step 3; Bridson, Fedkiw &
//! Anderson 2002): the pairs that touch during a step from x^n along the
//! motion dx, each with the normal its collision impulse stops it along.

use super::candidates::Candidates;
use super::geometry::{Stencil, V3};
use super::{filter_map, impulse, Contacts, IMPACT_FRACTION};

/// A pair found touching during the step.
pub(super) struct Hit {
    pub stencil: Stencil,
    pub w: [f64; 4],
    pub normal: V3,
}

impl Contacts {
    /// The pairs that touch during the step along `dx`, by the model's
    /// own search.
    pub(super) fn touching(&mut self, c: &Option<Candidates>, dx: &[f64]) -> Vec<Hit> {
        match c {
            Some(c) => self.detect(c, dx),
            None => self.layered_detect(dx),
        }
    }

    /// The pairs that touch during the step from x^n along `dx`, with the
    /// normal that points from the second feature to the first as they
    /// stood at the start. A pair whose start distance (or the bound held
    /// for it) exceeds what its nodes move relative to each other by more
    /// than the tolerance cannot touch: its cubic is not solved.
    fn detect(&self, candidates: &Candidates, dx: &[f64]) -> Vec<Hit> {
        let eta = IMPACT_FRACTION * self.repulsion.thickness;
        filter_map(&candidates.pairs, |p| {
            self.hit(&p.stencil(), p.distance, dx, eta)
        })
    }

    /// The pair `st`, at least `bound` apart at x^n, if it touches (comes
    /// within `eta`) during the step along `dx`, with the normal that
    /// points from its second feature to its first as they stood at the
    /// start; None, without the cubic, if its bound exceeds what its nodes
    /// move relative to each other by more than `eta`.
    pub(super) fn hit(&self, st: &Stencil, bound: f64, dx: &[f64], eta: f64) -> Option<Hit> {
        let x = &self.start;
        if bound - st.approach(dx) > eta {
            return None;
        }
        let s = st.impact(x, dx, eta)?;
        let at = st.at(x, dx, s);
        let touch = st.closest(&at);
        let start = st.at(x, dx, 0.0);
        let before: V3 = (0..4).map(|i| start[i] * touch.w[i]).sum();
        let rel = impulse::relative(st, &touch.w, dx);
        if let Some(normal) = self.body_normal(st, &touch.w, dx, s) {
            // A body stops the feature along its true normal.
            return Some(Hit {
                stencil: *st,
                w: touch.w,
                normal,
            });
        }
        let normal = st
            .plane_normal(&at)
            .try_normalize(1e-300)
            .or_else(|| touch.separation.try_normalize(1e-300))
            .or_else(|| (-rel).try_normalize(1e-300))?;
        // The side the first feature stood on at the start; if the
        // start says nothing, the side the motion leaves.
        let side = normal.dot(&before);
        let sign = if side != 0.0 {
            side.signum()
        } else {
            -normal.dot(&rel).signum()
        };
        Some(Hit {
            stencil: *st,
            w: touch.w,
            normal: normal * sign,
        })
    }
}
