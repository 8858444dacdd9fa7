//! Identification on axes it was never tuned on: effect-free axes of the independent test
//! generator (`host-sim/tests/generators/axis.rs`: written from scratch, no code shared with
//! the plant or the core; soft and stiff contacts, light and heavy masses, damped and
//! undamped bristles, an ideal force actuator or a hydraulic cylinder, a 1 um encoder), run
//! through the two identification experiments an engineer would run on them and identified
//! from the CSV records exactly as `host-sim identify --sweep S --dynamic D` does.
//!
//! Experiments: a constant-velocity sweep (8 speeds, 0.5..100 mm/s, each out and back for
//! 0.8 s with 0.3 s rests) and a 0.5 Hz sinusoid for 4 s whose amplitude is the larger of
//! 0.6 mm and 20 pre-sliding lengths (`Fs / sigma0`), so it slides between reversals.
//!
//! `cargo run --release -p host-sim --example identify_independent [-- N]` (`WRITE=DIR` also
//! writes each axis's two records there; `INTERVALS=1` prints each parameter's 95 % interval
//! and the truth on stderr; `TOLD=1` tells the identification how each axis logs its force,
//! as `identify --force-timing` does: a force actuator its set-point, held over the period;
//! a cylinder its chamber pressures, sampled)
#[path = "../tests/generators/mod.rs"]
mod generators;

use generators::axis::{record_along, Axis, DT};
use host_sim::experiments;
use host_sim::identify::{self, Algorithm, IdentData};
use host_sim::record::Record;
use host_sim::stats::median;
use rayon::prelude::*;
use std::path::Path;

fn sweep_reference(stroke_m: f64) -> Vec<f64> {
    let mut xr = vec![0.0; 300];
    for v in experiments::log_speeds(5e-4, 0.1, 8) {
        let leg = 0.8f64.min(0.4 * stroke_m / v);
        let steps = (leg / DT) as usize;
        for dir in [1.0, -1.0] {
            let x0 = *xr.last().unwrap_or(&0.0);
            for k in 1..=steps {
                xr.push(x0 + dir * v * k as f64 * DT);
            }
            let x1 = *xr.last().unwrap();
            xr.extend(std::iter::repeat_n(x1, 300));
        }
    }
    xr
}

fn sine_reference(amplitude: f64) -> Vec<f64> {
    let w = std::f64::consts::TAU * 0.5;
    let mut xr = vec![0.0; 200];
    xr.extend((0..4000).map(|k| amplitude * (w * k as f64 * DT).sin()));
    xr
}

struct Outcome {
    seed: u64,
    line: String,
    errors: Option<[f64; 6]>,
    /// Which of the six (Table-3 order) the identifiability scan bounds.
    identified: [bool; 6],
    sigma0_holds: bool,
    edges: bool,
}

