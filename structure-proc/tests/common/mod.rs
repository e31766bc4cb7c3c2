//! Models shared by the structure tests.
#![allow(dead_code)]

use structure_proc::forces::damping::Law;
use structure_proc::Model;
pub use structure_section::{
    Annulus, Damping, Elasticity, Fabric, Fibre, Integrator, Membrane, NewtonParams, Scheme,
    StructureSection,
};

pub fn uniform(k: f64) -> Elasticity {
    Elasticity::Uniform(k)
}
pub fn fibre(area: f64, young_modulus: f64) -> Elasticity {
    Elasticity::Fibre(Fibre {
        area,
        young_modulus,
    })
}
pub fn membrane(young_modulus: f64, poisson_ratio: f64, thickness: f64) -> Elasticity {
    Elasticity::Membrane(Membrane {
        young_modulus,
        poisson_ratio,
        thickness,
    })
}

/// The annulus canopy of thesis §3.2 (rim fixed) with the given elasticity.
pub fn canopy(e: Elasticity, gravity: [f64; 3], damping: Option<Law>) -> Model {
    let (stiffness, fibre, membrane) = match e {
        Elasticity::Uniform(k) => (Some(k), None, None),
        Elasticity::Fibre(f) => (None, Some(f), None),
        Elasticity::Membrane(m) => (None, None, Some(m)),
    };
    let section = StructureSection {
        substeps: 1,
        integrator: Integrator::VelocityVerlet,
        device: Default::default(),
        newmark: Default::default(),
        hht: Default::default(),
        newton: Default::default(),
        adaptive: Default::default(),
        gravity,
        damping: match damping {
            None => Damping::None,
            Some(Law::RelativeVelocity) => Damping::RelativeVelocity,
            Some(Law::Axial) => Damping::Viscous,
        },
        damping_coefficient: (damping == Some(Law::Axial)).then_some(0.02),
        annulus: Some(Annulus {
            inner_radius: 0.1,
            outer_radius: 1.0,
            rings: 12,
            outer_nodes: 107,
            fabric: Fabric {
                areal_density: 1.0,
                stiffness,
                fibre,
                membrane,
            },
            height: 0.0,
        }),
        parachute: None,
        cloth: None,
        disk: None,
        cords: vec![],
        strings: vec![],
        points: vec![],
        springs: vec![],
        porous: None,
        collision: None,
    };
    structure_proc::build_model(&section, None, 1e-3).unwrap()
}

/// Bend and shear the canopy so every element is stretched or compressed.
pub fn deform(m: &mut Model) {
    for n in 0..m.nodes() {
        let (x, y) = (m.x[3 * n], m.x[3 * n + 1]);
        m.x[3 * n + 2] = 0.3 * (1.0 - x * x - y * y) + 0.01 * (7.0 * x).sin();
        m.x[3 * n] *= 1.0 + 0.02 * y;
    }
}

/// Every scheme with its parameters, Newmark in three variants.
pub fn all_schemes() -> Vec<Scheme> {
    let newton = NewtonParams::default();
    let mut v: Vec<Scheme> = Integrator::ALL
        .iter()
        .map(|&i| {
            Scheme::resolve(
                i,
                Default::default(),
                Default::default(),
                newton,
                Default::default(),
            )
        })
        .collect();
    // A first-order Newmark: γ ≠ 1/2.
    v.push(Scheme::Newmark {
        beta: 0.3,
        gamma: 0.6,
        alpha: 0.0,
        newton,
    });
    v
}

/// Whether the scheme solves with Newton iterations and conjugate gradients.
pub fn is_newton(s: Scheme) -> bool {
    matches!(s, Scheme::Newmark { .. } | Scheme::BackwardEuler { .. })
}

/// A network of free nodes at `x` with `mass`, the given triangles over all
/// nodes before `canopy`, and strings (springs) after.
pub fn network(
    x: &[f64],
    mass: &[f64],
    triangles: Vec<[usize; 3]>,
    canopy: usize,
    springs: &[(usize, usize)],
) -> structure_proc::network::Network {
    let mut net = structure_proc::network::Network {
        mass: mass.to_vec(),
        kind: mass
            .iter()
            .map(|&m| {
                if m > 0.0 {
                    structure_proc::NodeKind::Free
                } else {
                    structure_proc::NodeKind::Fixed
                }
            })
            .collect(),
        triangles,
        canopy_nodes: canopy,
        ..structure_proc::network::Network::default()
    };
    for &(i, j) in springs {
        let rest = (0..3)
            .map(|c| (x[3 * i + c] - x[3 * j + c]).powi(2))
            .sum::<f64>()
            .sqrt();
        net.springs.push(structure_proc::Spring {
            i,
            j,
            k: 100.0,
            rest,
            tension_only: true,
            eps: 0.0,
        });
    }
    net.prepare();
    net
}

/// The structure of `scenarios/c9-drop.toml`, its parachute changed by `change`.
pub fn c9_drop(change: impl FnOnce(&mut structure_section::Parachute)) -> StructureSection {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenarios/c9-drop.toml");
    let mut s = structure_section::Scene::load_file(std::path::Path::new(path), "structure-proc")
        .unwrap()
        .structure;
    change(s.parachute.as_mut().unwrap());
    s
}

/// Node `n`'s position.
pub fn point(m: &Model, n: usize) -> [f64; 3] {
    [m.x[3 * n], m.x[3 * n + 1], m.x[3 * n + 2]]
}

pub fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// One structure step of `dt` without loads, then the contact pass if given.
pub fn step(
    m: &mut structure_proc::Model,
    stepper: &mut dyn structure_proc::Integrator,
    contacts: Option<&mut structure_proc::collision::Contacts>,
    dt: f64,
) {
    let start = m.x.clone();
    m.step(stepper, &structure_proc::forces::Loads::default(), dt)
        .unwrap();
    if let Some(c) = contacts {
        c.begin_step(&start);
        let (mass, inv) = (m.net.mass.clone(), m.net.inv_mass.clone());
        c.resolve(&mut m.x, &mut m.v, &mass, &inv, dt).unwrap();
    }
}

/// The structure of a TOML `[structure]` section.
pub fn section(text: &str) -> structure_section::StructureSection {
    toml::from_str(text).unwrap()
}
