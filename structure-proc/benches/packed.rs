//! The contact pass over a packed opening (issue 46, item 2), as
//! `cargo bench -p structure-proc --bench packed`: the C-9 of
//! `scenarios/c9-deploy.toml`, packed at line stretch into a bundle 1 m
//! across (its gores pleated along the axis), first pressed on from
//! outside for [`CRUSH`] s by a quarter of the ram air's pressure (its
//! folds forced onto each other), then blown open from inside by the
//! whole of it, for [`OPENING`] s in all with its sub-steps, two threads,
//! with the collision pass of `[structure.collision]` (its layer
//! [`THICKNESS`]) in each model, and without it. Per row:
//!
//! - `step µs`: the structure's own sub-step (the integrator and its force
//!   evaluation), the mean over the opening;
//! - `contact µs` and `contact/step`: the contact pass per sub-step and its
//!   ratio to the sub-step, the figure issue 46 asks to be at most 5;
//! - `crossings`: the most crossing pairs at any millisecond (parry's
//!   count, `collision/intersections.rs`), which the pass must keep at 0;
//! - `width`: the bundle's width across at the end [m], how far it opened.
//!
//! `PACKED_BENCH_OPENING=0.02` runs a shorter opening;
//! `PACKED_BENCH_MODEL=layered` one model.

use std::path::Path;
use std::time::Instant;
use structure_proc::collision::{intersections, Contacts, Surface};
use structure_proc::forces::Loads;
use structure_proc::stepper::{Scheme, Stepper};
use structure_proc::{build_model, Model};
use structure_section::collision::ContactModel;
use structure_section::Collision;

/// The jump across the fabric [Pa]: the ram air's ½ρv² at 40 m/s,
/// 0.5 · 1.225 · 40² ≈ 980 Pa, pressing the bundle open from inside.
const JUMP: f64 = 980.0;

/// Seconds of the opening ...
const OPENING: f64 = 0.05;

/// ... of which the first are pressed on from outside.
const CRUSH: f64 = 0.01;

/// The layer kept between features [m]: under the bundle's narrowest gap
/// between folds that share no node.
const THICKNESS: f64 = 2e-3;

fn section() -> structure_section::Scene {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenarios/c9-deploy.toml");
    structure_section::Scene::load_file(Path::new(path), "structure-proc")
        .expect("shipped scenario")
}

/// What one opening measured.
struct Opening {
    step: f64,
    contact: f64,
    crossings: usize,
    width: f64,
    stats: Option<structure_proc::collision::Stats>,
}

/// Open the bundle with the pass of `model`, or none.
fn opening(model: Option<ContactModel>, seconds: f64) -> Opening {
    let s = section();
    let h = s.structure.dt(s.scenario.coupling.window);
    let mut m: Model = build_model(&s.structure, None, h).expect("the C-9 builds");
    let mut scheme = Scheme::of(&s.structure);
    let crush = vec![-0.25 * JUMP; m.triangles.len()];
    let blow = vec![JUMP; m.triangles.len()];
    let spec = model.map(|model| Collision {
        model,
        thickness: THICKNESS,
        ..Collision::default()
    });
    let mut contacts = spec.map(|spec| Contacts::new(&m.net, &spec).expect("a surface"));
    let surface = Surface::of(&m.net);
    let steps = (seconds / h).round() as usize;
    let every = (1e-3 / h).round() as usize;
    let (mut step, mut contact, mut crossings) = (0.0, 0.0, 0);
    for k in 1..=steps {
        let t = Instant::now();
        if let Some(c) = &mut contacts {
            c.begin_step(&m.x);
        }
        let t1 = Instant::now();
        let jumps = if k as f64 * h <= CRUSH { &crush } else { &blow };
        let loads = Loads { pressure: jumps };
        scheme.step(&mut m, &loads, h).expect("sub-step");
        let t2 = Instant::now();
        if let Some(c) = &mut contacts {
            let (mass, inv) = (&m.net.mass, &m.net.inv_mass);
            c.resolve(&mut m.x, &mut m.v, mass, inv, h)
                .expect("the pass resolves");
        }
        let t3 = Instant::now();
        step += (t2 - t1).as_secs_f64();
        contact += (t1 - t).as_secs_f64() + (t3 - t2).as_secs_f64();
        if k % every == 0 {
            crossings = crossings.max(intersections(&surface, &m.x).total());
        }
    }
    Opening {
        step: step / steps as f64,
        contact: contact / steps as f64,
        crossings,
        width: width(&m),
        stats: contacts.map(|c| c.stats),
    }
}

/// The canopy's width across the axis [m]: twice its largest distance
/// from the axis through its mean.
fn width(m: &Model) -> f64 {
    let n = m.net.canopy_nodes;
    let (cx, cy) = (0..n).fold((0.0, 0.0), |(a, b), k| (a + m.x[3 * k], b + m.x[3 * k + 1]));
    let (cx, cy) = (cx / n as f64, cy / n as f64);
    let r = (0..n).map(|k| (m.x[3 * k] - cx).hypot(m.x[3 * k + 1] - cy));
    2.0 * r.fold(0.0, f64::max)
}

fn main() {
    let seconds: f64 = std::env::var("PACKED_BENCH_OPENING")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(OPENING);
    let all = [
        ("none", None),
        ("pairwise", Some(ContactModel::Pairwise)),
        ("layered", Some(ContactModel::Layered)),
    ];
    let chosen = std::env::var("PACKED_BENCH_MODEL").ok();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("pool");
    println!(
        "packed C-9 of c9-deploy.toml pressed by {} Pa for {CRUSH} s, then opened by {JUMP} Pa to {seconds} s; layer {THICKNESS} m, 2 threads (means per sub-step)",
        0.25 * JUMP
    );
    println!(
        "{:>9} {:>9} {:>11} {:>13} {:>10} {:>8}   impulses",
        "model", "step µs", "contact µs", "contact/step", "crossings", "width m"
    );
    for (name, model) in all {
        if chosen
            .as_deref()
            .is_some_and(|c| c != name && name != "none")
        {
            continue;
        }
        let o = pool.install(|| opening(model, seconds));
        println!(
            "{:>9} {:>9.1} {:>11.1} {:>13.2} {:>10} {:>8.2}   {:?}",
            name,
            o.step * 1e6,
            o.contact * 1e6,
            o.contact / o.step,
            o.crossings,
            o.width,
            o.stats.map(|s| (s.proximity, s.collisions, s.zone_steps)),
        );
    }
}
