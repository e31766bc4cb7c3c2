//! Mass properties from geometry (dissertation eqs. 2.5–2.7) against the
//! textbook formulas for a uniform solid.

use exchange::mass::MassProperties;
use exchange::Shape;
use nalgebra::Vector3;
use parry3d_f64::shape::Ball;
use rigid_section::mesh::TriangleMesh;
use rigid_section::ShapeSpec;
use std::f64::consts::PI;

fn of(spec: ShapeSpec, density: f64) -> MassProperties {
    MassProperties::of_shape(&spec.shape().unwrap(), density)
}

fn close(a: Vector3<f64>, b: Vector3<f64>, tol: f64) -> bool {
    (a - b).norm() <= tol * b.norm()
}

#[test]
fn sphere_cuboid_and_cylinder_match_their_formulas() {
    let rho = 700.0;
    // Sphere: m = ρ·4πr³/3, I = 2mr²/5 about every axis.
    let r = 0.3;
    let p = of(ShapeSpec::Sphere { radius: r }, rho);
    let m = rho * 4.0 / 3.0 * PI * r.powi(3);
    assert!((p.mass / m - 1.0).abs() < 1e-14);
    assert!(close(p.principal, Vector3::repeat(0.4 * m * r * r), 1e-14));
    // Cuboid a × b × c: I_x = m(b² + c²)/12 and cyclic; sorted ascending.
    let (a, b, c) = (0.4, 1.0, 0.7);
    let p = of(ShapeSpec::Cuboid { size: [a, b, c] }, rho);
    let m = rho * a * b * c;
    assert!((p.mass / m - 1.0).abs() < 1e-14);
    let ix = m * (b * b + c * c) / 12.0;
    let iy = m * (a * a + c * c) / 12.0;
    let iz = m * (a * a + b * b) / 12.0;
    assert!(
        close(p.principal, Vector3::new(iy, iz, ix), 1e-14),
        "{}",
        p.principal
    );
    // Its smallest moment is about y, the longest edge: Q's first column is ±y.
    assert!((p.axes.column(0).y.abs() - 1.0).abs() < 1e-14);
    assert!((p.axes.determinant() - 1.0).abs() < 1e-14);
    // Cylinder of radius r and height h along z: I_z = mr²/2, I_x = I_y = m(3r² + h²)/12.
    let (r, h) = (0.25, 1.8);
    let p = of(
        ShapeSpec::Cylinder {
            radius: r,
            height: h,
        },
        rho,
    );
    let m = rho * PI * r * r * h;
    assert!((p.mass / m - 1.0).abs() < 1e-14);
    let side = m * (3.0 * r * r + h * h) / 12.0;
    assert!(close(
        p.principal,
        Vector3::new(m * r * r / 2.0, side, side),
        1e-14
    ));
    // The axial (smallest) moment's axis is z, so parry's y-axis cylinder was turned.
    assert!((p.axes.column(0).z.abs() - 1.0).abs() < 1e-14);
    assert!(p.centre.norm() < 1e-15);
}

#[test]
fn a_meshed_sphere_approaches_the_sphere_at_second_order() {
    // The inscribed polyhedron's error falls as the square of the mesh size.
    let (r, rho) = (0.5, 1000.0);
    let exact = of(ShapeSpec::Sphere { radius: r }, rho);
    let error = |n: u32| {
        let (points, triangles) = Ball::new(r).to_trimesh(2 * n, n);
        let mesh = TriangleMesh {
            vertices: points.iter().map(|p| [p.x, p.y, p.z]).collect(),
            triangles,
        };
        let p =
            MassProperties::of_shape(&Shape::mesh(&mesh.vertices, &mesh.triangles).unwrap(), rho);
        let dm = (p.mass / exact.mass - 1.0).abs();
        let di = (p.principal - exact.principal).norm() / exact.principal.norm();
        assert!(p.centre.norm() < 1e-12 * r, "centre {}", p.centre);
        dm.max(di)
    };
    let errors: Vec<f64> = [8, 16, 32, 64].into_iter().map(error).collect();
    for pair in errors.windows(2) {
        let ratio = pair[0] / pair[1];
        assert!(
            (3.5..4.5).contains(&ratio),
            "errors {errors:?}: ratio {ratio}"
        );
    }
    assert!(errors[3] < 2e-3, "errors {errors:?}");
}

#[test]
fn an_obj_cube_weighs_as_the_cuboid_it_is() {
    // A unit cube off the origin, read from a file: same mass and moments as
    // the analytic cuboid, centre of mass at its middle.
    let dir = std::env::temp_dir().join(format!("canopy-mass-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("cube.obj");
    std::fs::write(
        &file,
        "# unit cube from (1,2,3)\nv 1 2 3\nv 2 2 3\nv 2 3 3\nv 1 3 3\nv 1 2 4\nv 2 2 4\nv 2 3 4\nv 1 3 4\n\
         f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n",
    )
    .unwrap();
    let mesh = of(ShapeSpec::Mesh { file }, 500.0);
    let cube = of(ShapeSpec::Cuboid { size: [1.0; 3] }, 500.0);
    assert!((mesh.mass - cube.mass).abs() < 1e-12);
    assert!(close(mesh.principal, cube.principal, 1e-12));
    assert!((mesh.centre - Vector3::new(1.5, 2.5, 3.5)).norm() < 1e-12);
    // Passed: nothing to look at (a failure leaves the file there).
    std::fs::remove_dir_all(&dir).unwrap();
}
