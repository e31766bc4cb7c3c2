//! The pressure jump across the canopy, received from the fluid process or
//! given by the porous law of `[structure.porous]` (the `porous` crate): each
//! triangle pushes its three vertices with a third of jump·area·n.

use super::spring::point;
use nalgebra::{Matrix3, Vector3};
pub use porous::area_normal2;

/// jump·area·n/3, the share of each vertex of `tri`; `jump` in Pa.
#[inline]
pub fn vertex_load(x: &[f64], tri: &[usize; 3], jump: f64) -> Vector3<f64> {
    if jump == 0.0 {
        return Vector3::zeros();
    }
    Vector3::from(area_normal2(x, tri)) * (jump / 6.0)
}

/// (s·C)·p on each vertex of `tri` for the porous load's resistance to the
/// triangle's motion, C = −∂F/∂v = c·n·nᵀ on every vertex pair (see
/// [`porous::Porous::triangle_damping`]).
#[inline]
pub fn porous_damping_product(
    law: &porous::Porous,
    x: &[f64],
    v: &[f64],
    tri: &[usize; 3],
    s: f64,
    p: &[f64],
) -> Vector3<f64> {
    let (c, n) = law.triangle_damping(x, v, tri);
    if c == 0.0 {
        return Vector3::zeros();
    }
    let n = Vector3::from(n);
    let q: Vector3<f64> = tri.iter().map(|&j| point(p, j)).sum();
    n * (s * c * n.dot(&q))
}

/// The block s·c·n nᵀ of s·C that couples every vertex pair of `tri`
/// ([`porous_damping_product`] sums it over the three vertices' p).
#[inline]
pub fn porous_damping_block(
    law: &porous::Porous,
    x: &[f64],
    v: &[f64],
    tri: &[usize; 3],
    s: f64,
) -> Matrix3<f64> {
    let (c, n) = law.triangle_damping(x, v, tri);
    let n = Vector3::from(n);
    n * n.transpose() * (s * c)
}
