//! What the incompressible flow needs of the structure's canopy, checked
//! by the structure before a run (it knows its canopy, and reads the
//! flow's box through fluid-section): fabric keys only with a canopy surface to carry them, and
//! in a 2-D box (one cell along an axis) a canopy that spans that cell, as
//! fluid-proc's markers act across the whole depth.

use crate::{ClothPlane, StructureSection};
use fluid_section::{FluidModel, FluidSection, POROSITY_WITHOUT_CANOPY};
use scenario::Checker;

/// Checks the canopy of `s` in the flow of `fluid`, when that is the
/// incompressible model.
pub fn check(c: &mut Checker, fluid: &FluidSection, s: &StructureSection) {
    if fluid.model != FluidModel::Incompressible {
        return;
    }
    let surface = s.annulus.is_some() || s.parachute.is_some() || s.cloth.is_some();
    if fluid.porosity.is_some() && !surface {
        c.problem(&["fluid", "porosity"], POROSITY_WITHOUT_CANOPY.into());
    }
    let Some(b) = &fluid.flow_box else {
        return;
    };
    let Some(thin) = (0..3).find(|&d| b.cells[d] == 1) else {
        return;
    };
    let axis = ["x", "y", "z"][thin];
    let shaped = [
        ("annulus", s.annulus.is_some()),
        ("parachute", s.parachute.is_some()),
    ];
    if let Some((name, _)) = shaped.iter().find(|(_, given)| *given) {
        c.problem(
            &["fluid", "box", "cells"],
            format!(
                "the flow box is one cell thick along {axis} (a 2-D flow), where a canopy must \
                 span that cell: [structure.{name}] needs a 3-D box, or use a [structure.cloth] \
                 as deep as the box"
            ),
        );
        return;
    }
    let Some(cloth) = &s.cloth else { return };
    // The cloth's extent along each axis: width along x, depth along y
    // (horizontal) or z (vertical), a plane at the origin along the other.
    let o = cloth.origin;
    let deep = match cloth.plane {
        ClothPlane::Horizontal => 1,
        ClothPlane::Vertical => 2,
    };
    let span = [0, 1, 2].map(|d| match d {
        0 => (o[0], o[0] + cloth.width),
        _ if d == deep => (o[d], o[d] + cloth.depth),
        _ => (o[d], o[d]),
    });
    let (lo, hi) = (b.lower[thin], b.upper[thin]);
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * (hi - lo);
    if !(close(span[thin].0, lo) && close(span[thin].1, hi)) {
        c.problem(
            &["structure", "cloth"],
            format!(
                "the flow box is one cell thick along {axis} (a 2-D flow), from {lo} to {hi} m, \
                 and a canopy in it must span that cell; the cloth spans {axis} = {} to {} m",
                span[thin].0, span[thin].1
            ),
        );
    }
}
