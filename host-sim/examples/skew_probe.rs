//! How the independent generator's true model, driven by the measured motion, errs with the
//! force read later than logged (`Protocol::force_skew_samples`): records of
//! `tests/generators/axis.rs`, one per effect (and effect-free) for each seed. Its
//! force-actuated records log beside each position the force held over the period before it;
//! its hydraulic records compute the force from pressures sampled with the position.
//!
//! `cargo run --release -p host-sim --example skew_probe -- FIRST_SEED COUNT [issue]`
//!
//! Prints per record the actuator and the true model's error with the force as logged, read
//! half a sample later, and at the best skew of a grid of 0.1 samples within one sample either
//! way (and that skew) [%, samples].

#[path = "../tests/generators/mod.rs"]
mod generators;

use generators::axis::{record_on_axes, truth_error_pct, Axes};
use host_sim::diagnose::inverse::{Prepared, Protocol};
use host_sim::record::Record;
use rayon::prelude::*;
use std::path::Path;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let first: u64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(3120);
    let count: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(5);
    let axes = if args.iter().any(|a| a == "issue") {
        Axes::Issue
    } else {
        Axes::Wide
    };
    let jobs: Vec<(Option<&'static str>, u64)> = (first..first + count)
        .flat_map(|s| {
            std::iter::once(None)
                .chain(generators::axis::EFFECTS.iter().map(|e| Some(*e)))
                .map(move |e| (e, s))
        })
        .collect();
    let rows: Vec<String> = jobs
        .par_iter()
        .map(|&(effect, seed)| {
            let (text, axis) = record_on_axes(effect, seed, axes);
            let rec = Record::parse(&text, Path::new("probe.csv")).expect("record");
            let p = Prepared::new(&rec, "probe.csv", Protocol::default()).expect("prepared");
            let truth = |s: f64| truth_error_pct(&axis, &p.with_force_read_later(s));
            let (best, best_err) = (-10..=10)
                .map(|k| (0.1 * k as f64, truth(0.1 * k as f64)))
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .expect("a grid");
            format!(
                "{:<24} {seed:>6} {:<9} {:>8.2} {:>8.2} {:>8.2} {:>6.1}",
                effect.unwrap_or("none"),
                format!("{:?}", axis.actuator).to_lowercase(),
                truth(0.0),
                truth(0.5),
                best_err,
                best,
            )
        })
        .collect();
    println!(
        "{:<24} {:>6} {:<9} {:>8} {:>8} {:>8} {:>6}",
        "effect", "seed", "actuator", "truth@0", "@0.5", "@best", "best"
    );
    for r in rows {
        println!("{r}");
    }
}
