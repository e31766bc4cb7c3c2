//! `[structure.parachute]` and `[structure.cloth]`: the generated structures of
//! dissertation §2.3, §4.2 (parachutes with suspension lines) and §4.3 (cloth).

use super::Fabric;
use scenario::Checker;
use serde::{Deserialize, Serialize};

/// Feet and inches to metres (exact, international foot of 1959).
pub const FOOT: f64 = 0.3048;
pub const INCH: f64 = 0.0254;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum ParachuteModel {
    /// C-9 personnel parachute: 28 ft flat circular, 28 gores and lines, no vent
    /// (dissertation §4.2.2), 7 m lines (§4.2.3).
    C9,
    /// T-10: 35 ft flat circular, 30 gores and lines, 20-inch vent.
    T10,
    /// G-11 cargo parachute: 100 ft flat circular, 120 gores and lines.
    G11,
    /// Intruder (dissertation table 5.2 names it, gives no geometry): assumed a small
    /// 16-gore flat circular canopy of 4.5 m with a 0.3 m vent.
    Intruder,
    /// T-11 (dissertation table 5.2 names it, gives no geometry): assumed a flat
    /// cross of 35 ft span, a central square and four square arms, 28 lines
    /// spread along the four arm ends.
    T11,
    /// Everything from the keys below.
    Custom,
}

/// The outline of a flat canopy.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CanopyShape {
    /// A disc divided into gores.
    Circular,
    /// A cross: a central square of side D₀/3 and four square arms.
    Cross,
}

/// The flat canopy a model stands for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CanopyGeometry {
    pub shape: CanopyShape,
    /// Nominal (flat) diameter D₀ [m]; the tip-to-tip span of a cross.
    pub diameter: f64,
    /// Gores, one line at each seam; for a cross, the number of lines, a
    /// quarter of them along each arm end.
    pub gores: u32,
    /// Vent diameter [m]; 0 for none.
    pub vent: f64,
    /// Suspension-line length from skirt to confluence [m].
    pub line_length: f64,
}

impl CanopyGeometry {
    /// Distance from the axis to the farthest line attachment [m]: the
    /// skirt's radius, or a cross's arm-end corner at √(1.5² + 0.5²)·D₀/3.
    pub fn skirt_radius(&self) -> f64 {
        match self.shape {
            CanopyShape::Circular => 0.5 * self.diameter,
            CanopyShape::Cross => 2.5f64.sqrt() * self.diameter / 3.0,
        }
    }

    /// The nominal area S₀ the drag coefficient C_D0 refers to [m²]: the
    /// flat canopy's, vent included (Knacke 1992, ch. 5): πD₀²/4 for a
    /// circular canopy, five squares of side D₀/3 for a cross.
    pub fn nominal_area(&self) -> f64 {
        match self.shape {
            CanopyShape::Circular => 0.25 * std::f64::consts::PI * self.diameter.powi(2),
            CanopyShape::Cross => 5.0 * (self.diameter / 3.0).powi(2),
        }
    }
}

impl ParachuteModel {
    /// The preset, None for `custom`. Where the dissertation gives no line length we assume
    /// 0.82·D₀, the C-9's ratio (7 m / 8.53 m).
    pub fn geometry(self) -> Option<CanopyGeometry> {
        let g = |d: f64, gores, vent, lines: Option<f64>| CanopyGeometry {
            shape: CanopyShape::Circular,
            diameter: d,
            gores,
            vent,
            line_length: lines.unwrap_or(0.82 * d),
        };
        match self {
            ParachuteModel::C9 => Some(g(28.0 * FOOT, 28, 0.0, Some(7.0))),
            ParachuteModel::T10 => Some(g(35.0 * FOOT, 30, 20.0 * INCH, None)),
            ParachuteModel::G11 => Some(g(100.0 * FOOT, 120, 0.0, None)),
            ParachuteModel::Intruder => Some(g(4.5, 16, 0.3, None)),
            ParachuteModel::T11 => Some(CanopyGeometry {
                shape: CanopyShape::Cross,
                ..g(35.0 * FOOT, 28, 0.0, None)
            }),
            ParachuteModel::Custom => None,
        }
    }
}

