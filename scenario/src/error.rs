//! The one message a user gets for a bad scenario: file, line, key, what is wrong.

use super::check::{path_string, Problem};
use super::spans;
use std::fmt;
use std::path::{Path, PathBuf};

#[derive(Debug, Clone)]
pub struct ScenarioError {
    pub file: PathBuf,
    /// 1-based line, when the problem has a place in the file.
    pub line: Option<usize>,
    pub column: Option<usize>,
    /// Dotted key path, e.g. `rigid.bodies[0].mass`.
    pub key: Option<String>,
    pub message: String,
}

impl ScenarioError {
    pub fn io(path: &Path, e: &std::io::Error) -> Self {
        ScenarioError {
            file: path.to_path_buf(),
            line: None,
            column: None,
            key: None,
            message: format!("cannot read the scenario: {e}"),
        }
    }

    pub fn from_toml(path: &Path, text: &str, e: &toml::de::Error) -> Self {
        let offset = e.span().map(|s| s.start);
        let (line, column) = match offset {
            Some(o) => {
                let (l, c) = spans::line_col(text, o);
                (Some(l), Some(c))
            }
            None => (None, None),
        };
        let key = offset
            .and_then(|o| spans::key_at(text, o))
            .map(|p| path_string(&p))
            .filter(|k| !k.is_empty());
        ScenarioError {
            file: path.to_path_buf(),
            line,
            column,
            key,
            message: toml_message(e, text.len()),
        }
    }

    pub fn from_problem(path: &Path, text: &str, p: Problem) -> Self {
        let at = spans::span_of(text, &p.path).map(|s| spans::line_col(text, s.start));
        ScenarioError {
            file: path.to_path_buf(),
            line: at.map(|a| a.0),
            column: at.map(|a| a.1),
            key: Some(path_string(&p.path)),
            message: p.message,
        }
    }

    /// An error about a key whose place is found by its path (used by the launcher's checks).
    pub fn at_key(path: &Path, text: &str, keys: &[&str], message: String) -> Self {
        let p = Problem {
            path: keys
                .iter()
                .map(|k| super::check::Seg::Key(k.to_string()))
                .collect(),
            message,
        };
        Self::from_problem(path, text, p)
    }
}

impl fmt::Display for ScenarioError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(l) = self.line {
            write!(f, ":{l}")?;
            if let Some(c) = self.column {
                write!(f, ":{c}")?;
            }
        }
        if let Some(k) = &self.key {
            write!(f, ": key `{k}`")?;
        }
        write!(f, ": {}", self.message)
    }
}

impl std::error::Error for ScenarioError {}

/// toml's message on one line (its messages can span lines), or, where it
/// gives none (a value missing at the end of the text), what is wrong.
fn toml_message(e: &toml::de::Error, len: usize) -> String {
    let message = e
        .message()
        .trim()
        .lines()
        .map(str::trim)
        .collect::<Vec<_>>()
        .join("; ");
    match (message.is_empty(), e.span()) {
        (false, _) => message,
        (true, Some(s)) if s.start >= len => {
            "the file ends where a value should follow: is it cut short?".to_string()
        }
        (true, _) => "a value should follow here".to_string(),
    }
}
