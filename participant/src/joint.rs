//! One relaxation over the fields of several writers: in the parallel
//! scheme the quasi-Newton update acts on every exchanged field together
//! (Mehl, Uekermann et al., *Parallel coupling numerics for partitioned
//! fluid–structure interaction simulations*, 2016), while each writer
//! keeps its own fields, columns and values in its own memory.
//!
//! IQN-ILS's least-squares problem c = argmin ‖V c + r‖ over the stacked
//! rows of all writers needs only sums over rows: the Gram matrix VᵀV and
//! Vᵀr. Each writer computes its own part of them over its own rows (its
//! [`Share`], m² + m numbers for m columns, instead of its fields), the
//! writers exchange shares, each adds them in the run's participant order
//! and so solves the same small problem to the same bits, and relaxes its
//! own fields with its own W: x̃ = x + W c. The QR2 filter (Haelterman et
//! al. 2016) needs only inner products too: a column's part orthogonal
//! to the newer kept ones is what is left of its norm² after a Cholesky
//! step on the Gram matrix. Aitken's ω is a ratio of two sums the same way.
//! The inner product is scaled per field (`iqn_ils::Scale`).

/// One writer's part of a joint relaxation at one try.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Share {
    /// A writer that relaxes nothing in this run (none of its accelerated
    /// fields is read): its share counts for nothing.
    pub idle: bool,
    /// Whether this writer's fields all met their limits.
    pub converged: bool,
    /// Whether this writer had sent a value of the same layout before.
    pub comparable: bool,
    /// Columns m, the Gram matrix of the newest m (row-major) and Vᵀr.
    pub columns: usize,
    pub gram: Vec<f64>,
    pub against: Vec<f64>,
    /// Aitken's numerator r_{k−1}·(r_k − r_{k−1}) and denominator
    /// ‖r_k − r_{k−1}‖² over this writer's rows.
    pub num: f64,
    pub den: f64,
}

/// Values of a share before its matrix: flags, m, num, den.
const HEAD: usize = 6;

impl Share {
    /// The share of a writer that relaxes nothing.
    pub fn idle() -> Share {
        Share {
            idle: true,
            converged: true,
            comparable: true,
            ..Share::default()
        }
    }

    /// The share as the values of a field.
    pub fn to_values(&self) -> Vec<f64> {
        let flag = |b: bool| if b { 1.0 } else { 0.0 };
        let mut v = vec![
            flag(self.converged),
            flag(self.comparable),
            self.columns as f64,
            self.num,
            self.den,
            flag(self.idle),
        ];
        v.extend_from_slice(&self.gram);
        v.extend_from_slice(&self.against);
        v
    }

    /// A share read from another writer; None when the values do not make
    /// one (a participant that is not canopy's library).
    pub fn from_values(v: &[f64]) -> Option<Share> {
        let m = *v.get(2)? as usize;
        if v.len() != HEAD + m * m + m {
            return None;
        }
        Some(Share {
            converged: v[0] != 0.0,
            comparable: v[1] != 0.0,
            columns: m,
            num: v[3],
            den: v[4],
            idle: v[5] != 0.0,
            gram: v[HEAD..HEAD + m * m].to_vec(),
            against: v[HEAD + m * m..].to_vec(),
        })
    }

    /// The sum of `shares`, in their order: all converged, all comparable,
    /// over the newest columns that every writer has; idle shares left out.
    pub fn total(shares: &[Share]) -> Share {
        let shares: Vec<&Share> = shares.iter().filter(|s| !s.idle).collect();
        let m = shares.iter().map(|s| s.columns).min().unwrap_or(0);
        let mut t = Share {
            converged: true,
            comparable: true,
            columns: m,
            gram: vec![0.0; m * m],
            against: vec![0.0; m],
            num: 0.0,
            den: 0.0,
            idle: false,
        };
        for s in shares {
            t.converged &= s.converged;
            t.comparable &= s.comparable;
            t.num += s.num;
            t.den += s.den;
            for i in 0..m {
                t.against[i] += s.against[i];
                for j in 0..m {
                    t.gram[i * m + j] += s.gram[i * s.columns + j];
                }
            }
        }
        t
    }

