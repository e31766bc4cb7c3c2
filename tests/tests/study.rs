//! `coupler study accuracy` from the command line, as a user runs it: it
//! hands over to the `study` executable and leaves a CSV, a Markdown table and
//! the work-precision plot as PNG and SVG. The undamped oscillator's exact
//! solution is x₀·cos(ω₀t) (seed 003 appendix A with c = 0).

use canopy_tests::*;

#[test]
fn accuracy_study_writes_csv_table_and_plots() {
    let dir = scratch("study");
    let out = dir.join("osc");
    let o = coupler(&[
        "study",
        "accuracy",
        "--system",
        "oscillator",
        "--integrators",
        "rk4,velocity-verlet",
        "--levels",
        "6",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        o.status.success(),
        "study failed:\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let csv = std::fs::read_to_string(out.join("accuracy.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), 12, "2 integrators × 6 steps");
    // Halving the step divides RK4's error by 2⁴ and Verlet's by 2², within 10 %.
    for (name, order) in [("rk4", 4), ("velocity-verlet", 2)] {
        let errors: Vec<f64> = rows
            .iter()
            .filter(|r| r[0] == name)
            .map(|r| r[2].parse().unwrap())
            .collect();
        let ratio = errors[4] / errors[5];
        let expected = 2f64.powi(order);
        assert!(
            (ratio / expected - 1.0).abs() < 0.1,
            "{name}: error ratio {ratio}, expected {expected}"
        );
    }
    let table = std::fs::read_to_string(out.join("accuracy.md")).unwrap();
    assert!(table.contains("| rk4 | 4 |") && table.contains("| velocity-verlet | 2 |"));
    let png = std::fs::read(out.join("work-precision.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let svg = std::fs::read_to_string(out.join("work-precision.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("velocity-verlet"));
}

#[test]
fn an_unknown_integrator_is_bad_input() {
    let o = coupler(&["study", "accuracy", "--integrators", "leapfrog"]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("no integrator is called `leapfrog`"), "{err}");
}
