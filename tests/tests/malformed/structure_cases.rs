//! The malformed structure and rigid-body scenarios: keys of `[structure]`
//! and `[rigid]`, which structure-proc and rigid-proc check, each edited
//! into the shipped pendulum scene.

use super::{replace, Case};

/// A cloth whose areal density would overflow the arithmetic, put before `[rigid]`.
const CLOTH_1E308: &str = "[structure.cloth]\nwidth = 1.0\ndepth = 1.0\nnodes_x = 3\nnodes_y = 3\norigin = [0.0, 0.0, 0.0]\n\n[structure.cloth.fabric]\nareal_density = 1e308\nstiffness = 10.0\n\n[rigid]\n";

/// The porous load of `[structure.porous]` (thesis eqs. 6–10), appended to a scenario.
/// A C-9 on the ball, pre-shaped wider than its flat diameter, put before `[rigid]`.
const PRESHAPED_WIDE: &str = "[structure.parachute]\nmodel = \"c9\"\nbody = \"ball\"\nline_axial_stiffness = 8.0e3\nline_density = 5.0e-3\npreshaped_diameter = 9.0\n\n[structure.parachute.fabric]\nareal_density = 0.05\nstiffness = 1.0e3\n\n[rigid]\n";

/// A C-9 on the ball packed as wide as it is flat, put before `[rigid]`.
const PACKED_WIDE: &str = "[structure.parachute]\nmodel = \"c9\"\nbody = \"ball\"\nline_axial_stiffness = 8.0e3\nline_density = 5.0e-3\npack_diameter = 9.0\n\n[structure.parachute.fabric]\nareal_density = 0.05\nstiffness = 1.0e3\n\n[rigid]\n";
/// A reefed canopy: packed (or flat) with a reefing line of ratio τ.
const REEFED_FLAT: &str = "[structure.parachute]\nmodel = \"c9\"\nbody = \"ball\"\nline_axial_stiffness = 8.0e3\nline_density = 5.0e-3\n\n[structure.parachute.fabric]\nareal_density = 0.05\nstiffness = 1.0e3\n\n[structure.parachute.reefing]\nratio = 0.3\n\n[rigid]\n";
const REEFED_TIGHT: &str = "[structure.parachute]\nmodel = \"c9\"\nbody = \"ball\"\nline_axial_stiffness = 8.0e3\nline_density = 5.0e-3\npack_diameter = 1.0\n\n[structure.parachute.fabric]\nareal_density = 0.05\nstiffness = 1.0e3\n\n[structure.parachute.reefing]\nratio = 0.1\n\n[rigid]\n";
const REEFED_WHOLE: &str = "[structure.parachute]\nmodel = \"c9\"\nbody = \"ball\"\nline_axial_stiffness = 8.0e3\nline_density = 5.0e-3\npack_diameter = 1.0\n\n[structure.parachute.fabric]\nareal_density = 0.05\nstiffness = 1.0e3\n\n[structure.parachute.reefing]\nratio = 1.0\ncut_time = 0.5\n\n[rigid]\n";

/// A C-9 on the ball asked to start both packed and pre-shaped.
const PACKED_AND_PRESHAPED: &str = "[structure.parachute]\nmodel = \"c9\"\nbody = \"ball\"\nline_axial_stiffness = 8.0e3\nline_density = 5.0e-3\npreshaped_diameter = 6.0\npack_diameter = 0.4\n\n[structure.parachute.fabric]\nareal_density = 0.05\nstiffness = 1.0e3\n\n[rigid]\n";

/// A disk of no rings, put before `[rigid]`.
const DISK_NO_RINGS: &str = "[structure.disk]\ndiameter = 1.0\nrings = 0\n\n[structure.disk.fabric]\nareal_density = 0.1\nstiffness = 10.0\n\n[rigid]\n";

/// Three strings on top of each other, put before `[rigid]`.
const CORDS_NO_SPACING: &str = "[[structure.cords]]\nfrom = [0.0, 0.0, 1.0]\nto = [1.0, 0.0, 1.0]\nsegments = 4\nlinear_density = 0.01\naxial_stiffness = 10.0\ncount = 3\n\n[rigid]\n";

