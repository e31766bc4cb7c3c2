//! Suspension lines: chains of string segments (thesis eq. 3) from the skirt to
//! the confluence, each with a rest-length change and a break rule of its own
//! (dissertation §4.2.3: uneven and breaking lines).

use crate::model::{Model, NodeKind, Spring};

#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    /// Spring indices of its segments, the skirt end first.
    pub springs: Vec<usize>,
    /// Break at this time [s] …
    pub break_time: Option<f64>,
    /// … or once a segment's tension exceeds this [N].
    pub break_tension: Option<f64>,
    pub broken: bool,
}

/// Add a line from node `from` to node `to` of `segments` string segments of
/// total rest length `rest`, axial stiffness E·A `ea` [N] and mass per length
/// `density` [kg/m]. Interior nodes start on the straight chord; the line's mass
/// is lumped to its nodes, half a segment to each end node.
#[allow(clippy::too_many_arguments)]
pub fn add_line(
    m: &mut Model,
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
        m.x[3 * from..3 * from + 3].to_vec(),
        m.x[3 * to..3 * to + 3].to_vec(),
    );
    let mut nodes = vec![from];
    for s in 1..segments {
        let f = s as f64 / segments as f64;
        let n = m.nodes();
        m.x.extend((0..3).map(|c| a[c] + f * (b[c] - a[c])));
        m.v.extend([0.0; 3]);
        m.mass.push(seg_mass);
        m.kind.push(NodeKind::Free);
        nodes.push(n);
    }
    nodes.push(to);
    for end in [from, to] {
        if m.kind[end] == NodeKind::Free {
            m.mass[end] += 0.5 * seg_mass;
        }
    }
    let springs = nodes
        .windows(2)
        .map(|w| {
            m.springs.push(Spring {
                i: w[0],
                j: w[1],
                k: ea / seg_rest,
                rest: seg_rest,
                tension_only: true,
                eps: 0.0,
            });
            m.springs.len() - 1
        })
        .collect();
    Line {
        springs,
        break_time: None,
        break_tension: None,
        broken: false,
    }
}

impl Model {
    /// Break the lines whose time has come or whose tension is too high: the
    /// segment at the skirt stops carrying force. Returns a message per break.
    pub fn break_lines(&mut self) -> Vec<String> {
        let mut events = Vec::new();
        for (index, line) in self.lines.iter_mut().enumerate() {
            if line.broken || (line.break_time.is_none() && line.break_tension.is_none()) {
                continue;
            }
            let tension = line
                .springs
                .iter()
                .map(|&s| self.springs[s].tension(&self.x))
                .fold(0.0, f64::max);
            let due = line.break_time.is_some_and(|t| self.time >= t)
                || line.break_tension.is_some_and(|t| tension > t);
            if due {
                line.broken = true;
                let top = line.springs[0];
                self.springs[top].k = 0.0;
                if let Some(d) = self.dampers.get_mut(top) {
                    d.c = 0.0;
                }
                events.push(format!(
                    "line {index} broke at t = {:.6} s with tension {tension:.3} N",
                    self.time
                ));
            }
        }
        if !events.is_empty() {
            self.prepare();
        }
        events
    }
}
