//! The iceoryx2 plumbing shared by the coupler's end and the participants':
//! message ports for bincode control messages, `[f64]` ports for fields,
//! wake-up events, the blackboard flag on which a waiting participant says
//! it sleeps, and a wait that spins briefly and then blocks.
//!
//! Nothing is lost on these channels: a full buffer holds its writer back
//! rather than dropping a value, and every field value carries its number
//! in the sequence of values written, which its reader checks.

use iceoryx2::node::NodeView;
use iceoryx2::port::listener::{Listener, ListenerWaitError};
use iceoryx2::port::notifier::Notifier;
use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::reader::EntryHandle;
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::port::writer::EntryHandleMut;
use iceoryx2::port::{BackpressureAction, BackpressureInfo};
use iceoryx2::prelude::*;
use std::time::{Duration, Instant};

pub use crate::service::Ipc;
pub type BytesOut = Publisher<Ipc, [u8], ()>;
pub type BytesIn = Subscriber<Ipc, [u8], ()>;
/// A field value's header: its number in the sequence of values written,
/// and when it was sent ([`monotonic_ns`]).
pub type Stamp = [u64; 2];
/// A field's publisher.
pub type FieldOut = Publisher<Ipc, [f64], Stamp>;
pub type FieldIn = Subscriber<Ipc, [f64], Stamp>;
pub type FieldSample = iceoryx2::sample::Sample<Ipc, [f64], Stamp>;
/// A field's value being written, in loaned shared memory.
pub type FieldLoan = iceoryx2::sample_mut::SampleMut<Ipc, [f64], Stamp>;
/// A participant's own "asleep" flag, and another's, read.
pub type FlagOut = EntryHandleMut<Ipc, u64, u64>;
pub type FlagIn = EntryHandle<Ipc, u64, u64>;
pub type Board = iceoryx2::service::port_factory::blackboard::PortFactory<Ipc, u64>;

/// How long a waiting side polls before it blocks on its event, when it
/// has no reason to expect its data soon.
pub const SPIN: Duration = Duration::from_micros(60);
/// Longest single block on an event before the abort flag, the deadline
/// and the data are checked again (a lost wake-up costs at most this).
pub const BLOCK_SLICE: Duration = Duration::from_millis(10);
/// Unread values a field's reader may hold back before its writer waits.
/// Under the staggered schedule a reader takes each value before its writer
/// can make the next, but for the last ones, which nobody reads.
const FIELD_BUFFER: usize = 2;
/// Unread control messages before their sender waits.
const MESSAGE_BUFFER: usize = 16;
/// The key of the one entry on a participant's blackboard.
pub const ASLEEP_KEY: u64 = 0;
/// A participant's word on its last try at a window (`verdict.rs`), and
/// with it its worst unconverged field: index among the measured + 1 (0:
/// none), ‖r‖₂ and ‖x‖₂ as f64 bits.
pub const TRY_KEYS: [u64; 4] = [1, 2, 3, 4];

#[derive(Debug, thiserror::Error)]
pub enum ChannelError {
    #[error("iceoryx2: {0}")]
    Ipc(String),
    #[error("no answer within {0:.1} s")]
    Timeout(f64),
    #[error("aborted")]
    Aborted,
    #[error("malformed control message: {0}")]
    Decode(String),
}

pub fn ipc_err<E: std::fmt::Debug>(what: &'static str) -> impl Fn(E) -> ChannelError {
    move |e| ChannelError::Ipc(format!("{what}: {e:?}"))
}

fn service_name(name: &str) -> Result<ServiceName, ChannelError> {
    name.try_into().map_err(ipc_err("service name"))
}

/// iceoryx2 warns on stderr that it runs with its built-in default config;
/// that is intended here, and the warning would pollute every log.
fn quiet() {
    set_log_level(LogLevel::Error);
}

/// A node for this process. Signal handling is left to the process: a
/// participant killed by a signal must die, and the coupler handles Ctrl-C itself.
pub fn node(name: &str) -> Result<Node<Ipc>, ChannelError> {
    quiet();
    let node_name: NodeName = name.try_into().map_err(ipc_err("node name"))?;
    NodeBuilder::new()
        .name(&node_name)
        .config(&node_config())
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<Ipc>()
        .map_err(ipc_err("create node"))
}

