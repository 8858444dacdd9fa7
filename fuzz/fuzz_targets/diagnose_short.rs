//! The diagnosis on short records shaped by the bytes: 500..1500 samples of a logger's
//! timing (jitter, gaps), motion (sinusoids, holds, steps, raw byte-driven positions) and
//! force (friction-like, constant, spiky, huge). It refuses with an error or it returns a
//! diagnosis whose every reported error is finite: never a panic, never a NaN.
#![no_main]

use host_sim::diagnose::{self, Options};
use host_sim::record::Record;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if data.len() < 8 {
        return;
    }
    let (h, raw) = data.split_at(8);
    let n = 500 + usize::from(u16::from_le_bytes([h[0], h[1]]) % 1000);
    let dt = [1e-3, 2e-3, 1e-2, 1e-4][usize::from(h[2] % 4)];
    let jitter = f64::from(h[3] % 8) / 10.0;
    let amplitude = [0.0, 1e-6, 1e-3, 0.05, 1e3][usize::from(h[4] % 5)];
    let freq = 0.1 + f64::from(h[5]) / 16.0;
    let force_scale = [0.0, 1.0, 500.0, 1e9][usize::from(h[6] % 4)];
    let shape = h[7];
    let byte = |i: usize| raw.get(i % raw.len().max(1)).copied().unwrap_or(0);
    let mut rec = Record::default();
    let mut t = 0.0;
    for i in 0..n {
        let b = byte(i);
        // logger timing: jitter, and now and then a gap
        t += dt * (1.0 + jitter * (f64::from(b) / 255.0 - 0.5)) * if b == 255 { 50.0 } else { 1.0 };
        let phase = 2.0 * std::f64::consts::PI * freq * t;
        let x = match shape % 4 {
            0 => amplitude * phase.sin(),
            1 => amplitude * (phase.sin()).signum(),
            2 => amplitude * f64::from(b) / 255.0,
            _ => amplitude * phase.sin() + 1e-6 * f64::from(b),
        };
        let v = amplitude * phase.cos();
        let force = match shape / 4 % 4 {
            0 => force_scale * v.signum() + 0.1 * force_scale * v,
            1 => force_scale,
            2 => force_scale * (f64::from(b) - 128.0) / 128.0,
            _ => force_scale * v.signum() * (1.0 + (b == 0) as u8 as f64 * 100.0),
        };
        rec.t.push(t);
        rec.x.push(x);
        rec.force.push(force);
    }
    if shape & 0x40 != 0 {
        let half: Vec<f64> = rec
            .t
            .iter()
            .map(|_| 5e6 + f64::from(byte(7)) * 1e5)
            .collect();
        rec.p_a = Some(half.clone());
        rec.p_b = Some(half);
    }
    let opts = Options {
        auto: usize::from(shape >> 7),
        ..Default::default()
    };
    if let Ok(d) = diagnose::diagnose(&rec, "fuzz.csv", &opts) {
        for s in &d.stages {
            assert!(
                s.fit.rel_err_pct.is_finite(),
                "{}: {}",
                s.label,
                s.fit.rel_err_pct
            );
            for c in &s.candidates {
                if let Some(e) = c.rel_err_pct {
                    assert!(e.is_finite(), "{}: {e}", c.kind);
                }
            }
        }
    }
});
