//! `host-sim`: the lugre-servo command-line tool.

use clap::{Parser, Subcommand, ValueEnum};
use host_sim::experiments;
use host_sim::params_file::ParamFile;
use host_sim::plant::{PlantConfig, SensorConfig};
use host_sim::record::Record;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

mod cli;

#[derive(Parser)]
#[command(
    name = "host-sim",
    version,
    about = "Electro-hydraulic servo axis simulator and LuGre friction tools"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// The whole story on the simulated Table 2 cylinder (writes into --out).
    Demo {
        /// Output folder for CSVs, parameter files and reports.
        #[arg(long, default_value = "demo-out")]
        out: PathBuf,
    },
    /// Identifies the LuGre parameters (static and dynamic stage) with a genetic algorithm or
    /// CMA-ES, on simulated experiments or measured records.
    Identify(IdentifyArgs),
    /// Closed-loop tracking benchmark: the core's controller against the simulator.
    Track {
        /// Writes the results as JSON.
        #[arg(long)]
        json: Option<PathBuf>,
        /// Writes an SVG plot of the low-speed tracking error.
        #[arg(long)]
        plot: Option<PathBuf>,
        /// Sensor noise seed.
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
    /// Compares a friction model with a measured record, finds where it fails and which
    /// physical effect is missing, adds effects and reports the error falling.
    Diagnose(DiagnoseArgs),
    /// Runs one experiment on the simulated axis and writes the record as CSV.
    Simulate {
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
    },
}

#[derive(clap::Args)]
struct DiagnoseArgs {
    /// The measured record (CSV). Give it several times (or a folder of CSVs) for records of
    /// one axis under different conditions: friction levels against pressure, temperature
    /// and numeric `# key=value` metadata, across records.
    #[arg(long, required = true)]
    data: Vec<PathBuf>,
    /// A parameter file: mass and friction are used as given for the comparison.
    #[arg(long)]
    params: Option<PathBuf>,
    /// Moving mass [kg] (identified from the record when neither this nor --params is given).
    #[arg(long)]
    mass: Option<f64>,
    /// Effects to add to the model, in order (comma separated).
    #[arg(long, value_delimiter = ',')]
    add: Vec<String>,
    /// Then add the suggested effects: the first significant candidate, again and again,
    /// until none is significant (at most three).
    #[arg(long)]
    auto: bool,
    /// Another record to test the fitted model on (no refit).
    #[arg(long)]
    validate: Option<PathBuf>,
    /// Writes a self-contained HTML report.
    #[arg(long)]
    report: Option<PathBuf>,
    /// Writes the results as JSON.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Writes the final (extended) model as a parameter file.
    #[arg(long)]
    out_params: Option<PathBuf>,
    /// The true model of a simulated record (`simulate` writes FILE.truth.toml beside the CSV):
    /// gives the noise floor.
    #[arg(long)]
    truth: Option<PathBuf>,
}

#[derive(clap::Args)]
struct IdentifyArgs {
    /// Algorithm (single run).
    #[arg(long, value_enum, default_value = "improved")]
    algorithm: Alg,
    /// Sensor setting for simulated data.
    #[arg(long, value_enum, default_value = "ideal")]
    noise: Noise,
    /// Seed (single run).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Measured constant-velocity sweep (CSV with x_ref) instead of simulated data.
    #[arg(long)]
    sweep: Option<PathBuf>,
    /// Measured dynamic record (CSV) instead of simulated data.
    #[arg(long)]
    dynamic: Option<PathBuf>,
    /// Moving mass [kg] (measured data).
    #[arg(long, default_value_t = 200.0)]
    mass: f64,
    /// Parameter file to write.
    #[arg(long, default_value = "identified.toml")]
    out: PathBuf,
    /// Benchmark every algorithm for seeds 1..=N.
    #[arg(long)]
    bench: bool,
    /// Number of seeds of the benchmark.
    #[arg(long, default_value_t = 20)]
    seeds: u64,
    /// Benchmark results as JSON.
    #[arg(long)]
    json: Option<PathBuf>,
}

#[derive(Clone, Copy, ValueEnum)]
enum Alg {
    Traditional,
    Adaptive,
    Improved,
    Cmaes,
}

#[derive(Clone, Copy, ValueEnum)]
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
}

/// Sensor settings.
#[derive(Clone, Copy, ValueEnum, PartialEq)]
enum Noise {
    /// Perfect sensors (the paper's setting).
    Ideal,
    /// Quantised encoder, noisy pressures, one-sample delay.
    Realistic,
}

fn sensors(noise: Noise, seed: u64) -> SensorConfig {
    match noise {
        Noise::Ideal => SensorConfig::ideal(),
        Noise::Realistic => SensorConfig::realistic(seed),
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Demo { out } => cli::demo::run(&out),
        Command::Diagnose(args) => cli::diagnose::run(&args),
        Command::Track { json, plot, seed } => {
            cli::track::run(json.as_deref(), plot.as_deref(), seed)
        }
        Command::Identify(a) => {
            use host_sim::identify::Algorithm;
            cli::identify::run(&cli::identify::Args {
                algorithm: match a.algorithm {
                    Alg::Traditional => Algorithm::Traditional,
                    Alg::Adaptive => Algorithm::Adaptive,
                    Alg::Improved => Algorithm::Improved,
                    Alg::Cmaes => Algorithm::Cmaes,
                },
                realistic: a.noise == Noise::Realistic,
                seed: a.seed,
                sweep: a.sweep,
                dynamic: a.dynamic,
                mass: a.mass,
                out: a.out,
                bench_seeds: a.bench.then_some(a.seeds),
                json: a.json,
            })
        }
        Command::Simulate {
            experiment,
            out,
            params,
            effect,
            strength,
            noise,
            seed,
            duration,
        } => simulate(
            experiment,
            &out,
            params.as_deref(),
            &effect,
            strength,
            sensors(noise, seed),
            duration,
        ),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn simulate(
    experiment: Experiment,
    out: &Path,
    params: Option<&Path>,
    effects: &[String],
    strength: f64,
    sensors: SensorConfig,
    duration: f64,
) -> Result<(), String> {
    let mut cfg = PlantConfig::default();
    if let Some(p) = params {
        let (file, model) = ParamFile::read(p)?;
        cfg.friction = model;
        cfg.cylinder.moving_mass_kg = file.axis.moving_mass_kg;
    }
    for e in effects {
        host_sim::scenarios::with_effect(&mut cfg, e, strength)?;
    }
    if !(duration.is_finite() && duration > 0.0) {
        return Err("--duration must be a positive number of seconds".into());
    }
    let rec = run_experiment(experiment, &cfg, sensors, duration);
    rec.write(out)
        .map_err(|e| format!("{}: {e}", out.display()))?;
    println!("wrote {} ({} samples)", out.display(), rec.len());
    let truth = out.with_extension("truth.toml");
    let mut file = ParamFile::new(&cfg.friction, cfg.cylinder.moving_mass_kg);
    file.fit.source = Some("host-sim simulate: the plant's true friction".into());
    file.write(&truth)
        .map_err(|e| format!("{}: {e}", truth.display()))?;
    println!("wrote {} (the plant's true model)", truth.display());
    Ok(())
}

fn run_experiment(
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
    }
}
