//! `[rigid]`: the bodies rigid-proc moves (dissertation §2.1, §2.4, §3.1.1, §3.4):
//! mass points, or finite bodies with a shape whose mass, centre of mass and
//! inertia come from their geometry.

use exchange::Motion;
use mesh::TriangleMesh;
use nalgebra::{Rotation3, Vector3};
use scenario::{section, Checker, Problem, ScenarioError, Seg};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

mod attachments;
mod body;
pub mod mesh;
mod scene;

pub use attachments::{attachments, AttachmentSpec};
pub use scene::Scene;

/// Standard acceleration of gravity [m/s²] (3rd CGPM, 1901).
pub const STANDARD_GRAVITY: f64 = 9.80665;

/// Gravity pointing down −z, the default of every section that takes one.
pub fn default_gravity() -> [f64; 3] {
    [0.0, 0.0, -STANDARD_GRAVITY]
}

#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RigidSection {
    /// Gravitational acceleration [m/s²].
    #[serde(default = "default_gravity")]
    pub gravity: [f64; 3],
    /// Coefficient of restitution C_R of dissertation eq. (3.31) for contacts
    /// between bodies that do not give their own.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restitution: Option<f64>,
    pub bodies: Vec<BodySpec>,
}

#[derive(Debug, Clone, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    pub name: String,
    /// The body's geometry; left out, the body is a mass point.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shape: Option<ShapeSpec>,
    /// Mass [kg]. With a shape, give this or `density`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass: Option<f64>,
    /// Density [kg/m³] of a shaped body.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<f64>,
    /// Where the body's own frame starts [m]: a mass point's position, the
    /// centre of a sphere, cuboid or cylinder, a mesh's origin.
    pub position: [f64; 3],
    /// The body frame's initial rotation from the world axes, as a rotation
    /// vector (axis × angle) [rad].
    #[serde(default)]
    pub orientation: [f64; 3],
    /// Initial velocity of the centre of mass [m/s].
    #[serde(default)]
    pub velocity: [f64; 3],
    /// Initial angular velocity, in world axes [rad/s].
    #[serde(default)]
    pub angular_velocity: [f64; 3],
    #[serde(default)]
    pub motion: Motion,
    /// This body's C_R; a contact uses the mean of its two bodies' values.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restitution: Option<f64>,
    /// Linear viscous drag b [N·s/m]: force −b·v. For a pendulum of length L,
    /// b = c/L² gives the damping torque −c·θ̇ of thesis eq. (61).
    #[serde(default)]
    pub linear_damping: f64,
    /// A dynamic body held until this time [s]: it moves on at its
    /// `velocity` and `angular_velocity` whatever acts on it (as a
    /// prescribed one), then by its loads (a payload that holds its
    /// parachute until release).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub release_time: Option<f64>,
}

/// A body's geometry, in its own frame.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
pub enum ShapeSpec {
    Sphere {
        /// [m]
        radius: f64,
    },
    Cuboid {
        /// Edge lengths along the body's x, y and z axes [m].
        size: [f64; 3],
    },
    Cylinder {
        /// [m]
        radius: f64,
        /// Length along the body's z axis [m].
        height: f64,
    },
    /// A closed triangle mesh in a Wavefront OBJ file, relative to the scenario.
    Mesh { file: PathBuf },
}

impl ShapeSpec {
    /// The enclosed volume of an analytic shape [m³]; 0 for a mesh, which
    /// [`RigidSection::resolve_meshes`] weighs once it is read.
    fn analytic_volume(&self) -> f64 {
        use std::f64::consts::PI;
        match self {
            ShapeSpec::Sphere { radius } => 4.0 / 3.0 * PI * radius.powi(3),
            ShapeSpec::Cuboid { size } => size.iter().product(),
            ShapeSpec::Cylinder { radius, height } => PI * radius * radius * height,
            ShapeSpec::Mesh { .. } => 0.0,
        }
    }
}

impl BodySpec {
    /// The rotation from body axes to world axes at the start.
    pub fn rotation(&self) -> Rotation3<f64> {
        Rotation3::from_scaled_axis(Vector3::from(self.orientation))
    }

    /// World position at the start of a point given in the body's frame [m].
    pub fn world_point(&self, local: [f64; 3]) -> [f64; 3] {
        let p = Vector3::from(self.position) + self.rotation() * Vector3::from(local);
        p.into()
    }

    /// The density a shaped body has, from `density` or `mass` over its volume.
    pub fn density_of(&self, volume: f64) -> f64 {
        match (self.density, self.mass) {
            (Some(rho), _) => rho,
            (None, Some(m)) => m / volume,
            (None, None) => 0.0,
        }
    }
}

impl RigidSection {
    /// Body `i`'s C_R: its own value, else the scene's (0 if neither; the
    /// check demands one wherever two shaped bodies can touch).
    pub fn body_restitution(&self, i: usize) -> f64 {
        self.bodies[i]
            .restitution
            .or(self.restitution)
            .unwrap_or(0.0)
    }

    /// `[rigid]` of the scenario `text` (read from `path`), checked, with
    /// its mesh files read relative to the scenario's folder; None when the
    /// file has no `[rigid]` table.
    pub fn load(path: &Path, text: &str) -> Result<Option<RigidSection>, ScenarioError> {
        let Some(mut rigid) = section::read::<RigidSection>(path, text, "rigid")? else {
            return Ok(None);
        };
        section::checked(path, text, |c| rigid.check(c))?;
        let dir = path.parent().unwrap_or(Path::new("."));
        rigid.resolve_meshes(dir).map_err(|(i, e)| {
            let at = |k: &str| Seg::Key(k.into());
            let problem = Problem {
                path: vec![
                    at("rigid"),
                    at("bodies"),
                    Seg::Index(i),
                    at("shape"),
                    at("file"),
                ],
                message: e.to_string(),
            };
            ScenarioError::from_problem(path, text, problem)
        })?;
        Ok(Some(rigid))
    }

