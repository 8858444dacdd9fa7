//! Which sensor limits which parameter: the realistic identification (improved GA, seed 1)
//! repeated with one sensor made better at a time.
//!
//! `cargo run --release -p host-sim --example sensor_limits`
use host_sim::identify::*;
use host_sim::plant::{PlantConfig, SensorConfig};
use lugre_servo::friction::LugreParams;
fn main() {
    let cfg = PlantConfig::default();
    let truth = LugreParams::table2();
    let r = SensorConfig::realistic(1);
    for (name, s) in [
        ("realistic", r),
        (
            "encoder 10 nm",
            SensorConfig {
                encoder_resolution_m: 1e-8,
                ..r
            },
        ),
        (
            "encoder 1 nm",
            SensorConfig {
                encoder_resolution_m: 1e-9,
                ..r
            },
        ),
        (
            "no pressure noise",
            SensorConfig {
                pressure_noise_pa: 0.0,
                ..r
            },
        ),
        (
            "no delay",
            SensorConfig {
                delay_samples: 0,
                ..r
            },
        ),
        ("ideal sensors", SensorConfig::ideal()),
    ] {
        let d = realistic_data_with(&cfg, s);
        let res = identify(Algorithm::Improved, &d, 1, Some(&truth));
        let e = res.errors_pct.unwrap();
        println!("{name:18} s0 {:7.3}% s1 {:7.2}% s2 {:6.3}% fc {:6.3}% dfs {:6.3}% vs {:6.3}%  s1 ident {:?}", e.sigma0, e.sigma1, e.sigma2, e.fc, e.fs_minus_fc, e.vs, res.identifiability[1].map(|i| (i.identifiable, i.interval95)));
    }
}
