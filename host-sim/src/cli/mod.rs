//! The subcommands, one file each: its clap `Args` and its `run`.

pub mod demo;
pub mod diagnose;
pub mod identify;
pub mod pil;
pub mod simulate;
pub mod track;

use host_sim::plant::SensorConfig;
use host_sim::{Error, Result};
use std::path::Path;

/// Sensor settings of simulated data.
#[derive(Clone, Copy, Debug, clap::ValueEnum, PartialEq)]
pub enum Noise {
    /// Perfect sensors (the paper's setting).
    Ideal,
    /// Quantised encoder, noisy pressures, one-sample delay.
    Realistic,
}

impl Noise {
    /// The sensor models, with their noise seed.
    pub fn sensors(self, seed: u64) -> SensorConfig {
        match self {
            Self::Ideal => SensorConfig::ideal(),
            Self::Realistic => SensorConfig::realistic(seed),
        }
    }
}

/// Writes `value` as pretty JSON and says so.
pub fn write_json<T: serde::Serialize>(path: &Path, value: &T) -> Result<()> {
    let text = serde_json::to_string_pretty(value)?;
    write_text(path, &text)
}

/// Writes a text file and says so.
pub fn write_text(path: &Path, text: &str) -> Result<()> {
    std::fs::write(path, text).map_err(|e| Error::io(path, e))?;
    println!("wrote {}", path.display());
    Ok(())
}
