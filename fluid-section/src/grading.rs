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
            c.rule(&["upper"], || {
                "inside [fluid.box], above lower, leaving parts cells growing from it fill".into()
            });
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
            self.check_placement(c, lower, upper);
        });
    }

    /// The core inside the box, and its outer parts ones that cells
    /// growing from it fill.
    fn check_placement(&self, c: &mut Checker, lower: [f64; 3], upper: [f64; 3]) {
        let outside = (0..3).find(|&d| {
            !(lower[d] <= self.lower[d]
                && self.lower[d] < self.upper[d]
                && self.upper[d] <= upper[d])
        });
        let grows = self.growth > 1.0 && self.spacing > 0.0;
        let unfilled = (0..3).find(|&d| self.widths(lower, upper, d).is_none());
        if let (None, true, Some(d)) = (outside, grows, unfilled) {
            c.problem(
                &["upper"],
                format!(
                    "the core's edges along {}, moved out to whole cells of {} m, leave a \
                     part beside the box's side that cells growing from {} m by at most {} \
                     cannot fill (one cell fills {} to {} m): move the core's edge by a part \
                     of a cell, or the side",
                    ["x", "y", "z"][d],
                    self.spacing,
                    self.spacing,
                    self.growth,
                    self.spacing,
                    self.spacing * self.growth
                ),
            );
        }
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
    }
}

/// The widths of the cells of an axis of `length` [m] whose `core` = [lo,
/// hi] (from the axis's start) has cells of width `h`, growing by at most
/// `growth` per cell toward each end. The core's ends move outward to
/// whole cells. Each outer part takes the fewest whole cells that reach its
/// end at that growth, and the growth that fits them into it exactly (any
/// count: the multigrid merges a graded axis's cells pair by pair where
/// they are fine, fluid-proc's `Axis::coarse_plan`, not by halving it). A core
/// spanning the axis gives uniform cells (as many as fit, at least one).
/// None where the core does not fit, or leaves an outer part such cells
/// cannot fill: one cell of h·r with 1 ≤ r ≤ growth fills from h to
/// h·growth, two from 2h to h(g + g²), and so on (a part of 0.44 m beside
/// cells of 0.71 m would need cells narrower than the core's).
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
    let m = parts.map(|l| fewest_cells(l, h, growth));
    // Fewer cells cannot reach the side; these, not one narrower than h.
    if (0..2).any(|s| (m[s] as f64) * h > parts[s] * (1.0 + 1e-12)) {
        return None;
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
    /// h, grow by no more than the growth from cell to cell, and are the
    /// fewest that do: one cell fewer on a side could not reach it.
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
        // 7.5 m on each side: 13 cells growing by 1.1 reach 6.74 m, 14 reach 7.69.
        let below = w.iter().take_while(|&&x| x != 0.25).count();
        assert_eq!((below, w.len()), (14, 48), "{w:?}");
        assert!(reach(0.25, 1.1, below - 1) < 7.5 && reach(0.25, 1.1, below) >= 7.5);
        // A core spanning the axis: uniform cells; one outside: none.
        assert_eq!(graded_widths(0.5, [0.0, 0.5], 0.5, 1.1), Some(vec![0.5]));
        assert_eq!(graded_widths(2.0, [1.0, 3.0], 0.5, 1.1), None);
        // The core's top moved out to 10 m leaves 0.2 m, narrower than a
        // core cell; to 9.5 m, 0.7 m, between what one cell of 0.5 m
        // growing by 1.1 fills (0.5–0.55 m) and two (1.0–1.155 m): none.
        // To 8.5 m, 1.7 m: three cells.
        assert_eq!(graded_widths(10.2, [1.0, 9.6], 0.5, 1.1), None);
        assert_eq!(graded_widths(10.2, [1.0, 9.3], 0.5, 1.1), None);
        assert_eq!(
            graded_widths(10.2, [1.0, 8.5], 0.5, 1.1).map(|w| w.len()),
            Some(20)
        );
    }
}
