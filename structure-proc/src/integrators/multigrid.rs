//! The Newton step's linear system M + a·K + b·C solved by conjugate
//! gradients preconditioned with smoothed-aggregation algebraic multigrid
//! (Vaněk, Mandel & Brezina, Computing 56, 1996): a V-cycle costs a few
//! passes over the matrix, and the iterations it needs grow slowly with the
//! mesh (the guide's implicit bench, docs/src/structure-speed.md: 8 a solve on 529 nodes, 11 on
//! 50 176).
//!
//! The hierarchy: nodes are grouped into aggregates (a node and its
//! strongly coupled neighbours, greedily; Vaněk et al.'s ε = 0.08); the
//! tentative prolongator P₀ moves each aggregate's nodes together (the
//! three translations, the modes M + a·K barely resists), smoothed once by
//! block Jacobi, P = (I − ω/ρ·D⁻¹A)·P₀ with ω = 4/3 and ρ ≈ ρ(D⁻¹A) by
//! power iteration; the coarse matrix is Pᵀ·A·P, and so on down to at most
//! [`COARSEST`] nodes, solved by a dense Cholesky factorization. A V-cycle
//! smooths with block Gauss–Seidel, [`SWEEPS`] forward on the way down and
//! as many backward on the way up, so it is symmetric and positive
//! definite, as conjugate gradients need.
//!
//! Measured on the membrane cloth at 50 176 nodes (bench `implicit`, two
//! sweeps): power iteration instead of Gershgorin's bound (1.55× too
//! large, so the smoothing of P₀ was too weak) took the iterations a solve
//! from 16.5 to 13, and the strength threshold from 13 to 9 (all
//! neighbours made aggregates of 11 nodes and coarse spaces too poor). One
//! sweep instead of two costs more iterations (11) but less time from 10⁴
//! nodes up, and its iterations grow more slowly. Rotations beside the
//! translations in the coarse spaces (6 × 6 coarse blocks; branch
//! `multigrid-rigid-modes`) took a fifth of the iterations off but cost as
//! much in bigger coarse levels: 3 % slower at 50 176 nodes.
//!
//! As with the Cholesky solver, the hierarchy is kept from one Newton step
//! and time step to the next and built anew only when the iterations it
//! preconditions stall past [`LAGGED_ITERATIONS`].

use super::block_sparse::{Bsr, Bsr32, B3};
use super::cg::Cg;
use super::System;
use crate::forces::jacobian::Block;
use nalgebra::{DMatrix, Vector3};

/// Nodes of the coarsest level, solved directly.
pub const COARSEST: usize = 64;

/// The most nodes a level that stops coarsening may have to be solved
/// directly (a dense factorization of 1 200 unknowns); with more, the
/// Newton step falls back on the diagonal preconditioner.
const MOST_DENSE: usize = 400;

/// Iterations preconditioned by the kept hierarchy before it is built anew.
const LAGGED_ITERATIONS: u32 = 30;

/// Gauss–Seidel sweeps before and after each coarse correction.
const SWEEPS: usize = 1;

/// Vaněk et al.'s threshold ε: j is a strong neighbour of i where
/// ‖A_ij‖ > ε·√(‖A_ii‖·‖A_jj‖) (Frobenius norms of the blocks).
const STRENGTH: f64 = 0.08;

/// Power iterations for ρ(D⁻¹A), and the margin put on their estimate
/// (which approaches ρ from below).
const POWER_ITERATIONS: usize = 20;
const POWER_MARGIN: f64 = 1.05;

/// The prolongator smoothing's weight ω (over ρ(D⁻¹A)).
const OMEGA: f64 = 4.0 / 3.0;

#[derive(Default)]
pub struct Multigrid {
    blocks: Vec<Block>,
    /// Each node's blocks, for the block count and node count they were
    /// made for (a network's blocks come in a fixed order).
    by_row: Option<(Vec<Vec<usize>>, usize, usize)>,
    levels: Vec<Level>,
    coarse: Option<DenseCholesky>,
    cg: Cg,
    /// Conjugate-gradient iterations of the last solve, both tries together.
    pub iterations: u32,
}

