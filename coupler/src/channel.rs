//! The iceoryx2 plumbing shared by the coupler and the participants: message
//! ports for bincode control messages, `[f64]` ports for fields, wake-up events,
//! and a wait that spins briefly and then blocks.
//!
//! Waiting must not spin for long: a scene runs up to four processes on as few
//! as two cores, and a busy-polling process starves the one doing the work
//! (DESIGN.md, "Processes and what they exchange").

use iceoryx2::port::listener::{Listener, ListenerWaitError};
use iceoryx2::port::notifier::Notifier;
use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::*;
use std::time::{Duration, Instant};

pub type Ipc = ipc::Service;
pub type BytesOut = Publisher<Ipc, [u8], ()>;
pub type BytesIn = Subscriber<Ipc, [u8], ()>;
pub type FieldOut = Publisher<Ipc, [f64], ()>;
pub type FieldIn = Subscriber<Ipc, [f64], ()>;
pub type FieldSample = iceoryx2::sample::Sample<Ipc, [f64], ()>;

/// How long a waiting side polls before it blocks on its event. Short enough
/// that a waiting process gives its core back within a few scheduler ticks.
pub const SPIN: Duration = Duration::from_micros(60);
/// Longest single block on an event before the abort flag and deadline are checked again.
const BLOCK_SLICE: Duration = Duration::from_millis(20);

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

pub(crate) fn ipc_err<E: std::fmt::Debug>(what: &'static str) -> impl Fn(E) -> ChannelError {
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
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<Ipc>()
        .map_err(ipc_err("create node"))
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
        .subscriber_max_buffer_size(4)
        .subscriber_max_borrowed_samples(2)
        .history_size(0)
        .open_or_create()
        .map_err(ipc_err("open message service"))
}

fn field_service(
    node: &Node<Ipc>,
    name: &str,
) -> Result<
    iceoryx2::service::port_factory::publish_subscribe::PortFactory<Ipc, [f64], ()>,
    ChannelError,
> {
    node.service_builder(&service_name(name)?)
        .publish_subscribe::<[f64]>()
        .max_publishers(1)
        .max_subscribers(1)
        // The consumer reads the newest sample; an older unread one is overwritten
        // (safe overflow), so a read never holds more than the one it returns.
        .subscriber_max_buffer_size(1)
        .subscriber_max_borrowed_samples(2)
        .history_size(0)
        .open_or_create()
        .map_err(ipc_err("open field service"))
}

pub fn bytes_out(node: &Node<Ipc>, name: &str) -> Result<BytesOut, ChannelError> {
    bytes_service(node, name)?
        .publisher_builder()
        .initial_max_slice_len(4096)
        .allocation_strategy(AllocationStrategy::PowerOfTwo)
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

/// A field publisher; `len_hint` values fit without reallocation, larger loans grow the segment.
pub fn field_out(node: &Node<Ipc>, name: &str, len_hint: usize) -> Result<FieldOut, ChannelError> {
    field_service(node, name)?
        .publisher_builder()
        .initial_max_slice_len(len_hint.max(1))
        .allocation_strategy(AllocationStrategy::PowerOfTwo)
        .max_loaned_samples(1)
        .create()
        .map_err(ipc_err("create field publisher"))
}

pub fn field_in(node: &Node<Ipc>, name: &str) -> Result<FieldIn, ChannelError> {
    field_service(node, name)?
        .subscriber_builder()
        .create()
        .map_err(ipc_err("create field subscriber"))
}

pub fn notifier(node: &Node<Ipc>, name: &str) -> Result<Notifier<Ipc>, ChannelError> {
    node.service_builder(&service_name(name)?)
        .event()
        .open_or_create()
        .map_err(ipc_err("open event service"))?
        .notifier_builder()
        .create()
        .map_err(ipc_err("create notifier"))
}

pub fn listener(node: &Node<Ipc>, name: &str) -> Result<Listener<Ipc>, ChannelError> {
    node.service_builder(&service_name(name)?)
        .event()
        .open_or_create()
        .map_err(ipc_err("open event service"))?
        .listener_builder()
        .create()
        .map_err(ipc_err("create listener"))
}

/// Encode and publish one control message, then wake the reader.
pub fn send_message<T: serde::Serialize>(
    out: &BytesOut,
    wake: &Notifier<Ipc>,
    msg: &T,
) -> Result<(), ChannelError> {
    let bytes = crate::protocol::encode(msg);
    let sample = out
        .loan_slice_uninit(bytes.len())
        .map_err(ipc_err("loan message"))?;
    sample
        .write_from_slice(&bytes)
        .send()
        .map_err(ipc_err("send message"))?;
    wake.notify().map_err(ipc_err("notify"))?;
    Ok(())
}

/// Take one control message if one is waiting.
pub fn try_receive_message<T: for<'de> serde::Deserialize<'de>>(
    inp: &BytesIn,
) -> Result<Option<T>, ChannelError> {
    match inp.receive().map_err(ipc_err("receive message"))? {
        None => Ok(None),
        Some(sample) => crate::protocol::decode(sample.payload())
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
        // A notification that arrived after `poll` is kept by the event, so this returns at once.
        match listener.timed_wait(|_| {}, slice) {
            // A signal (SIGCHLD, SIGINT handled elsewhere) only cuts the wait short.
            Ok(_) | Err(ListenerWaitError::InterruptSignal) => {}
            Err(e) => return Err(ipc_err("wait on event")(e)),
        }
    }
}

/// Remove what dead canopy processes left behind (shared memory, service entries).
/// Returns how many dead nodes were cleaned.
pub fn cleanup_dead_nodes() -> usize {
    quiet();
    let mut cleaned = 0;
    let _ = Node::<Ipc>::list(Config::global_config(), |state| {
        if let NodeState::Dead(view) = state {
            if view
                .blocking_remove_stale_resources(Duration::from_millis(500))
                .is_ok()
            {
                cleaned += 1;
            }
        }
        CallbackProgression::Continue
    });
    cleaned
}

/// Names of the services that exist for one run (for checks that nothing was left behind).
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
