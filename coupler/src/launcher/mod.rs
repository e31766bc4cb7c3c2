//! The `coupler` executable's library half: check a scenario, launch and
//! supervise its participants, drive the coupling schedule, write the run
//! directory. Only the `coupler` binary uses this (feature `launcher`).

pub mod bench;
pub mod checks;
pub mod coupling;
pub mod iterations;
pub mod manifest;
pub mod monitors;
pub mod programs;
pub mod progress;
pub mod report;
pub mod restart;
pub mod run;
pub mod study;
pub mod supervise;

use participant::scheme::{Acceleration, Implicit, Measured, Scheme};
use participant::Timing;
use programs::Program;
use scenario::implicit::{AccelerationName, OnMax};
use scenario::{Answer, Scenario, ScenarioError};
use std::path::{Path, PathBuf};

/// Exit code for bad input (scenario, arguments, missing program).
pub const EXIT_BAD_INPUT: i32 = 2;
/// Exit code for a run that failed or diverged.
pub const EXIT_RUN_FAILED: i32 = 1;
/// Exit code after Ctrl-C.
pub const EXIT_INTERRUPTED: i32 = 130;

/// A scenario with the program that plays each participant, and each
/// program's answer to `--check`.
pub struct Checked {
    pub path: PathBuf,
    /// The file as read: what every participant reads its section from.
    pub text: String,
    pub scenario: Scenario,
    /// Each participant's name and program, in the scenario's order.
    pub programs: Vec<(String, Program)>,
    /// `mpirun`, when a participant runs on several ranks.
    pub mpirun: Option<PathBuf>,
    /// Each participant's answer to `--check`, in the order of `programs`.
    pub answers: Vec<(String, Answer)>,
}

/// Load the scenario, find its programs and have each check its section:
/// every problem, one line each (file, line, key and message).
pub fn load_checked(path: &Path) -> Result<Checked, Vec<String>> {
    let mut checked = load_coupling(path).map_err(|e| vec![e.to_string()])?;
    checked.answers = checks::ask_all(&mut checked.programs, path, &checked.text)?;
    refuse_what_a_program_cannot_do(&checked).map_err(|e| vec![e.to_string()])?;
    Ok(checked)
}

/// Keys that need every program to do something it may not: `scheme =
/// "implicit"` takes windows again from checkpoints, `[run]
/// checkpoint_interval` writes run checkpoints. Each program says in its
/// `--check` answer what it does; the first key one cannot serve is
/// refused at its line.
fn refuse_what_a_program_cannot_do(checked: &Checked) -> Result<(), ScenarioError> {
    type Can = fn(&Answer) -> bool;
    let s = &checked.scenario;
    let needs: [(bool, Can, [&str; 2], &str); 2] = [
        (
            s.coupling.implicit_settings().is_some(),
            |a| a.checkpoints,
            ["coupling", "scheme"],
            "scheme = \"implicit\" takes windows again from their checkpoints, and the \
             program of `{who}` does not save and restore them (its `--check` answer says \
             so): use scheme = \"explicit\"",
        ),
        (
            s.run.checkpoint_interval.is_some(),
            |a| a.restarts,
            ["run", "checkpoint_interval"],
            "checkpoint_interval asks every participant to write run checkpoints, and the \
             program of `{who}` does not (its `--check` answer says so): remove the key",
        ),
    ];
    for (wanted, can, key, message) in needs {
        let unable: Vec<&str> = (checked.answers.iter())
            .filter(|(_, a)| !can(a))
            .map(|(name, _)| name.as_str())
            .collect();
        if wanted && !unable.is_empty() {
            let message = message.replace("{who}", &unable.join("`, `"));
            return Err(ScenarioError::at_key(
                &checked.path,
                &checked.text,
                &key,
                message,
            ));
        }
    }
    Ok(())
}

