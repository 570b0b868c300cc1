//! Errors of [`crate::solve`].

use geodesics_window::{SourceError, SpikeError};
use thiserror::Error;

/// Why a PVTP solve was refused. Every variant names the offending source
/// (its index in the `sources` slice) or option and its value.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum PvtpError {
    /// A source, or the distance limit, was refused.
    #[error(transparent)]
    Source(#[from] SourceError),
    /// The mesh has a needle-like vertex that windows would wind around
    /// (see [`geodesics_window::check_spikes`]).
    #[error(transparent)]
    Spike(#[from] SpikeError),
    /// The PAVTP reset parameters are not usable.
    #[error(
        "window reset needs a finite lambda > 0 and a finite lambda_g >= 0 (got lambda {lambda}, lambda_g {lambda_g})"
    )]
    Reset {
        /// λ given.
        lambda: f64,
        /// λ_g given.
        lambda_g: f64,
    },
    /// More threads than [`max_threads`](crate::max_threads) allows: on a
    /// machine with few CPUs the thread pool alone then takes minutes.
    #[error(
        "{threads} threads asked for; at most {max} on this machine ({cpus} logical CPUs; one thread per CPU is fastest)"
    )]
    TooManyThreads {
        /// Threads asked for.
        threads: usize,
        /// The most allowed here.
        max: usize,
        /// Logical CPUs of this machine.
        cpus: usize,
    },
    /// The thread pool could not be created.
    #[error("cannot start a pool of {threads} threads: {message}")]
    ThreadPool {
        /// Threads asked for.
        threads: usize,
        /// What rayon said.
        message: String,
    },
}
