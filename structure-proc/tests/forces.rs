//! Force terms of the spring-mass model against their energies, the membrane
//! law against linear elasticity, and momentum conservation
//! (dissertation §2.3, thesis §2.1, §3.2).

mod common;

use common::*;
use std::f64::consts::PI;
use structure_proc::annulus::annulus;
use structure_proc::forces::damping::{Damper, Law};
use structure_proc::forces::delingette::{lame, TriangleSprings};
use structure_proc::forces::{elastic_energy, gravity_energy, Dynamics, Loads};
use structure_proc::rectangle::{rectangle, Edge};
use structure_proc::{Model, NodeKind, Spring, System};

#[test]
fn annulus_mesh_is_a_valid_annulus_of_about_703_nodes() {
    let m = annulus(0.1, 1.0, 12, 107, 0.0).unwrap();
    let nodes = m.points.len() / 3;
    assert!(
        (690..=720).contains(&nodes),
        "{nodes} nodes (thesis table 3: 703)"
    );
    // An annulus has Euler characteristic V − E + F = 0.
    let mut edges = std::collections::BTreeSet::new();
    let mut area = 0.0;
    for t in &m.triangles {
        for k in 0..3 {
            let (i, j) = (t[k], t[(k + 1) % 3]);
            edges.insert((i.min(j), i.max(j)));
        }
        let n = structure_proc::forces::area_normal2(&m.points, t);
        assert!(n[2] > 0.0, "every triangle faces +z");
        area += 0.5 * n[2];
    }
    assert_eq!(
        nodes as i64 - edges.len() as i64 + m.triangles.len() as i64,
        0
    );
    // Inscribed polygons lose a little area; within 1% of π(R² − r²).
    let exact = PI * (1.0 - 0.01);
    assert!((area / exact - 1.0).abs() < 0.01, "area {area} vs {exact}");
}

/// Central differences of `energy` against the force of the model without
/// damping or loads: F = −∂E/∂x for every free coordinate, relative 1e-6.
fn assert_force_is_minus_gradient(m: &Model, energy: impl Fn(&Model, &[f64]) -> f64) {
    let mut f = vec![0.0; m.x.len()];
    m.force(&Loads::default(), &mut f);
    let h = 1e-6;
    let scale = f.iter().fold(0.0f64, |a, b| a.max(b.abs())).max(1e-3);
    let mut worst: f64 = 0.0;
    for i in 0..m.x.len() {
        if m.kind[i / 3] != NodeKind::Free {
            continue;
        }
        let mut xp = m.x.clone();
        xp[i] += h;
        let mut xm = m.x.clone();
        xm[i] -= h;
        let grad = (energy(m, &xp) - energy(m, &xm)) / (2.0 * h);
        worst = worst.max((f[i] + grad).abs() / scale);
    }
    assert!(
        worst < 1e-6,
        "force differs from −∂E/∂x by {worst} of the largest force"
    );
}

