//! `monitors.png`: every run's report, each monitor of `monitors.csv`
//! against simulated time in a panel of its own, titled with its column
//! and its axes labelled with time [s] and the unit its participant
//! declared (`units.csv`), so that a person can look rather than read (the
//! designer's numbers of issue 23 among them).

use super::iterations::{register_font, FONT};
use plotters::prelude::*;
use std::path::Path;

/// Panels per row, and each panel's size in pixels.
const COLUMNS: usize = 4;
const PANEL: (u32, u32) = (320, 200);
/// Most panels drawn (the first monitors, in the file's order).
const MOST: usize = 64;
/// The summary's picture: its panels per row, each panel's size, and the
/// height of the text above them, in pixels.
const PAGE_COLUMNS: usize = 2;
const PAGE_PANEL: (u32, u32) = (560, 300);
const PAGE_HEAD: u32 = 170;
/// Most points drawn per monitor: longer runs are thinned evenly.
const POINTS: usize = 2000;

/// A monitor's name and values, one per row of `monitors.csv`.
type Column = (String, Vec<f64>);

/// Time and the monitors with a finite value, from `monitors.csv`.
fn read(csv: &Path) -> Option<(Vec<f64>, Vec<Column>)> {
    let text = std::fs::read_to_string(csv).ok()?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next()?.split(',').collect();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| {
            l.split(',')
                .map(|v| v.parse().unwrap_or(f64::NAN))
                .collect()
        })
        .filter(|r: &Vec<f64>| r.len() == header.len())
        .collect();
    let column = |i: usize| rows.iter().map(|r| r[i]).collect::<Vec<f64>>();
    let monitors = (1..header.len())
        .map(|i| (header[i].to_string(), column(i)))
        .filter(|(_, v)| v.iter().any(|x| x.is_finite()))
        .collect();
    Some((column(0), monitors))
}

/// Each column's unit, from `units.csv` (none for a column it lacks).
fn units(csv: &Path) -> std::collections::HashMap<String, String> {
    let text = std::fs::read_to_string(csv).unwrap_or_default();
    text.lines()
        .skip(1)
        .filter_map(|l| l.split_once(','))
        .map(|(c, u)| (c.to_string(), u.to_string()))
        .collect()
}

/// Write `monitors.png` in `run_dir` from its `monitors.csv`; nothing for a
/// run without rows.
pub fn write(run_dir: &Path) -> Result<(), Box<dyn std::error::Error>> {
    let Some((time, mut monitors)) = read(&run_dir.join("monitors.csv")) else {
        return Ok(());
    };
    monitors.truncate(MOST);
    let units = units(&run_dir.join(super::monitors::UNITS));
    if time.len() < 2 || monitors.is_empty() {
        return Ok(());
    }
    register_font();
    let rows = monitors.len().div_ceil(COLUMNS);
    let size = (PANEL.0 * COLUMNS as u32, PANEL.1 * rows as u32);
    let png = run_dir.join("monitors.png");
    let area = BitMapBackend::new(&png, size).into_drawing_area();
    area.fill(&WHITE)?;
    let step = time.len().div_ceil(POINTS).max(1);
    for (panel, (name, values)) in area.split_evenly((rows, COLUMNS)).iter().zip(&monitors) {
        let unit = units.get(name).map_or("", String::as_str);
        draw(panel, (name, unit), &time, values, step)?;
    }
    area.present()?;
    Ok(())
}

/// One monitor, its (name, unit), against time in `panel`, every
/// `step`-th row.
fn draw(
    panel: &DrawingArea<BitMapBackend, plotters::coord::Shift>,
    (name, unit): (&str, &str),
    time: &[f64],
    values: &[f64],
    step: usize,
) -> Result<(), Box<dyn std::error::Error>> {
    let points: Vec<(f64, f64)> = (0..time.len())
        .step_by(step)
        .filter(|&i| values[i].is_finite() && time[i].is_finite())
        .map(|i| (time[i], values[i]))
        .collect();
    let (t0, t1) = (time[0], time[time.len() - 1]);
    let ((lo, hi), clipped) = shown_range(&points, t0 + START_SHARE * (t1 - t0));
    // A constant monitor gets a band about its value.
    let pad = match (hi > lo, lo == 0.0) {
        (true, _) => 0.05 * (hi - lo),
        (false, true) => 1.0,
        (false, false) => 0.5 * lo.abs(),
    };
    let caption = match clipped {
        true => format!("{name} (its start off the scale)"),
        false => name.to_string(),
    };
    let mut chart = ChartBuilder::on(panel)
        .caption(caption, (FONT, 13))
        .margin(6)
        .x_label_area_size(32)
        .y_label_area_size(66)
        .build_cartesian_2d(t0..t1.max(t0 + 1e-300), (lo - pad)..(hi + pad))?;
    chart
        .configure_mesh()
        .x_labels(4)
        .y_labels(5)
        .label_style((FONT, 10))
        .axis_desc_style((FONT, 10))
        .x_desc("time [s]")
        .y_desc(match unit {
            "" => String::new(),
            u => format!("[{u}]"),
        })
        .y_label_formatter(&|v| match (1e-3..1e4).contains(&v.abs()) {
            true => format!("{v:.3}"),
            false => format!("{v:.2e}"),
        })
        .draw()?;
    chart.draw_series(LineSeries::new(points, BLUE.stroke_width(1)))?;
    Ok(())
}

