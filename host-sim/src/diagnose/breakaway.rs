//! Evidence beyond sliding: departures from rest, their breakaway peaks and the force that held
//! the axis while it rested.
//!
//! Sliding samples cannot tell some effects apart or reveal them at all. Dwell stiction only
//! acts at the moment the axis breaks away after a rest; asymmetry and an offset are nearly
//! collinear while the axis slides. The events where the axis leaves a rest carry that
//! evidence:
//!
//! - a **departure** is the end of a rest: the speed averaged over [`REST_SPEED_WINDOW_S`]
//!   stayed below [`STUCK_SPEED`] for at least [`MIN_REST_S`], then the axis moves off in
//!   direction `d` (averaged, because a resting axis still creeps by encoder counts: soft seals
//!   deflect tens of micrometres before they slide, and each count is a spike of the filtered
//!   velocity);
//! - its **breakaway peak** is `max d F(t)` over `[end - PRE_S, end + POST_S]` (the force in the
//!   scores' band, so a model's peak is read from its filtered prediction the same way);
//! - its **holding force** is the mean force over the rest.
//!
//! Two uses:
//! 1. Every candidate is also scored on the peaks: with `r_e` the measured minus the model's
//!    peak at departure `e` and `n` departures, `dBIC_peaks = n ln(RSS_current / RSS_candidate)`
//!    (one independent sample per departure) is added to the candidate's sliding dBIC.
//!    `dwell_stiction` must in addition grow with the rest time ([`DWELL_MIN_GROWTH_DBIC`]),
//!    or, since session 92, the model must leave more than the measurement accounts for (a
//!    level every rest saturates, `ranking::judge`), and it is not tested on a record with too
//!    few departures or rest times that hardly vary ([`MIN_DEPARTURES`], [`MIN_REST_SPAN`]):
//!    there the record cannot reveal it.
//! 2. A model-free trend for the report: the peaks per direction against the rest time,
//!    `peak = b_d + c_a a + c_v v + dF (1 - exp(-t_rest / tau))`, least squares for
//!    `(b_+, b_-, c_a, c_v, dF)` at each `tau` of a log grid, `dBIC = n ln(RSS_0 / RSS_1) -
//!    2 ln n` against `peak = b_d + c_a a + c_v v`. `a` and `v` are the departure's largest
//!    acceleration and speed ([`Departure::kinematics`]): a peak also carries the inertial
//!    force of the start and the sliding friction at the speed reached, and where hard starts
//!    follow long rests (a dwell before a fast move, a sinusoid's reversals the short rests)
//!    they grow with the rest on a record without dwell stiction.

use super::inverse::{Prepared, STUCK_SPEED};
use serde::Serialize;

/// The rest test's speed is the position change over this window \[s\].
pub const REST_SPEED_WINDOW_S: f64 = 0.02;
/// Shortest rest that counts \[s\].
pub const MIN_REST_S: f64 = 0.02;
/// The breakaway window starts this long before the rest ends \[s\] (the force ramps while the
/// bristles deflect below the encoder's resolution).
pub const PRE_S: f64 = 0.05;
/// The breakaway window ends this long after the rest ends \[s\] (or where the next rest starts).
pub const POST_S: f64 = 0.15;
/// A departure needs the axis to reach this speed within the window [m/s].
pub const DEPARTURE_SPEED: f64 = 5.0 * STUCK_SPEED;
/// Fewest departures on which `dwell_stiction` is tested (and the peaks count in every
/// candidate's evidence). 6 until session 81: of ~820 used records of the independent
/// generator 7 had 5, two of them dwell records whose term was then untested (both named at
/// 5) and none an effect-free record whose dwell term came near the cut
/// (`docs/registrations/s81/prereg.txt`).
pub const MIN_DEPARTURES: usize = 5;
/// Fewest departures on which the dwell trend weighs the departures' kinematics: two more
/// columns leave it at least five degrees of freedom.
pub const MIN_DEPARTURES_KINEMATICS: usize = 10;