    /// Make mesh paths absolute (relative to `dir`, the scenario's folder) and
    /// read every mesh, so a bad one is reported before anything starts.
    /// Returns the index of the body and the mesh error on failure.
    pub fn resolve_meshes(
        &mut self,
        dir: &std::path::Path,
    ) -> Result<(), (usize, mesh::MeshError)> {
        for (i, b) in self.bodies.iter_mut().enumerate() {
            if let Some(ShapeSpec::Mesh { file }) = &mut b.shape {
                if file.is_relative() {
                    *file = dir.join(&*file);
                }
                let mesh = TriangleMesh::read_obj(file).map_err(|e| (i, e))?;
                let volume = mesh.volume();
                if b.density.is_none() && b.mass.is_some_and(|m| !(m / volume).is_finite()) {
                    return Err((
                        i,
                        mesh::MeshError {
                            file: file.clone(),
                            line: None,
                            message: format!("encloses too small a volume ({volume:e} m³)"),
                        },
                    ));
                }
            }
        }
        Ok(())
    }

    pub fn check(&self, c: &mut Checker) {
        c.within("rigid", None, |c| {
            c.finite3(&["gravity"], self.gravity);
            if let Some(r) = self.restitution {
                check_restitution(c, r);
            }
            if self.bodies.is_empty() {
                c.problem(&["bodies"], "lists no body".into());
            }
            let shaped = self.bodies.iter().filter(|b| b.shape.is_some()).count();
            for (i, b) in self.bodies.iter().enumerate() {
                c.within("bodies", Some(i), |c| {
                    c.plain_name(&["name"], &b.name, false);
                    if self.bodies[..i].iter().any(|o| o.name == b.name) {
                        c.problem(&["name"], format!("body name `{}` is used twice", b.name));
                    }
                    check_mass(c, b);
                    c.finite3(&["position"], b.position);
                    c.finite3(&["orientation"], b.orientation);
                    c.finite3(&["velocity"], b.velocity);
                    c.finite3(&["angular_velocity"], b.angular_velocity);
                    c.finite_nonneg(&["linear_damping"], b.linear_damping);
                    if let Some(t) = b.release_time {
                        c.finite_nonneg(&["release_time"], t);
                        if b.motion != Motion::Dynamic {
                            c.problem(
                                &["release_time"],
                                "release_time holds a dynamic body until then: this one \
                                 never moves by its loads"
                                    .into(),
                            );
                        }
                    }
                    match b.restitution {
                        Some(r) => check_restitution(c, r),
                        None if shaped >= 2 && b.shape.is_some() && self.restitution.is_none() => {
                            c.problem(
                                &["restitution"],
                                "bodies with shapes can touch: give their coefficient of \
                                 restitution here or as [rigid] restitution (C_R of dissertation eq. 3.31)"
                                    .into(),
                            )
                        }
                        None => {}
                    }
                    if b.shape.is_none() && b.angular_velocity != [0.0; 3] {
                        c.problem(
                            &["angular_velocity"],
                            "a mass point does not rotate: give the body a shape".into(),
                        );
                    }
                });
            }
        });
    }
}

/// The C_R of a contact between bodies whose own values are `a` and `b`: their mean.
pub fn pair_restitution(a: f64, b: f64) -> f64 {
    0.5 * (a + b)
}

pub fn check_restitution(c: &mut Checker, r: f64) {
    if !(0.0..=1.0).contains(&r) {
        c.problem(
            &["restitution"],
            format!("restitution = {r} must lie in [0, 1]"),
        );
    }
}

/// A mass point needs `mass`; a shaped body `mass` or `density`, not both,
/// and a shape with positive, finite sizes.
fn check_mass(c: &mut Checker, b: &BodySpec) {
    let Some(shape) = &b.shape else {
        if b.density.is_some() {
            c.problem(
                &["density"],
                "a mass point has no volume: give mass, or a shape".into(),
            );
        }
        match b.mass {
            Some(m) => c.positive(&["mass"], m, "kg"),
            None if b.motion == Motion::Dynamic => {
                c.problem(&["mass"], "a mass point needs its mass".into())
            }
            None => {}
        }
        return;
    };
    c.within("shape", None, |c| match shape {
        ShapeSpec::Sphere { radius } => c.positive(&["radius"], *radius, "m"),
        ShapeSpec::Cuboid { size } => {
            for s in size {
                c.positive(&["size"], *s, "m");
            }
        }
        ShapeSpec::Cylinder { radius, height } => {
            c.positive(&["radius"], *radius, "m");
            c.positive(&["height"], *height, "m");
        }
        ShapeSpec::Mesh { file } => {
            if file.as_os_str().is_empty() {
                c.problem(&["file"], "names no file".into());
            }
        }
    });
    match (b.mass, b.density) {
        (Some(m), None) => c.positive(&["mass"], m, "kg"),
        (None, Some(rho)) => c.positive(&["density"], rho, "kg/m³"),
        (None, None) if b.motion != Motion::Dynamic => {}
        _ => c.problem(
            &["mass"],
            "give exactly one of mass [kg] or density [kg/m³]".into(),
        ),
    }
    // Analytic shapes can be weighed now; a mesh is weighed once it is read.
    let volume = shape.analytic_volume();
    if volume > 0.0 && !b.density_of(volume).is_finite() {
        c.problem(&["mass"], "gives an infinite density for this shape".into());
    }
}
