//! The canopy in the incompressible flow through the coupler (the dissertation
//! §3.3): structure-proc sends the canopy, fluid-proc holds the air to it
//! as an immersed sheet and sends back the pressure jump on each triangle,
//! read side by side through the local index coating (§3.3.2). Both cases
//! have exact solutions because the sheet spans a box periodic across it,
//! so the flow is one-dimensional.

use canopy_tests::*;

/// Standard gravity [m/s²], as the scenes give it.
const G: f64 = 9.81;

/// Darcy–Forchheimer drop of the fabric of `scenarios/sheet-updraft.toml`
/// at the air's speed w through it [Pa], thesis eqs. (6)–(9) with
/// Ergun's coefficients (eqs. 7–8): ε = 0.5, D = 1 mm, e = 0.1 mm, ISA air
/// (ρ = 1.225 kg/m³, μ = 1.7894·10⁻⁵ Pa·s).
fn updraft_fabric_drop(w: f64) -> f64 {
    let (eps, d, e, mu, rho) = (0.5, 1.0e-3, 1.0e-4, 1.7894e-5, 1.225);
    let a = 150.0 * mu * (1.0 - eps) * (1.0 - eps) / (d * d * eps * eps);
    let b = 1.75 * rho * (1.0 - eps) / (d * eps * eps);
    let vf = eps * w;
    e * (a * vf + b * vf * vf.abs())
}

/// The updraft of `scenarios/sheet-updraft.toml` [m/s] and its sheet's
/// areal density [kg/m²].
const UPDRAFT: f64 = 1.8;
const AREAL_DENSITY: f64 = 0.05;