/// iceoryx2's defaults with its own cleanup of dead nodes off: run when a
/// node is created or dropped or a service opened, it can wait for ever on
/// a shared-memory file that a process killed while creating it left empty
/// (iceoryx2 0.10 retries a zero-sized mapping with no timeout), and then
/// a participant or the coupler hangs. The coupler cleans instead, between
/// runs and with a time limit ([`cleanup_dead_nodes`]).
fn node_config() -> Config {
    let mut config = Config::global_config().clone();
    config.global.node.cleanup_dead_nodes_on_creation = false;
    config.global.node.cleanup_dead_nodes_on_destruction = false;
    config.global.service.cleanup_dead_nodes_on_open = false;
    config
}

// Both ends must open a service with identical settings, so one function each.

fn bytes_service(
    node: &Node<Ipc>,
    name: &str,
) -> Result<
    iceoryx2::service::port_factory::publish_subscribe::PortFactory<Ipc, [u8], ()>,
    ChannelError,
> {
    node.service_builder(&service_name(name)?)
        .publish_subscribe::<[u8]>()
        .max_publishers(1)
        .max_subscribers(1)
        .subscriber_max_buffer_size(MESSAGE_BUFFER)
        .subscriber_max_borrowed_samples(2)
        .enable_safe_overflow(false)
        .history_size(0)
        .open_or_create()
        .map_err(ipc_err("open message service"))
}

fn field_service(
    node: &Node<Ipc>,
    name: &str,
    readers: usize,
) -> Result<
    iceoryx2::service::port_factory::publish_subscribe::PortFactory<Ipc, [f64], Stamp>,
    ChannelError,
> {
    node.service_builder(&service_name(name)?)
        .publish_subscribe::<[f64]>()
        .user_header::<Stamp>()
        .max_publishers(1)
        .max_subscribers(readers.max(1))
        .subscriber_max_buffer_size(FIELD_BUFFER)
        // The value being read and the one before, while a reader swaps them.
        .subscriber_max_borrowed_samples(2)
        .enable_safe_overflow(false)
        .history_size(0)
        .open_or_create()
        .map_err(ipc_err("open field service"))
}

pub fn bytes_out(node: &Node<Ipc>, name: &str) -> Result<BytesOut, ChannelError> {
    bytes_service(node, name)?
        .publisher_builder()
        // A batch of monitor rows fits without growing the segment.
        .initial_max_slice_len(1 << 16)
        .allocation_strategy(AllocationStrategy::PowerOfTwo)
        .backpressure_strategy(BackpressureStrategy::RetryUntilDelivered)
        .max_loaned_samples(1)
        .create()
        .map_err(ipc_err("create message publisher"))
}

pub fn bytes_in(node: &Node<Ipc>, name: &str) -> Result<BytesIn, ChannelError> {
    bytes_service(node, name)?
        .subscriber_builder()
        .create()
        .map_err(ipc_err("create message subscriber"))
}

/// A field publisher for `readers` readers; `len_hint` values fit without
/// reallocation, larger loans grow the segment. A reader whose buffer is
/// full holds the writer back for at most `patience`; then the send fails
/// (a reader that does not read every value it declared).
pub fn field_out(
    node: &Node<Ipc>,
    name: &str,
    readers: usize,
    len_hint: usize,
    patience: Duration,
) -> Result<FieldOut, ChannelError> {
    field_service(node, name, readers)?
        .publisher_builder()
        .initial_max_slice_len(len_hint.max(1))
        .allocation_strategy(AllocationStrategy::PowerOfTwo)
        .backpressure_strategy(BackpressureStrategy::RetryUntilDelivered)
        .set_backpressure_handler(move |info: &BackpressureInfo| {
            if info.elapsed_time < patience {
                std::thread::yield_now();
                BackpressureAction::Retry
            } else {
                BackpressureAction::DiscardDataAndFail
            }
        })
        .max_loaned_samples(1)
        .create()
        .map_err(ipc_err("create field publisher"))
}

pub fn field_in(node: &Node<Ipc>, name: &str, readers: usize) -> Result<FieldIn, ChannelError> {
    field_service(node, name, readers)?
        .subscriber_builder()
        .create()
        .map_err(ipc_err("create field subscriber"))
}

fn event(
    node: &Node<Ipc>,
    name: &str,
) -> Result<iceoryx2::service::port_factory::event::PortFactory<Ipc>, ChannelError> {
    // One event id (the default, 0): a listener's every wake-up drains
    // all the ids the service holds (255 by iceoryx2's default).
    node.service_builder(&service_name(name)?)
        .event()
        .event_id_max_value(0)
        .open_or_create()
        .map_err(ipc_err("open event service"))
}

pub fn notifier(node: &Node<Ipc>, name: &str) -> Result<Notifier<Ipc>, ChannelError> {
    event(node, name)?
        .notifier_builder()
        .create()
        .map_err(ipc_err("create notifier"))
}

