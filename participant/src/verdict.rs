//! Whether an implicit window goes on or is taken again: every participant
//! posts a word on its try at the window (window, try, whether its own
//! accelerated fields converged) on its blackboard, and each then reads
//! all the others' words and comes to the same verdict by the same rule.
//! No coupler takes part, so a try costs no round trip through it.
//!
//! A participant that already posted a later word has seen the verdict on
//! this try: a later try at the same window means "again", a later window
//! "go on". That happens when a participant needs nothing more from the
//! others before its next try, such as the fluid once the structure has
//! sent its relaxed positions.

/// A word: 0 is "none yet"; windows count from 1 in it.
pub fn word(window: u64, iteration: u32, converged: bool) -> u64 {
    (window + 1) << 20 | (iteration as u64 & 0x7ffff) << 1 | converged as u64
}

fn read(word: u64) -> Option<(u64, u32, bool)> {
    let window = (word >> 20).checked_sub(1)?;
    Some((window, ((word >> 1) & 0x7ffff) as u32, word & 1 == 1))
}

/// What the others' words say about try `iteration` at `window`.
#[derive(Debug, Clone, PartialEq)]
pub enum Heard {
    /// Someone has not posted on it yet.
    Waiting,
    /// Every word is on it: the participants whose fields did not converge.
    All { unconverged: Vec<usize> },
    /// Someone is past it, so the verdict was given: again (true) or go on.
    Decided(bool),
}

/// Read `words` (participant index, word) on try `iteration` at `window`.
pub fn hear(words: impl Iterator<Item = (usize, u64)>, window: u64, iteration: u32) -> Heard {
    let mut unconverged = Vec::new();
    for (p, w) in words {
        let Some((pw, pk, converged)) = read(w) else {
            return Heard::Waiting;
        };
        match (pw, pk).cmp(&(window, iteration)) {
            std::cmp::Ordering::Less => return Heard::Waiting,
            std::cmp::Ordering::Greater => return Heard::Decided(pw == window),
            std::cmp::Ordering::Equal if !converged => unconverged.push(p),
            std::cmp::Ordering::Equal => {}
        }
    }
    Heard::All { unconverged }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_say_where_each_participant_is() {
        let at = |w, k, c| word(w, k, c);
        let heard = |ws: &[u64]| hear(ws.iter().copied().enumerate(), 3, 1);
        assert_eq!(heard(&[0, at(3, 1, true)]), Heard::Waiting);
        assert_eq!(heard(&[at(3, 0, false), at(3, 1, true)]), Heard::Waiting);
        let all = heard(&[at(3, 1, false), at(3, 1, true)]);
        assert_eq!(
            all,
            Heard::All {
                unconverged: vec![0]
            }
        );
        assert_eq!(
            heard(&[at(3, 2, false), at(3, 1, true)]),
            Heard::Decided(true)
        );
        assert_eq!(
            heard(&[at(4, 0, false), at(3, 1, true)]),
            Heard::Decided(false)
        );
    }
}
