//! The fields a structure participant exchanges, by name (docs/PROTOCOL.md,
//! "Fields"): the names are the interface, matched by the coupler to the
//! fluid's and the rigid bodies' declarations.

/// Written once at the start: 3 vertex indices per canopy triangle.
pub const CANOPY_TRIANGLES: &str = "canopy.triangles";
/// Written at the start and every window end: 3 per canopy vertex [m].
pub const CANOPY_POSITIONS: &str = "canopy.positions";
/// As the positions [m/s].
pub const CANOPY_VELOCITIES: &str = "canopy.velocities";
/// Read once a window: the pressure jump per canopy triangle [Pa].
pub const CANOPY_PRESSURE: &str = "canopy.pressure";
/// Read every step: each attachment point's position and velocity (6).
pub const ATTACHMENT_STATE: &str = "attachment.state";
/// Written every step: each attachment point's impulse [N·s] (3).
pub const ATTACHMENT_IMPULSE: &str = "attachment.impulse";
/// Read every step: the rigid bodies the nodes collide with (13 each).
pub const COLLISION_BODIES: &str = "collision.bodies";
/// Written every step: what the collisions gave each body (6 each).
pub const COLLISION_IMPULSE: &str = "collision.impulse";
