//! Zero-phase Butterworth low-pass filtering (forward-backward, as `filtfilt`).
//!
//! A 4th-order Butterworth is two biquads from the bilinear transform with pre-warping; each
//! pass starts in the steady state of its first input sample, and the signal is extended at
//! both ends by odd reflection so the edges do not ring.

use std::cell::Cell;

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

/// The most runs one pass filters side by side: a single signal's chunks
/// ([`Chunks::LANES_WANTED`]) or the signals of one half of [`LowPass::filtfilt_many`]'s
/// (at most `2 LANES`).
const MAX_RUNS: usize = Chunks::LANES_WANTED;

// `filtfilt_lockstep` hands a pass at most `2 LANES` signals
const _: () = assert!(2 * LANES <= MAX_RUNS);

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

    /// Samples after which a pass started in the wrong state has forgotten it: the slowest
    /// pole's transient `r^W` is below 1e-22 of the signal (far below f64's rounding), so a
    /// recursion started `W` samples early, in the steady state of its first input, joins the
    /// exact one within rounding. A biquad's complex pole pair has radius `sqrt(a2)`.
    fn memory_samples(&self) -> usize {
        let r = self
            .sections
            .iter()
            .map(|s| s.a[1].abs().sqrt())
            .fold(0.0f64, f64::max);
        if r <= 0.0 {
            return 1;
        }
        // an unstable or non-finite pole never forgets: no chunks
        if r.is_nan() || r >= 1.0 {
            return usize::MAX;
        }
        // a cascade of two sections: allow the polynomial factor of a repeated pole as well
        ((-22.0 * std::f64::consts::LN_10) / r.ln() * 1.2).ceil() as usize + 8
    }

    /// Zero-phase filtering of several signals of the same length at once. The recursions of
    /// different signals are independent, so running them in lock-step lets the CPU overlap
    /// them (one serial biquad chain per signal would leave it waiting on each result).
    ///
    /// A single long signal is cut into chunks that run side by side instead
    /// (`filtfilt_chunked`): within rounding of the one long recursion, not bit for
    /// bit, and 1.7x faster (measured on 60 000 samples, when the runs were copied). Two
    /// signals or more are each the one long recursion, bit for bit. More than two lane groups
    /// are filtered as two halves of whole groups, side by side where a rayon thread is idle
    /// (bit for bit the same; halves of one group each lost more overlap than they gained: 9.2 s
    /// of CPU against 8.6 s on a 60 s diagnosis).
    pub fn filtfilt_many(&self, xs: &[&[f64]]) -> Vec<Vec<f64>> {
        if let [x] = xs {
            let plan = Chunks::plan(x.len() + 2 * Self::padding(x.len()), self.memory_samples());
            if plan.count > 1 {
                return vec![self.filtfilt_chunked(x, &plan)];
            }
        }
        self.filtfilt_lockstep(xs)
    }

    /// Samples added at each end by odd reflection.
    fn padding(n: usize) -> usize {
        n.saturating_sub(1).min(300)
    }

    /// `x` extended by [`Self::padding`] samples at each end by odd reflection (so the edges
    /// do not ring); `x` has at least 3 samples.
    fn padded_vec(x: &[f64]) -> Vec<f64> {
        let (n, pad) = (x.len(), Self::padding(x.len()));
        let mut y = Vec::with_capacity(n + 2 * pad);
        y.extend((0..pad).map(|i| 2.0 * x[0] - x[pad - i]));
        y.extend_from_slice(x);
        y.extend((0..pad).map(|i| 2.0 * x[n - 1] - x[n - 2 - i]));
        y
    }

    /// The signal `y` padded by [`Self::padded_vec`] cut back to its `n` samples, in place.
    fn unpadded(mut y: Vec<f64>, n: usize) -> Vec<f64> {
        let pad = Self::padding(n);
        y.copy_within(pad..pad + n, 0);
        y.truncate(n);
        y
    }

    /// [`Self::filtfilt_many`] of one signal, cut into `plan.count` runs in lock-step: every
    /// run but the first starts [`Self::memory_samples`] early in the steady state of its
    /// first input and keeps only what follows, where it equals the one long recursion
    /// within rounding (the first run is that recursion, bit for bit).
    ///
    /// The runs are overlapping views of the one padded signal, filtered in place: at row `i`
    /// run `c` reads its `i`-th sample and writes it back only where it keeps it
    /// ([`Chunks::skipped`]). A sample run `c` keeps lies beyond the end of every earlier run
    /// and no later run reads it after row `i`, so every run reads the pass's input, as when
    /// each run was copied into a buffer of its own and back (which cost more than the
    /// filtering: 0.53 against 0.28 ms on 60 000 samples, `filter_timing`).
    fn filtfilt_chunked(&self, x: &[f64], plan: &Chunks) -> Vec<f64> {
        let mut y = Self::padded_vec(x);
        {
            // overlapping views of one buffer, written through shared cells
            let cells = Cell::from_mut(y.as_mut_slice()).as_slice_of_cells();
            let skipped: Vec<usize> = (0..plan.count).map(|c| plan.skipped(c)).collect();
            for backward in [false, true] {
                let runs: Vec<&[Cell<f64>]> = (0..plan.count)
                    .map(|c| &cells[plan.stretch(c, backward)])
                    .collect();
                self.pass(&runs, &skipped, backward);
            }
        }
        Self::unpadded(y, x.len())
    }

    /// One pass of the fused sections over runs of equal length in lock-step, in place:
    /// forward, or from each run's last sample to its first; run `c` writes back its samples
    /// from row `skipped[c]` on. `LANES` runs share one vector instruction (lane-wise IEEE
    /// arithmetic: bit for bit the scalar recursion), and the second section's recursion on one
    /// sample overlaps the first's on the next (the same arithmetic, in the same order, as one
    /// section after the other). Each section starts in the steady state of its run's first
    /// input sample. A run is only read at a row before it is written there, so runs may
    /// overlap where none reads what another kept (see [`Self::filtfilt_chunked`]).
    fn pass(&self, runs: &[&[Cell<f64>]], skipped: &[usize], backward: bool) {
        let Some(len) = runs.first().map(|r| r.len()) else {
            return;
        };
        // both callers keep to this by construction (`Chunks::plan` makes at most MAX_RUNS
        // runs of one length; `filtfilt_lockstep` halves more than 2 LANES signals of one
        // length): a breach is a bug, never a signal left silently unfiltered
        assert!(
            runs.len() <= MAX_RUNS && skipped.len() >= runs.len(),
            "{} runs",
            runs.len()
        );
        assert!(
            runs.iter().all(|r| r.len() == len),
            "runs of unequal length"
        );
        // fixed-size tables (a lane without a run is an empty one, which reads zeros that
        // stay zero): the compiler keeps the loop in registers, as it did not over slices
        let (count, groups) = (runs.len(), runs.len().div_ceil(LANES));
        let mut lane: [&[Cell<f64>]; MAX_RUNS] = [&[]; MAX_RUNS];
        lane[..count].copy_from_slice(runs);
        let mut keep_from = [usize::MAX; MAX_RUNS];
        keep_from[..count].copy_from_slice(&skipped[..count]);
        let [first, second] = &self.sections;
        let mut state = [[[[0.0; LANES]; 2]; 2]; MAX_RUNS.div_ceil(LANES)];
        for i in 0..len {
            let at = if backward { len - 1 - i } else { i };
            for (g, [s0, s1]) in state.iter_mut().enumerate().take(groups) {
                let mut x = [0.0; LANES];
                for (l, x) in x.iter_mut().enumerate() {
                    if let Some(v) = lane[g * LANES + l].get(at) {
                        *x = v.get();
                    }
                }
                if i == 0 {
                    *s0 = first.steady_state_lanes(&x);
                }
                let y = first.step_lanes(s0, &x);
                if i == 0 {
                    *s1 = second.steady_state_lanes(&y);
                }
                let out = second.step_lanes(s1, &y);
                for (l, v) in out.iter().enumerate() {
                    if i >= keep_from[g * LANES + l] {
                        lane[g * LANES + l][at].set(*v);
                    }
                }
            }
        }
    }

    /// [`Self::filtfilt_many`] with every signal one lane, each filtered in place in its own
    /// padded copy.
    fn filtfilt_lockstep(&self, xs: &[&[f64]]) -> Vec<Vec<f64>> {
        let k = xs.len();
        let n = xs.first().map_or(0, |x| x.len());
        if xs.iter().any(|x| x.len() != n) {
            return xs.iter().map(|x| self.filtfilt(x)).collect();
        }
        if n < 3 {
            return xs.iter().map(|x| x.to_vec()).collect();
        }
        // lanes never mix: two halves of whole lane groups side by side where a thread is
        // idle give the same numbers bit for bit
        if k > 2 * LANES {
            let h = k.div_ceil(2 * LANES) * LANES;
            let (mut a, b) = rayon::join(
                || self.filtfilt_lockstep(&xs[..h]),
                || self.filtfilt_lockstep(&xs[h..]),
            );
            a.extend(b);
            return a;
        }
        let mut ys: Vec<Vec<f64>> = xs.iter().map(|x| Self::padded_vec(x)).collect();
        {
            let runs: Vec<&[Cell<f64>]> = ys
                .iter_mut()
                .map(|y| Cell::from_mut(y.as_mut_slice()).as_slice_of_cells())
                .collect();
            let skipped = vec![0; k];
            for backward in [false, true] {
                self.pass(&runs, &skipped, backward);
            }
        }
        ys.into_iter().map(|y| Self::unpadded(y, n)).collect()
    }

    /// The rms a white noise of unit variance keeps through the zero-phase filter: the norm
    /// `||h||_2 = sqrt(sum h_k^2)` of its impulse response (about `sqrt(0.90 fc / (fs / 2))`
    /// where the cutoff is well below Nyquist). A white noise `sigma` reads `sigma ||h||_2` in
    /// the band.
    pub fn noise_gain(&self) -> f64 {
        let memory = self.memory_samples().min(1 << 20);
        let mut impulse = vec![0.0; 4 * memory + 1];
        impulse[2 * memory] = 1.0;
        self.filtfilt(&impulse)
            .iter()
            .map(|h| h * h)
            .sum::<f64>()
            .sqrt()
    }

    /// Zero-phase filtering of `x` (returns a new vector of the same length).
    pub fn filtfilt(&self, x: &[f64]) -> Vec<f64> {
        self.filtfilt_many(&[x]).pop().unwrap_or_default()
    }
}

