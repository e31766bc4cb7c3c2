//! The canopy in the incompressible flow (dissertation §3.3): an open surface of
//! triangles the structure moves. Each window:
//! 1. markers about one cell apart on its triangles take the fabric's
//!    velocity, interpolated from the vertices (`sheet_markers`);
//! 2. the flow holds the air's normal velocity there to the fabric's
//!    (`immersed.rs`: direct forcing with Peskin's δ, eq. 3.25, the
//!    fabric's reaction spread to the grid and the grid's velocity
//!    interpolated to it) — all of it for a closed fabric, and for a porous
//!    one only what the Darcy–Forchheimer law of thesis eqs. (6)–(10)
//!    lets through; along the fabric the air slips, as the structure takes
//!    only the normal jump;
//! 3. the pressure jump on each triangle is read side by side through the
//!    local index coating (`coating.rs`, §3.3.2) and sent to the structure.

use crate::surface::{pieces_as, Cuts, Marker};
use nalgebra::Point3;
use porous::Porous;

/// Markers on the canopy's triangles cut to at most `spacing` [m]: `x` and
/// `v` the vertices' positions (in the box's frame) and velocities, xyz per
/// vertex. Gives the markers and their velocities.
pub fn sheet_markers(
    x: &[f64],
    v: &[f64],
    triangles: &[[usize; 3]],
    spacing: f64,
) -> (Vec<Marker>, Vec<[f64; 3]>) {
    sheet_markers_cut(x, v, triangles, spacing, &mut SheetCuts::default())
}

/// How every triangle of the canopy was cut at a window's first try, to be
/// cut alike at the window's repeats under implicit coupling
/// (`surface::Cuts` says why).
#[derive(Debug, Clone, Default)]
pub struct SheetCuts {
    recorded: Vec<u8>,
    /// Cut as recorded rather than by the edges' lengths.
    pub replay: bool,
}

/// [`sheet_markers`], the triangles cut as `cuts` recorded when it
/// replays, else by their lengths, recorded.
pub fn sheet_markers_cut(
    x: &[f64],
    v: &[f64],
    triangles: &[[usize; 3]],
    spacing: f64,
    cuts: &mut SheetCuts,
) -> (Vec<Marker>, Vec<[f64; 3]>) {
    let mut markers = Vec::new();
    let mut velocities = Vec::new();
    let mut how = match cuts.replay && !cuts.recorded.is_empty() {
        true => Cuts::Replay {
            from: &cuts.recorded,
            at: 0,
        },
        false => {
            cuts.recorded.clear();
            Cuts::Choose {
                spacing,
                into: Some(&mut cuts.recorded),
            }
        }
    };
    for t in triangles {
        let corners = t.map(|i| Point3::new(x[3 * i], x[3 * i + 1], x[3 * i + 2]));
        pieces_as(corners, &mut how, &mut |(w, m)| {
            markers.push(m);
            velocities.push([0, 1, 2].map(|d| (0..3).map(|j| w[j] * v[3 * t[j] + d]).sum()));
        });
    }
    (markers, velocities)
}

/// The fabric's law as the forcing takes it: Δp = a·w + b·w|w| [Pa] for
/// the air's velocity w relative to the fabric along its normal. With
/// v_f = ε·w (thesis eq. 9) in Δp = e(A·v_f + B·v_f|v_f|) (eq. 6):
/// a = e·A·ε, b = e·B·ε².
pub fn porous_law(p: &Porous) -> [f64; 2] {
    let (e, eps) = (p.thickness, p.porosity);
    [e * p.a * eps, e * p.b * eps * eps]
}