/// Longest rest over shortest rest needed to test `dwell_stiction` (its force grows with the
/// rest time: with rests of one length there is nothing to compare).
pub const MIN_REST_SPAN: f64 = 4.0;
/// Growth with the rest time is shown where the fitted dwell term beats the same term with
/// every rest counted as long (time constant [`REST_INDEPENDENT_TAU_S`]: a breakaway level of
/// its own, whatever the rest) by at least this evidence (sliding dBIC plus the peaks'); it then
/// has to cut the current model's error by the decision's cut (`DWELL_MIN_ERROR_CUT`; until
/// session 80 the twin's error). A term whose growth is not shown is a level every rest of the
/// record saturates: until session 92 it was never significant; since then it is judged as
/// every effect is where the current model leaves more than the measurement accounts for
/// (`ranking::judge`), and held elsewhere, where the level at the departures can be the
/// reading's.
pub const DWELL_MIN_GROWTH_DBIC: f64 = 2.0;

/// The model-free trend of the peaks ([`DwellTrend`]) counts as growth with the rest time at
/// this evidence, for a growth above zero ([`DwellTrend::shows_growth`]). Shown in the output
/// and the report; until session 24 it gated `dwell_stiction` (with the trend of the peaks the
/// current model left unexplained): the model's bristle then carried a stale deflection
/// through every rest, and a dwell term absorbed that on effect-free records. With the bristle
/// carrying the measured holding force at rest the model-based test holds on its own, and the
/// trend, which failed on 15 of 40 calibration dwell records, no longer decides.
pub const DWELL_MIN_TREND_DBIC: f64 = 2.0;

/// The time constant of the rest-independent breakaway level [`DWELL_MIN_GROWTH_DBIC`] tests
/// against \[s\]: every rest a departure can follow (at least [`MIN_REST_S`]) reaches 95 % of
/// its level, while the few milliseconds a reversal spends under the stick speed do not
/// (until session 24 1 ms, which raised the level at every reversal too).
pub const REST_INDEPENDENT_TAU_S: f64 = MIN_REST_S / 3.0;

/// One departure from rest.
#[derive(Clone, Debug, Serialize)]
pub struct Departure {
    /// Sample where the rest ended.
    pub index: usize,
    /// Time where the rest ended \[s\].
    pub time_s: f64,
    /// How long the axis rested before it \[s\].
    pub rest_s: f64,
    /// Direction of the motion that followed (+1 or -1).
    pub direction: f64,
    /// Breakaway peak of the measured force, signed (`d max d F`) \[N\].
    pub peak_n: f64,
    /// Mean measured force over the rest \[N\].
    pub holding_n: f64,
    /// The departure's kinematics over the window, in its direction: the largest
    /// acceleration \[m/s^2\] and speed \[m/s\] (filtered like the force). The dwell trend
    /// weighs them as nuisances: a peak carries the inertial force of the start and the
    /// sliding friction at the speed reached, whatever the rest before it.
    pub kinematics: [f64; 2],
    /// Samples the peak is read over (`[end - PRE_S, end + POST_S]`, cut at the next rest):
    /// a model's peak is read over the same ones.
    #[serde(skip)]
    pub window: std::ops::Range<usize>,
}

/// The departures of a record and what their peaks say on their own.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Breakaway {
    /// Every departure, in time order.
    pub departures: Vec<Departure>,
    /// The model-free dwell trend of the peaks, when there are enough departures.
    pub trend: Option<DwellTrend>,
    /// Why `dwell_stiction` cannot be tested on this record, if it cannot.
    pub untestable: Option<String>,
    /// The evidence is not used (an ablation: [`super::Options::ignore_breakaway`]).
    #[serde(skip)]
    pub ignored: bool,
}

