//! The incompressible flow a scenario's `[fluid]` section describes.

use crate::grid::Grid;
use crate::incompressible::{FlowSetup, Incompressible};
use crate::side::{bcs, Side};
use coupler::scenario::flow::SideSpec;
use coupler::scenario::FluidSection;

/// The flow of `[fluid]` with model = "incompressible", at its initial
/// velocity (None when the section has no box, which the scenario check
/// refuses for this model).
pub fn flow_from(section: &FluidSection) -> Option<Incompressible> {
    let b = section.flow_box?;
    let sides = section.resolved_sides()?.map(|s| {
        s.map(|s| match s {
            SideSpec::Wall => Side::WALL,
            SideSpec::Velocity(v) => Side::Velocity(v),
            SideSpec::Outflow => Side::Outflow,
            SideSpec::Periodic => Side::Periodic,
        })
    });
    let grid = Grid {
        n: b.cells.map(|n| n as usize),
        h: b.spacing(),
        bc: bcs(&sides),
    };
    let mut flow = Incompressible::new(FlowSetup {
        grid,
        sides,
        density: section.density,
        nu: section.viscosity / section.density,
    });
    if let Some(v) = section.initial_velocity {
        for (u, v) in flow.u.u.iter_mut().zip(v) {
            u.fill(v);
        }
        flow.impose_sides();
    }
    Some(flow)
}