fn run(seed: u64) -> Outcome {
    let axis = Axis::random(None, seed);
    let truth = axis.lugre_params();
    let travel = axis.static_n / axis.sigma0;
    let (sweep, _) = record_along(&axis, seed * 31 + 1, &sweep_reference(axis.stroke_m));
    let (dynamic, _) = record_along(
        &axis,
        seed * 31 + 2,
        &sine_reference((20.0 * travel).max(6e-4)),
    );
    if let Ok(dir) = std::env::var("WRITE") {
        // the two records, to try by hand (`host-sim identify --sweep --dynamic`)
        std::fs::create_dir_all(&dir).expect("folder");
        std::fs::write(format!("{dir}/{seed}-sweep.csv"), &sweep).expect("write");
        std::fs::write(format!("{dir}/{seed}-dynamic.csv"), &dynamic).expect("write");
    }
    let parse = |text: &str, name: &str| Record::parse(text, Path::new(name));
    let data: Result<IdentData, String> = (|| {
        let s = parse(&sweep, "sweep.csv").map_err(|e| e.to_string())?;
        let d = parse(&dynamic, "dynamic.csv").map_err(|e| e.to_string())?;
        let mut data = identify::dynamic_from_record(&d, axis.mass_kg, "dynamic.csv")
            .map_err(|e| e.to_string())?;
        data.points = identify::steady_points_from_record(&s, axis.mass_kg, "sweep.csv")
            .map_err(|e| e.to_string())?;
        if std::env::var("TOLD").is_ok() {
            // what the rig's engineer knows: a force actuator logs its set-point (held over
            // the period), a cylinder its chamber pressures (sampled)
            data.force_timing = Some(match format!("{:?}", axis.actuator).as_str() {
                "Force" => identify::ForceTiming::Held,
                _ => identify::ForceTiming::Sampled,
            });
        }
        Ok(data)
    })();
    let head = format!(
        "seed {seed:3} {:9} M {:5.0} kg  sigma0 {:.2e} (pre-sliding {:6.1} um)  sigma1/crit {:.2}",
        format!("{:?}", axis.actuator),
        axis.mass_kg,
        axis.sigma0,
        travel * 1e6,
        axis.sigma1 / (axis.sigma0 * axis.mass_kg).sqrt()
    );
    let data = match data {
        Ok(d) => d,
        Err(e) => {
            return Outcome {
                seed,
                line: format!("{head}  refused: {e}"),
                errors: None,
                identified: [false; 6],
                sigma0_holds: false,
                edges: false,
            }
        }
    };
    if std::env::var("POINTS").is_ok() {
        for q in &data.points {
            eprintln!(
                "seed {seed} v {:+.5} measured {:8.1} truth {:8.1}",
                q.velocity,
                q.force,
                truth.steady_state_force(q.velocity)
            );
        }
    }
    let r = identify::identify(Algorithm::Improved, &data, seed, Some(&truth));
    let e = r.errors_pct.expect("truth given");
    if std::env::var("INTERVALS").is_ok() {
        let t = [
            axis.sigma0,
            axis.sigma1,
            axis.sigma2,
            axis.coulomb_n,
            axis.static_n - axis.coulomb_n,
            axis.stribeck_m_per_s,
        ];
        for (k, name) in ["sigma0", "sigma1", "sigma2", "Fc", "Fs-Fc", "vs"]
            .iter()
            .enumerate()
        {
            if let Some(i) = r.identifiability[k] {
                eprintln!("seed {seed} {name:7} value {:.4e} truth {:.4e} 95% [{:.4e}, {:.4e}] identifiable {}", r.values[k], t[k], i.interval95[0], i.interval95[1], i.identifiable);
            }
        }
    }
    let i0 = r.identifiability[0];
    let holds =
        i0.is_some_and(|i| i.interval95[0] <= axis.sigma0 && axis.sigma0 <= i.interval95[1]);
    Outcome {
        seed,
        line: format!(
            "{head}  read {} force {:?}  errors: sigma0 {:6.1} % sigma1 {:6.1} % sigma2 {:5.2} % Fc {:5.2} % Fs-Fc {:6.2} % vs {:6.2} %  sigma0 interval holds: {holds}  at bound {:?}",
            if data.encoder_resolution_m > 0.0 { "edges    " } else { "staircase" },
            r.force_timing,
            e.sigma0, e.sigma1, e.sigma2, e.fc, e.fs_minus_fc, e.vs, r.at_bound
        ),
        errors: Some([e.sigma0, e.sigma1, e.sigma2, e.fc, e.fs_minus_fc, e.vs]),
        identified: r.identifiability.map(|i| i.is_some_and(|i| i.identifiable)),
        sigma0_holds: holds,
        edges: data.encoder_resolution_m > 0.0,
    }
}

fn main() {
    let n: u64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(20);
    let start = std::time::Instant::now();
    let mut out: Vec<Outcome> = (1..=n).into_par_iter().map(|s| run(1000 + s)).collect();
    out.sort_by_key(|o| o.seed);
    for o in &out {
        println!("{}", o.line);
    }
    let done: Vec<&Outcome> = out.iter().filter(|o| o.errors.is_some()).collect();
    let median_error = |k: usize, only_identified: bool| {
        let v: Vec<f64> = done
            .iter()
            .filter(|o| !only_identified || o.identified[k])
            .map(|o| o.errors.unwrap()[k])
            .collect();
        (median(&v), v.len())
    };
    println!(
        "{} axes, {} identified ({} read at the edges), {:.0} s; sigma0 interval holds the truth {}/{}",
        out.len(),
        done.len(),
        done.iter().filter(|o| o.edges).count(),
        start.elapsed().as_secs_f64(),
        done.iter().filter(|o| o.sigma0_holds).count(),
        done.len()
    );
    println!("parameter   median error (all)   flagged identified   median error (those)");
    for (k, name) in ["sigma0", "sigma1", "sigma2", "Fc", "Fs-Fc", "vs"]
        .iter()
        .enumerate()
    {
        let (all, _) = median_error(k, false);
        let (those, n_id) = median_error(k, true);
        println!(
            "{name:8} {all:15.1} % {n_id:14}/{:<2} {those:18.1} %",
            done.len()
        );
    }
}
