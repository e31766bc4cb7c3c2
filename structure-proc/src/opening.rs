//! A parachute's opening and steady descent, summed up at the end of a
//! run from the designer's monitors (`designer.rs`) at the start and at
//! every window end: into `manifest.json` (`parachute`) and one line on the
//! coupler's stderr, through the participant library's summary.
//!
//! The steady descent is the run's last `STEADY` seconds: mean descent
//! speed, its spread (largest less smallest over the mean), the mean
//! horizontal speed and the glide angle they make, C_D0 on the descent
//! (from the air's force up, the weight it carries) and on the flight path
//! (the drag against the motion), and the mean projected diameter D_p.
//! The opening time is the
//! first time D_p reaches 95 % of that steady D_p from below; a canopy
//! released flat starts wider than it flies, so for one that never narrows
//! below 95 % it is the first time D_p comes within 5 % of it. The peak
//! opening force is the largest pull of the lines on the payload before
//! the steady part. From the start's speed v (line stretch, for a packed
//! start) come the handbook's two numbers of an opening (Knacke 1992,
//! ch. 5): the opening-force coefficient C_x = F_peak/(½ρv²S₀C_D0) and the
//! filling constant n = t_f·v/D₀, t_f the opening time less the start's.

use crate::designer::ParachuteParts;
use participant::{Monitor, Summary};

/// The manifest key of the summary.
pub const SUMMARY: &str = "parachute";

/// The designer's monitors on the summary's picture, `parachute.png`
/// (those without a value, the air's without a fluid, are left out).
const PICTURE: [&str; 7] = [
    "parachute.descent_speed",
    "parachute.horizontal_speed",
    "parachute.projected_diameter",
    "parachute.drag",
    "parachute.drag_coefficient",
    "parachute.payload_force",
    "parachute.tilt",
];

/// One row of the record: the designer's monitors at one time.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Row {
    /// [s]
    pub time: f64,
    /// The payload's −v_z [m/s].
    pub descent_speed: f64,
    /// The payload's speed across the vertical [m/s].
    pub horizontal_speed: f64,
    /// C_D0 on the flight path: the drag against the payload's motion
    /// over ½ρ|v|²S₀ [1]; NaN without a fluid.
    pub drag_coefficient: f64,
    /// [m]
    pub projected_diameter: f64,
    /// The lines' pull on the payload [N].
    pub payload_force: f64,
    /// The air's force on the canopy along +z [N]; NaN without a fluid.
    pub air_force_up: f64,
}

impl Row {
    /// The row of `time` [s] from the designer's `monitors`; none for a
    /// model without them. Without a fluid, the air's values read NaN.
    fn of(time: f64, monitors: &[Monitor]) -> Option<Row> {
        let value = |name: &str| {
            let name = format!("parachute.{name}");
            monitors.iter().find(|m| m.name == name).map(|m| m.value)
        };
        let or_nan = |name: &str| value(name).unwrap_or(f64::NAN);
        Some(Row {
            time,
            descent_speed: value("descent_speed")?,
            horizontal_speed: or_nan("horizontal_speed"),
            drag_coefficient: or_nan("drag_coefficient"),
            projected_diameter: or_nan("projected_diameter"),
            payload_force: or_nan("payload_force"),
            air_force_up: or_nan("air_force_up"),
        })
    }
}

/// The rows the summary is taken from, at the start and at each window
/// end. A window taken again drops its rows with the checkpoint it
/// restarts from ([`Record::truncate`]); a run checkpoint keeps them all.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Record {
    pub rows: Vec<Row>,
    /// ½ρS₀ [kg/m], the air's density ρ times the nominal area S₀, halved:
    /// what C_D0 and C_x divide by; None without a fluid.
    pub dynamic_area: Option<f64>,
    /// D₀ [m], what the filling constant divides by.
    pub nominal_diameter: f64,
}

impl Record {
    /// An empty record for the parachute of `parts`.
    pub fn new(parts: &ParachuteParts) -> Record {
        Record {
            rows: Vec::new(),
            dynamic_area: parts.dynamic_area(),
            nominal_diameter: parts.nominal_diameter,
        }
    }

    /// Adds the row of `time` [s] from the designer's `monitors`; none for
    /// a model without them. Without a fluid, C_D0 reads NaN.
    pub fn add(&mut self, time: f64, monitors: &[Monitor]) {
        self.rows.extend(Row::of(time, monitors));
    }

    /// Back to its first `rows` rows.
    pub fn truncate(&mut self, rows: usize) {
        self.rows.truncate(rows);
    }

