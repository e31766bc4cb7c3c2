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

/// The process of participant `name` of run `run_id`, by the variables
/// the coupler gives it.
fn participant_pid(run_id: &str, name: &str) -> Option<i32> {
    let wanted = [
        format!("CANOPY_RUN_ID={run_id}"),
        format!("CANOPY_PARTICIPANT={name}"),
    ];
    std::fs::read_dir("/proc")
        .ok()?
        .flatten()
        .find_map(|entry| {
            let pid: i32 = entry.file_name().to_string_lossy().parse().ok()?;
            let env = std::fs::read(format!("/proc/{pid}/environ")).ok()?;
            let env = String::from_utf8_lossy(&env);
            let vars: Vec<&str> = env.split('\0').collect();
            wanted
                .iter()
                .all(|w| vars.contains(&w.as_str()))
                .then_some(pid)
        })
}

/// Rows `monitors.csv` in `out` holds so far.
fn rows_so_far(out: &Path) -> usize {
    std::fs::read(out.join("monitors.csv"))
        .map_or(0, |t| t.iter().filter(|&&b| b == b'\n').count())
        .saturating_sub(1)
}

/// Issue 42: in `c9-drop-body` the fluid waits for the canopy from the
/// structure, which waits for the attachment from the rigid body. The
/// rigid body stopped (SIGSTOP) is the one that did not answer, whoever
/// of the waiters gives up first.
#[test]
fn a_participant_stopped_at_the_end_of_a_chain_of_waits_is_the_culprit() {
    let dir = scratch("stopped-rigid");
    let path = variant("c9-drop-body", &dir, |s| {
        s.run.end_time = 60.0;
        s.coupling.timeout = 3.0;
    });
    let out = dir.join("run");
    let child = run_command(&path, &out)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let since = std::time::Instant::now();
    while rows_so_far(&out) < 20 {
        assert!(since.elapsed().as_secs() < 120, "the run never got going");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let run_id = manifest(&out)["run_id"].as_str().unwrap().to_string();
    let rigid = participant_pid(&run_id, "rigid").expect("rigid-proc runs");
    // SAFETY: kill(2) on a process of the run this test started.
    assert_eq!(unsafe { libc::kill(rigid, libc::SIGSTOP) }, 0);
    let o = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("participant `rigid` did not answer within 3.0 s"),
        "{stderr}"
    );
    assert_eq!(manifest(&out)["culprit"], "rigid", "{stderr}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A tmpfs of `bytes` mounted at `at`, unmounted when dropped; None where
/// this process may not mount one.
struct SmallDisk(std::path::PathBuf);

impl SmallDisk {
    fn mount(at: &Path, bytes: u64) -> Option<SmallDisk> {
        std::fs::create_dir_all(at).unwrap();
        let size = format!("size={bytes}");
        let ok = std::process::Command::new("mount")
            .args(["-t", "tmpfs", "-o", &size, "tmpfs"])
            .arg(at)
            .status()
            .is_ok_and(|s| s.success());
        ok.then(|| SmallDisk(at.to_path_buf()))
    }
}

impl Drop for SmallDisk {
    fn drop(&mut self) {
        let _ = std::process::Command::new("umount").arg(&self.0).status();
    }
}

/// Issue 42: a disk really full (a 1 MiB tmpfs, where every file, the
/// manifest's new copy included, finds no room) stops the run with the
/// file named, and the manifest says the run failed and why, not that it
/// runs.
#[test]
fn a_run_stopped_by_a_full_disk_says_so_in_its_manifest() {
    let dir = scratch("full-tmpfs");
    let path = variant("pendulum", &dir, |s| {
        s.run.end_time = 40.0;
        s.run.output_interval = 1.0;
    });
    let Some(disk) = SmallDisk::mount(&dir.join("disk"), 1 << 20) else {
        eprintln!("cannot mount a tmpfs here (not root?): the full-disk run is skipped");
        return;
    };
    let out = disk.0.join("run");
    let o = run(&path, &out);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    let monitors = out.join("monitors.csv");
    assert!(
        stderr.contains(&format!("cannot write {}", monitors.display())),
        "{stderr}"
    );
    let m = manifest(&out);
    assert_eq!(m["status"], "failed", "{stderr}");
    let error = m["error"].as_str().unwrap_or_default();
    assert!(error.contains("monitors.csv"), "{error}");
    let text = std::fs::read_to_string(&monitors).unwrap();
    assert!(text.ends_with('\n'), "a torn last row");
    assert_eq!(files_aside(&out), Vec::<std::path::PathBuf>::new());
    // A report that found no room is left out, never cut short: if there
    // is one, it ends with PNG's closing IEND chunk.
    if let Ok(png) = std::fs::read(out.join("monitors.png")) {
        assert!(
            png.ends_with(b"IEND\xae\x42\x60\x82"),
            "a torn monitors.png"
        );
    }
    drop(disk);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 42: far from 0 s the clock is still exact where the scenario
/// check lets a run start: at 10^6 s (f64 steps of 1.2e-10 s, 8.6e6 to a
/// window), every row has its own time, start + k·window to a clock step,
/// and the outputs come every output_interval, not every window.
#[test]
fn a_run_far_from_time_zero_keeps_its_times_and_output_interval() {
    let dir = scratch("far-clock");
    let (start, window, every) = (1e6, 1e-3, 0.05);
    let path = variant("pendulum", &dir, |s| {
        s.run.start_time = start;
        s.run.end_time = start + 0.5;
        s.run.output_interval = every;
        s.coupling.window = window;
    });
    let out = dir.join("run");
    run_ok(&path, &out);
    let times = Monitors::read(&out).column("time");
    assert_eq!(times.len(), 501, "a row at the start and one per window");
    let step = start.next_up() - start;
    for (k, t) in times.iter().enumerate() {
        let exact = start + k as f64 * window;
        assert!(
            (t - exact).abs() <= 2.0 * step,
            "row {k}: {t} against {exact}"
        );
    }
    let pvd = std::fs::read_to_string(out.join("bodies.pvd")).unwrap();
    let outputs = pvd.matches("<DataSet").count();
    assert_eq!(outputs, 11, "0.5 s every 0.05 s, the first state too");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 42: a participant that fails before the first monitor row (it
/// leaves a file aside, as one killed while writing would) stops the run
/// with a message that says nothing was written rather than "outputs
/// written so far", and the file aside is gone.
#[test]
fn a_run_that_stops_before_its_first_row_says_so_and_leaves_no_file_aside() {
    let dir = scratch("fails-at-once");
    let out = dir.join("run");
    let quitter = dir.join("quitter.sh");
    let script = format!(
        "#!/bin/sh\n# Answers the check, then leaves files aside and fails.\n\
         [ \"$1\" = --check ] && exit 0\nmkdir -p {out}/vtk\n\
         : > {out}/bodies.pvd.tmp\n: > {out}/vtk/ball_000000.vtu.tmp\nexit 3\n",
        out = out.display()
    );
    std::fs::write(&quitter, script).unwrap();
    let mut perms = std::fs::metadata(&quitter).unwrap().permissions();
    std::os::unix::fs::PermissionsExt::set_mode(&mut perms, 0o755);
    std::fs::set_permissions(&quitter, perms).unwrap();
    let path = variant("pendulum", &dir, |s| {
        s.participants.get_mut("rigid").unwrap().program = quitter.display().to_string();
    });
    let o = run(&path, &out);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(!out.join("monitors.csv").exists(), "{stderr}");
    assert!(!stderr.contains("outputs written so far"), "{stderr}");
    assert!(
        stderr.contains("it stopped before its first monitor row: no output was written"),
        "{stderr}"
    );
    assert_eq!(files_aside(&out), Vec::<std::path::PathBuf>::new());
    std::fs::remove_dir_all(&dir).unwrap();
}
