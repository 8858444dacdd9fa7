//! How well our dwell term can fit the independent generator's dwell records, against the
//! floor: the baseline with a dwell term refitted (linear parameters) at every point of a
//! grid of time constant, renewal distance and stick speed, best point per stick speed. With
//! `BODY_CLOCKS=1` instead: the generator's own shape with its clock replaced by clocks read
//! off the measured motion (session 19: none comes near the floor that reads the record's
//! clock).
//!
//! `cargo run --release -p host-sim --example dwell_fit_probe -- [FIRST_SEED] [N]`
//! (defaults 1700 10: the calibration dwell records).
#[path = "../tests/generators/mod.rs"]
mod generators;
use generators::axis::random_record;
use host_sim::diagnose::{self, fit, Options};
use host_sim::record::Record;
use lugre_servo::friction::effects::DwellStiction;
use rayon::prelude::*;
use std::path::Path;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let s0: u64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(1700);
    let n: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(10);
    let out: Vec<String> = (s0..s0 + n)
        .collect::<Vec<_>>()
        .par_iter()
        .map(|&seed| {
            let (text, axis) = random_record(Some("dwell_stiction"), seed);
            let rec = Record::parse(&text, Path::new("x.csv")).unwrap();
            let opts = Options {
                skip_final_ranking: true,
                ..Default::default()
            };
            let d = diagnose::diagnose(&rec, "x.csv", &opts).unwrap();
            let p = &d.prepared;
            let n_eff = fit::effective_samples(p, 20.0);
            let floor = generators::axis::truth_error_pct(&axis, p);
            let base = &d.stages[0].fit;
            let cand = d.stages[0]
                .candidates
                .iter()
                .find(|c| c.kind == lugre_servo::friction::EffectKind::DwellStiction)
                .and_then(|c| c.fit.as_ref())
                .map_or(f64::NAN, |f| f.rel_err_pct);
            let mut s = format!(
                "{seed} {:?} {:?}\n  floor {floor:.2} %, baseline {:.2} %, dwell candidate {cand:.2} %\n",
                axis.actuator, axis.shape, base.rel_err_pct
            );
            // the truth with a clock on the measured body speed (ours) instead of its own
            let renewal = match axis.shape {
                generators::axis::Shape::Dwell { renewal_m, .. } => renewal_m,
                _ => unreachable!(),
            };
            let body_clocks: &[f64] = if std::env::var("BODY_CLOCKS").is_ok() {
                &[5e-5]
            } else {
                &[]
            };
            for &stick in body_clocks {
              for (win, renewal) in [(1usize, renewal), (20, 1e-5), (20, 1e-4), (50, 1e-6), (50, 1e-5), (50, 1e-4), (100, 1e-5), (100, 1e-4)] {
                let mut age = 0.0f64;
                let speed: Vec<f64> = (0..p.len()).map(|i| if win == 1 { p.v_step[i] } else { (p.x[i] - p.x[i.saturating_sub(win)]) / (win as f64 * p.dt) }).collect();
                let trace: Vec<f64> = speed
                    .iter()
                    .map(|v| {
                        if v.abs() < stick {
                            age += p.dt;
                        } else {
                            age *= (-v.abs() * p.dt / renewal).exp();
                        }
                        age
                    })
                    .collect();
                let mut reset = 0.0f64;
                let trace_reset: Vec<f64> = speed
                    .iter()
                    .map(|v| {
                        if v.abs() < stick {
                            reset += p.dt;
                        } else {
                            reset = 0.0;
                        }
                        reset
                    })
                    .collect();
                let with = |t: Vec<f64>| {
                    let a = generators::axis::Axis {
                        dwell_trace: Some(generators::axis::DwellTrace(std::sync::Arc::new(t))),
                        ..axis.clone()
                    };
                    generators::axis::truth_error_pct(&a, p)
                };
                s += &format!(
                    "  truth with a body-speed clock (stick {stick:.0e}, window {win} ms, renewal {renewal:.0e}): decaying {:.2} %, restarting {:.2} %\n",
                    with(trace),
                    with(trace_reset)
                );
              }
            }
            let fits: &[f64] = if std::env::var("BODY_CLOCKS").is_ok() { &[] } else { &[2e-5, 5e-5, 2e-4] };
            for &stick in fits {
                let mut best = (f64::INFINITY, 0.0, 0.0, 0.0);
                for tau in [0.05, 0.1, 0.2, 0.35, 0.5, 1.0, 2.0, 5.0] {
                    for renewal in [1e-5, 1e-4, 3e-4, 1e-3, 3e-3, 1e-2] {
                        let mut m = base.model;
                        m.friction.effects.dwell_stiction = Some(DwellStiction {
                            max_increase: 0.0,
                            time_constant: tau,
                            stick_velocity: stick,
                            renewal_distance: renewal,
                        });
                        let f = fit::refit(&m, p, None, n_eff);
                        if f.rel_err_pct < best.0 {
                            let inc = f
                                .model
                                .friction
                                .effects
                                .dwell_stiction
                                .map_or(0.0, |d| d.max_increase);
                            best = (f.rel_err_pct, tau, renewal, inc);
                        }
                    }
                }
                s += &format!(
                    "  stick {stick:.0e}: best {:.2} % at tau {} s, renewal {:.0e} m, dF {:.0} N\n",
                    best.0, best.1, best.2, best.3
                );
            }
            s
        })
        .collect();
    for s in out {
        print!("{s}");
    }
}
