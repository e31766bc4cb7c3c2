//! The malformed flow scenarios: the incompressible and euler models' keys
//! and the ranks the fluid runs on, each edited into a shipped scene.

use super::{replace, Case};
use canopy_tests::{scenario_path, workspace};

/// The shipped scenario `name` with `from` replaced by `to`.
fn shipped_with(name: &str, from: &str, to: &str) -> String {
    let text = std::fs::read_to_string(scenario_path(name)).unwrap();
    if from.is_empty() {
        return text;
    }
    replace(&text, from, to)
}

/// The shipped cavity scenario with `from` replaced by `to` (flow cases).
fn cavity_with(from: &str, to: &str) -> String {
    shipped_with("cavity", from, to)
}

/// The shipped Sod shock tube with `from` replaced by `to` (gas cases).
fn sod_with(from: &str, to: &str) -> String {
    shipped_with("sod", from, to)
}

/// The same played by `tests/fixtures/plain-solver`, whose `--check`
/// answer offers neither window nor run checkpoints.
fn plain_sod(from: &str, to: &str) -> String {
    let plain = workspace().join("tests/fixtures/plain-solver");
    let program = format!("program = \"{}\"", plain.display());
    replace(&sod_with(from, to), "program = \"fluid-proc\"", &program)
}

pub const CASES: &[Case] = &[
    Case {
        name: "implicit-with-a-program-without-checkpoints",
        edit: |_| plain_sod("[coupling]\n", "[coupling]\nscheme = \"implicit\"\n"),
        key: Some("coupling.scheme"),
        says: "the program of `fluid` does not save and restore them",
        line_of: Some("scheme = \"implicit\""),
    },
    Case {
        name: "run-checkpoints-with-a-program-without-them",
        edit: |_| {
            let with = "output_interval = 0.05";
            plain_sod(with, &format!("{with}\ncheckpoint_interval = 0.1"))
        },
        key: Some("run.checkpoint_interval"),
        says: "the program of `fluid` does not",
        line_of: Some("checkpoint_interval = 0.1"),
    },
    Case {
        name: "flow-probe-outside-the-box",
        edit: |_| {
            let probe = "[[fluid.probes]]\nname = \"far\"\npoint = [2.0, 0.5, 0.0]\n";
            format!("{}\n{probe}", cavity_with("", ""))
        },
        key: Some("fluid.probes[0].point"),
        says: "lies outside the box",
        line_of: Some("point = [2.0, 0.5, 0.0]"),
    },
    Case {
        name: "frame-follows-no-body",
        edit: |_| {
            let frame = "[fluid.frame]\nfollow = \"jumper\"\n";
            format!("{}\n{frame}", shipped_with("c9-tunnel", "", ""))
        },
        key: Some("fluid.frame.follow"),
        says: "is neither \"canopy\" nor a body of [[rigid.bodies]]",
        line_of: Some("follow = \"jumper\""),
    },
    Case {
        name: "frame-follows-a-canopy-no-structure-sends",
        edit: |_| {
            let frame = "[fluid.frame]\nfollow = \"canopy\"\n";
            format!("{}\n{frame}", shipped_with("c9-tunnel", "", ""))
        },
        key: Some("fluid.frame.follow"),
        says: "needs a participant `structure` to send the canopy",
        line_of: Some("follow = \"canopy\""),
    },
    Case {
        name: "frame-in-a-box-without-outflow",
        edit: |_| {
            let frame = "[fluid.frame]\nfollow = \"canopy\"\n";
            format!("{}\n{frame}", cavity_with("", ""))
        },
        key: Some("fluid.frame.follow"),
        says: "needs an `outflow` side",
        line_of: Some("follow = \"canopy\""),
    },
    Case {
        name: "flow-huge-box-bound",
        edit: |_| cavity_with("upper = [1.0, 1.0,", "upper = [1e308, 1.0,"),
        key: Some("fluid.box.upper"),
        says: "is beyond the 1e30",
        line_of: Some("upper = [1e308"),
    },
    Case {
        name: "flow-unpaired-periodic",
        edit: |_| cavity_with("y_high =", "x_low = \"periodic\"\ny_high ="),
        key: Some("fluid.sides.x_low"),
        says: "periodic sides come in pairs",
        line_of: Some("x_low = \"periodic\""),
    },
    Case {
        name: "flow-fabric-incomplete",
        edit: |_| cavity_with("viscosity = 0.01", "porosity = 0.5\nviscosity = 0.01"),
        key: Some("fluid.porosity"),
        says: "give `diameter` too",
        line_of: Some("porosity = 0.5"),
    },
    Case {
        name: "flow-fabric-without-canopy",
        edit: |_| {
            cavity_with(
                "viscosity = 0.01",
                "porosity = 0.5\ndiameter = 7e-3\nthickness = 1e-4\nviscosity = 0.01",
            )
        },
        key: Some("fluid.porosity"),
        says: "no participant `structure` sends a canopy",
        line_of: Some("porosity = 0.5"),
    },
    Case {
        name: "flow-2d-annulus",
        edit: |_| shipped_with("canopy-flow", "cells = [30, 30, 40]", "cells = [30, 1, 40]"),
        key: Some("fluid.box.cells"),
        says: "[structure.annulus] needs a 3-D box",
        line_of: Some("cells = [30, 1, 40]"),
    },
    Case {
        name: "flow-2d-cloth-too-shallow",
        edit: |_| {
            let t = shipped_with("sheet-updraft", "cells = [8, 8, 32]", "cells = [8, 1, 32]");
            replace(&t, "upper = [1.0, 1.0, 4.0]", "upper = [1.0, 0.125, 4.0]")
        },
        key: Some("structure.cloth"),
        says: "the cloth spans y = 0 to 1 m",
        line_of: Some("[structure.cloth]"),
    },
    Case {
        name: "flow-free-stream-key",
        edit: |_| {
            cavity_with(
                "viscosity = 0.01",
                "free_stream = [0.0, 0.0, 1.0]\nviscosity = 0.01",
            )
        },
        key: Some("fluid.free_stream"),
        says: "free_stream is not a key of model = \"incompressible\"",
        line_of: Some("free_stream = [0.0"),
    },
    Case {
        name: "flow-needs-box",
        edit: |_| cavity_with("[fluid.box]", "[fluid.bx]"),
        key: Some("fluid.bx"),
        says: "unknown field `bx`",
        line_of: Some("[fluid.bx]"),
    },
    Case {
        name: "flow-without-box",
        edit: |_| {
            let t = cavity_with("", "");
            let start = t.find("[fluid.box]").unwrap();
            let end = t.find("[fluid.sides]").unwrap();
            format!("{}{}", &t[..start], &t[end..])
        },
        key: Some("fluid.model"),
        says: "needs the key `box`",
        line_of: Some("model = \"incompressible\""),
    },
    Case {
        name: "flow-courant",
        edit: |_| cavity_with("window = 3.125e-3", "window = 0.05"),
        key: Some("coupling.window"),
        says: "(the Courant number)",
        line_of: Some("window = 0.05"),
    },
    Case {
        name: "flow-inflow-without-outflow",
        edit: |_| cavity_with("y_high =", "y_low = { inflow = [0.0, 1.0, 0.0] }\ny_high ="),
        key: Some("fluid.sides"),
        says: "none is an outflow",
        line_of: Some("[fluid.sides]"),
    },
    Case {
        name: "flow-one-cell-wall",
        edit: |_| cavity_with("y_high =", "z_low = \"wall\"\nz_high = \"wall\"\ny_high ="),
        key: Some("fluid.sides.z_low"),
        says: "one cell thick along z",
        line_of: Some("z_low = \"wall\""),
    },
    Case {
        name: "flow-too-few-cells",
        edit: |_| cavity_with("cells = [128, 128, 1]", "cells = [128, 2, 1]"),
        key: Some("fluid.box.cells"),
        says: "or at least 4",
        line_of: Some("cells = [128, 2, 1]"),
    },
    Case {
        name: "flow-lid-along-thin-axis",
        edit: |_| cavity_with("velocity = [1.0, 0.0, 0.0]", "velocity = [0.0, 0.0, 1.0]"),
        key: Some("fluid.sides.y_high"),
        says: "moves along z, but the box is one cell thick there",
        line_of: Some("velocity = [0.0, 0.0, 1.0]"),
    },
    Case {
        name: "gas-velocity-side",
        edit: |_| {
            sod_with(
                "x_high = \"outflow\"",
                "x_high = { velocity = [1.0, 0.0, 0.0] }",
            )
        },
        key: Some("fluid.sides.x_high"),
        says: "belongs to model = \"incompressible\"",
        line_of: Some("x_high = { velocity"),
    },
    Case {
        name: "gas-wave-too-large",
        edit: |_| {
            sod_with(
                "density = 0.125\n",
                "density = 0.125\ndensity_wave = { amplitude = 0.2, wavenumber = [5.0, 0.0, 0.0] }\n",
            )
        },
        key: Some("fluid.regions[0].density_wave.amplitude"),
        says: "the density turns negative",
        line_of: Some("density_wave = "),
    },
    Case {
        name: "gas-first-region-partial",
        edit: |_| {
            sod_with(
                "density = 0.125",
                "lower = [0.2, 0.0, 0.0]\ndensity = 0.125",
            )
        },
        key: Some("fluid.regions[0].lower"),
        says: "the first region must cover the whole box",
        line_of: Some("lower = [0.2"),
    },
    Case {
        name: "gas-region-pressure",
        edit: |_| sod_with("pressure = 1.0", "pressure = -1.0"),
        key: Some("fluid.regions[1].pressure"),
        says: "pressure = -1 must be > 0 Pa",
        line_of: Some("pressure = -1.0"),
    },
    Case {
        name: "gas-gamma",
        edit: |_| sod_with("gamma = 1.4", "gamma = 1.0"),
        key: Some("fluid.gamma"),
        says: "gamma = 1 must be > 1",
        line_of: Some("gamma = 1.0"),
    },
    Case {
        name: "gas-cfl",
        edit: |_| sod_with("gamma = 1.4", "gamma = 1.4\ncfl = 1.5"),
        key: Some("fluid.cfl"),
        says: "cfl = 1.5 must lie in (0, 1]",
        line_of: Some("cfl = 1.5"),
    },
    Case {
        name: "gas-density-key",
        edit: |_| sod_with("gamma = 1.4", "gamma = 1.4\ndensity = 1.2"),
        key: Some("fluid.density"),
        says: "density is not a key of model = \"euler\"",
        line_of: Some("density = 1.2"),
    },
    Case {
        name: "gas-without-regions",
        edit: |_| {
            let t = sod_with("", "");
            let start = t.find("[[fluid.regions]]").unwrap();
            t[..start].to_string()
        },
        key: Some("fluid.model"),
        says: "needs the key `regions`",
        line_of: Some("model = \"euler\""),
    },
    Case {
        name: "gas-with-a-body-in-a-tube",
        edit: |_| {
            let t = sod_with(
                "program = \"fluid-proc\"",
                "program = \"fluid-proc\"\n\n[participants.rigid]\nprogram = \"rigid-proc\"",
            );
            t + "\n[[rigid.bodies]]\nname = \"ball\"\ndensity = 1.0\nposition = [0.5, 0.0, 0.0]\n\
                 shape = { type = \"sphere\", radius = 0.1 }\n"
        },
        key: Some("rigid.bodies[0].shape"),
        says: "is one cell thick along two axes",
        line_of: Some("shape = {"),
    },
    Case {
        name: "gas-body-with-periodic-sides",
        edit: |_| {
            let t = shipped_with("piston", "x_low = \"outflow\"", "x_low = \"periodic\"");
            replace(&t, "x_high = \"outflow\"", "x_high = \"periodic\"")
        },
        key: Some("fluid.sides.x_low"),
        says: "do not wrap round a periodic side",
        line_of: Some("x_low = \"periodic\""),
    },
    Case {
        name: "gas-parabolic-side",
        edit: |_| {
            sod_with(
                "x_low = \"outflow\"",
                "x_low = { parabolic = [1.0, 0.0, 0.0] }",
            )
        },
        key: Some("fluid.sides.x_low"),
        says: "a side with a given velocity belongs to model = \"incompressible\"",
        line_of: Some("x_low = { parabolic"),
    },
    Case {
        name: "gas-state-side-not-physical",
        edit: |_| {
            sod_with(
                "x_low = \"outflow\"",
                "x_low = { state = { density = -1.0, velocity = [2.0, 0.0, 0.0], pressure = 10.0 } }",
            )
        },
        key: Some("fluid.sides.x_low.state.density"),
        says: "density",
        line_of: Some("x_low = { state"),
    },
    Case {
        name: "flow-state-side",
        edit: |_| {
            cavity_with(
                "# the lid; the other sides are walls",
                "\nx_low = { state = { density = 1.0, velocity = [1.0, 0.0, 0.0], pressure = 1.0 } }",
            )
        },
        key: Some("fluid.sides.x_low"),
        says: "a side held at a gas state belongs to model = \"euler\"",
        line_of: Some("x_low = { state"),
    },
    Case {
        name: "ranks-on-structure",
        edit: |t| {
            replace(
                t,
                "program = \"structure-proc\"",
                "program = \"structure-proc\"\nranks = 2",
            )
        },
        key: Some("participants.structure.ranks"),
        says: "structure-proc runs as one process",
        line_of: Some("ranks = 2"),
    },
    Case {
        name: "ranks-zero",
        edit: |_| {
            sod_with(
                "program = \"fluid-proc\"",
                "program = \"fluid-proc\"\nranks = 0",
            )
        },
        key: Some("participants.fluid.ranks"),
        says: "ranks must be at least 1",
        line_of: Some("ranks = 0"),
    },
    Case {
        name: "ranks-incompressible-thinner-than-halo",
        edit: |_| {
            cavity_with(
                "program = \"fluid-proc\"",
                "program = \"fluid-proc\"\nranks = 50",
            )
        },
        key: Some("participants.fluid.ranks"),
        says: "leaves fewer than 3 cells per rank along y (128 cells)",
        line_of: Some("ranks = 50"),
    },
    Case {
        name: "ranks-thinner-than-halo",
        edit: |_| {
            sod_with(
                "program = \"fluid-proc\"",
                "program = \"fluid-proc\"\nranks = 200",
            )
        },
        key: Some("participants.fluid.ranks"),
        says: "leaves fewer than 3 cells per rank along x (400 cells)",
        line_of: Some("ranks = 200"),
    },
    // Issue 45: the fine core of a graded box.
    Case {
        name: "flow-core-outside-the-box",
        edit: |_| {
            shipped_with(
                "c9-graded",
                "upper = [5.5, 5.5, 4.0]",
                "upper = [5.5, 5.5, 30.0]",
            )
        },
        key: Some("fluid.box.core.lower"),
        says: "must lie inside the box",
        line_of: Some("lower = [-5.5, -5.5, -2.5]"),
    },
    Case {
        name: "flow-core-growing-too-fast",
        edit: |_| shipped_with("c9-graded", "growth = 1.2 ", "growth = 1.5 "),
        key: Some("fluid.box.core.growth"),
        says: "at most 1.2 times as wide",
        line_of: Some("growth = 1.5"),
    },
    Case {
        // Cells of 0.9 m: the core's top along x moves out to 13.5 m from
        // the box's low side, leaving 2.5 m, more than two cells growing
        // by 1.2 reach (2.376 m) and less than three fill (2.7 m).
        name: "flow-core-leaving-a-part-no-cells-fill",
        edit: |_| shipped_with("c9-graded", "spacing = 0.25 ", "spacing = 0.9 "),
        key: Some("fluid.box.core.upper"),
        says: "cannot fill",
        line_of: Some("upper = [5.5, 5.5, 4.0]"),
    },
    Case {
        name: "flow-core-and-cells",
        edit: |_| {
            let cells = "upper = [8.0, 8.0, 24.0]         # m: the dissertation's 16 × 16 × 36 m";
            shipped_with(
                "c9-graded",
                cells,
                &format!("{cells}\ncells = [32, 32, 72]"),
            )
        },
        key: Some("fluid.box.cells"),
        says: "cells follow from [fluid.box.core]",
        line_of: Some("cells = [32, 32, 72]"),
    },
    Case {
        name: "flow-box-without-cells",
        edit: |_| cavity_with("cells = [", "# cells = ["),
        key: Some("fluid.box.lower"),
        says: "the box needs its cells",
        line_of: Some("lower = "),
    },
];
