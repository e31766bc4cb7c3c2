//! What a solver says of its whole run when it ends: named values the
//! coupler writes into the run's `manifest.json` under the name the solver
//! declared ([`crate::Declaration::summary`]), and one line it prints for
//! the person who ran it. The solver computes them from its own state; the
//! coupler reads no solver's monitors.

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
}

impl Summary {
    /// A summary `name` of `values` with its `line`.
    pub fn new(name: impl Into<String>, values: Vec<(String, f64)>, line: String) -> Summary {
        Summary {
            name: name.into(),
            values,
            line,
        }
    }
}
