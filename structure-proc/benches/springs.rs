//! Speed of the spring-mass solver (issue 3, item 8), as `cargo bench -p structure-proc`:
//!
//! - `force/<threads>t/<springs>`: one evaluation of the total force on a cloth
//!   of 10³ to 10⁶ springs (edges and bending springs, no damping); the
//!   throughput criterion prints is spring updates per second;
//! - `step/<threads>t/cloth-100x100`: one Euler–Cromer step (one force
//!   evaluation) of the 100 × 100 cloth, about 59 000 springs;
//! - `implicit-vs-explicit/…`: the cloth-hanging scene on 100 × 100 nodes, one
//!   backward-Euler step of the scene's window against the velocity-Verlet
//!   sub-steps that cover the same window at the explicit stability limit;
//! - with `WARP_PYTHON` set to a Python that has warp-lang (see
//!   `../shared/peers/README.md`): the peer's cloth step
//!   (`../shared/peers/warp_cloth.py`, or `WARP_CLOTH`) right before and right
//!   after canopy's, timed the peer's way (median of 200 steps after 20), and
//!   the ratio of spring updates per second.

mod common;

use common::{cloth_section, spring_cloth};
use criterion::{black_box, criterion_group, BatchSize, BenchmarkId, Criterion, Throughput};
use structure_proc::forces::Loads;
use structure_proc::{build_model, integrator, Model};
use structure_section::Integrator as Scheme;

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
}

fn force(c: &mut Criterion) {
    let mut g = c.benchmark_group("force");
    g.sample_size(20);
    // n × n nodes give about 5.9 n² springs.
    for n in [13, 41, 130, 412] {
        let m = spring_cloth(n);
        let mut f = vec![0.0; m.x.len()];
        g.throughput(Throughput::Elements(m.springs.len() as u64));
        for threads in [1, 2] {
            let p = pool(threads);
            let id = BenchmarkId::new(format!("{threads}t"), m.springs.len());
            g.bench_with_input(id, &m, |b, m| {
                p.install(|| b.iter(|| m.force(&Loads::default(), black_box(&mut f))))
            });
        }
    }
    g.finish();
}

fn step(c: &mut Criterion) {
    let mut g = c.benchmark_group("step");
    g.sample_size(30);
    let mut m = spring_cloth(100);
    let dt = 1e-5;
    g.throughput(Throughput::Elements(m.springs.len() as u64));
    for threads in [1, 2] {
        let p = pool(threads);
        let mut scheme = integrator(scheme_of(Scheme::EulerCromer));
        g.bench_function(format!("{threads}t/cloth-100x100"), |b| {
            p.install(|| b.iter(|| m.step(scheme.as_mut(), &Loads::default(), dt).unwrap()))
        });
    }
    g.finish();
}

fn scheme_of(i: Scheme) -> structure_section::Scheme {
    let mut section = cloth_section(2).0;
    section.integrator = i;
    section.scheme()
}

/// ω_max of dissertation eq. (3.7), node by node (Gershgorin's bound on M⁻¹K).
fn omega_max(m: &Model) -> f64 {
    structure_proc::stability::omega_max(&m.inv_mass, &m.couplings)
}

fn implicit_vs_explicit(c: &mut Criterion) {
    let mut g = c.benchmark_group("implicit-vs-explicit");
    g.sample_size(10);
    let (section, window) = cloth_section(100);
    let mut m = build_model(&section, None, window).expect("cloth builds");
    // Start from a cloth already falling, 0.05 s into the scene.
    let mut be = integrator(section.scheme());
    for _ in 0..25 {
        m.step(be.as_mut(), &Loads::default(), window).unwrap();
    }
    // Velocity Verlet is stable for ω·h < 2.
    let substeps = (window * omega_max(&m) / 2.0).ceil() as usize;
    eprintln!(
        "cloth 100 x 100: window {window} s, omega_max {:.3e} 1/s, {substeps} velocity-Verlet sub-steps",
        omega_max(&m)
    );
    g.bench_function("backward-euler/1-step", |b| {
        b.iter_batched(
            || m.clone(),
            |mut m| m.step(be.as_mut(), &Loads::default(), window).unwrap(),
            BatchSize::LargeInput,
        )
    });
    let mut vv = integrator(scheme_of(Scheme::VelocityVerlet));
    g.bench_function(format!("velocity-verlet/{substeps}-steps"), |b| {
        b.iter_batched(
            || m.clone(),
            |mut m| {
                for _ in 0..substeps {
                    m.step(vv.as_mut(), &Loads::default(), window / substeps as f64)
                        .unwrap();
                }
                m
            },
            BatchSize::LargeInput,
        )
    });
    g.finish();
}

