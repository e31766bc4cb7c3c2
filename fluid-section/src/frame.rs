//! `[fluid.frame]`: a flow box that follows the parachute down (issue 23).
//!
//! The box moves with what it follows, so a descent of any length stays in
//! it: the air is solved in the box's frame, the structure and the bodies
//! stay in the ground's (fluid-proc's `frame.rs` says how and why).

use crate::flow::{SideSpec, SIDE_KEYS};
use scenario::Checker;
use serde::{Deserialize, Serialize};

/// What `follow` names for the canopy rather than a body.
pub const FOLLOW_CANOPY: &str = "canopy";

/// `[fluid.frame]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FrameSpec {
    /// `"canopy"` (the mean velocity of the canopy's vertices) or the name
    /// of a `[[rigid.bodies]]` entry (the payload).
    pub follow: String,
    /// The box's velocity at the start [m/s]: the followed body's initial
    /// velocity when left out, or zero for the canopy.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity: Option<[f64; 3]>,
    /// Altitude of the world's z = 0 above the ground [m]: the
    /// `frame_altitude` monitor adds it (0 when left out).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub altitude: Option<f64>,
}

impl FrameSpec {
    /// The frame's keys on their own, and what the box's `sides` must be
    /// for a box that moves: an outflow somewhere (the inflow changes with
    /// the frame's velocity, so only an outflow balances it) and no wall
    /// or parabolic side (walls do not travel with the parachute).
    pub fn check(&self, c: &mut Checker, sides: Option<[[SideSpec; 2]; 3]>) {
        c.within("frame", None, |c| {
            if self.follow != FOLLOW_CANOPY {
                c.plain_name(&["follow"], &self.follow, true);
            }
            if let Some(v) = self.velocity {
                c.finite3(&["velocity"], v);
            }
            if let Some(a) = self.altitude {
                if !a.is_finite() {
                    c.problem(&["altitude"], format!("altitude = {a} is not finite"));
                }
            }
            let Some(sides) = sides else { return };
            if !sides.iter().flatten().any(|s| *s == SideSpec::Outflow) {
                c.problem(
                    &["follow"],
                    "a box that follows the parachute needs an `outflow` side (the p = 0 \
                     top of the C-9 box): the inflow changes with the frame's velocity, \
                     and only an outflow lets out what it brings"
                        .into(),
                );
            }
            for (d, s) in (0..3).flat_map(|d| (0..2).map(move |s| (d, s))) {
                let what = match sides[d][s] {
                    SideSpec::Parabolic(_) => "parabolic, a channel's inflow,",
                    SideSpec::Wall => "a wall",
                    _ => continue,
                };
                c.problem(
                    &["follow"],
                    format!(
                        "[fluid.sides] {} is {what} and a box that follows the parachute has \
                         no walls: make it `periodic`, an `inflow` (the air's velocity over \
                         the ground, [0, 0, 0] for still air) or an `outflow`",
                        SIDE_KEYS[d][s]
                    ),
                );
            }
        });
    }

    /// The frame's velocity at the start [m/s], the followed body's
    /// `initial` velocity standing in for a `velocity` left out.
    pub fn start_velocity(&self, initial: Option<[f64; 3]>) -> [f64; 3] {
        self.velocity.or(initial).unwrap_or([0.0; 3])
    }

    pub fn altitude(&self) -> f64 {
        self.altitude.unwrap_or(0.0)
    }

    pub fn follows_canopy(&self) -> bool {
        self.follow == FOLLOW_CANOPY
    }
}
