//! The structure on a GPU (the `structure-gpu` crate, dissertation
//! chapter 5): which networks the device path takes so far, and a
//! network as the device reads it.

use crate::forces::damping::Law;
use crate::network::{Network, NodeKind};

/// What of a network the device path does not take yet.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("the GPU path does not take {0} yet (springs, strings, dampers and gravity only)")]
pub struct Unsupported(pub &'static str);

/// `net` as the device reads it, or the first part it does not take.
pub fn network(net: &Network) -> Result<structure_gpu::Network, Unsupported> {
    if !net.membrane.is_empty() {
        return Err(Unsupported("Delingette membranes"));
    }
    if net.porous.is_some() {
        return Err(Unsupported("the porous load"));
    }
    if net.kind.iter().any(|k| matches!(k, NodeKind::Attached(_))) {
        return Err(Unsupported("nodes attached to rigid bodies"));
    }
    let springs = net.springs.iter().map(|s| structure_gpu::Spring {
        i: s.i,
        j: s.j,
        k: s.k,
        rest: s.rest,
        tension_only: s.tension_only,
        eps: s.eps,
    });
    let dampers = net.dampers.iter().map(|d| structure_gpu::Damper {
        i: d.i,
        j: d.j,
        c: d.c,
        slack_below: d.slack_below,
    });
    Ok(structure_gpu::Network {
        mass: net.mass.clone(),
        inv_mass: net.inv_mass.clone(),
        gravity: net.gravity,
        springs: springs.collect(),
        dampers: dampers.collect(),
        damping: net.damping.map(|law| match law {
            Law::RelativeVelocity => structure_gpu::DampingLaw::RelativeVelocity,
            Law::Axial => structure_gpu::DampingLaw::Axial,
        }),
    })
}
