//! `[fluid.box.core]`: a box of cells fine where the canopy is and coarse
//! toward its sides (issue 45). Along each axis the cells have one width h
//! in the core and grow by a constant ratio, at most `growth`, from the
//! core's ends to the box's sides (a graded tensor-product grid; fluid-proc's
//! `axis.rs` gives its stencils). In a box that follows the parachute the
//! canopy stays near one place, so the fine cells can stay there.
//!
//! A graded grid rather than nested boxes of finer cells: it keeps one
//! structured MAC grid, so the projection stays one multigrid-preconditioned
//! solve and the slabs of the MPI split stay as they are, and its stencils
//! stay second order where the widths vary smoothly (fluid-proc's
//! `tests/graded.rs`: the Taylor–Green error in the core falls 3.6× per
//! halving). Its cost is the cells of the core's slabs that reach the sides
//! (the core's cross-section along each axis), which nested boxes would not
//! pay.

use scenario::Checker;
use serde::{Deserialize, Serialize};

/// Largest growth of one cell's width over the next a graded box takes.
/// The stencils' error grows with r − 1 where widths change (a term
/// (r − 1)·h·u″ beside the uniform grid's h²·u‴); at 1.2 the core of the
/// Taylor–Green test keeps its second order (`tests/graded.rs` of
/// fluid-proc), the bound the grid-generation literature gives (Thompson,
/// Warsi & Mastin, *Numerical Grid Generation*, 1985, ch. 8: ratios of
/// adjacent widths within about 1.2).
pub const MAX_GROWTH: f64 = 1.2;

/// The powers of two a graded axis's count is rounded up to a multiple
/// of, the largest not above a quarter of it: so that the multigrid's
/// levels halve it (fluid-proc's `multigrid.rs`).
const HALVINGS: [usize; 3] = [8, 4, 2];

/// `[fluid.box.core]`: the fine core of a graded box.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Core {
    /// Lowest corner of the core [m]: inside the box.
    pub lower: [f64; 3],
    /// Highest corner of the core [m]: inside the box. An axis whose core
    /// spans the whole box is uniform at `spacing` (one cell of it: a 2-D
    /// flow's thin axis).
    pub upper: [f64; 3],
    /// Width of the core's cells [m]; the core's ends move out to whole cells.
    pub spacing: f64,
    /// Largest ratio of a cell's width to the next one's toward the sides
    /// (at most 1.2).
    pub growth: f64,
}

impl Core {
    /// The widths of the cells along axis d of a box from `lower` to
    /// `upper` [m] (None where the core does not fit in the box).
    pub fn widths(&self, lower: [f64; 3], upper: [f64; 3], d: usize) -> Option<Vec<f64>> {
        let length = upper[d] - lower[d];
        let core = [self.lower[d] - lower[d], self.upper[d] - lower[d]];
        graded_widths(length, core, self.spacing, self.growth)
    }

    pub fn check(&self, c: &mut Checker, lower: [f64; 3], upper: [f64; 3]) {
        c.within("core", None, |c| {
            c.finite3(&["lower"], self.lower);
            c.finite3(&["upper"], self.upper);
            c.positive(&["spacing"], self.spacing, "m");
            c.rule(&["growth"], || format!("> 1, ≤ {MAX_GROWTH}"));
            c.rule(&["lower"], || "inside [fluid.box]".into());
            c.rule(&["upper"], || "inside [fluid.box], above lower".into());
            if !(self.growth > 1.0 && self.growth <= MAX_GROWTH) {
                c.problem(
                    &["growth"],
                    format!(
                        "growth = {}: a cell may be at most {MAX_GROWTH} times as wide as the \
                         next one toward the core, for the stencils to stay second order, \
                         and must grow (above 1)",
                        self.growth
                    ),
                );
            }
            let outside = (0..3).find(|&d| {
                !(lower[d] <= self.lower[d]
                    && self.lower[d] < self.upper[d]
                    && self.upper[d] <= upper[d])
            });
            if let Some(d) = outside {
                c.problem(
                    &["lower"],
                    format!(
                        "the core from {:?} to {:?} must lie inside the box from {lower:?} to \
                         {upper:?}, its upper corner above its lower (along {})",
                        self.lower,
                        self.upper,
                        ["x", "y", "z"][d]
                    ),
                );
            }
        });
    }
}

