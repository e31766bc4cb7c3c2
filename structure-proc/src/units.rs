//! The SI unit of each monitor the structure reports: its declaration
//! gives them to the coupler, which writes them to `units.csv` and labels
//! the report's axes with them.

use crate::stability::OMEGA_MAX_MONITOR;

/// Monitor `name`'s unit ("1" for a ratio; empty for none known).
pub fn unit_of(name: &str) -> &'static str {
    match name {
        "kinetic_energy" | "potential_energy" => "J",
        "centre_deflection" => "m",
        OMEGA_MAX_MONITOR => "rad/s",
        "collision_impulses" => "impulses",
        "parachute.altitude" | "parachute.projected_diameter" | "parachute.apex_height" => "m",
        "parachute.descent_speed" | "parachute.horizontal_speed" => "m/s",
        "parachute.tilt" => "°",
        "parachute.drag_coefficient" => "1",
        "parachute.drag"
        | "parachute.air_force_up"
        | "parachute.payload_force"
        | "parachute.line_tension_max" => "N",
        n if n.starts_with("momentum.") => "kg·m/s",
        n if n.starts_with("collision_impulse.") => "N·s",
        "contact.impact_zone_steps" => "steps",
        n if n.starts_with("contact.") => "impulses",
        // A named point: its position and velocity.
        n if [".x", ".y", ".z"].iter().any(|s| n.ends_with(s)) => "m",
        n if [".vx", ".vy", ".vz"].iter().any(|s| n.ends_with(s)) => "m/s",
        _ => "",
    }
}
