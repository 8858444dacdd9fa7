//! Signal tools that diagnosis and identification share, one per file: zero-phase low-pass
//! filtering ([`filter`]), differentiation ([`difference`]) and the effective number of
//! independent samples of a correlated series ([`autocorrelation`]).

pub mod autocorrelation;
pub mod difference;
pub mod filter;

pub use autocorrelation::integrated_autocorrelation_time;
pub use difference::central_difference;
pub use filter::{segmented, LowPass};
