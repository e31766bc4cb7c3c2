//! One error type per stage: joining a run, and exchanging once it runs.

pub use crate::channel::ChannelError;

/// Why [`crate::connect`] or [`crate::Joining::declare`] failed.
#[derive(Debug, thiserror::Error)]
pub enum JoinError {
    #[error("not launched by the coupler: environment variable {0} is not set")]
    NotLaunched(&'static str),
    #[error("{0}")]
    Channel(#[from] ChannelError),
    #[error("expected {expected} from the coupler, it sent {got}")]
    Protocol { expected: &'static str, got: String },
    #[error("declaration: {0}")]
    Declaration(String),
}

/// Why a call of a running [`crate::Participant`] failed.
#[derive(Debug, thiserror::Error)]
pub enum ExchangeError {
    #[error("{0}")]
    Channel(#[from] ChannelError),
    #[error("field `{0}` was not declared")]
    Undeclared(String),
    #[error("field `{0}` is not exchanged in this run: no participant writes it")]
    NotConnected(String),
    #[error("field `{field}` is declared as {declared}, but {written} values were written")]
    Length {
        field: String,
        declared: String,
        written: usize,
    },
    #[error("no value of field `{field}` came from `{writer}` within {seconds:.1} s")]
    Stalled {
        field: String,
        writer: String,
        seconds: f64,
    },
    #[error("field `{field}`: value {got} arrived where value {expected} was due")]
    OutOfOrder {
        field: String,
        expected: u64,
        got: u64,
    },
    #[error(
        "field `{field}`: its readers ({}) left earlier values unread until the \
         timeout; a participant must read every value of a field it declares it reads",
        readers.join(", ")
    )]
    Unread { field: String, readers: Vec<String> },
    #[error(
        "window {window} did not converge in {tries} tries (the most `[coupling.implicit] \
         max_iterations` allows): {detail}"
    )]
    Unconverged {
        window: u64,
        tries: u32,
        detail: String,
    },
    #[error(
        "field `{0}` is written before the window's end, so it cannot be accelerated: \
         implicit coupling relaxes a field once a try, at its end (take it out of \
         `[coupling.implicit] accelerate`, or exchange it once a window, \
         e.g. impulse_substeps = 1)"
    )]
    AcceleratedMidWindow(String),
    #[error(
        "field `{0}` was not published at Initialize: under scheme = \"parallel-implicit\" \
         every participant takes a window's first try from the others' values before it, \
         so each publishes at Initialize what it writes at window ends"
    )]
    NotPublishedAtStart(String),
    #[error(
        "`{0}` sent {1} values as its share of the joint relaxation, which do not make one \
         (a participant built on another version of the coupling library?)"
    )]
    MalformedShare(String, usize),
    #[error("run checkpoint: {0}")]
    Checkpoint(String),
    #[error("the coupler (process {0}) is gone: the run was stopped")]
    CouplerGone(u32),
    #[error("monitor `{0}` was not declared")]
    UndeclaredMonitor(String),
    #[error("{0}")]
    Misuse(&'static str),
}
