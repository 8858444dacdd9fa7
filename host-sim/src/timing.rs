//! Logger timing: what a rig's software-timed logger writes, made usable.
//!
//! Rig loggers do not sample on a uniform grid: intervals jitter (10..17 ms at a nominal
//! 100 Hz), some records run at about 60 Hz, and the logger stalls now and then (gaps of a few
//! hundred milliseconds). The diagnosis filters and differentiates on a uniform grid, so a record
//! is made uniform here, by a stated method:
//!
//! 1. **Segments.** An interval longer than [`GAP_PERIODS`] median intervals is a gap: the
//!    record is split there and nothing is interpolated across it. Each segment is filtered,
//!    differentiated and simulated on its own (the friction state restarts at its first sample).
//!    Segments shorter than [`MIN_SEGMENT_SAMPLES`] are dropped.
//! 2. **Grid.** The grid period `h` is the median interval rounded to three significant digits;
//!    every segment is resampled onto `t_start + k h` by linear interpolation of every column
//!    (position, force, pressures, temperature, extras). Records whose intervals already lie
//!    within 5 % of the median are left sample for sample as they are.
//!
//! Refused, because nothing can repair them: time that does not increase (the reader refuses it
//! with file and line), a sample rate below [`MIN_RATE_HZ`] (too slow to see a reversal), and a
//! record whose segments are all too short.

use crate::error::{DataProblem, Error, Result};
use crate::record::Record;
use std::ops::Range;

/// An interval longer than this many median intervals splits the record.
pub const GAP_PERIODS: f64 = 5.0;
/// Segments shorter than this are dropped \[samples\].
pub const MIN_SEGMENT_SAMPLES: usize = 50;
/// Slowest sample rate accepted \[Hz\].
pub const MIN_RATE_HZ: f64 = 20.0;
/// Intervals within this fraction of the median count as regular.
const REGULAR_TOLERANCE: f64 = 0.05;

/// A record on a uniform grid, in segments.
#[derive(Clone, Debug)]
pub struct Uniform {
    /// The samples (time stamps jump between segments; uniform within each).
    pub record: Record,
    /// Grid period \[s\].
    pub period_s: f64,
    /// The segments, as index ranges into `record`.
    pub segments: Vec<Range<usize>>,
    /// What was done, in words (empty when the record was already uniform and whole).
    pub notes: Vec<String>,
}

/// Makes a record uniform (see the module docs); `name` is used in messages.
pub fn uniform(rec: &Record, name: &str) -> Result<Uniform> {
    let n = rec.len();
    if n < 2 {
        return Err(Error::data(name, DataProblem::TooFewSamples(n)));
    }
    let intervals: Vec<f64> = rec.t.windows(2).map(|w| w[1] - w[0]).collect();
    if let Some(i) = intervals.iter().position(|d| d.is_nan() || *d <= 0.0) {
        return Err(Error::data(
            name,
            DataProblem::TimeNotIncreasing {
                sample: i + 2,
                t_s: rec.t[i + 1],
                previous_s: rec.t[i],
            },
        ));
    }
    let median = crate::stats::median(&intervals);
    if 1.0 / median < MIN_RATE_HZ {
        return Err(Error::data(
            name,
            DataProblem::TooSlow {
                median_interval_s: median,
            },
        ));
    }
    // split at gaps
    let mut raw: Vec<Range<usize>> = Vec::new();
    let mut start = 0;
    let mut gaps = Vec::new();
    for (i, d) in intervals.iter().enumerate() {
        if *d > GAP_PERIODS * median {
            raw.push(start..i + 1);
            gaps.push(*d);
            start = i + 1;
        }
    }
    raw.push(start..n);
    let dropped: usize = raw
        .iter()
        .filter(|r| r.len() < MIN_SEGMENT_SAMPLES)
        .map(|r| r.len())
        .sum();
    let kept: Vec<Range<usize>> = raw
        .into_iter()
        .filter(|r| r.len() >= MIN_SEGMENT_SAMPLES)
        .collect();
    if kept.is_empty() {
        return Err(Error::data(name, DataProblem::OnlyShortSegments));
    }
    let regular = intervals
        .iter()
        .all(|d| (d - median).abs() <= REGULAR_TOLERANCE * median || *d > GAP_PERIODS * median);
    let mut notes = Vec::new();
    if !regular {
        let (lo, hi) = intervals
            .iter()
            .filter(|d| **d <= GAP_PERIODS * median)
            .fold((f64::INFINITY, 0.0f64), |(l, h), d| (l.min(*d), h.max(*d)));
        notes.push(format!(
            "sampling is irregular (intervals {}..{}, median {}): resampled onto a uniform {} grid by linear interpolation",
            seconds(lo),
            seconds(hi),
            seconds(median),
            seconds(round3(median))
        ));
    }
    if !gaps.is_empty() {
        notes.push(format!(
            "{} logger gap{} longer than {} (longest {}) split the record into {} segments; nothing is interpolated across a gap",
            gaps.len(),
            if gaps.len() == 1 { "" } else { "s" },
            seconds(GAP_PERIODS * median),
            seconds(gaps.iter().cloned().fold(0.0, f64::max)),
            gaps.len() + 1
        ));
    }
    if dropped > 0 {
        notes.push(format!(
            "{dropped} samples in stretches shorter than {MIN_SEGMENT_SAMPLES} samples between gaps were left out"
        ));
    }
    if regular && kept.len() == 1 && kept[0] == (0..n) {
        return Ok(Uniform {
            record: rec.clone(),
            period_s: median,
            segments: kept,
            notes,
        });
    }
    let h = if regular { median } else { round3(median) };
    let mut out = Record {
        meta: rec.meta.clone(),
        ..Default::default()
    };
    let opt = |c: &Option<Vec<f64>>| c.as_ref().map(|_| Vec::new());
    out.v = opt(&rec.v);
    out.x_ref = opt(&rec.x_ref);
    out.p_a = opt(&rec.p_a);
    out.p_b = opt(&rec.p_b);
    out.temp = opt(&rec.temp);
    out.extra = rec
        .extra
        .iter()
        .map(|(k, _)| (k.clone(), Vec::new()))
        .collect();
    let mut segments = Vec::new();
    for r in &kept {
        let first = out.t.len();
        if regular {
            push_range(&mut out, rec, r.clone());
        } else {
            let t0 = rec.t[r.start];
            let t1 = rec.t[r.end - 1];
            let m = ((t1 - t0) / h).floor() as usize + 1;
            if m < MIN_SEGMENT_SAMPLES {
                continue;
            }
            let mut j = r.start;
            for k in 0..m {
                let t = t0 + k as f64 * h;
                while j + 2 < r.end && rec.t[j + 1] <= t {
                    j += 1;
                }
                let w = ((t - rec.t[j]) / (rec.t[j + 1] - rec.t[j])).clamp(0.0, 1.0);
                push_interpolated(&mut out, rec, j, w, t);
            }
        }
        segments.push(first..out.t.len());
    }
    Ok(Uniform {
        record: out,
        period_s: h,
        segments,
        notes,
    })
}

