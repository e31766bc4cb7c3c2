//! The plots, as PNG and SVG: the work-precision plot (error against CPU
//! time on log–log axes, one curve per integrator) and the stability map.

use crate::accuracy::{Run, Status};
use crate::stability::{predicted_omega_h, Cell, Chain, Limit, Outcome};
use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;
use structure_section::Integrator;

/// Dark, distinct line colours (Okabe–Ito and Tableau), one per integrator.
const COLOURS: [RGBColor; 13] = [
    RGBColor(0, 0, 0),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 158, 115),
    RGBColor(213, 94, 0),
    RGBColor(0, 114, 178),
    RGBColor(204, 121, 167),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(214, 39, 40),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Family name the embedded font is registered under.
const FONT: &str = "sans-serif";

/// Register the embedded font once, so the PNG renders its text on a machine
/// without fonts.
fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let _ = plotters::style::register_font(
            FONT,
            FontStyle::Normal,
            epaint_default_fonts::UBUNTU_LIGHT,
        );
    });
}

type Error = Box<dyn std::error::Error>;

/// Draws `runs` (only those that finished) into `png` and `svg`.
pub fn work_precision(runs: &[Run], title: &str, png: &Path, svg: &Path) -> Result<(), Error> {
    register_font();
    let size = (1100, 760);
    draw(
        runs,
        title,
        BitMapBackend::new(png, size).into_drawing_area(),
    )?;
    draw(runs, title, SVGBackend::new(svg, size).into_drawing_area())?;
    Ok(())
}

/// Range covering the positive values of `v`, widened to whole decades.
fn decades(v: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = v
        .filter(|x| *x > 0.0 && x.is_finite())
        .fold((f64::MAX, f64::MIN), |(a, b), x| (a.min(x), b.max(x)));
    if lo > hi {
        return 1e-3..1.0;
    }
    10f64.powf(lo.log10().floor())..10f64.powf(hi.log10().ceil().max(lo.log10().floor() + 1.0))
}

fn draw<B: DrawingBackend>(
    runs: &[Run],
    title: &str,
    area: DrawingArea<B, plotters::coord::Shift>,
) -> Result<(), Error>
where
    B::ErrorType: 'static,
{
    area.fill(&WHITE)?;
    let done: Vec<&Run> = runs
        .iter()
        .filter(|r| r.status == Status::Ok && r.error > 0.0)
        .collect();
    let x = decades(done.iter().map(|r| r.cpu_seconds));
    let y = decades(done.iter().map(|r| r.error));
    let mut chart = ChartBuilder::on(&area)
        .caption(title, (FONT, 24))
        .margin(16)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d(x.log_scale(), y.log_scale())?;
    chart
        .configure_mesh()
        .x_desc("CPU time per run [s]")
        .y_desc("error")
        .label_style((FONT, 16))
        .axis_desc_style((FONT, 18))
        .x_label_formatter(&|v| format!("{v:.0e}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()?;
    let integrators = crate::integrators_in(done.iter().map(|r| r.integrator));
    for (k, i) in integrators.iter().enumerate() {
        let colour = COLOURS[k % COLOURS.len()].to_rgba();
        let mut pts: Vec<(f64, f64)> = done
            .iter()
            .filter(|r| r.integrator == *i)
            .map(|r| (r.cpu_seconds, r.error))
            .collect();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        chart
            .draw_series(LineSeries::new(pts.clone(), colour.stroke_width(2)))?
            .label(i.name())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
            });
        chart.draw_series(pts.into_iter().map(|p| Circle::new(p, 3, colour.filled())))?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerLeft)
        .label_font((FONT, 15))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()?;
    area.present()?;
    Ok(())
}

/// Colours of the stability map's cells: stable, unstable, failed.
const STABLE: RGBColor = RGBColor(171, 221, 164);
const UNSTABLE: RGBColor = RGBColor(244, 165, 130);
const FAILED: RGBColor = RGBColor(200, 200, 200);