#[test]
fn every_force_term_is_minus_the_gradient_of_its_energy() {
    // Hookean springs, uniform and k = A·E/l⁰ (thesis eqs. 67, 71).
    for e in [uniform(100.0), fibre(1e-6, 9.575e7)] {
        let mut m = canopy(e, [0.0; 3], None);
        deform(&mut m);
        assert_force_is_minus_gradient(&m, |m, x| elastic_energy(m, x));
    }
    // Delingette's triangular springs (dissertation eqs. 2.29–2.33).
    let mut m = canopy(membrane(1e6, 0.3, 1e-4), [0.0; 3], None);
    deform(&mut m);
    assert_force_is_minus_gradient(&m, |m, x| elastic_energy(m, x));
    // Gravity alone.
    let mut m = canopy(membrane(1e6, 0.3, 1e-4), [0.3, -1.0, -9.81], None);
    m.membrane.clear();
    m.prepare();
    deform(&mut m);
    assert_force_is_minus_gradient(&m, |m, x| gravity_energy(m, x));
    // Strings: tension only beyond the compressive tolerance (thesis eq. 3),
    // one taut and one slack inside its tolerance.
    let mut m = Model::default();
    for (x, kind, mass) in [
        ([0.0, 0.0, 0.0], NodeKind::Fixed, 0.0),
        ([0.3, 0.2, 1.1], NodeKind::Free, 1.0),
        ([0.3, 0.2, 1.6], NodeKind::Free, 1.0),
    ] {
        m.x.extend(x);
        m.v.extend([0.0; 3]);
        m.kind.push(kind);
        m.mass.push(mass);
    }
    for (i, j, rest) in [(0, 1, 1.0), (1, 2, 0.49)] {
        m.springs.push(Spring {
            i,
            j,
            k: 50.0,
            rest,
            tension_only: true,
            eps: 0.02,
        });
    }
    m.prepare();
    let mut f = vec![0.0; 9];
    m.force(&Loads::default(), &mut f);
    assert_eq!(
        &f[6..9],
        &[0.0; 3],
        "a string within its tolerance is slack"
    );
    assert_force_is_minus_gradient(&m, |m, x| elastic_energy(m, x));
}

/// The Jacobian product the implicit schemes use, against central differences
/// of the force: exact for springs under tension and for the dampers.
#[test]
fn jacobian_product_matches_finite_differences_of_the_force() {
    // The annulus with springs; a sheet of right triangles for the membrane,
    // whose edges all stay under tension when stretched (the product drops the
    // geometric stiffness of compressed edges on purpose).
    let sheet = {
        let mut m = membrane_sheet(0.0, 1e6, 0.3, 1e-4);
        m.dampers = m
            .membrane
            .iter()
            .flat_map(|t| t.edge_stiffness())
            .map(|(i, j, _)| Damper {
                i,
                j,
                c: 0.02,
                slack_below: 0.0,
            })
            .collect();
        m.damping = Some(Law::Axial);
        m.prepare();
        m
    };
    for mut m in [canopy(uniform(100.0), [0.0; 3], Some(Law::Axial)), sheet] {
        for n in 0..m.nodes() {
            // Radial stretch keeps every edge under tension.
            m.x[3 * n] *= 1.05;
            m.x[3 * n + 1] *= 1.05;
            m.x[3 * n + 2] = 0.02 * (5.0 * m.x[3 * n]).sin();
            m.v[3 * n + 2] = (3.0 * m.x[3 * n + 1]).cos();
        }
        // K at rest (the axial dashpot's direction depends on x only through
        // v ≠ 0, which the implicit solve leaves to Newton), C at speed.
        let mut at_rest = m.clone();
        at_rest.v.fill(0.0);
        for (model, a, b) in [(&at_rest, 1.0, 0.0), (&m, 0.0, 1.0)] {
            let loads = Loads::default();
            let sys = Dynamics {
                net: &model.net,
                loads: &loads,
            };
            let p: Vec<f64> = (0..model.x.len())
                .map(|i| ((i * 7919) % 13) as f64 / 13.0 - 0.5)
                .collect();
            let h = 1e-6;
            let shift = |s: f64| {
                let x: Vec<f64> = model.x.iter().zip(&p).map(|(x, p)| x + s * a * p).collect();
                let v: Vec<f64> = model.v.iter().zip(&p).map(|(v, p)| v + s * b * p).collect();
                let mut f = vec![0.0; x.len()];
                sys.force(&x, &v, &mut f);
                f
            };
            let (fp, fm) = (shift(h), shift(-h));
            let expect: Vec<f64> = fp
                .iter()
                .zip(&fm)
                .map(|(u, w)| -(u - w) / (2.0 * h))
                .collect();
            let mut out = vec![0.0; model.x.len()];
            sys.jacobian_product(&model.x, &model.v, a, b, &p, &mut out);
            let scale = expect.iter().fold(0.0f64, |s, v| s.max(v.abs()));
            let worst = out
                .iter()
                .zip(&expect)
                .fold(0.0f64, |s, (o, e)| s.max((o - e).abs()));
            assert!(
                worst < 1e-6 * scale,
                "(a, b) = ({a}, {b}): off by {worst} of {scale}"
            );
        }
    }
}

