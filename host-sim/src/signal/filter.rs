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

    /// [`Self::steady_state`] of each lane: `[s1 of every lane, s2 of every lane]`.
    #[inline]
    fn steady_state_lanes(&self, x: &[f64; LANES]) -> [[f64; LANES]; 2] {
        let mut out = [[0.0; LANES]; 2];
        for (l, &x) in x.iter().enumerate() {
            [out[0][l], out[1][l]] = self.steady_state(x);
        }
        out
    }

    /// One sample of each lane through the biquad, `y = b0 x + s1`,
    /// `s1' = b1 x - a1 y + s2`, `s2' = b2 x - a2 y`: returns the outputs and advances the
    /// states. Written lane-wise so that it compiles to vector instructions.
    #[inline(always)]
    fn step_lanes(&self, state: &mut [[f64; LANES]; 2], x: &[f64; LANES]) -> [f64; LANES] {
        let [b0, b1, b2] = self.b;
        let [a1, a2] = self.a;
        let [s1, s2] = *state;
        let mut y = [0.0; LANES];
        for l in 0..LANES {
            y[l] = b0 * x[l] + s1[l];
        }
        for l in 0..LANES {
            state[0][l] = b1 * x[l] - a1 * y[l] + s2[l];
            state[1][l] = b2 * x[l] - a2 * y[l];
        }
        y
    }
}

/// Signals filtered side by side in one vector instruction (two f64 in SSE2, every x86-64).
const LANES: usize = 2;

/// A zero-phase low-pass filter.
#[derive(Clone, Debug)]
pub struct LowPass {
    sections: [Biquad; 2],
}

impl LowPass {
    /// 4th-order Butterworth with cutoff `cutoff_hz` at `sample_hz` (cutoff clamped below
    /// Nyquist). Applied forward and backward, the magnitude is squared (8th order, -6 dB at
    /// the cutoff) and the phase is zero.
    pub fn butterworth4(cutoff_hz: f64, sample_hz: f64) -> Self {
        let fc = cutoff_hz.min(0.45 * sample_hz);
        let k = (std::f64::consts::PI * fc / sample_hz).tan();
        let sections = [0.765_366_864_730_179_9, 1.847_759_065_022_573_5] // 2 cos(pi/8), 2 cos(3pi/8)
            .map(|q| {
                let norm = 1.0 / (1.0 + q * k + k * k);
                let b0 = k * k * norm;
                Biquad {
                    b: [b0, 2.0 * b0, b0],
                    a: [2.0 * (k * k - 1.0) * norm, (1.0 - q * k + k * k) * norm],
                }
            });
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
        // interleaved layout: sample-major, the signals of a sample side by side in lanes of
        // LANES (the last lane group padded with zero signals, which stay zero); each end
        // extended by odd reflection
        let groups = k.div_ceil(LANES);
        let mut buf = vec![[0.0; LANES]; m * groups];
        for (j, x) in xs.iter().enumerate() {
            let (g, l) = (j / LANES, j % LANES);
            let at = |i: usize| i * groups + g;
            for i in 0..pad {
                buf[at(i)][l] = 2.0 * x[0] - x[pad - i];
            }
            for i in 0..n {
                buf[at(pad + i)][l] = x[i];
            }
            for i in 0..pad {
                buf[at(pad + n + i)][l] = 2.0 * x[n - 1] - x[n - 2 - i];
            }
        }
        // The sections run fused, sample by sample: the second section's recursion on one
        // sample overlaps the first's on the next (the same arithmetic, in the same order, as
        // one section after the other), and the lanes of a group are one vector instruction
        // (lane-wise IEEE arithmetic: bit for bit the scalar recursion). Each section starts
        // in the steady state of its first input sample.
        let [first, second] = &self.sections;
        let mut state = vec![[[[0.0; LANES]; 2]; 2]; groups];
        let start = |row: &mut [[f64; LANES]], state: &mut [[[[f64; LANES]; 2]; 2]]| {
            for (x, [s0, s1]) in row.iter_mut().zip(state.iter_mut()) {
                *s0 = first.steady_state_lanes(x);
                let y = first.step_lanes(s0, x);
                *s1 = second.steady_state_lanes(&y);
                *x = second.step_lanes(s1, &y);
            }
        };
        let run = |row: &mut [[f64; LANES]], state: &mut [[[[f64; LANES]; 2]; 2]]| {
            for (x, [s0, s1]) in row.iter_mut().zip(state.iter_mut()) {
                *x = second.step_lanes(s1, &first.step_lanes(s0, x));
            }
        };
        let mut rows = buf.chunks_exact_mut(groups);
        if let Some(row) = rows.next() {
            start(row, &mut state);
        }
        rows.for_each(|row| run(row, &mut state));
        let mut rows = buf.chunks_exact_mut(groups).rev();
        if let Some(row) = rows.next() {
            start(row, &mut state);
        }
        rows.for_each(|row| run(row, &mut state));
        (0..k)
            .map(|j| {
                let (g, l) = (j / LANES, j % LANES);
                (0..n).map(|i| buf[(pad + i) * groups + g][l]).collect()
            })
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

    /// The textbook recursion, one signal, one section after the other: the reference the
    /// fused, lane-wise filter must equal bit for bit.
    fn reference_filtfilt(f: &LowPass, x: &[f64]) -> Vec<f64> {
        let n = x.len();
        let pad = (n - 1).min(300);
        let mut y: Vec<f64> = (0..pad)
            .map(|i| 2.0 * x[0] - x[pad - i])
            .chain(x.iter().copied())
            .chain((0..pad).map(|i| 2.0 * x[n - 1] - x[n - 2 - i]))
            .collect();
        for backward in [false, true] {
            if backward {
                y.reverse();
            }
            for sec in &f.sections {
                let [b0, b1, b2] = sec.b;
                let [a1, a2] = sec.a;
                let [mut s1, mut s2] = sec.steady_state(y[0]);
                for v in y.iter_mut() {
                    let out = b0 * *v + s1;
                    (s1, s2) = (b1 * *v - a1 * out + s2, b2 * *v - a2 * out);
                    *v = out;
                }
            }
            if backward {
                y.reverse();
            }
        }
        y[pad..pad + n].to_vec()
    }

    #[test]
    fn lanes_and_fusion_change_no_bit() {
        let f = LowPass::butterworth4(20.0, 1000.0);
        let n = 2500;
        let xs: Vec<Vec<f64>> = (0..5)
            .map(|j| {
                (0..n)
                    .map(|i| {
                        let t = i as f64 * 1e-3;
                        let spike = if i % 97 == j { 3.0 } else { 0.0 };
                        (j as f64 + 1.0) * (7.0 * t + j as f64).sin() + spike
                    })
                    .collect()
            })
            .collect();
        // one, an odd number (a padded lane) and several signals at once
        for k in [1, 2, 3, 5] {
            let refs: Vec<&[f64]> = xs[..k].iter().map(|x| x.as_slice()).collect();
            for (j, y) in f.filtfilt_many(&refs).iter().enumerate() {
                let r = reference_filtfilt(&f, &xs[j]);
                assert!(
                    y.iter().zip(&r).all(|(a, b)| a.to_bits() == b.to_bits()),
                    "k = {k}, signal {j}"
                );
            }
        }
    }

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
