//! Signal tools that diagnosis and identification share, one per file: zero-phase low-pass
//! filtering ([`filter`]), differentiation ([`difference`]), the effective number of
//! independent samples of a correlated series ([`autocorrelation`]) and what a record's
//! sensors resolve ([`sensor`]).

pub mod autocorrelation;
pub mod difference;
pub mod filter;
pub mod sensor;

pub use autocorrelation::integrated_autocorrelation_time;
pub use difference::central_difference;
pub use filter::{segmented, LowPass};
pub use sensor::{
    edge_interpolated, encoder_resolution, force_noise, force_noise_fourth_difference,
};
