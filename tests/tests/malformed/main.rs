//! Malformed scenarios: each gets one message naming the file, the line and the
//! key, and exit code 2, never a panic.

use canopy_tests::*;

mod flow_cases;
mod structure_cases;

struct Case {
    name: &'static str,
    /// Turn the shipped pendulum scenario into the bad one.
    edit: fn(&str) -> String,
    /// The key the message must name (None: the problem has no key, e.g. a syntax error).
    key: Option<&'static str>,
    /// A phrase the message must contain.
    says: &'static str,
    /// Text on the line the message must point at.
    line_of: Option<&'static str>,
}

fn replace(text: &str, from: &str, to: &str) -> String {
    assert!(
        text.contains(from),
        "the scenario no longer contains {from:?}"
    );
    text.replacen(from, to, 1)
}

const CASES: &[Case] = &[
    // Issue 42: at 1e15 s the f64 clock steps by 0.125 s, and 1 ms windows
    // ended at repeated times.
    Case {
        name: "start-time-the-clock-cannot-resolve",
        edit: |t| {
            replace(
                t,
                "end_time = 10.0",
                "start_time = 1e15\nend_time = 1.00000000000001e15",
            )
        },
        key: Some("run.start_time"),
        says: "near it the clock (f64) steps by 1.25e-1 s",
        line_of: Some("start_time = 1e15"),
    },
    Case {
        name: "unknown-table",
        edit: |t| format!("{t}\n[bogus]\nx = 1\n"),
        key: Some("bogus"),
        says: "no participant `bogus` is listed",
        line_of: Some("[bogus]"),
    },
    Case {
        name: "unknown-key",
        edit: |t| replace(t, "end_time = 10.0", "end_time = 10.0\ncolour = \"red\""),
        key: Some("run.colour"),
        says: "unknown field `colour`",
        line_of: Some("colour"),
    },
    Case {
        name: "wrong-type",
        edit: |t| replace(t, "end_time = 10.0", "end_time = \"ten\""),
        key: Some("run.end_time"),
        says: "invalid type: string",
        line_of: Some("end_time"),
    },
    Case {
        name: "wrong-type-int",
        edit: |t| replace(t, "\nsubsteps = 4 ", "\nsubsteps = 4.5 "),
        key: Some("structure.substeps"),
        says: "invalid type",
        line_of: Some("substeps = 4.5"),
    },
    Case {
        name: "missing-value",
        edit: |t| replace(t, "end_time = 10.0\n", ""),
        key: Some("run"),
        says: "missing field `end_time`",
        line_of: Some("[run]"),
    },
    Case {
        name: "zero-window",
        edit: |t| replace(t, "window = 1e-3", "window = 0.0"),
        key: Some("coupling.window"),
        says: "must be > 0 s",
        line_of: Some("window = 0.0"),
    },
    Case {
        name: "negative-window",
        edit: |t| replace(t, "window = 1e-3", "window = -1e-3"),
        key: Some("coupling.window"),
        says: "must be > 0 s",
        line_of: Some("window = -1e-3"),
    },
    Case {
        name: "zero-substeps",
        edit: |t| replace(t, "\nsubsteps = 4 ", "\nsubsteps = 0 "),
        key: Some("structure.substeps"),
        says: "must be at least 1",
        line_of: Some("substeps = 0"),
    },
    // Before issue 44 the structure's sub-steps were a coupling key.
    Case {
        name: "substeps-where-they-were",
        edit: |t| {
            replace(
                t,
                "impulse_substeps = 4",
                "structure_substeps = 4\nimpulse_substeps = 4",
            )
        },
        key: Some("coupling.structure_substeps"),
        says: "write `substeps = N` in its table ([structure]",
        line_of: Some("structure_substeps = 4"),
    },
    Case {
        name: "zero-impulse-substeps",
        edit: |t| replace(t, "impulse_substeps = 4", "impulse_substeps = 0"),
        key: Some("coupling.impulse_substeps"),
        says: "must be at least 1",
        line_of: Some("impulse_substeps = 0"),
    },
    Case {
        name: "impulse-not-dividing",
        edit: |t| replace(t, "impulse_substeps = 4", "impulse_substeps = 3"),
        key: Some("structure.substeps"),
        says: "is not a multiple of [coupling] impulse_substeps = 3",
        line_of: Some("substeps = 4 "),
    },
    Case {
        name: "end-before-start",
        edit: |t| replace(t, "end_time = 10.0", "start_time = 20.0\nend_time = 10.0"),
        key: Some("run.end_time"),
        says: "must be after start_time",
        line_of: Some("end_time = 10.0"),
    },
    Case {
        name: "non-finite",
        edit: |t| replace(t, "end_time = 10.0", "end_time = nan"),
        key: Some("run.end_time"),
        says: "finite",
        line_of: Some("end_time = nan"),
    },
    Case {
        name: "zero-timeout",
        edit: |t| {
            replace(
                t,
                "impulse_substeps = 4",
                "impulse_substeps = 4\ntimeout = 0",
            )
        },
        key: Some("coupling.timeout"),
        says: "must be > 0 s",
        line_of: Some("timeout = 0"),
    },
    Case {
        name: "negative-timeout",
        edit: |t| {
            replace(
                t,
                "impulse_substeps = 4",
                "impulse_substeps = 4\ntimeout = -1.0",
            )
        },
        key: Some("coupling.timeout"),
        says: "must be > 0 s",
        line_of: Some("timeout = -1.0"),
    },
    Case {
        name: "missing-program",
        edit: |t| {
            replace(
                t,
                "program = \"rigid-proc\"",
                "program = \"no-such-solver\"",
            )
        },
        key: Some("participants.rigid.program"),
        says: "program `no-such-solver` not found",
        line_of: Some("no-such-solver"),
    },
    Case {
        name: "program-path",
        edit: |t| {
            replace(
                t,
                "program = \"rigid-proc\"",
                "program = \"./nothing/here\"",
            )
        },
        key: Some("participants.rigid.program"),
        says: "is not an executable file",
        line_of: Some("./nothing/here"),
    },
    Case {
        name: "participant-without-section",
        edit: |t| {
            replace(
                t,
                "[participants.rigid]",
                "[participants.fluid]\nprogram = \"fluid-proc\"\n\n[participants.rigid]",
            )
        },
        key: Some("participants.fluid"),
        says: "has no [fluid] section",
        line_of: Some("[participants.fluid]"),
    },
    Case {
        name: "bad-run-name",
        edit: |t| replace(t, "name = \"pendulum\"", "name = \"../up\""),
        key: Some("run.name"),
        says: "must be a non-empty name",
        line_of: Some("name = \"../up\""),
    },
    Case {
        name: "huge-timeout",
        edit: |t| {
            replace(
                t,
                "impulse_substeps = 4",
                "impulse_substeps = 4\ntimeout = 1e30",
            )
        },
        key: Some("coupling.timeout"),
        says: "is more than",
        line_of: Some("timeout = 1e30"),
    },
    Case {
        name: "too-many-windows",
        edit: |t| replace(t, "window = 1e-3", "window = 1e-12"),
        key: Some("coupling.window"),
        says: "gives more than",
        line_of: Some("window = 1e-12"),
    },
    Case {
        name: "checkpoint-interval-not-positive",
        edit: |t| {
            replace(
                t,
                "end_time = 10.0",
                "end_time = 10.0\ncheckpoint_interval = 0.0",
            )
        },
        key: Some("run.checkpoint_interval"),
        says: "must be > 0",
        line_of: Some("checkpoint_interval = 0.0"),
    },
    Case {
        name: "unknown-scheme",
        edit: |t| {
            let with = "impulse_substeps = 4     # impulse exchange every structure sub-step";
            replace(t, with, &format!("{with}\nscheme = \"semi-implicit\""))
        },
        key: Some("coupling.scheme"),
        says: "unknown variant `semi-implicit`",
        line_of: Some("scheme = \"semi-implicit\""),
    },
    Case {
        name: "implicit-settings-of-an-explicit-scheme",
        edit: |t| format!("{t}\n[coupling.implicit]\nrelaxation = 0.3\n"),
        key: Some("coupling.implicit"),
        says: "scheme is \"explicit\"",
        line_of: Some("[coupling.implicit]"),
    },
    Case {
        name: "accelerating-a-field-of-every-impulse-sub-step",
        edit: |t| {
            let with = "impulse_substeps = 4     # impulse exchange every structure sub-step";
            let implicit = "scheme = \"implicit\"\n\n[coupling.implicit]\naccelerate = \
                            [\"attachment.state\"]";
            replace(t, with, &format!("{with}\n{implicit}"))
        },
        key: Some("coupling.implicit.accelerate"),
        says: "is exchanged at every impulse sub-step",
        line_of: Some("accelerate = [\"attachment.state\"]"),
    },
    Case {
        name: "implicit-relaxation-out-of-range",
        edit: |t| {
            let with = "impulse_substeps = 4     # impulse exchange every structure sub-step";
            let implicit = "scheme = \"implicit\"\n\n[coupling.implicit]\nrelaxation = 3.0";
            replace(t, with, &format!("{with}\n{implicit}"))
        },
        key: Some("coupling.implicit.relaxation"),
        says: "must lie in (0, 2]",
        line_of: Some("relaxation = 3.0"),
    },
    Case {
        name: "complement-relaxation-out-of-range",
        edit: |t| {
            let with = "impulse_substeps = 4     # impulse exchange every structure sub-step";
            let implicit =
                "scheme = \"implicit\"\n\n[coupling.implicit]\ncomplement_relaxation = 1.5";
            replace(t, with, &format!("{with}\n{implicit}"))
        },
        key: Some("coupling.implicit.complement_relaxation"),
        says: "must lie in (0, 1]",
        line_of: Some("complement_relaxation = 1.5"),
    },
    Case {
        name: "limits-of-a-field-not-accelerated",
        edit: |t| {
            let with = "impulse_substeps = 4     # impulse exchange every structure sub-step";
            let implicit = "scheme = \"implicit\"\n\n[coupling.implicit]\naccelerate = \
                            [\"body.states\"]\n\n[[coupling.implicit.field]]\n\
                            name = \"canopy.positions\"\nrelative = 1e-6";
            replace(t, with, &format!("{with}\n{implicit}"))
        },
        key: Some("coupling.implicit.field[0].name"),
        says: "is not accelerated",
        line_of: Some("name = \"canopy.positions\""),
    },
    Case {
        name: "syntax-error",
        edit: |t| replace(t, "end_time = 10.0", "end_time = = 10.0"),
        key: None,
        says: "invalid string",
        line_of: Some("end_time = = 10.0"),
    },
    Case {
        name: "output-interval-below-the-clock",
        edit: |t| replace(t, "output_interval = 0.05", "output_interval = 1e-17"),
        key: Some("run.output_interval"),
        says: "asks for more than",
        line_of: Some("output_interval = 1e-17"),
    },
    Case {
        name: "cut-short-after-a-key",
        edit: |t| t[..t.find("window = 1e-3").unwrap() + "window =".len()].to_string(),
        key: None,
        says: "the file ends where a value should follow: is it cut short?",
        line_of: Some("window ="),
    },
];

