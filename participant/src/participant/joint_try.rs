//! The end of a participant's try at a window under implicit coupling:
//! its accelerated fields relaxed and sent, alone (the serial scheme) or
//! together with the other writers' (the parallel scheme, `joint.rs`:
//! each sends its share of the joint relaxation and reads the others'),
//! and its word on the try posted.

use super::Participant;
use crate::error::ExchangeError;
use crate::implicit::share_field;
use crate::joint::Share;
use crate::verdict;
use crate::wire::FromParticipant;
use std::time::{Duration, Instant};

/// How often at most a participant tells the coupler of a try closed: a
/// window of many long tries sends no monitor row for minutes, and the
/// coupler, which hears nothing else meanwhile, would take the run for
/// hung after `[coupling] timeout`.
const TRIED_EVERY: Duration = Duration::from_secs(1);

impl Participant {
    /// Close try `iteration` at `window`; returns how long it waited for
    /// the other writers' shares.
    pub(super) fn close_try(
        &mut self,
        window: u64,
        iteration: u32,
    ) -> Result<Duration, ExchangeError> {
        let relaxing = Instant::now();
        let tries = self.tries.as_mut().expect("an implicit plan has tries");
        let presence = &self.waiter.presence;
        let mut waited = Duration::ZERO;
        match tries.settings.parallel {
            false => {
                tries.close_try(&mut self.outputs, presence)?;
            }
            true => {
                let own = tries.share_try();
                let shares;
                (shares, waited) = self.exchange_shares(own)?;
                let tries = self.tries.as_mut().expect("an implicit plan has tries");
                let presence = &self.waiter.presence;
                tries.close_joint(&Share::total(&shares), &mut self.outputs, presence)?;
            }
        }
        self.clock.stats.accelerate_s += relaxing.elapsed().saturating_sub(waited).as_secs_f64();
        let tries = self.tries.as_ref().expect("an implicit plan has tries");
        let presence = &self.waiter.presence;
        let word = verdict::word(window, iteration, tries.converged);
        presence.own().post_word(word, tries.worst());
        presence.wake_all_sleeping()?;
        if self.reported.elapsed() >= TRIED_EVERY {
            let tries = iteration + 1;
            self.control
                .post(&FromParticipant::Tried { window, tries })?;
            self.reported = Instant::now();
        }
        Ok(waited)
    }

    /// Send `own` share to the other writers and read theirs: every
    /// writer's share in the run's participant order, and how long their
    /// arrival was waited for.
    fn exchange_shares(&mut self, own: Share) -> Result<(Vec<Share>, Duration), ExchangeError> {
        let values = own.to_values();
        let out = self
            .outputs
            .find(&share_field(&self.name))
            .expect("a writer under the parallel scheme declares its share");
        let presence = &self.waiter.presence;
        self.outputs
            .write(out, values.len(), |v| v.copy_from_slice(&values), presence)?;
        let mut shares = Vec::new();
        let mut waited = Duration::ZERO;
        for name in self.setup.participants.clone() {
            if name == self.name {
                shares.push(own.clone());
                continue;
            }
            let field = share_field(&name);
            if !self.is_connected(&field) {
                continue;
            }
            let (view, w) = self.receive(&field)?;
            waited += w;
            let share = Share::from_values(&view)
                .ok_or_else(|| ExchangeError::MalformedShare(name.clone(), view.len()))?;
            shares.push(share);
        }
        Ok((shares, waited))
    }
}
