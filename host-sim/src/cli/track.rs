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
}

/// Runs the subcommand.
pub fn run(a: &Args) -> Result<()> {
    benchmark(a.json.as_deref(), a.plot.as_deref(), a.seed)
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