/// 1-based line of the first occurrence of `needle` (which may span lines: its first line counts).
fn line_of(text: &str, needle: &str) -> usize {
    let at = text
        .find(needle)
        .unwrap_or_else(|| panic!("{needle:?} not in the bad scenario"));
    text[..at].matches('\n').count() + 1
}

/// What `mpirun`'s absence makes of a case that asks for more than one rank.
const NO_MPIRUN: &str = "under mpirun, which is not on PATH";

/// Whether the bad scenario `text` runs a participant on several ranks,
/// which the coupler refuses first, at the same key, where `mpirun` is
/// missing.
fn asks_for_ranks(text: &str) -> bool {
    text.lines()
        .filter_map(|l| l.trim().strip_prefix("ranks = "))
        .any(|n| n.trim().parse::<u32>().is_ok_and(|n| n > 1))
}

/// Check `case` with `coupler check` (PATH as `path_env` says, if given),
/// expecting it to say `says`: what is wrong with the answer, if anything.
fn wrong_with(
    case: &Case,
    dir: &std::path::Path,
    good: &str,
    says: &str,
    path_env: Option<&str>,
) -> Option<String> {
    let text = (case.edit)(good);
    let path = dir.join(format!("{}.toml", case.name));
    std::fs::write(&path, &text).unwrap();
    let mut command = std::process::Command::new(coupler_exe());
    command.args(["check", path.to_str().unwrap()]);
    if let Some(p) = path_env {
        command.env("PATH", p);
    }
    let out = command.output().expect("run coupler");
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    let mut wrong = Vec::new();
    if out.status.code() != Some(2) {
        wrong.push(format!("exit {:?}", out.status.code()));
    }
    if stderr.contains("panicked") {
        wrong.push("panicked".into());
    }
    if stderr.trim().lines().count() != 1 {
        wrong.push("not one line".into());
    }
    if !stderr.contains(&format!("{}:", path.display())) {
        wrong.push("no file name".into());
    }
    if let Some(key) = case.key {
        if !stderr.contains(&format!("key `{key}`")) {
            wrong.push(format!("no key `{key}`"));
        }
    }
    if !stderr.contains(says) {
        wrong.push(format!("does not say {says:?}"));
    }
    if let Some(marker) = case.line_of {
        let line = line_of(&text, marker);
        if !stderr.contains(&format!("{}:{line}:", path.display())) {
            wrong.push(format!("not at line {line}"));
        }
    }
    (!wrong.is_empty()).then(|| {
        format!(
            "{}: {} — got: {}",
            case.name,
            wrong.join(", "),
            stderr.trim()
        )
    })
}

