//! Writes generated seal-rig records (see `tests/generators/rig.rs`) into a folder, to try
//! `host-sim diagnose` on them by hand:
//! `cargo run --release -p host-sim --example gen_rig -- DIR N` (N random rigs), or
//! `... -- DIR series [SEED [RECORDS_SEED]]` (one pressure-energised seal at 1, 2.5, 4, 5.5
//! and 7 bar, for `host-sim diagnose --data DIR --report R.html`; `across_records`' rig r is
//! `series 31+r 500+r`).

#[path = "../tests/generators/mod.rs"]
mod generators;

use generators::rig::{random_record, series, Seal};
use generators::Rng;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let dir = std::path::PathBuf::from(args.get(1).map_or("target/rig", |s| s.as_str()));
    std::fs::create_dir_all(&dir).expect("create the output folder");
    if args.get(2).map(String::as_str) == Some("series") {
        let seed: u64 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(21);
        let records_seed: u64 = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(seed);
        let seal = Seal::random(&mut Rng::new(seed), true);
        for (name, text) in series(&seal, &[1.0, 2.5, 4.0, 5.5, 7.0], records_seed) {
            let path = dir.join(&name);
            std::fs::write(&path, text).expect("write the record");
            println!("{}", path.display());
        }
        println!("true Coulomb slope {:.3} N/bar", seal.coulomb_per_bar);
        return;
    }
    let n: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(5);
    for i in 0..n {
        let (text, truth) = random_record(1000 + i);
        let path = dir.join(format!("rig{i:02}.csv"));
        std::fs::write(&path, text).expect("write the record");
        println!("{}: {truth:?}", path.display());
    }
}
