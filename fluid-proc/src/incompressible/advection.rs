//! The advection term (u·∇)u of eq. (3.18) on the MAC grid, in flux form
//! ∇·(u u_c), which equals it for a solenoidal field and conserves momentum
//! discretely. Along each axis a, the flux of component c through the point
//! half-way between two of its faces is ū_a·û_c:
//! - ū_a, the advecting velocity there, is the average of the two nearest
//!   a-faces (second order);
//! - û_c, the advected value, is the upwind WENO5 reconstruction from the
//!   five faces on the side ū_a comes from (§3.2.1, `weno5.rs`).
//!
//! On a graded axis the averages and the reconstruction are taken in the
//! cells' index (the mapped grid's coordinate, second order where the widths
//! vary smoothly) and the difference of the fluxes divides by the control
//! length (`metric.rs`).

use crate::incompressible::metric::Metric;
use crate::incompressible::padded::Padded;
use crate::incompressible::rows;
use crate::weno5::reconstruct;

/// N_c = Σ_a ∂(u_a u_c)/∂x_a on the unknown faces of component `c`, written
/// to `out` (same layout as `u[c]`); `flux` is scratch of the same size.
/// `u` holds every component, ghosts filled (`None` for one that is zero
/// throughout: the z of a 2-D flow).
pub fn advection(
    u: &[Option<Padded>; 3],
    c: usize,
    metric: &Metric,
    flux: &mut [f64],
    out: &mut [f64],
) {
    let uc = u[c].as_ref().expect("an advected component exists");
    let lay = uc.lay;
    let unknown = lay.unknown_box();
    out.fill(0.0);
    for a in 0..3 {
        if lay.g[a] == 0 {
            continue;
        }
        let Some(ua) = u[a].as_ref() else { continue };
        let s = lay.stride[a];
        // The fluxes at the points half-way between face f and f + e_a, for
        // every unknown face f and the one below each.
        let mut range = unknown;
        range[a][0] -= 1;
        let d = &uc.data;
        rows::each(&lay, range, [&mut *flux], |row, [flux]| {
            for i in 0..row.len {
                let p = row.at + i;
                let mut f = row.first;
                f[0] += i as isize;
                let v = if a == c {
                    0.5 * (d[p] + d[p + s])
                } else {
                    // The a-face above f along a, on the two cells beside face f along c.
                    let mut q = f;
                    q[a] += 1;
                    let hi = ua.lay.at(q);
                    q[c] -= 1;
                    0.5 * (ua.data[hi] + ua.data[ua.lay.at(q)])
                };
                let value = if v >= 0.0 {
                    reconstruct([d[p - 2 * s], d[p - s], d[p], d[p + s], d[p + 2 * s]])
                } else {
                    reconstruct([d[p + 3 * s], d[p + 2 * s], d[p + s], d[p], d[p - s]])
                };
                flux[row.offset + i] = v * value;
            }
        });
        // 1/(control length) along a, per padded index (1/h if uniform).
        let inv = &metric.axes[a].inv_len;
        let flux = &*flux;
        rows::each(&lay, unknown, [&mut *out], |row, [out]| {
            let first = [0, 1, 2].map(|t| (row.first[t] + lay.g[t] as isize) as usize);
            for i in 0..row.len {
                let p = row.at + i;
                let k = first[a] + if a == 0 { i } else { 0 };
                out[row.offset + i] += (flux[p] - flux[p - s]) * inv[k];
            }
        });
    }
}
