//! Zero-phase Butterworth low-pass filtering (forward-backward, as `filtfilt`).
//!
//! A 4th-order Butterworth is two biquads from the bilinear transform with pre-warping; each
//! pass starts in the steady state of its first input sample, and the signal is extended at
//! both ends by odd reflection so the edges do not ring.

/// One biquad in transposed direct form II.
#[derive(Clone, Copy, Debug)]
struct Biquad {
    b: [f64; 3],
    a: [f64; 2],
}

impl Biquad {
    /// The state `[s1, s2]` of a biquad that has seen the constant input `x0` forever (its
    /// output `x0` times the DC gain): a pass started there does not ring.
    fn steady_state(&self, x0: f64) -> [f64; 2] {
        let [b0, b1, b2] = self.b;
        let [a1, a2] = self.a;
        let y0 = x0 * ((b0 + b1 + b2) / (1.0 + a1 + a2));
        let s2 = b2 * x0 - a2 * y0;
        [b1 * x0 - a1 * y0 + s2, s2]
    }

    /// One sample through the biquad: returns the output and advances the state.
    #[inline]
    fn step(&self, state: &mut [f64; 2], x: f64) -> f64 {
        let [b0, b1, b2] = self.b;
        let [a1, a2] = self.a;
        let [s1, s2] = *state;
        let y = b0 * x + s1;
        *state = [b1 * x - a1 * y + s2, b2 * x - a2 * y];
        y
    }
}

/// A zero-phase low-pass filter.
#[derive(Clone, Debug)]
pub struct LowPass {
    sections: Vec<Biquad>,
}

impl LowPass {
    /// 4th-order Butterworth with cutoff `cutoff_hz` at `sample_hz` (cutoff clamped below
    /// Nyquist). Applied forward and backward, the magnitude is squared (8th order, -6 dB at
    /// the cutoff) and the phase is zero.
    pub fn butterworth4(cutoff_hz: f64, sample_hz: f64) -> Self {
        let fc = cutoff_hz.min(0.45 * sample_hz);
        let k = (std::f64::consts::PI * fc / sample_hz).tan();
        let sections = [0.765_366_864_730_179_9, 1.847_759_065_022_573_5] // 2 cos(pi/8), 2 cos(3pi/8)
            .iter()
            .map(|&q| {
                let norm = 1.0 / (1.0 + q * k + k * k);
                let b0 = k * k * norm;
                Biquad {
                    b: [b0, 2.0 * b0, b0],
                    a: [2.0 * (k * k - 1.0) * norm, (1.0 - q * k + k * k) * norm],
                }
            })
            .collect();
        Self { sections }
    }

    /// Zero-phase filtering of several signals of the same length at once. The recursions of
    /// different signals are independent, so running them in lock-step lets the CPU overlap
    /// them (one serial biquad chain per signal would leave it waiting on each result).
    pub fn filtfilt_many(&self, xs: &[&[f64]]) -> Vec<Vec<f64>> {
        let k = xs.len();
        let n = xs.first().map_or(0, |x| x.len());
        if xs.iter().any(|x| x.len() != n) {
            return xs.iter().map(|x| self.filtfilt(x)).collect();
        }
        if n < 3 {
            return xs.iter().map(|x| x.to_vec()).collect();
        }
        let pad = (n - 1).min(300);
        let m = n + 2 * pad;
        // interleaved layout: sample-major, k signals per sample; each end extended by odd
        // reflection
        let mut buf = vec![0.0; m * k];
        for (j, x) in xs.iter().enumerate() {
            for i in 0..pad {
                buf[i * k + j] = 2.0 * x[0] - x[pad - i];
            }
            for i in 0..n {
                buf[(pad + i) * k + j] = x[i];
            }
            for i in 0..pad {
                buf[(pad + n + i) * k + j] = 2.0 * x[n - 1] - x[n - 2 - i];
            }
        }
        // The sections run fused, sample by sample: the second section's recursion on one
        // sample overlaps the first's on the next (the same arithmetic, in the same order, as
        // one section after the other). State of section q, signal j: `state[q * k + j]`.
        let mut state = vec![[0.0; 2]; k * self.sections.len()];
        for backward in [false, true] {
            for step in 0..m {
                let i = if backward { m - 1 - step } else { step };
                let row = &mut buf[i * k..(i + 1) * k];
                for (sec, state) in self.sections.iter().zip(state.chunks_exact_mut(k)) {
                    if step == 0 {
                        // each section starts in the steady state of its first input sample
                        for (s, x) in state.iter_mut().zip(row.iter()) {
                            *s = sec.steady_state(*x);
                        }
                    }
                    for (s, x) in state.iter_mut().zip(row.iter_mut()) {
                        *x = sec.step(s, *x);
                    }
                }
            }
        }
        (0..k)
            .map(|j| (0..n).map(|i| buf[(pad + i) * k + j]).collect())
            .collect()
    }

    /// Zero-phase filtering of `x` (returns a new vector of the same length).
    pub fn filtfilt(&self, x: &[f64]) -> Vec<f64> {
        self.filtfilt_many(&[x]).pop().unwrap_or_default()
    }
}

/// Zero-phase filtering of each column, segment by segment (never across a logger gap).
pub fn segmented(f: &LowPass, segments: &[std::ops::Range<usize>], xs: &[&[f64]]) -> Vec<Vec<f64>> {
    if let [whole] = segments {
        if whole.start == 0 && xs.iter().all(|x| x.len() == whole.end) {
            return f.filtfilt_many(xs);
        }
    }
    let mut out: Vec<Vec<f64>> = xs.iter().map(|x| Vec::with_capacity(x.len())).collect();
    for r in segments {
        let parts: Vec<&[f64]> = xs.iter().map(|x| &x[r.clone()]).collect();
        for (o, y) in out.iter_mut().zip(f.filtfilt_many(&parts)) {
            o.extend(y);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passes_dc_and_slow_sines_and_stops_fast_ones() {
        let f = LowPass::butterworth4(20.0, 1000.0);
        let n = 4000;
        let slow: Vec<f64> = (0..n)
            .map(|i| 3.0 + (2.0 * std::f64::consts::PI * 2.0 * i as f64 / 1000.0).sin())
            .collect();
        let fast: Vec<f64> = (0..n)
            .map(|i| (2.0 * std::f64::consts::PI * 150.0 * i as f64 / 1000.0).sin())
            .collect();
        let ys = f.filtfilt(&slow);
        let yf = f.filtfilt(&fast);
        let err = ys
            .iter()
            .zip(&slow)
            .skip(500)
            .take(3000)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        let amp = yf
            .iter()
            .skip(500)
            .take(3000)
            .map(|v| v.abs())
            .fold(0.0, f64::max);
        assert!(err < 1e-3, "2 Hz distorted by {err}");
        let both = f.filtfilt_many(&[&slow, &fast]);
        assert!(both[0].iter().zip(&ys).all(|(a, b)| (a - b).abs() < 1e-12));
        assert!(both[1].iter().zip(&yf).all(|(a, b)| (a - b).abs() < 1e-12));
        // 4th-order Butterworth at 20 Hz, forward and backward: |H(150 Hz)|^2 = 5.4e-8
        assert!(amp < 1e-6, "150 Hz leaks {amp}");
    }
}