/// A 1 m × 0.5 m membrane sheet of 21 × 11 nodes, all free, unit masses;
/// `jitter` (fraction of the spacing) moves interior nodes to make the mesh
/// unstructured: angles and edge lengths vary from triangle to triangle.
fn membrane_sheet(jitter: f64, young: f64, nu: f64, t: f64) -> Model {
    let (len, width, nx, ny) = (1.0, 0.5, 21, 11);
    let mesh = rectangle(len, width, nx, ny, [0.0; 3]);
    let mut x = mesh.points.clone();
    let hx = len / (nx - 1) as f64;
    for j in 1..ny - 1 {
        for i in 1..nx - 1 {
            let n = mesh.node(i, j);
            let r = ((n * 2654435761) % 1000) as f64 / 1000.0;
            let s = ((n * 40503) % 997) as f64 / 997.0;
            x[3 * n] += jitter * hx * (r - 0.5);
            x[3 * n + 1] += jitter * hx * (s - 0.5);
        }
    }
    let (lambda, mu) = lame(young, nu, t);
    let mut m = Model {
        x: x.clone(),
        v: vec![0.0; x.len()],
        ..Default::default()
    };
    m.mass = vec![1.0; nx * ny];
    m.kind = vec![NodeKind::Free; nx * ny];
    for tri in &mesh.triangles {
        m.membrane
            .push(TriangleSprings::new(&x, *tri, lambda, mu).unwrap());
    }
    m.prepare();
    m
}

/// A homogeneous uniaxial stretch ε_x = ε, ε_y = −ν ε of a membrane strip must
/// leave interior nodes in equilibrium, need a total end force E·t·W·ε and no
/// lateral force (dissertation eqs. 2.29–2.32 against plane-stress elasticity).
fn check_uniaxial(jitter: f64) {
    let (young, nu, t) = (2.0e6, 0.3, 1.0e-4);
    let (len, width, nx, ny) = (1.0, 0.5, 21, 11);
    let mesh = rectangle(len, width, nx, ny, [0.0; 3]);
    let mut m = membrane_sheet(jitter, young, nu, t);
    let eps = 1e-4;
    for n in 0..nx * ny {
        m.x[3 * n] *= 1.0 + eps;
        m.x[3 * n + 1] *= 1.0 - nu * eps;
    }
    let mut f = vec![0.0; m.x.len()];
    m.force(&Loads::default(), &mut f);
    let end_force: f64 = mesh.edge(Edge::X1).iter().map(|&n| -f[3 * n]).sum();
    let expected = young * t * width * eps;
    assert!(
        (end_force / expected - 1.0).abs() < 0.02,
        "end force {end_force} N vs E·t·W·ε = {expected} N"
    );
    let lateral: f64 = mesh.edge(Edge::Y1).iter().map(|&n| f[3 * n + 1]).sum();
    assert!(
        lateral.abs() < 0.02 * expected * width / len,
        "lateral force {lateral} N"
    );
    let mut interior: f64 = 0.0;
    for j in 1..ny - 1 {
        for i in 1..nx - 1 {
            let n = mesh.node(i, j);
            interior = interior.max(f[3 * n].abs().max(f[3 * n + 1].abs()));
        }
    }
    assert!(
        interior < 0.02 * expected / ny as f64,
        "interior node force {interior} N"
    );
}

#[test]
fn delingette_membrane_stretches_as_the_continuum_on_a_regular_mesh() {
    check_uniaxial(0.0);
}

#[test]
fn delingette_membrane_stretches_as_the_continuum_on_an_unstructured_mesh() {
    check_uniaxial(0.5);
}

