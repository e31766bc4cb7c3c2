//! The work-precision plot: error against CPU time on log–log axes, one
//! curve per integrator, as PNG and SVG.

use crate::accuracy::{Run, Status};
use coupler::scenario::structure::Integrator;
use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;

/// Dark, distinct line colours (Okabe–Ito and Tableau), one per integrator.
const COLOURS: [RGBColor; 12] = [
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
    let mut integrators: Vec<Integrator> = Vec::new();
    for r in &done {
        if !integrators.contains(&r.integrator) {
            integrators.push(r.integrator);
        }
    }
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
