//! The wake-up event of canopy's iceoryx2 service (`service.rs`): a
//! counter in the event's own shared memory that a sleeping listener waits
//! on with Linux's `futex`. A notification is one atomic add, and one
//! `FUTEX_WAKE` only while the listener sleeps; a sleep is one
//! `FUTEX_WAIT`. iceoryx2's default event (a Unix datagram socket) pays a
//! `sendto` per notification and five system calls per sleep; its
//! semaphore event waits for a monotonic deadline by polling with
//! `nanosleep`. Between two processes taking turns beside other work,
//! every hand-off is a wake-up (`presence.rs`), so those calls are most of
//! what the hand-off costs (docs/src/exchange-speed.md).
//!
//! No notification is lost: the listener compares the counter with the
//! last value it saw, and the kernel compares it once more before it
//! sleeps, so a notification between the listener's look and its sleep
//! makes the sleep return at once.

use crate::futex;
use iceoryx2_bb_elementary_traits::testing::abandonable::Abandonable;
use iceoryx2_bb_elementary_traits::zero_copy_send::ZeroCopySend;
use iceoryx2_bb_lock_free::mpmc::counting_bit_set::RelocatableCountingBitSet;
use iceoryx2_bb_system_types::file_name::FileName;
use iceoryx2_bb_system_types::path::Path;
use iceoryx2_cal::dynamic_storage::{posix_shared_memory, DynamicStorage};
use iceoryx2_cal::event::common::EventImpl;
use iceoryx2_cal::event::event_state::EventState;
use iceoryx2_cal::event::trigger::{Configuration, HandlerInterface, State, WaiterInterface};
use iceoryx2_cal::event::{
    ListenerCreateError, ListenerWaitError, NotifierNotifyError, NotifierOpenError,
};
use iceoryx2_cal::named_concept::{NamedConceptPathHintRemoveError, NamedConceptRemoveError};
use std::mem::MaybeUninit;
use std::ptr::NonNull;
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::Duration;

/// iceoryx2's counting event with the futex trigger.
pub type FutexEvent =
    EventImpl<RelocatableCountingBitSet, FutexMgmt, Storage, FutexNotifier, FutexListener>;
type Storage = posix_shared_memory::Storage<State<RelocatableCountingBitSet, FutexMgmt>>;

/// The trigger's words, in the event's shared memory.
#[derive(Debug)]
#[repr(C)]
pub struct FutexMgmt {
    /// Notifications so far (wrapping).
    count: AtomicU32,
    /// Whether the listener sleeps, or is about to.
    sleeping: AtomicU32,
}

// SAFETY: two plain 32-bit words with a fixed layout, no pointers.
unsafe impl ZeroCopySend for FutexMgmt {}

/// A notifier's end: the shared words.
#[derive(Debug)]
pub struct FutexNotifier {
    mgmt: *const FutexMgmt,
}

/// The listener's end: the shared words and the count it saw last.
#[derive(Debug)]
pub struct FutexListener {
    mgmt: *const FutexMgmt,
    seen: AtomicU32,
}

// SAFETY: the words are atomics in shared memory that iceoryx2 keeps mapped
// as long as the port that holds this end.
unsafe impl Send for FutexNotifier {}
unsafe impl Sync for FutexNotifier {}
unsafe impl Send for FutexListener {}
unsafe impl Sync for FutexListener {}

impl Abandonable for FutexNotifier {
    unsafe fn abandon_in_place(_this: NonNull<Self>) {}
}

impl Abandonable for FutexListener {
    unsafe fn abandon_in_place(_this: NonNull<Self>) {}
}

impl FutexNotifier {
    fn mgmt(&self) -> &FutexMgmt {
        // SAFETY: see the Send impl.
        unsafe { &*self.mgmt }
    }
}

impl FutexListener {
    fn mgmt(&self) -> &FutexMgmt {
        // SAFETY: see the Send impl.
        unsafe { &*self.mgmt }
    }

    /// Sleep until the count moves from what was seen, or `timeout`.
    fn sleep(&self, timeout: Option<Duration>) -> Result<(), ListenerWaitError> {
        let m = self.mgmt();
        let seen = self.seen.load(Ordering::Relaxed);
        // Said before the last look (both SeqCst): a notifier that adds
        // after this look sees the flag and wakes the futex.
        m.sleeping.store(1, Ordering::SeqCst);
        let result = match m.count.load(Ordering::SeqCst) == seen {
            true => futex::wait(&m.count, seen, timeout).map_err(|cut| match cut {
                futex::Cut::Signal => ListenerWaitError::InterruptSignal,
                futex::Cut::Refused(_) => ListenerWaitError::InternalFailure,
            }),
            false => Ok(()),
        };
        m.sleeping.store(0, Ordering::SeqCst);
        self.catch_up();
        result
    }