/// A level's matrices, kept in f32 for the cycles (a preconditioner needs
/// no more; the products sum in f64 and the iterations stay f64).
struct Level {
    a: Bsr32,
    inverse_diagonal: Vec<B3>,
    /// To this level from the next coarser one, and its transpose.
    p: Bsr32,
    pt: Bsr32,
}

impl Multigrid {
    /// y ← (M + a·K + b·C)⁻¹·rhs at (x, v) over the free degrees of freedom
    /// (y = 0 on the others), `apply` being that matrix's product, by
    /// conjugate gradients to `tol` preconditioned with the kept hierarchy,
    /// or with a new one; `false` if `sys` gives no blocks or they do not
    /// converge in `max_iterations`: the caller falls back on the diagonal.
    #[allow(clippy::too_many_arguments)]
    pub fn solve(
        &mut self,
        sys: &dyn System,
        x: &[f64],
        v: &[f64],
        (a, b): (f64, f64),
        mut apply: impl FnMut(&[f64], &mut [f64]),
        rhs: &[f64],
        y: &mut [f64],
        tol: f64,
        max_iterations: u32,
    ) -> bool {
        self.iterations = 0;
        if !self.levels.is_empty() && self.solve_cg(&mut apply, rhs, y, tol, LAGGED_ITERATIONS) {
            return true;
        }
        if !self.build(sys, x, v, a, b) {
            return false;
        }
        self.solve_cg(&mut apply, rhs, y, tol, max_iterations)
    }

    fn solve_cg(
        &mut self,
        apply: &mut impl FnMut(&[f64], &mut [f64]),
        rhs: &[f64],
        y: &mut [f64],
        tol: f64,
        max_iterations: u32,
    ) -> bool {
        let (levels, coarse) = (&self.levels, &self.coarse);
        let precondition = |r: &[f64], z: &mut [f64]| vcycle(levels, coarse, 0, r, z);
        self.iterations += self
            .cg
            .solve_with(apply, rhs, precondition, y, tol, max_iterations);
        self.cg.converged && y.iter().all(|v| v.is_finite())
    }

    /// The hierarchy of M + a·K + b·C at (x, v); `false` if `sys` gives no
    /// blocks or the coarsest matrix is not positive definite.
    fn build(&mut self, sys: &dyn System, x: &[f64], v: &[f64], a: f64, b: f64) -> bool {
        if !sys.jacobian_blocks(x, v, a, b, &mut self.blocks) {
            return false;
        }
        let mut m = self.fine_matrix(sys.inv_mass());
        self.levels.clear();
        while m.rows > COARSEST {
            let (aggregate, count) = aggregates(&m);
            if count * 5 > m.rows * 4 {
                break; // too little coarsening to pay
            }
            let inverse_diagonal = m.diagonal_inverses();
            let p = prolongator(&m, &inverse_diagonal, &aggregate, count);
            let pt = p.transpose();
            let coarse = pt.mul(&m.mul(&p));
            let a = Bsr32::new(&std::mem::replace(&mut m, coarse));
            self.levels.push(Level {
                inverse_diagonal: a.diagonal_inverses(),
                a,
                p: Bsr32::new(&p),
                pt: Bsr32::new(&pt),
            });
        }
        if m.rows > MOST_DENSE {
            return false;
        }
        self.coarse = DenseCholesky::new(&m);
        let a = Bsr32::new(&m);
        self.levels.push(Level {
            inverse_diagonal: a.diagonal_inverses(),
            a,
            p: Bsr32::default(),
            pt: Bsr32::default(),
        });
        self.coarse.is_some()
    }