fn each_column(out: &mut Record, rec: &Record, mut f: impl FnMut(&mut Vec<f64>, &[f64])) {
    f(&mut out.x, &rec.x);
    f(&mut out.force, &rec.force);
    for (o, s) in [
        (&mut out.v, &rec.v),
        (&mut out.x_ref, &rec.x_ref),
        (&mut out.p_a, &rec.p_a),
        (&mut out.p_b, &rec.p_b),
        (&mut out.temp, &rec.temp),
    ] {
        if let (Some(o), Some(s)) = (o.as_mut(), s.as_ref()) {
            f(o, s);
        }
    }
    for ((_, o), (_, s)) in out.extra.iter_mut().zip(&rec.extra) {
        f(o, s);
    }
}

fn push_range(out: &mut Record, rec: &Record, r: Range<usize>) {
    out.t.extend_from_slice(&rec.t[r.clone()]);
    each_column(out, rec, |o, s| o.extend_from_slice(&s[r.clone()]));
}

fn push_interpolated(out: &mut Record, rec: &Record, j: usize, w: f64, t: f64) {
    out.t.push(t);
    each_column(out, rec, |o, s| o.push(s[j] + w * (s[j + 1] - s[j])));
}

/// `x` rounded to three significant digits.
fn round3(x: f64) -> f64 {
    if !(x.is_finite() && x > 0.0) {
        return x;
    }
    let e = 10f64.powi(x.log10().floor() as i32 - 2);
    (x / e).round() * e
}

/// A duration for people: "10 ms", "0.31 s", "125 us" (three significant digits, no float
/// noise such as 0.009999999999999787).
pub fn seconds(s: f64) -> String {
    if !s.is_finite() {
        return format!("{s} s");
    }
    let a = s.abs();
    let (v, unit) = if a >= 1.0 || a == 0.0 {
        (s, "s")
    } else if a >= 1e-3 {
        (s * 1e3, "ms")
    } else {
        (s * 1e6, "us")
    };
    format!("{} {unit}", sig3(v))
}

/// A frequency for people: "100 Hz", "59.9 Hz".
pub fn hz(f: f64) -> String {
    format!("{} Hz", sig3(f))
}

/// `v` with `digits` significant digits, for people: in plain decimals from 1e-3 to 1e5
/// ("0.7203", "-9.5", "1147"), in exponent form outside ("2.519e10", "1e-5"), without
/// trailing zeros either way; 0 as "0", a value that is not finite as Rust writes it.
pub fn number(v: f64, digits: usize) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let digits = digits.max(1);
    // rounding can carry a value over a power of ten (99999.9 -> 1.000e5): judged as written
    let exp = format!("{v:.*e}", digits - 1);
    let power: i32 = exp
        .split_once('e')
        .map_or(0, |(_, p)| p.parse().unwrap_or(0));
    if (-3..5).contains(&power) {
        // the value as rounded to its digits, written with as many decimals as they reach
        let rounded: f64 = exp.parse().unwrap_or(v);
        let decimals = (digits as i32 - 1 - power).max(0) as usize;
        without_trailing_zeros(format!("{rounded:.decimals$}"))
    } else {
        let (mantissa, power) = exp.split_once('e').unwrap_or((&exp, "0"));
        format!("{}e{power}", without_trailing_zeros(mantissa.to_string()))
    }
}

