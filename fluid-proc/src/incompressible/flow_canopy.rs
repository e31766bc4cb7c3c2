//! The structure's canopy as the incompressible flow sees it: its
//! triangles (sent once), placed every window where the structure left
//! them, and the pressure jump on each sent back (`canopy.rs`,
//! `immersed.rs` and `coating.rs` do the physics).

use crate::incompressible::canopy::{porous_law, sheet_markers_cut, SheetCuts};
use crate::incompressible::clearance::keep_clear;
use crate::incompressible::coating::{Coating, Selection};
use crate::incompressible::grid::Grid;
use crate::incompressible::immersed::ImmersedBody;
use crate::incompressible::Incompressible;
use crate::{check_triangles, triangles_from_field, Porous};
use fluid_section::FluidSection;

/// How far a canopy's extent along a 2-D flow's thin axis may differ from
/// the box's depth, relative: the fabric stretches a little across it.
const SPAN_TOLERANCE: f64 = 1e-3;

pub struct FlowCanopy {
    triangles: Option<Vec<[usize; 3]>>,
    /// The fabric's law (`canopy::porous_law`); None for a closed fabric.
    law: Option<[f64; 2]>,
    /// The box's low corner in the world at the start [m].
    lower: [f64; 3],
    /// The vertices where they were last placed, in the box's frame [m].
    x: Vec<f64>,
    jumps: Vec<f64>,
    /// How the triangles were cut into markers at the window's first try;
    /// under implicit coupling its repeats cut them alike.
    cuts: SheetCuts,
    /// The cells the jumps were read from at the window's first try, and
    /// how (each side's plane as a fixed sum over them, and its weight);
    /// its repeats read alike (`coating::Selection`).
    read: Selection,
    replay_read: bool,
    implicit: bool,
}

impl FlowCanopy {
    /// A canopy of the fabric `[fluid]` describes: porous with its
    /// `porosity`, `diameter` and `thickness`, closed without them.
    pub fn new(section: &FluidSection, lower: [f64; 3]) -> FlowCanopy {
        FlowCanopy {
            triangles: None,
            law: section
                .fabric()
                .map(|f| porous_law(&Porous::new(&f.params()))),
            lower,
            x: Vec::new(),
            jumps: Vec::new(),
            cuts: SheetCuts::default(),
            read: Selection::default(),
            replay_read: false,
            implicit: false,
        }
    }

    /// An implicit window begins: its first try cuts the triangles by
    /// their lengths, its repeats as the first did.
    pub fn new_window(&mut self) {
        self.implicit = true;
        self.cuts.replay = false;
        self.replay_read = false;
    }

    /// Whether the connectivity, which the structure sends once, is still
    /// to be read.
    pub fn needs_triangles(&self) -> bool {
        self.triangles.is_none()
    }

    /// How many triangles the canopy has (0 before they are read).
    pub fn triangle_count(&self) -> usize {
        self.triangles.as_ref().map_or(0, Vec::len)
    }

    pub fn set_triangles(&mut self, field: &[f64]) {
        self.triangles = Some(triangles_from_field(field));
    }

    /// Puts the canopy in `flow` at the vertices' world positions `x`
    /// moving with velocities `v` (xyz per vertex).
    pub fn place(&mut self, x: &[f64], v: &[f64], flow: &mut Incompressible) -> Result<(), String> {
        let triangles = self.triangles.as_deref().unwrap_or(&[]);
        if x.len() % 3 != 0 {
            return Err(format!(
                "the structure sent {} canopy coordinates, not three per vertex",
                x.len()
            ));
        }
        check_triangles(triangles, x.len() / 3)?;
        if x.len() != v.len() {
            return Err(format!(
                "the structure sent {} canopy positions and {} velocities",
                x.len(),
                v.len()
            ));
        }
        if x.iter().chain(v).any(|c| !c.is_finite()) {
            return Err("the canopy's positions or velocities are not finite".into());
        }
        // Where the box is now: it moves when it follows the parachute.
        let origin = flow.box_origin(self.lower);
        self.x.clear();
        self.x
            .extend(x.iter().enumerate().map(|(i, c)| c - origin[i % 3]));
        let g = flow.grid();
        // A 2-D flow has no depth to resolve: the canopy must span the box's
        // one cell along its thin axis, each marker acting across it. That
        // axis is periodic, so where along it the canopy sits is no matter.
        for d in (0..3).filter(|&d| g.n[d] == 1) {
            let depth = g.h[d];
            let along = self.x.iter().skip(d).step_by(3);
            let (lo, hi) = along.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &c| {
                (lo.min(c), hi.max(c))
            });
            if !self.x.is_empty() && ((hi - lo) / depth - 1.0).abs() > SPAN_TOLERANCE {
                let axis = ["x", "y", "z"][d];
                return Err(format!(
                    "the canopy spans {:.6} m along {axis}, not the 2-D flow box's depth of \
                     {depth:.6} m: a canopy in a 2-D flow must span the box's one cell along {axis}",
                    hi - lo
                ));
            }
        }
        let spacing = g.spacing_range().0;
        let (markers, velocities) =
            sheet_markers_cut(&self.x, v, triangles, spacing, &mut self.cuts);
        self.cuts.replay = self.implicit;
        keep_clear(g, &markers, origin, "the canopy")?;
        let canopy = flow.canopy.get_or_insert_with(ImmersedBody::default);
        canopy.porous = self.law;
        canopy.place_sheet(markers, velocities);
        Ok(())
    }

    /// The pressure jump p⁻ − p⁺ across each triangle where it was last
    /// placed [Pa] (dissertation §3.3.2; the load is jump·area·n, n the normal
    /// of the vertex order), from the `pressure` [Pa] of the whole box `g`.
    pub fn jumps(&mut self, g: &Grid, pressure: &[f64]) -> &[f64] {
        let triangles = self.triangles.as_deref().unwrap_or(&[]);
        self.jumps.resize(triangles.len(), 0.0);
        if !(self.replay_read && self.read.fits(triangles.len())) {
            self.read = Coating::new(g, &self.x, triangles).select(g, &self.x, triangles);
        }
        self.replay_read = self.implicit;
        self.read.jumps(pressure, &mut self.jumps);
        &self.jumps
    }

    /// The mean velocity [m/s] of the vertices `v` (xyz per vertex): what
    /// a box that follows the canopy moves with.
    pub fn mean_velocity(v: &[f64]) -> [f64; 3] {
        let n = (v.len() / 3).max(1) as f64;
        let mut sum = [0.0; 3];
        for c in v.chunks_exact(3) {
            (0..3).for_each(|d| sum[d] += c[d]);
        }
        sum.map(|s| s / n)
    }

    /// The mean jump over the triangles [Pa], as the porous free-stream
    /// model reports it; NaN before any.
    pub fn mean_jump(&self) -> f64 {
        if self.jumps.is_empty() {
            return f64::NAN;
        }
        self.jumps.iter().sum::<f64>() / self.jumps.len() as f64
    }
}
