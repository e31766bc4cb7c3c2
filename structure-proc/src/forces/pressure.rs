//! The pressure jump across the canopy, received from the fluid process: each
//! triangle pushes its three vertices with a third of jump·area·n.

use super::spring::point;
use nalgebra::Vector3;

/// (x1 − x0) × (x2 − x0): twice the area times the unit normal.
#[inline]
pub fn area_normal2(x: &[f64], tri: &[usize; 3]) -> [f64; 3] {
    let p0 = point(x, tri[0]);
    let n = (point(x, tri[1]) - p0).cross(&(point(x, tri[2]) - p0));
    [n[0], n[1], n[2]]
}

/// jump·area·n/3, the share of each vertex of `tri`; `jump` in Pa.
#[inline]
pub fn vertex_load(x: &[f64], tri: &[usize; 3], jump: f64) -> Vector3<f64> {
    if jump == 0.0 {
        return Vector3::zeros();
    }
    Vector3::from(area_normal2(x, tri)) * (jump / 6.0)
}
