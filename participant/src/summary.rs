//! What a solver says of its whole run when it ends: named values the
//! coupler writes into the run's `manifest.json` under the name the solver
//! declared ([`crate::Declaration::summary`]), and one line it prints for
//! the person who ran it, and the monitors to draw under that line on a
//! one-page picture. The solver computes them from its own state; the
//! coupler reads no solver's monitors but those it is told to draw.

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// The manifest key, as declared.
    pub name: String,
    /// Each value's name (with its unit, `descent_speed_m_s`, where it has
    /// one) and value; NaN where the run gave none (written as null).
    pub values: Vec<(String, f64)>,
    /// One line for a person, printed when the run ends.
    pub line: String,
    /// Monitors of this participant (declared names) to draw against time
    /// on a one-page picture of the run, `<name>.png`, with the line
    /// written above them; none: no picture.
    pub plots: Vec<String>,
}

impl Summary {
    /// A summary `name` of `values` with its `line`.
    pub fn new(name: impl Into<String>, values: Vec<(String, f64)>, line: String) -> Summary {
        Summary {
            name: name.into(),
            values,
            line,
            plots: Vec::new(),
        }
    }

    /// The summary with a picture: `monitors` against time under its line.
    pub fn plotting<S: Into<String>>(mut self, monitors: impl IntoIterator<Item = S>) -> Self {
        self.plots = monitors.into_iter().map(Into::into).collect();
        self
    }
}
