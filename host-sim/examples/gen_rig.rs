//! Writes generated seal-rig records (see `tests/generators/rig.rs`) into a folder, to try
//! `host-sim diagnose` on them by hand: `cargo run --release -p host-sim --example gen_rig -- DIR N`.

#[path = "../tests/generators/mod.rs"]
mod generators;

use generators::rig::{record, Logger, Seal};
use generators::Rng;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let dir = std::path::PathBuf::from(args.get(1).map_or("target/rig", |s| s.as_str()));
    let n: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(5);
    std::fs::create_dir_all(&dir).expect("create the output folder");
    for i in 0..n {
        let mut rng = Rng::new(1000 + i);
        let seal = Seal::random(&mut rng, true);
        let logger = Logger::random(&mut rng);
        let bar = rng.range(1.0, 7.0);
        let (text, truth) = record(&seal, bar, logger, 77 + i);
        let path = dir.join(format!("rig{i:02}.csv"));
        std::fs::write(&path, text).expect("write the record");
        println!("{}: {truth:?}", path.display());
    }
}