/// Breakaway peaks against the rest time before them.
#[derive(Clone, Debug, Serialize)]
pub struct DwellTrend {
    /// Peak level after a short rest, forward and backward (magnitudes) \[N\].
    pub level_n: [f64; 2],
    /// Growth of the peak from a short to a long rest, `dF` \[N\].
    pub increase_n: f64,
    /// Its 95 % half-width \[N\].
    pub increase_ci_n: f64,
    /// Time constant of the growth \[s\] (grid value).
    pub time_constant_s: f64,
    /// Evidence for the growth against constant levels.
    pub delta_bic: f64,
    /// The departures' acceleration and speed were weighed as nuisances
    /// ([`MIN_DEPARTURES_KINEMATICS`] departures or more, and they vary).
    pub weighs_kinematics: bool,
}

impl DwellTrend {
    /// What the output adds after the trend's numbers: whether the departures' kinematics
    /// were weighed (empty where not).
    pub fn kinematics_note(&self) -> &'static str {
        if self.weighs_kinematics {
            " (each departure's acceleration and speed weighed)"
        } else {
            ""
        }
    }

    /// The peaks grow with the rest time: evidence of at least [`DWELL_MIN_TREND_DBIC`] for a
    /// positive growth (peaks that fall with the rest are no dwell stiction, however strong
    /// the evidence).
    pub fn shows_growth(&self) -> bool {
        self.delta_bic >= DWELL_MIN_TREND_DBIC && self.increase_n > 0.0
    }
}

/// Grid of the trend's time constant \[s\].
const TAU_GRID: [f64; 12] = [
    0.02, 0.04, 0.07, 0.1, 0.15, 0.2, 0.3, 0.5, 0.8, 1.2, 2.0, 4.0,
];

/// The window of a departure: `[end - PRE_S, end + POST_S]`, cut at the next rest.
fn window(p: &Prepared, end: usize, next_rest: usize) -> std::ops::Range<usize> {
    let pre = (PRE_S / p.dt).round() as usize;
    let post = (POST_S / p.dt).round() as usize;
    end.saturating_sub(pre)..(end + post).min(next_rest).min(p.len())
}

/// Largest `d f` over the window, signed back (`d max d f`).
fn peak(f: &[f64], w: std::ops::Range<usize>, d: f64) -> f64 {
    d * f[w].iter().fold(f64::NEG_INFINITY, |m, x| m.max(d * x))
}