    /// M + a·K + b·C over the free nodes, the identity on held ones (1/m = 0).
    fn fine_matrix(&mut self, inv_mass: &[f64]) -> Bsr {
        let nodes = inv_mass.len();
        let current =
            |r: &(Vec<Vec<usize>>, usize, usize)| r.1 == self.blocks.len() && r.2 == nodes;
        if !self.by_row.as_ref().is_some_and(current) {
            let mut rows = vec![Vec::new(); nodes];
            for (k, &(i, _, _)) in self.blocks.iter().enumerate() {
                rows[i].push(k);
            }
            self.by_row = Some((rows, self.blocks.len(), nodes));
        }
        let (rows, _, _) = self.by_row.as_ref().expect("just made");
        let free = |n: usize| inv_mass[n] != 0.0;
        Bsr::from_rows(nodes, nodes, |i, row| {
            if !free(i) {
                return row.add(i, &B3::identity());
            }
            row.add(i, &(B3::identity() / inv_mass[i]));
            for &k in &rows[i] {
                let (_, j, s) = &self.blocks[k];
                if free(*j) {
                    row.add(*j, s);
                }
            }
        })
    }
}

/// Each node's aggregate and their count: first a node whose strong
/// neighbours are all free takes them; then a node left joins a strong
/// neighbour's aggregate; then what is left groups with its strong
/// neighbours left.
#[allow(clippy::needless_range_loop)] // i is a node: its row and its aggregate
fn aggregates(a: &Bsr) -> (Vec<usize>, usize) {
    const NONE: usize = usize::MAX;
    let n = a.rows;
    let (start, strong) = strong_neighbours(a);
    let neighbours = |i: usize| strong[start[i]..start[i + 1]].iter().copied();
    let mut agg = vec![NONE; n];
    let mut count = 0;
    for i in 0..n {
        if agg[i] == NONE && neighbours(i).all(|j| agg[j] == NONE) {
            agg[i] = count;
            for j in neighbours(i) {
                agg[j] = count;
            }
            count += 1;
        }
    }
    let first = agg.clone();
    for i in 0..n {
        if agg[i] == NONE {
            if let Some(j) = neighbours(i).find(|&j| first[j] != NONE) {
                agg[i] = first[j];
            }
        }
    }
    for i in 0..n {
        if agg[i] == NONE {
            agg[i] = count;
            for j in neighbours(i) {
                if agg[j] == NONE {
                    agg[j] = count;
                }
            }
            count += 1;
        }
    }
    (agg, count)
}

/// Each node's strong neighbours ([`STRENGTH`]), as compressed rows.
fn strong_neighbours(a: &Bsr) -> (Vec<usize>, Vec<usize>) {
    let diagonal: Vec<f64> = (0..a.rows)
        .map(|i| {
            a.row(i)
                .find(|&(j, _)| j == i)
                .map_or(0.0, |(_, b)| b.norm())
        })
        .collect();
    let (mut start, mut strong) = (vec![0], Vec::new());
    for i in 0..a.rows {
        let coupled = |&(j, b): &(usize, &B3)| {
            j != i && b.norm() > STRENGTH * (diagonal[i] * diagonal[j]).sqrt()
        };
        strong.extend(a.row(i).filter(coupled).map(|(j, _)| j));
        start.push(strong.len());
    }
    (start, strong)
}

/// P = (I − ω/ρ·D⁻¹A)·P₀, P₀ the identity block from each node to its
/// aggregate.
fn prolongator(a: &Bsr, inverse_diagonal: &[B3], agg: &[usize], count: usize) -> Bsr {
    let w = OMEGA / spectral_radius(a, inverse_diagonal);
    Bsr::from_rows(a.rows, count, |i, row| {
        row.add(agg[i], &B3::identity());
        for (j, b) in a.row(i) {
            row.add(agg[j], &(inverse_diagonal[i] * b * -w));
        }
    })
}