/// The widths of the cells of an axis of `length` [m] whose `core` = [lo,
/// hi] (from the axis's start) has cells of width `h`, growing by at most
/// `growth` per cell toward each end. The core's ends move outward to
/// whole cells. Each outer part takes the fewest whole cells that reach its
/// end at that growth, a few more where the count must reach a multiple of
/// a power of two, and the growth that fits them into it exactly. A core
/// spanning the axis gives uniform cells (as many as fit, at least one).
/// None where the core does not fit.
pub fn graded_widths(length: f64, core: [f64; 2], h: f64, growth: f64) -> Option<Vec<f64>> {
    let [lo, hi] = core;
    let slack = 1e-9 * length;
    if !(lo >= -slack && lo < hi && hi <= length + slack && h > 0.0 && growth > 1.0) {
        return None;
    }
    if lo <= slack && hi >= length - slack {
        let n = (length / h).round().max(1.0) as usize;
        return Some(vec![length / n as f64; n]);
    }
    let first = (lo.max(0.0) / h + 1e-9).floor();
    let cells = ((hi / h - 1e-9).ceil() - first).max(1.0) as usize;
    let below = first * h;
    let above = length - below - cells as f64 * h;
    if above < -slack {
        return None;
    }
    let parts = [below, above.max(0.0)];
    let mut m = parts.map(|l| fewest_cells(l, h, growth));
    let n = cells + m[0] + m[1];
    let multiple = HALVINGS.iter().copied().find(|&k| n >= 4 * k).unwrap_or(1);
    let extra = n.next_multiple_of(multiple) - n;
    if m[0] + m[1] > 0 {
        let low = extra * m[0] / (m[0] + m[1]);
        m = [m[0] + low, m[1] + extra - low];
    }
    let mut w: Vec<f64> = outer(parts[0], h, m[0]).into_iter().rev().collect();
    w.extend(std::iter::repeat_n(h, cells));
    w.extend(outer(parts[1], h, m[1]));
    Some(w)
}

/// h·r + h·r² + … + h·rᵐ.
fn reach(h: f64, r: f64, m: usize) -> f64 {
    (1..=m).map(|k| h * r.powi(k as i32)).sum()
}

/// The fewest cells growing from h by `growth` that reach `length`.
fn fewest_cells(length: f64, h: f64, growth: f64) -> usize {
    let mut m = 0;
    while reach(h, growth, m) < length * (1.0 - 1e-12) {
        m += 1;
    }
    m
}

/// The widths of `m` cells filling an outer part of `length` from the
/// core's h outward, each the same ratio to the one before: the ratio that
/// fits them exactly (by bisection).
fn outer(length: f64, h: f64, m: usize) -> Vec<f64> {
    if m == 0 {
        return Vec::new();
    }
    let (mut a, mut b) = (0.0, 2.0);
    while reach(h, b, m) < length {
        b *= 2.0;
    }
    for _ in 0..200 {
        let r = 0.5 * (a + b);
        if reach(h, r, m) < length {
            a = r;
        } else {
            b = r;
        }
    }
    let r = 0.5 * (a + b);
    (1..=m).map(|k| h * r.powi(k as i32)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The graded widths fill the length exactly, keep the core uniform at
    /// h, grow by no more than the growth from cell to cell, and come in a
    /// count the multigrid halves.
    #[test]
    fn graded_widths_fill_the_axis_within_their_growth() {
        let w = graded_widths(20.0, [7.5, 12.5], 0.25, 1.1).unwrap();
        let total: f64 = w.iter().sum();
        assert!((total - 20.0).abs() < 1e-9, "length {total}");
        for p in w.windows(2) {
            let q = p[1] / p[0];
            assert!((1.0 / 1.1 - 1e-12..=1.1 + 1e-12).contains(&q), "ratio {q}");
        }
        assert_eq!(w.iter().filter(|&&x| x == 0.25).count(), 20);
        assert_eq!(w.len() % 8, 0, "{} cells halve thrice", w.len());
        // A core spanning the axis: uniform cells; one outside: none.
        assert_eq!(graded_widths(0.5, [0.0, 0.5], 0.5, 1.1), Some(vec![0.5]));
        assert_eq!(graded_widths(2.0, [1.0, 3.0], 0.5, 1.1), None);
    }
}
