//! What a participant's program answers to `PROGRAM --check SCENARIO NAME`
//! (NAME: the participant it plays): the contract by which the coupler
//! checks sections it does not know.
//!
//! - All good: exit 0 and, on stdout, nothing or an [`Answer`] in TOML
//!   (notes for `coupler check` to print, warnings, and values for the run's
//!   manifest).
//! - Bad input: exit 2 and one line per problem on stderr, each as
//!   [`ScenarioError`] prints it (`file:line:col: key `k`: message`).
//!
//! [`answer_check`] and [`answer_check_as`] do both for a program written
//! in Rust.

use crate::error::ScenarioError;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The flag a participant's program answers (`PROGRAM --check SCENARIO NAME`).
pub const CHECK_FLAG: &str = "--check";

/// Exit code of a program that found bad input.
pub const EXIT_BAD_INPUT: i32 = 2;

/// A participant's answer to `--check` when its section is good.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Answer {
    /// Lines `coupler check` prints under the participant's name.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
    /// Things the user should know before a run (for example a step above
    /// the integrator's stability limit); printed on stderr, never fatal.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// Values the run's `manifest.json` records under
    /// `checked.<participant>` (for example the stability estimate).
    #[serde(default, skip_serializing_if = "toml::Table::is_empty")]
    pub manifest: toml::Table,
    /// Whether the program, run on this scenario, saves and restores window
    /// checkpoints (what `[coupling] scheme = "implicit"` needs, and what
    /// its declaration then says with `checkpoints()`).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub checkpoints: bool,
    /// Whether it writes run checkpoints and resumes from them (what `[run]
    /// checkpoint_interval` needs; its declaration says `restarts()`).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub restarts: bool,
}

impl Answer {
    /// An answer saying only that the program saves and restores window
    /// checkpoints.
    pub fn with_checkpoints() -> Answer {
        Answer {
            checkpoints: true,
            ..Default::default()
        }
    }

    /// The same, saying too that it writes run checkpoints and resumes
    /// from them.
    pub fn with_restarts() -> Answer {
        Answer {
            checkpoints: true,
            restarts: true,
            ..Default::default()
        }
    }
}

impl Answer {
    /// The answer as the program prints it.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("an answer always serialises")
    }

    /// Reads a program's stdout.
    pub fn parse(text: &str) -> Result<Answer, String> {
        toml::from_str(text).map_err(|e| e.message().trim().to_string())
    }
}

/// Answers `--check SCENARIO [NAME]` when those are the program's
/// arguments: reads the file, calls `check` with its path and text, prints
/// the answer or the problem, and exits 0 or 2. Returns (doing nothing) for
/// any other arguments, so a program's `main` starts with it. For a program
/// that knows the name of its table; [`answer_check_as`] is told it.
pub fn answer_check(check: impl FnOnce(&Path, &str) -> Result<Answer, ScenarioError>) {
    answer(|_, path, text| check(path, text));
}

/// [`answer_check`] for a program whose table is named after the
/// participant it plays: `check` gets that name first, the coupler's third
/// argument (`PROGRAM --check SCENARIO NAME`; NAME is the program's key
/// under `[participants]`, as `Joining::name` says in a run). Run by hand
/// without NAME, the check says so and exits 2.
pub fn answer_check_as(check: impl FnOnce(&str, &Path, &str) -> Result<Answer, ScenarioError>) {
    answer(|name, path, text| match name {
        Some(name) => check(name, path, text),
        None => Err(ScenarioError {
            file: path.to_path_buf(),
            line: None,
            column: None,
            key: None,
            message: format!(
                "which participant to check? This program reads the table named after \
                 the participant it plays: give it as `{CHECK_FLAG} SCENARIO NAME`"
            ),
        }),
    });
}

/// `--check SCENARIO [NAME]`: `check(name, path, text)`, its answer
/// printed, and exit; any other arguments: return.
fn answer(check: impl FnOnce(Option<&str>, &Path, &str) -> Result<Answer, ScenarioError>) {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (flag, path, name) = match args.as_slice() {
        [flag, path] => (flag, path, None),
        [flag, path, name] => (flag, path, Some(name.as_str())),
        _ => return,
    };
    if flag != CHECK_FLAG {
        return;
    }
    let path = Path::new(path);
    let result = crate::read_text(path).and_then(|text| check(name, path, &text));
    match result {
        Ok(answer) => {
            print!("{}", answer.to_toml());
            std::process::exit(0);
        }
        Err(e) => {
            // The line as the coupler relays it: it starts with the file.
            eprintln!("{e}");
            std::process::exit(EXIT_BAD_INPUT);
        }
    }
}
