//! A reefing line round the skirt (Knacke, *Parachute Recovery Systems
//! Design Manual*, 1992, ch. 6): a cord through rings at the skirt's gore
//! seams whose length π·τ·D₀ holds the mouth to a circle of diameter τ·D₀,
//! τ the reefing ratio, until cutters release it and the canopy opens on.
//!
//! The cord is tied at each ring: one tension-only segment from each seam
//! to the next, of rest length L_R/N and the suspension lines' axial
//! stiffness and mass per length. A cord sliding freely through its rings
//! would carry one tension all round; tied, each segment carries its own,
//! which differ only where the mouth is uneven. Cut, every segment stops
//! carrying force at once (`lines::break_lines`).

use crate::lines::add_line;
use crate::model::Model;
use structure_section::Parachute;

/// Ties the reefing line of `p`, if it has one, through the seam nodes
/// `skirt`, in order round the skirt, of the suspension lines' material.
pub fn add_reefing_line(m: &mut Model, p: &Parachute, skirt: &[usize]) {
    let Some(r) = &p.reefing else { return };
    let rest = r.length(p.geometry().diameter) / skirt.len() as f64;
    for (k, &from) in skirt.iter().enumerate() {
        let to = skirt[(k + 1) % skirt.len()];
        let mut segment = add_line(
            (&mut m.x, &mut m.v, &mut m.net),
            from,
            to,
            1,
            rest,
            p.line_axial_stiffness,
            p.line_density,
        );
        segment.reefing = true;
        segment.break_time = r.cut_time;
        m.lines.push(segment);
    }
}
