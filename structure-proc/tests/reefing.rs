//! The reefing line (issue 46, item 5; Knacke 1992, ch. 6): a cord of
//! length π·τ·D₀ tied through rings at the skirt's seams. Built on the
//! packed C-9 of `scenarios/c9-drop.toml`, it is checked against the
//! statics of a loop of tied segments: slack at the packed start, and
//! with the seams spread on a regular N-gon of circumradius R each seam
//! pulled in along the radius by 2·T·sin(π/N), T = E·A·(ℓ/ℓ₀ − 1) with
//! ℓ = 2R·sin(π/N) and ℓ₀ = π·τ·D₀/N; its mass is the line's density
//! times its length; cut, it pulls no more, and a window taken again from
//! a checkpoint before the cut has it whole.

mod common;

use common::{c9_drop, point};
use structure_proc::checkpoint::Checkpoint;
use structure_proc::forces::Loads;
use structure_proc::{build_model, Model};
use structure_section::parachute::Reefing;
use structure_section::{ParachuteModel, StructureSection};

const RATIO: f64 = 0.2;
const CUT: f64 = 0.5;
const PACK: f64 = 1.0;

/// The packed C-9, reefed at `RATIO` and cut at `CUT`, or unreefed.
fn packed(reefed: bool) -> (StructureSection, Model) {
    let s = c9_drop(|p| {
        p.pack_diameter = Some(PACK);
        p.reefing = reefed.then_some(Reefing {
            ratio: RATIO,
            cut_time: Some(CUT),
        });
    });
    let m = build_model(&s, None, 1e-4).unwrap();
    (s, m)
}

/// The seam nodes where the lines start, round the skirt.
fn seams(m: &Model) -> Vec<usize> {
    let lines = m.lines.iter().filter(|l| !l.reefing);
    lines.map(|l| m.net.springs[l.springs[0]].i).collect()
}

/// The force the reefed model's nodes feel beyond the unreefed one's at
/// the same positions and velocities, less the gravity on the cord's mass.
fn reefing_force(reefed: &Model, bare: &Model, gravity: [f64; 3]) -> Vec<f64> {
    let mut f = vec![0.0; reefed.x.len()];
    let mut g = vec![0.0; bare.x.len()];
    reefed.force(&Loads::default(), &mut f);
    bare.force(&Loads::default(), &mut g);
    let mut df: Vec<f64> = f.iter().zip(&g).map(|(a, b)| a - b).collect();
    for n in 0..reefed.net.nodes() {
        let dm = reefed.net.mass[n] - bare.net.mass[n];
        (0..3).for_each(|c| df[3 * n + c] -= dm * gravity[c]);
    }
    df
}

/// Puts the seams on a regular polygon of circumradius `r` about the
/// axis at their own heights, in both models.
fn spread_seams(models: [&mut Model; 2], seams: &[usize], r: f64) {
    let n = seams.len() as f64;
    for m in models {
        for (k, &s) in seams.iter().enumerate() {
            let a = std::f64::consts::TAU * k as f64 / n;
            m.x[3 * s] = r * a.cos();
            m.x[3 * s + 1] = r * a.sin();
        }
    }
}

#[test]
fn a_reefing_line_starts_slack_and_weighs_its_length() {
    let (s, reefed) = packed(true);
    let (_, bare) = packed(false);
    let d0 = ParachuteModel::C9.geometry().unwrap().diameter;
    let p = s.parachute.as_ref().unwrap();
    assert_eq!(
        reefed.net.nodes(),
        bare.net.nodes(),
        "tied segments add no node"
    );
    let added: f64 = reefed.net.mass.iter().sum::<f64>() - bare.net.mass.iter().sum::<f64>();
    let expected = p.line_density * std::f64::consts::PI * RATIO * d0;
    assert!(
        (added / expected - 1.0).abs() < 1e-9,
        "{added} kg against {expected}"
    );
    let df = reefing_force(&reefed, &bare, s.gravity);
    let most = df.iter().fold(0.0f64, |a, f| a.max(f.abs()));
    assert!(most < 1e-9, "the slack line pulls {most} N");
}

#[test]
fn a_reefed_skirt_spread_wider_is_pulled_in_as_the_loops_statics_say() {
    let (s, mut reefed) = packed(true);
    let (_, mut bare) = packed(false);
    let p = s.parachute.as_ref().unwrap();
    let d0 = ParachuteModel::C9.geometry().unwrap().diameter;
    let seams = seams(&bare);
    let n = seams.len() as f64;
    let (sin, rest) = (
        (std::f64::consts::PI / n).sin(),
        std::f64::consts::PI * RATIO * d0 / n,
    );
    // Stretched 2 %: the mouth 2 % wider than τ·D₀'s polygon.
    let r = 1.02 * rest / (2.0 * sin);
    spread_seams([&mut reefed, &mut bare], &seams, r);
    let tension = p.line_axial_stiffness * (2.0 * r * sin / rest - 1.0);
    let df = reefing_force(&reefed, &bare, s.gravity);
    for &k in &seams {
        let [x, y, _] = point(&reefed, k);
        let inward = -(df[3 * k] * x + df[3 * k + 1] * y) / r;
        let along = (df[3 * k + 1] * x - df[3 * k] * y) / r;
        let expected = 2.0 * tension * sin;
        assert!(
            (inward / expected - 1.0).abs() < 1e-9,
            "seam {k}: {inward} N against {expected}"
        );
        assert!(along.abs() < 1e-9 * expected && df[3 * k + 2].abs() < 1e-9 * expected);
    }
    let elsewhere = (0..reefed.net.nodes()).filter(|k| !seams.contains(k));
    let most = elsewhere
        .flat_map(|k| df[3 * k..3 * k + 3].to_vec())
        .fold(0.0f64, |a, f| a.max(f.abs()));
    assert!(most < 1e-9, "{most} N off the seams");
}

#[test]
fn cut_the_reefing_line_pulls_no_more_and_a_checkpoint_mends_it() {
    let (s, mut reefed) = packed(true);
    let (_, mut bare) = packed(false);
    let seams = seams(&bare);
    let d0 = ParachuteModel::C9.geometry().unwrap().diameter;
    let rest = std::f64::consts::PI * RATIO * d0 / seams.len() as f64;
    let r = 1.1 * rest / (2.0 * (std::f64::consts::PI / seams.len() as f64).sin());
    spread_seams([&mut reefed, &mut bare], &seams, r);
    let mut before = Checkpoint::default();
    reefed.save(&mut before);
    assert!(reefed.break_lines(0.999 * CUT).is_empty());
    let events = reefed.break_lines(CUT);
    assert_eq!(events.len(), 1, "{events:?}");
    assert!(
        events[0].starts_with("the reefing line was cut at t = 0.5"),
        "{events:?}"
    );
    let largest = |m: &Model| {
        let df = reefing_force(m, &bare, s.gravity);
        df.iter().fold(0.0f64, |a, f| a.max(f.abs()))
    };
    assert!(
        largest(&reefed) < 1e-9,
        "cut, it still pulls {} N",
        largest(&reefed)
    );
    reefed.restore(&before);
    assert!(
        largest(&reefed) > 1.0,
        "mended, it pulls {} N",
        largest(&reefed)
    );
}
