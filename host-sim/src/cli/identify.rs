//! `host-sim identify`.

use host_sim::identify::{self, Algorithm, IdentData, RunResult};
use host_sim::params_file::ParamFile;
use host_sim::plant::PlantConfig;
use host_sim::record::Record;
use host_sim::stats::median;
use host_sim::{Error, Result};
use indicatif::{ProgressBar, ProgressStyle};
use lugre_servo::friction::{FrictionModel, LugreParams};
use rayon::prelude::*;
use serde::Serialize;
use std::path::{Path, PathBuf};

use super::Noise;

/// Options of `identify`.
#[derive(clap::Args)]
pub struct Args {
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
    /// How the dynamic record's force was logged: `sampled` at each instant (a load cell,
    /// chamber pressures), `held` over the period before each sample (a drive's force
    /// set-point), or `auto` (the better fit of the two).
    #[arg(long, value_enum, default_value = "auto")]
    force_timing: Timing,
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

/// The force timings, as typed on the command line.
#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Timing {
    Auto,
    Sampled,
    Held,
}

/// The algorithms, as typed on the command line.
#[derive(Clone, Copy, clap::ValueEnum)]
enum Alg {
    Traditional,
    Adaptive,
    Improved,
    Cmaes,
}

impl From<Alg> for Algorithm {
    fn from(a: Alg) -> Self {
        match a {
            Alg::Traditional => Algorithm::Traditional,
            Alg::Adaptive => Algorithm::Adaptive,
            Alg::Improved => Algorithm::Improved,
            Alg::Cmaes => Algorithm::Cmaes,
        }
    }
}

fn data(a: &Args, seed: u64) -> Result<(IdentData, Option<LugreParams<f64>>, String)> {
    match (&a.sweep, &a.dynamic) {
        (Some(s), Some(d)) => {
            let sweep = Record::read(s)?;
            let dynamic = Record::read(d)?;
            let points =
                identify::steady_points_from_record(&sweep, a.mass, &s.display().to_string())?;
            let mut data =
                identify::dynamic_from_record(&dynamic, a.mass, &d.display().to_string())?;
            data.points = points;
            data.force_timing = match a.force_timing {
                Timing::Auto => None,
                Timing::Sampled => Some(identify::ForceTiming::Sampled),
                Timing::Held => Some(identify::ForceTiming::Held),
            };
            Ok((
                data,
                None,
                format!("measured: {} and {}", s.display(), d.display()),
            ))
        }
        (None, None) => {
            let truth = LugreParams::table2();
            if a.noise == Noise::Realistic {
                Ok((
                    identify::realistic_data(&PlantConfig::default(), seed),
                    Some(truth),
                    "realistic".into(),
                ))
            } else {
                Ok((identify::ideal_data(&truth), Some(truth), "ideal".into()))
            }
        }
        _ => Err(Error::Usage(
            "give both --sweep FILE and --dynamic FILE, or neither (simulated data)",
        )),
    }
}

/// Prints a Table-3 style comparison of runs.
pub fn print_table(runs: &[&RunResult], truth: Option<&LugreParams<f64>>) {
    print!("  {:<8}", "param");
    if truth.is_some() {
        print!(" {:>12}", "truth");
    }
    for r in runs {
        print!(" {:>24}", r.algorithm.name());
    }
    println!();
    let t = truth.map(identify::table3_values);
    for (i, n) in NAMES.iter().enumerate() {
        print!("  {:<8}", n);
        if let Some(t) = t {
            print!(" {:>12.5e}", t[i]);
        }
        for r in runs {
            match t {
                Some(t) => print!(
                    " {:>13.5e} ({:>6.3} %)",
                    r.values[i],
                    100.0 * (r.values[i] - t[i]).abs() / t[i]
                ),
                None => print!(" {:>24.5e}", r.values[i]),
            }
        }
        println!();
    }
}

#[derive(Serialize)]
struct Bench<'a> {
    setting: &'a str,
    runs: &'a [RunResult],
}

/// Runs the subcommand.
pub fn run(a: &Args) -> Result<()> {
    if a.bench {
        return bench(a, a.seeds);
    }
    let algorithm = Algorithm::from(a.algorithm);
    let (data, truth, setting) = data(a, a.seed)?;
    println!(
        "identifying ({setting}) with the {} algorithm, seed {}",
        algorithm.name(),
        a.seed
    );
    let r = identify::identify(algorithm, &data, a.seed, truth.as_ref());
    print_table(&[&r], truth.as_ref());
    println!(
        "  costs: static {:.3e}, dynamic {:.3e}; {} evaluations, {:.2} s",
        r.costs.0, r.costs.1, r.evaluations, r.wall_s
    );
    println!(
        "  dynamic record: force read as {}{}; position read {}",
        r.force_timing.describe(),
        match (data.force_timing, data.force_if_held.is_empty()) {
            (_, true) => "",
            (None, false) => " (the better fit)",
            (Some(_), false) => " (as told)",
        },
        if data.encoder_resolution_m > 0.0 {
            "at its count edges"
        } else if !data.velocity_staircase.is_empty() {
            "between its count edges (intervals cover the staircase reading too)"
        } else {
            "as it is"
        }
    );
    print_identifiability(&r);
    if !r.at_bound.is_empty() {
        println!(
            "  warning: at a search-range bound: {}",
            r.at_bound.join(", ")
        );
    }
    let params = identify::params_of(&r).ok_or(Error::InvalidIdentifiedSet)?;
    if let Some(w) = params.warning() {
        println!("  warning: {w}");
    }
    write_params(&params, a.mass, &r, &setting, &a.out)
}

