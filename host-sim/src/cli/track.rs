//! `host-sim track`.

use host_sim::chart::{self, Frame, Line};
use host_sim::track::{self, Tracking};
use host_sim::Result;
use std::path::{Path, PathBuf};

fn row(name: &str, t: &Tracking, reference: Option<&Tracking>) {
    let rel = reference.map_or(String::new(), |r| {
        format!(
            "  rms {:>5.1} %  reversal peak {:>5.1} % of pid",
            100.0 * t.rms_err_m / r.rms_err_m,
            100.0 * t.reversal_err_m / r.reversal_err_m
        )
    });
    println!(
        "  {:<22} rms {:>8.2} um  max {:>8.2} um  reversal peak {:>8.2} um{rel}",
        name,
        t.rms_err_m * 1e6,
        t.max_err_m * 1e6,
        t.reversal_err_m * 1e6
    );
}

/// The low-speed error plot (SVG).
fn plot(pid: &[(f64, f64)], full: &[(f64, f64)]) -> Result<String> {
    let um = |d: &[(f64, f64)]| d.iter().step_by(5).map(|(t, e)| (*t, e * 1e6)).collect();
    let ymax = pid
        .iter()
        .chain(full)
        .map(|(_, e)| e.abs() * 1e6)
        .fold(1.0f64, f64::max)
        * 1.05;
    chart::lines(
        320,
        &Frame {
            title: "Low-speed tracking error (2 mm, 0.2 Hz sinusoid)",
            x_desc: "time [s]",
            y_desc: "x_ref - x [um]",
            x: (0.0, pid.last().map_or(1.0, |p| p.0)),
            y: (-ymax, ymax),
        },
        &[
            Line {
                label: "plain cascade (pid)",
                color: chart::FIRST_MODEL,
                points: um(pid),
            },
            Line {
                label: "full controller",
                color: chart::FINAL_MODEL,
                points: um(full),
            },
        ],
    )
}

/// Options of `track`.
#[derive(clap::Args)]
pub struct Args {
    /// Writes the results as JSON.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Writes an SVG plot of the low-speed tracking error.
    #[arg(long)]
    plot: Option<PathBuf>,
    /// Sensor noise seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// The robustness matrix instead: plants x controller models x configurations x
    /// scenarios (see `host_sim::robustness`); --json writes every case, --plot the matrix.
    #[arg(long)]
    robustness: bool,
}

/// Runs the subcommand.
pub fn run(a: &Args) -> Result<()> {
    if a.robustness {
        return robustness(a);
    }
    benchmark(a.json.as_deref(), a.plot.as_deref(), a.seed)
}

