//! The incompressible flow a scenario's `[fluid]` section describes, at
//! its initial state.

use crate::comm::{Comm, Single};
use crate::incompressible::axis::Axis;
use crate::incompressible::grid::Grid;
use crate::incompressible::part::Part;
use crate::incompressible::side::{bcs, Side};
use crate::incompressible::{FlowSetup, Incompressible};
use fluid_section::flow::SideSpec;
use fluid_section::FluidSection;
use std::sync::Arc;

/// The flow of `[fluid]` with model = "incompressible", at its initial
/// velocity (None when the section has no box, which the scenario check
/// refuses for this model).
pub fn flow_from(section: &FluidSection) -> Option<Incompressible> {
    flow_on(section, Arc::new(Single))
}

/// [`flow_from`], this rank's slab of it (`part.rs`).
pub fn flow_on(section: &FluidSection, comm: Arc<dyn Comm>) -> Option<Incompressible> {
    let (grid, sides) = grid_of(section)?;
    let part = Part::on(comm, grid.n, sides);
    let setup = FlowSetup {
        grid,
        sides,
        density: section.density(),
        nu: section.viscosity() / section.density(),
    };
    let mut flow = Incompressible::on(setup, part);
    if let Some(v) = section.initial_velocity {
        for (u, v) in flow.u.u.iter_mut().zip(v) {
            u.fill(v);
        }
        flow.impose_sides();
    }
    Some(flow)
}

/// The whole box's grid and sides of `[fluid]` (None without a box).
pub fn grid_of(section: &FluidSection) -> Option<(Grid, [[Side; 2]; 3])> {
    let b = section.flow_box?;
    let mut sides = [[Side::WALL; 2]; 3];
    for (d, pair) in section.resolved_sides()?.iter().enumerate() {
        for (s, side) in pair.iter().enumerate() {
            sides[d][s] = match *side {
                SideSpec::Wall => Side::WALL,
                SideSpec::Velocity(v) => Side::Velocity(v),
                SideSpec::Parabolic(v) => Side::Parabolic(v),
                SideSpec::Outflow => Side::Outflow,
                SideSpec::Periodic => Side::Periodic,
                // A gas's side: the scenario check refuses it here.
                SideSpec::State(_) => return None,
            };
        }
    }
    let bc = bcs(&sides);
    let grid = match b.core {
        None => Grid::uniform(b.cells.map(|n| n as usize), b.spacing(), bc),
        Some(_) => {
            let axis = |d: usize| {
                let periodic = sides[d][0] == Side::Periodic;
                Some(Axis::of_widths(&b.widths(d)?, periodic))
            };
            Grid::of_axes([axis(0)?, axis(1)?, axis(2)?], bc)
        }
    };
    Some((grid, sides))
}
