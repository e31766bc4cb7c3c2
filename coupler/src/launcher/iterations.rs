//! What implicit coupling took, per window, gathered after a run from the
//! monitors the participant library adds (`participant::scheme::TRIES`…):
//! `iterations.csv` (window, time, tries, each accelerated field's last
//! relative residual, IQN-ILS columns used), `iterations.png` (tries and
//! residuals against the window), and the mean and largest tries for the
//! manifest. A failed run gets them too, up to its last whole row.

use participant::scheme::{COLUMNS, RESIDUAL, TRIES};
use plotters::prelude::*;
use std::path::Path;

pub struct Iterations {
    /// The accelerated fields, in the order of their residuals.
    fields: Vec<String>,
    rows: Vec<Row>,
}

struct Row {
    time: f64,
    tries: f64,
    residuals: Vec<f64>,
    /// Columns used, summed over the writers.
    columns: f64,
}

impl Iterations {
    /// From `monitors.csv`; None for an explicit run (no tries column) or
    /// one that ended before its first window.
    pub fn gather(monitors: &Path) -> Option<Iterations> {
        let text = std::fs::read_to_string(monitors).ok()?;
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next()?.split(',').collect();
        let ends = |h: &str, suffix: &str| h.ends_with(&format!(".{suffix}"));
        let tries = header.iter().position(|h| ends(h, TRIES))?;
        let marker = format!(".{RESIDUAL}");
        let residuals: Vec<(usize, String)> = (header.iter().enumerate())
            .filter_map(|(i, h)| {
                h.find(&marker)
                    .map(|at| (i, h[at + marker.len()..].to_string()))
            })
            .collect();
        let columns: Vec<usize> = (0..header.len())
            .filter(|&i| ends(header[i], COLUMNS))
            .collect();
        let rows: Vec<Row> = lines
            .skip(1)
            .filter_map(|line| {
                let v: Vec<f64> = line
                    .split(',')
                    .map(|x| x.parse().unwrap_or(f64::NAN))
                    .collect();
                (v.len() == header.len()).then(|| Row {
                    time: v[0],
                    tries: v[tries],
                    residuals: residuals.iter().map(|(i, _)| v[*i]).collect(),
                    columns: columns.iter().map(|&i| v[i]).sum(),
                })
            })
            .collect();
        (!rows.is_empty()).then(|| {
            let mut it = Iterations {
                fields: residuals.into_iter().map(|(_, f)| f).collect(),
                rows,
            };
            it.drop_unread_fields();
            it
        })
    }

    /// Leave out the fields whose residual is never measured: written by
    /// a participant but read by none in this run (the fluid's
    /// `body.loads` without rigid bodies).
    fn drop_unread_fields(&mut self) {
        let measured: Vec<usize> = (0..self.fields.len())
            .filter(|&f| self.rows.iter().any(|r| !r.residuals[f].is_nan()))
            .collect();
        let keep = |all: &[f64]| measured.iter().map(|&f| all[f]).collect();
        self.fields = measured.iter().map(|&f| self.fields[f].clone()).collect();
        for r in &mut self.rows {
            r.residuals = keep(&r.residuals);
        }
    }

    pub fn mean(&self) -> f64 {
        self.rows.iter().map(|r| r.tries).sum::<f64>() / self.rows.len() as f64
    }

    pub fn largest(&self) -> f64 {
        self.rows.iter().map(|r| r.tries).fold(0.0, f64::max)
    }

    /// The manifest's summary.
    pub fn summary(&self) -> serde_json::Value {
        serde_json::json!({
            "windows": self.rows.len(),
            "mean_iterations": self.mean(),
            "largest_iterations": self.largest(),
        })
    }

    /// `iterations.csv` and `iterations.png` into `dir`.
    pub fn write(&self, dir: &Path) -> Result<(), Box<dyn std::error::Error>> {
        let mut csv = String::from("window,time,iterations");
        for f in &self.fields {
            csv.push_str(&format!(",residual {f}"));
        }
        csv.push_str(",columns\n");
        for (w, r) in self.rows.iter().enumerate() {
            csv.push_str(&format!("{w},{},{}", r.time, r.tries));
            for x in &r.residuals {
                csv.push_str(&format!(",{x}"));
            }
            csv.push_str(&format!(",{}\n", r.columns));
        }
        std::fs::write(dir.join("iterations.csv"), csv)?;
        self.plot(&dir.join("iterations.png"))
    }

    /// Tries per window above, the last try's relative residual of each
    /// field below (log scale).
    fn plot(&self, png: &Path) -> Result<(), Box<dyn std::error::Error>> {
        register_font();
        let area = BitMapBackend::new(png, (1000, 700)).into_drawing_area();
        area.fill(&WHITE)?;
        let (top, bottom) = area.split_vertically(330);
        let n = self.rows.len() as f64;
        let most = self.largest().max(1.0) + 1.0;
        let mut chart = ChartBuilder::on(&top)
            .caption("implicit coupling: tries per window", (FONT, 20))
            .margin(12)
            .x_label_area_size(35)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..n, 0.0..most)?;
        chart
            .configure_mesh()
            .y_desc("tries")
            .label_style((FONT, 14))
            .axis_desc_style((FONT, 16))
            .draw()?;
        let tries = self
            .rows
            .iter()
            .enumerate()
            .map(|(w, r)| (w as f64, r.tries));
        chart.draw_series(LineSeries::new(tries, BLUE.stroke_width(2)))?;
        let positive = self.rows.iter().flat_map(|r| r.residuals.iter().copied());
        let (lo, hi) = positive
            .filter(|x| *x > 0.0 && x.is_finite())
            .fold((f64::MAX, f64::MIN), |(a, b), x| (a.min(x), b.max(x)));
        let (lo, hi) = if lo > hi {
            (1e-12, 1.0)
        } else {
            (lo / 2.0, hi * 2.0)
        };
        let mut chart = ChartBuilder::on(&bottom)
            .caption(
                "last try's relative residual, norm(r) / norm(x)",
                (FONT, 20),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..n, (lo..hi).log_scale())?;
        chart
            .configure_mesh()
            .x_desc("window")
            .label_style((FONT, 14))
            .axis_desc_style((FONT, 16))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()?;
        for (k, field) in self.fields.iter().enumerate() {
            let colour = Palette99::pick(k).to_rgba();
            let points = (self.rows.iter().enumerate())
                .filter(|(_, r)| r.residuals[k] > 0.0)
                .map(|(w, r)| (w as f64, r.residuals[k]));
            chart
                .draw_series(LineSeries::new(points, colour.stroke_width(2)))?
                .label(field.as_str())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour));
        }
        chart
            .configure_series_labels()
            .label_font((FONT, 14))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()?;
        area.present()?;
        Ok(())
    }
}

/// Family name the embedded font is registered under.
pub(super) const FONT: &str = "sans-serif";

pub(super) fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let _ = plotters::style::register_font(
            FONT,
            FontStyle::Normal,
            epaint_default_fonts::UBUNTU_LIGHT,
        );
    });
}