impl Breakaway {
    /// Finds the departures of a prepared record (segment by segment: never across a gap).
    pub fn find(p: &Prepared) -> Self {
        let min_rest = (MIN_REST_S / p.dt).ceil() as usize;
        let half = ((0.5 * REST_SPEED_WINDOW_S / p.dt).round() as usize).max(1);
        let mut departures = Vec::new();
        for seg in &p.segments {
            // the speed over the window centred on i, within the segment
            let stuck = |i: usize| {
                let (a, b) = (
                    i.saturating_sub(half).max(seg.start),
                    (i + half).min(seg.end - 1),
                );
                b > a && ((p.x[b] - p.x[a]) / ((b - a) as f64 * p.dt)).abs() < STUCK_SPEED
            };
            let mut i = seg.start;
            while i < seg.end {
                if !stuck(i) {
                    i += 1;
                    continue;
                }
                let start = i;
                while i < seg.end && stuck(i) {
                    i += 1;
                }
                let rest_end = i;
                // the rest's first samples at a segment start may be mid-rest: not counted
                if rest_end == seg.end || rest_end - start < min_rest || start == seg.start {
                    continue;
                }
                // the centred window flags motion half a window early: the axis leaves here
                let end = (rest_end + half).min(seg.end - 1);
                let mut next = end;
                while next < seg.end && !stuck(next) {
                    next += 1;
                }
                let w = window(p, end, next);
                let Some(fast) = (end..w.end).find(|&k| p.v[k].abs() >= DEPARTURE_SPEED) else {
                    continue;
                };
                let d = p.v[fast].signum();
                let peak_n = peak(&p.force, w.clone(), d);
                // a breakaway pushes in the direction of the motion that follows; a start
                // carried by inertia or a passing load is no breakaway
                if d * peak_n <= 0.0 {
                    continue;
                }
                let held = &p.force[start..rest_end];
                let most = |c: &[f64]| {
                    w.clone()
                        .map(|k| d * c[k])
                        .fold(f64::NEG_INFINITY, f64::max)
                };
                let kinematics = [most(&p.acceleration_filtered), most(&p.velocity_filtered)];
                departures.push(Departure {
                    index: end,
                    time_s: p.t[end],
                    rest_s: (rest_end - start) as f64 * p.dt,
                    direction: d,
                    peak_n,
                    holding_n: held.iter().sum::<f64>() / held.len() as f64,
                    kinematics,
                    window: w,
                });
            }
        }
        let rests: Vec<f64> = departures.iter().map(|d| d.rest_s).collect();
        let longest = rests.iter().cloned().fold(0.0, f64::max);
        let shortest = rests.iter().cloned().fold(f64::INFINITY, f64::min);
        let untestable = if departures.len() < MIN_DEPARTURES {
            Some(format!(
                "the record has {} departure(s) from a rest of {:.0} ms or more (needs {MIN_DEPARTURES}): record dwells of varied length",
                departures.len(),
                MIN_REST_S * 1e3
            ))
        } else if longest < MIN_REST_SPAN * shortest {
            Some(format!(
                "its rests hardly vary in length ({:.2} to {:.2} s; needs a ratio of {MIN_REST_SPAN:.0}): record dwells of varied length",
                shortest, longest
            ))
        } else {
            None
        };
        let trend = untestable.is_none().then(|| trend(&departures)).flatten();
        Self {
            departures,
            trend,
            untestable,
            ignored: false,
        }
    }

    /// No evidence beyond sliding: candidates are judged on the sliding samples alone, as
    /// before this module existed (for measuring what it changes).
    pub fn ignored() -> Self {
        Self {
            ignored: true,
            ..Self::default()
        }
    }

    /// The breakaway peaks of a model's filtered force prediction, one per departure.
    pub fn model_peaks(&self, prediction: &[f64]) -> Vec<f64> {
        self.departures
            .iter()
            .map(|d| peak(prediction, d.window.clone(), d.direction))
            .collect()
    }

    /// The dwell trend of values at the departures (signed like the peaks), e.g. a model's
    /// peak residuals.
    pub fn trend_of(&self, signed: &[f64]) -> Option<DwellTrend> {
        trend_of(&self.departures, signed)
    }

    /// The dwell trend of the peaks a model leaves unexplained (measured minus the model's
    /// peak at each departure) against the rest time: `None` where the record cannot test
    /// dwell stiction ([`Self::untestable`]) or the fit is degenerate. Unlike the measured
    /// peaks' trend, the residual's carries neither the inertial force of each departure's
    /// acceleration nor a breakaway level the model already gives.
    pub fn unexplained_trend(&self, prediction: &[f64]) -> Option<DwellTrend> {
        if self.untestable.is_some() || self.departures.is_empty() {
            return None;
        }
        let residual: Vec<f64> = self
            .model_peaks(prediction)
            .iter()
            .zip(&self.departures)
            .map(|(m, d)| d.peak_n - m)
            .collect();
        self.trend_of(&residual)
    }

    /// Sum of squared peak residuals of a model's prediction [N^2].
    pub fn peak_rss(&self, prediction: &[f64]) -> f64 {
        self.model_peaks(prediction)
            .iter()
            .zip(&self.departures)
            .map(|(m, d)| (d.peak_n - m).powi(2))
            .sum()
    }

