//! What a parachute designer reads (issue 23, item 4), every window: the
//! payload's altitude, descent and horizontal speed, the canopy's projected diameter,
//! apex height and tilt, the air's drag on the canopy and its coefficient
//! C_D0 = D/(½ρv²S₀) on the nominal area (Knacke, *Parachute Recovery
//! Systems Design Manual*, 1992, ch. 5), the lines' pull on the payload and
//! the largest line tension. The coupler's run report takes the opening
//! time and the peak opening force from them.

use crate::forces::spring::point;
use crate::model::Model;
use nalgebra::Vector3;
use participant::Monitor;

/// Angular sectors around the canopy's axis in which its widest reach is
/// taken for the projected diameter.
const SECTORS: usize = 36;

/// The monitors' names, `structure.parachute.<name>`; those of
/// [`AIR_MONITORS`] only where a fluid sends the canopy's pressure.
pub const PARACHUTE_MONITORS: [&str; 11] = [
    "parachute.altitude",
    "parachute.descent_speed",
    "parachute.horizontal_speed",
    "parachute.projected_diameter",
    "parachute.apex_height",
    "parachute.tilt",
    "parachute.drag",
    "parachute.drag_coefficient",
    "parachute.air_force_up",
    "parachute.payload_force",
    "parachute.line_tension_max",
];

/// The monitors of the air's force on the canopy.
const AIR_MONITORS: [&str; 3] = [
    "parachute.drag",
    "parachute.drag_coefficient",
    "parachute.air_force_up",
];

/// What the monitors need to know of a parachute beyond its nodes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParachuteParts {
    /// The confluence, where the payload hangs.
    pub hub: usize,
    /// The nominal area S₀ [m²].
    pub nominal_area: f64,
    /// The nominal diameter D₀ [m] (a cross: its span), for the filling
    /// constant n = t_f·v/D₀.
    pub nominal_diameter: f64,
    /// The air's density ρ [kg/m³] for C_D0; None without a fluid, which
    /// leaves the air's monitors out.
    pub air_density: Option<f64>,
}

impl ParachuteParts {
    /// ½ρS₀ [kg/m], what C_D0 divides the speed squared by; None without
    /// a fluid.
    pub fn dynamic_area(&self) -> Option<f64> {
        self.air_density.map(|rho| 0.5 * rho * self.nominal_area)
    }
}

impl Model {
    /// The designer's monitors, with the fluid's pressure jump per canopy
    /// triangle (`pressure`; the drag is NaN before the first). None for a model
    /// without a parachute.
    pub fn parachute_monitors(&self, pressure: Option<&[f64]>) -> Option<Vec<Monitor>> {
        let p = self.parachute?;
        let x = &self.x;
        let payload = point(x, p.hub);
        let velocity = point(&self.v, p.hub);
        let centroid = (0..self.canopy_nodes)
            .map(|n| point(x, n))
            .sum::<Vector3<f64>>()
            / self.canopy_nodes.max(1) as f64;
        // The canopy's axis, from the payload up through its centroid.
        let axis = (centroid - payload).normalize();
        let apex = self.vent.iter().map(|&n| point(x, n)).sum::<Vector3<f64>>()
            / self.vent.len().max(1) as f64;
        let speed = velocity.norm();
        // The air's force on the canopy (NaN before the first pressure),
        // and its part against the payload's motion.
        let force = pressure.map_or(Vector3::repeat(f64::NAN), |jump| self.canopy_force(jump));
        let drag = match speed > 0.0 {
            true => -force.dot(&velocity) / speed,
            false => force.z,
        };
        let values = [
            payload.z,
            -velocity.z,
            velocity.x.hypot(velocity.y),
            self.projected_diameter(&axis, &centroid),
            (apex - payload).dot(&axis),
            axis.z.clamp(-1.0, 1.0).acos().to_degrees(),
            drag,
            drag / (p.dynamic_area().unwrap_or(f64::NAN) * speed * speed),
            force.z,
            self.payload_force(p.hub).norm(),
            self.largest_line_tension(),
        ];
        let names = PARACHUTE_MONITORS.iter();
        let monitors = names.zip(values).map(|(n, v)| Monitor::new(*n, v));
        let aired =
            |m: &Monitor| p.air_density.is_some() || !AIR_MONITORS.contains(&m.name.as_str());
        Some(monitors.filter(aired).collect())
    }

    /// Σ jump·area·n over the canopy's triangles [N] (the load the
    /// structure takes, n the normal of the vertex order).
    fn canopy_force(&self, jump: &[f64]) -> Vector3<f64> {
        let x = &self.x;
        self.triangles
            .iter()
            .zip(jump)
            .map(|(t, j)| {
                let [a, b, c] = t.map(|n| point(x, n));
                (b - a).cross(&(c - a)) * (0.5 * j)
            })
            .sum()
    }

    /// The mean over sectors around `axis` of the canopy's widest reach
    /// from it, doubled [m]: the diameter of its projection on the plane
    /// across the axis.
    fn projected_diameter(&self, axis: &Vector3<f64>, centre: &Vector3<f64>) -> f64 {
        let u = axis
            .cross(&Vector3::x())
            .try_normalize(1e-9)
            .unwrap_or_else(|| axis.cross(&Vector3::y()).normalize());
        let w = axis.cross(&u);
        let mut reach = [0.0f64; SECTORS];
        for n in 0..self.canopy_nodes {
            let r = point(&self.x, n) - centre;
            let (a, b) = (r.dot(&u), r.dot(&w));
            let angle = b.atan2(a) + std::f64::consts::PI;
            let s = ((angle / std::f64::consts::TAU * SECTORS as f64) as usize).min(SECTORS - 1);
            reach[s] = reach[s].max(a.hypot(b));
        }
        let filled: Vec<f64> = reach.into_iter().filter(|r| *r > 0.0).collect();
        2.0 * filled.iter().sum::<f64>() / filled.len().max(1) as f64
    }

    /// The lines' pull on the confluence `hub` [N].
    fn payload_force(&self, hub: usize) -> Vector3<f64> {
        let x = &self.x;
        let pulls = self.lines.iter().flat_map(|l| &l.springs).map(|&s| {
            let s = &self.net.springs[s];
            match (s.i == hub, s.j == hub) {
                (true, _) => s.force(x),
                (_, true) => -s.force(x),
                _ => Vector3::zeros(),
            }
        });
        pulls.sum()
    }

    /// The largest tension in any suspension line's segment [N].
    fn largest_line_tension(&self) -> f64 {
        let lines = self.lines.iter().filter(|l| !l.reefing);
        let springs = lines.flat_map(|l| &l.springs);
        springs.fold(0.0, |most, &s| {
            most.max(self.net.springs[s].tension(&self.x))
        })
    }
}