    /// The run's summary; None without a parachute's monitors or with
    /// fewer than two rows in its steady part.
    pub fn summary(&self) -> Option<Summary> {
        let reference = Reference {
            dynamic_area: self.dynamic_area.unwrap_or(f64::NAN),
            diameter: self.nominal_diameter,
        };
        let o = Opening::of(&self.rows, reference)?;
        Some(Summary::new(SUMMARY, o.values(), o.describe()).plotting(PICTURE))
    }
}

/// Seconds at the run's end taken as its steady descent (the issue's
/// "last 2 s"), or the run's last half when it is shorter than twice that.
pub const STEADY: f64 = 2.0;

/// What the coefficients refer to.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Reference {
    /// ½ρS₀ [kg/m]; NaN without a fluid.
    dynamic_area: f64,
    /// D₀ [m].
    diameter: f64,
}

/// What a run's parachute did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Opening {
    pub descent_speed: f64,
    /// (max − min)/mean of the descent speed over the steady part.
    pub speed_spread: f64,
    /// The mean speed across the vertical [m/s].
    pub horizontal_speed: f64,
    /// The flight path from the vertical, atan of the mean horizontal over
    /// the mean descent speed [°].
    pub glide_angle: f64,
    /// The mean C_D0 on the flight path (the drag against the motion).
    pub drag_coefficient: f64,
    /// C_D0 on the descent: the mean air force up over ½ρS₀ times the
    /// mean descent speed squared, the coefficient of the handbook's rate
    /// of descent v = √(2W/(ρS₀C_D0)) (Knacke 1992, ch. 5). In a steady
    /// descent the force up is the weight; gliding, the drag on the path
    /// is smaller by about cos³ of the glide angle.
    pub descent_drag_coefficient: f64,
    pub projected_diameter: f64,
    /// None when D_p never comes near its steady value.
    pub opening_time: Option<f64>,
    pub peak_opening_force: f64,
    /// When the peak came [s], and the payload's speed then [m/s]: what a
    /// finite-mass opening's peak is read at (Knacke 1992, ch. 5).
    pub peak_time: f64,
    pub speed_at_peak: f64,
    /// The payload's speed at the start [m/s]: at line stretch, for a
    /// packed start.
    pub start_speed: f64,
    /// The opening time less the start's [s]: the filling time t_f from
    /// line stretch, for a packed start.
    pub filling_time: f64,
    /// The opening-force coefficient C_x = F_peak/(q·S₀·C_D0), q = ½ρv²
    /// at the start's speed and C_D0 the steady one on the flight path
    /// (Knacke 1992, ch. 5: "infinite mass" when the speed holds).
    pub opening_force_coefficient: f64,
    /// The filling constant n = t_f·v/D₀ at the start's speed (Knacke
    /// 1992, ch. 5).
    pub filling_constant: f64,
    /// The steady part: from this time to the run's end [s].
    pub steady_from: f64,
}

