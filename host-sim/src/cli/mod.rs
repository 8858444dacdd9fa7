//! Subcommand implementations.

pub mod diagnose;