    /// The peaks' evidence for a candidate whose peak residual sum ([`Self::peak_rss`]) is
    /// `candidate_peak_rss` over a model whose sum is `current_peak_rss` \[N^2\]
    /// (`n ln(RSS_current / RSS_candidate)`), once there are [`MIN_DEPARTURES`] departures,
    /// enough to be more than anecdote; `None` before.
    pub fn counted_peak_dbic(&self, current_peak_rss: f64, candidate_peak_rss: f64) -> Option<f64> {
        let n = self.departures.len();
        if n < MIN_DEPARTURES {
            return None;
        }
        Some(if current_peak_rss > 0.0 && candidate_peak_rss > 0.0 {
            n as f64 * (current_peak_rss / candidate_peak_rss).ln()
        } else {
            0.0
        })
    }
}

/// The model-free dwell trend (see the module docs); `None` when the fit is degenerate.
fn trend(deps: &[Departure]) -> Option<DwellTrend> {
    let peaks: Vec<f64> = deps.iter().map(|d| d.peak_n).collect();
    trend_of(deps, &peaks)
}

/// The dwell trend of signed values at the departures (one per departure, signed like the
/// peaks) against the rest before each: `m = b_d + c_a a + c_v v + dF (1 - exp(-t_rest /
/// tau))` against `m = b_d + c_a a + c_v v`, with `a` and `v` the departure's
/// [`Departure::kinematics`] once there are [`MIN_DEPARTURES_KINEMATICS`] departures (before,
/// or where they do not vary, without them).
fn trend_of(deps: &[Departure], signed: &[f64]) -> Option<DwellTrend> {
    (deps.len() >= MIN_DEPARTURES_KINEMATICS)
        .then(|| trend_with(deps, signed, true))
        .flatten()
        .or_else(|| trend_with(deps, signed, false))
}

/// The dwell trend of [`trend_of`], with the kinematic columns or without; `None` when a
/// column is zero (a record that departs in one direction only) or the columns are collinear.
fn trend_with(deps: &[Departure], signed: &[f64], kinematic: bool) -> Option<DwellTrend> {
    let n = deps.len();
    let mags: Vec<f64> = deps
        .iter()
        .zip(signed)
        .map(|(d, s)| d.direction * s)
        .collect();
    let mut cols: Vec<Vec<f64>> = vec![
        deps.iter().map(|d| f64::from(d.direction > 0.0)).collect(),
        deps.iter().map(|d| f64::from(d.direction < 0.0)).collect(),
    ];
    if kinematic {
        for j in 0..2 {
            cols.push(deps.iter().map(|d| d.kinematics[j]).collect());
        }
    }
    let null = least_squares(&cols, &mags)?;
    let mut best: Option<(LeastSquares, f64)> = None;
    for tau in TAU_GRID {
        cols.push(deps.iter().map(|d| -(-d.rest_s / tau).exp_m1()).collect());
        let fit = least_squares(&cols, &mags);
        cols.pop();
        if let Some(fit) = fit {
            if best.as_ref().is_none_or(|b| fit.rss < b.0.rss) {
                best = Some((fit, tau));
            }
        }
    }
    let (fit, tau) = best?;
    let k = cols.len() + 1;
    let dof = n.saturating_sub(k).max(1);
    let se = (fit.rss / dof as f64 * fit.last_variance).sqrt();
    let delta_bic = n as f64 * (null.rss / fit.rss.max(1e-300)).ln() - 2.0 * (n as f64).ln();
    // the short-rest level per direction at the record's mean kinematics
    let nuisance: f64 = fit.beta[2..cols.len()]
        .iter()
        .zip(&cols[2..])
        .map(|(b, c)| b * c.iter().sum::<f64>() / n as f64)
        .sum();
    Some(DwellTrend {
        level_n: [fit.beta[0] + nuisance, fit.beta[1] + nuisance],
        increase_n: fit.beta[k - 1],
        increase_ci_n: crate::stats::student_t95(dof) * se,
        time_constant_s: tau,
        delta_bic,
        weighs_kinematics: kinematic,
    })
}

