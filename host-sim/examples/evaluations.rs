//! Evaluations each stage needs before its best individual has all its parameters within 1 %
//! of the truth, improved GA against CMA-ES, ideal setting, seeds 1..=20 (None: never).
//!
//! `cargo run --release -p host-sim --example evaluations`
use host_sim::identify::*;
use lugre_servo::friction::LugreParams;
fn main() {
    let t = LugreParams::table2();
    let d = ideal_data(&t);
    for alg in [Algorithm::Improved, Algorithm::Cmaes] {
        let v: Vec<_> = (1..=20)
            .map(|s| identify(alg, &d, s, Some(&t)).stage_evaluations_to_1pct)
            .collect();
        println!("{alg:?}: {v:?}");
    }
}