/// ρ(D⁻¹A) by power iteration from a fixed start, with a margin above the
/// estimate; at least 1, D⁻¹A's diagonal.
fn spectral_radius(a: &Bsr, inverse_diagonal: &[B3]) -> f64 {
    let norm = |v: &[f64]| v.iter().map(|e| e * e).sum::<f64>().sqrt();
    let mut x: Vec<f64> = (0..3 * a.rows)
        .map(|d| 1.0 + (d * 7919 % 13) as f64 / 13.0)
        .collect();
    let mut y = vec![0.0; x.len()];
    let mut estimate = 1.0;
    for _ in 0..POWER_ITERATIONS {
        for (i, yi) in y.chunks_exact_mut(3).enumerate() {
            let mut s = Vector3::zeros();
            for (j, b) in a.row(i) {
                s += b * Vector3::new(x[3 * j], x[3 * j + 1], x[3 * j + 2]);
            }
            yi.copy_from_slice((inverse_diagonal[i] * s).as_slice());
        }
        let (ny, nx) = (norm(&y), norm(&x));
        if ny.is_nan() || ny == 0.0 {
            break;
        }
        estimate = ny / nx;
        x.iter_mut().zip(&y).for_each(|(xi, yi)| *xi = yi / ny);
    }
    (POWER_MARGIN * estimate).max(1.0)
}

/// z ← one V-cycle from level `l` on r (z ≈ A⁻¹·r).
fn vcycle(levels: &[Level], coarse: &Option<DenseCholesky>, l: usize, r: &[f64], z: &mut [f64]) {
    let level = &levels[l];
    if l + 1 == levels.len() {
        return match coarse {
            Some(c) => c.solve(r, z),
            None => z.copy_from_slice(r),
        };
    }
    z.fill(0.0);
    for _ in 0..SWEEPS {
        gauss_seidel(level, r, z, false);
    }
    let mut residual = vec![0.0; r.len()];
    level.a.apply(z, &mut residual);
    for (e, ri) in residual.iter_mut().zip(r) {
        *e = ri - *e;
    }
    let mut rc = vec![0.0; 3 * level.pt.rows];
    level.pt.apply(&residual, &mut rc);
    let mut zc = vec![0.0; rc.len()];
    vcycle(levels, coarse, l + 1, &rc, &mut zc);
    level.p.apply(&zc, &mut residual);
    for (zi, c) in z.iter_mut().zip(&residual) {
        *zi += c;
    }
    for _ in 0..SWEEPS {
        gauss_seidel(level, r, z, true);
    }
}

/// One block Gauss–Seidel sweep on A·z = r, forward or backward.
fn gauss_seidel(level: &Level, r: &[f64], z: &mut [f64], backward: bool) {
    let a = &level.a;
    if backward {
        // Each row's blocks are read backwards too, so that the sweep
        // streams through memory in one direction, which the hardware
        // prefetchers follow (rows backwards, blocks forwards cost 5× once
        // the matrix is out of the cache).
        for i in (0..a.rows).rev() {
            relax(level, r, z, i, a.row(i).rev());
        }
    } else {
        for i in 0..a.rows {
            relax(level, r, z, i, a.row(i));
        }
    }
}

/// z_i ← D_i⁻¹·(r_i − Σ_{j≠i} A_ij·z_j), `row` being row i's blocks.
fn relax(
    level: &Level,
    r: &[f64],
    z: &mut [f64],
    i: usize,
    row: impl Iterator<Item = (usize, B3)>,
) {
    let mut s = Vector3::new(r[3 * i], r[3 * i + 1], r[3 * i + 2]);
    for (j, b) in row {
        if j != i {
            s -= b * Vector3::new(z[3 * j], z[3 * j + 1], z[3 * j + 2]);
        }
    }
    let zi = level.inverse_diagonal[i] * s;
    z[3 * i..3 * i + 3].copy_from_slice(zi.as_slice());
}

/// The coarsest level's Cholesky factor L (A = L·Lᵀ), dense.
struct DenseCholesky(nalgebra::Cholesky<f64, nalgebra::Dyn>);

