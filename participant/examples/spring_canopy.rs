//! A structure solver written from docs/PROTOCOL.md alone: the annulus canopy as springs with
//! lumped masses under the fluid's pressure jump and gravity, by symplectic Euler with the thesis
//! eq. (68) damping. `cargo build --release -p participant --example spring_canopy`.

use participant::{Cadence, Command, Declaration, Monitor, Participant};
use scenario::{section, ScenarioError};
use std::{collections::BTreeMap, f64::consts::PI, path::Path};

type V3 = [f64; 3];
/// The keys it reads. structure-proc's `integrator` and `damping` may stay in
/// the table (unknown keys are left here, not below): it has one method.
#[derive(serde::Deserialize)]
struct Structure {
    gravity: V3,
    substeps: u32,          // sub-steps a window: a structure's own clock
    steps_per_substep: u32, // this solver's own key
    annulus: Annulus,
}
#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Annulus {
    inner_radius: f64,
    outer_radius: f64,
    rings: usize,
    outer_nodes: usize,
    fabric: Fabric,
}
#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Fabric {
    stiffness: f64,
    areal_density: f64,
}
/// `[structure]`, read and checked with canopy's messages (file:line: key).
fn load(name: &str, path: &Path, text: &str) -> Result<Structure, ScenarioError> {
    let s: Structure = section::read(path, text, name)?
        .ok_or_else(|| section::missing(path, name, "spring_canopy"))?;
    section::checked(path, text, |c| {
        c.within(name, None, |c| {
            c.nonzero(&["substeps"], s.substeps as f64);
            c.nonzero(&["steps_per_substep"], s.steps_per_substep as f64);
            c.positive(&["annulus", "fabric", "stiffness"], s.annulus.fabric.stiffness, "N/m");
        })
    })?;
    Ok(s)
}

/// The annulus of PROTOCOL.md: rings from the inside, counter-clockwise, odd ones turned by half a
/// spacing, stitched in angle order, normals along +z. Positions, triangles, each ring's first node.
fn annulus(a: &Annulus) -> (Vec<V3>, Vec<[usize; 3]>, Vec<usize>) {
    let r =
        |i| a.inner_radius + (a.outer_radius - a.inner_radius) * i as f64 / (a.rings - 1) as f64;
    let n = |i| ((a.outer_nodes as f64 * r(i) / a.outer_radius).round() as usize).max(6);
    let th = |i, k| PI * (i % 2) as f64 / n(i) as f64 + 2.0 * PI * k as f64 / n(i) as f64;
    let (mut x, mut first, mut tris) = (vec![], vec![], vec![]);
    for i in 0..a.rings {
        first.push(x.len());
        x.extend((0..n(i)).map(|k| [r(i) * th(i, k).cos(), r(i) * th(i, k).sin(), 0.0]));
    }
    for i in 0..a.rings - 1 {
        let (sa, sb, na, nb, mut ia, mut ib) = (first[i], first[i + 1], n(i), n(i + 1), 0, 0);
        while ia < na || ib < nb {
            let (a0, b0) = (sa + ia % na, sb + ib % nb);
            let on_a = ib == nb || (ia < na && th(i, ia + 1) <= th(i + 1, ib + 1));
            (ia, ib) = (ia + on_a as usize, ib + !on_a as usize);
            tris.push([a0, b0, if on_a { sa + ia % na } else { sb + ib % nb }]);
        }
    }
    (x, tris, first)
}