impl Opening {
    /// From `rows`, the coefficients referred to `reference`.
    fn of(rows: &[Row], reference: Reference) -> Option<Opening> {
        let dynamic_area = reference.dynamic_area;
        let end = rows.last()?.time;
        let steady_from = (end - STEADY).max(0.5 * end);
        let steady: Vec<&Row> = rows.iter().filter(|r| r.time >= steady_from).collect();
        if steady.len() < 2 {
            return None;
        }
        let mean =
            |f: fn(&Row) -> f64| steady.iter().map(|r| f(r)).sum::<f64>() / steady.len() as f64;
        let speed = mean(|r| r.descent_speed);
        let (lo, hi) = steady
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| {
                (lo.min(r.descent_speed), hi.max(r.descent_speed))
            });
        let across = mean(|r| r.horizontal_speed);
        let diameter = mean(|r| r.projected_diameter);
        let before = rows.iter().filter(|r| r.time < steady_from);
        let measured = before.filter(|r| r.payload_force.is_finite());
        // The first row of the largest pull.
        let at_peak = measured.fold(None, |most: Option<&Row>, r| match most {
            Some(m) if m.payload_force >= r.payload_force => Some(m),
            _ => Some(r),
        });
        // No pull at all (nothing on the lines) is no peak: 0 N, at no time.
        let at_peak = at_peak.filter(|r| r.payload_force > 0.0);
        let peak = at_peak.map_or(0.0, |r| r.payload_force);
        let opening = opening_time(rows, diameter);
        let start = rows[0];
        // At rest at the start (NaN: no horizontal monitor), no C_x or n.
        let start_speed = start.descent_speed.hypot(start.horizontal_speed);
        let start_speed = if start_speed > 0.0 {
            start_speed
        } else {
            f64::NAN
        };
        let filling_time = opening.map_or(f64::NAN, |t| t - start.time);
        let on_path = mean(|r| r.drag_coefficient);
        Some(Opening {
            descent_speed: speed,
            speed_spread: (hi - lo) / speed,
            horizontal_speed: across,
            glide_angle: across.atan2(speed).to_degrees(),
            drag_coefficient: on_path,
            descent_drag_coefficient: mean(|r| r.air_force_up) / (dynamic_area * speed * speed),
            projected_diameter: diameter,
            opening_time: opening,
            peak_opening_force: peak,
            peak_time: at_peak.map_or(f64::NAN, |r| r.time),
            speed_at_peak: at_peak.map_or(f64::NAN, |r| r.descent_speed.hypot(r.horizontal_speed)),
            start_speed,
            filling_time,
            opening_force_coefficient: peak / (dynamic_area * start_speed.powi(2) * on_path),
            filling_constant: filling_time * start_speed / reference.diameter,
            steady_from,
        })
    }

    /// The values by name, as the manifest holds them: [s], [m/s], [1],
    /// [m/s], [°], [1], [1], [m], [s] (NaN: not reached), [N], [s], [m/s],
    /// [m/s], [s], [1], [1].
    fn values(&self) -> Vec<(String, f64)> {
        [
            ("steady_from", self.steady_from),
            ("descent_speed", self.descent_speed),
            ("descent_speed_spread", self.speed_spread),
            ("horizontal_speed", self.horizontal_speed),
            ("glide_angle", self.glide_angle),
            ("drag_coefficient", self.drag_coefficient),
            ("descent_drag_coefficient", self.descent_drag_coefficient),
            ("projected_diameter", self.projected_diameter),
            ("opening_time", self.opening_time.unwrap_or(f64::NAN)),
            ("peak_opening_force", self.peak_opening_force),
            ("peak_time", self.peak_time),
            ("speed_at_peak", self.speed_at_peak),
            ("start_speed", self.start_speed),
            ("filling_time", self.filling_time),
            ("opening_force_coefficient", self.opening_force_coefficient),
            ("filling_constant", self.filling_constant),
        ]
        .map(|(k, v)| (k.to_string(), v))
        .to_vec()
    }

    /// One line for a person.
    pub fn describe(&self) -> String {
        let opening = self
            .opening_time
            .map_or("not reached".into(), |t| format!("{t:.2} s"));
        let cd = match self.drag_coefficient.is_nan() {
            true => "no C_D0 (no fluid)".to_string(),
            false => format!(
                "C_D0 {:.3} on the descent, {:.3} on the flight path",
                self.descent_drag_coefficient, self.drag_coefficient
            ),
        };
        // Knacke's two numbers, where the run gives them.
        let handbook = match self.opening_force_coefficient.is_finite() {
            true => format!(
                " (C_x {:.2}, n {:.1} at the start's {:.1} m/s)",
                self.opening_force_coefficient, self.filling_constant, self.start_speed
            ),
            false => String::new(),
        };
        format!(
            "parachute: steady descent {:.3} m/s (spread {:.1} % after t = {:.2} s, gliding \
             {:.1}° from the vertical), {cd}, projected diameter {:.2} m, opening time \
             {opening}, peak opening force {:.0} N{handbook}",
            self.descent_speed,
            100.0 * self.speed_spread,
            self.steady_from,
            self.glide_angle,
            self.projected_diameter,
            self.peak_opening_force
        )
    }
}

