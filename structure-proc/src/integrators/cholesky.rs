//! The Newton step's linear system M + a·K + b·C solved with a sparse
//! Cholesky factorization (faer's supernodal LLᵀ with a fill-reducing
//! ordering). Conjugate gradients on a stiff membrane need more iterations
//! the finer the mesh (their count follows the condition number); a
//! factorization does not, but costs more than its triangular solves.
//! So a factorization is kept: later Newton steps, and later time steps,
//! solve by conjugate gradients preconditioned with it (the matrix changes
//! little from one to the next), and it is computed anew, and the step
//! solved by it directly, only when those fail to converge in
//! `LAGGED_ITERATIONS`. The ordering is computed once for the network's
//! pattern and kept while the pattern stays.

use super::cg::Cg;
use super::System;
use crate::forces::jacobian::Block;
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat};
use faer::{MatMut, Side};

/// The pattern's analysis: its sorted structure, how the entries map into
/// it, and the symbolic factorization.
struct Analysis {
    structure: SymbolicSparseColMat<usize>,
    argsort: Argsort<usize>,
    symbolic: SymbolicLlt<usize>,
}

#[derive(Default)]
pub struct Cholesky {
    blocks: Vec<Block>,
    values: Vec<f64>,
    /// The analysis, and the block count and size it was made for: a
    /// network's blocks come in a fixed order, so the pattern changes only
    /// with their number.
    analysis: Option<(Analysis, usize, usize)>,
    /// The kept factorization.
    factor: Option<Llt<usize, f64>>,
    cg: Cg,
}

/// Conjugate-gradient iterations preconditioned by the kept factorization
/// before it is computed anew.
const LAGGED_ITERATIONS: u32 = 10;

/// Every entry of M + a·K + b·C over the free degrees of freedom, in a
/// fixed order: the diagonal (the mass; 1 on held degrees of freedom, which
/// y = 0 solves), then the blocks' entries between free ones.
fn entries(blocks: &[Block], inv_mass: &[f64], n: usize, mut entry: impl FnMut(usize, usize, f64)) {
    let free = |d: usize| inv_mass[d / 3] != 0.0;
    for d in 0..n {
        entry(d, d, if free(d) { 1.0 / inv_mass[d / 3] } else { 1.0 });
    }
    for &(i, j, s) in blocks {
        for r in 0..3 {
            for c in 0..3 {
                let (row, col) = (3 * i + r, 3 * j + c);
                if free(row) && free(col) {
                    entry(row, col, s[(r, c)]);
                }
            }
        }
    }
}

impl Cholesky {
    /// y ← (M + a·K + b·C)⁻¹·rhs at (x, v) over the free degrees of freedom
    /// (1/m ≠ 0; y = 0 on the others), `apply` being that matrix's product:
    /// by conjugate gradients to `tol` preconditioned with the kept
    /// factorization, or by a new one. `false` if `sys` gives no blocks or
    /// the matrix is not positive definite: the caller falls back on
    /// conjugate gradients.
    #[allow(clippy::too_many_arguments)]
    pub fn solve(
        &mut self,
        sys: &dyn System,
        x: &[f64],
        v: &[f64],
        (a, b): (f64, f64),
        apply: impl FnMut(&[f64], &mut [f64]),
        rhs: &[f64],
        y: &mut [f64],
        tol: f64,
    ) -> bool {
        let n = rhs.len();
        if let Some(llt) = &self.factor {
            let precondition = |r: &[f64], z: &mut [f64]| {
                z.copy_from_slice(r);
                llt.solve_in_place(MatMut::from_column_major_slice_mut(z, n, 1));
            };
            self.cg
                .solve_with(apply, rhs, precondition, y, tol, LAGGED_ITERATIONS);
            if self.cg.converged && y.iter().all(|v| v.is_finite()) {
                return true;
            }
        }
        self.factor = self.factorize(sys, x, v, a, b, n);
        let Some(llt) = &self.factor else {
            return false;
        };
        y.copy_from_slice(rhs);
        llt.solve_in_place(MatMut::from_column_major_slice_mut(y, n, 1));
        y.iter().all(|v| v.is_finite())
    }

    /// The factorization of M + a·K + b·C at (x, v) over `n` degrees of
    /// freedom; `None` if `sys` gives no blocks or it is not positive definite.
    fn factorize(
        &mut self,
        sys: &dyn System,
        x: &[f64],
        v: &[f64],
        a: f64,
        b: f64,
        n: usize,
    ) -> Option<Llt<usize, f64>> {
        if !sys.jacobian_blocks(x, v, a, b, &mut self.blocks) {
            return None;
        }
        let inv_mass = sys.inv_mass();
        let current = |an: &(Analysis, usize, usize)| an.1 == self.blocks.len() && an.2 == n;
        if !self.analysis.as_ref().is_some_and(current) {
            let mut pattern = Vec::new();
            entries(&self.blocks, inv_mass, n, |row, col, _| {
                pattern.push(Pair::new(row, col))
            });
            self.analysis = analyse(n, &pattern).map(|an| (an, self.blocks.len(), n));
        }
        let (an, _, _) = self.analysis.as_ref()?;
        self.values.clear();
        entries(&self.blocks, inv_mass, n, |_, _, value| {
            self.values.push(value)
        });
        let matrix =
            SparseColMat::new_from_argsort(an.structure.clone(), &an.argsort, &self.values).ok()?;
        Llt::try_new_with_symbolic(an.symbolic.clone(), matrix.as_ref(), Side::Lower).ok()
    }
}

/// The sorted structure and the symbolic factorization of the pattern.
fn analyse(n: usize, pattern: &[Pair<usize, usize>]) -> Option<Analysis> {
    let (structure, argsort) = SymbolicSparseColMat::try_new_from_indices(n, n, pattern).ok()?;
    let symbolic = SymbolicLlt::try_new(structure.as_ref(), Side::Lower).ok()?;
    Some(Analysis {
        structure,
        argsort,
        symbolic,
    })
}
