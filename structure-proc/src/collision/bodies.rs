//! Free structure nodes against the rigid bodies' shapes: the point-against-
//! body tests of dissertation §3.4, each body one impact zone that takes the
//! reaction of every impulse it gives (§2.5).
//!
//! After each structure step, a node that ends closer to a body's surface
//! than `thickness`, or inside it, or that crossed the surface during the
//! step (a swept test from its start position, so thin bodies are not
//! tunnelled through) is put back `thickness` out along the surface normal.
//! If it still approaches, it gets the impulse along the normal
//! j = −(1 + C_R)·vₙ / (1/mᵢ + 1/m_b + n·((I_b⁻¹(r×n))×r)) — the dissertation's
//! eqs. (3.28) + (3.31) with the body's rotational terms, the same impulse
//! rigid–rigid contacts use — and the body gets −j at the contact point.
//!
//! The bodies are the rigid solver's at the start of the impulse sub-step.
//! Within it a body translates with its centre's velocity and keeps its
//! attitude (an angle error of |ω|·h); the nodes are tested in the body's
//! frame at the start, so a static body is exact. The momentum each body
//! received goes back to the rigid solver, which applies it at the start of
//! the same sub-step, so linear momentum is exchanged exactly.

use exchange::body::{self, Body};
use exchange::fields::{MOMENTUM_LEN, STATE_LEN};
use exchange::Motion;
use nalgebra::{Isometry3, Point3, Vector3};
use parry3d_f64::query::{PointProjection, Ray};
use parry3d_f64::shape::SharedShape;
use rigid_section::RigidSection;
use structure_section::Collision;

/// The bodies the structure's free nodes collide with.
pub struct Obstacles {
    /// Every body of `[rigid]`, in order; bodies without a shape take no part.
    pub bodies: Vec<Body>,
    /// Each body's motion in the scenario; a body held until its
    /// `release_time` moves as a prescribed one before it.
    motions: Vec<Motion>,
    thickness: f64,
    /// C_R of a node against each body: the body's own, else the collision default.
    restitution: Vec<f64>,
    /// Time since the start of the impulse sub-step [s].
    tau: f64,
    /// Linear then angular impulse given to each body in this impulse
    /// sub-step, [`MOMENTUM_LEN`] per body (world axes, about the centre).
    pub momenta: Vec<f64>,
    /// Node–body impulses given so far.
    pub impulses: u64,
    /// Their sum on the nodes so far [N·s]: the bodies' push on the structure.
    pub received: Vector3<f64>,
    /// Node positions at the start of the step, for the swept test.
    start: Vec<f64>,
}

/// Where a node meets a body, in the body's frame at the start of the sub-step.
struct Hit {
    point: Vector3<f64>,
    /// Unit outward normal of the surface there.
    normal: Vector3<f64>,
}

impl Obstacles {
    pub fn new(rigid: &RigidSection, spec: &Collision) -> Result<Obstacles, String> {
        let bodies = rigid.bodies()?;
        let mut o = Obstacles {
            momenta: vec![0.0; MOMENTUM_LEN * bodies.len()],
            motions: bodies.iter().map(|b| b.motion).collect(),
            bodies,
            thickness: spec.thickness,
            restitution: rigid
                .bodies
                .iter()
                .map(|b| b.restitution.unwrap_or(spec.restitution))
                .collect(),
            tau: 0.0,
            impulses: 0,
            received: Vector3::zeros(),
            start: Vec::new(),
        };
        o.hold(0.0);
        Ok(o)
    }

    /// Start the impulse sub-step at `time` [s] with the bodies' states as
    /// the rigid solver sends them ([`STATE_LEN`] per body); the momenta
    /// start from zero.
    pub fn set_states(&mut self, states: &[f64], time: f64) {
        for (b, s) in self.bodies.iter_mut().zip(states.chunks_exact(STATE_LEN)) {
            b.read_state(s);
        }
        self.hold(time);
        self.momenta.fill(0.0);
        self.tau = 0.0;
    }

    /// Each body's motion at `time`, as rigid-proc moves it: a held body
    /// has no inverse mass until its release.
    fn hold(&mut self, time: f64) {
        body::hold(&mut self.bodies, &self.motions, time);
    }

    /// Give body `b` the linear momentum `lin` and the angular momentum
    /// `ang` about its centre (world axes): its velocities change at once,
    /// and the rigid solver gets them with this sub-step's momenta.
    pub fn push(&mut self, b: usize, lin: &Vector3<f64>, ang: &Vector3<f64>) {
        self.bodies[b].apply_momentum(lin, ang);
        let m = &mut self.momenta[MOMENTUM_LEN * b..MOMENTUM_LEN * (b + 1)];
        for c in 0..3 {
            m[c] += lin[c];
            m[3 + c] += ang[c];
        }
    }

