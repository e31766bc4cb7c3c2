//! The gas a scenario's `[fluid]` section describes (model = "euler"),
//! at its initial state, with the scene's bodies in it.

use crate::comm::{Comm, Single, Slab};
use crate::euler::bodies::GasBody;
use crate::euler::gas::{Gas, Primitive};
use crate::euler::{Compressible, GasSetup, GasSide};
use exchange::Body;
use fluid_section::flow::{body_halo_cells, SideSpec};
use fluid_section::{FluidSection, Scene};
use std::sync::Arc;

/// The gas of `[fluid]` with model = "euler", each cell taking the last
/// region that holds its centre (None when the section lacks the box or
/// the regions, or has a side with a given velocity: the scenario check
/// refuses those for this model).
pub fn gas_from(section: &FluidSection) -> Option<Compressible> {
    gas_on(section, Arc::new(Single))
}

/// [`gas_from`], this rank's slab of it.
pub fn gas_on(section: &FluidSection, comm: Arc<dyn Comm>) -> Option<Compressible> {
    let b = section.flow_box?;
    let regions = section.regions.as_deref()?;
    let mut sides = [[GasSide::Wall; 2]; 3];
    for (d, pair) in section.resolved_sides()?.iter().enumerate() {
        for (s, side) in pair.iter().enumerate() {
            sides[d][s] = match side {
                SideSpec::Wall => GasSide::Wall,
                SideSpec::Outflow => GasSide::Outflow,
                SideSpec::Periodic => GasSide::Periodic,
                SideSpec::State(w) => GasSide::State(Primitive {
                    density: w.density,
                    velocity: w.velocity,
                    pressure: w.pressure,
                }),
                SideSpec::Velocity(_) | SideSpec::Parabolic(_) => return None,
            };
        }
    }
    let h = b.spacing();
    let setup = GasSetup {
        n: b.cells.map(|n| n as usize),
        h,
        sides,
        gas: Gas {
            gamma: section.gamma(),
        },
        cfl: section.cfl(),
    };
    let centre = |c: [usize; 3]| [0, 1, 2].map(|d| b.lower[d] + (c[d] as f64 + 0.5) * h[d]);
    // Every region's check passed, and the first covers the box.
    let region = |x| {
        regions
            .iter()
            .rev()
            .find(|r| r.contains(x))
            .unwrap_or(&regions[0])
    };
    Some(Compressible::on(setup, comm, |c| {
        let x = centre(c);
        let r = region(x);
        Primitive {
            density: r.density_at(x),
            velocity: r.velocity,
            pressure: r.pressure,
        }
    }))
}

/// The gas of a scene on this rank, and the bodies of its `[rigid]`
/// section.
pub struct GasScene {
    /// The gas of `[fluid]` (model = "euler"), the shaped bodies placed
    /// in it at their initial poses.
    pub gas: Compressible,
    /// Every `[[rigid.bodies]]` entry, as rigid-proc holds it.
    pub rigid: Vec<Body>,
    /// The index in `rigid` of each body in the gas (mass points have no
    /// surface and stay out of it), in the order of the gas's bodies.
    pub shaped: Vec<usize>,
    /// The box's low corner in the world [m].
    pub origin: [f64; 3],
}

/// The scene's gas on this rank with its bodies in it.
pub fn gas_scene(scene: &Scene, comm: Arc<dyn Comm>) -> Result<GasScene, String> {
    let section = &scene.fluid;
    let mut gas =
        gas_on(section, comm).ok_or("[fluid] lacks the box or the regions of the euler model")?;
    let rigid = scene
        .rigid
        .as_ref()
        .map_or(Ok(Vec::new()), |r| r.bodies())?;
    let origin = section.flow_box.map_or([0.0; 3], |b| b.lower);
    let spacing = gas.grid().finest();
    let mut shaped = Vec::new();
    for (i, body) in rigid.iter().enumerate() {
        if let Some(b) = GasBody::of(body, origin, gas.time, spacing) {
            gas.bodies.push(b);
            shaped.push(i);
        }
    }
    check_seen(&gas)?;
    if !gas.bodies.is_empty() {
        let (n, h) = (gas.setup.n, gas.setup.h);
        let planes = body_halo_cells(h, n.map(|n| n > 1), Slab::axis(n));
        gas.widen_halo(planes as usize);
    }
    gas.place_bodies();
    Ok(GasScene {
        gas,
        rigid,
        shaped,
        origin,
    })
}

/// Whether the gas can see each of its bodies: a 2-D or 3-D box (the
/// scenario check refuses a 1-D one), and a body across a 2-D box's
/// mid-plane.
fn check_seen(gas: &Compressible) -> Result<(), String> {
    let varies = gas.setup.n.iter().filter(|&&n| n > 1).count();
    if varies < 2 && !gas.bodies.is_empty() {
        return Err(
            "a body with a shape needs a gas box more than one cell thick along \
                    at least two axes (a 2-D or 3-D flow)"
                .into(),
        );
    }
    let cells = gas.grid();
    match gas.bodies.iter().find(|b| !b.is_seen(&cells, gas.time)) {
        Some(b) => Err(format!(
            "body `{}` does not reach the mid-plane of the 2-D gas box, so the gas would \
             not see it: place it across the box's thin axis",
            b.name
        )),
        None => Ok(()),
    }
}
