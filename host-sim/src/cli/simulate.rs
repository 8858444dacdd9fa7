//! `host-sim simulate`: one experiment on the simulated axis, written as a record.

use super::Noise;
use host_sim::experiments;
use host_sim::params_file::ParamFile;
use host_sim::plant::{PlantConfig, SensorConfig};
use host_sim::record::Record;
use host_sim::{Error, Result};
use std::path::PathBuf;

/// Options of `simulate`.
#[derive(clap::Args)]
pub struct Args {
    /// Which experiment.
    #[arg(value_enum)]
    experiment: Experiment,
    /// Output CSV.
    #[arg(long, short)]
    out: PathBuf,
    /// Plant friction from a parameter file (default: Table 2).
    #[arg(long)]
    params: Option<PathBuf>,
    /// Extra physical effects to switch on in the plant, with demo-sized strengths
    /// (comma separated; see `lugre_servo::friction::effects`).
    #[arg(long, value_delimiter = ',')]
    effect: Vec<String>,
    /// Strength of the switched-on effects (1 = clearly visible, 0.3 = subtle).
    #[arg(long, default_value_t = 1.0)]
    strength: f64,
    /// Sensor models.
    #[arg(long, value_enum, default_value = "realistic")]
    noise: Noise,
    /// Noise seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Duration [s] (trajectories and ramp).
    #[arg(long, default_value_t = 20.0)]
    duration: f64,
}

/// The experiments.
#[derive(Clone, Copy, clap::ValueEnum)]
enum Experiment {
    /// Constant-velocity sweep in both directions (steady-state friction curve).
    Sweep,
    /// Slow force ramp below breakaway (pre-sliding).
    Ramp,
    /// Slow sinusoid with many reversals.
    Sine,
    /// Trapezoidal moves with dwells.
    Trapezoid,
    /// The composite record used for diagnosis: moves across the stroke at many speeds, dwells.
    Diagnosis,
    /// The realistic identification's dynamic experiment (0.6 mm, 0.5 Hz, 2 s; `sweep` is
    /// its static one): `identify --sweep S.csv --dynamic D.csv` on the two gives the same
    /// result as `identify --noise realistic`.
    IdentSine,
}

/// Runs the subcommand: the record, and beside it `FILE.truth.toml`, the plant's true model.
pub fn run(a: &Args) -> Result<()> {
    let mut cfg = PlantConfig::default();
    if let Some(p) = &a.params {
        let (file, model) = ParamFile::read(p)?;
        cfg.friction = model;
        cfg.cylinder.moving_mass_kg = file.axis.moving_mass_kg;
    }
    for e in &a.effect {
        host_sim::scenarios::with_effect(&mut cfg, e, a.strength)?;
    }
    if !(a.duration.is_finite() && a.duration > 0.0) {
        return Err(Error::Argument {
            flag: "--duration",
            problem: "must be a positive number of seconds".into(),
        });
    }
    let rec = record(a.experiment, &cfg, a.noise.sensors(a.seed), a.duration);
    rec.write(&a.out).map_err(|e| Error::io(&a.out, e))?;
    println!("wrote {} ({} samples)", a.out.display(), rec.len());
    let truth = a.out.with_extension("truth.toml");
    let mut file = ParamFile::new(&cfg.friction, cfg.cylinder.moving_mass_kg);
    file.fit.source = Some("host-sim simulate: the plant's true friction".into());
    file.write(&truth).map_err(|e| Error::io(&truth, e))?;
    println!("wrote {} (the plant's true model)", truth.display());
    Ok(())
}

fn record(
    experiment: Experiment,
    cfg: &PlantConfig,
    sensors: SensorConfig,
    duration: f64,
) -> Record {
    match experiment {
        Experiment::Sweep => {
            experiments::velocity_sweep(cfg, sensors, &experiments::log_speeds(5e-4, 0.1, 12)).0
        }
        Experiment::Ramp => experiments::presliding_ramp(cfg, sensors, 0.7, duration),
        Experiment::Sine => experiments::sinusoid(cfg, sensors, 0.01, 0.25, duration),
        Experiment::Trapezoid => {
            experiments::trapezoid(cfg, sensors, 0.05, 0.05, 0.5, 0.5, duration)
        }
        Experiment::Diagnosis => host_sim::scenarios::diagnosis_run(cfg, sensors, duration),
        Experiment::IdentSine => host_sim::identify::dynamic_experiment(cfg, sensors),
    }
}
