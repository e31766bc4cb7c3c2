//! Speed of the spring-mass solver (issue 3, item 8), as `cargo bench -p structure-proc`:
//!
//! - `force/<threads>t/<springs>`: one evaluation of the total force on a cloth
//!   of 10³ to 10⁶ springs (edges and bending springs, no damping); the
//!   throughput criterion prints is spring updates per second;
//! - `step/<threads>t/cloth-100x100`: one Euler–Cromer step (one force
//!   evaluation) of the 100 × 100 cloth, about 59 000 springs;
//! - `implicit-vs-explicit/…`: the cloth-hanging scene on 100 × 100 nodes, one
//!   backward-Euler step of the scene's window against the velocity-Verlet
//!   sub-steps that cover the same window at the explicit stability limit.

mod common;

use common::{cloth_section, spring_cloth};
use criterion::{
    black_box, criterion_group, criterion_main, BatchSize, BenchmarkId, Criterion, Throughput,
};
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

criterion_group!(benches, force, step, implicit_vs_explicit);
criterion_main!(benches);