/// The share of a run at its start whose values may run off a panel.
const START_SHARE: f64 = 0.1;
/// How many times the rest of a run's span the start may reach beyond it
/// before it runs off the panel.
const START_REACH: f64 = 10.0;

/// The range of `points` (time, value) a panel shows, and whether values
/// before `after` [s] run off it: they do where they reach more than
/// [`START_REACH`] times the span of the later values beyond those (a
/// ratio taken at rest, such as C_D0 = D/(q·S₀) before the payload has
/// speed, would flatten the rest of the run to a line).
fn shown_range(points: &[(f64, f64)], after: f64) -> ((f64, f64), bool) {
    let range = |it: &mut dyn Iterator<Item = f64>| {
        it.fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)))
    };
    let all = range(&mut points.iter().map(|p| p.1));
    let later = range(&mut points.iter().filter(|p| p.0 >= after).map(|p| p.1));
    let span = later.1 - later.0;
    let reach = (later.0 - all.0).max(all.1 - later.1);
    match span > 0.0 && reach > START_REACH * span {
        true => (later, true),
        false => (all, false),
    }
}

/// The summary's picture, `<summary name>.png` in `run_dir`: the run's
/// name and the summary's line, one clause a line, above the monitors of
/// `participant` the summary asked for, each against time with its unit
/// (those without a value left out); nothing when none has one.
pub fn summary_page(
    run_dir: &Path,
    participant: &str,
    summary: &participant::Summary,
) -> Result<(), Box<dyn std::error::Error>> {
    // The run's own pictures keep their names: no page overwrites them.
    if ["monitors", "iterations"].contains(&summary.name.as_str()) {
        eprintln!(
            "warning: summary `{}` names one of the run's own pictures: no page",
            summary.name
        );
        return Ok(());
    }
    let Some((time, monitors)) = read(&run_dir.join("monitors.csv")) else {
        return Ok(());
    };
    let wanted: Vec<String> = (summary.plots.iter())
        .map(|m| format!("{participant}.{m}"))
        .collect();
    let shown: Vec<&Column> = (wanted.iter())
        .filter_map(|w| monitors.iter().find(|(name, _)| name == w))
        .collect();
    if time.len() < 2 || shown.is_empty() {
        return Ok(());
    }
    register_font();
    let units = units(&run_dir.join(super::monitors::UNITS));
    let rows = shown.len().div_ceil(PAGE_COLUMNS);
    let size = (
        PAGE_PANEL.0 * PAGE_COLUMNS as u32,
        PAGE_HEAD + PAGE_PANEL.1 * rows as u32,
    );
    let png = run_dir.join(format!("{}.png", summary.name));
    let area = BitMapBackend::new(&png, size).into_drawing_area();
    area.fill(&WHITE)?;
    let (head, panels) = area.split_vertically(PAGE_HEAD);
    let run = run_dir
        .file_name()
        .map_or(String::new(), |n| n.to_string_lossy().to_string());
    head.draw_text(
        &format!("{run}: {}", summary.name),
        &(FONT, 24).into_text_style(&head),
        (16, 10),
    )?;
    for (i, clause) in summary.line.split(", ").enumerate() {
        let at = (24, 48 + 22 * i as i32);
        head.draw_text(clause, &(FONT, 17).into_text_style(&head), at)?;
    }
    let step = time.len().div_ceil(POINTS).max(1);
    for (panel, (name, values)) in panels.split_evenly((rows, PAGE_COLUMNS)).iter().zip(shown) {
        let unit = units.get(name).map_or("", String::as_str);
        draw(panel, (name, unit), &time, values, step)?;
    }
    area.present()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ratio_taken_at_rest_runs_off_the_panel_and_the_rest_fills_it() {
        // C_D0 = D/(q·S₀) of a payload released from rest: 90 at the
        // start, then between 0.3 and 0.5.
        let cd: Vec<(f64, f64)> = (0..100)
            .map(|i| {
                (
                    i as f64 * 0.03,
                    if i < 2 { 90.0 } else { 0.3 + 0.002 * i as f64 },
                )
            })
            .collect();
        let ((lo, hi), clipped) = shown_range(&cd, 0.3);
        assert!(clipped);
        assert_eq!((lo, hi), (0.3 + 0.002 * 10.0, 0.3 + 0.002 * 99.0));
        // A descent speed rising from 0 keeps its whole range.
        let v: Vec<(f64, f64)> = (0..100)
            .map(|i| (i as f64 * 0.03, (i as f64).min(30.0)))
            .collect();
        assert_eq!(shown_range(&v, 0.3), ((0.0, 30.0), false));
    }
}
