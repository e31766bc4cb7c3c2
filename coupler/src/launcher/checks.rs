//! Each participant's program checks its own section: `PROGRAM --check
//! SCENARIO` (docs/PROTOCOL.md, "Checking a scenario"). The coupler asks
//! every listed program at once, and gathers every problem (each program
//! reports its first, as `file:line:col: key `k`: message`; two programs
//! that read one table give the same line, printed once) and every answer.

use super::programs::{self, Program};
use scenario::{Answer, ScenarioError, CHECK_FLAG};
use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// How long a program may take to read, check and answer (a structure
/// program builds its model for the stability estimate).
const ANSWER_WITHIN: Duration = Duration::from_secs(60);

/// What one program said.
enum Said {
    Answer(Answer),
    Problems(Vec<String>),
}

/// Asks every program in `programs` (name, program) about the scenario at
/// `path`, whose text is `text`: their answers in the same order, or every
/// problem, one line each, in the order of the programs.
pub fn ask_all(
    programs: &mut [(String, Program)],
    path: &Path,
    text: &str,
) -> Result<Vec<(String, Answer)>, Vec<String>> {
    let said: Vec<Said> = std::thread::scope(|s| {
        let asks: Vec<_> = programs
            .iter_mut()
            .map(|(name, program)| {
                let name = name.clone();
                s.spawn(move || ask(&name, program, (path, text)))
            })
            .collect();
        asks.into_iter()
            .map(|a| {
                a.join()
                    .unwrap_or_else(|_| Said::Problems(vec!["a check panicked".into()]))
            })
            .collect()
    });
    let mut answers = Vec::new();
    let mut problems: Vec<String> = Vec::new();
    for ((name, _), said) in programs.iter().zip(said) {
        match said {
            Said::Answer(a) => answers.push((name.clone(), a)),
            Said::Problems(lines) => {
                for l in lines {
                    if !problems.contains(&l) {
                        problems.push(l);
                    }
                }
            }
        }
    }
    match problems.is_empty() {
        true => Ok(answers),
        false => Err(problems),
    }
}

/// Asks participant `name`'s `program` about the scenario at `path`
/// whose text is `text`. A problem with the program itself is put at its
/// `program` key.
fn ask(name: &str, program: &mut Program, (path, text): (&Path, &str)) -> Said {
    let about = |what: String| {
        let key = ["participants", name, "program"];
        let message = format!("participant `{name}`: {what}");
        Said::Problems(vec![
            ScenarioError::at_key(path, text, &key, message).to_string()
        ])
    };
    let exe = match programs::ensure_built(program) {
        Ok(p) => p,
        Err(e) => return about(e),
    };
    let (code, out, err) = match run_within(&exe, path, name, ANSWER_WITHIN) {
        Ok(r) => r,
        Err(e) => return about(e),
    };
    let shown = exe.display();
    match code {
        Some(0) => match Answer::parse(&out) {
            Ok(a) => Said::Answer(a),
            Err(e) => about(format!(
                "`{shown} {CHECK_FLAG}` printed no answer it could read: {e}"
            )),
        },
        Some(scenario::answer::EXIT_BAD_INPUT) => {
            let lines: Vec<String> = err
                .lines()
                .filter(|l| !l.trim().is_empty())
                .map(String::from)
                .collect();
            // A participant's refusal names the scenario file; a program
            // that exits 2 otherwise (a usage error) is not one.
            let names_the_file = |l: &String| l.starts_with(&format!("{}:", path.display()));
            match lines.first() {
                None => about(format!(
                    "`{shown} {CHECK_FLAG}` refused the scenario and said nothing"
                )),
                Some(_) if lines.iter().any(names_the_file) => Said::Problems(lines),
                Some(first) => about(format!(
                    "`{shown} {CHECK_FLAG}` exited with code 2 without naming the \
                     scenario: is it a canopy participant? It said: {}",
                    first.trim_start_matches("error: ")
                )),
            }
        }
        other => about(format!(
            "`{shown} {CHECK_FLAG}` ended with {} instead of answering: {}",
            other.map_or("a signal".to_string(), |c| format!("exit code {c}")),
            err.lines().next().unwrap_or("no message")
        )),
    }
}

/// Runs `program --check scenario name` for at most `limit`: its exit code
/// and what it printed on stdout and stderr.
fn run_within(
    program: &Path,
    scenario: &Path,
    name: &str,
    limit: Duration,
) -> Result<(Option<i32>, String, String), String> {
    let mut child = Command::new(program)
        .arg(CHECK_FLAG)
        .arg(scenario)
        .arg(name)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot start {}: {e}", program.display()))?;
    // Drain both pipes while waiting, so a talkative program cannot block on them.
    let drain = |pipe: Option<Box<dyn Read + Send>>| {
        std::thread::spawn(move || {
            let mut text = String::new();
            if let Some(mut p) = pipe {
                let _ = p.read_to_string(&mut text);
            }
            text
        })
    };
    let stdout = drain(
        child
            .stdout
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let stderr = drain(
        child
            .stderr
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            break status;
        }
        if started.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!(
                "{} did not answer {CHECK_FLAG} within {} s",
                program.display(),
                limit.as_secs()
            ));
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let out = stdout.join().unwrap_or_default();
    let err = stderr.join().unwrap_or_default();
    Ok((status.code(), out, err))
}