/// How a pass cuts each signal of `m` samples into `count` runs of `run_len` samples that
/// cover it: run 0 starts at 0 and keeps all it computes; every later run starts `memory`
/// samples before the part it keeps (the last one earlier still: it ends at the signal's end).
#[derive(Clone, Copy, Debug)]
struct Chunks {
    count: usize,
    run_len: usize,
    memory: usize,
    m: usize,
}

impl Chunks {
    /// Runs in flight that keep the CPU's pipelines busy (measured on one signal of 60 000
    /// samples when the runs were still copied into a buffer of their own: 6 runs 0.47 ms
    /// against 0.81 ms for the one long recursion; 4 or 8 runs 0.51 ms). Changing it moves the
    /// runs' seams, and so the filtered numbers by rounding.
    const LANES_WANTED: usize = 6;

    fn plan(m: usize, memory: usize) -> Self {
        let one = Self {
            count: 1,
            run_len: m,
            memory: 0,
            m,
        };
        // each run keeps at least three times what it spends on forgetting its start
        let affordable = m / memory.saturating_mul(4).max(1);
        let count = Self::LANES_WANTED.min(affordable);
        if count < 2 {
            return one;
        }
        Self {
            count,
            // count runs of L overlapping by `memory`: count L - (count - 1) memory >= m
            run_len: (m + (count - 1) * memory).div_ceil(count),
            memory,
            m,
        }
    }

