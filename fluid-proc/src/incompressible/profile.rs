//! Velocity profiles along a line of faces, for comparison with tabulated
//! solutions (the cavity's centre lines, a channel's cross-section).

use crate::incompressible::Incompressible;

/// The lid-driven cavity at Re = 100, converged: u_min on the vertical
/// centre line, v_max and v_min on the horizontal one, in units of the lid
/// speed. Botella & Peyret, Comput. Fluids 27, 421–433 (1998), Chebyshev
/// spectral solution. The cavity test and the benchmark measure against it.
pub const CAVITY_RE100_EXTREMA: [f64; 3] = [-0.2140424, 0.1795728, -0.2538030];
use crate::incompressible::side::{parabola, Side};

/// Component `d` on the faces along axis `along` (≠ d) through face
/// `through` (its coordinate along `along` is ignored), as (position from
/// the box's low side, value) from side to side: the sides' values at 0 and
/// at the box length, the faces at the cell centres between. A side gives
/// its velocity, an outflow the nearest face's, a periodic side the mean of
/// the two end faces (the value on the wrap).
pub fn face_line(
    flow: &Incompressible,
    d: usize,
    along: usize,
    through: [usize; 3],
) -> Vec<(f64, f64)> {
    let g = flow.grid();
    let n = g.n[along];
    let axis = &g.axes[along];
    let mut m = g.n;
    m[d] += 1;
    let value = |k: usize| {
        let mut f = through;
        f[along] = k;
        flow.u.u[d][f[0] + m[0] * (f[1] + m[1] * f[2])]
    };
    let inside: Vec<(f64, f64)> = (0..n).map(|k| (axis.centre(k as i64), value(k))).collect();
    let side = |s: usize| match flow.setup.sides[along][s] {
        Side::Velocity(v) => v[d],
        Side::Parabolic(v) => {
            // The line's place across the side: faces of d at i·h, cells
            // elsewhere at (i + ½)·h.
            let sides = &flow.setup.sides;
            let across = (0..3).filter(|&t| t != along && sides[t][0] != Side::Periodic);
            let shape: f64 = across
                .map(|t| {
                    let a = &g.axes[t];
                    let i = through[t] as f64 + if t == d { 0.0 } else { 0.5 };
                    let x = match t == d {
                        true => a.face(through[t]),
                        false => a.centre(through[t] as i64),
                    };
                    // On a uniform axis the index's fraction, the same bits.
                    parabola(match a.is_uniform() {
                        true => i / g.n[t] as f64,
                        false => x / a.length(),
                    })
                })
                .product();
            v[d] * shape
        }
        Side::Outflow => inside[if s == 0 { 0 } else { n - 1 }].1,
        Side::Periodic => 0.5 * (inside[0].1 + inside[n - 1].1),
        Side::Rank => unreachable!("the box's own sides face no rank"),
    };
    let ends = (side(0), side(1));
    let mut line = vec![(0.0, ends.0)];
    line.extend(inside);
    line.push((axis.face(n), ends.1));
    line
}

/// The line's value at `s`, linear between its points.
pub fn value_at(line: &[(f64, f64)], s: f64) -> f64 {
    let k = line.partition_point(|p| p.0 <= s).clamp(1, line.len() - 1);
    let ((a, fa), (b, fb)) = (line[k - 1], line[k]);
    fa + (fb - fa) * (s - a) / (b - a)
}

/// The line's maximum (`sign` = 1) or minimum (−1) inside it, from the
/// parabola through the extreme point and its two neighbours (points
/// equally spaced, as the faces are away from the sides).
pub fn extremum(line: &[(f64, f64)], sign: f64) -> f64 {
    let k = (2..line.len() - 2)
        .max_by(|&a, &b| (sign * line[a].1).total_cmp(&(sign * line[b].1)))
        .expect("a line of at least five points");
    let (a, b, c) = (line[k - 1].1, line[k].1, line[k + 1].1);
    let curvature = a - 2.0 * b + c;
    if curvature == 0.0 {
        return b;
    }
    b - 0.125 * (c - a) * (c - a) / curvature
}
