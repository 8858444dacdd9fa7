//! Subcommand implementations.

pub mod demo;
pub mod diagnose;
pub mod identify;
pub mod track;
