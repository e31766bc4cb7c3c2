//! The exchanged fields, by name, and their layouts (docs/PROTOCOL.md,
//! "Fields"): the names are the interface, matched by the coupler from the
//! writer's declaration to its readers'. Each field is a flat `[f64]` of
//! items, every item the same number of values.
//!
//! | field | writer | items | values per item |
//! |---|---|---|---|
//! | `canopy.triangles` | structure, once | canopy triangles | [`TRIANGLE_LEN`]: vertex indices |
//! | `canopy.positions` | structure, each window | canopy vertices | [`VECTOR_LEN`] [m] |
//! | `canopy.velocities` | structure, each window | canopy vertices | [`VECTOR_LEN`] [m/s] |
//! | `canopy.pressure` | fluid, each window | canopy triangles | 1: jump [Pa] |
//! | `attachment.state` | rigid bodies, each sub-step | attachment points | [`ATTACHMENT_STATE_LEN`] |
//! | `attachment.impulse` | structure, each sub-step | attachment points | [`VECTOR_LEN`] [N·s] |
//! | `collision.bodies` | rigid bodies, each sub-step | bodies | [`STATE_LEN`] |
//! | `collision.impulse` | structure, each sub-step | bodies | [`MOMENTUM_LEN`] |
//! | `body.states` | rigid bodies, each window | bodies | [`STATE_LEN`] |
//! | `body.loads` | fluid, each window | bodies | [`LOAD_LEN`] |

/// Written once at the start: the vertex indices of each canopy triangle.
pub const CANOPY_TRIANGLES: &str = "canopy.triangles";
/// Written at the start and every window end: each canopy vertex [m].
pub const CANOPY_POSITIONS: &str = "canopy.positions";
/// As the positions [m/s].
pub const CANOPY_VELOCITIES: &str = "canopy.velocities";
/// Written every window by the fluid: the signed pressure jump across each
/// canopy triangle [Pa]; the load on a triangle is jump · area · n, n the
/// unit normal of its vertex order.
pub const CANOPY_PRESSURE: &str = "canopy.pressure";
/// Written every impulse sub-step by the rigid bodies: each attachment
/// point's position and velocity.
pub const ATTACHMENT_STATE: &str = "attachment.state";
/// Written every impulse sub-step by the structure: each attachment
/// point's impulse on its body [N·s].
pub const ATTACHMENT_IMPULSE: &str = "attachment.impulse";
/// Written every impulse sub-step by the rigid bodies: every body's state,
/// for the structure's collisions.
pub const COLLISION_BODIES: &str = "collision.bodies";
/// Written every impulse sub-step by the structure: the momentum its
/// collisions gave each body.
pub const COLLISION_IMPULSE: &str = "collision.impulse";
/// Written at the start and every window end by the rigid bodies: every
/// body's state, for the fluid.
pub const BODY_STATES: &str = "body.states";
/// Written every window by the fluid: its mean force and torque over the
/// window on each body.
pub const BODY_LOADS: &str = "body.loads";

/// Every field above, in the table's order.
pub const ALL: [&str; 10] = [
    CANOPY_TRIANGLES,
    CANOPY_POSITIONS,
    CANOPY_VELOCITIES,
    CANOPY_PRESSURE,
    ATTACHMENT_STATE,
    ATTACHMENT_IMPULSE,
    COLLISION_BODIES,
    COLLISION_IMPULSE,
    BODY_STATES,
    BODY_LOADS,
];

/// A vector's values: x, y, z.
pub const VECTOR_LEN: usize = 3;
/// A triangle's values: its three vertex indices (exact integers as f64),
/// counter-clockwise seen along its normal.
pub const TRIANGLE_LEN: usize = 3;
/// An attachment point's values: position [m], then velocity [m/s].
pub const ATTACHMENT_STATE_LEN: usize = 6;
/// A body's state: centre of mass x [m], velocity v [m/s], Euler parameters
/// e₀…e₃ (world → principal axes, dissertation eq. 3.5), angular velocity ω
/// in world axes [rad/s].
pub const STATE_LEN: usize = 13;
/// A momentum change given to a body: linear impulse [N·s], then angular
/// impulse about its centre of mass [N·m·s], world axes.
pub const MOMENTUM_LEN: usize = 6;
/// A load on a body: force [N], then torque about its centre of mass
/// [N·m], world axes.
pub const LOAD_LEN: usize = 6;

/// The fields exchanged at every impulse sub-step: with more than one a
/// window, they cannot be relaxed once a window.
pub const PER_IMPULSE: [&str; 4] = [
    ATTACHMENT_STATE,
    ATTACHMENT_IMPULSE,
    COLLISION_BODIES,
    COLLISION_IMPULSE,
];