    /// IQN-ILS's coefficients from the summed share: the columns the QR2
    /// filter keeps (newest first) and c over them, c = −(V_KᵀV_K)⁻¹V_Kᵀr
    /// by the Cholesky factor L of V_KᵀV_K (L = Rᵀ of V_K = QR); None
    /// when no column is kept.
    pub fn coefficients(&self, filter: f64) -> Option<(Vec<usize>, Vec<f64>)> {
        let m = self.columns;
        let g = |i: usize, j: usize| self.gram[i * m + j];
        // Rows of L, row j holding L[j][0..=j] over the kept columns.
        let mut l: Vec<Vec<f64>> = Vec::new();
        let mut kept = Vec::new();
        for j in 0..m {
            let norm2 = g(j, j);
            // y = L⁻¹ G[K, j]: the column's components along the kept
            // columns' orthonormal basis.
            let mut y = Vec::with_capacity(kept.len() + 1);
            for (a, row) in l.iter().enumerate() {
                let s: f64 = (0..a).map(|b| row[b] * y[b]).sum();
                y.push((g(kept[a], j) - s) / row[a]);
            }
            let left2 = norm2 - y.iter().map(|y| y * y).sum::<f64>();
            if norm2 > 0.0 && left2 > filter * filter * norm2 {
                y.push(left2.sqrt());
                l.push(y);
                kept.push(j);
            }
        }
        if kept.is_empty() {
            return None;
        }
        // L z = −V_Kᵀr, then Lᵀ c = z.
        let k = kept.len();
        let mut z = vec![0.0; k];
        for a in 0..k {
            let s: f64 = (0..a).map(|b| l[a][b] * z[b]).sum();
            z[a] = (-self.against[kept[a]] - s) / l[a][a];
        }
        let mut c = vec![0.0; k];
        for a in (0..k).rev() {
            let s: f64 = (a + 1..k).map(|b| l[b][a] * c[b]).sum();
            c[a] = (z[a] - s) / l[a][a];
        }
        Some((kept, c))
    }

    /// Aitken's ω for the whole vector after `last` ω: the secant step on
    /// the summed products (Küttler & Wall 2008, eq. 44).
    pub fn aitken(&self, last: f64) -> f64 {
        match self.den > 0.0 {
            true => -last * self.num / self.den,
            false => last,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::iqn_ils::{Columns, Limits};

    /// Rows of V split between two writers give, once their shares are
    /// summed, the least-squares coefficients of the whole V: those of a
    /// QR decomposition of the stacked matrix (nalgebra) over the columns
    /// the filter keeps, to round-off.
    #[test]
    fn shares_of_split_rows_solve_the_least_squares_problem_of_all_rows() {
        let limits = Limits {
            reused_windows: 0,
            max_columns: 10,
            filter: 1e-2,
        };
        // Four columns of six rows; the last pushed nearly repeats the
        // first, so the filter drops the older of the two.
        let cols: [[f64; 6]; 4] = [
            [1.0, 0.5, -0.3, 2.0, 0.1, 0.0],
            [0.2, -1.0, 0.7, 0.4, 1.5, -0.6],
            [0.9, 0.3, 0.3, -1.2, 0.8, 0.25],
            [1.0, 0.5, -0.3, 2.0, 0.1, 1e-3],
        ];
        let r = [0.3, -0.2, 0.5, 1.0, -0.7, 0.4];
        let (mut top, mut bottom) = (Columns::default(), Columns::default());
        for c in &cols {
            top.push(c[..2].to_vec(), c[..2].to_vec(), 0, limits);
            bottom.push(c[2..].to_vec(), c[2..].to_vec(), 0, limits);
        }
        let share = |c: &mut Columns, r: &[f64]| Share {
            columns: c.count(),
            gram: c.gram(),
            against: c.against(r),
            ..Share::default()
        };
        let total = Share::total(&[share(&mut top, &r[..2]), share(&mut bottom, &r[2..])]);
        let (kept, c) = total.coefficients(limits.filter).unwrap();
        assert_eq!(kept, vec![0, 1, 2], "the oldest column is dropped");
        let mut joint = top.combine(&kept, &c);
        joint.extend(bottom.combine(&kept, &c));
        // Newest first, as pushed: columns 3, 2, 1 of `cols`.
        let v = nalgebra::DMatrix::from_fn(6, 3, |i, j| cols[3 - j][i]);
        let rhs = nalgebra::DVector::from_iterator(6, r.iter().map(|x| -x));
        let qr = v.clone().qr();
        let c_qr = qr
            .r()
            .solve_upper_triangular(&(qr.q().transpose() * rhs))
            .unwrap();
        let step = v * c_qr;
        for (a, b) in joint.iter().zip(step.iter()) {
            assert!((a - b).abs() < 1e-12, "{joint:?} against {step:?}");
        }
    }

    #[test]
    fn a_share_survives_its_trip_as_field_values() {
        let s = Share {
            converged: true,
            comparable: true,
            columns: 2,
            gram: vec![1.0, 2.0, 2.0, 5.0],
            against: vec![0.5, -1.0],
            num: 0.25,
            den: 4.0,
            idle: false,
        };
        assert_eq!(Share::from_values(&s.to_values()), Some(s));
        assert_eq!(Share::from_values(&[1.0, 1.0, 3.0]), None);
        assert_eq!(
            Share::from_values(&Share::idle().to_values()),
            Some(Share::idle())
        );
    }
}