pub fn listener(node: &Node<Ipc>, name: &str) -> Result<Listener<Ipc>, ChannelError> {
    event(node, name)?
        .listener_builder()
        .create()
        .map_err(ipc_err("create listener"))
}

/// Every key of a participant's blackboard, in the order of its entries.
const BOARD_KEYS: [u64; 5] = [
    ASLEEP_KEY,
    TRY_KEYS[0],
    TRY_KEYS[1],
    TRY_KEYS[2],
    TRY_KEYS[3],
];

/// The entries of [`BOARD_KEYS`], each as `entry` opens it.
fn entries<T>(entry: impl Fn(&u64) -> Result<T, ChannelError>) -> Result<[T; 5], ChannelError> {
    let all = BOARD_KEYS
        .iter()
        .map(entry)
        .collect::<Result<Vec<T>, _>>()?;
    Ok(all
        .try_into()
        .unwrap_or_else(|_| unreachable!("one entry per key")))
}

/// A participant's own blackboard with its "asleep" flag (0: awake) and
/// its word on its last try at a window (0: none yet), [`TRY_KEYS`].
pub fn own_flag(node: &Node<Ipc>, name: &str) -> Result<(Board, [FlagOut; 5]), ChannelError> {
    let mut creator = node
        .service_builder(&service_name(name)?)
        .blackboard_creator::<u64>();
    for key in BOARD_KEYS {
        creator = creator.add::<u64>(key, 0);
    }
    let board = creator.create().map_err(ipc_err("create blackboard"))?;
    let writer = board
        .writer_builder()
        .create()
        .map_err(ipc_err("create blackboard writer"))?;
    let flags = entries(|key| {
        writer
            .entry::<u64>(key)
            .map_err(ipc_err("blackboard entry"))
    })?;
    Ok((board, flags))
}

/// Another participant's "asleep" flag and word on its last try, to read.
pub fn peer_flag(node: &Node<Ipc>, name: &str) -> Result<(Board, [FlagIn; 5]), ChannelError> {
    let board = node
        .service_builder(&service_name(name)?)
        .blackboard_opener::<u64>()
        .open()
        .map_err(ipc_err("open blackboard"))?;
    let reader = board
        .reader_builder()
        .create()
        .map_err(ipc_err("create blackboard reader"))?;
    let flags = entries(|key| {
        reader
            .entry::<u64>(key)
            .map_err(ipc_err("blackboard entry"))
    })?;
    Ok((board, flags))
}

/// The system-wide monotonic clock in nanoseconds: comparable between the
/// processes of one machine, so a reader can tell how long after its
/// sending a value arrived.
pub fn monotonic_ns() -> u64 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime only writes into the struct we pass.
    unsafe { libc::clock_gettime(libc::CLOCK_MONOTONIC, &mut t) };
    t.tv_sec as u64 * 1_000_000_000 + t.tv_nsec as u64
}

/// Encode and publish one control message, then wake the reader.
pub fn send_message<T: serde::Serialize>(
    out: &BytesOut,
    wake: &Notifier<Ipc>,
    msg: &T,
) -> Result<(), ChannelError> {
    post_message(out, msg)?;
    wake.notify().map_err(ipc_err("notify"))?;
    Ok(())
}

/// Encode and publish one control message for a reader that looks by
/// itself: no wake-up, whose system call costs tens of µs on a virtual
/// machine.
pub fn post_message<T: serde::Serialize>(out: &BytesOut, msg: &T) -> Result<(), ChannelError> {
    let bytes = crate::wire::encode(msg);
    let sample = out
        .loan_slice_uninit(bytes.len())
        .map_err(ipc_err("loan message"))?;
    sample
        .write_from_slice(&bytes)
        .send()
        .map_err(ipc_err("send message"))?;
    Ok(())
}

/// Take one control message if one is waiting.
pub fn try_receive_message<T: for<'de> serde::Deserialize<'de>>(
    inp: &BytesIn,
) -> Result<Option<T>, ChannelError> {
    match inp.receive().map_err(ipc_err("receive message"))? {
        None => Ok(None),
        Some(sample) => crate::wire::decode(sample.payload())
            .map(Some)
            .map_err(|e| ChannelError::Decode(e.to_string())),
    }
}

