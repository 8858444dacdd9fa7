//! The diagnosis's cost counted (`inverse::simulated_samples`): each simulation adds the
//! record's samples once, whichever outputs it keeps. Alone in its test binary, so no other
//! test's simulations run while it counts.

use host_sim::diagnose::inverse::{simulated_samples, AxisModel, Prepared, Protocol};
use host_sim::record::Record;
use lugre_servo::friction::{FrictionModel, LugreParams};
use std::path::Path;

#[test]
fn every_simulation_counts_the_records_samples_once() {
    // a 0.5 Hz sinusoid with pauses at its turning points, 10 000 samples at 1 kHz: long
    // enough that a segment is simulated as two halves side by side
    let n = 10_000;
    let mut text = String::from("t,x,force\n");
    for i in 0..n {
        let t = i as f64 * 1e-3;
        let x = 0.01 * (std::f64::consts::PI * t).sin().clamp(-0.95, 0.95);
        text += &format!("{t},{x},1.0\n");
    }
    let rec = Record::parse(&text, Path::new("r.csv")).unwrap();
    let p = Prepared::new(&rec, "r.csv", Protocol::default()).unwrap();
    let m = AxisModel {
        mass_kg: 50.0,
        friction: FrictionModel::plain(
            LugreParams::new(1e7, 0.0, 800.0, 100.0, 130.0, 5e-3).unwrap(),
        ),
    };
    let decay = m.stribeck_decay(&p);
    let before = simulated_samples();
    let _ = m.simulate(&p);
    assert_eq!(simulated_samples() - before, p.len() as u64);
    let _ = m.simulate_with_decay(&p, &decay);
    let _ = m.friction_with_decay(&p, &decay);
    assert_eq!(simulated_samples() - before, 3 * p.len() as u64);
    // a prediction is a simulation too
    let _ = m.predict(&p);
    assert_eq!(simulated_samples() - before, 4 * p.len() as u64);
}
