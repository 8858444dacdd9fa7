//! `host-sim track`.

use host_sim::track::{self, Tracking};
use plotters::prelude::*;
use std::path::Path;

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

/// Writes the low-speed error plot.
pub fn plot(path: &Path, pid: &[(f64, f64)], full: &[(f64, f64)]) -> Result<(), String> {
    let root = SVGBackend::new(path, (900, 320)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let ymax = pid
        .iter()
        .chain(full)
        .map(|(_, e)| e.abs() * 1e6)
        .fold(1.0f64, f64::max)
        * 1.05;
    let tmax = pid.last().map_or(1.0, |p| p.0);
    let mut c = ChartBuilder::on(&root)
        .caption(
            "Low-speed tracking error (2 mm, 0.2 Hz sinusoid)",
            ("sans-serif", 18),
        )
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..tmax, -ymax..ymax)
        .map_err(|e| e.to_string())?;
    c.configure_mesh()
        .x_desc("time [s]")
        .y_desc("x_ref - x [um]")
        .draw()
        .map_err(|e| e.to_string())?;
    for (data, color, label) in [
        (pid, RGBColor(214, 96, 77), "plain cascade (pid)"),
        (full, RGBColor(33, 102, 172), "full controller"),
    ] {
        c.draw_series(LineSeries::new(
            data.iter().step_by(5).map(|(t, e)| (*t, e * 1e6)),
            color,
        ))
        .map_err(|e| e.to_string())?
        .label(label)
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
    }
    c.configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(|e| e.to_string())?;
    root.present().map_err(|e| e.to_string())
}

/// Runs the benchmark.
pub fn run(json: Option<&Path>, plot_path: Option<&Path>, seed: u64) -> Result<(), String> {
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
        std::fs::write(
            p,
            serde_json::to_string_pretty(&r).map_err(|e| e.to_string())?,
        )
        .map_err(|e| format!("{}: {e}", p.display()))?;
        println!("wrote {}", p.display());
    }
    if let Some(p) = plot_path {
        plot(p, &pid, &full)?;
        println!("wrote {}", p.display());
    }
    Ok(())
}