/// The stability map, one panel per integrator: stiffness k across, step h
/// up, each cell coloured by its outcome, with the predicted limit
/// y*/ω_max (black), the dissertation's ω_max·h = 0.1 (blue, dashed) and the
/// bisected limit (dots) over it.
pub fn stability_map(
    chain: &Chain,
    cells: &[Cell],
    limits: &[Limit],
    png: &Path,
    svg: &Path,
) -> Result<(), Error> {
    register_font();
    let integrators = crate::integrators_in(cells.iter().map(|c| c.integrator));
    let cols = integrators.len().clamp(1, 4);
    let rows = integrators.len().div_ceil(cols).max(1);
    let size = (380 * cols as u32, 340 * rows as u32 + 70);
    let grid = (rows, cols);
    let png = BitMapBackend::new(png, size).into_drawing_area();
    draw_map(chain, cells, limits, &integrators, grid, png)?;
    let svg = SVGBackend::new(svg, size).into_drawing_area();
    draw_map(chain, cells, limits, &integrators, grid, svg)?;
    Ok(())
}

/// Sorted distinct values of `v`.
fn distinct(v: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut out: Vec<f64> = v.collect();
    out.sort_by(f64::total_cmp);
    out.dedup();
    out
}

/// The stability map's title and legend.
fn draw_map_title<B: DrawingBackend>(
    head: &DrawingArea<B, plotters::coord::Shift>,
) -> Result<(), Error>
where
    B::ErrorType: 'static,
{
    head.titled(
        "Stability on a linear spring chain",
        (FONT, 22),
    )?
    .draw_text(
        &format!(
            "green: stable; red: unstable (non-finite, or energy > {} E0 after {} steps); grey: Newton failed; black line: predicted limit y*/w_max; blue dashed: the dissertation w_max h = 0.1; dots: bisected limit",
            crate::stability::GROWTH,
            crate::stability::STEPS
        ),
        &(FONT, 13).into_text_style(head),
        (10, 8),
    )?;
    Ok(())
}

/// Half a grid spacing in log, as a factor (1.5 for a single value).
fn half_step(grid: &[f64]) -> f64 {
    if grid.len() < 2 {
        1.5
    } else {
        (grid[1] / grid[0]).sqrt()
    }
}

fn draw_map<B: DrawingBackend>(
    chain: &Chain,
    cells: &[Cell],
    limits: &[Limit],
    integrators: &[Integrator],
    (rows, cols): (usize, usize),
    area: DrawingArea<B, plotters::coord::Shift>,
) -> Result<(), Error>
where
    B::ErrorType: 'static,
{
    area.fill(&WHITE)?;
    let (head, body) = area.split_vertically(70);
    draw_map_title(&head)?;
    let ks = distinct(cells.iter().map(|c| c.k));
    let dts = distinct(cells.iter().map(|c| c.dt));
    let (fk, fd) = (half_step(&ks), half_step(&dts));
    let k_range = ks[0] / fk..ks[ks.len() - 1] * fk;
    let dt_range = dts[0] / fd..dts[dts.len() - 1] * fd;
    for (panel, i) in body.split_evenly((rows, cols)).iter().zip(integrators) {
        let mut chart = ChartBuilder::on(panel)
            .caption(i.name(), (FONT, 17))
            .margin(8)
            .x_label_area_size(36)
            .y_label_area_size(56)
            .build_cartesian_2d(k_range.clone().log_scale(), dt_range.clone().log_scale())?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("k [N/m]")
            .y_desc("h [s]")
            .label_style((FONT, 12))
            .axis_desc_style((FONT, 13))
            .x_label_formatter(&|v| format!("{v:.0e}"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()?;
        chart.draw_series(cells.iter().filter(|c| c.integrator == *i).map(|c| {
            let colour = match c.outcome {
                Outcome::Stable(_) => STABLE,
                Outcome::Unstable { .. } => UNSTABLE,
                Outcome::Failed(_) => FAILED,
            };
            Rectangle::new(
                [(c.k / fk, c.dt / fd), (c.k * fk, c.dt * fd)],
                colour.filled(),
            )
        }))?;
        let line = |y: f64| -> Vec<(f64, f64)> {
            ks.iter().map(|&k| (k, y / chain.omega_max(k))).collect()
        };
        chart.draw_series(DashedLineSeries::new(
            line(structure_proc::stability::SEED_OMEGA_H),
            6,
            4,
            RGBColor(0, 90, 200).stroke_width(2),
        ))?;
        if let Some(y) = predicted_omega_h(*i) {
            chart.draw_series(LineSeries::new(line(y), BLACK.stroke_width(2)))?;
        }
        chart.draw_series(
            limits
                .iter()
                .filter(|l| l.integrator == *i)
                .filter_map(|l| Some((l.k, l.measured.filter(|h| *h > 0.0)?)))
                .map(|p| Circle::new(p, 3, BLACK.filled())),
        )?;
    }
    area.present()?;
    Ok(())
}
