//! The parameter file (TOML) that identification writes and every other tool reads: the
//! core's reader and validator (`lugre_servo::params_file`, feature `params-file`), which the
//! firmware's build script uses too, so a file the host accepts is the file the firmware
//! builds.
pub use lugre_servo::params_file::*;
