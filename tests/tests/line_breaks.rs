//! Breaking lines in a run (dissertation §4.2.3): the C-9 drop with the 14 lines
//! on the +y half of the skirt breaking at t = 0.1 s. The driver breaks them at
//! the first sub-step past their time and says so in the structure log, and
//! from then on only the −y half pulls, so the payload swings towards −y where
//! by symmetry it would have stayed on the axis. Until the break the run is
//! the unbroken one bit for bit, which lets `c9_in_flow.rs` take the first
//! seconds of `c9-broken-lines` for the even C-9.

use canopy_tests::*;
use structure_section::parachute::LineBreak;

#[test]
fn half_the_lines_break_on_time_and_the_payload_swings_away() {
    let dir = scratch("line-breaks");
    let drop = |name: &str, end: f64, breaks: bool| {
        let here = dir.join(name);
        std::fs::create_dir_all(&here).unwrap();
        let path = variant("c9-drop", &here, |s| {
            s.run.end_time = end;
            s.run.output_interval = 0.0;
            if breaks {
                s.parachute_mut().line_breaks.push(LineBreak {
                    lines: (0..14).collect(),
                    time: Some(0.1),
                    tension: None,
                });
            }
        });
        run_ok(&path, &here.join("run"));
        Monitors::read(&here.join("run"))
    };
    let whole = drop("whole", 0.1, false);
    let m = drop("broken", 0.5, true);
    let log = std::fs::read_to_string(dir.join("broken/run/logs/structure.log")).unwrap();
    let breaks: Vec<&str> = log.lines().filter(|l| l.contains(" broke at ")).collect();
    assert_eq!(breaks.len(), 14, "{log}");
    for (k, b) in breaks.iter().enumerate() {
        // Δt_s = 1e-4 s: the break comes within one sub-step of 0.1 s.
        assert!(
            b.starts_with(&format!("line {k} broke at t = 0.100")),
            "{b}"
        );
    }
    let (t, y) = (m.column("time"), m.column("structure.confluence.y"));
    let before = t.iter().position(|&t| t >= 0.1).unwrap();
    // Bit for bit (a NaN monitor, such as a drag before there is any
    // flow, equals itself here).
    assert_eq!(whole.header, m.header);
    let same = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
    let differs = (0..before).find(|&k| !same(&whole.rows[k], &m.rows[k]));
    assert!(
        differs.is_none(),
        "a break not yet due changed the run at t = {:?} s",
        differs.map(|k| t[k])
    );
    assert!(
        y[before].abs() < 1e-9,
        "on the axis before: y = {} m",
        y[before]
    );
    let last = *y.last().unwrap();
    assert!(last < -1e-3, "payload at y = {last} m after the break");
}
