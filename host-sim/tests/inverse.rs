//! What the inverse model scores: a reading at rest is not motion, and a record's edges are
//! not scored (the filters' transients, a force whose motion the record no longer holds).

use host_sim::diagnose::inverse::{
    reading_at_rest, AxisModel, Prepared, Protocol, REST_COUNTS, STUCK_SPEED,
};
use host_sim::record::Record;
use lugre_servo::friction::{FrictionModel, LugreParams};
use std::path::Path;

const COUNT: f64 = 1e-6;
const DT: f64 = 1e-3;

fn quantised(x: f64) -> f64 {
    (x / COUNT).round() * COUNT
}

/// A reading toggling between two counts is at rest; steady motion at the stuck threshold is
/// not; an unquantised reading never is.
#[test]
fn a_toggling_count_is_rest_and_slow_motion_is_not() {
    let n = 2000;
    let x: Vec<f64> = (0..n)
        .map(|i| {
            if i < 1000 {
                // one count, on for 2 periods of 3
                if i % 3 == 0 {
                    0.0
                } else {
                    COUNT
                }
            } else {
                quantised(STUCK_SPEED * (i - 1000) as f64 * DT)
            }
        })
        .collect();
    let whole: Vec<std::ops::Range<usize>> = std::iter::once(0..n).collect();
    let rest = reading_at_rest(&x, &whole, COUNT, DT);
    assert!(rest[..1000].iter().all(|r| *r), "toggling is rest");
    assert!(
        rest[1020..].iter().all(|r| !*r),
        "0.2 mm/s on a 1 um count is motion, to the record's last sample"
    );
    assert!(reading_at_rest(&x, &whole, 0.0, DT).iter().all(|r| !*r));
    // what the threshold means: less than REST_COUNTS counts in 10 ms is slower than STUCK_SPEED
    const { assert!(REST_COUNTS * COUNT / 0.01 < STUCK_SPEED) };
}

fn model() -> AxisModel {
    AxisModel {
        mass_kg: 50.0,
        friction: FrictionModel::plain(
            LugreParams::new(1e7, 0.0, 800.0, 100.0, 130.0, 5e-3).unwrap(),
        ),
    }
}

/// A record of `model` along a sinusoid with stops (1 um reading), its force the model's own
/// along the exact motion.
fn record_text(spike_at_end: f64) -> String {
    let m = model();
    let n = 6000;
    let x: Vec<f64> = (0..n)
        .map(|i| {
            let t = i as f64 * DT;
            // 0.5 Hz, with a pause at each turning point
            0.01 * (std::f64::consts::PI * t).sin().clamp(-0.95, 0.95)
        })
        .collect();
    let rec = Record::parse(
        &csv(&x.iter().map(|_| 1.0).collect::<Vec<_>>(), &x),
        Path::new("r.csv"),
    )
    .unwrap();
    let exact = Prepared::new(&rec, "r.csv", Protocol::default()).unwrap();
    let mut force = m.predict(&exact);
    *force.last_mut().unwrap() += spike_at_end;
    let xq: Vec<f64> = x.iter().map(|v| quantised(*v)).collect();
    csv(&force, &xq)
}

fn csv(force: &[f64], x: &[f64]) -> String {
    let mut s = String::from("t,x,force\n");
    for (i, (f, x)) in force.iter().zip(x).enumerate() {
        s.push_str(&format!("{:.3},{x:.7},{f:.4}\n", i as f64 * DT));
    }
    s
}

/// A force spike in the last sample (a feed-forward step the record ends on) leaves the
/// true model's error as it was (within 0.01 % of the force): the record's edges are not
/// scored. Scored, the spike was the error.
#[test]
fn a_force_at_the_last_sample_is_not_scored() {
    let err = |spike: f64| {
        let rec = Record::parse(&record_text(spike), Path::new("r.csv")).unwrap();
        let p = Prepared::new(&rec, "r.csv", Protocol::default()).unwrap();
        p.rel_err_pct(&model().predict(&p))
    };
    let (clean, spiked) = (err(0.0), err(20_000.0));
    println!("true model: {clean:.3} % clean, {spiked:.3} % with a spike in the last sample");
    assert!(clean < 5.0, "{clean}");
    // with 2 filter periods left out instead of 4 it read 2.7 %
    assert!((spiked - clean).abs() < 0.01, "{clean} -> {spiked}");
}
