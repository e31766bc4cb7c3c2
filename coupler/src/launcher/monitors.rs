//! `monitors.csv`: one row per coupling window with the total kinetic and
//! potential energy and every monitor the participants report, as `role.name`.

use crate::protocol::{Monitor, Role};
use std::collections::BTreeMap;
use std::io::{BufWriter, Write};
use std::path::Path;

pub struct Monitors {
    out: BufWriter<std::fs::File>,
    latest: BTreeMap<Role, Vec<Monitor>>,
    columns: Option<Vec<(Role, String)>>,
}

impl Monitors {
    pub fn create(path: &Path) -> std::io::Result<Monitors> {
        Ok(Monitors {
            out: BufWriter::new(std::fs::File::create(path)?),
            latest: BTreeMap::new(),
            columns: None,
        })
    }

    /// Keep the newest monitors of `role`; an empty list (mid-window replies) keeps the old ones.
    pub fn update(&mut self, role: Role, monitors: Vec<Monitor>) {
        if !monitors.is_empty() {
            self.latest.insert(role, monitors);
        }
    }

    /// Write one row at simulated `time`. The first row fixes the columns.
    pub fn row(&mut self, time: f64) -> std::io::Result<()> {
        if self.columns.is_none() {
            let cols: Vec<(Role, String)> = self
                .latest
                .iter()
                .flat_map(|(r, ms)| ms.iter().map(|m| (*r, m.name.clone())))
                .collect();
            let mut header = String::from("time,kinetic_energy,potential_energy");
            for (r, n) in &cols {
                header.push_str(&format!(",{}.{}", r.name(), n));
            }
            writeln!(self.out, "{header}")?;
            self.columns = Some(cols);
        }
        let value = |role: Role, name: &str| {
            self.latest
                .get(&role)
                .and_then(|ms| ms.iter().find(|m| m.name == name))
                .map(|m| m.value)
                .unwrap_or(f64::NAN)
        };
        let sum = |name: &str| {
            Role::ALL
                .iter()
                .filter_map(|r| {
                    self.latest
                        .get(r)
                        .and_then(|ms| ms.iter().find(|m| m.name == name))
                        .map(|m| m.value)
                })
                .sum::<f64>()
        };
        let mut line = format!(
            "{time},{},{}",
            sum("kinetic_energy"),
            sum("potential_energy")
        );
        for (r, n) in self.columns.as_ref().into_iter().flatten() {
            line.push_str(&format!(",{}", value(*r, n)));
        }
        writeln!(self.out, "{line}")
    }

    pub fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()
    }
}