fn all_cases() -> impl Iterator<Item = &'static Case> {
    CASES
        .iter()
        .chain(structure_cases::CASES)
        .chain(flow_cases::CASES)
}

/// Every case, on this machine as it is: a case that asks for several
/// ranks meets the rank checks where `mpirun` is installed, and the
/// refusal for want of it where it is not (and MPI is not required).
#[test]
fn every_malformed_scenario_gets_its_own_message_and_exit_code_2() {
    assert!(CASES.len() + structure_cases::CASES.len() + flow_cases::CASES.len() >= 20);
    let dir = scratch("malformed");
    let good = std::fs::read_to_string(scenario_path("pendulum")).unwrap();
    let mpirun = has_mpirun();
    let failures: Vec<String> = all_cases()
        .filter_map(|case| {
            let ranks = asks_for_ranks(&(case.edit)(&good));
            let says = if ranks && !mpirun {
                NO_MPIRUN
            } else {
                case.says
            };
            wrong_with(case, &dir, &good, says, None)
        })
        .collect();
    assert!(failures.is_empty(), "\n{}", failures.join("\n"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The cases that ask for several ranks on a machine without `mpirun`
/// (PATH empty; the programs are found beside the coupler): the refusal
/// names the missing program at the same key and line.
#[test]
fn without_mpirun_the_cases_with_ranks_name_the_missing_mpirun() {
    let dir = scratch("malformed-no-mpirun");
    let good = std::fs::read_to_string(scenario_path("pendulum")).unwrap();
    let ranked: Vec<&Case> = all_cases()
        .filter(|case| asks_for_ranks(&(case.edit)(&good)))
        .collect();
    assert!(ranked.len() >= 3, "the rank cases are gone");
    let failures: Vec<String> = (ranked.iter())
        .filter_map(|case| wrong_with(case, &dir, &good, NO_MPIRUN, Some("")))
        .collect();
    assert!(failures.is_empty(), "\n{}", failures.join("\n"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_fifo_given_as_the_scenario_is_refused_not_waited_on() {
    // Reading a FIFO blocks until a writer comes, which never does.
    let dir = scratch("fifo");
    let fifo = dir.join("scenario.toml");
    let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    // SAFETY: mkfifo only reads the path we pass.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0);
    // The clock starts once the executables are built.
    ensure_built();
    let started = std::time::Instant::now();
    let out = coupler(&["check", fifo.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("it is not a regular file"), "{stderr}");
    assert!(started.elapsed() < std::time::Duration::from_secs(10));
}

#[test]
fn a_missing_scenario_file_is_bad_input() {
    let out = coupler(&["check", "/nonexistent/scenario.toml"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("cannot read the scenario"));
}

#[test]
fn the_shipped_scenarios_pass_check() {
    for name in [
        "pendulum",
        "canopy-porous",
        "pendulum-body",
        "c9-drop-body",
        "cuboids",
        "spinning-top",
        "ball-drop",
        "point-ball",
        "cloth-drop",
        "ball-cloth",
        "cavity",
        "c9-tunnel",
        "c9-frontier-grid",
        "sod",
        "shu-osher",
    ] {
        let out = coupler(&["check", scenario_path(name).to_str().unwrap()]);
        assert!(
            out.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

#[test]
fn a_bad_mesh_is_reported_with_its_own_line_and_the_scenario_key() {
    // A face naming a vertex that does not exist, on line 3 of the mesh.
    let dir = scratch("bad-mesh");
    std::fs::write(dir.join("bad.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 99\n").unwrap();
    let good = std::fs::read_to_string(scenario_path("pendulum")).unwrap();
    let text = replace(
        &good,
        "mass = 1.0\n",
        "mass = 1.0\nshape = { type = \"mesh\", file = \"bad.obj\" }\n",
    );
    let path = dir.join("mesh.toml");
    std::fs::write(&path, &text).unwrap();
    let out = coupler(&["check", path.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    let line = line_of(&text, "shape = ");
    assert!(
        stderr.contains(&format!("{}:{line}:", path.display())),
        "{stderr}"
    );
    assert!(
        stderr.contains("key `rigid.bodies[0].shape.file`"),
        "{stderr}"
    );
    assert!(
        stderr.contains("bad.obj:3: face vertex 99 does not exist"),
        "{stderr}"
    );
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
}

/// A program that is no canopy participant exits 2 on `--check` with a
/// usage error (issue 42): the refusal names the scenario's line and key
/// of the program, the participant and the program, on one line, rather
/// than relaying the usage error alone.
#[test]
fn a_program_that_does_not_know_check_is_named_with_its_participant() {
    let dir = scratch("not-a-participant");
    let good = std::fs::read_to_string(scenario_path("pendulum")).unwrap();
    for (k, program) in ["/bin/ls", "coupler"].into_iter().enumerate() {
        let text = replace(
            &good,
            "program = \"rigid-proc\"",
            &format!("program = \"{program}\""),
        );
        let path = dir.join(format!("program-{k}.toml"));
        std::fs::write(&path, &text).unwrap();
        let out = coupler(&["check", path.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
        let line = line_of(&text, &format!("program = \"{program}\""));
        let expected = [
            format!("{}:{line}:", path.display()),
            "key `participants.rigid.program`".to_string(),
            "participant `rigid`".to_string(),
            "exited with code 2 without naming the scenario".to_string(),
        ];
        for e in expected {
            assert!(stderr.contains(&e), "{program}: no {e:?} in {stderr}");
        }
        assert!(
            stderr.contains(program.trim_start_matches("/bin/")),
            "{stderr}"
        );
        assert!(!stderr.contains("error: error:"), "{stderr}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
