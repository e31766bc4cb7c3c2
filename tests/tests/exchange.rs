//! The coupling exchange between real processes: the schedule each
//! participant sees, failure handling, isolation of runs. (Bit-exact
//! fields: `participant/tests/exchange.rs`.)

use canopy_tests::*;
use std::time::{Duration, Instant};

/// Sub-steps a participant reported taking, from the manifest.
fn substeps(manifest: &serde_json::Value, role: &str) -> u64 {
    let p = manifest["processes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["role"] == role)
        .unwrap();
    p["substeps"].as_u64().unwrap()
}

/// Run a variant of a shipped scene into `dir/<name>`; its manifest and window count.
fn run_variant(
    scene: &str,
    dir: &std::path::Path,
    change: impl FnOnce(&mut canopy_tests::Scenario),
) -> (serde_json::Value, u64) {
    let path = variant(scene, dir, change);
    let out = dir.join(scene);
    run_ok(&path, &out);
    let m = manifest(&out);
    let windows = m["schedule"]["windows"].as_u64().unwrap();
    (m, windows)
}

#[test]
fn each_participant_sees_the_scheduled_substeps() {
    let dir = scratch("counts");
    let (m, windows) = run_variant("pendulum", &dir, |s| {
        s.run.end_time = 0.05;
        s.coupling.window = 1e-3;
        s.structure_mut().substeps = 6;
        s.coupling.impulse_substeps = 3;
    });
    assert_eq!(windows, 50);
    assert_eq!(substeps(&m, "structure"), windows * 6);
    assert_eq!(substeps(&m, "rigid"), windows * 3);

    let (m, windows) = run_variant("canopy-porous", &dir, |s| {
        s.run.end_time = 0.1;
        s.structure_mut().substeps = 5;
    });
    assert_eq!(windows, 50);
    assert_eq!(substeps(&m, "fluid"), windows);
    assert_eq!(substeps(&m, "structure"), windows * 5);
}

/// Children of `pid`, from /proc.
fn children_of(pid: u32) -> Vec<(u32, String)> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir("/proc").unwrap().flatten() {
        let Ok(p) = entry.file_name().to_string_lossy().parse::<u32>() else {
            continue;
        };
        let Ok(stat) = std::fs::read_to_string(format!("/proc/{p}/stat")) else {
            continue;
        };
        // pid (comm) state ppid …: comm may hold spaces, so split after the last ')'.
        let Some(close) = stat.rfind(')') else {
            continue;
        };
        let fields: Vec<&str> = stat[close + 2..].split_whitespace().collect();
        if fields.get(1).and_then(|f| f.parse::<u32>().ok()) == Some(pid) {
            let comm = stat[stat.find('(').unwrap() + 1..close].to_string();
            out.push((p, comm));
        }
    }
    out
}

fn alive(pid: u32) -> bool {
    // SAFETY: signal 0 only checks that the process exists.
    unsafe { libc::kill(pid as i32, 0) == 0 }
}

#[test]
fn a_killed_participant_fails_the_run_within_two_seconds() {
    let dir = scratch("sigkill");
    let (mut coupler, kids, out) = start_long_run(&dir, 60.0);
    std::thread::sleep(Duration::from_millis(300));
    let (victim, _) = kids
        .iter()
        .find(|(_, c)| c.starts_with("structure"))
        .expect("structure-proc runs")
        .clone();
    let killed = Instant::now();
    // SAFETY: plain syscall on a child of the coupler we started.
    unsafe { libc::kill(victim as i32, libc::SIGKILL) };
    let status = coupler.wait().unwrap();
    let took = killed.elapsed();
    let mut stderr = String::new();
    std::io::Read::read_to_string(coupler.stderr.as_mut().unwrap(), &mut stderr).unwrap();

    assert!(!status.success(), "the run must fail");
    assert_eq!(status.code(), Some(1));
    assert!(took < Duration::from_secs(2), "took {took:?}");
    assert!(
        stderr.contains("participant `structure`") && stderr.contains("SIGKILL"),
        "message: {stderr}"
    );
    for (pid, comm) in &kids {
        assert!(!alive(*pid), "{comm} ({pid}) is still alive");
    }
    let m = manifest(&out);
    assert_eq!(m["status"], "failed");
    assert_eq!(m["culprit"], "structure");
    let run_id = m["run_id"].as_str().unwrap();
    assert_eq!(
        participant::supervisor::services_of_run(run_id),
        Vec::<String>::new(),
        "stale services left"
    );
    // What was written stays readable.
    let monitors = Monitors::read(&out);
    assert!(monitors.rows.len() > 1);
}

