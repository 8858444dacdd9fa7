//! The zero-phase filter's time on a 60 s record at 1 kHz: what a diagnosis's refits spend on
//! every scored model (one column, `LowPass::filtfilt_many` cuts it into runs side by side)
//! and on every linearisation (several columns in lock-step).
//!
//! `cargo run --release -p host-sim --example filter_timing -- [REPS]` (default 200) prints,
//! for 1, 2, 3, 5 and 8 columns of 60 000 samples, the median and the fastest wall time of
//! one call over REPS calls, in microseconds, and a checksum of the outputs (the same on two
//! builds whose filters agree bit for bit). One thread: nothing else runs beside it. The
//! machine is noisy: compare two builds by running them one after another, not against a
//! number.

use host_sim::signal::LowPass;
use std::time::Instant;

fn main() {
    let reps: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(200);
    let n = 60_000;
    let f = LowPass::butterworth4(20.0, 1000.0);
    // friction-like columns: a slow wave, sign flips at reversals, a little noise
    let columns: Vec<Vec<f64>> = (0..8)
        .map(|j| {
            (0..n)
                .map(|i| {
                    let t = i as f64 * 1e-3;
                    let v = (0.7 * t + j as f64).sin();
                    800.0 * v.signum() + 300.0 * v + 5.0 * ((i * 7919 + j) % 101) as f64 / 101.0
                })
                .collect()
        })
        .collect();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build();
    let Ok(pool) = pool else {
        eprintln!("no thread pool");
        std::process::exit(1);
    };
    pool.install(|| {
        println!("columns  median_us  fastest_us  checksum");
        for k in [1, 2, 3, 5, 8] {
            let refs: Vec<&[f64]> = columns[..k].iter().map(|x| x.as_slice()).collect();
            let mut times = Vec::with_capacity(reps);
            let mut checksum = 0.0;
            for _ in 0..reps {
                let t = Instant::now();
                let out = f.filtfilt_many(&refs);
                times.push(t.elapsed().as_secs_f64() * 1e6);
                checksum = out.iter().flatten().sum::<f64>();
            }
            times.sort_by(f64::total_cmp);
            println!(
                "{k:>7}  {:>9.0}  {:>10.0}  {checksum:.17e}",
                times[reps / 2],
                times[0]
            );
        }
    });
}
