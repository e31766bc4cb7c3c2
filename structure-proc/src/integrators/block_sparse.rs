//! Sparse matrices of 3×3 blocks between nodes (block compressed rows), for
//! the multigrid preconditioner: products, the transpose, the Galerkin
//! product Pᵀ·A·P, and the block diagonal's inverses. Row by row with a
//! marker array (Gustavson's method), so each costs the entries it makes.

use nalgebra::Matrix3;

pub type B3 = Matrix3<f64>;

/// Block row i holds columns `col[start[i]..start[i + 1]]`, ascending.
#[derive(Debug, Clone, Default)]
pub struct Bsr {
    pub rows: usize,
    pub cols: usize,
    pub start: Vec<usize>,
    pub col: Vec<usize>,
    pub val: Vec<B3>,
}

impl Bsr {
    /// Row by row from `row(i, push)`, which pushes (column, block) pairs;
    /// a column pushed twice in a row is summed.
    pub fn from_rows(rows: usize, cols: usize, mut row: impl FnMut(usize, &mut Row)) -> Bsr {
        let mut m = Bsr {
            rows,
            cols,
            start: vec![0],
            ..Bsr::default()
        };
        let mut acc = Row::new(cols);
        for i in 0..rows {
            row(i, &mut acc);
            acc.drain_into(&mut m.col, &mut m.val);
            m.start.push(m.col.len());
        }
        m
    }

    pub fn row(&self, i: usize) -> impl Iterator<Item = (usize, &B3)> {
        let r = self.start[i]..self.start[i + 1];
        self.col[r.clone()].iter().copied().zip(&self.val[r])
    }

    /// Aᵀ.
    pub fn transpose(&self) -> Bsr {
        let mut rows: Vec<Vec<(usize, B3)>> = vec![Vec::new(); self.cols];
        for i in 0..self.rows {
            for (j, b) in self.row(i) {
                rows[j].push((i, b.transpose()));
            }
        }
        Bsr::from_rows(self.cols, self.rows, |j, acc| {
            for &(i, b) in &rows[j] {
                acc.add(i, &b);
            }
        })
    }

    /// A·B.
    pub fn mul(&self, b: &Bsr) -> Bsr {
        assert_eq!(self.cols, b.rows);
        Bsr::from_rows(self.rows, b.cols, |i, acc| {
            for (k, a) in self.row(i) {
                for (j, bkj) in b.row(k) {
                    acc.add(j, &(a * bkj));
                }
            }
        })
    }

    /// The inverses of the diagonal blocks; the identity where one is singular.
    pub fn diagonal_inverses(&self) -> Vec<B3> {
        (0..self.rows)
            .map(|i| inverse_or_identity(self.row(i).find(|&(j, _)| j == i).map(|(_, b)| *b)))
            .collect()
    }
}

/// A diagonal block's inverse; the identity where it is missing or singular.
fn inverse_or_identity(d: Option<B3>) -> B3 {
    d.and_then(|d| d.try_inverse()).unwrap_or_else(B3::identity)
}

/// One row being summed: the blocks by column, and which columns it has.
pub struct Row {
    block: Vec<B3>,
    seen: Vec<bool>,
    cols: Vec<usize>,
}

impl Row {
    fn new(cols: usize) -> Row {
        Row {
            block: vec![B3::zeros(); cols],
            seen: vec![false; cols],
            cols: Vec::new(),
        }
    }

    pub fn add(&mut self, j: usize, b: &B3) {
        if !self.seen[j] {
            self.seen[j] = true;
            self.block[j] = B3::zeros();
            self.cols.push(j);
        }
        self.block[j] += b;
    }

    fn drain_into(&mut self, col: &mut Vec<usize>, val: &mut Vec<B3>) {
        self.cols.sort_unstable();
        for &j in &self.cols {
            col.push(j);
            val.push(self.block[j]);
            self.seen[j] = false;
        }
        self.cols.clear();
    }
}

/// A [`Bsr`] kept for products only, in f32 blocks and 32-bit columns: half
/// the bytes a product reads, which is what a multigrid cycle pays for once
/// its matrices outgrow the cache. Products sum in f64.
#[derive(Debug, Clone, Default)]
pub struct Bsr32 {
    pub rows: usize,
    start: Vec<usize>,
    col: Vec<u32>,
    val: Vec<nalgebra::Matrix3<f32>>,
}

impl Bsr32 {
    pub fn new(m: &Bsr) -> Bsr32 {
        assert!(m.cols <= u32::MAX as usize);
        Bsr32 {
            rows: m.rows,
            start: m.start.clone(),
            col: m.col.iter().map(|&j| j as u32).collect(),
            val: m.val.iter().map(|b| b.cast::<f32>()).collect(),
        }
    }

    /// The inverses of the (rounded) diagonal blocks, so that a smoother and
    /// a residual of this matrix read the same matrix; the identity where
    /// one is singular.
    pub fn diagonal_inverses(&self) -> Vec<B3> {
        (0..self.rows)
            .map(|i| inverse_or_identity(self.row(i).find(|&(j, _)| j == i).map(|(_, b)| b)))
            .collect()
    }

    /// Row i's blocks, from either end (a backward sweep reads them
    /// backwards, so that it streams through memory in one direction).
    pub fn row(&self, i: usize) -> impl DoubleEndedIterator<Item = (usize, B3)> + '_ {
        let r = self.start[i]..self.start[i + 1];
        let blocks = self.val[r.clone()].iter().map(|b| b.cast::<f64>());
        self.col[r].iter().map(|&j| j as usize).zip(blocks)
    }

    /// y ← A·x (3 values a node).
    pub fn apply(&self, x: &[f64], y: &mut [f64]) {
        for (i, yi) in y.chunks_exact_mut(3).enumerate() {
            let mut s = nalgebra::Vector3::zeros();
            for (j, b) in self.row(i) {
                s += b * nalgebra::Vector3::new(x[3 * j], x[3 * j + 1], x[3 * j + 2]);
            }
            yi.copy_from_slice(s.as_slice());
        }
    }
}
