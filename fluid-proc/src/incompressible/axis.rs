//! The cells along one axis of the box: uniform, or graded (stretched) from
//! a fine uniform core toward the sides, so that a box that follows a
//! parachute can be fine where the canopy is and coarse far from it
//! (issue 45). Each stencil of the MAC grid reads two lengths here:
//! - a cell's width w_i (between its faces), the control length of a
//!   cell-centred value and the distance between two faces;
//! - a face's gap g_i = (w_{i−1} + w_i)/2 (between the centres of the cells
//!   beside it), the control length of a face value and the distance
//!   between two cell centres.
//!
//! On a uniform axis both are h, and the stencils keep the uniform grid's
//! own operations (so its results stay the same to the bit); on a graded
//! one they are the finite-volume stencils of the mapped grid, second order
//! where the widths vary smoothly (growth ratio r with r − 1 = O(h): the
//! grading refines with the grid, `graded`).
//!
//! Widths are kept for `PAD` cells beyond each end too: mirrored beyond a
//! side of the box (the ghost of a mirrored value sits at the mirrored
//! place), wrapped across a periodic one, and another rank's beyond a
//! slab's side (`slice`), so a gap at an end reads like one inside.

/// Widths kept beyond each end: the velocity's three ghost layers and the
/// face one further.
pub const PAD: usize = crate::layout::GHOSTS + 1;

/// A graded axis's multigrid level merges two neighbours whose widths sum
/// to at most this many of its finest (`Axis::coarse_plan`): two of the
/// finest, or two that grew by up to a quarter.
const MERGED: f64 = 2.5;

#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// Widths of cells −PAD .. n + PAD [m].
    widths: Vec<f64>,
    /// Where the axis's first face lies from the box's low side [m].
    start: f64,
    /// The one width of a uniform axis, ghosts included.
    uniform: Option<f64>,
    /// A graded axis's faces 0..=n from its start [m] (empty if uniform).
    faces: Vec<f64>,
    /// A graded axis's cell centres 0..n from the box's low side [m]
    /// (`place` of i + ½, looked up: the immersed kernels read them for
    /// every marker; empty if uniform).
    centres: Vec<f64>,
}

impl Axis {
    /// `n` cells of width `h`.
    pub fn uniform(n: usize, h: f64) -> Axis {
        Axis {
            widths: vec![h; n + 2 * PAD],
            start: 0.0,
            uniform: Some(h),
            faces: Vec::new(),
            centres: Vec::new(),
        }
    }

    /// Cells of the given widths, the ghosts wrapped (`periodic`) or
    /// mirrored beyond the ends. Uniform widths make a uniform axis.
    pub fn of_widths(w: &[f64], periodic: bool) -> Axis {
        let n = w.len();
        if w.iter().all(|&x| x == w[0]) {
            return Axis::uniform(n, w[0]);
        }
        let beyond = |i: isize| -> f64 {
            let n = n as isize;
            let j = match (periodic, i) {
                (true, _) => i.rem_euclid(n),
                (false, i) if i < 0 => (-1 - i).min(n - 1),
                (false, i) if i >= n => (2 * n - 1 - i).max(0),
                (false, i) => i,
            };
            w[j as usize]
        };
        let p = PAD as isize;
        let faces = std::iter::once(0.0)
            .chain(w.iter().scan(0.0, |x, w| {
                *x += w;
                Some(*x)
            }))
            .collect();
        Axis {
            widths: (-p..n as isize + p).map(beyond).collect(),
            start: 0.0,
            uniform: None,
            faces,
            centres: Vec::new(),
        }
        .with_centres()
    }

    /// A graded axis with its centres' table filled.
    fn with_centres(mut self) -> Axis {
        if self.uniform.is_none() {
            self.centres = (0..self.n()).map(|i| self.place(i as f64 + 0.5)).collect();
        }
        self
    }

    /// Cells along an axis of `length` [m] graded from `core` = [lo, hi]
    /// (from the axis's start) of cells of width `h`, growing by at most
    /// `ratio` per cell toward each end (`grading.rs` of fluid-section says
    /// how). None when the core does not fit in the axis.
    pub fn graded(length: f64, core: [f64; 2], h: f64, ratio: f64, periodic: bool) -> Option<Axis> {
        let w = fluid_section::grading::graded_widths(length, core, h, ratio)?;
        Some(Axis::of_widths(&w, periodic))
    }

    pub fn n(&self) -> usize {
        self.widths.len() - 2 * PAD
    }

    /// Width of cell i (−PAD ≤ i < n + PAD) [m].
    #[inline(always)]
    pub fn width(&self, i: isize) -> f64 {
        self.widths[(i + PAD as isize) as usize]
    }