/// Poll `poll` until it yields, spinning for [`SPIN`] and then blocking on
/// `listener`. Gives up at `timeout` or when `abort()` turns true.
pub fn wait_until<T>(
    listener: &Listener<Ipc>,
    timeout: Option<Duration>,
    abort: &dyn Fn() -> bool,
    mut poll: impl FnMut() -> Result<Option<T>, ChannelError>,
) -> Result<T, ChannelError> {
    let start = Instant::now();
    loop {
        if let Some(v) = poll()? {
            return Ok(v);
        }
        let waited = start.elapsed();
        if waited < SPIN {
            std::thread::yield_now();
            continue;
        }
        if abort() {
            return Err(ChannelError::Aborted);
        }
        let slice = match timeout {
            Some(t) if waited >= t => return Err(ChannelError::Timeout(t.as_secs_f64())),
            Some(t) => (t - waited).min(BLOCK_SLICE),
            None => BLOCK_SLICE,
        };
        block(listener, slice)?;
    }
}

/// Sleep on `listener` for at most `slice`. A notification that arrived
/// before is kept by the event, so this returns at once then.
pub fn block(listener: &Listener<Ipc>, slice: Duration) -> Result<(), ChannelError> {
    // A slice of at least 1 µs: iceoryx2's socket event, used before the
    // futex event (`futex_event.rs`), took a zero timeout for "for ever",
    // and the coupler, which polls for rows posted without a wake-up, hung
    // in the last moments before a deadline. The futex takes zero as zero;
    // the floor stays so that no event can block for ever here.
    let slice = slice.max(MIN_BLOCK);
    match listener.timed_wait(|_| {}, slice) {
        // A signal (SIGCHLD, SIGINT handled elsewhere) only cuts the wait short.
        Ok(_) | Err(ListenerWaitError::InterruptSignal) => Ok(()),
        Err(e) => Err(ipc_err("wait on event")(e)),
    }
}

/// The shortest wait [`block`] passes to iceoryx2 (see there).
pub const MIN_BLOCK: Duration = Duration::from_micros(1);

/// Remove what dead canopy processes left behind (shared memory, service
/// entries), and the entries of nodes whose process was killed while it
/// created them. Returns how many dead nodes were cleaned. Shared-memory
/// files left empty go first (older than [`HALF_CREATED_AGE`]); should a
/// fresher one still hold iceoryx2's cleanup, it is left to the next call
/// after [`CLEANUP_WITHIN`].
#[cfg_attr(not(feature = "coupler"), allow(dead_code))]
pub fn cleanup_dead_nodes() -> usize {
    quiet();
    remove_empty_shared_memory(HALF_CREATED_AGE);
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(cleanup_listed_dead_nodes());
    });
    rx.recv_timeout(CLEANUP_WITHIN).unwrap_or(0)
}

/// How long [`cleanup_dead_nodes`] lets iceoryx2 clean.
#[cfg_attr(not(feature = "coupler"), allow(dead_code))]
pub const CLEANUP_WITHIN: Duration = Duration::from_secs(5);

/// Where iceoryx2 keeps its shared memory (POSIX shm on Linux); its files
/// start with the config's prefix.
#[cfg_attr(not(feature = "coupler"), allow(dead_code))]
const SHARED_MEMORY_DIR: &str = "/dev/shm";

