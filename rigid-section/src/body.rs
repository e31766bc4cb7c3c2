//! The body and the shape a `[[rigid.bodies]]` entry describes, as every
//! solver sees them (the `exchange` crate): rigid-proc moves them, the
//! structure's nodes collide with them, the flow's markers follow them.

use crate::mesh::TriangleMesh;
use crate::{BodySpec, RigidSection, ShapeSpec};
use exchange::body::{Body, Start};
use exchange::Shape;
use nalgebra::Vector3;

impl BodySpec {
    /// The body at its start (mesh paths already absolute, as
    /// `RigidSection::resolve_meshes` leaves them): a shaped body's density
    /// is `density`, else `mass` over its volume. An error names the body.
    pub fn body(&self) -> Result<Body, String> {
        let shape = self.shape.as_ref().map(ShapeSpec::shape).transpose();
        let shape = shape.map_err(|e| format!("body `{}`: {e}", self.name))?;
        let start = Start {
            name: self.name.clone(),
            motion: self.motion,
            density: shape.as_ref().map_or(0.0, |s| self.density_of(s.volume())),
            point_mass: self.mass.unwrap_or(0.0),
            position: Vector3::from(self.position),
            rotation: self.rotation(),
            velocity: Vector3::from(self.velocity),
            angular_velocity: Vector3::from(self.angular_velocity),
            damping: self.linear_damping,
            release_time: self.release_time,
        };
        Ok(Body::new(start, shape))
    }
}

impl RigidSection {
    /// Every body at its start, in order.
    pub fn bodies(&self) -> Result<Vec<Body>, String> {
        self.bodies.iter().map(BodySpec::body).collect()
    }
}

impl ShapeSpec {
    /// The shape in the body's own frame; a mesh is read from its
    /// (absolute) file.
    pub fn shape(&self) -> Result<Shape, String> {
        Ok(match self {
            ShapeSpec::Sphere { radius } => Shape::sphere(*radius),
            ShapeSpec::Cuboid { size } => Shape::cuboid(*size),
            ShapeSpec::Cylinder { radius, height } => Shape::cylinder(*radius, *height),
            ShapeSpec::Mesh { file } => {
                let mesh = TriangleMesh::read_obj(file).map_err(|e| e.to_string())?;
                Shape::mesh(&mesh.vertices, &mesh.triangles)?
            }
        })
    }
}
