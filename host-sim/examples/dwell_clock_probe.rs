//! Where a dwell clock read off the measured motion differs from the record's own (the
//! generator's true clock): per stretch of samples, the true dwell increase against the one
//! the same shape gets from a body-speed clock (the speed over WINDOW samples; forgetting over
//! the shape's renewal distance, or at once with `--restart`): the 25 stretches of 50 ms that
//! differ most where the axis moves.
//! `cargo run --release -p host-sim --example dwell_clock_probe -- SEED [STICK] [WINDOW] [--restart]`
#[path = "../tests/generators/mod.rs"]
mod generators;
use generators::axis::{random_record, Shape};
use host_sim::diagnose::inverse::Prepared;
use host_sim::record::Record;
use std::path::Path;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let seed: u64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(1700);
    let stick: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(5e-5);
    let (text, axis) = random_record(Some("dwell_stiction"), seed);
    let rec = Record::parse(&text, Path::new("x.csv")).unwrap();
    let p = Prepared::new(&rec, "x.csv", Default::default()).unwrap();
    let Shape::Dwell {
        increase_n,
        tau_s,
        hill,
        renewal_m,
    } = axis.shape
    else {
        unreachable!()
    };
    let w = |age: f64| {
        let t = age.max(0.0).powf(hill);
        increase_n * t / (t + tau_s.powf(hill))
    };
    let truth = axis.dwell_trace.clone().unwrap().0;
    let mut age = 0.0f64;
    let win: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1);
    let restart = args.iter().any(|a| a == "--restart");
    let body: Vec<f64> = (0..p.len())
        .map(|i| {
            let v = if win == 1 {
                p.v_step[i]
            } else {
                (p.x[i] - p.x[i.saturating_sub(win)]) / (win as f64 * p.dt)
            };
            if v.abs() < stick {
                age += p.dt
            } else if restart {
                age = 0.0
            } else {
                age *= (-v.abs() * p.dt / renewal_m).exp()
            }
            age
        })
        .collect();
    println!("{axis:?}");
    // per 50 ms block: mean |v|, true and body increase (mean), moving share
    let mut rows = vec![];
    for b in (0..p.len()).step_by(50) {
        let e = (b + 50).min(p.len());
        let n = (e - b) as f64;
        let wt: f64 = (b..e).map(|i| w(truth[i])).sum::<f64>() / n;
        let wb: f64 = (b..e).map(|i| w(body[i])).sum::<f64>() / n;
        let mv: f64 = (b..e).map(|i| p.weight[i]).sum::<f64>() / n;
        let v: f64 = (b..e).map(|i| p.v[i].abs()).sum::<f64>() / n;
        rows.push((b, v, mv, wt, wb));
    }
    let total: f64 = rows.iter().map(|r| r.2 * (r.3 - r.4).powi(2)).sum();
    println!("scored squared gap {total:.0} N^2 (per block means)");
    let mut sorted = rows.clone();
    sorted.sort_by(|a, b| (b.2 * (b.3 - b.4).powi(2)).total_cmp(&(a.2 * (a.3 - a.4).powi(2))));
    for r in sorted.iter().take(25) {
        let (b, v, mv, wt, wb) = *r;
        println!("t {:7.2} s |v| {:8.5} m/s moving {:.2} true +{:6.1} N body-clock +{:6.1} N  true age {:.3} body age {:.3}",
            b as f64 * p.dt, v, mv, wt, wb, truth[b + 25.min(p.len() - 1 - b)], body[b + 25.min(p.len() - 1 - b)]);
    }
}