    /// Remember the positions `x` at the start of a structure step.
    pub fn begin_step(&mut self, x: &[f64]) {
        self.start.clear();
        self.start.extend_from_slice(x);
    }

    /// Resolve the contacts of the step of length `dt` that took the nodes
    /// from the positions given to [`Obstacles::begin_step`] to `x`, `v`.
    /// Nodes with `inv_mass` 0 (fixed, attached) take no part. Returns the
    /// number of impulses given.
    pub fn resolve(&mut self, x: &mut [f64], v: &mut [f64], inv_mass: &[f64], dt: f64) -> usize {
        let mut given = 0;
        for b in 0..self.bodies.len() {
            // Impulses change a body's velocities, not its pose: one frame
            // serves every node.
            let Some(frame) = Frame::of(&self.bodies[b], self.thickness) else {
                continue;
            };
            for (i, &w) in inv_mass.iter().enumerate() {
                if w > 0.0 {
                    given += self.node_against(b, &frame, i, x, v, w, dt) as usize;
                }
            }
        }
        self.tau += dt;
        self.impulses += given as u64;
        given
    }

    /// Node `i` against body `b`; true if it gave an impulse.
    #[allow(clippy::too_many_arguments)]
    fn node_against(
        &mut self,
        b: usize,
        frame: &Frame,
        i: usize,
        x: &mut [f64],
        v: &mut [f64],
        inv_m: f64,
        dt: f64,
    ) -> bool {
        let at = |a: &[f64]| Vector3::new(a[3 * i], a[3 * i + 1], a[3 * i + 2]);
        let body = &self.bodies[b];
        // The node's path relative to the body's pose at the sub-step start.
        let shift = body.state.v * self.tau;
        let q0 = at(&self.start) - shift;
        let q1 = at(x) - shift - body.state.v * dt;
        let Some(hit) = frame.hit(&q0, &q1, self.thickness) else {
            return false;
        };
        let end = hit.point + hit.normal * self.thickness;
        let placed = end + shift + body.state.v * dt;
        let vi = at(v);
        let vn = (vi - body.velocity_at(&hit.point)).dot(&hit.normal);
        let mut gave = false;
        let mut vi_new = vi;
        if vn < 0.0 {
            let k = inv_m + body.inv_effective_mass(&hit.point, &hit.normal);
            let j = hit.normal * (-(1.0 + self.restitution[b]) * vn / k);
            vi_new += j * inv_m;
            self.received += j;
            let r = hit.point - body.state.x;
            self.push(b, &-j, &r.cross(&-j));
            gave = true;
        }
        for c in 0..3 {
            x[3 * i + c] = placed[c];
            v[3 * i + c] = vi_new[c];
        }
        gave
    }
}

/// A shaped body's geometry at the start of the impulse sub-step.
struct Frame {
    shape: SharedShape,
    /// World ← shape frame.
    pose: Isometry3<f64>,
    /// The own frame's origin, centre of the bounding sphere.
    centre: Vector3<f64>,
    /// Bounding radius plus the layer [m].
    reach: f64,
}

impl Frame {
    fn of(body: &Body, thickness: f64) -> Option<Frame> {
        let shape = body.shape.as_ref()?;
        Some(Frame {
            shape: shape.shape.clone(),
            pose: body.shape_pose(),
            centre: body.own_pose().translation.vector,
            reach: shape.bounding_radius() + thickness,
        })
    }

    /// Whether the path `q0 → q1` (body frame at the sub-step start) crossed
    /// the surface, or ends inside or within `thickness` of it.
    fn hit(&self, q0: &Vector3<f64>, q1: &Vector3<f64>, thickness: f64) -> Option<Hit> {
        // Far from the bounding sphere all along the path: no contact.
        if distance_to_segment(&self.centre, q0, q1) > self.reach {
            return None;
        }
        let (shape, pose, centre) = (&self.shape, &self.pose, self.centre);
        // A path longer than the layer may have passed through the body:
        // the first crossing from outside wins.
        let path = q1 - q0;
        let start = Point3::from(*q0);
        if path.norm() > thickness && !surface_point(shape, pose, &start).is_inside {
            let ray = Ray::new(start, path);
            if let Some(toi) = shape.cast_ray_and_get_normal(pose, &ray, 1.0, false) {
                let mut normal = toi.normal.normalize();
                if normal.dot(&path) > 0.0 {
                    normal = -normal;
                }
                return Some(Hit {
                    point: ray.point_at(toi.time_of_impact).coords,
                    normal,
                });
            }
        }
        // Otherwise the end: inside, or within the layer.
        let end = Point3::from(*q1);
        let proj = surface_point(shape, pose, &end);
        let to_node = q1 - proj.point.coords;
        let d = to_node.norm();
        if !(proj.is_inside || d < thickness) {
            return None;
        }
        let outward = if proj.is_inside { -1.0 } else { 1.0 };
        let normal = if d > 0.0 {
            to_node * (outward / d)
        } else {
            // Exactly on the surface: the way out from the centre.
            (q1 - centre).normalize()
        };
        Some(Hit {
            point: proj.point.coords,
            normal,
        })
    }
}

