//! The pressure jump across the canopy, received from the fluid process: each
//! triangle pushes its three vertices with a third of jump·area·n.

use super::spring::{add_to, point};

/// (x1 − x0) × (x2 − x0): twice the area times the unit normal.
#[inline]
pub fn area_normal2(x: &[f64], tri: &[usize; 3]) -> [f64; 3] {
    let p0 = point(x, tri[0]);
    let n = (point(x, tri[1]) - p0).cross(&(point(x, tri[2]) - p0));
    [n[0], n[1], n[2]]
}

/// Adds jump·area·n/3 to every vertex; `jump` holds one value per triangle [Pa].
pub fn add_pressure(triangles: &[[usize; 3]], jump: &[f64], x: &[f64], f: &mut [f64]) {
    for (tri, &p) in triangles.iter().zip(jump) {
        if p == 0.0 {
            continue;
        }
        let n2 = area_normal2(x, tri);
        let share = nalgebra::Vector3::from(n2) * (p / 6.0);
        for &node in tri {
            add_to(f, node, &share);
        }
    }
}
