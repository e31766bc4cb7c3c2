//! Suspension lines: chains of string segments (thesis eq. 3) from the skirt to
//! the confluence, each with a rest-length change and a break rule of its own
//! (dissertation §4.2.3: uneven and breaking lines); and the reefing line's
//! segments round the skirt (`reefing.rs`), which break together when
//! the line is cut.

use crate::network::{Network, NodeKind, Spring};

#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    /// Spring indices of its segments, the skirt end first.
    pub springs: Vec<usize>,
    /// Break at this time [s] …
    pub break_time: Option<f64>,
    /// … or once a segment's tension exceeds this [N].
    pub break_tension: Option<f64>,
    pub broken: bool,
    /// A segment of the reefing line (`reefing.rs`), not a suspension line.
    pub reefing: bool,
}

impl Line {
    /// Whether it can still break: not yet broken, with a time or a tension to break at.
    pub fn may_break(&self) -> bool {
        !self.broken && (self.break_time.is_some() || self.break_tension.is_some())
    }
}

/// Add a line from node `from` to node `to` of `segments` string segments of
/// total rest length `rest`, axial stiffness E·A `ea` [N] and mass per length
/// `density` [kg/m]. Interior nodes start on the straight chord; the line's mass
/// is lumped to its nodes, half a segment to each end node.
#[allow(clippy::too_many_arguments)]
pub fn add_line(
    (x, v, net): (&mut Vec<f64>, &mut Vec<f64>, &mut Network),
    from: usize,
    to: usize,
    segments: usize,
    rest: f64,
    ea: f64,
    density: f64,
) -> Line {
    let seg_rest = rest / segments as f64;
    let seg_mass = density * rest / segments as f64;
    let (a, b) = (
        x[3 * from..3 * from + 3].to_vec(),
        x[3 * to..3 * to + 3].to_vec(),
    );
    let mut nodes = vec![from];
    for s in 1..segments {
        let f = s as f64 / segments as f64;
        let n = net.nodes();
        x.extend((0..3).map(|c| a[c] + f * (b[c] - a[c])));
        v.extend([0.0; 3]);
        net.mass.push(seg_mass);
        net.kind.push(NodeKind::Free);
        nodes.push(n);
    }
    nodes.push(to);
    for end in [from, to] {
        if net.kind[end] == NodeKind::Free {
            net.mass[end] += 0.5 * seg_mass;
        }
    }
    let springs = nodes
        .windows(2)
        .map(|w| {
            net.springs.push(Spring {
                i: w[0],
                j: w[1],
                k: ea / seg_rest,
                rest: seg_rest,
                tension_only: true,
                eps: 0.0,
            });
            net.springs.len() - 1
        })
        .collect();
    Line {
        springs,
        break_time: None,
        break_tension: None,
        broken: false,
        reefing: false,
    }
}

/// Break the `lines` of `net` whose time has come at `time` or whose
/// tension at `x` is too high: the segment at the skirt stops carrying
/// force. Returns a message per break, one for the whole reefing line.
pub fn break_lines(lines: &mut [Line], net: &mut Network, x: &[f64], time: f64) -> Vec<String> {
    let mut events = Vec::new();
    let mut cut: Option<f64> = None;
    for (index, line) in lines.iter_mut().enumerate() {
        if line.broken || (line.break_time.is_none() && line.break_tension.is_none()) {
            continue;
        }
        let tension = line
            .springs
            .iter()
            .map(|&s| net.springs[s].tension(x))
            .fold(0.0, f64::max);
        let due = line.break_time.is_some_and(|t| time >= t)
            || line.break_tension.is_some_and(|t| tension > t);
        if due {
            line.broken = true;
            let top = line.springs[0];
            net.springs[top].k = 0.0;
            if let Some(d) = net.dampers.get_mut(top) {
                d.c = 0.0;
            }
            if line.reefing {
                cut = Some(cut.unwrap_or(0.0).max(tension));
                continue;
            }
            events.push(format!(
                "line {index} broke at t = {time:.6} s with tension {tension:.3} N"
            ));
        }
    }
    if let Some(tension) = cut {
        events.push(format!(
            "the reefing line was cut at t = {time:.6} s with tension {tension:.3} N"
        ));
    }
    if !events.is_empty() {
        net.prepare();
    }
    events
}
