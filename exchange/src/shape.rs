//! A body's geometry (dissertation §2.4: the parachutist or cargo as a finite
//! rigid body), held as a parry shape placed in the body's own frame.
//! Geometry stays apart from dynamics: this file knows nothing of motion.

use nalgebra::{Isometry3, Point3, Vector3};
use parry3d_f64::shape::{SharedShape, TriMeshFlags};
use std::f64::consts::FRAC_PI_2;

/// Segments around a sphere or cylinder when it is drawn.
const DRAW_SEGMENTS: u32 = 24;

/// A shape and where it sits in the body's own frame.
#[derive(Clone)]
pub struct Shape {
    pub shape: SharedShape,
    /// Own frame ← shape frame. parry's cylinders run along y; ours along z.
    pub placement: Isometry3<f64>,
}

impl Shape {
    /// A sphere of `radius` [m] about the own frame's origin.
    pub fn sphere(radius: f64) -> Shape {
        Shape::at_origin(SharedShape::ball(radius))
    }

    /// A box of edge lengths `size` along the own x, y and z axes [m],
    /// centred on the origin.
    pub fn cuboid(size: [f64; 3]) -> Shape {
        Shape::at_origin(SharedShape::cuboid(
            size[0] / 2.0,
            size[1] / 2.0,
            size[2] / 2.0,
        ))
    }

    /// A cylinder of `radius` and `height` [m] along the own z axis,
    /// centred on the origin.
    pub fn cylinder(radius: f64, height: f64) -> Shape {
        Shape {
            shape: SharedShape::cylinder(height / 2.0, radius),
            // A quarter turn about x takes parry's y axis to our z axis.
            placement: Isometry3::rotation(Vector3::x() * FRAC_PI_2),
        }
    }

    /// A closed triangle mesh, outward-wound (its reader has checked it
    /// closed and outward), in the own frame [m].
    pub fn mesh(vertices: &[[f64; 3]], triangles: &[[u32; 3]]) -> Result<Shape, String> {
        let vertices = vertices.iter().map(|v| Point3::from(*v)).collect();
        // ORIENTED lets point queries tell inside from outside by pseudo-normals.
        let shape =
            SharedShape::trimesh_with_flags(vertices, triangles.to_vec(), TriMeshFlags::ORIENTED)
                .map_err(|e| format!("parry refused the mesh: {e:?}"))?;
        Ok(Shape::at_origin(shape))
    }

    fn at_origin(shape: SharedShape) -> Shape {
        Shape {
            shape,
            placement: Isometry3::identity(),
        }
    }

    /// The enclosed volume [m³].
    pub fn volume(&self) -> f64 {
        self.shape.mass_properties(1.0).mass()
    }

    /// Radius of a sphere about the own frame's origin that holds the shape [m].
    pub fn bounding_radius(&self) -> f64 {
        let s = self.shape.compute_local_bounding_sphere();
        (self.placement * s.center).coords.norm() + s.radius
    }

    /// The radius of the circles a sphere or cylinder is drawn with (its
    /// own radius; the bounding sphere's for another shape) [m].
    pub fn drawn_radius(&self) -> f64 {
        if let Some(ball) = self.shape.as_ball() {
            return ball.radius;
        }
        match self.shape.as_cylinder() {
            Some(c) => c.radius,
            None => self.bounding_radius(),
        }
    }

    /// A closed triangulation of the surface in the own frame, for output.
    pub fn surface(&self) -> (Vec<Point3<f64>>, Vec<[u32; 3]>) {
        self.surface_with(DRAW_SEGMENTS)
    }

    /// A closed, outward-wound triangulation of the surface in the own
    /// frame, a sphere or cylinder drawn with `segments` around (at least
    /// 4); a cuboid's or mesh's own triangles.
    pub fn surface_with(&self, segments: u32) -> (Vec<Point3<f64>>, Vec<[u32; 3]>) {
        let segments = segments.max(4);
        let (points, triangles) = if let Some(b) = self.shape.as_ball() {
            b.to_trimesh(segments, segments / 2)
        } else if let Some(c) = self.shape.as_cuboid() {
            c.to_trimesh()
        } else if let Some(c) = self.shape.as_cylinder() {
            c.to_trimesh(segments)
        } else if let Some(m) = self.shape.as_trimesh() {
            (m.vertices().to_vec(), m.indices().to_vec())
        } else {
            (Vec::new(), Vec::new())
        };
        let placed = points.iter().map(|p| self.placement * p).collect();
        (placed, triangles)
    }
}