#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Parachute {
    pub model: ParachuteModel,
    /// Overrides of the model's geometry (all four needed for `custom`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub nominal_diameter: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gores: Option<u32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vent_diameter: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub line_length: Option<f64>,
    /// The mesh resolution: node rings from the vent (or centre) to the skirt,
    /// or for a cross, mesh cells across an arm.
    #[serde(default = "default_resolution")]
    pub resolution: u32,
    /// Height of the flat canopy, or of a pre-shaped or packed one's top [m].
    #[serde(default)]
    pub height: f64,
    /// Start pre-shaped: the canopy laid on a spherical cap this wide
    /// across the skirt [m], its seams at their flat lengths; flat when
    /// left out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preshaped_diameter: Option<f64>,
    /// Start packed, at line stretch: the canopy gathered along its axis
    /// into a bundle this wide [m], its seams straight from the top (at
    /// `height`) down to the skirt, its rings pleated into the pack (the
    /// rings wider than it get 2 nodes or more in every pleat), the lines
    /// straight and taut below; flat when left out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pack_diameter: Option<f64>,
    pub fabric: Fabric,
    /// Extra stiffness [N/m] of the gore seams (the radial edges between gores).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seam_stiffness: Option<f64>,
    /// Axial stiffness E·A of a suspension line [N].
    pub line_axial_stiffness: f64,
    /// Line mass per length [kg/m].
    pub line_density: f64,
    /// Mass points per line, confluence excluded.
    #[serde(default = "default_segments")]
    pub line_segments: u32,
    /// A payload mass point at the confluence [kg] …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub payload_mass: Option<f64>,
    /// … or the rigid body the confluence is attached to, …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub body: Option<String>,
    /// … at this point of the body's own frame [m] (default its origin): where
    /// the suspension lines meet the parachutist or cargo (dissertation fig. 2.5).
    #[serde(default)]
    pub body_point: [f64; 3],
    /// Uneven lines (dissertation §4.2.3).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub line_changes: Vec<LineChange>,
    /// Breaking lines (dissertation §4.2.3).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub line_breaks: Vec<LineBreak>,
    /// A reefing line round the skirt, holding the mouth small until it
    /// is cut; unreefed when left out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reefing: Option<Reefing>,
    /// The parachute's velocity at release [m/s]: every node of canopy,
    /// lines and a mass-point payload starts with it; at rest, or the body
    /// payload's own `velocity` in `[[rigid.bodies]]`, when left out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity: Option<[f64; 3]>,
    /// A mass-point payload holds the parachute, moving on at `velocity`
    /// whatever pulls on it, until this time [s]; then it falls free.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub release_time: Option<f64>,
}

#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LineChange {
    /// Line indices, 0-based, counter-clockwise from +x.
    pub lines: Vec<u32>,
    /// Change of rest length [m] (negative: shorter).
    pub rest_length_change: f64,
}

#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LineBreak {
    pub lines: Vec<u32>,
    /// Break at this time [s] …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<f64>,
    /// … or when the tension exceeds this [N].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tension: Option<f64>,
}

/// A reefing line through rings at the skirt's gore seams, holding the
/// mouth to a circle of diameter τ·D₀ until cutters release it (Knacke,
/// *Parachute Recovery Systems Design Manual*, 1992, ch. 6: the reefing
/// ratio τ = D_R/D₀, D_R = L_R/π of a line of length L_R). The line is
/// tied at each seam's ring: a segment from seam to seam, tension only,
/// of the line's axial stiffness and mass per length.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Reefing {
    /// Reefing ratio τ = D_R/D₀: the line is π·τ·D₀ long.
    pub ratio: f64,
    /// The cutters fire at this time [s] and the line stops holding;
    /// reefed to the end when left out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cut_time: Option<f64>,
}

impl Reefing {
    /// The line's length π·τ·D₀ [m] on a canopy of nominal diameter `d0`.
    pub fn length(&self, d0: f64) -> f64 {
        std::f64::consts::PI * self.ratio * d0
    }
}

fn default_resolution() -> u32 {
    8
}
fn default_segments() -> u32 {
    8
}

impl Parachute {
    /// The model's geometry with the overrides applied (`check` ensures a `custom` one is complete).
    pub fn geometry(&self) -> CanopyGeometry {
        let base = self.model.geometry().unwrap_or(CanopyGeometry {
            shape: CanopyShape::Circular,
            diameter: f64::NAN,
            gores: 0,
            vent: 0.0,
            line_length: f64::NAN,
        });
        CanopyGeometry {
            shape: base.shape,
            diameter: self.nominal_diameter.unwrap_or(base.diameter),
            gores: self.gores.unwrap_or(base.gores),
            vent: self.vent_diameter.unwrap_or(base.vent),
            line_length: self.line_length.unwrap_or(base.line_length),
        }
    }

    pub fn check(&self, c: &mut Checker, has_body: impl Fn(&str) -> Option<String>) {
        c.within("parachute", None, |c| {
            self.check_geometry(c);
            self.check_elements(c);
            self.check_payload(c, has_body);
            self.check_lines(c);
            self.check_reefing(c);
        });
    }

