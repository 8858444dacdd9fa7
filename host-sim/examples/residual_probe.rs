//! Where the error lives, on the independent generator's records: the scored squared residual
//! of the generator's true model (driven by the measured motion through the pipeline: the
//! noise floor) and of the diagnosis's fitted baseline, binned by speed and by the time since
//! the axis last rested. Per record, one summary line: the floor and the baseline, the share
//! of the floor's squared error below [`SLOW`] and the share of scored samples there, and
//! both models' rms residual above [`FAST`] (where a missing Stribeck shape, viscous law or
//! temperature dependence shows and the true model is near the force noise).
//!
//! `cargo run --release -p host-sim --example residual_probe -- [EFFECT|none] [FIRST_SEED] [N] [-v]`
//! (defaults `none 500 1`; `-v` prints the bins). Seeds are the suite's (`axis_suite`): held-out
//! effect-free from 500, effect `k` of `EFFECTS` from `20000 + 100 k`; calibration 100 and
//! `1000 + 100 k`.

#[path = "../tests/generators/mod.rs"]
mod generators;

use generators::axis::random_record;
use host_sim::diagnose::{self, Options};
use host_sim::record::Record;
use rayon::prelude::*;
use std::path::Path;

/// Below this speed a sample counts as slow in the summary [m/s].
const SLOW: f64 = 5e-3;
/// Above this speed a sample counts as fast in the summary [m/s].
const FAST: f64 = 1e-2;

/// Scored residuals of two filtered model forces, gathered over the samples a key selects.
#[derive(Default)]
struct Bin {
    samples: f64,
    truth_ss: f64,
    base_ss: f64,
}

impl Bin {
    fn rms(&self) -> (f64, f64) {
        let n = self.samples.max(1.0);
        ((self.truth_ss / n).sqrt(), (self.base_ss / n).sqrt())
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let effect_arg = args.get(1).cloned().unwrap_or("none".into());
    let first: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(500);
    let count: u64 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1);
    let verbose = args.iter().any(|a| a == "-v");
    let effect = generators::axis::effect_named(&effect_arg).unwrap_or_else(|e| panic!("{e}"));
    let seeds: Vec<u64> = (first..first + count).collect();
    let out: Vec<String> = seeds
        .par_iter()
        .map(|&seed| probe(effect, seed, verbose))
        .collect();
    println!(
        "{:>6} {:<9} {:>7} {:>7} {:>15} {:>15} {:>17}",
        "seed",
        "actuator",
        "floor %",
        "base %",
        "floor err slow",
        "samples slow",
        "fast rms t / b N"
    );
    for s in out {
        print!("{s}");
    }
}

fn probe(effect: Option<&'static str>, seed: u64, verbose: bool) -> String {
    let (text, axis) = random_record(effect, seed);
    let rec = Record::parse(&text, Path::new("probe.csv")).expect("generated record");
    let opts = Options {
        skip_final_ranking: true,
        ..Default::default()
    };
    let d = diagnose::diagnose(&rec, "probe.csv", &opts).expect("diagnosis");
    let p = &d.prepared;
    let truth = p.filter(&generators::axis::truth_force(&axis, p));
    let base = &d.stages[0].fit.prediction;
    // time since the last sample left out of the score (a rest)
    let mut since = vec![0.0; p.len()];
    let mut last = 0;
    for (i, s) in since.iter_mut().enumerate() {
        if p.weight[i] == 0.0 {
            last = i;
        }
        *s = (i - last) as f64 * p.dt;
    }
    let gather = |key: &dyn Fn(usize) -> bool| {
        let mut b = Bin::default();
        for i in (0..p.len()).filter(|&i| p.weight[i] > 0.0 && key(i)) {
            b.samples += 1.0;
            b.truth_ss += (p.force[i] - truth[i]).powi(2);
            b.base_ss += (p.force[i] - base[i]).powi(2);
        }
        b
    };
    let all = gather(&|_| true);
    let slow = gather(&|i| p.v[i].abs() < SLOW);
    let fast = gather(&|i| p.v[i].abs() >= FAST);
    let pct = |x: f64, of: f64| 100.0 * x / of.max(1e-300);
    let (fast_t, fast_b) = fast.rms();
    let mut s = format!(
        "{seed:>6} {:<9} {:>7.2} {:>7.2} {:>13.0} % {:>13.0} % {:>8.1} / {:<6.1}\n",
        format!("{:?}", axis.actuator).to_lowercase(),
        100.0 * all.truth_ss.sqrt() / p.force_norm,
        d.stages[0].fit.rel_err_pct,
        pct(slow.truth_ss, all.truth_ss),
        pct(slow.samples, all.samples),
        fast_t,
        fast_b,
    );
    if verbose {
        let norm2 = p.force_norm * p.force_norm;
        let mut table = |name: &str, key: &dyn Fn(usize) -> f64, edges: &[f64]| {
            s += &format!("   by {name} (share of the squared force norm, %; rms, N):\n");
            for w in edges.windows(2) {
                let b = gather(&|i| (w[0]..w[1]).contains(&key(i)));
                let (rt, rb) = b.rms();
                s += &format!(
                    "     [{:7.4}, {:7.4}) {:>6} samples  truth {:6.2}  baseline {:6.2}  ({rt:.1} / {rb:.1})\n",
                    w[0],
                    w[1].min(99.0),
                    b.samples,
                    1e4 * b.truth_ss / norm2,
                    1e4 * b.base_ss / norm2,
                );
            }
        };
        let speeds = [
            0.0,
            0.5e-3,
            1e-3,
            2e-3,
            5e-3,
            1e-2,
            2e-2,
            5e-2,
            f64::INFINITY,
        ];
        let times = [0.0, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, f64::INFINITY];
        table("speed [m/s]", &|i| p.v[i].abs(), &speeds);
        table("time since rest [s]", &|i| since[i], &times);
    }
    s
}