/// Removes iceoryx2's shared-memory files that are empty and older than
/// `age`: a process was killed between creating one and sizing it (which
/// takes microseconds), and iceoryx2 would wait for ever to open it.
#[cfg_attr(not(feature = "coupler"), allow(dead_code))]
fn remove_empty_shared_memory(age: Duration) {
    let prefix = Config::global_config().global.prefix.to_string();
    let Ok(entries) = std::fs::read_dir(SHARED_MEMORY_DIR) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().to_string();
        let Ok(meta) = e.metadata() else { continue };
        let old = meta
            .modified()
            .is_ok_and(|t| t.elapsed().is_ok_and(|el| el > age));
        if name.starts_with(&prefix) && meta.is_file() && meta.len() == 0 && old {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

/// iceoryx2's cleanup of the dead nodes it lists; entries it cannot clean
/// go by hand.
#[cfg_attr(not(feature = "coupler"), allow(dead_code))]
fn cleanup_listed_dead_nodes() -> usize {
    let mut cleaned = 0;
    let mut unfinished = Vec::new();
    let _ = Node::<Ipc>::list(Config::global_config(), |state| {
        if let NodeState::Dead(view) = state {
            let id = view.id().to_string();
            match view.blocking_remove_stale_resources(Duration::from_millis(500)) {
                Ok(_) => cleaned += 1,
                // Killed while it created or dropped itself: its details are
                // gone and iceoryx2 cannot clean it; its entries go by hand.
                Err(_) => unfinished.extend(u128::from_str_radix(&id, 16).ok()),
            }
        }
        CallbackProgression::Continue
    });
    remove_half_created_nodes(&unfinished, HALF_CREATED_AGE);
    cleaned
}

/// Node entries no cleanup would remove: dead nodes, and entries with no
/// monitor older than [`HALF_CREATED_AGE`]. Zero after
/// [`cleanup_dead_nodes`] (for tests).
#[cfg_attr(not(feature = "coupler"), allow(dead_code))]
pub fn stale_node_entries() -> usize {
    quiet();
    let mut dead = 0;
    let _ = Node::<Ipc>::list(Config::global_config(), |state| {
        dead += matches!(state, NodeState::Dead(_)) as usize;
        CallbackProgression::Continue
    });
    dead + half_created(HALF_CREATED_AGE).len()
}

/// A node's entry with no monitor this old was abandoned while its node was
/// created (creating one takes milliseconds).
#[cfg_attr(not(feature = "coupler"), allow(dead_code))]
pub const HALF_CREATED_AGE: Duration = Duration::from_secs(5);

/// The node folder, and the name of node `id`'s monitor file in it.
#[cfg_attr(not(feature = "coupler"), allow(dead_code))]
fn node_files() -> (std::path::PathBuf, impl Fn(&str) -> std::path::PathBuf) {
    let config = Config::global_config();
    let dir = std::path::PathBuf::from(config.global.node_dir().to_string());
    let prefix = config.global.prefix.to_string();
    let at = dir.clone();
    (dir, move |id: &str| {
        at.join(format!("{prefix}{id}.node_monitor"))
    })
}

/// Node entries older than `age` with no monitor: their process was killed
/// between creating the entry and its monitor, and iceoryx2 does not list
/// them at all.
#[cfg_attr(not(feature = "coupler"), allow(dead_code))]
fn half_created(age: Duration) -> Vec<std::path::PathBuf> {
    let (dir, monitor) = node_files();
    let Ok(entries) = std::fs::read_dir(&dir) else {
        return Vec::new();
    };
    entries
        .flatten()
        .filter(|e| {
            let id = e.file_name().to_string_lossy().to_string();
            let old = e
                .metadata()
                .and_then(|m| m.modified())
                .is_ok_and(|t| t.elapsed().is_ok_and(|el| el > age));
            e.path().is_dir() && old && !monitor(&id).exists()
        })
        .map(|e| e.path())
        .collect()
}

/// Remove the entries of nodes whose process was killed while it created
/// or dropped its node, which iceoryx2 lists as dead but cannot clean
/// (`dead`, by id), or does not list at all ([`half_created`]), so that no
/// cleanup of its own would ever remove them.
#[cfg_attr(not(feature = "coupler"), allow(dead_code))]
fn remove_half_created_nodes(dead: &[u128], age: Duration) {
    let (dir, monitor) = node_files();
    for id in dead.iter().map(u128::to_string) {
        let _ = std::fs::remove_dir_all(dir.join(&id));
        for part in ["", "_context", "_owner_lock"] {
            let _ = std::fs::remove_file(format!("{}{part}", monitor(&id).display()));
        }
    }
    for path in half_created(age) {
        let _ = std::fs::remove_dir_all(path);
    }
}

/// Names of the services that exist for one run (for checks that nothing was left behind).
#[cfg_attr(not(feature = "coupler"), allow(dead_code))]
pub fn services_of_run(run_id: &str) -> Vec<String> {
    quiet();
    let prefix = format!("{}/{run_id}/", crate::names::PREFIX);
    let mut found = Vec::new();
    let _ = Ipc::list(Config::global_config(), |details| {
        let name = details.static_details.name().as_str().to_string();
        if name.starts_with(&prefix) {
            found.push(name);
        }
        CallbackProgression::Continue
    });
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_wait_of_less_than_a_microsecond_returns() {
        // 1 ns became SO_RCVTIMEO = 0 s 0 µs, which blocks for ever.
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let name = format!("block-test-{}", std::process::id());
            let node = node(&name).unwrap();
            let listener = listener(&node, &format!("{name}/wake")).unwrap();
            for slice in [
                Duration::ZERO,
                Duration::from_nanos(1),
                Duration::from_nanos(999),
            ] {
                block(&listener, slice).unwrap();
            }
            tx.send(()).unwrap();
        });
        assert!(
            rx.recv_timeout(Duration::from_secs(10)).is_ok(),
            "a sub-microsecond wait blocked"
        );
    }
}