    /// A reefing line on a circular canopy whose skirt starts inside it:
    /// packed or pre-shaped no wider than τ·D₀, so that the line starts
    /// slack rather than snapping the skirt shut at t = 0.
    fn check_reefing(&self, c: &mut Checker) {
        let Some(r) = &self.reefing else { return };
        c.within("reefing", None, |c| {
            let g = self.geometry();
            c.fraction(&["ratio"], r.ratio);
            c.rule(&["ratio"], || {
                "the skirt starts no wider than τ·D₀: packed or pre-shaped".into()
            });
            if !(r.ratio > 0.0 && r.ratio < 1.0) {
                return;
            }
            if let Some(t) = r.cut_time {
                c.finite_nonneg(&["cut_time"], t);
            }
            let skirt = self.pack_diameter.or(self.preshaped_diameter);
            let reefed = r.ratio * g.diameter;
            match skirt {
                _ if g.shape == CanopyShape::Cross => c.problem(
                    &["ratio"],
                    "a cross canopy has no round skirt to reef".into(),
                ),
                None => c.problem(
                    &["ratio"],
                    format!(
                        "a flat canopy's skirt (D₀ = {:.3} m) is wider than the reefed mouth \
                         (τ·D₀ = {reefed:.3} m): reef a packed or pre-shaped start",
                        g.diameter
                    ),
                ),
                Some(d) if d > reefed => c.problem(
                    &["ratio"],
                    format!(
                        "ratio = {} reefs the mouth to τ·D₀ = {reefed:.3} m, narrower than the \
                         skirt starts ({d} m): the line would start stretched",
                        r.ratio
                    ),
                ),
                Some(_) => {}
            }
        });
    }

    /// The canopy's shape: model, diameter, gores, vent, lines' reach.
    fn check_geometry(&self, c: &mut Checker) {
        if self.model == ParachuteModel::Custom
            && (self.nominal_diameter.is_none()
                || self.gores.is_none()
                || self.line_length.is_none())
        {
            c.problem(
                &["model"],
                "model = \"custom\" needs nominal_diameter, gores and line_length".into(),
            );
        }
        let g = self.geometry();
        c.positive(&["nominal_diameter"], g.diameter, "m");
        if !(3..=1000).contains(&g.gores) {
            c.problem(
                &["gores"],
                format!("gores = {} must lie in 3..=1000", g.gores),
            );
        }
        c.finite_nonneg(&["vent_diameter"], g.vent);
        if g.vent >= 0.5 * g.diameter {
            c.problem(
                &["vent_diameter"],
                format!(
                    "vent_diameter = {} m must be under half the diameter",
                    g.vent
                ),
            );
        }
        c.positive(&["line_length"], g.line_length, "m");
        if g.line_length <= g.skirt_radius() {
            c.problem(
                &["line_length"],
                format!(
                    "line_length = {} m cannot reach the axis from a skirt of radius {} m",
                    g.line_length,
                    g.skirt_radius()
                ),
            );
        }
        if g.shape == CanopyShape::Cross {
            let per_arm = g.gores / 4;
            if g.gores % 4 != 0 || per_arm < 2 || per_arm > self.resolution + 1 {
                c.problem(
                    &["gores"],
                    format!(
                        "a cross canopy needs lines in fours, 2 to resolution + 1 = {} per arm end; gores = {} gives {}",
                        self.resolution + 1,
                        g.gores,
                        g.gores as f64 / 4.0
                    ),
                );
            }
            if g.vent != 0.0 {
                c.problem(&["vent_diameter"], "a cross canopy has no vent".into());
            }
            if self.seam_stiffness.is_some() {
                c.problem(
                    &["seam_stiffness"],
                    "a cross canopy has no gore seams".into(),
                );
            }
        }
    }

    /// Resolution, fabric, seams and lines' material.
    fn check_elements(&self, c: &mut Checker) {
        if !(2..=200).contains(&self.resolution) {
            c.problem(
                &["resolution"],
                format!("resolution = {} must lie in 2..=200", self.resolution),
            );
        }
        c.finite(&["height"], self.height);
        if let Some(d) = self.preshaped_diameter {
            if let Err(msg) = self.geometry().dome_radius(d) {
                c.problem(&["preshaped_diameter"], msg);
            }
        }
        if let Some(d) = self.pack_diameter {
            if self.preshaped_diameter.is_some() {
                c.problem(
                    &["pack_diameter"],
                    "a canopy starts packed or pre-shaped, not both: leave out one of \
                     pack_diameter and preshaped_diameter"
                        .into(),
                );
            } else if let Err(msg) = self.geometry().pleats(d) {
                c.problem(&["pack_diameter"], msg);
            }
        }
        self.fabric.check(c);
        if let Some(k) = self.seam_stiffness {
            c.positive(&["seam_stiffness"], k, "N/m");
        }
        c.positive(&["line_axial_stiffness"], self.line_axial_stiffness, "N");
        c.positive(&["line_density"], self.line_density, "kg/m");
        if !(1..=1000).contains(&self.line_segments) {
            c.problem(
                &["line_segments"],
                format!(
                    "line_segments = {} must lie in 1..=1000",
                    self.line_segments
                ),
            );
        }
    }

