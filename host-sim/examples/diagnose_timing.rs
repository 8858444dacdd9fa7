//! The diagnosis's time on 60 s records at 1 kHz, all candidates ranked (issue 9's target:
//! at most 5 s, release, 2 cores): records of the independent axis generator
//! (`tests/generators/axis.rs`), one effect-free and one per effect for each seed, diagnosed one
//! after another as `host-sim diagnose --data F` does (the CSV parsed, default options), each
//! with the whole thread pool.
//!
//! `cargo run --release -p host-sim --example diagnose_timing -- [SEED ...] [--json F]`
//! (default seeds 1000..1004: 45 records, the ones `axis_suite 0 0 --write DIR --seed N` writes).
//! Prints each record's wall time (and of it the two baselines', the candidates' and the nested
//! check's, `diagnose::PhaseTimes`; every phase in the JSON), then the median, the maximum and
//! how many took over 5 s;
//! `--json F` writes the same; `--encoder-um R`, `--noise-x K` and `--log-hz F` measure every
//! record through other sensors (`Sensors::from_args`; a coarse count makes the diagnosis fit a
//! second first baseline, `diagnose::prepare`); `--contact maxwell` puts a generalized
//! Maxwell-slip contact under the same axes (`generators::axis::Maxwell`); `--axes issue` times
//! the axes issue 9 describes (`generators::axis::Axes::Issue`). Generating a record is not
//! timed. The machine is noisy: compare two builds by running them one after another on the
//! same records, not against a number. Each row also counts the samples the diagnosis
//! simulated (`Msamples`, millions; `simulated_samples` in the JSON,
//! `diagnose::inverse::simulated_samples`): most of its work, the same on any machine under
//! any load (session 108: the wall clock moved by 20..50 % between runs of one build).
//!
//! `diagnose_timing --compare A1.json,A2.json B1.json,B2.json` compares two builds' runs
//! (each a comma-separated list of `--json` files, interleaved runs of one build) record by
//! record: each record's time averaged over its build's runs, then the median of the paired
//! differences B - A and of the ratios B / A, beside the two builds' medians, each build's
//! slowest record (on its mean over the runs), and the records whose first significant
//! candidate differs. The median of the paired differences is the
//! robust yardstick: a build's overall median moves with which records sit near it (session
//! 50: main's two runs' medians 2.06 and 2.11 s, the paired difference of a change +0.03 s
//! while its overall median moved +0.11 s).

#[path = "../tests/generators/mod.rs"]
mod generators;

use generators::axis::{random_record_of, Axes, ContactKind, DwellLaw, Family, Sensors, EFFECTS};
use host_sim::diagnose::{self, inverse, Options};
use host_sim::record::Record;
use std::path::Path;
use std::time::Instant;

/// The target for one record \[s\].
const TARGET_S: f64 = 5.0;

#[derive(serde::Serialize)]
struct Row {
    effect: String,
    seed: u64,
    /// parse and diagnose, wall clock \[s\]
    seconds: f64,
    /// samples the diagnosis simulated (`inverse::simulated_samples`): its cost counted, the
    /// same on any machine under any load
    simulated_samples: u64,
    /// times the baseline was replaced by a better start (`diagnose::Restart`)
    restarts: usize,
    /// the first significant candidate, if any
    first_significant: Option<String>,
    /// where the diagnosis spent its time (its own clock: without parsing the CSV)
    phases: diagnose::PhaseTimes,
}