    /// Every notification so far counts as seen.
    fn catch_up(&self) {
        self.seen
            .store(self.mgmt().count.load(Ordering::Acquire), Ordering::Relaxed);
    }
}

impl<E: EventState, S: DynamicStorage<State<E, FutexMgmt>>> HandlerInterface<E, FutexMgmt, S>
    for FutexNotifier
{
    fn open(
        _name: &FileName,
        _config: &Configuration,
        mgmt: &FutexMgmt,
    ) -> Result<Self, NotifierOpenError> {
        Ok(FutexNotifier { mgmt })
    }

    fn notify(&self) -> Result<(), NotifierNotifyError> {
        let m = self.mgmt();
        m.count.fetch_add(1, Ordering::SeqCst);
        if m.sleeping.load(Ordering::SeqCst) != 0 {
            futex::wake(&m.count);
        }
        Ok(())
    }
}

impl<E: EventState, S: DynamicStorage<State<E, FutexMgmt>>> WaiterInterface<E, FutexMgmt, S>
    for FutexListener
{
    const IS_FILE_DESCRIPTOR_BASED: bool = false;

    unsafe fn remove(
        _name: &FileName,
        _config: &Configuration,
    ) -> Result<bool, NamedConceptRemoveError> {
        // Nothing lives outside the event's shared memory.
        Ok(true)
    }

    fn remove_path_hint(_value: &Path) -> Result<(), NamedConceptPathHintRemoveError> {
        Ok(())
    }

    fn create(
        _name: &FileName,
        _config: &Configuration,
        mgmt: &mut MaybeUninit<FutexMgmt>,
    ) -> Result<Self, ListenerCreateError> {
        let mgmt = mgmt.write(FutexMgmt {
            count: AtomicU32::new(0),
            sleeping: AtomicU32::new(0),
        });
        Ok(FutexListener {
            mgmt,
            seen: AtomicU32::new(0),
        })
    }

    fn try_wait(&self) -> Result<(), ListenerWaitError> {
        self.catch_up();
        Ok(())
    }

    fn timed_wait(&self, timeout: Duration) -> Result<(), ListenerWaitError> {
        self.sleep(Some(timeout))
    }

    fn blocking_wait(&self) -> Result<(), ListenerWaitError> {
        self.sleep(None)
    }

    fn empty_buffer(&self) -> Result<(), ListenerWaitError> {
        self.catch_up();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use crate::channel::{self, block};
    use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
    use std::sync::Arc;
    use std::time::{Duration, Instant};

    /// Two threads take turns through two events, each sleeping on its own
    /// until the other's turn is done: every turn is handed over by one
    /// notification that comes while the listener looks or sleeps. A lost
    /// notification leaves a sleeper to its timeout, so no sleep may last
    /// that long (the first that does stops both sides), and every turn is
    /// seen.
    #[test]
    fn no_notification_is_lost_between_a_look_and_a_sleep() {
        const TURNS: u64 = 20_000;
        const SLICE: Duration = Duration::from_millis(500);
        let name = format!("futex-test-{}", std::process::id());
        let turn = Arc::new(AtomicU64::new(0));
        let lost = Arc::new(AtomicBool::new(false));
        let side = |me: u64| {
            let (name, turn, lost) = (name.clone(), turn.clone(), lost.clone());
            move || {
                let node = channel::node(&format!("{name}-{me}")).unwrap();
                let mine = channel::listener(&node, &format!("{name}/wake{me}")).unwrap();
                let theirs = channel::notifier(&node, &format!("{name}/wake{}", 1 - me)).unwrap();
                for t in (me..2 * TURNS).step_by(2) {
                    // Look, then sleep: as a participant's wait does.
                    while turn.load(Ordering::SeqCst) != t {
                        let slept = Instant::now();
                        block(&mine, SLICE).unwrap();
                        if slept.elapsed() >= SLICE / 2 {
                            lost.store(true, Ordering::SeqCst);
                        }
                        if lost.load(Ordering::SeqCst) {
                            theirs.notify().unwrap();
                            return;
                        }
                    }
                    turn.store(t + 1, Ordering::SeqCst);
                    theirs.notify().unwrap();
                }
            }
        };
        let (a, b) = (std::thread::spawn(side(0)), std::thread::spawn(side(1)));
        a.join().unwrap();
        b.join().unwrap();
        assert!(
            !lost.load(Ordering::SeqCst),
            "a sleep lasted {SLICE:?}/2 or more at turn {}: a notification was lost",
            turn.load(Ordering::SeqCst)
        );
        assert_eq!(turn.load(Ordering::SeqCst), 2 * TURNS);
    }
}