    /// One payload: a mass point or a rigid body that exists; the release.
    fn check_payload(&self, c: &mut Checker, has_body: impl Fn(&str) -> Option<String>) {
        if let Some(v) = self.velocity {
            c.finite3(&["velocity"], v);
        }
        if let Some(t) = self.release_time {
            c.finite_nonneg(&["release_time"], t);
            if self.body.is_some() {
                c.problem(
                    &["release_time"],
                    "release_time here holds a mass-point payload (payload_mass); hold a body \
                     payload with its own release_time in [[rigid.bodies]]"
                        .into(),
                );
            }
        }
        match (&self.payload_mass, &self.body) {
            (Some(m), None) => {
                c.positive(&["payload_mass"], *m, "kg");
                if self.body_point != [0.0; 3] {
                    c.problem(
                        &["body_point"],
                        "a mass-point payload has no body: body_point goes with body".into(),
                    );
                }
            }
            (None, Some(b)) => {
                c.finite3(&["body_point"], self.body_point);
                if let Some(msg) = has_body(b) {
                    c.problem(&["body"], msg);
                }
            }
            _ => c.problem(
                &["payload_mass"],
                "give exactly one of payload_mass (a mass point) or body (a rigid body)".into(),
            ),
        }
    }

    /// Uneven and breaking lines name lines that exist.
    fn check_lines(&self, c: &mut Checker) {
        let g = self.geometry();
        let check_lines = |c: &mut Checker, lines: &[u32]| {
            if let Some(l) = lines.iter().find(|&&l| l >= g.gores) {
                c.problem(
                    &["lines"],
                    format!(
                        "line {l} does not exist: there are {} lines (0 to {})",
                        g.gores,
                        g.gores.saturating_sub(1)
                    ),
                );
            }
        };
        for (i, ch) in self.line_changes.iter().enumerate() {
            c.within("line_changes", Some(i), |c| {
                check_lines(c, &ch.lines);
                c.finite(&["rest_length_change"], ch.rest_length_change);
                if ch.rest_length_change <= -g.line_length {
                    c.problem(
                        &["rest_length_change"],
                        "would leave the line no length".into(),
                    );
                }
            });
        }
        for (i, b) in self.line_breaks.iter().enumerate() {
            c.within("line_breaks", Some(i), |c| {
                check_lines(c, &b.lines);
                match (b.time, b.tension) {
                    (Some(t), None) => c.finite_nonneg(&["time"], t),
                    (None, Some(t)) => c.positive(&["tension"], t, "N"),
                    _ => c.problem(
                        &["time"],
                        "give exactly one of time (s) or tension (N)".into(),
                    ),
                }
            });
        }
    }
}

/// Which part of a rectangular cloth is held.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum ClothHold {
    /// The edge x = 0, x = width, y = 0 or y = depth.
    EdgeX0,
    EdgeX1,
    EdgeY0,
    EdgeY1,
    /// One corner node.
    CornerX0Y0,
    CornerX1Y0,
    CornerX0Y1,
    CornerX1Y1,
}

#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum ClothPlane {
    /// In the plane z = origin.z.
    #[default]
    Horizontal,
    /// In the plane y = origin.y, depth along +z: hangs under gravity.
    Vertical,
}

#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Cloth {
    /// Size along x [m] and along the second axis [m].
    pub width: f64,
    pub depth: f64,
    /// Nodes along each side: the mesh resolution.
    pub nodes_x: u32,
    pub nodes_y: u32,
    /// Corner (x = 0, y = 0) [m].
    #[serde(default)]
    pub origin: [f64; 3],
    #[serde(default)]
    pub plane: ClothPlane,
    pub fabric: Fabric,
    /// Springs [N/m] between the far vertices of adjacent triangles (the dissertation, end of §2.3).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bending_stiffness: Option<f64>,
    /// What is held in place.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub fixed: Vec<ClothHold>,
}

impl Cloth {
    pub fn check(&self, c: &mut Checker) {
        c.within("cloth", None, |c| {
            c.positive(&["width"], self.width, "m");
            c.positive(&["depth"], self.depth, "m");
            for (key, n) in [("nodes_x", self.nodes_x), ("nodes_y", self.nodes_y)] {
                if !(2..=4000).contains(&n) {
                    c.problem(&[key], format!("{key} = {n} must lie in 2..=4000"));
                }
            }
            c.finite3(&["origin"], self.origin);
            self.fabric.check(c);
            if let Some(k) = self.bending_stiffness {
                c.positive(&["bending_stiffness"], k, "N/m");
            }
        });
    }
}
