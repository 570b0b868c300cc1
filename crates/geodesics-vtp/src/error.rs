//! Errors of [`crate::solve`].

use geodesics_window::{SourceError, SpikeError};
use thiserror::Error;

/// Why a VTP solve was refused. Every variant names the offending source
/// (its index in the `sources` slice), value or vertex.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum VtpError {
    /// A source, or the distance limit, was refused.
    #[error(transparent)]
    Source(#[from] SourceError),
    /// The mesh has a needle-like vertex that windows would wind around
    /// (see [`geodesics_window::check_spikes`]).
    #[error(transparent)]
    Spike(#[from] SpikeError),
    /// The AVTP reset parameters are not usable.
    #[error(
        "window reset needs a finite lambda > 0 and a finite lambda_g >= 0 (got lambda {lambda}, lambda_g {lambda_g})"
    )]
    Reset {
        /// λ given.
        lambda: f64,
        /// λ_g given.
        lambda_g: f64,
    },
}
