//! Writes generated seal-rig records (see `tests/generators/rig.rs`) into a folder, to try
//! `host-sim diagnose` on them by hand: `cargo run --release -p host-sim --example gen_rig -- DIR N`.

#[path = "../tests/generators/mod.rs"]
mod generators;

use generators::rig::random_record;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let dir = std::path::PathBuf::from(args.get(1).map_or("target/rig", |s| s.as_str()));
    let n: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(5);
    std::fs::create_dir_all(&dir).expect("create the output folder");
    for i in 0..n {
        let (text, truth) = random_record(1000 + i);
        let path = dir.join(format!("rig{i:02}.csv"));
        std::fs::write(&path, text).expect("write the record");
        println!("{}: {truth:?}", path.display());
    }
}
