//! The cross-shaped T-11 canopy (dissertation table 5.2; the geometry is our
//! assumption, see docs/src/structure.md): a flat cross of five squares of side D₀/3.

use structure_proc::cross::cross_canopy;
use structure_section::parachute::ParachuteModel;

#[test]
fn t11_cross_is_a_valid_flat_cross_with_its_lines_on_the_arm_ends() {
    let g = ParachuteModel::T11.geometry().unwrap();
    for cells in [6, 8, 13] {
        let m = cross_canopy(&g, cells, 2.0).unwrap();
        let nodes = m.points.len() / 3;
        // Area of five squares of side a = D₀/3, exact for a flat grid.
        let a = g.diameter / 3.0;
        let mut area = 0.0;
        let mut edges = std::collections::BTreeSet::new();
        for t in &m.triangles {
            let n = structure_proc::forces::area_normal2(&m.points, t);
            assert!(n[2] > 0.0, "every triangle faces +z");
            area += 0.5 * n[2];
            for k in 0..3 {
                let (i, j) = (t[k], t[(k + 1) % 3]);
                edges.insert((i.min(j), i.max(j)));
            }
        }
        assert!((area / (5.0 * a * a) - 1.0).abs() < 1e-12, "area {area}");
        // A disc-like surface: Euler characteristic V − E + F = 1.
        assert_eq!(
            nodes as i64 - edges.len() as i64 + m.triangles.len() as i64,
            1
        );
        // 28 distinct lines, 7 on each arm end at |x| or |y| = 1.5 a.
        assert_eq!(m.skirt.len(), 28);
        let distinct: std::collections::BTreeSet<_> = m.skirt.iter().collect();
        assert_eq!(distinct.len(), 28);
        for &s in &m.skirt {
            let (x, y) = (m.points[3 * s], m.points[3 * s + 1]);
            let tip = x.abs().max(y.abs());
            assert!((tip - 1.5 * a).abs() < 1e-12 && x.abs().min(y.abs()) <= 0.5 * a + 1e-12);
        }
        // The farthest attachment is the arm-end corner the line check uses.
        let far = m
            .skirt
            .iter()
            .map(|&s| m.points[3 * s].hypot(m.points[3 * s + 1]))
            .fold(0.0, f64::max);
        assert!((far / g.skirt_radius() - 1.0).abs() < 1e-12);
    }
}