impl DenseCholesky {
    /// `None` if `a` is not positive definite.
    fn new(a: &Bsr) -> Option<DenseCholesky> {
        let n = 3 * a.rows;
        let mut dense = DMatrix::zeros(n, n);
        for i in 0..a.rows {
            for (j, b) in a.row(i) {
                dense.view_mut((3 * i, 3 * j), (3, 3)).copy_from(b);
            }
        }
        // Pᵀ·A·P is symmetric up to round-off; factor its symmetric part.
        let sym = (&dense + dense.transpose()) * 0.5;
        sym.cholesky().map(DenseCholesky)
    }

    fn solve(&self, r: &[f64], z: &mut [f64]) {
        let x = self.0.solve(&nalgebra::DVector::from_column_slice(r));
        z.copy_from_slice(x.as_slice());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::forces::{Dynamics, Loads};
    use crate::integrators::newton::operator;

    fn norm(v: &[f64]) -> f64 {
        v.iter().map(|x| x * x).sum::<f64>().sqrt()
    }

    /// Backward Euler's Newton system M + h·C + h²·K on `cloth-hanging`'s
    /// membrane cloth at n × n nodes, 3 steps into its fall, solved to a
    /// relative residual of 10⁻⁸ (checked by the product): the iterations.
    fn iterations(n: u32) -> u32 {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../scenarios/cloth-hanging.toml"
        );
        let scene =
            structure_section::Scene::load_file(std::path::Path::new(path), "structure-proc")
                .expect("shipped scenario");
        let mut section = scene.structure;
        let cloth = section.cloth.as_mut().expect("cloth");
        (cloth.nodes_x, cloth.nodes_y) = (n, n);
        let dt = scene.scenario.coupling.window;
        let mut m = crate::build_model(&section, None, dt).expect("cloth builds");
        let mut stepper = crate::integrator(section.scheme());
        for _ in 0..3 {
            m.step(stepper.as_mut(), &Loads::default(), dt)
                .expect("step");
        }
        let loads = Loads::default();
        let sys = Dynamics {
            net: &m.net,
            loads: &loads,
        };
        let (x, v, (a, b)) = (&m.x, &m.v, (dt * dt, dt));
        let rhs: Vec<f64> = (0..x.len())
            .map(|d| match sys.inv_mass()[d / 3] {
                0.0 => 0.0,
                _ => ((d * 7919) % 101) as f64 - 50.0,
            })
            .collect();
        let mut y = vec![0.0; rhs.len()];
        let mut mg = Multigrid::default();
        let apply = operator(&sys, x, v, a, b);
        assert!(mg.solve(&sys, x, v, (a, b), apply, &rhs, &mut y, 1e-8, 500));
        let mut residual = vec![0.0; y.len()];
        operator(&sys, x, v, a, b)(&y, &mut residual);
        for (r, f) in residual.iter_mut().zip(&rhs) {
            *r -= f;
        }
        assert!(norm(&residual) <= 1e-8 * norm(&rhs), "{n} x {n}: residual");
        mg.iterations
    }

    /// Multigrid's promise (Vaněk, Mandel & Brezina 1996): iterations
    /// bounded independently of the mesh; with translations alone for the
    /// coarse spaces they may still grow, but no faster than log n, which
    /// is what a solve costing n log n (issue 25) allows: 16 times the
    /// nodes, at most ln(64²)/ln(16²) = 1.5 times the iterations.
    #[test]
    fn iterations_grow_no_faster_than_log_n() {
        let (coarse, fine) = (iterations(16), iterations(64));
        eprintln!("multigrid iterations: {coarse} on 16 x 16 nodes, {fine} on 64 x 64");
        let log_growth = (64.0f64 * 64.0).ln() / (16.0f64 * 16.0).ln();
        assert!(
            fine as f64 <= log_growth * coarse as f64,
            "{coarse} then {fine} iterations"
        );
    }
}