/// The nearest surface point to `p` and whether `p` is inside. (parry's
/// feature query is the one that tells inside from outside for a mesh, by
/// its pseudo-normals; plain projection treats a mesh as a surface.)
fn surface_point(shape: &SharedShape, pose: &Isometry3<f64>, p: &Point3<f64>) -> PointProjection {
    shape.project_point_and_get_feature(pose, p).0
}

/// Distance from `p` to the segment `a → b`.
fn distance_to_segment(p: &Vector3<f64>, a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(&ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t - p).norm()
}

/// Segments around a sphere or cylinder when its surface is meshed for the
/// structure's contact pass: the chord sits 1 − cos(π/24) ≈ 0.9 % of the
/// radius inside the true surface, well inside the node–body layer for the
/// scenes' bodies.
const SURFACE_SEGMENTS: u32 = 24;

/// The shaped bodies' surfaces as the contact pass meets them: static
/// bodies' points fixed in the world, moving bodies' carried by them.
#[derive(Debug, Clone, Default)]
pub struct BodySurfaces {
    /// World positions (xyz) of every body's surface points, as the scene
    /// places the bodies.
    pub points: Vec<f64>,
    /// Their triangles, over node numbers from the `first` given.
    pub triangles: Vec<[usize; 3]>,
    /// Each body's points and true shape, static or moving.
    pub carried: Vec<Carried>,
}

/// A body's surface points: carried by the body if it moves, fixed in the
/// world if it is static.
#[derive(Debug, Clone)]
pub struct Carried {
    /// The body's place in `[rigid]`.
    pub body: usize,
    /// Whether the body moves (takes the reaction of the impulses it
    /// gives); a static body's points stay where the scene put them.
    pub moves: bool,
    /// The node number of its first point.
    pub first: usize,
    /// Its points in the body's own frame.
    pub own: Vec<Point3<f64>>,
    /// Its centre of mass as the scene places it.
    pub centre: Vector3<f64>,
    /// Its true shape, for the normal at a contact.
    pub shape: SharedShape,
    /// World ← shape frame as the scene places it.
    pub pose: Isometry3<f64>,
}

impl Carried {
    /// The body's surface point nearest to `p` and the unit outward normal
    /// there, the body posed by `pose`.
    pub fn surface_at(
        &self,
        pose: &Isometry3<f64>,
        p: &Vector3<f64>,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let proj = surface_point(&self.shape, pose, &Point3::from(*p));
        let out = (p - proj.point.coords) * if proj.is_inside { -1.0 } else { 1.0 };
        let normal = out
            .try_normalize(1e-300)
            .unwrap_or_else(|| (proj.point.coords - pose.translation.vector).normalize());
        (proj.point.coords, normal)
    }
}

/// The surfaces of `rigid`'s shaped bodies, their points numbered from
/// `first` on: the static ones', and the moving ones' too if `moving`.
pub fn surfaces(
    rigid: Option<&RigidSection>,
    first: usize,
    moving: bool,
) -> Result<BodySurfaces, String> {
    let mut out = BodySurfaces::default();
    for (index, spec) in rigid.iter().flat_map(|r| &r.bodies).enumerate() {
        if spec.shape.is_none() || (spec.motion != Motion::Static && !moving) {
            continue;
        }
        let body = spec.body()?;
        let Some(shape) = &body.shape else { continue };
        let (own, tris) = shape.surface_with(SURFACE_SEGMENTS);
        let base = first + out.points.len() / 3;
        let pose = body.own_pose();
        for p in &own {
            out.points.extend_from_slice((pose * p).coords.as_slice());
        }
        out.triangles
            .extend(tris.iter().map(|t| t.map(|k| base + k as usize)));
        out.carried.push(Carried {
            body: index,
            moves: spec.motion != Motion::Static,
            first: base,
            own,
            centre: body.state.x,
            shape: shape.shape.clone(),
            pose: body.shape_pose(),
        });
    }
    Ok(out)
}