/// Checks a settled sheet-updraft run in `out`, its sheet `area` [m²]: the
/// drop across the sheet carries its weight, Δp = ρ_s·g, and it rises at
/// V = U − w* with Δp(w*) = ρ_s·g (thesis eq. 10: the law takes the
/// air's velocity relative to the fabric); both within 0.5 %.
fn assert_hovers(out: &std::path::Path, area: f64) {
    let weight = AREAL_DENSITY * G;
    // w* by bisection: the drop grows with w.
    let (mut lo, mut hi) = (0.0, UPDRAFT);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if updraft_fabric_drop(mid) < weight {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let rise = UPDRAFT - 0.5 * (lo + hi);
    let m = Monitors::read(out);
    let jump = *m.column("fluid.mean_pressure_jump").last().unwrap();
    let speed = m.column("structure.momentum.z").last().unwrap() / (AREAL_DENSITY * area);
    assert!(
        (jump / weight - 1.0).abs() < 5e-3,
        "jump {jump} Pa against the weight {weight} Pa"
    );
    assert!(
        (speed / rise - 1.0).abs() < 5e-3,
        "the sheet rises at {speed} m/s against {rise} m/s"
    );
}

/// A porous sheet hovering in an updraft, the scene as shipped (measured:
/// the jump 1.3·10⁻⁵ and the speed 6·10⁻⁵ off).
#[test]
fn a_porous_sheet_hovers_where_its_drop_carries_its_weight() {
    let dir = scratch("sheet-updraft");
    let out = dir.join("run");
    run_ok(&scenario_path("sheet-updraft"), &out);
    assert_hovers(&out, 1.0);
}

/// The same with the flow on the GPU (`[fluid] device = "gpu"`, issue 47):
/// the sheet's markers spread the fabric's drag on the device, and the
/// sheet settles where the exact solution says, within the same 0.5 %.
/// CI runs it on Mesa's CPU adapter; without an adapter it says so and
/// passes, unless `CANOPY_REQUIRE_GPU` is set.
#[test]
fn a_porous_sheet_hovers_with_its_flow_on_the_gpu() {
    let dir = scratch("sheet-updraft-gpu");
    let scenario = variant("sheet-updraft", &dir, |s| {
        s.fluid.as_mut().unwrap().device = fluid_section::Device::Gpu;
    });
    if !gpu_check_passes(&scenario) {
        return;
    }
    let out = dir.join("run");
    run_ok(&scenario, &out);
    assert_hovers(&out, 1.0);
}

/// The same in a 2-D box, one cell (0.125 m) deep along y: a strip of the
/// sheet as deep as the box, its markers acting across the depth.
#[test]
fn a_porous_strip_hovers_in_a_2d_box_too() {
    let depth = 0.125;
    let dir = scratch("sheet-updraft-2d");
    let scenario = variant("sheet-updraft", &dir, |s| {
        let b = s.fluid.as_mut().unwrap().flow_box.as_mut().unwrap();
        b.upper[1] = depth;
        b.cells[1] = 1;
        let cloth = s.structure.as_mut().unwrap().cloth.as_mut().unwrap();
        cloth.depth = depth;
        cloth.nodes_y = 2;
    });
    let out = dir.join("run");
    run_ok(&scenario, &out);
    assert_hovers(&out, depth);
}

/// A closed sheet across a box periodic on every side, under gravity: the
/// sheet cannot let air through, so it drives the whole column of air, and
/// the two fall together at a = −g·ρ_s/(ρ_s + ρ·L) (Newton's second law for
/// sheet and column). Only gravity acts from outside, on the sheet, so the
/// momentum of sheet and air together is −ρ_s·A·g·t: the jump the coating
/// reads must be the force the forcing gave the air.
const CLOSED_COLUMN: &str = r#"
[run]
name = "closed-column"
end_time = 0.3
output_interval = 0.3

[coupling]
window = 0.01

[participants.fluid]
program = "fluid-proc"

[participants.structure]
program = "structure-proc"

[fluid]
model = "incompressible"
density = 1.2
viscosity = 1.8e-5

[fluid.box]
lower = [0.0, 0.0, 0.0]
upper = [1.0, 1.0, 2.0]
cells = [8, 8, 16]

[fluid.sides]
x_low = "periodic"
x_high = "periodic"
y_low = "periodic"
y_high = "periodic"
z_low = "periodic"
z_high = "periodic"

[structure]
substeps = 20
integrator = "velocity-verlet"
gravity = [0.0, 0.0, -9.81]

[structure.cloth]
width = 1.0
depth = 1.0
nodes_x = 9
nodes_y = 9
origin = [0.0, 0.0, 1.0]
plane = "horizontal"

[structure.cloth.fabric]
areal_density = 5.0
stiffness = 100.0
"#;

#[test]
fn a_closed_sheet_drives_the_air_column_and_momentum_is_conserved() {
    let (areal_density, density, height) = (5.0, 1.2, 2.0);
    let dir = scratch("closed-column");
    let scenario = dir.join("closed-column.toml");
    std::fs::write(&scenario, CLOSED_COLUMN).unwrap();
    let out = dir.join("run");
    run_ok(&scenario, &out);
    let m = Monitors::read(&out);
    let t = m.column("time");
    let sheet = m.column("structure.momentum.z");
    let air = m.column("fluid.momentum_z");
    // The sheet is 1 m²: momentum per areal density is its velocity.
    for i in 0..t.len() {
        let expected = -areal_density * G * t[i];
        let total = sheet[i] + air[i];
        assert!(
            (total - expected).abs() < 1e-5 * areal_density * G * t[t.len() - 1],
            "t = {} s: momentum {total} against {expected} kg·m/s",
            t[i]
        );
    }
    // The acceleration over the second half, after the start's transient.
    let (i, j) = (t.len() / 2, t.len() - 1);
    let accel = (sheet[j] - sheet[i]) / areal_density / (t[j] - t[i]);
    let exact = -G * areal_density / (areal_density + density * height);
    assert!(
        (accel / exact - 1.0).abs() < 0.01,
        "the sheet accelerates at {accel} m/s² against {exact}"
    );
}

/// The first swing of a canopy: the largest centre deflection over the run
/// and when it comes [m, s].
fn first_swing(out: &std::path::Path) -> (f64, f64) {
    let m = Monitors::read(out);
    let t = m.column("time");
    let d = m.column("structure.centre_deflection");
    let i = (0..d.len()).fold(0, |best, k| if d[k] > d[best] { k } else { best });
    (d[i], t[i])
}

/// The annulus of `canopy-flow.toml` in its flow field against the same
/// canopy in the porous free stream of thesis §2.1 (`canopy-porous.toml`).
/// The fabric drops only 2.5 % of the stream's dynamic pressure, so the
/// stream passes it nearly undisturbed and the two models must load it
/// alike: the first swing's depth and time within 10 %. On 0.15 m cells
/// (6.7 across the canopy's radius, coarser than the shipped scene's 0.1 m
/// to keep the test short) the flow field's swing is 5.6 % shallower
/// (measured): near the rim the δ kernel smears the jump over two cells.
#[test]
fn the_flow_field_loads_a_permeable_canopy_as_the_free_stream_does() {
    let dir = scratch("canopy-flow");
    let end = 0.3;
    let flow = variant("canopy-flow", &dir, |s| {
        s.run.end_time = end;
        s.run.output_interval = end;
        s.coupling.window = 1e-3;
        let b = s.fluid.as_mut().unwrap().flow_box.as_mut().unwrap();
        b.upper[2] = 2.6;
        b.cells = [20, 20, 24];
    });
    let stream = variant("canopy-porous", &dir, |s| {
        s.run.end_time = end;
        s.run.output_interval = end;
    });
    let (flow_out, stream_out) = (dir.join("flow"), dir.join("stream"));
    run_ok(&flow, &flow_out);
    run_ok(&stream, &stream_out);
    let (depth, when) = first_swing(&flow_out);
    let (depth0, when0) = first_swing(&stream_out);
    assert!(
        (depth / depth0 - 1.0).abs() < 0.1,
        "the flow field's swing {depth} m against the free stream's {depth0} m"
    );
    assert!(
        (when / when0 - 1.0).abs() < 0.1,
        "deepest at {when} s against {when0} s"
    );
}
