//! Diagnosis across records, benchmarked on generated rigs with a known answer
//! (`tests/generators/rig.rs`): each rig is run at five pressures (1..7 bar); on half of the
//! rigs the seal is pressure-energised (Coulomb rises 0.4..1.5 N/bar), on the other half it is
//! not. Prints how often the pressure dependence is found when it is there and when it is
//! not, and whether reruns of one condition agree within their intervals.
//!
//! `cargo run --release -p host-sim --example across_records -- [RIGS] [RERUN_RIGS] [--verbose]`
//! (defaults 20 and 10; `--verbose` prints every record's levels)

#[path = "../tests/generators/mod.rs"]
mod generators;

use generators::rig::{series, Seal};
use generators::Rng;
use host_sim::diagnose::{across, Options};
use host_sim::record::Record;
use rayon::prelude::*;

fn rig_records(seal: &Seal, bars: &[f64], seed: u64) -> Vec<(String, Record)> {
    series(seal, bars, seed)
        .into_iter()
        .map(|(name, text)| {
            let rec = Record::parse(&text, std::path::Path::new(&name)).expect("parse");
            (name, rec)
        })
        .collect()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let num = |i: usize, d: u64| args.get(i).and_then(|s| s.parse().ok()).unwrap_or(d);
    let rigs = num(1, 20);
    let rerun_rigs = num(2, 10);
    let verbose = args.iter().any(|a| a == "--verbose");
    let wall = std::time::Instant::now();
    let bars = [1.0, 2.5, 4.0, 5.5, 7.0];
    let opts = Options::default();
    let mut found = [0usize; 2];
    let mut cases = [0usize; 2];
    let mut slope_err = Vec::new();
    let mut covered = 0usize;
    for r in 0..rigs {
        let dependent = r % 2 == 0;
        let mut rng = Rng::new(31 + r);
        let seal = Seal::random(&mut rng, dependent);
        let recs = rig_records(&seal, &bars, 500 + r);
        let a = across::analyse(&recs, &opts).expect("analysed");
        let t = a
            .trends
            .iter()
            .find(|t| t.level == "coulomb_force_n" && t.condition == "pressure_bar")
            .expect("a pressure trend");
        cases[usize::from(dependent)] += 1;
        found[usize::from(dependent)] += usize::from(t.significant);
        covered +=
            usize::from(t.ci_low <= seal.coulomb_per_bar && seal.coulomb_per_bar <= t.ci_high);
        slope_err.push(t.slope - seal.coulomb_per_bar);
        if verbose {
            for l in &a.records {
                let (fc, h) = l.interval95("coulomb_force_n").unwrap_or_default();
                println!(
                    "  {}: {:?}, Fc {fc:.3} +- {h:.3} N, error {:.2} %",
                    l.name, l.conditions, l.rel_err_pct
                );
            }
        }
        println!(
            "rig {r:2} true {:.3} N/bar: {}",
            seal.coulomb_per_bar,
            t.sentence()
        );
    }
    // reruns: five runs of one condition, pairs whose 95 % intervals overlap
    let mut pairs = [0usize; 2];
    let mut overlap = [0usize; 2];
    for r in 0..rerun_rigs {
        let mut rng = Rng::new(77 + r);
        let seal = Seal::random(&mut rng, true);
        let recs = rig_records(&seal, &[4.0; 5], 900 + r);
        let levels: Vec<across::RecordLevels> = recs
            .par_iter()
            .map(|(n, rec)| across::record_levels(rec, n, &opts).expect("fit"))
            .collect();
        for (j, name) in ["coulomb_force_n", "viscous_coefficient_n_s_per_m"]
            .iter()
            .enumerate()
        {
            let mut apart = 0;
            for a in 0..levels.len() {
                for b in a + 1..levels.len() {
                    let (ya, ha) = levels[a].interval95(name).unwrap_or_default();
                    let (yb, hb) = levels[b].interval95(name).unwrap_or_default();
                    pairs[j] += 1;
                    let ok = (ya - yb).abs() <= ha + hb;
                    overlap[j] += usize::from(ok);
                    apart += usize::from(!ok);
                }
            }
            if apart > 0 {
                // which reruns disagree: each run's value +- its 95 % half-width
                let runs: Vec<String> = levels
                    .iter()
                    .map(|l| {
                        let (y, h) = l.interval95(name).unwrap_or_default();
                        format!("{y:.4} +- {h:.4}")
                    })
                    .collect();
                println!("rig {r} {name}: {apart} pairs apart: {}", runs.join(", "));
            }
        }
    }
    println!(
        "\npressure dependence found when present: {}/{} ({:.0} %)",
        found[1],
        cases[1],
        100.0 * found[1] as f64 / cases[1].max(1) as f64
    );
    println!(
        "pressure dependence claimed when absent: {}/{} ({:.0} %)",
        found[0],
        cases[0],
        100.0 * found[0] as f64 / cases[0].max(1) as f64
    );
    println!(
        "the slope's 95 % interval holds the true slope: {covered}/{}",
        cases[0] + cases[1]
    );
    println!(
        "median |slope error|: {:.3} N/bar",
        host_sim::stats::median(&slope_err.iter().map(|e| e.abs()).collect::<Vec<_>>())
    );
    println!(
        "reruns of one condition: 95 % intervals overlap for Fc {}/{} pairs, sigma2 {}/{} pairs",
        overlap[0], pairs[0], overlap[1], pairs[1]
    );
    println!("({:.1} s)", wall.elapsed().as_secs_f64());
}