#[derive(serde::Serialize)]
struct Summary {
    records: usize,
    median_s: f64,
    max_s: f64,
    over_target: usize,
    target_s: f64,
    threads: usize,
    rows: Vec<Row>,
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let Some(i) = args.iter().position(|a| a == "--compare") {
        let (Some(a), Some(b)) = (args.get(i + 1), args.get(i + 2)) else {
            eprintln!("--compare takes two comma-separated lists of --json files");
            std::process::exit(2);
        };
        compare(a, b);
        return;
    }
    let json = args
        .iter()
        .position(|a| a == "--json")
        .and_then(|i| args.get(i + 1).cloned());
    let sensors = Sensors::from_args(&args);
    let contact = ContactKind::from_args(&args);
    let axes = Axes::from_args(&args);
    let law = DwellLaw::from_args(&args);
    let takes_value = |flag: &str| {
        ["--json", "--contact", "--axes", "--dwell-law"].contains(&flag)
            || Sensors::FLAGS.contains(&flag)
    };
    // seeds as separate arguments or comma-separated (`1139 1140` or `1139,1140`)
    let mut seeds: Vec<u64> = Vec::new();
    for (i, a) in args.iter().enumerate() {
        if a.starts_with("--") || (i > 0 && takes_value(&args[i - 1])) {
            continue;
        }
        for s in a.split(',').filter(|s| !s.is_empty()) {
            match s.parse() {
                Ok(seed) => seeds.push(seed),
                Err(_) => {
                    eprintln!(
                        "error: argument {}: seed {s:?} is not a whole number",
                        i + 1
                    );
                    std::process::exit(2);
                }
            }
        }
    }
    if seeds.is_empty() {
        seeds = (1000..=1004).collect();
    }
    println!(
        "{:<24} {:>5} {:>8} {:>8} {:>8} {:>8} {:>8} {:>9}  first significant",
        "record", "seed", "seconds", "baseline", "cands", "nested", "restarts", "Msamples"
    );
    let mut rows = Vec::new();
    for &seed in &seeds {
        for effect in std::iter::once(None).chain(EFFECTS.map(Some)) {
            let name = effect.unwrap_or("none");
            let (text, _) = random_record_of(effect, seed, sensors, contact, Family::A, axes, law);
            let path = format!("{name}-{seed}.csv");
            let start = Instant::now();
            let simulated_before = inverse::simulated_samples();
            let rec = Record::parse(&text, Path::new(&path)).expect("a generated record parses");
            let d = diagnose::diagnose(&rec, &path, &Options::default()).expect("diagnosis");
            let seconds = start.elapsed().as_secs_f64();
            let simulated_samples = inverse::simulated_samples() - simulated_before;
            let first_significant = d.stages[0]
                .first_significant()
                .map(|c| c.kind.name().to_string());
            let restarts = d.stages[0].restarts.len();
            let t = d.times;
            println!(
                "{name:<24} {seed:>5} {seconds:>8.2} {:>8.2} {:>8.2} {:>8.2} {restarts:>8} {:>9.1}  {}",
                t.first_baseline_s + t.baseline_s,
                t.candidates_s,
                t.nested_s,
                simulated_samples as f64 * 1e-6,
                first_significant.as_deref().unwrap_or("-")
            );
            rows.push(Row {
                effect: name.into(),
                seed,
                seconds,
                simulated_samples,
                restarts,
                first_significant,
                phases: t,
            });
        }
    }
    let mut times: Vec<f64> = rows.iter().map(|r| r.seconds).collect();
    times.sort_by(f64::total_cmp);
    let summary = Summary {
        records: rows.len(),
        median_s: host_sim::stats::median(&times),
        max_s: times.last().copied().unwrap_or(f64::NAN),
        over_target: times.iter().filter(|t| **t > TARGET_S).count(),
        target_s: TARGET_S,
        threads: rayon::current_num_threads(),
        rows,
    };
    println!(
        "\n{} records, {} threads: median {:.2} s, max {:.2} s, {} over {TARGET_S} s",
        summary.records, summary.threads, summary.median_s, summary.max_s, summary.over_target
    );
    if let Some(path) = json {
        std::fs::write(&path, serde_json::to_string_pretty(&summary).expect("json"))
            .expect("write json");
        println!("wrote {path}");
    }
}

/// One build's runs (`--json` files, comma-separated): each record's (effect, seed) with its
/// time averaged over the runs \[s\] and its first run's first significant candidate.
fn runs(list: &str) -> Vec<((String, u64), f64, Option<String>)> {
    let files: Vec<serde_json::Value> = list
        .split(',')
        .map(|f| {
            let parsed = std::fs::read_to_string(f)
                .map_err(|e| e.to_string())
                .and_then(|t| serde_json::from_str(&t).map_err(|e| e.to_string()));
            parsed.unwrap_or_else(|e| {
                eprintln!("{f}: {e}");
                std::process::exit(2)
            })
        })
        .collect();
    fn rows(v: &serde_json::Value) -> &[serde_json::Value] {
        v["rows"].as_array().map_or(&[], Vec::as_slice)
    }
    let key = |r: &serde_json::Value| {
        (
            r["effect"].as_str().unwrap_or("?").to_string(),
            r["seed"].as_u64().unwrap_or(0),
        )
    };
    rows(&files[0])
        .iter()
        .map(|r| {
            let k = key(r);
            let times: Vec<f64> = files
                .iter()
                .filter_map(|f| rows(f).iter().find(|q| key(q) == k))
                .filter_map(|q| q["seconds"].as_f64())
                .collect();
            let mean = times.iter().sum::<f64>() / times.len() as f64;
            let first = r["first_significant"].as_str().map(str::to_string);
            (k, mean, first)
        })
        .collect()
}

/// `--compare`: build B against build A, record by record (see the module's docs).
fn compare(a: &str, b: &str) {
    let (ra, rb) = (runs(a), runs(b));
    let mut diffs = Vec::new();
    let mut ratios = Vec::new();
    for (k, ta, fa) in &ra {
        let Some((_, tb, fb)) = rb.iter().find(|(kb, _, _)| kb == k) else {
            continue;
        };
        diffs.push(tb - ta);
        ratios.push(tb / ta);
        if fa != fb {
            println!(
                "{} {}: first significant {} -> {}",
                k.0,
                k.1,
                fa.as_deref().unwrap_or("-"),
                fb.as_deref().unwrap_or("-")
            );
        }
    }
    let median = host_sim::stats::median;
    let overall = |r: &[((String, u64), f64, Option<String>)]| {
        median(&r.iter().map(|x| x.1).collect::<Vec<f64>>())
    };
    println!(
        "{} records paired: A median {:.3} s, B median {:.3} s; paired B - A median {:+.3} s, B / A median {:.3}",
        diffs.len(),
        overall(&ra),
        overall(&rb),
        median(&diffs),
        median(&ratios)
    );
    // the slowest record of each build, on its mean over the build's runs
    let slowest = |r: &[((String, u64), f64, Option<String>)]| {
        r.iter()
            .max_by(|x, y| x.1.total_cmp(&y.1))
            .map_or("-".to_string(), |(k, t, _)| {
                format!("{t:.2} s ({} {})", k.0, k.1)
            })
    };
    println!(
        "slowest record (mean over the runs): A {}, B {}",
        slowest(&ra),
        slowest(&rb)
    );
}