#[test]
fn degenerate_triangle_is_refused() {
    let x = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 2.0, 1e-12, 0.0];
    let err = TriangleSprings::new(&x, [0, 1, 2], 1.0, 1.0).unwrap_err();
    assert!(err.to_string().contains("degenerate"), "{err}");
}

/// Σ m v and Σ x × m v of a free network (no fixed node, no gravity).
fn momenta(m: &Model) -> ([f64; 3], [f64; 3]) {
    let (mut p, mut l) = ([0.0; 3], [0.0; 3]);
    for n in 0..m.nodes() {
        let x = &m.x[3 * n..3 * n + 3];
        let mv: Vec<f64> = (0..3).map(|c| m.mass[n] * m.v[3 * n + c]).collect();
        for c in 0..3 {
            p[c] += mv[c];
        }
        l[0] += x[1] * mv[2] - x[2] * mv[1];
        l[1] += x[2] * mv[0] - x[0] * mv[2];
        l[2] += x[0] * mv[1] - x[1] * mv[0];
    }
    (p, l)
}

fn free_canopy(e: Elasticity, law: Law) -> Model {
    let mut m = canopy(e, [0.0; 3], Some(law));
    for n in 0..m.nodes() {
        m.kind[n] = NodeKind::Free;
        m.mass[n] = 4e-3 * (1.0 + 0.5 * (n % 3) as f64);
        m.x[3 * n] *= 1.05;
        m.v[3 * n + 2] = (3.0 * m.x[3 * n]).sin();
        m.v[3 * n] = 0.3 * m.x[3 * n + 1];
    }
    m.prepare();
    m
}

#[test]
fn linear_momentum_is_conserved_to_round_off_by_every_integrator() {
    // Kang's eq. (55) weighs each node's neighbours by their own masses, so it
    // does not conserve momentum on uneven masses; it is left out.
    for scheme in all_schemes()
        .into_iter()
        .filter(|s| !matches!(s, Scheme::Kang))
    {
        for (e, law) in [
            (uniform(100.0), Law::RelativeVelocity),
            (membrane(1e5, 0.3, 1e-4), Law::Axial),
        ] {
            let mut m = free_canopy(e, law);
            let dt = 1e-3;
            let (p0, _) = momenta(&m);
            let mut integrator = structure_proc::integrator(scheme);
            for _ in 0..50 {
                m.step(integrator.as_mut(), &Loads::default(), dt).unwrap();
            }
            let (p1, _) = momenta(&m);
            let scale: f64 = (0..m.nodes())
                .map(|n| m.mass[n] * m.v[3 * n + 2].abs())
                .sum();
            // Implicit schemes: as exact as their conjugate-gradient solve.
            let tol = if is_newton(scheme) { 1e-9 } else { 1e-13 };
            for c in 0..3 {
                assert!(
                    (p1[c] - p0[c]).abs() < tol * scale,
                    "{scheme:?} component {c}: {} → {}",
                    p0[c],
                    p1[c]
                );
            }
        }
    }
}

#[test]
fn angular_momentum_is_conserved_to_round_off_by_the_symplectic_integrators() {
    // Springs, triangular springs and the dashpots of eq. (2.38) act along
    // edges, so they exert no net torque; Euler–Cromer and velocity Verlet keep
    // Σ x × m v exactly for such central forces. (Eq. 68's damping is not
    // central and does not conserve it.)
    for scheme in [Scheme::EulerCromer, Scheme::VelocityVerlet] {
        let mut m = free_canopy(membrane(1e5, 0.3, 1e-4), Law::Axial);
        m.springs.push(Spring {
            i: 0,
            j: 400,
            k: 30.0,
            rest: 0.5,
            tension_only: false,
            eps: 0.0,
        });
        m.dampers.push(Damper {
            i: 0,
            j: 400,
            c: 0.01,
            slack_below: 0.0,
        });
        m.prepare();
        let dt = 1e-3;
        let (_, l0) = momenta(&m);
        let mut integrator = structure_proc::integrator(scheme);
        for _ in 0..200 {
            m.step(integrator.as_mut(), &Loads::default(), dt).unwrap();
        }
        let (_, l1) = momenta(&m);
        let scale = l0.iter().map(|v| v.abs()).sum::<f64>();
        for c in 0..3 {
            assert!(
                (l1[c] - l0[c]).abs() < 1e-12 * scale,
                "{scheme:?} component {c}: {} → {}",
                l0[c],
                l1[c]
            );
        }
    }
}