fn robustness(a: &Args) -> Result<()> {
    use host_sim::robustness::{self as rb, Scenario};
    use indicatif::{ProgressBar, ProgressStyle};
    let wall = std::time::Instant::now();
    let sensors = host_sim::plant::SensorConfig::realistic(a.seed);
    // the disturbance observer's tuning rule (see lugre_servo::control::dob)
    println!("dob cut-off sweep (plain plant, model-free; RMS as % of pid per scenario):");
    let plain = host_sim::plant::PlantConfig::default();
    let rms = |features, cutoff| {
        Scenario::ALL.map(|s| {
            let mut ctrl = lugre_servo::control::ControllerConfig::for_simulated_axis(
                lugre_servo::friction::FrictionModel::plain(
                    lugre_servo::friction::LugreParams::table2(),
                ),
                features,
            );
            ctrl.dob_cutoff_hz = cutoff;
            let r = track::run(&plain, sensors, ctrl, &|t| s.reference(t), s.duration_s());
            r.tracking.rms_err_m
        })
    };
    let pid = rms(lugre_servo::control::Features::PID, 0.0);
    let mut best = (f64::INFINITY, 0.0);
    for f in lugre_servo::control::dob::TUNING_GRID_HZ {
        let r = rms(lugre_servo::control::Features::DISTURBANCE_OBSERVER, f);
        let pct = [0, 1, 2].map(|i| 100.0 * r[i] / pid[i]);
        let worst = pct.iter().cloned().fold(0.0, f64::max);
        if worst < best.0 {
            best = (worst, f);
        }
        println!(
            "  f_Q {f:>5} Hz: low_speed {:>6.1} %  point_to_point {:>6.1} %  creep {:>6.1} %",
            pct[0], pct[1], pct[2]
        );
    }
    println!(
        "  best (lowest worst-case): {} Hz; in use: {} Hz",
        best.1,
        lugre_servo::control::controller::DOB_CUTOFF_HZ
    );
    let bar = ProgressBar::new(rb::runs() as u64);
    bar.set_style(
        ProgressStyle::with_template("  {bar:40} {pos}/{len} runs {elapsed}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    if std::env::var_os("CI").is_some() {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    let m = rb::matrix(a.seed, &|| bar.inc(1));
    bar.finish_and_clear();
    let plants: Vec<String> = rb::plants().into_iter().map(|(n, _)| n).collect();
    let pct = |plant: &str, model: &str, config: &str, scenario: &str, f: fn(&rb::Case) -> f64| {
        let pid = m.get(plant, model, "pid", scenario).map(f);
        let c = m.get(plant, model, config, scenario).map(f);
        match (c, pid) {
            (Some(c), Some(p)) if p > 0.0 => 100.0 * c / p,
            _ => f64::NAN,
        }
    };
    println!(
        "\nlow_speed: full as % of pid RMS (reversal peak % of pid), by plant and controller model"
    );
    print!("  {:<24}", "plant");
    for model in rb::MODELS {
        print!(" {model:>14}");
    }
    println!();
    let mut grid = Vec::new();
    let (mut worst, mut worst_at) = (0.0f64, String::new());
    let mut worst_rev: f64 = 0.0;
    for p in &plants {
        print!("  {p:<24}");
        let mut row = Vec::new();
        for model in rb::MODELS {
            let rms = pct(p, model, "full", "low_speed", |c| c.rms_err_m);
            let rev = pct(p, model, "full", "low_speed", |c| c.reversal_err_m);
            print!(" {:>6.1} ({:>4.0})", rms, rev);
            if rb::WITHIN_30_PERCENT.contains(&model) {
                if rms > worst {
                    worst = rms;
                    worst_at = format!("{p} / {model}");
                }
                worst_rev = worst_rev.max(rev);
            }
            row.push(rms);
        }
        println!();
        grid.push(row);
    }
    println!(
        "  worst within +-30 % static mismatch: {worst:.1} % of pid ({worst_at}); largest reversal peak {worst_rev:.0} % of pid"
    );
    println!("\nidentified model on the plain plant: RMS [um] (reversal peak [um], settle [s])");
    print!("  {:<16}", "scenario");
    for (c, _) in rb::CONFIGS {
        print!(" {c:>24}");
    }
    println!();
    for s in Scenario::ALL {
        print!("  {:<16}", s.name());
        for (c, _) in rb::CONFIGS {
            match m.get("plain", "identified", c, s.name()) {
                Some(k) => print!(
                    " {:>8.2} ({:>6.1}, {:>5})",
                    k.rms_err_m * 1e6,
                    k.reversal_err_m * 1e6,
                    k.settle_s.map_or("-".into(), |t| format!("{t:.2}"))
                ),
                None => print!(" {:>24}", "failed"),
            }
        }
        println!();
    }
    let faults: usize = m.cases.iter().map(|c| c.fault_ticks).sum();
    println!(
        "\n{} cases ({} runs) in {:.1} s; fault ticks over all cases: {faults}",
        m.cases.len(),
        rb::runs(),
        wall.elapsed().as_secs_f64()
    );
    if let Some(p) = &a.json {
        super::write_json(p, &m)?;
    }
    if let Some(p) = &a.plot {
        let table = |config: &str| -> Vec<Vec<f64>> {
            plants
                .iter()
                .map(|p| {
                    rb::MODELS
                        .iter()
                        .map(|m| pct(p, m, config, "low_speed", |c| c.rms_err_m))
                        .collect()
                })
                .collect()
        };
        let svg = chart::heatmaps(
            2 * (50 + 30 * plants.len() as u32),
            &plants,
            &rb::MODELS.map(String::from),
            &[
                (
                    "low_speed RMS error, % of the plain cascade's: model feed-forward + LuGre observer",
                    table("feedforward_observer"),
                ),
                (
                    "... and full (+ residual observer, refinement)",
                    grid,
                ),
            ],
            (20.0, 100.0),
        )?;
        super::write_text(p, &svg)?;
    }
    Ok(())
}

/// Runs the benchmark, writes the JSON and the plot where asked.
pub fn benchmark(json: Option<&Path>, plot_path: Option<&Path>, seed: u64) -> Result<()> {
    let wall = std::time::Instant::now();
    let (r, pid, full) = track::benchmark(seed);
    println!("low_speed (2 mm, 0.2 Hz: peak 2.5 mm/s, Stribeck region; realistic sensors):");
    let l = &r.low_speed;
    row("pid", &l.pid, None);
    row("feedforward", &l.feedforward, Some(&l.pid));
    row(
        "feedforward_observer",
        &l.feedforward_observer,
        Some(&l.pid),
    );
    row("full", &l.full, Some(&l.pid));
    println!("drift (oil warms ~18 K: sigma2 -30 %, Fc +18 %; 50 mm, 0.4 Hz):");
    let d = &r.drift;
    row("no_drift", &d.no_drift, None);
    row("fixed", &d.fixed, Some(&d.no_drift));
    row("refined", &d.refined, Some(&d.no_drift));
    println!(
        "  refined [Fc, Fs-Fc, sigma2] = [{:.1}, {:.1}, {:.0}], drifted truth [{:.1}, {:.1}, {:.0}]",
        d.refined_params[0], d.refined_params[1], d.refined_params[2], d.drifted_truth[0], d.drifted_truth[1], d.drifted_truth[2]
    );
    println!("({:.1} s)", wall.elapsed().as_secs_f64());
    if let Some(p) = json {
        super::write_json(p, &r)?;
    }
    if let Some(p) = plot_path {
        super::write_text(p, &plot(&pid, &full)?)?;
    }
    Ok(())
}