#[test]
fn two_runs_of_one_scenario_at_once_do_not_interfere() {
    let dir = scratch("twice");
    let path = variant("pendulum", &dir, |s| s.run.end_time = 1.0);
    let start = |name: &str| {
        run_command(&path, &dir.join(name))
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap()
    };
    let (mut a, mut b) = (start("a"), start("b"));
    assert!(a.wait().unwrap().success() && b.wait().unwrap().success());
    let (ma, mb) = (manifest(&dir.join("a")), manifest(&dir.join("b")));
    assert_ne!(ma["run_id"], mb["run_id"]);
    // Deterministic physics: both runs produce the same monitors, bit for bit.
    let read = |n: &str| std::fs::read_to_string(dir.join(n).join("monitors.csv")).unwrap();
    assert_eq!(read("a"), read("b"));
}

/// Start a long pendulum run and wait until both participants are up.
fn start_long_run(
    dir: &std::path::Path,
    timeout: f64,
) -> (std::process::Child, Vec<(u32, String)>, std::path::PathBuf) {
    let path = variant("pendulum", dir, |s| {
        s.run.end_time = 1e5;
        s.coupling.timeout = timeout;
    });
    let out = dir.join("run");
    let child = run_command(&path, &out)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let started = Instant::now();
    loop {
        let kids = children_of(child.id());
        let rows = std::fs::read_to_string(out.join("monitors.csv"))
            .map(|t| t.lines().count())
            .unwrap_or(0);
        if kids.len() == 2 && rows > 1 {
            return (child, kids, out);
        }
        assert!(
            started.elapsed() < Duration::from_secs(20),
            "the run did not start"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn a_participant_that_stops_answering_fails_the_run_after_the_timeout() {
    let dir = scratch("hang");
    let (mut coupler, kids, out) = start_long_run(&dir, 1.0);
    let (victim, _) = kids
        .iter()
        .find(|(_, c)| c.starts_with("rigid"))
        .unwrap()
        .clone();
    // SAFETY: plain syscall on a child of the coupler we started.
    unsafe { libc::kill(victim as i32, libc::SIGSTOP) };
    let status = coupler.wait().unwrap();
    let mut stderr = String::new();
    std::io::Read::read_to_string(coupler.stderr.as_mut().unwrap(), &mut stderr).unwrap();
    assert_eq!(status.code(), Some(1));
    assert!(
        stderr.contains("participant `rigid` did not answer within 1.0 s"),
        "{stderr}"
    );
    for (pid, comm) in &kids {
        assert!(!alive(*pid), "{comm} ({pid}) is still alive");
    }
    assert_eq!(manifest(&out)["culprit"], "rigid");
}

#[test]
fn ctrl_c_stops_everything_cleanly() {
    let dir = scratch("ctrlc");
    let (mut coupler, kids, out) = start_long_run(&dir, 60.0);
    // SAFETY: plain syscall on the coupler we started.
    unsafe { libc::kill(coupler.id() as i32, libc::SIGINT) };
    let status = coupler.wait().unwrap();
    assert_eq!(status.code(), Some(130));
    for (pid, comm) in &kids {
        assert!(!alive(*pid), "{comm} ({pid}) is still alive");
    }
    let m = manifest(&out);
    assert_eq!(m["status"], "interrupted");
    assert_eq!(
        participant::supervisor::services_of_run(m["run_id"].as_str().unwrap()),
        Vec::<String>::new()
    );
    assert!(Monitors::read(&out).rows.len() > 1);
}

#[test]
fn three_participants_exchange_every_field_each_sub_step() {
    use canopy_tests::ParticipantSpec;
    use rigid_section::{BodySpec, RigidSection};
    use structure_section::StringSpec;
    // The porous canopy plus a payload hanging from a string: fluid, structure and
    // rigid all take part, with two impulse sub-steps per window.
    let dir = scratch("three");
    let (m, windows) = run_variant("canopy-porous", &dir, |s| {
        s.run.end_time = 0.1;
        s.structure_mut().substeps = 4;
        s.coupling.impulse_substeps = 2;
        s.participants
            .insert("rigid", ParticipantSpec::program("rigid-proc"));
        s.structure.as_mut().unwrap().strings.push(StringSpec {
            anchor: [0.0, 0.0, -1.0],
            body: "payload".into(),
            stiffness: 1e4,
            rest_length: 1.0,
            compressive_tolerance: 0.0,
            body_point: [0.0; 3],
        });
        s.rigid = Some(RigidSection {
            gravity: [0.0, 0.0, -9.81],
            restitution: None,
            bodies: vec![BodySpec {
                name: "payload".into(),
                mass: Some(1.0),
                position: [0.0, 0.0, -2.0],
                ..Default::default()
            }],
        });
    });
    assert_eq!(substeps(&m, "fluid"), windows);
    assert_eq!(substeps(&m, "structure"), windows * 4);
    assert_eq!(substeps(&m, "rigid"), windows * 2);
    // The payload hangs on its string: it stays within the string's stretch of z = −2 m.
    let z = Monitors::read(&dir.join("canopy-porous")).column("rigid.payload.z");
    assert!(
        z.iter().all(|z| (z + 2.0).abs() < 5e-3),
        "payload left its string: {:?}",
        z.last()
    );
}

#[test]
fn participants_do_not_outlive_a_killed_coupler() {
    let dir = scratch("orphans");
    let (mut coupler, kids, out) = start_long_run(&dir, 60.0);
    let run_id = manifest(&out)["run_id"].as_str().unwrap().to_string();
    // SAFETY: plain syscall on the coupler we started.
    unsafe { libc::kill(coupler.id() as i32, libc::SIGKILL) };
    coupler.wait().unwrap();
    let started = Instant::now();
    // They die with their parent (PR_SET_PDEATHSIG); init reaps them.
    while kids.iter().any(|(pid, _)| alive(*pid) && !zombie(*pid)) {
        assert!(
            started.elapsed() < Duration::from_secs(2),
            "participants outlived the coupler: {kids:?}"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    // What the dead processes left is cleaned as the next run starts. A run
    // another test starts meanwhile may be cleaning the same dead nodes, and
    // iceoryx2 lets one cleaner at a time: ours then gives up on them after
    // its wait, so try again until they are gone or the bound passes.
    let started = Instant::now();
    loop {
        participant::supervisor::cleanup_dead_nodes();
        let left = participant::supervisor::services_of_run(&run_id);
        if left.is_empty() {
            break;
        }
        assert!(
            started.elapsed() < ORPHANS_CLEANED_WITHIN,
            "the killed run's services were not cleaned within {ORPHANS_CLEANED_WITHIN:?}: {left:?}"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// How long the services of a killed run may outlive it when other runs
/// clean at the same time: two of `cleanup_dead_nodes`' bounds.
const ORPHANS_CLEANED_WITHIN: Duration = Duration::from_secs(10);

fn zombie(pid: u32) -> bool {
    std::fs::read_to_string(format!("/proc/{pid}/stat"))
        .map(|s| {
            s.rsplit(')')
                .next()
                .unwrap_or("")
                .trim_start()
                .starts_with('Z')
        })
        .unwrap_or(true)
}