    /// Where run `c` starts in the signal.
    fn run_start(&self, c: usize) -> usize {
        if c + 1 == self.count {
            self.m - self.run_len
        } else {
            c * (self.run_len - self.memory)
        }
    }

    /// The samples run `c` covers in a pass: forward from [`Self::run_start`], or in a backward
    /// pass (over the reversed signal) the mirrored stretch, which the run reads from its end.
    fn stretch(&self, c: usize, backward: bool) -> std::ops::Range<usize> {
        let a = self.run_start(c);
        if backward {
            self.m - a - self.run_len..self.m - a
        } else {
            a..a + self.run_len
        }
    }

    /// How many of run `c`'s first samples it does not keep: up to where the previous run's
    /// kept part ended.
    fn skipped(&self, c: usize) -> usize {
        if c == 0 {
            0
        } else {
            self.run_start(c - 1) + self.run_len - self.run_start(c)
        }
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
            textbook_pass(f, &mut y);
            if backward {
                y.reverse();
            }
        }
        y[pad..pad + n].to_vec()
    }

    /// One forward pass of the sections over `y`, one section after the other, each started in
    /// the steady state of its first input, in place: the textbook recursion.
    fn textbook_pass(f: &LowPass, y: &mut [f64]) {
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
    }

    /// The noise gain against Parseval on the filter's frequency response: the bilinear
    /// Butterworth's `|H|^2 = 1 / (1 + (tan(w / 2) / tan(wc / 2))^8)`, squared by the two passes,
    /// so `||h||^2 = (1 / pi) int_0^pi |H|^4 dw`.
    #[test]
    fn noise_gain_is_the_impulse_response_norm() {
        for (fc, fs) in [(20.0, 1000.0), (20.0, 250.0), (5.0, 100.0), (100.0, 1000.0)] {
            let k = (std::f64::consts::PI * fc / fs).tan();
            let steps = 200_000;
            let dw = std::f64::consts::PI / steps as f64;
            let power: f64 = (0..steps)
                .map(|i| {
                    let w = (i as f64 + 0.5) * dw;
                    let h2 = 1.0 / (1.0 + ((w / 2.0).tan() / k).powi(8));
                    h2 * h2 * dw
                })
                .sum::<f64>()
                / std::f64::consts::PI;
            let gain = LowPass::butterworth4(fc, fs).noise_gain();
            assert!(
                (gain / power.sqrt() - 1.0).abs() < 1e-4,
                "{fc} Hz at {fs} Hz: {gain} against {}",
                power.sqrt()
            );
        }
    }

    #[test]
    fn lanes_and_fusion_change_no_bit() {
        let f = LowPass::butterworth4(20.0, 1000.0);
        let n = 2500;
        let xs: Vec<Vec<f64>> = (0..8)
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
        // one, an odd number (a padded lane) and several signals at once (five and eight:
        // two halves of whole lane groups, side by side)
        for k in [1, 2, 3, 5, 8] {
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
    fn chunks_cover_every_sample_once_after_forgetting_their_start() {
        for memory in [1, 50, 1272] {
            for m in [4 * memory + 1, 6000, 60_601, 123_457] {
                let plan = Chunks::plan(m, memory);
                assert!(plan.count >= 1 && plan.count <= Chunks::LANES_WANTED);
                let mut next = 0;
                for c in 0..plan.count {
                    let start = plan.run_start(c);
                    assert!(
                        start + plan.run_len <= m,
                        "run {c} of {m} leaves the signal"
                    );
                    let kept_from = start + plan.skipped(c);
                    assert_eq!(kept_from, next, "m {m}, run {c}: a gap or an overlap");
                    if c > 0 {
                        assert!(plan.skipped(c) >= memory, "run {c} keeps samples too early");
                    }
                    next = start + plan.run_len;
                }
                assert_eq!(next, m, "m {m}: the runs end before the signal");
            }
        }
    }

    /// `n` samples at 1 kHz of steps between 400 and -250 every `step_every` samples, a ramp
    /// and a sine.
    fn steps_ramp_and_sine(n: usize, step_every: usize) -> Vec<f64> {
        (0..n)
            .map(|i| {
                let t = i as f64 * 1e-3;
                let step = if (i / step_every) % 2 == 0 {
                    400.0
                } else {
                    -250.0
                };
                step + 30.0 * (11.0 * t).sin() + 5.0 * t
            })
            .collect()
    }

    #[test]
    fn a_chunked_signal_is_the_long_recursion_within_rounding() {
        let f = LowPass::butterworth4(20.0, 1000.0);
        let n = 60_000;
        // a state error at a run's start would show for ~1000 samples
        let x = steps_ramp_and_sine(n, 7000);
        let plan = Chunks::plan(n + 2 * LowPass::padding(n), f.memory_samples());
        assert!(plan.count > 1, "the test must exercise the chunks");
        let r = reference_filtfilt(&f, &x);
        let scale = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let off_reference = |y: &[f64]| {
            y.iter()
                .zip(&r)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max)
        };
        let worst = off_reference(&f.filtfilt(&x));
        assert!(
            worst < 1e-12 * scale,
            "chunked filter off by {worst:e} of {scale}"
        );
        // the memory is what makes it right: runs that start 10 samples early are visibly off
        let careless = Chunks::plan(n + 2 * LowPass::padding(n), 10);
        let worst = off_reference(&f.filtfilt_chunked(&x, &careless));
        assert!(
            worst > 1e-3 * scale,
            "a 10-sample memory should show: {worst:e}"
        );
    }

    /// Each run of a chunked pass filtered alone, in a copy of its own, by the textbook
    /// recursion, and its kept part stitched in: what the in-place runs must equal bit for
    /// bit (each must read the pass's input, never a sample another run already wrote).
    fn runs_filtered_alone(f: &LowPass, x: &[f64], plan: &Chunks) -> Vec<f64> {
        let len = plan.run_len;
        let mut y = LowPass::padded_vec(x);
        for backward in [false, true] {
            let mut next = y.clone();
            for c in 0..plan.count {
                let stretch = plan.stretch(c, backward);
                let mut run = y[stretch.clone()].to_vec();
                if backward {
                    run.reverse();
                }
                textbook_pass(f, &mut run);
                if backward {
                    run.reverse();
                }
                let kept = plan.skipped(c)..len;
                if backward {
                    // mirrored: the kept part is the stretch's beginning
                    let keep = len - plan.skipped(c);
                    next[stretch.start..stretch.start + keep].copy_from_slice(&run[..keep]);
                } else {
                    next[stretch.start + kept.start..stretch.end].copy_from_slice(&run[kept]);
                }
            }
            y = next;
        }
        LowPass::unpadded(y, x.len())
    }

    #[test]
    fn chunks_filtered_in_place_are_each_run_filtered_alone_bit_for_bit() {
        let f = LowPass::butterworth4(20.0, 1000.0);
        for n in [12_000, 60_000, 123_457] {
            // steps every 3 s, so that a run that read another's output cannot go unnoticed
            let x = steps_ramp_and_sine(n, 3001);
            let m = n + 2 * LowPass::padding(n);
            for plan in [Chunks::plan(m, f.memory_samples()), Chunks::plan(m, 10)] {
                assert!(plan.count > 1, "n {n}: the test must exercise the chunks");
                let alone = runs_filtered_alone(&f, &x, &plan);
                let in_place = f.filtfilt_chunked(&x, &plan);
                assert!(
                    in_place
                        .iter()
                        .zip(&alone)
                        .all(|(a, b)| a.to_bits() == b.to_bits()),
                    "n {n}, {} runs",
                    plan.count
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
