//! The real-rig benchmark on generated stand-ins (the held-back rig records are not ours to
//! ship): seal-rig records from the independent generator (`tests/generators/rig.rs`: external
//! drive at 6..15 mm/s, a load cell, one chamber at 1..7 bar, a jittery 60..100 Hz logger with
//! stalls), each written to a file and run as a new user would (`diagnose --auto --out-params`).
//!
//! `cargo run --release -p host-sim --example rig_suite -- [N] [--json FILE]`
//!
//! Prints, per record and in total: analysed, mass >= 0, baseline / static table,
//! with the suggested effects / static asymmetric + offset table, and whether the parameter
//! file was written physical (or refused with a reason).

#[path = "../tests/generators/mod.rs"]
mod generators;

use generators::rig::random_record;
use host_sim::diagnose::{self, Options};
use host_sim::record::Record;
use rayon::prelude::*;

#[derive(serde::Serialize)]
struct Row {
    record: String,
    analysed: bool,
    error: Option<String>,
    mass_kg: f64,
    static_pct: f64,
    baseline_pct: f64,
    static_asym_pct: f64,
    suggested_pct: f64,
    added: Vec<String>,
    file: String,
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: u64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(40);
    let json = args
        .iter()
        .position(|a| a == "--json")
        .and_then(|i| args.get(i + 1).cloned());
    let dir = std::env::temp_dir().join("lugre-rig-suite");
    std::fs::create_dir_all(&dir).expect("temp folder");
    let wall = std::time::Instant::now();
    let rows: Vec<Row> = (0..n)
        .into_par_iter()
        .map(|i| {
            let (text, _truth) = random_record(5000 + i);
            let path = dir.join(format!("rig{i:03}.csv"));
            std::fs::write(&path, text).expect("write");
            let name = path.display().to_string();
            let rec = Record::read(&path).expect("readable");
            let opts = Options {
                auto: 3,
                ..Default::default()
            };
            match diagnose::diagnose(&rec, &name, &opts) {
                Err(e) => Row {
                    record: name,
                    analysed: false,
                    error: Some(e.to_string()),
                    mass_kg: f64::NAN,
                    static_pct: f64::NAN,
                    baseline_pct: f64::NAN,
                    static_asym_pct: f64::NAN,
                    suggested_pct: f64::NAN,
                    added: vec![],
                    file: "none".into(),
                },
                Ok(d) => {
                    // what `--out-params` would do: refuse an undetermined mass, and values
                    // that fail the core's physical check (`parameter_file` applies it since
                    // session 108, saying what the fit left at an edge)
                    let file = match diagnose::parameter_file(&d, None) {
                        Ok(_) => "written, physical".into(),
                        Err(e @ host_sim::Error::ModelNotPhysical { .. }) => {
                            format!("NON-PHYSICAL (refused): {e}")
                        }
                        Err(e) => {
                            format!("refused: {}", e.to_string().split(';').next().unwrap_or(""))
                        }
                    };
                    Row {
                        record: name,
                        analysed: true,
                        error: None,
                        mass_kg: d.model().mass_kg,
                        static_pct: d.tables.symmetric.rel_err_pct,
                        baseline_pct: d.stages[0].fit.rel_err_pct,
                        static_asym_pct: d.tables.asymmetric.rel_err_pct,
                        suggested_pct: d.last_stage().fit.rel_err_pct,
                        added: d.stages[1..].iter().map(|s| s.label.clone()).collect(),
                        file,
                    }
                }
            }
        })
        .collect();
    println!(
        "{:<10} {:>8} {:>9} {:>9} {:>9} {:>9}  {:<40} file",
        "record", "M [kg]", "table %", "LuGre %", "asym+off", "+effects", "added"
    );
    for r in &rows {
        let short = r.record.rsplit('/').next().unwrap_or("");
        if let Some(e) = &r.error {
            println!("{short:<10} NOT ANALYSED: {e}");
            continue;
        }
        println!(
            "{short:<10} {:>8.3} {:>9.2} {:>9.2} {:>9.2} {:>9.2}  {:<40} {}",
            r.mass_kg,
            r.static_pct,
            r.baseline_pct,
            r.static_asym_pct,
            r.suggested_pct,
            r.added.join(" "),
            r.file
        );
    }
    let ok: Vec<&Row> = rows.iter().filter(|r| r.analysed).collect();
    let count = |f: &dyn Fn(&Row) -> bool| ok.iter().filter(|r| f(r)).count();
    let total = rows.len();
    println!("\nanalysed: {}/{total}", ok.len());
    println!("negative mass: {}", count(&|r| r.mass_kg < 0.0));
    println!(
        "baseline <= 1.05x static table: {}/{}",
        count(&|r| r.baseline_pct <= 1.05 * r.static_pct),
        ok.len()
    );
    println!(
        "with the suggested effects <= static asymmetric + offset: {}/{}",
        count(&|r| r.suggested_pct <= r.static_asym_pct),
        ok.len()
    );
    println!(
        "parameter files: {} written physical, {} refused with a reason, {} non-physical",
        count(&|r| r.file.starts_with("written")),
        count(&|r| r.file.starts_with("refused")),
        count(&|r| r.file.starts_with("NON"))
    );
    let med = |f: &dyn Fn(&Row) -> f64| {
        host_sim::stats::median(&ok.iter().map(|r| f(r)).collect::<Vec<_>>())
    };
    println!(
        "median error: static table {:.2} %, LuGre baseline {:.2} %, static asym + offset {:.2} %, with suggested effects {:.2} %",
        med(&|r| r.static_pct),
        med(&|r| r.baseline_pct),
        med(&|r| r.static_asym_pct),
        med(&|r| r.suggested_pct)
    );
    println!("({total} records, {:.1} s)", wall.elapsed().as_secs_f64());
    if let Some(path) = json {
        std::fs::write(&path, serde_json::to_string_pretty(&rows).expect("json"))
            .expect("write json");
        println!("wrote {path}");
    }
}