    /// Distance between the centres of cells i − 1 and i: face i's gap [m].
    #[inline(always)]
    pub fn gap(&self, i: isize) -> f64 {
        match self.uniform {
            Some(h) => h,
            None => 0.5 * (self.width(i - 1) + self.width(i)),
        }
    }

    /// Whether every cell has the same width.
    pub fn is_uniform(&self) -> bool {
        self.uniform.is_some()
    }

    /// The finest and coarsest widths [m].
    pub fn width_range(&self) -> (f64, f64) {
        let inside = &self.widths[PAD..PAD + self.n()];
        inside
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), &w| (a.min(w), b.max(w)))
    }

    /// Where face i lies from the box's low side [m].
    pub fn face(&self, i: usize) -> f64 {
        match self.uniform {
            Some(h) => self.start + i as f64 * h,
            None => self.start + self.faces[i],
        }
    }

    /// Where the centre of cell i lies from the box's low side [m]: (i + ½)h
    /// on a uniform axis, whatever i; on a graded one, a cell beyond an end
    /// the next one out of cells as wide as the end's.
    pub fn centre(&self, i: i64) -> f64 {
        match self.uniform {
            Some(h) => (i as f64 + 0.5) * h + self.start,
            None => match usize::try_from(i).ok().and_then(|i| self.centres.get(i)) {
                Some(&c) => c,
                None => self.place(i as f64 + 0.5),
            },
        }
    }

    /// The axis's length [m].
    pub fn length(&self) -> f64 {
        self.face(self.n()) - self.start
    }

    /// Where x (from the box's low side) [m] lies in cells: face i at i,
    /// linear within a cell (x/h on a uniform axis), beyond an end in
    /// cells as wide as the end's.
    pub fn coordinate(&self, x: f64) -> f64 {
        if let Some(h) = self.uniform {
            return (x - self.start) / h;
        }
        let x = x - self.start;
        let n = self.n();
        let i = self.faces.partition_point(|&f| f <= x).clamp(1, n) - 1;
        i as f64 + (x - self.faces[i]) / self.faces_width(i)
    }

    /// The inverse of `coordinate` [m].
    fn place(&self, xi: f64) -> f64 {
        let n = self.n();
        let i = (xi.floor().max(0.0) as usize).min(n - 1);
        self.start + self.faces[i] + (xi - i as f64) * self.faces_width(i)
    }

    fn faces_width(&self, i: usize) -> f64 {
        self.faces[i + 1] - self.faces[i]
    }

    /// The span of the axis's cells of its finest width h, from the first
    /// such cell's low face to the last one's high face [m]: the fine core
    /// of a graded axis, the whole of a uniform one.
    pub fn core(&self) -> [f64; 2] {
        let (h, n) = (self.width_range().0, self.n());
        let fine: Vec<usize> = (0..n).filter(|&i| self.width(i as isize) == h).collect();
        [self.face(fine[0]), self.face(fine[fine.len() - 1] + 1)]
    }

    /// Cells lo..hi of this axis (a rank's slab), the cells beyond them
    /// this axis's own.
    pub fn slice(&self, lo: usize, hi: usize) -> Axis {
        let faces = match self.uniform {
            Some(_) => Vec::new(),
            None => self.faces[lo..=hi]
                .iter()
                .map(|f| f - self.faces[lo])
                .collect(),
        };
        Axis {
            widths: self.widths[lo..hi + 2 * PAD].to_vec(),
            start: self.face(lo),
            uniform: self.uniform,
            faces,
            centres: Vec::new(),
        }
        .with_centres()
    }

    /// Every cell split in two (a grid convergence study's next grid): the
    /// two parts in the ratio q = (w_{i+1}/w_{i−1})^¼ of the local growth,
    /// so that a geometric run of ratio r becomes one of ratio √r over the
    /// same length and the grid is the same mapping of a finer uniform one:
    /// its count doubles, and with it every multigrid level's.
    pub fn refined(&self, periodic: bool) -> Axis {
        if let Some(h) = self.uniform {
            return Axis::uniform(2 * self.n(), 0.5 * h);
        }
        let mut w = Vec::with_capacity(2 * self.n());
        for i in 0..self.n() as isize {
            let q = (self.width(i + 1) / self.width(i - 1)).powf(0.25);
            let first = self.width(i) / (1.0 + q);
            w.extend([first, self.width(i) - first]);
        }
        Axis::of_widths(&w, periodic)
    }

    /// Each cell's parent on the next coarser multigrid level, or None when
    /// the axis does not coarsen. A uniform axis halves (an even count of
    /// at least `least` cells). A graded one merges a pair of neighbours
    /// only where the two together are at most `MERGED` times the level's
    /// spacing `h` (the core's cells merged so far): the fine cells merge,
    /// the wide ones wait until the level's cells have grown to them. So
    /// each level is semi-coarsened where its cells are long along the
    /// axis, and the coarse correction reaches the errors the point
    /// smoother leaves along the long cells.
    pub fn coarse_plan(&self, h: f64, least: usize) -> Option<Vec<usize>> {
        let n = self.n();
        if self.uniform.is_some() {
            return (n.is_multiple_of(2) && n >= least).then(|| (0..n).map(|i| i / 2).collect());
        }
        let reach = MERGED * h;
        let mut plan = Vec::with_capacity(n);
        let mut i = 0;
        while i < n {
            let parent = plan.last().map_or(0, |&p| p + 1);
            let pair = i + 1 < n && self.width(i as isize) + self.width(i as isize + 1) <= reach;
            plan.extend(std::iter::repeat_n(parent, 1 + pair as usize));
            i += 1 + pair as usize;
        }
        (plan[n - 1] + 1 < n).then_some(plan)
    }

    /// The cells merged by `plan` (`coarse_plan`), `periodic` as this axis.
    pub fn coarsened(&self, plan: &[usize], periodic: bool) -> Axis {
        if let Some(h) = self.uniform {
            return Axis::uniform(self.n() / 2, 2.0 * h);
        }
        let mut w = vec![0.0; plan[plan.len() - 1] + 1];
        for (i, &p) in plan.iter().enumerate() {
            w[p] += self.width(i as isize);
        }
        Axis::of_widths(&w, periodic)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A graded axis keeps its core of the finest cells where it was put,
    /// and places and coordinates invert each other.
    #[test]
    fn a_graded_axis_keeps_its_core_and_maps_places_to_cells() {
        let a = Axis::graded(20.0, [7.5, 12.5], 0.25, 1.1, false).unwrap();
        let n = a.n();
        let [lo, hi] = a.core();
        assert!(
            (lo - 7.5).abs() < 1e-9 && (hi - 12.5).abs() < 1e-9,
            "core {lo}..{hi}"
        );
        assert!((a.length() - 20.0).abs() < 1e-9);
        for i in 0..n {
            let c = a.coordinate(a.centre(i as i64));
            assert!((c - (i as f64 + 0.5)).abs() < 1e-9, "cell {i}: {c}");
        }
    }

    /// Ghost widths mirror beyond a side and wrap across a periodic one;
    /// a slice keeps the neighbours' widths beyond its ends.
    #[test]
    fn ghost_widths_mirror_wrap_and_slice() {
        let w = [1.0, 2.0, 3.0, 4.0];
        let m = Axis::of_widths(&w, false);
        assert_eq!(
            (m.width(-1), m.width(-2), m.width(4), m.width(5)),
            (1.0, 2.0, 4.0, 3.0)
        );
        assert_eq!(m.gap(0), 1.0);
        let p = Axis::of_widths(&w, true);
        assert_eq!((p.width(-1), p.width(4)), (4.0, 1.0));
        assert_eq!(p.gap(0), 2.5);
        let s = m.slice(1, 3);
        assert_eq!((s.n(), s.width(-1), s.width(2)), (2, 1.0, 4.0));
        assert_eq!((s.face(0), s.face(2)), (1.0, 6.0));
        // Coordinates: faces at whole numbers, linear within a cell.
        assert_eq!(
            (m.coordinate(0.0), m.coordinate(2.0), m.coordinate(4.5)),
            (0.0, 1.5, 2.5)
        );
        assert_eq!(
            (m.centre(1), m.centre(3), m.coordinate(m.centre(2))),
            (2.0, 8.0, 2.5)
        );
        // At a level's spacing of 1.5, two together of at most 3.75: 1 + 2.
        let plan = m.coarse_plan(1.5, 4).unwrap();
        assert_eq!(plan, [0, 0, 1, 2]);
        assert_eq!(m.coarsened(&plan, false).width(0), 3.0);
        let r = Axis::graded(10.0, [4.0, 6.0], 0.5, 1.2, false).unwrap();
        let f = r.refined(false);
        assert_eq!(f.n(), 2 * r.n());
        assert!((f.face(f.n()) - 10.0).abs() < 1e-12);
        // Deep in a geometric run, the growth is √r.
        let q = f.width(2) / f.width(3);
        let coarse = r.width(0) / r.width(1);
        assert!((q - coarse.sqrt()).abs() < 1e-12, "{q} against √{coarse}");
    }
}
