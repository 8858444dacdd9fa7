//! # host-sim
//!
//! The host side of lugre-servo: an electro-hydraulic cylinder simulator that stands in for
//! hardware ([`plant`]), the experiments engineers run on a rig ([`experiments`]), the common
//! measurement format ([`record`]) and parameter file ([`params_file`]).

pub mod chart;
pub mod diagnose;
pub mod error;
pub mod experiments;
pub mod identify;
/// The parameter file (TOML) identification writes and every other tool reads: the core's
/// reader and validator, which the firmware's build script uses too.
pub use lugre_servo::params_file;
pub mod pil;
pub mod plant;
pub mod record;
pub mod robustness;
pub mod scenarios;
pub mod signal;
pub mod stats;
pub mod timing;
pub mod track;

pub use error::{Error, Result};