/// Three significant digits without trailing zeros.
pub fn sig3(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let digits = (2 - v.abs().log10().floor() as i32).max(0) as usize;
    without_trailing_zeros(format!("{v:.digits$}"))
}

/// A decimal number's text without the zeros after its last significant decimal ("4.500" ->
/// "4.5", "4.000" -> "4"); a text without a decimal point as it is.
fn without_trailing_zeros(s: String) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Plain decimals from 1e-3 to 1e5, exponent form outside, trailing zeros dropped, and a
    /// rounding that carries over a power of ten written in the form of its result.
    #[test]
    fn numbers_for_people() {
        assert_eq!(number(0.72032, 5), "0.72032");
        assert_eq!(number(0.720321, 4), "0.7203");
        assert_eq!(number(-0.95, 5), "-0.95");
        assert_eq!(number(4.0, 5), "4");
        assert_eq!(number(1147.26, 4), "1147");
        assert_eq!(number(1147.26, 3), "1150");
        assert_eq!(number(-2.519e10, 4), "-2.519e10");
        assert_eq!(number(1e-5, 5), "1e-5");
        assert_eq!(number(1.0e-3, 3), "0.001");
        assert_eq!(number(99999.96, 4), "1e5");
        assert_eq!(number(0.00099996, 4), "0.001");
        assert_eq!(number(0.0, 4), "0");
        assert_eq!(number(f64::NAN, 4), "NaN");
        assert_eq!(number(123.0, 0), "100");
    }

    fn jittered(n: usize, seed: u64) -> Record {
        // a logger at a nominal 100 Hz: intervals 10..17 ms, one 0.3 s stall
        let mut s = seed;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut t = 0.0;
        let mut rec = Record::default();
        for i in 0..n {
            rec.t.push(t);
            rec.x.push(0.01 * (t * 2.0).sin());
            rec.force.push(3.0 * t);
            t += if i == n / 2 {
                0.3
            } else {
                0.010 + 0.007 * rnd()
            };
        }
        rec
    }

    #[test]
    fn jittered_logger_is_resampled_and_split_at_the_stall() {
        let rec = jittered(2000, 7);
        let u = uniform(&rec, "rig.csv").unwrap();
        assert_eq!(u.segments.len(), 2, "{:?}", u.notes);
        for r in &u.segments {
            for w in u.record.t[r.clone()].windows(2) {
                assert!(((w[1] - w[0]) - u.period_s).abs() < 1e-9);
            }
        }
        // nothing interpolated across the stall: the segments are 0.3 s apart
        let gap = u.record.t[u.segments[1].start] - u.record.t[u.segments[0].end - 1];
        assert!(gap > 0.25, "gap {gap}");
        // linear columns are reproduced exactly by linear interpolation
        for (t, f) in u.record.t.iter().zip(&u.record.force) {
            assert!((f - 3.0 * t).abs() < 1e-9);
        }
        assert!(u.notes.iter().any(|n| n.contains("resampled")));
        assert!(u
            .notes
            .iter()
            .any(|n| n.contains("split the record into 2 segments")));
        assert!(
            !u.notes.iter().any(|n| n.contains("0.0099999")),
            "{:?}",
            u.notes
        );
    }

    #[test]
    fn regular_records_pass_unchanged() {
        let mut rec = Record::default();
        for i in 0..1000 {
            rec.t.push(i as f64 * 1e-3);
            rec.x.push(0.0);
            rec.force.push(0.0);
        }
        let u = uniform(&rec, "r").unwrap();
        assert_eq!(u.record, rec);
        assert!(u.notes.is_empty());
        assert_eq!(u.segments, vec![0..1000]);
    }

    #[test]
    fn too_slow_records_are_refused_with_a_readable_rate() {
        let mut rec = Record::default();
        for i in 0..100 {
            rec.t.push(i as f64 * 0.1);
            rec.x.push(0.0);
            rec.force.push(0.0);
        }
        let e = uniform(&rec, "slow.csv").unwrap_err().to_string();
        assert!(
            e.contains("slow.csv") && e.contains("10 Hz") && e.contains("100 ms"),
            "{e}"
        );
    }

    #[test]
    fn numbers_are_formatted_for_people() {
        assert_eq!(seconds(0.009999999999999787), "10 ms");
        assert_eq!(seconds(0.3), "300 ms");
        assert_eq!(seconds(1.25), "1.25 s");
        assert_eq!(seconds(125e-6), "125 us");
        assert_eq!(hz(59.94), "59.9 Hz");
    }
}
