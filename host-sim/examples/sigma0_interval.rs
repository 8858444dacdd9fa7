//! Realistic sigma0 over noise seeds 1..=N (improved GA): the signed error, the 95 % interval
//! and whether it holds the truth.
//!
//! `cargo run --release -p host-sim --example sigma0_interval [-- N]`
use host_sim::identify::*;
use host_sim::plant::{PlantConfig, SensorConfig};
use host_sim::stats::median;
use lugre_servo::friction::LugreParams;
use rayon::prelude::*;

fn main() {
    let n: u64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(20);
    let cfg = PlantConfig::default();
    let truth = LugreParams::table2();
    let s0 = truth.bristle_stiffness();
    let runs: Vec<(u64, f64, [f64; 2], bool)> = (1..=n)
        .into_par_iter()
        .map(|seed| {
            let d = realistic_data_with(&cfg, SensorConfig::realistic(seed));
            let r = identify(Algorithm::Improved, &d, seed, Some(&truth));
            let i = r.identifiability[0].map_or([f64::NAN; 2], |i| i.interval95);
            let err = 100.0 * (r.values[0] / s0 - 1.0);
            (seed, err, i, i[0] <= s0 && s0 <= i[1])
        })
        .collect();
    for (seed, err, i, holds) in &runs {
        println!("seed {seed:2}  sigma0 {err:+6.2} %  95 % interval [{:.3e}, {:.3e}]  holds the truth: {holds}", i[0], i[1]);
    }
    println!(
        "median |error| {:.2} %, median signed {:+.2} %, interval holds the truth {}/{n}",
        median(&runs.iter().map(|r| r.1.abs()).collect::<Vec<_>>()),
        median(&runs.iter().map(|r| r.1).collect::<Vec<_>>()),
        runs.iter().filter(|r| r.3).count()
    );
}
