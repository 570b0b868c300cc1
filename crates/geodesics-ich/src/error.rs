//! Errors of [`crate::solve`].

use geodesics_window::{SourceError, SpikeError};
use thiserror::Error;

/// Why an ICH solve was refused. Every variant names the offending source
/// (its index in the `sources` slice), value or vertex.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum IchError {
    /// A source, or the distance limit, was refused.
    #[error(transparent)]
    Source(#[from] SourceError),
    /// The mesh has a needle-like vertex that windows would wind around
    /// (see [`geodesics_window::check_spikes`]).
    #[error(transparent)]
    Spike(#[from] SpikeError),
}