/// Median time [s] of one Euler–Cromer step of the 100 × 100 spring cloth on
/// `threads` threads, the peer script's way: 200 steps after 20.
fn cloth_step_median(threads: usize) -> f64 {
    let mut m = spring_cloth(100);
    let mut scheme = integrator(scheme_of(Scheme::EulerCromer));
    pool(threads).install(|| {
        let mut times: Vec<f64> = (0..220)
            .map(|_| {
                let start = std::time::Instant::now();
                m.step(scheme.as_mut(), &Loads::default(), 1e-5).unwrap();
                start.elapsed().as_secs_f64()
            })
            .skip(20)
            .collect();
        times.sort_by(f64::total_cmp);
        times[times.len() / 2]
    })
}

/// warp-lang's step median [s] and spring count from its script's line
/// "… N springs … step median T ms …".
fn warp_step(python: &str, script: &str) -> Result<(f64, f64), String> {
    let out = std::process::Command::new(python)
        .arg(script)
        .output()
        .map_err(|e| format!("cannot run {python}: {e}"))?;
    let text = String::from_utf8_lossy(&out.stdout);
    let line = text
        .lines()
        .find(|l| l.contains("step median"))
        .ok_or_else(|| {
            format!(
                "{script} printed no step median: {text}{}",
                String::from_utf8_lossy(&out.stderr)
            )
        })?;
    let before = |key: &str| -> Option<f64> {
        let words: Vec<&str> = line.split([' ', ',']).filter(|w| !w.is_empty()).collect();
        let at = words.iter().position(|w| *w == key)?;
        words.get(at.checked_sub(1)?)?.parse().ok()
    };
    let after = |key: &str| -> Option<f64> {
        let rest = line.split(key).nth(1)?;
        rest.split_whitespace().next()?.parse().ok()
    };
    match (after("step median"), before("springs")) {
        (Some(ms), Some(springs)) => Ok((ms * 1e-3, springs)),
        _ => Err(format!("cannot read {line:?}")),
    }
}

/// The peer's cloth right before and right after canopy's (issue 25, item 4).
fn warp_side_by_side() {
    let Ok(python) = std::env::var("WARP_PYTHON") else {
        eprintln!("warp-lang side by side: skipped (set WARP_PYTHON to a Python with warp-lang)");
        return;
    };
    let script = std::env::var("WARP_CLOTH").unwrap_or_else(|_| {
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../shared/peers/warp_cloth.py"
        )
        .into()
    });
    let springs = spring_cloth(100).springs.len() as f64;
    let run = || warp_step(&python, &script).unwrap_or_else(|e| panic!("warp-lang: {e}"));
    let (before, peer_springs) = run();
    let ours = [1, 2].map(cloth_step_median);
    let (after, _) = run();
    let warp_rate = peer_springs / (0.5 * (before + after));
    println!("\n100 x 100 cloth, one step, side by side (medians of 200 steps):");
    println!(
        "  warp-lang cpu, 1 thread, f32, {peer_springs} springs: {:.3} ms before, {:.3} ms after",
        before * 1e3,
        after * 1e3
    );
    for (threads, t) in [1, 2].iter().zip(ours) {
        let rate = springs / t;
        println!(
            "  canopy Euler-Cromer, {threads} thread(s), f64, {springs} springs: {:.3} ms, {:.2e} spring updates/s, {:.2}x warp-lang",
            t * 1e3,
            rate,
            rate / warp_rate
        );
    }
}

criterion_group!(benches, force, step, implicit_vs_explicit);

fn main() {
    benches();
    warp_side_by_side();
    Criterion::default().configure_from_args().final_summary();
}
