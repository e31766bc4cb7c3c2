//! The cell-centred operator A = −∇²ₕ of the pressure Poisson equation
//! (seed 000 eq. 3.19 after eliminating u^{n+1}): the 7-point stencil, a
//! Neumann side dropping its term (the ghost equals the cell), a Dirichlet
//! side φ = 0 on the face doubling it (the ghost is −φ_c). A is symmetric and
//! positive semi-definite; its null space is the constants when no side is
//! Dirichlet.

use crate::grid::{Bc, Grid, Neighbour};

/// What cell `c`'s equation holds along one axis direction: the neighbour's
/// coefficient and index, or only a term on the diagonal.
#[derive(Debug, Clone, Copy)]
pub enum Term {
    Off(usize, f64),
    Diagonal(f64),
    None,
}

pub fn term(g: &Grid, c: [usize; 3], d: usize, up: bool) -> Term {
    let w = 1.0 / (g.h[d] * g.h[d]);
    match g.neighbour(c, d, up) {
        Neighbour::Cell(m) if m == g.index(c) => Term::None,
        Neighbour::Cell(m) => Term::Off(m, w),
        Neighbour::Side(Bc::Dirichlet) => Term::Diagonal(2.0 * w),
        Neighbour::Side(_) => Term::None,
    }
}

/// The six terms of cell `c`'s row.
pub fn row(g: &Grid, c: [usize; 3]) -> [Term; 6] {
    let mut t = [Term::None; 6];
    for d in 0..3 {
        t[2 * d] = term(g, c, d, false);
        t[2 * d + 1] = term(g, c, d, true);
    }
    t
}

/// The diagonal of A in each cell.
pub fn diagonal(g: &Grid) -> Vec<f64> {
    (0..g.cells())
        .map(|i| {
            row(g, g.coords(i))
                .iter()
                .map(|t| match t {
                    Term::Off(_, w) | Term::Diagonal(w) => *w,
                    Term::None => 0.0,
                })
                .sum()
        })
        .collect()
}

/// out = A x.
pub fn apply(g: &Grid, x: &[f64], out: &mut [f64]) {
    for (i, o) in out.iter_mut().enumerate() {
        let mut s = 0.0;
        for t in row(g, g.coords(i)) {
            s += match t {
                Term::Off(m, w) => w * (x[i] - x[m]),
                Term::Diagonal(w) => w * x[i],
                Term::None => 0.0,
            };
        }
        *o = s;
    }
}
