//! Runs that meet trouble outside the physics: two runs into one directory
//! at once, and a disk that fills up. Each ends cleanly, says why, and
//! leaves what it wrote readable.

use canopy_tests::*;
use std::os::unix::process::CommandExt;
use std::path::Path;

#[test]
fn of_two_runs_into_one_directory_at_once_exactly_one_runs() {
    let dir = scratch("same-out");
    let path = variant("pendulum", &dir, |s| s.run.end_time = 0.05);
    for trial in 0..8 {
        let out = dir.join(format!("run{trial}"));
        let start = || {
            run_command(&path, &out)
                .stdout(std::process::Stdio::null())
                .stderr(std::process::Stdio::piped())
                .spawn()
                .unwrap()
        };
        let (a, b) = (start(), start());
        let (a, b) = (a.wait_with_output().unwrap(), b.wait_with_output().unwrap());
        let mut codes = [a.status.code(), b.status.code()];
        codes.sort();
        assert_eq!(codes, [Some(0), Some(2)], "trial {trial}");
        let refused = if a.status.code() == Some(2) { &a } else { &b };
        let says = String::from_utf8_lossy(&refused.stderr);
        assert!(says.contains("is not empty"), "{says}");
        assert_eq!(manifest(&out)["status"], "completed");
    }
}

/// Files under `dir` whose extension is `tmp`.
fn files_aside(dir: &Path) -> Vec<std::path::PathBuf> {
    let mut found = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let p = entry.path();
        if p.is_dir() {
            found.extend(files_aside(&p));
        } else if p.extension().is_some_and(|x| x == "tmp") {
            found.push(p);
        }
    }
    found
}

#[test]
fn a_full_disk_stops_the_run_naming_the_file_and_leaves_whole_rows() {
    // A file size limit stands in for a full disk: a write past it fails
    // as one on a full disk does (SIGXFSZ ignored, the write returns an
    // error). 4 MiB leaves room for the shared memory of the run's channels
    // and the outputs, and monitors.csv reaches it first.
    const LIMIT: u64 = 4 << 20;
    let dir = scratch("full-disk");
    let path = variant("pendulum", &dir, |s| {
        s.run.end_time = 20.0;
        s.run.output_interval = 1.0;
    });
    let out = dir.join("run");
    let mut command = run_command(&path, &out);
    // SAFETY: setrlimit and signal only change this child's own limits and
    // dispositions, which its children inherit.
    unsafe {
        command.pre_exec(|| {
            let limit = libc::rlimit {
                rlim_cur: LIMIT,
                rlim_max: LIMIT,
            };
            libc::setrlimit(libc::RLIMIT_FSIZE, &limit);
            libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
            Ok(())
        });
    }
    let o = command.output().unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains(&format!(
            "cannot write {}",
            out.join("monitors.csv").display()
        )),
        "{stderr}"
    );
    let text = std::fs::read_to_string(out.join("monitors.csv")).unwrap();
    assert!(text.ends_with('\n'), "a torn last row");
    let fields: Vec<usize> = text.lines().map(|l| l.split(',').count()).collect();
    assert!(fields.len() > 1000 && fields.iter().all(|&n| n == fields[0]));
    assert!(text.len() as u64 <= LIMIT);
    assert_eq!(files_aside(&out), Vec::<std::path::PathBuf>::new());
    assert_eq!(manifest(&out)["status"], "failed");
}

#[test]
fn runs_killed_while_they_start_leave_nothing_a_later_run_does_not_clean() {
    // The coupler killed at once or a little later, its participants with
    // it (PR_SET_PDEATHSIG), some in the middle of creating their nodes.
    let dir = scratch("killed-at-start");
    let path = variant("pendulum", &dir, |s| s.run.end_time = 0.5);
    let mut runs = Vec::new();
    for trial in 0..15u64 {
        let out = dir.join(format!("run{trial}"));
        let mut child = run_command(&path, &out)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(10 * trial));
        // SAFETY: plain syscall on the coupler we started.
        unsafe { libc::kill(child.id() as i32, libc::SIGKILL) };
        child.wait().unwrap();
        // What a killed run wrote stays readable: no monitors.csv without its header.
        if let Ok(text) = std::fs::read_to_string(out.join("monitors.csv")) {
            assert!(text.starts_with("time,"), "trial {trial}: {text:?}");
        }
        if let Ok(text) = std::fs::read_to_string(out.join("manifest.json")) {
            let m: serde_json::Value = serde_json::from_str(&text).unwrap();
            runs.push(m["run_id"].as_str().unwrap().to_string());
        }
    }
    // The participants die with their coupler, even one it started just
    // before it was killed; then a later run's cleanup (here called
    // directly) leaves no entry behind.
    std::thread::sleep(
        participant::supervisor::HALF_CREATED_AGE + std::time::Duration::from_secs(1),
    );
    let orphans = processes_of_runs(&runs);
    assert!(
        orphans.is_empty(),
        "participants outlived their coupler: {orphans:?}"
    );
    participant::supervisor::cleanup_dead_nodes();
    assert_eq!(participant::supervisor::stale_node_entries(), 0);
}

#[test]
fn a_program_that_never_connects_fails_the_run_after_coupling_timeout() {
    // The connect wait is the scenario's timeout (at least 5 s, for a
    // loaded machine), not a fixed one.
    let dir = scratch("never-connects");
    let mute = dir.join("mute.sh");
    std::fs::write(&mute, "#!/bin/sh\n# Answers the check, then never connects.\n[ \"$1\" = --check ] && exit 0\nexec sleep 60\n").unwrap();
    let mut perms = std::fs::metadata(&mute).unwrap().permissions();
    std::os::unix::fs::PermissionsExt::set_mode(&mut perms, 0o755);
    std::fs::set_permissions(&mute, perms).unwrap();
    let path = variant("pendulum", &dir, |s| {
        s.coupling.timeout = 7.0;
        s.participants.get_mut("rigid").unwrap().program = mute.display().to_string();
    });
    let started = std::time::Instant::now();
    let failed = run_failed(&path, &dir.join("run"));
    let took = started.elapsed().as_secs_f64();
    assert!(
        failed.contains("participant `rigid` did not answer within 7.0 s: it never connected"),
        "{failed}"
    );
    assert!((7.0..20.0).contains(&took), "took {took} s");
}

/// Live processes (not zombies) started for one of `runs`, by the run id
/// in their environment.
fn processes_of_runs(runs: &[String]) -> Vec<u32> {
    let mut found = Vec::new();
    for entry in std::fs::read_dir("/proc").unwrap().flatten() {
        let Ok(pid) = entry.file_name().to_string_lossy().parse::<u32>() else {
            continue;
        };
        let Ok(env) = std::fs::read(format!("/proc/{pid}/environ")) else {
            continue;
        };
        let env = String::from_utf8_lossy(&env);
        let ours = env
            .split('\0')
            .filter_map(|v| v.strip_prefix("CANOPY_RUN_ID="))
            .any(|id| runs.iter().any(|r| r == id));
        let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap_or_default();
        let zombie = stat
            .rsplit(')')
            .next()
            .unwrap_or("")
            .trim_start()
            .starts_with('Z');
        if ours && !zombie {
            found.push(pid);
        }
    }
    found
}
