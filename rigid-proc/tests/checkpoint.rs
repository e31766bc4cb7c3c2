//! A window taken again from its checkpoint, with the same inputs, ends
//! bit for bit where the first try did: what implicit coupling needs to
//! repeat a window until the interface converges. The window holds the
//! oblique, off-centre impact of `contact.rs` and an attachment impulse.

use rigid_proc::checkpoint::Checkpoint;
use rigid_proc::Bodies;
use rigid_section::RigidSection;

mod common;

/// Step [s]; steps before the window and in it (the bodies meet at about
/// 0.13 s, inside the window).
const H: f64 = 1e-4;
const BEFORE: usize = 1000;
const WINDOW: usize = 600;

/// Every body's state as bits, and the contact count.
fn outcome(b: &Bodies) -> (Vec<u64>, u64) {
    let mut bits = Vec::new();
    for body in &b.bodies {
        let s = body.state;
        let values = s.x.iter().chain(&s.v).chain(s.e.iter()).chain(&s.w);
        bits.extend(values.map(|x| x.to_bits()));
    }
    (bits, b.contact_impulses)
}

fn window(b: &mut Bodies) {
    for k in 0..WINDOW {
        // A structure's pull on the block, changing from step to step.
        let pull = [0.0, 0.0, 1e-3 * (k as f64).sin()];
        b.step(H, &pull, &[]);
    }
}

#[test]
fn a_window_repeated_from_its_checkpoint_ends_bit_for_bit_alike() {
    // The impact of `contact.rs`, under gravity and half elastic.
    let mut section: RigidSection = toml::from_str(common::IMPACT).unwrap();
    section.gravity = [0.0, 0.0, -9.81];
    section.restitution = Some(0.5);
    let attached = [rigid_section::AttachmentSpec {
        body: "block".into(),
        point: [0.2, 0.0, 0.0],
    }];
    let mut b = Bodies::new(&section, &attached).unwrap();
    for _ in 0..BEFORE {
        b.step(H, &[0.0; 3], &[]);
    }
    assert_eq!(b.contact_impulses, 0, "they meet in the window, not before");
    let mut saved = Checkpoint::default();
    b.save(&mut saved);
    window(&mut b);
    let end = outcome(&b);
    assert!(end.1 > 0, "they meet in the window");
    b.restore(&saved);
    assert_eq!(b.contact_impulses, 0);
    window(&mut b);
    assert!(outcome(&b) == end, "the repeated window ends elsewhere");
}