const POROUS: &str = "[structure.porous]\nfree_stream = [0.0, 0.0, 1.0]\nporosity = 0.1\ndiameter = 1e-3\nthickness = 1e-4\n";

pub const CASES: &[Case] = &[
    Case {
        name: "unknown-body-key",
        edit: |t| replace(t, "mass = 1.0", "mass = 1.0\nmas = 2.0"),
        key: Some("rigid.bodies[0].mas"),
        says: "unknown field `mas`",
        line_of: Some("mas = 2.0"),
    },
    Case {
        name: "missing-mass",
        edit: |t| replace(t, "mass = 1.0\n", ""),
        key: Some("rigid.bodies[0].mass"),
        says: "a mass point needs its mass",
        line_of: None,
    },
    Case {
        name: "negative-mass",
        edit: |t| replace(t, "mass = 1.0", "mass = -1.0"),
        key: Some("rigid.bodies[0].mass"),
        says: "must be > 0 kg",
        line_of: Some("mass = -1.0"),
    },
    Case {
        name: "zero-mass",
        edit: |t| replace(t, "mass = 1.0", "mass = 0.0"),
        key: Some("rigid.bodies[0].mass"),
        says: "must be > 0 kg",
        line_of: Some("mass = 0.0"),
    },
    Case {
        name: "unknown-integrator",
        edit: |t| {
            replace(
                t,
                "integrator = \"euler-cromer\"",
                "integrator = \"leapfrog\"",
            )
        },
        key: Some("structure.integrator"),
        says: "unknown variant `leapfrog`",
        line_of: Some("leapfrog"),
    },
    Case {
        name: "unknown-body",
        edit: |t| replace(t, "body = \"ball\"", "body = \"moon\""),
        key: Some("structure.strings[0].body"),
        says: "no rigid body is named `moon`",
        line_of: Some("moon"),
    },
    Case {
        name: "negative-stiffness",
        edit: |t| replace(t, "stiffness = 1.0e5", "stiffness = -1.0e5"),
        key: Some("structure.strings[0].stiffness"),
        says: "must be > 0 N/m",
        line_of: Some("stiffness = -1.0e5"),
    },
    Case {
        name: "zero-rest-length",
        edit: |t| replace(t, "rest_length = 1.0", "rest_length = 0.0"),
        key: Some("structure.strings[0].rest_length"),
        says: "must be > 0 m",
        line_of: Some("rest_length = 0.0"),
    },
    Case {
        name: "negative-damping",
        edit: |t| replace(t, "linear_damping = 0.0", "linear_damping = -0.1"),
        key: Some("rigid.bodies[0].linear_damping"),
        says: "must be ≥ 0",
        line_of: Some("linear_damping = -0.1"),
    },
    Case {
        name: "duplicate-body",
        edit: |t| {
            format!(
                "{t}\n[[rigid.bodies]]\nname = \"ball\"\nmass = 2.0\nposition = [0.0, 0.0, -2.0]\n"
            )
        },
        key: Some("rigid.bodies[1].name"),
        says: "used twice",
        line_of: Some("name = \"ball\"\nmass = 2.0"),
    },
    Case {
        name: "short-vector",
        edit: |t| {
            replace(
                t,
                "gravity = [0.0, 0.0, -9.81]\n\n[[rigid",
                "gravity = [0.0, -9.81]\n\n[[rigid",
            )
        },
        key: Some("rigid.gravity"),
        says: "invalid length 2",
        line_of: Some("gravity = [0.0, -9.81]"),
    },
    Case {
        name: "section-without-participant",
        edit: |t| replace(t, "[participants.rigid]\nprogram = \"rigid-proc\"\n", ""),
        key: Some("rigid"),
        says: "no participant `rigid` is listed",
        line_of: Some("[rigid]"),
    },
    Case {
        name: "bad-body-name",
        edit: |t| t.replace("\"ball\"", "\"ball,1\""),
        key: Some("rigid.bodies[0].name"),
        says: "must be a non-empty name",
        line_of: Some("name = \"ball,1\""),
    },
    Case {
        name: "viscous-without-coefficient",
        edit: |t| {
            replace(
                t,
                "integrator = \"euler-cromer\"",
                "integrator = \"euler-cromer\"\ndamping = \"viscous\"",
            )
        },
        key: Some("structure.damping_coefficient"),
        says: "needs damping_coefficient",
        line_of: None,
    },
    Case {
        name: "newmark-gamma-below-half",
        edit: |t| {
            replace(
                t,
                "integrator = \"euler-cromer\"",
                "integrator = \"newmark\"\nnewmark = { beta = 0.25, gamma = 0.3 }",
            )
        },
        key: Some("structure.newmark.gamma"),
        says: "must lie in [0.5, 1]",
        line_of: Some("gamma = 0.3"),
    },
    Case {
        name: "hht-alpha-out-of-range",
        edit: |t| {
            replace(
                t,
                "integrator = \"euler-cromer\"",
                "integrator = \"hht\"\nhht = { alpha = 0.5 }",
            )
        },
        key: Some("structure.hht.alpha"),
        says: "must lie in [-1/3, 0]",
        line_of: Some("alpha = 0.5"),
    },
    Case {
        name: "adaptive-tolerance-out-of-range",
        edit: |t| {
            replace(
                t,
                "integrator = \"euler-cromer\"",
                "integrator = \"dormand-prince\"\nadaptive = { tolerance = 0.0 }",
            )
        },
        key: Some("structure.adaptive.tolerance"),
        says: "must lie strictly between 0 and 1",
        line_of: Some("tolerance = 0.0"),
    },
    Case {
        name: "collision-with-nothing-to-collide",
        edit: |t| format!("{t}\n[structure.collision]\nself_contact = false\n"),
        key: Some("structure.collision.self_contact"),
        says: "no [[rigid.bodies]] entry has a shape",
        line_of: Some("self_contact = false"),
    },
    Case {
        name: "disk-without-rings",
        edit: |t| replace(t, "[rigid]\n", DISK_NO_RINGS),
        key: Some("structure.disk.rings"),
        says: "rings = 0 must lie in 1..=400",
        line_of: Some("rings = 0"),
    },
    Case {
        name: "cords-on-top-of-each-other",
        edit: |t| replace(t, "[rigid]\n", CORDS_NO_SPACING),
        key: Some("structure.cords[0].spacing"),
        says: "several strings need a spacing",
        line_of: Some("[[structure.cords]]"),
    },
    Case {
        name: "collision-friction-negative",
        edit: |t| format!("{t}\n[structure.collision]\nfriction = -0.3\n"),
        key: Some("structure.collision.friction"),
        says: "must be",
        line_of: Some("friction = -0.3"),
    },
    Case {
        name: "collision-model-unknown",
        edit: |t| format!("{t}\n[structure.collision]\nmodel = \"simultaneous\"\n"),
        key: Some("structure.collision.model"),
        says: "pairwise",
        line_of: Some("model = \"simultaneous\""),
    },
    Case {
        name: "collision-thickness-negative",
        edit: |t| format!("{t}\n[structure.collision]\nthickness = -1e-3\n"),
        key: Some("structure.collision.thickness"),
        says: "must be > 0 m",
        line_of: Some("thickness = -1e-3"),
    },
    Case {
        name: "spring-to-unknown-point",
        edit: |t| {
            format!("{t}\n[[structure.points]]\nname = \"p\"\nposition = [0.0, 0.0, 1.0]\nfixed = true\n\n[[structure.springs]]\nends = [\"p\", \"q\"]\nstiffness = 1.0\n")
        },
        key: Some("structure.springs[0].ends"),
        says: "no point is named `q`",
        line_of: Some("ends = "),
    },
    Case {
        name: "porous-load-without-a-surface",
        edit: |t| format!("{t}\n{POROUS}"),
        key: Some("structure.porous"),
        says: "a porous load needs a canopy surface",
        line_of: Some("[structure.porous]"),
    },
    Case {
        name: "porous-porosity-out-of-range",
        edit: |t| {
            format!(
                "{t}\n{}",
                POROUS.replace("porosity = 0.1", "porosity = 1.5")
            )
        },
        key: Some("structure.porous.porosity"),
        says: "must lie strictly between 0 and 1",
        line_of: Some("porosity = 1.5"),
    },
    Case {
        name: "porous-load-twice",
        edit: |t| {
            let fluid = "[participants.fluid]\nprogram = \"fluid-proc\"\n\n[fluid]\nfree_stream = [0.0, 0.0, 1.0]\nporosity = 0.1\ndiameter = 1e-3\nthickness = 1e-4\n";
            format!("{t}\n{fluid}\n{POROUS}")
        },
        key: Some("structure.porous"),
        says: "participant `fluid` loads the canopy too",
        line_of: Some("[structure.porous]"),
    },
    Case {
        name: "missing-mesh",
        edit: |t| {
            replace(
                t,
                "mass = 1.0\n",
                "mass = 1.0\nshape = { type = \"mesh\", file = \"nowhere.obj\" }\n",
            )
        },
        key: Some("rigid.bodies[0].shape.file"),
        says: "nowhere.obj: cannot read the mesh",
        line_of: Some("shape = "),
    },
    Case {
        name: "mass-and-density",
        edit: |t| {
            replace(
                t,
                "mass = 1.0\n",
                "mass = 1.0\ndensity = 7800.0\nshape = { type = \"sphere\", radius = 0.1 }\n",
            )
        },
        key: Some("rigid.bodies[0].mass"),
        says: "exactly one of mass",
        line_of: Some("mass = 1.0"),
    },
    Case {
        name: "restitution-above-one",
        edit: |t| replace(t, "[rigid]\n", "[rigid]\nrestitution = 1.5\n"),
        key: Some("rigid.restitution"),
        says: "must lie in [0, 1]",
        line_of: Some("restitution = 1.5"),
    },
    Case {
        name: "negative-radius",
        edit: |t| {
            replace(
                t,
                "mass = 1.0\n",
                "mass = 1.0\nshape = { type = \"sphere\", radius = -0.1 }\n",
            )
        },
        key: Some("rigid.bodies[0].shape.radius"),
        says: "radius = -0.1 must be > 0 m",
        line_of: Some("shape = "),
    },
    Case {
        name: "huge-stiffness",
        edit: |t| replace(t, "stiffness = 1.0e5", "stiffness = 1e308"),
        key: Some("structure.strings[0].stiffness"),
        says: "is beyond the 1e30 N/m canopy accepts",
        line_of: Some("stiffness = 1e308"),
    },
    Case {
        name: "huge-areal-density",
        edit: |t| replace(t, "[rigid]\n", CLOTH_1E308),
        key: Some("structure.cloth.fabric.areal_density"),
        says: "is beyond the 1e30 kg/m² canopy accepts",
        line_of: Some("areal_density = 1e308"),
    },
    Case {
        name: "preshaped-wider-than-flat",
        edit: |t| replace(t, "[rigid]\n", PRESHAPED_WIDE),
        key: Some("structure.parachute.preshaped_diameter"),
        says: "to under D₀ = 8.534 m (flat: leave it out)",
        line_of: Some("preshaped_diameter = 9.0"),
    },
    Case {
        name: "packed-as-wide-as-flat",
        edit: |t| replace(t, "[rigid]\n", PACKED_WIDE),
        key: Some("structure.parachute.pack_diameter"),
        says: "must lie above 0 and under D₀ = 8.534 m",
        line_of: Some("pack_diameter = 9.0"),
    },
    Case {
        name: "packed-and-preshaped",
        edit: |t| replace(t, "[rigid]\n", PACKED_AND_PRESHAPED),
        key: Some("structure.parachute.pack_diameter"),
        says: "starts packed or pre-shaped, not both",
        line_of: Some("pack_diameter = 0.4"),
    },
    Case {
        name: "reefed-flat",
        edit: |t| replace(t, "[rigid]\n", REEFED_FLAT),
        key: Some("structure.parachute.reefing.ratio"),
        says: "reef a packed or pre-shaped start",
        line_of: Some("ratio = 0.3"),
    },
    Case {
        name: "reefed-narrower-than-the-pack",
        edit: |t| replace(t, "[rigid]\n", REEFED_TIGHT),
        key: Some("structure.parachute.reefing.ratio"),
        says: "the line would start stretched",
        line_of: Some("ratio = 0.1"),
    },
    Case {
        name: "reefed-to-the-whole-canopy",
        edit: |t| replace(t, "[rigid]\n", REEFED_WHOLE),
        key: Some("structure.parachute.reefing.ratio"),
        says: "must lie strictly between 0 and 1",
        line_of: Some("ratio = 1.0"),
    },
];