/// The first time the projected diameter reaches 95 % of `steady` from
/// below, or comes within 5 % of it when it never was below.
fn opening_time(rows: &[Row], steady: f64) -> Option<f64> {
    let low = 0.95 * steady;
    let mut was_below = false;
    for r in rows {
        match r.projected_diameter < low {
            true => was_below = true,
            false if was_below => return Some(r.time),
            false => {}
        }
    }
    rows.iter()
        .find(|r| (r.projected_diameter / steady - 1.0).abs() <= 0.05)
        .map(|r| r.time)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A canopy that narrows from 8 m to 4 m by t = 0.5 s, opens linearly
    /// to 6 m by t = 2 s and flies steady after: 95 % of 6 m, 5.7 m, is
    /// reached at 0.5 + 1.5·1.7/2 = 1.775 s, the row of 1.78 s.
    #[test]
    fn the_opening_time_is_the_first_reach_of_95_percent_from_below() {
        let rows: Vec<Row> = (0..=500)
            .map(|i| {
                let t = i as f64 * 0.01;
                let d = match t {
                    t if t < 0.5 => 8.0 - 8.0 * t,
                    t if t < 2.0 => 4.0 + 2.0 * (t - 0.5) / 1.5,
                    _ => 6.0,
                };
                let force = if (t - 1.0).abs() < 1e-9 {
                    3000.0
                } else {
                    1000.0
                };
                Row {
                    time: t,
                    descent_speed: 6.0 + 0.03 * (t * 7.0).sin(),
                    drag_coefficient: 0.8,
                    projected_diameter: d,
                    payload_force: force,
                    ..Row::default()
                }
            })
            .collect();
        let none = Reference {
            dynamic_area: f64::NAN,
            diameter: 8.0,
        };
        let o = Opening::of(&rows, none).unwrap();
        assert!((o.opening_time.unwrap() - 1.78).abs() < 1e-9, "{o:?}");
        assert_eq!(o.peak_opening_force, 3000.0);
        // The peak's row: its time and the payload's speed then.
        assert!((o.peak_time - 1.0).abs() < 1e-12, "{o:?}");
        assert_eq!(o.speed_at_peak, 6.0 + 0.03 * (0.01f64 * 100.0 * 7.0).sin());
        assert!((o.steady_from - 3.0).abs() < 1e-12);
        assert!((o.projected_diameter - 6.0).abs() < 1e-12);
        assert!(o.speed_spread < 0.06 / 6.0 + 1e-12 && o.speed_spread > 0.0);
    }

    /// An infinite-mass opening from line stretch, made to Knacke's
    /// definitions (1992, ch. 5): held at 40 m/s, the projected diameter
    /// growing from a 0.4 m pack to 6 m by 0.5 s, the lines' pull peaking
    /// at 1.7·q·S₀·C_D0 at 0.4 s, C_D0 = 0.8 on the path. The filling time
    /// is the first row at 95 % of 6 m (5.7 m at 0.5·5.3/5.6 s, the row of
    /// 0.475 s), n = t_f·v/D₀, and C_x is the 1.7 put in.
    #[test]
    fn an_infinite_mass_opening_reads_the_handbooks_c_x_and_n() {
        let (v, s0, d0, rho) = (40.0, 57.2, 8.534, 1.225);
        let q = 0.5 * rho * v * v;
        let rows: Vec<Row> = (0..=600)
            .map(|i| {
                let t = i as f64 * 0.005;
                let peak = (t - 0.4).abs() < 1e-9;
                Row {
                    time: t,
                    descent_speed: v,
                    drag_coefficient: 0.8,
                    projected_diameter: 0.4 + 5.6 * (t / 0.5).min(1.0),
                    payload_force: if peak {
                        1.7 * q * s0 * 0.8
                    } else {
                        q * s0 * 0.8
                    },
                    ..Row::default()
                }
            })
            .collect();
        let reference = Reference {
            dynamic_area: 0.5 * rho * s0,
            diameter: d0,
        };
        let o = Opening::of(&rows, reference).unwrap();
        assert!((o.filling_time - 0.475).abs() < 1e-9, "{o:?}");
        assert!((o.filling_constant - 0.475 * v / d0).abs() < 1e-9, "{o:?}");
        assert!((o.opening_force_coefficient - 1.7).abs() < 1e-12, "{o:?}");
        assert!(o
            .describe()
            .contains("C_x 1.70, n 2.2 at the start's 40.0 m/s"));
    }

    /// A window taken again leaves no row of its discarded try: the record
    /// cut back to the checkpoint's length and the try's row added anew
    /// gives the rows of a run that took the window once; a model without
    /// the designer's monitors adds none.
    #[test]
    fn a_window_taken_again_leaves_no_row_of_its_first_try() {
        let row = |speed: f64| {
            [
                Monitor::new("parachute.descent_speed", speed),
                Monitor::new("parachute.projected_diameter", 6.0),
                Monitor::new("parachute.payload_force", 900.0),
            ]
        };
        let mut once = Record::default();
        let mut again = Record::default();
        for r in [&mut once, &mut again] {
            r.add(0.0, &row(0.0));
            r.add(1.0, &row(5.0));
        }
        let saved = again.rows.len();
        again.add(2.0, &row(99.0));
        again.truncate(saved);
        for r in [&mut once, &mut again] {
            r.add(2.0, &row(6.0));
        }
        let bits = |r: &Record| {
            let each = |w: &Row| {
                [
                    w.time,
                    w.descent_speed,
                    w.projected_diameter,
                    w.payload_force,
                ]
            };
            r.rows
                .iter()
                .flat_map(each)
                .map(|v| v.to_bits())
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(&again), bits(&once));
        // No fluid: C_D0 is NaN, and the summary says so (null in the manifest).
        assert!(once.rows[2].drag_coefficient.is_nan());
        let summary = once.summary().expect("two rows in the steady part");
        let cd = summary.values.iter().find(|(k, _)| k == "drag_coefficient");
        assert!(cd.is_some_and(|(_, v)| v.is_nan()), "{summary:?}");
        assert!(summary.line.contains("no C_D0"), "{}", summary.line);
        once.add(3.0, &[Monitor::new("kinetic_energy", 1.0)]);
        assert_eq!(once.rows.len(), 3);
    }
}
