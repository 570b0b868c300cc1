//! Errors of [`crate::solve`].

use geodesics_window::SourceError;
use thiserror::Error;

/// Why an ICH solve was refused. Every variant names the offending source
/// (its index in the `sources` slice) and value.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum IchError {
    /// A source, or the distance limit, was refused.
    #[error(transparent)]
    Source(#[from] SourceError),
}
