//! A parachute's opening and steady descent, summed up from the designer's
//! monitors of `monitors.csv` (`structure.parachute.*`, structure-proc's
//! `designer.rs`) at the end of a run: into `manifest.json` (`parachute`)
//! and one line on stderr.
//!
//! The steady descent is the run's last `STEADY` seconds: mean descent
//! speed, its spread (largest less smallest over the mean), mean drag
//! coefficient C_D0 and projected diameter D_p. The opening time is the
//! first time D_p reaches 95 % of that steady D_p from below; a canopy
//! released flat starts wider than it flies, so for one that never narrows
//! below 95 % it is the first time D_p comes within 5 % of it. The peak
//! opening force is the largest pull of the lines on the payload before
//! the steady part.

use serde_json::{json, Value};
use std::path::Path;

/// Seconds at the run's end taken as its steady descent (the issue's
/// "last 2 s"), or the run's last half when it is shorter than twice that.
pub const STEADY: f64 = 2.0;

const PREFIX: &str = "structure.parachute.";

/// What a run's parachute did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Opening {
    pub descent_speed: f64,
    /// (max − min)/mean of the descent speed over the steady part.
    pub speed_spread: f64,
    pub drag_coefficient: f64,
    pub projected_diameter: f64,
    /// None when D_p never comes near its steady value.
    pub opening_time: Option<f64>,
    pub peak_opening_force: f64,
    /// The steady part: from this time to the run's end [s].
    pub steady_from: f64,
}

impl Opening {
    /// From `monitors.csv`; None for a run without a parachute's monitors
    /// or with fewer than two rows in its steady part.
    pub fn read(csv: &Path) -> Option<Opening> {
        let text = std::fs::read_to_string(csv).ok()?;
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next()?.split(',').collect();
        let at = |name: &str| header.iter().position(|h| *h == format!("{PREFIX}{name}"));
        // Without a fluid process there is no drag: its column reads NaN.
        let columns = [
            0,
            at("descent_speed")?,
            at("drag_coefficient").unwrap_or(usize::MAX),
            at("projected_diameter")?,
            at("payload_force")?,
        ];
        let rows: Vec<[f64; 5]> = lines
            .map(|l| {
                l.split(',')
                    .map(|v| v.parse().unwrap_or(f64::NAN))
                    .collect::<Vec<f64>>()
            })
            .filter(|r| r.len() == header.len())
            .map(|r| columns.map(|c| r.get(c).copied().unwrap_or(f64::NAN)))
            .collect();
        Opening::of(&rows)
    }

    /// From rows of (time, descent speed, C_D0, D_p, payload force).
    fn of(rows: &[[f64; 5]]) -> Option<Opening> {
        let end = rows.last()?[0];
        let steady_from = (end - STEADY).max(0.5 * end);
        let steady: Vec<&[f64; 5]> = rows.iter().filter(|r| r[0] >= steady_from).collect();
        if steady.len() < 2 {
            return None;
        }
        let mean = |c: usize| steady.iter().map(|r| r[c]).sum::<f64>() / steady.len() as f64;
        let speed = mean(1);
        let (lo, hi) = steady
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| {
                (lo.min(r[1]), hi.max(r[1]))
            });
        let diameter = mean(3);
        let before = rows.iter().filter(|r| r[0] < steady_from);
        Some(Opening {
            descent_speed: speed,
            speed_spread: (hi - lo) / speed,
            drag_coefficient: mean(2),
            projected_diameter: diameter,
            opening_time: opening_time(rows, diameter),
            peak_opening_force: before.map(|r| r[4]).fold(0.0, f64::max),
            steady_from,
        })
    }

    pub fn to_json(&self) -> Value {
        json!({
            "steady_from": self.steady_from,
            "descent_speed": self.descent_speed,
            "descent_speed_spread": self.speed_spread,
            "drag_coefficient": self.drag_coefficient,
            "projected_diameter": self.projected_diameter,
            "opening_time": self.opening_time,
            "peak_opening_force": self.peak_opening_force,
        })
    }

    /// One line for a person.
    pub fn describe(&self) -> String {
        let opening = self
            .opening_time
            .map_or("not reached".into(), |t| format!("{t:.2} s"));
        let cd = match self.drag_coefficient.is_nan() {
            true => "no C_D0 (no fluid)".to_string(),
            false => format!("C_D0 {:.3}", self.drag_coefficient),
        };
        format!(
            "parachute: steady descent {:.3} m/s (spread {:.1} % after t = {:.2} s), {cd}, \
             projected diameter {:.2} m, opening time {opening}, peak opening force {:.0} N",
            self.descent_speed,
            100.0 * self.speed_spread,
            self.steady_from,
            self.projected_diameter,
            self.peak_opening_force
        )
    }
}

/// The first time the projected diameter reaches 95 % of `steady` from
/// below, or comes within 5 % of it when it never was below.
fn opening_time(rows: &[[f64; 5]], steady: f64) -> Option<f64> {
    let low = 0.95 * steady;
    let mut was_below = false;
    for r in rows {
        match r[3] < low {
            true => was_below = true,
            false if was_below => return Some(r[0]),
            false => {}
        }
    }
    rows.iter()
        .find(|r| (r[3] / steady - 1.0).abs() <= 0.05)
        .map(|r| r[0])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A canopy that narrows from 8 m to 4 m by t = 0.5 s, opens linearly
    /// to 6 m by t = 2 s and flies steady after: 95 % of 6 m, 5.7 m, is
    /// reached at 0.5 + 1.5·1.7/2 = 1.775 s, the row of 1.78 s.
    #[test]
    fn the_opening_time_is_the_first_reach_of_95_percent_from_below() {
        let rows: Vec<[f64; 5]> = (0..=500)
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
                [t, 6.0 + 0.03 * (t * 7.0).sin(), 0.8, d, force]
            })
            .collect();
        let o = Opening::of(&rows).unwrap();
        assert!((o.opening_time.unwrap() - 1.78).abs() < 1e-9, "{o:?}");
        assert_eq!(o.peak_opening_force, 3000.0);
        assert!((o.steady_from - 3.0).abs() < 1e-12);
        assert!((o.projected_diameter - 6.0).abs() < 1e-12);
        assert!(o.speed_spread < 0.06 / 6.0 + 1e-12 && o.speed_spread > 0.0);
    }
}
