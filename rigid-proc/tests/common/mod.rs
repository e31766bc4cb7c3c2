//! Scenes the rigid-proc tests share.

/// A block and a ball on an oblique, off-centre course: they meet at about
/// 0.13 s (dissertation §3.4's rigid–rigid impact, with C_R = 1).
pub const IMPACT: &str = r#"
gravity = [0.0, 0.0, 0.0]
restitution = 1.0

[[bodies]]
name = "block"
shape = { type = "cuboid", size = [0.4, 0.2, 0.3] }
mass = 3.0
position = [0.0, 0.0, 0.0]
orientation = [0.0, 0.0, 0.5]
velocity = [1.0, 0.1, 0.0]
angular_velocity = [0.0, 0.0, 0.3]

[[bodies]]
name = "ball"
shape = { type = "sphere", radius = 0.1 }
mass = 1.0
position = [0.5, 0.12, 0.05]
velocity = [-0.5, 0.0, 0.0]
"#;