/// The coupling part of the scenario, and its programs found.
fn load_coupling(path: &Path) -> Result<Checked, ScenarioError> {
    let text = scenario::read_text(path)?;
    let scenario = Scenario::parse(path, &text)?;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut programs = Vec::new();
    for role in scenario.participants.names() {
        let spec = scenario
            .participants
            .get(role)
            .expect("names() lists present participants");
        match programs::resolve(&spec.program, &dir) {
            Some(p) => programs.push((role.to_string(), p)),
            None => {
                let where_ = if spec.program.contains('/') {
                    format!(
                        "{} is not an executable file",
                        dir.join(&spec.program).display()
                    )
                } else {
                    "it is neither beside the coupler executable nor on PATH".to_string()
                };
                return Err(ScenarioError::at_key(
                    path,
                    &text,
                    &["participants", role, "program"],
                    format!("program `{}` not found: {where_}", spec.program),
                ));
            }
        }
    }
    let mut mpirun = None;
    for role in scenario.participants.names() {
        let ranks = scenario.participants.get(role).map_or(1, |s| s.ranks());
        if ranks > 1 && mpirun.is_none() {
            match programs::resolve("mpirun", &dir) {
                Some(Program::Found(p)) => mpirun = Some(p),
                _ => {
                    return Err(ScenarioError::at_key(
                        path,
                        &text,
                        &["participants", role, "ranks"],
                        format!(
                            "ranks = {ranks} starts `{}` under mpirun, which is not on PATH \
                             (Debian: apt-get install openmpi-bin)",
                            role
                        ),
                    ))
                }
            }
        }
    }
    Ok(Checked {
        path: path.to_path_buf(),
        text,
        scenario,
        programs,
        mpirun,
        answers: Vec::new(),
    })
}

/// Prints every problem `load_checked` found; the exit code for them.
pub fn refuse(problems: &[String]) -> i32 {
    for p in problems {
        eprintln!("error: {p}");
    }
    EXIT_BAD_INPUT
}

/// Prints the warnings of the participants' answers.
pub fn warn(checked: &Checked) {
    for (_, answer) in &checked.answers {
        for w in &answer.warnings {
            eprintln!("warning: {}: {w}", checked.path.display());
        }
    }
}

/// `coupler check`: the coupling part and every participant's section
/// checked, the schedule, and what each participant answered (for a
/// structure, the stable step).
pub fn check(path: &Path) -> i32 {
    let checked = match load_checked(path) {
        Ok(c) => c,
        Err(problems) => return refuse(&problems),
    };
    let s = &checked.scenario;
    let c = &s.coupling;
    println!("{}: ok — scene `{}`", path.display(), s.run.name);
    println!(
        "  time      {} → {} s, {} windows of Δt_f = {} s",
        s.run.start_time,
        s.run.end_time,
        timing(s).windows(),
        c.window
    );
    println!("  impulse sub-steps = {}", c.impulse_substeps);
    for (role, program) in &checked.programs {
        let ranks = s.participants.get(role).map_or(1, |p| p.ranks());
        if ranks > 1 {
            println!("  {role:<9} on {ranks} ranks, under mpirun");
        }
        match program {
            Program::Found(p) => println!("  {role:<9} {}", p.display()),
            Program::Buildable { package, .. } => {
                println!("  {role:<9} workspace package `{package}` (built on first run)")
            }
        }
    }
    for (role, answer) in &checked.answers {
        for note in &answer.notes {
            println!("  {role:<9} {note}");
        }
    }
    warn(&checked);
    0
}

/// The run's clock, as every participant gets it in its setup.
/// The coupling scheme the participants are told, from `[coupling]`.
pub fn scheme(s: &Scenario) -> Scheme {
    let Some(i) = s.coupling.implicit_settings() else {
        return Scheme::Explicit;
    };
    Scheme::Implicit(Implicit {
        fields: i
            .accelerated(s.coupling.bodies_iterate(), s.coupling.parallel())
            .iter()
            .map(|f| {
                let (relative, absolute) = i.limits(f);
                Measured {
                    field: f.clone(),
                    relative,
                    absolute,
                }
            })
            .collect(),
        acceleration: match i.acceleration {
            AccelerationName::Constant => Acceleration::Constant {
                omega: i.relaxation,
            },
            AccelerationName::Aitken => Acceleration::Aitken {
                initial: i.relaxation,
            },
            AccelerationName::IqnIls => Acceleration::IqnIls {
                initial: i.relaxation,
                reused_windows: i.reused_windows,
                max_columns: i.max_columns,
                filter: i.filter,
            },
        },
        min_iterations: i.min_iterations,
        max_iterations: i.max_iterations,
        go_on_at_max: i.on_max == OnMax::GoOn,
        parallel: s.coupling.parallel(),
        complement: i.complement_relaxation,
    })
}

pub fn timing(s: &Scenario) -> Timing {
    Timing {
        start_time: s.run.start_time,
        end_time: s.run.end_time,
        window: s.coupling.window,
        output_interval: s.run.output_interval,
        impulse_substeps: s.coupling.impulse_substeps,
        timeout: s.coupling.timeout,
        checkpoint_interval: s.run.checkpoint_interval.unwrap_or(0.0),
    }
}