/// Table-3 names of the parameters.
const NAMES: [&str; 6] = ["sigma0", "sigma1", "sigma2", "Fc", "Fs - Fc", "vs"];

/// Prints what the data says about each parameter (noisy data only).
pub fn print_identifiability(r: &RunResult) {
    if r.identifiability.iter().all(Option::is_none) {
        return;
    }
    println!("  what the data bounds (95 % likelihood-ratio interval along each parameter):");
    for (name, id) in NAMES.iter().zip(&r.identifiability) {
        let Some(id) = id else { continue };
        let verdict = if id.identifiable {
            "identified"
        } else {
            "NOT identifiable from this data: the interval reaches the search range's end; value = posterior mean"
        };
        if id.interval95[0] == id.interval95[1] {
            println!("    {name:<8} narrower than the scan grid (1/200 of the range)  {verdict}");
        } else {
            println!(
                "    {name:<8} [{:.4e}, {:.4e}]  {verdict}",
                id.interval95[0], id.interval95[1]
            );
        }
    }
}

/// Writes an identified parameter file.
pub fn write_params(
    params: &LugreParams<f64>,
    mass: f64,
    r: &RunResult,
    source: &str,
    out: &Path,
) -> Result<()> {
    let mut file = ParamFile::new(&FrictionModel::plain(*params), mass);
    file.fit.algorithm = Some(r.algorithm.name().into());
    file.fit.static_fitness = Some(r.costs.0);
    file.fit.dynamic_fitness = Some(r.costs.1);
    file.fit.source = Some(format!("host-sim identify ({source})"));
    file.fit.not_identifiable = NAMES
        .iter()
        .zip(&r.identifiability)
        .filter(|(_, id)| id.is_some_and(|i| !i.identifiable))
        .map(|(n, _)| n.to_string())
        .collect();
    file.write_checked(out)?;
    println!("wrote {}", out.display());
    Ok(())
}

fn bench(a: &Args, seeds: u64) -> Result<()> {
    let wall = std::time::Instant::now();
    let setting = match a.noise {
        Noise::Realistic => "realistic",
        Noise::Ideal => "ideal",
    };
    // one data set per seed (realistic: the sensor noise differs per seed)
    let sets: Vec<(u64, IdentData, Option<LugreParams<f64>>)> = (1..=seeds)
        .into_par_iter()
        .map(|s| {
            let (d, t, _) = data(a, s)?;
            Ok((s, d, t))
        })
        .collect::<Result<_>>()?;
    let jobs: Vec<(Algorithm, usize)> = Algorithm::ALL
        .iter()
        .flat_map(|&alg| (0..sets.len()).map(move |i| (alg, i)))
        .collect();
    let bar = ProgressBar::new(jobs.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("  {bar:40} {pos}/{len} runs {elapsed}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    if std::env::var_os("CI").is_some() {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    let runs: Vec<RunResult> = jobs
        .par_iter()
        .map(|&(alg, i)| {
            let (seed, d, t) = &sets[i];
            let r = identify::identify(alg, d, *seed, t.as_ref());
            bar.inc(1);
            r
        })
        .collect();
    bar.finish_and_clear();
    if let Some(path) = &a.json {
        super::write_json(
            path,
            &Bench {
                setting,
                runs: &runs,
            },
        )?;
    }
    println!(
        "setting {setting}, seeds 1..={seeds}, {} runs in {:.1} s",
        runs.len(),
        wall.elapsed().as_secs_f64()
    );
    println!(
        "  {:<12} {:>10} {:>10} | {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} | {:>10} {:>7} {:>8} {:>9}",
        "algorithm",
        "median max",
        "worst max",
        "sigma0",
        "sigma1",
        "sigma2",
        "Fc",
        "Fs-Fc",
        "vs",
        "evals->1%",
        "reach",
        "at bound",
        "not ident"
    );
    for alg in Algorithm::ALL {
        let rs: Vec<&RunResult> = runs.iter().filter(|r| r.algorithm == alg).collect();
        let errs: Vec<_> = rs.iter().filter_map(|r| r.errors_pct).collect();
        let worst: Vec<f64> = errs.iter().map(|e| e.worst()).collect();
        let med = |f: &dyn Fn(&identify::ErrorsPct) -> f64| {
            median(&errs.iter().map(f).collect::<Vec<_>>())
        };
        let to1: Vec<f64> = rs
            .iter()
            .filter_map(|r| r.evaluations_to_1pct.map(|e| e as f64))
            .collect();
        let reached = to1.len();
        // a run that never gets there counts as infinitely many evaluations
        let mut to1_all = to1.clone();
        to1_all.resize(rs.len(), f64::INFINITY);
        let not_ident = rs
            .iter()
            .filter(|r| r.identifiability.iter().flatten().any(|i| !i.identifiable))
            .count();
        println!(
            "  {:<12} {:>9.4}% {:>9.4}% | {:>8.4}% {:>8.4}% {:>8.4}% {:>8.4}% {:>8.4}% {:>8.4}% | {:>10} {:>7} {:>8} {:>9}",
            alg.name(),
            median(&worst),
            worst.iter().cloned().fold(0.0, f64::max),
            med(&|e| e.sigma0),
            med(&|e| e.sigma1),
            med(&|e| e.sigma2),
            med(&|e| e.fc),
            med(&|e| e.fs_minus_fc),
            med(&|e| e.vs),
            format!("{:.0}", median(&to1_all)),
            format!("{reached}/{}", rs.len()),
            rs.iter().filter(|r| !r.at_bound.is_empty()).count(),
            not_ident
        );
    }
    Ok(())
}