/// A least-squares fit: coefficients, residual sum of squares and the last coefficient's
/// variance factor `(A^T A)^-1` at its diagonal.
struct LeastSquares {
    beta: Vec<f64>,
    rss: f64,
    last_variance: f64,
}

/// Least squares on the columns `cols` (each scaled to unit rms, solved by SVD); `None` when
/// a column is zero or the columns are (nearly) collinear.
fn least_squares(cols: &[Vec<f64>], y: &[f64]) -> Option<LeastSquares> {
    let (n, k) = (y.len(), cols.len());
    if n <= k {
        return None;
    }
    let scale: Vec<f64> = cols
        .iter()
        .map(|c| (c.iter().map(|x| x * x).sum::<f64>() / n as f64).sqrt())
        .collect();
    if scale.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
        return None;
    }
    let a = nalgebra::DMatrix::from_fn(n, k, |i, j| cols[j][i] / scale[j]);
    let svd = a.clone().svd(true, true);
    let s = &svd.singular_values;
    let (smax, smin) = (s.max(), s.min());
    if smin.is_nan() || smin <= 1e-9 * smax {
        return None;
    }
    let b = nalgebra::DVector::from_column_slice(y);
    let x = svd.solve(&b, 0.0).ok()?;
    let rss = (&b - &a * &x).norm_squared();
    let v_t = svd.v_t.as_ref()?;
    let last = k - 1;
    let last_variance =
        (0..k).map(|j| (v_t[(j, last)] / s[j]).powi(2)).sum::<f64>() / (scale[last] * scale[last]);
    Some(LeastSquares {
        beta: x.iter().zip(&scale).map(|(b, s)| b / s).collect(),
        rss,
        last_variance,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn departures(rests: &[f64], increase: f64) -> Vec<Departure> {
        rests
            .iter()
            .enumerate()
            .map(|(i, &r)| {
                let d = if i % 2 == 0 { 1.0 } else { -1.0 };
                // a small deterministic scatter
                let wobble = 3.0 * ((i as f64) * 1.7).sin();
                let level = if d > 0.0 { 120.0 } else { 100.0 };
                Departure {
                    index: i,
                    time_s: i as f64,
                    rest_s: r,
                    direction: d,
                    peak_n: d * (level + increase * -(-r / 0.3f64).exp_m1() + wobble),
                    holding_n: 0.0,
                    kinematics: [0.0, 0.0],
                    window: 0..0,
                }
            })
            .collect()
    }

    /// A record of moves at 20 mm/s between rests of known length, the axis creeping by 1 um
    /// encoder counts while it rests; the force peaks at each departure by 50 N over its
    /// 200 N sliding level (signed with the motion).
    fn record(rests: &[f64]) -> (crate::record::Record, Vec<f64>) {
        let dt = 1e-3;
        let mut text = String::from("t,x,force\n");
        let (mut t, mut x, mut dir) = (0.0f64, 0.0f64, 1.0f64);
        let mut line = |t: f64, x: f64, f: f64| text.push_str(&format!("{t:.3},{x:.7},{f:.3}\n"));
        let mut dirs = Vec::new();
        for (k, &rest) in rests.iter().enumerate() {
            // a move of 0.4 s, then the rest
            for i in 0..400 {
                let f = if i < 30 { 250.0 } else { 200.0 };
                x += dir * 0.02 * dt;
                line(t, x, dir * f);
                t += dt;
            }
            let n = (rest / dt).round() as usize;
            for i in 0..n {
                // a 1 um creep now and then (an encoder count)
                let creep = if i % 97 == 50 { 1e-6 } else { 0.0 };
                x += creep;
                line(t, (x * 1e6).round() * 1e-6, 0.3 * dir * 200.0);
                t += dt;
            }
            if k % 2 == 1 {
                dir = -dir;
            }
            dirs.push(dir);
        }
        for _ in 0..400 {
            x += dir * 0.02 * dt;
            line(t, x, dir * 200.0);
            t += dt;
        }
        let rec = crate::record::Record::parse(&text, std::path::Path::new("r.csv")).unwrap();
        (rec, dirs)
    }

    #[test]
    fn finds_every_departure_with_its_rest_direction_and_peak() {
        let rests = [0.1, 0.5, 0.05, 1.2, 0.3, 2.0, 0.08];
        let (rec, dirs) = record(&rests);
        let p = Prepared::new(&rec, "r.csv", Default::default()).unwrap();
        let b = Breakaway::find(&p);
        assert_eq!(b.departures.len(), rests.len(), "{:?}", b.departures);
        for ((d, rest), dir) in b.departures.iter().zip(rests).zip(dirs) {
            // the rest's length within the 20 ms averaging window and the filters' blur
            assert!((d.rest_s - rest).abs() < 0.03, "{d:?} vs {rest}");
            assert_eq!(d.direction, dir, "{d:?}");
            // the departure's peak, past the 20 Hz band's smoothing, above the sliding level
            assert!(d.direction * d.peak_n > 200.0, "{d:?}");
        }
        // rests from 0.05 to 2 s: dwell stiction can be tested
        assert_eq!(b.untestable, None);
        // a record with two rests cannot test it, and says why
        let (rec, _) = record(&[0.5, 1.0]);
        let p = Prepared::new(&rec, "r.csv", Default::default()).unwrap();
        let b = Breakaway::find(&p);
        assert!(b.untestable.unwrap().contains("needs 5"));
        // at the boundary: one departure fewer than MIN_DEPARTURES is untestable, and exactly
        // MIN_DEPARTURES (rests still varied) is tested
        for (n, testable) in [(MIN_DEPARTURES - 1, false), (MIN_DEPARTURES, true)] {
            let (rec, _) = record(&rests[..n]);
            let p = Prepared::new(&rec, "r.csv", Default::default()).unwrap();
            let b = Breakaway::find(&p);
            assert_eq!(b.departures.len(), n);
            assert_eq!(b.untestable.is_none(), testable, "{n}: {:?}", b.untestable);
            assert_eq!(b.counted_peak_dbic(4.0, 1.0).is_some(), testable);
        }
    }

    const RESTS: [f64; 12] = [
        0.03, 2.0, 0.05, 1.0, 0.1, 0.5, 0.04, 3.0, 0.2, 0.08, 1.5, 0.3,
    ];

    #[test]
    fn the_trend_finds_peaks_that_grow_with_the_rest() {
        let t = trend(&departures(&RESTS, 40.0)).expect("trend");
        assert!(t.delta_bic > 10.0, "{t:?}");
        assert!((t.increase_n - 40.0).abs() < 8.0, "{t:?}");
        assert!(t.increase_n - t.increase_ci_n > 0.0, "{t:?}");
        // the direction levels are kept apart (asymmetric breakaway)
        assert!((t.level_n[0] - 120.0).abs() < 6.0 && (t.level_n[1] - 100.0).abs() < 6.0);
    }

    /// A prediction whose peak in each departure's window is `model(rest)` (the departures'
    /// windows laid side by side, 10 samples each).
    fn prediction_for(deps: &mut [Departure], model: impl Fn(f64) -> f64) -> Vec<f64> {
        let mut out = vec![0.0; 10 * deps.len()];
        for (k, d) in deps.iter_mut().enumerate() {
            d.window = 10 * k..10 * k + 10;
            out[10 * k + 4] = d.direction * model(d.rest_s);
            // a smaller value of the same sign elsewhere in the window is not the peak
            out[10 * k + 7] = 0.5 * d.direction * model(d.rest_s);
        }
        out
    }

    #[test]
    fn the_unexplained_trend_is_what_the_model_leaves_of_the_growth() {
        let growth = |r: f64| -40.0 * (-r / 0.3f64).exp_m1();
        let mut deps = departures(&RESTS, 40.0);
        let mut brk = Breakaway {
            departures: deps.clone(),
            ..Default::default()
        };
        // a model with one breakaway level per direction leaves the whole growth
        let flat = prediction_for(&mut deps, |_| 110.0);
        brk.departures = deps.clone();
        let t = brk.unexplained_trend(&flat).expect("trend");
        assert!(
            t.delta_bic > 10.0 && (t.increase_n - 40.0).abs() < 8.0,
            "{t:?}"
        );
        assert!(t.shows_growth());
        // a model whose peaks already grow with the rest leaves none
        let grows = prediction_for(&mut deps, |r| 110.0 + growth(r));
        brk.departures = deps.clone();
        let t = brk.unexplained_trend(&grows).expect("trend");
        assert!(t.delta_bic < 2.0 && !t.shows_growth(), "{t:?}");
        // nor on a record that cannot test dwell stiction
        brk.untestable = Some("too few departures".into());
        assert!(brk.unexplained_trend(&flat).is_none());
        // peaks that fall with the rest: a trend, but of the wrong sign
        let mut falling = departures(&RESTS, -40.0);
        let flat = prediction_for(&mut falling, |_| 110.0);
        let brk = Breakaway {
            departures: falling,
            ..Default::default()
        };
        let t = brk.unexplained_trend(&flat).expect("trend");
        assert!(t.delta_bic > 10.0 && t.increase_n < 0.0, "{t:?}");
        assert!(!t.shows_growth());
    }

    /// Departures whose peaks carry the inertial force of their start (a 200 kg axis at the
    /// departure's acceleration) and the viscous force at the speed reached, plus a growth
    /// `increase` with the rest; the long rests come before the hard starts (as a dwell
    /// before a fast move), so the inertial force alone rises with the rest.
    fn starts(rests: &[f64], increase: f64) -> Vec<Departure> {
        let mut deps = departures(rests, increase);
        let longest = rests.iter().cloned().fold(0.0, f64::max);
        for (k, d) in deps.iter_mut().enumerate() {
            let accel = 0.5 + 2.5 * d.rest_s / longest + 0.3 * ((k as f64) * 2.3).cos();
            let speed = 0.02 + 0.05 * ((k as f64) * 0.9).sin().abs();
            d.kinematics = [accel, speed];
            d.peak_n += d.direction * (200.0 * accel + 3000.0 * speed);
        }
        deps
    }

    #[test]
    fn the_trend_weighs_the_departures_kinematics() {
        let rests: Vec<f64> = RESTS.iter().chain(&RESTS).map(|r| r * 1.1).collect();
        // without the kinematics the inertial force reads as a growth with the rest
        let deps = starts(&rests, 0.0);
        let peaks: Vec<f64> = deps.iter().map(|d| d.peak_n).collect();
        let plain = trend_with(&deps, &peaks, false).expect("trend");
        assert!(plain.shows_growth(), "{plain:?}");
        // with them there is none
        let t = trend(&deps).expect("trend");
        assert!(!t.shows_growth(), "{t:?}");
        // a true growth beside the inertia is found, and its size
        let t = trend(&starts(&rests, 40.0)).expect("trend");
        assert!(
            t.shows_growth() && (t.increase_n - 40.0).abs() < 8.0,
            "{t:?}"
        );
        // too few departures for two more columns: the trend without them
        let few = starts(&rests[..MIN_DEPARTURES_KINEMATICS - 1], 0.0);
        let peaks: Vec<f64> = few.iter().map(|d| d.peak_n).collect();
        let t = trend(&few).expect("trend");
        let plain = trend_with(&few, &peaks, false).expect("trend");
        assert_eq!(t.delta_bic, plain.delta_bic);
    }

    #[test]
    fn constant_peaks_show_no_trend() {
        let t = trend(&departures(&RESTS, 0.0)).expect("trend");
        assert!(t.delta_bic < 2.0, "{t:?}");
        assert!(t.increase_n.abs() < t.increase_ci_n + 3.0, "{t:?}");
    }
}