/// Velocity Verlet keeps the force's position-only terms from the end of a
/// step to the start of the next (`forces/kept.rs`): its steps give the
/// same bits as fresh evaluations, on a damped membrane canopy (both
/// damping laws) under a pressure jump, with a taut string whose damper
/// acts above a slack length; and what was kept is forgotten when the
/// network changes and is prepared again (a line's stiffness, as a break
/// sets it).
#[test]
fn kept_position_terms_give_the_fresh_force_bit_for_bit() {
    use structure_proc::system::Afresh;
    for law in [Law::RelativeVelocity, Law::Axial] {
        let mut m = free_canopy(membrane(1e5, 0.3, 1e-4), law);
        let (i, j) = (0, 400);
        let span = (0..3)
            .map(|c| (m.x[3 * j + c] - m.x[3 * i + c]).powi(2))
            .sum::<f64>()
            .sqrt();
        m.springs.push(Spring {
            i,
            j,
            k: 30.0,
            rest: 0.9 * span,
            tension_only: true,
            eps: 0.0,
        });
        m.dampers.push(Damper {
            i,
            j,
            c: 0.01,
            slack_below: 0.9 * span,
        });
        m.prepare();
        let jumps: Vec<f64> = (0..m.triangles.len())
            .map(|k| 5.0 + (k % 7) as f64)
            .collect();
        let loads = Loads { pressure: &jumps };
        let dt = 1e-4;
        let mut fresh = m.clone();
        let mut kept_scheme = structure_proc::integrator(Scheme::VelocityVerlet);
        let mut fresh_scheme = structure_proc::integrator(Scheme::VelocityVerlet);
        for _ in 0..100 {
            m.step(kept_scheme.as_mut(), &loads, dt).unwrap();
            let sys = Dynamics {
                net: &fresh.net,
                loads: &loads,
            };
            fresh_scheme
                .step(&Afresh(&sys), dt, &mut fresh.x, &mut fresh.v)
                .unwrap();
            fresh.finish_step(fresh_scheme.reaction(), dt);
        }
        assert!(
            bits(&m.x) == bits(&fresh.x) && bits(&m.v) == bits(&fresh.v),
            "{law:?}: kept terms moved the state"
        );
        let moved =
            (0..m.x.len()).any(|k| m.x[k] != free_canopy(membrane(1e5, 0.3, 1e-4), law).x[k]);
        assert!(moved, "{law:?}: the canopy did not move");

        // The line's stiffness doubled and the network prepared again: the
        // next kept evaluation at the same positions sees it.
        let (mut kept, mut again) = (vec![0.0; m.x.len()], vec![0.0; m.x.len()]);
        let sys = Dynamics {
            net: &m.net,
            loads: &loads,
        };
        sys.force_keeping(&m.x, &m.v, &mut kept);
        let last = m.springs.len() - 1;
        m.springs[last].k *= 2.0;
        m.prepare();
        let sys = Dynamics {
            net: &m.net,
            loads: &loads,
        };
        sys.force_keeping(&m.x, &m.v, &mut kept);
        sys.force(&m.x, &m.v, &mut again);
        assert!(
            bits(&kept) == bits(&again),
            "{law:?}: a prepared network kept old terms"
        );
    }
}

/// The values' bits: −0 is not +0, and a NaN equals its own bits.
fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}
