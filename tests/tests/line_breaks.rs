//! Breaking lines in a run (dissertation §4.2.3): the C-9 drop with the 14 lines
//! on the +y half of the skirt breaking at t = 0.1 s. The driver breaks them at
//! the first sub-step past their time and says so in the structure log, and
//! from then on only the −y half pulls, so the payload swings towards −y where
//! by symmetry it would have stayed on the axis.

use canopy_tests::*;
use structure_section::parachute::LineBreak;

#[test]
fn half_the_lines_break_on_time_and_the_payload_swings_away() {
    let dir = scratch("line-breaks");
    let path = variant("c9-drop", &dir, |s| {
        s.run.end_time = 0.5;
        s.run.output_interval = 0.0;
        let p = s.parachute_mut();
        p.line_breaks.push(LineBreak {
            lines: (0..14).collect(),
            time: Some(0.1),
            tension: None,
        });
    });
    run_ok(&path, &dir.join("run"));
    let log = std::fs::read_to_string(dir.join("run/logs/structure.log")).unwrap();
    let breaks: Vec<&str> = log.lines().filter(|l| l.contains(" broke at ")).collect();
    assert_eq!(breaks.len(), 14, "{log}");
    for (k, b) in breaks.iter().enumerate() {
        // Δt_s = 1e-4 s: the break comes within one sub-step of 0.1 s.
        assert!(
            b.starts_with(&format!("line {k} broke at t = 0.100")),
            "{b}"
        );
    }
    let m = Monitors::read(&dir.join("run"));
    let (t, y) = (m.column("time"), m.column("structure.confluence.y"));
    let before = t.iter().position(|&t| t >= 0.1).unwrap();
    assert!(
        y[before].abs() < 1e-9,
        "on the axis before: y = {} m",
        y[before]
    );
    let last = *y.last().unwrap();
    assert!(last < -1e-3, "payload at y = {last} m after the break");
}
