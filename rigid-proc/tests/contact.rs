//! An oblique, off-centre impact (dissertation §3.4, eqs. 3.28–3.31 in their
//! rigid-body form): the impulse conserves linear and angular momentum, and
//! with C_R = 1 the kinetic energy, rotation included.

use rigid_proc::Bodies;
use rigid_section::RigidSection;

mod common;

#[test]
fn an_elastic_off_centre_impact_keeps_momentum_angular_momentum_and_energy() {
    let section: RigidSection = toml::from_str(common::IMPACT).unwrap();
    let mut b = Bodies::new(&section, &[]).unwrap();
    let (p0, l0, e0) = (b.momentum(), b.angular_momentum(), b.kinetic_energy());
    let spin0 = b.bodies[0].world_angular_velocity();
    let h = 1e-4;
    for _ in 0..4000 {
        b.step(h, &[], &[]);
    }
    assert!(b.contact_impulses >= 1, "they never met");
    // The block was hit off its centre: its spin changed.
    assert!((b.bodies[0].world_angular_velocity() - spin0).norm() > 0.1);
    assert!(
        (b.momentum() - p0).norm() < 1e-13 * p0.norm(),
        "momentum {} vs {p0}",
        b.momentum()
    );
    // Angular momentum about the origin: the impulse pair has no net moment,
    // and free flight keeps it (the RK4 rotation to its 1e-10 accuracy).
    assert!(
        (b.angular_momentum() - l0).norm() < 1e-9 * l0.norm(),
        "L {} vs {l0}",
        b.angular_momentum()
    );
    assert!(
        (b.kinetic_energy() / e0 - 1.0).abs() < 1e-9,
        "energy {} vs {e0}",
        b.kinetic_energy()
    );
}
