//! What each side of the flow box imposes on the velocity (dissertation §3.2.2,
//! the B(u*) of eq. 3.18), and what that means for the pressure correction.

use crate::incompressible::grid::Bc;

/// One side of the box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Side {
    /// The velocity on the side is given [m/s]: a no-slip wall (zero), a
    /// moving wall (a lid) or an inflow. φ has ∂φ/∂n = 0 there.
    Velocity([f64; 3]),
    /// A channel inflow: this peak velocity [m/s] times 4s(1 − s) across
    /// each direction along the side that is not periodic (`parabola`).
    Parabolic([f64; 3]),
    /// An outflow at p = 0: the velocity has no normal gradient.
    Outflow,
    /// Wraps to the opposite side, which must be periodic too.
    Periodic,
    /// Another rank's cells are beyond (a side of a slab, `part.rs`): its
    /// values are swapped in from there.
    Rank,
}

/// Poiseuille's profile 4s(1 − s) across a channel, s from 0 at one wall
/// to 1 at the other.
pub fn parabola(s: f64) -> f64 {
    4.0 * s * (1.0 - s)
}

/// The six sides: `sides[d] = [low, high]` along axis d.
pub type Sides = [[Side; 2]; 3];

impl Side {
    pub const WALL: Side = Side::Velocity([0.0; 3]);

    /// The velocity the side gives where its shape factor is `profile`
    /// (the product of `parabola` across it; 1 for a uniform side) [m/s].
    pub fn given(self, profile: f64) -> Option<[f64; 3]> {
        match self {
            Side::Velocity(v) => Some(v),
            Side::Parabolic(v) => Some(v.map(|v| v * profile)),
            _ => None,
        }
    }

    /// The condition on the pressure correction φ (eq. 3.19).
    pub fn bc(self) -> Bc {
        match self {
            Side::Velocity(_) | Side::Parabolic(_) => Bc::Neumann,
            Side::Outflow => Bc::Dirichlet,
            Side::Periodic => Bc::Periodic,
            Side::Rank => Bc::Rank,
        }
    }

    /// The same side with its given velocity set to zero: what the ghost
    /// values of a correction (a difference of two fields that both obey
    /// the sides) must obey.
    pub fn homogeneous(self) -> Side {
        match self {
            Side::Velocity(_) | Side::Parabolic(_) => Side::WALL,
            s => s,
        }
    }
}

/// The pressure sides of a box with these velocity sides.
pub fn bcs(sides: &Sides) -> [[Bc; 2]; 3] {
    sides.map(|s| s.map(Side::bc))
}
