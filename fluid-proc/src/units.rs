//! The SI unit of each monitor the flow reports, for every model: its
//! declaration gives them to the coupler, which writes them to `units.csv`
//! and labels the report's axes with them.

/// Monitor `name`'s unit ("1" for a ratio; empty for none known).
pub fn unit_of(name: &str) -> &'static str {
    let ends = |suffix: &str| name.ends_with(suffix);
    match name {
        "kinetic_energy" | "energy" | "energy_in" => "J",
        "mass" | "mass_in" => "kg",
        "max_divergence" => "1/s",
        "steady_residual" => "m/s²",
        "courant" => "1",
        "pressure_iterations" | "viscous_iterations" => "iterations",
        "steps" => "steps",
        "min_density" => "kg/m³",
        "min_pressure" | "mean_pressure_jump" => "Pa",
        "frame_altitude" => "m",
        "frame_descent_speed" => "m/s",
        n if n.starts_with("momentum_") => "kg·m/s",
        // A probe's pressure and velocity; a body's forces.
        n if n.starts_with("probe_") && ends("_pressure") => "Pa",
        n if n.starts_with("probe_") => "m/s",
        _ if ["_x", "_y", "_z"].iter().any(|a| ends(a)) && name.contains("_force_") => "N",
        _ => "",
    }
}