/// a − b, |d|, and (b − a) × (c − a): twice the area times the unit normal.
fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn norm(d: V3) -> f64 {
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}
fn area2(x: &[V3], t: &[usize; 3]) -> V3 {
    let (a, b) = (sub(x[t[1]], x[t[0]]), sub(x[t[2]], x[t[0]]));
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// The springs' network: masses, rest lengths by node pair, triangles, and how many nodes move
/// (those before the fixed rim).
struct Net {
    mass: Vec<f64>,
    springs: BTreeMap<(usize, usize), f64>,
    tris: Vec<[usize; 3]>,
    free: usize,
}

/// One sub-step of `h`: gravity, jump·area·n̂ (a third per vertex), springs with k·h·(v_j − v_i).
fn substep(s: &Structure, net: &Net, jump: &[f64], x: &mut [V3], v: &mut [V3], h: f64) {
    let k = s.annulus.fabric.stiffness;
    let mut f: Vec<V3> = net.mass.iter().map(|m| s.gravity.map(|g| m * g)).collect();
    for (t, jump) in net.tris.iter().zip(jump) {
        let a2 = area2(x, t);
        t.iter().for_each(|&i| (0..3).for_each(|c| f[i][c] += jump * a2[c] / 6.0));
    }
    for (&(i, j), rest) in &net.springs {
        let (d, len) = (sub(x[j], x[i]), norm(sub(x[j], x[i])));
        for c in 0..3 {
            let fc = k * (len - rest) * d[c] / len + k * h * (v[j][c] - v[i][c]);
            (f[i][c], f[j][c]) = (f[i][c] + fc, f[j][c] - fc);
        }
    }
    for i in 0..net.free {
        (0..3).for_each(|c| v[i][c] += h * f[i][c] / net.mass[i]);
        (0..3).for_each(|c| x[i][c] += h * v[i][c]);
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    scenario::answer_check_as(|name, path, text| {
        load(name, path, text).map(|_| scenario::Answer::with_restarts())
    });
    let joining = participant::connect()?;
    let s = load(joining.name(), joining.scenario_path(), joining.scenario())?;
    let (mut x, tris, first) = annulus(&s.annulus);
    let (n, vent, free) = (x.len(), first[1], first[s.annulus.rings - 1]); // the rim is fixed
    let timing = *joining.timing();
    let mut net = Net { mass: vec![0.0; n], springs: BTreeMap::new(), tris, free };
    for t in &net.tris {
        for e in 0..3 {
            net.mass[t[e]] += s.annulus.fabric.areal_density * 0.5 * norm(area2(&x, t)) / 3.0;
            let (i, j) = (t[e].min(t[(e + 1) % 3]), t[e].max(t[(e + 1) % 3]));
            net.springs.insert((i, j), norm(sub(x[i], x[j])));
        }
    }
    let tris = &net.tris;
    let mut p = joining.declare(
        Declaration::new(Cadence::PerWindow { substeps: s.substeps })
            .writes("canopy.triangles", 3, tris.len())
            .writes("canopy.positions", 3, n)
            .writes("canopy.velocities", 3, n)
            .reads("canopy.pressure") // a fluid must take part
            .monitors(["kinetic_energy", "centre_deflection"])
            .checkpoints() // it can take a window again: implicit coupling works
            .restarts(), // and write its state to disk: run checkpoints work
    )?;
    let (mut v, mut jump) = (vec![[0.0; 3]; n], vec![0.0; tris.len()]);
    let mut saved = (x.clone(), v.clone()); // the window's start, for implicit coupling
    let window_end = |p: &mut Participant, x: &[V3], v: &[V3]| {
        p.write_field("canopy.positions", 3 * n, |o| o.copy_from_slice(x.as_flattened()))?;
        p.write_field("canopy.velocities", 3 * n, |o| o.copy_from_slice(v.as_flattened()))?;
        let ke = (0..n).map(|i| 0.5 * net.mass[i] * norm(v[i]).powi(2)).sum();
        let centre = x[..vent].iter().map(|p| p[2]).sum::<f64>() / vent as f64; // the vent's mean
        p.done(vec![Monitor::new("kinetic_energy", ke), Monitor::new("centre_deflection", centre)])
    };
    loop {
        let command = p.next_command()?;
        match command {
            Command::Initialize | Command::Resume { .. } => {
                if let Command::Resume { window } = command {
                    (x, v) = participant::restart::read(&p.state_file(window))?;
                }
                let flat: Vec<f64> = tris.concat().iter().map(|&i| i as f64).collect();
                p.write_field("canopy.triangles", flat.len(), |o| o.copy_from_slice(&flat))?;
                window_end(&mut p, &x, &v)?;
            }
            Command::Advance(step) => {
                jump.copy_from_slice(&p.read_field("canopy.pressure")?); // once a window
                let h = step.dt / (step.substeps * s.steps_per_substep) as f64;
                for _ in 0..step.substeps * s.steps_per_substep {
                    substep(&s, &net, &jump, &mut x, &mut v, h);
                }
                window_end(&mut p, &x, &v)?;
            }
            Command::SaveCheckpoint => {
                saved = (x.clone(), v.clone());
                p.done(vec![])?
            }
            Command::RestoreCheckpoint => {
                (x, v) = saved.clone();
                p.done(vec![])?
            }
            Command::WriteCheckpoint { window } => {
                participant::restart::write(&p.state_file(window), &(&x, &v))?;
                p.done(vec![])?
            }
            Command::Output { .. } => p.done(vec![])?,
            Command::Stop => break,
        }
    }
    Ok(p.finish(timing.windows() * u64::from(s.substeps * s.steps_per_substep))?)
}
