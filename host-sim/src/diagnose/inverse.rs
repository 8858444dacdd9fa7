//! The inverse model: what force the axis really needed, and what a model predicts along the
//! measured motion.
//!
//! Protocol (the EMPS benchmark's IDIM pipeline): the position is low-passed with a zero-phase
//! 4th-order Butterworth at 100 Hz (at most [`MAX_POSITION_CUTOFF_SHARE_OF_RATE`] of the
//! sample rate); velocity and acceleration are central differences of it;
//! then every column (measured force, and every model force or regressor) goes through the
//! same zero-phase "parallel" low-pass (20 Hz), so that measurement and model are compared in
//! the same band. The relative force error is `100 ||F - F_hat|| / ||F||` on those columns.

use crate::error::{DataProblem, Error, Result};
use crate::record::Record;
use crate::signal::{central_difference, segmented, LowPass};
use lugre_servo::friction::{
    effects::{DwellAge, DwellClock},
    Conditions, FrictionModel, FrictionState, Levels,
};

/// Filter settings of the inverse model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Protocol {
    /// Zero-phase low-pass on the position before differentiation \[Hz\] (for a reading
    /// whose count is at most [`Self::reference_count_m`]).
    pub position_cutoff_hz: f64,
    /// Zero-phase low-pass applied to every force column \[Hz\].
    pub parallel_cutoff_hz: f64,
    /// The encoder count \[m\] the position cutoff is meant for (None: the cutoff whatever
    /// the count). For a coarser count the diagnosis also tries a lower cutoff
    /// ([`position_cutoff_for_count`], `diagnose::prepare`).
    pub reference_count_m: Option<f64>,
    /// How much later than logged the force is read, to line up with the motion \[samples\]
    /// ([`read_later`]; 0: as logged). A sampled loop holds each force over a period, and a
    /// logger may write beside a position the force that acted over the period before it
    /// (`+0.5`: read half a sample later), the one just commanded for the period after it
    /// (`-0.5`), or a filtered current later still. Where the force changes fast (a
    /// departure, a reversal at speed) a skew leaves `skew dt dF/dt` in every model's
    /// residual, the true model's too, and a flexible candidate absorbs it: the independent
    /// generator's force-actuated records log the force of the period before, and on its
    /// effect-free record 3183 (issue's axes; named viscous power) the true model along the
    /// measured motion errs 3.19 % with the force as logged and 1.13 % read half a sample
    /// later. A skew on a fine grid is not chosen from the record (see the README, "The force
    /// logged half a sample late"): the fitted model's bristle damping and mass absorb most
    /// of a skew, and its misfit moves the choice; it is the logger's, which its user knows.
    /// Where the user gives none, the diagnosis tries the two half-sample conventions against
    /// this reading and leaves it only on a large margin (`diagnose::choose_force_reading`).
    pub force_skew_samples: f64,
}

impl Default for Protocol {
    fn default() -> Self {
        Self {
            position_cutoff_hz: 100.0,
            parallel_cutoff_hz: 20.0,
            reference_count_m: Some(1e-6),
            force_skew_samples: 0.0,
        }
    }
}

/// A column read `skew` samples later, `y_i = u(t_i + skew dt)`, by linear interpolation
/// between neighbouring samples of the same segment (held at a segment's ends). `skew = 0`
/// returns the column as it is, bit for bit.
pub fn read_later(u: &[f64], segments: &[std::ops::Range<usize>], skew: f64) -> Vec<f64> {
    if skew == 0.0 || !skew.is_finite() {
        return u.to_vec();
    }
    let (whole, frac) = (skew.floor(), skew - skew.floor());
    let mut out = u.to_vec();
    for r in segments {
        let (lo, hi) = (r.start as i64, r.end as i64 - 1);
        let at = |j: i64| u[j.clamp(lo, hi) as usize];
        for i in r.clone() {
            let j = i as i64 + whole as i64;
            out[i] = (1.0 - frac) * at(j) + frac * at(j + 1);
        }
    }
    out
}

/// The lowest position cutoff a coarse count may bring, as a fraction of the protocol's
/// ([`position_cutoff_for_count`]). The filter must keep the motion: on a hydraulic axis with
/// a 9 Hz position loop read through a 5 um count (held-out Stribeck record 20504 of
/// `axis_suite --encoder-um 5`), the baseline's error was 2.0 % at 100 Hz, 1.35 % at 50 Hz,
/// 2.3 % at 35 Hz and 3.2 % at 30 Hz.
pub const MIN_POSITION_CUTOFF_SHARE: f64 = 0.5;

/// The highest position cutoff a record's sample rate allows, as a fraction of the rate:
/// a slow logger's record is filtered at most at this share of its rate, however high the
/// protocol's cutoff. (It was 0.2, a constant of the first diagnosis, until session 32: at
/// 250 Hz it filtered the position at 50 Hz, and on the held-out records of
/// `axis_suite --log-hz 250` the fast and hydraulic axes lost their motion: the generator's
/// true model erred 5.6 % (median, hydraulic) where it erred 1.7 % at 500 Hz, and the effect
/// was named on 29 of 40 records.) The zero-phase Butterworth is realisable up to 0.45 of the
/// rate ([`LowPass::butterworth4`]).
pub const MAX_POSITION_CUTOFF_SHARE_OF_RATE: f64 = 0.4;

/// The position cutoff for a reading quantised to `count` \[m\] (0: not quantised) \[Hz\].
/// Differentiated through a cutoff `fc`, a count's quantisation noise (white, `q^2 / 12`)
/// leaves a velocity noise of rms `2 pi q sqrt(fc^3 / (18 fs))`: 0.05 mm/s for a 1 um count
/// at 1 kHz and 100 Hz, a quarter of [`STUCK_SPEED`]. A count `q` coarser than the
/// protocol's reference keeps that noise by `fc = fc_ref (q_ref / q)^(2/3)`, down to
/// [`MIN_POSITION_CUTOFF_SHARE`] of `fc_ref`; a finer count keeps `fc_ref`. (At 100 Hz a 5 um
/// count reads about 0.2 mm/s of noise, as much as [`STUCK_SPEED`]: resting and creeping
/// samples are scored as moving on a noise velocity, and the Stribeck region blurs: on the
/// five held-out Stribeck records of `axis_suite --encoder-um 5` the effect was named on one.)
pub fn position_cutoff_for_count(protocol: &Protocol, count: f64) -> f64 {
    let share = match protocol.reference_count_m {
        // (a count read within 1 % of the reference is the reference)
        Some(q_ref) if count > 1.01 * q_ref => (q_ref / count)
            .powf(2.0 / 3.0)
            .max(MIN_POSITION_CUTOFF_SHARE),
        _ => 1.0,
    };
    share * protocol.position_cutoff_hz
}

/// A record made ready for the inverse model.
#[derive(Clone, Debug)]
pub struct Prepared {
    /// Sample period \[s\].
    pub dt: f64,
    /// Time \[s\].
    pub t: Vec<f64>,
    /// Filtered position \[m\].
    pub x: Vec<f64>,
    /// Velocity (central difference of the filtered position) [m/s].
    pub v: Vec<f64>,
    /// Acceleration [m/s^2].
    pub a: Vec<f64>,
    /// Mean velocity over the step ending at each sample [m/s] (drives the LuGre step).
    pub v_step: Vec<f64>,
    /// Measured force after the parallel filter \[N\].
    pub force: Vec<f64>,
    /// Measured force through the position's filter \[N\]: in the band of [`Self::a`], so
    /// that `F - M a` on it is the friction (at rest, the holding force) without the wider
    /// smear of the parallel filter around an abrupt stop.
    pub force_motion_band: Vec<f64>,
    /// Acceleration after the parallel filter [m/s^2]: the inertia's regression column, the
    /// same for every model (filtered once, with the record).
    pub acceleration_filtered: Vec<f64>,
    /// Velocity after the parallel filter [m/s]: the linear viscous term's regression column.
    pub velocity_filtered: Vec<f64>,
    /// Chamber pressure signal \[Pa\]: `p_a + p_b`, or the one chamber recorded.
    pub pressure_sum: Option<Vec<f64>>,
    /// Oil temperature \[degC\], if recorded.
    pub temperature: Option<Vec<f64>>,
    /// The parallel filter.
    pub parallel: LowPass,
    /// 1 where the axis moves (scored), 0 where it is stuck (see [`STUCK_SPEED`]).
    pub weight: Vec<f64>,
    /// Norm of the filtered measured force over the scored samples, the error's denominator
    /// (weighted like the residual) \[N\].
    pub force_norm: f64,
    /// Norm of the filtered measured force over all samples \[N\].
    pub force_norm_all: f64,
    /// Stretches of uniform sampling between logger gaps (index ranges; one for most records).
    pub segments: Vec<std::ops::Range<usize>>,
    /// What was done to the record's timing, in words (empty when nothing was).
    pub notes: Vec<String>,
    /// Largest measured force magnitude, unfiltered \[N\] (bounds the friction levels).
    pub max_abs_force: f64,
    /// Largest speed of the filtered motion [m/s] (bounds the viscous and damping terms).
    pub max_abs_velocity: f64,
    /// Top speed where the axis moves: the 99th percentile of |v| over the scored samples
    /// [m/s] (robust to a single spike, unlike the maximum).
    pub top_speed: f64,
    /// Inside a rest of the reading ([`reading_inside_rest`]): there a model's bristle carries
    /// the measured force ([`AxisModel::simulate`]).
    pub inside_rest: Vec<bool>,
    /// The position reading's count ([`crate::signal::encoder_resolution`]; 0: not
    /// quantised) \[m\].
    pub count_m: f64,
    /// The cutoff the position was filtered at \[Hz\]: the protocol's, at most
    /// [`MAX_POSITION_CUTOFF_SHARE_OF_RATE`] of the sample rate.
    pub position_cutoff_hz: f64,
    /// The force reading's white noise, rms, measured on the record
    /// ([`crate::signal::force_noise_fourth_difference`]) \[N\].
    pub force_noise_n: f64,
    /// How much later than logged the force is read \[samples\]
    /// ([`Protocol::force_skew_samples`]).
    pub force_skew_samples: f64,
    /// The force reading as logged (on the uniform grid, unfiltered) \[N\]: what
    /// [`Self::with_force_read_later`] reads later.
    pub force_logged: Vec<f64>,
    /// What that noise leaves in the scored force, after the parallel filter, rms
    /// ([`LowPass::noise_gain`]) \[N\]: the scale of the force a candidate effect explains
    /// (`diagnose::Candidate::explained_rms_n`).
    pub force_noise_in_band_n: f64,
}

/// The force as [`Prepared`] reads it: the logged force read `skew` samples later
/// ([`read_later`]), through the parallel filter and through the position's, and the norms.
struct ReadForce {
    force: Vec<f64>,
    force_motion_band: Vec<f64>,
    force_norm: f64,
    force_norm_all: f64,
}

impl ReadForce {
    fn new(
        logged: &[f64],
        skew: f64,
        [parallel, pos]: [&LowPass; 2],
        segments: &[std::ops::Range<usize>],
        weight: &[f64],
    ) -> Self {
        let aligned = read_later(logged, segments, skew);
        let by = |f: &LowPass| {
            segmented(f, segments, &[&aligned])
                .pop()
                .unwrap_or_default()
        };
        let (force, force_motion_band) = (by(parallel), by(pos));
        Self {
            force_norm: scored_norm(&force, weight),
            force_norm_all: force.iter().map(|f| f * f).sum::<f64>().sqrt(),
            force,
            force_motion_band,
        }
    }
}

/// Norm of a force column over the scored samples (`sqrt(sum w f^2)`) \[N\].
fn scored_norm(force: &[f64], weight: &[f64]) -> f64 {
    force
        .iter()
        .zip(weight)
        .map(|(f, w)| w * f * f)
        .sum::<f64>()
        .sqrt()
}

/// Below this speed (after filtering) the axis counts as stuck [m/s]. There friction balances
/// whatever force is applied, through bristle deflections far below any encoder's
/// resolution (0.16 um for Table 2), so no model driven by the measured motion can predict it:
/// stuck samples are left out of fits and scores (and reported as a regime of their own).
pub const STUCK_SPEED: f64 = 2e-4;

/// Left out of the scores at each end of a segment: this many periods of the parallel
/// filter's cutoff (200 ms at 20 Hz). A zero-phase filter starts and ends on a transient (its
/// odd-reflection padding turns a last sample that stands out into a step of twice its
/// height), the velocity and acceleration of a position cut mid-motion are edge estimates, and
/// a record that ends while a force acts (a feed-forward step in its last periods) shows that
/// force without the motion it causes. The independent generator's reference stops mid-move
/// at its last sample: with 5 samples left out (and only between logger gaps), the true
/// model's error on its 130 benchmark records had a median of 2.1 % and exceeded 5 % on 28
/// (up to 68 %, from that sample alone); with 2 periods 1.2 % and 12. In `tests/inverse.rs`
/// 2 periods still leaked a last-sample spike of 100x the force to 0.4 %, 4 leak nothing seen.
pub const EDGE_TRANSIENT_PERIODS: f64 = 4.0;

/// Length of the windows over which [`reading_at_rest`] measures the reading's travel \[s\].
pub const REST_WINDOW_S: f64 = 0.01;

/// Largest travel over a [`reading_at_rest`] window, in counts, that is not motion: a reading
/// that toggles between two neighbouring counts.
pub const REST_COUNTS: f64 = 1.5;

/// Samples where the raw position reading (count `count` \[m\]; 0: unquantised, none) is at
/// rest: over the [`REST_WINDOW_S`] before the sample or the one after it, it travels less
/// than [`REST_COUNTS`] counts. The filtered velocity alone misses two kinds of rest:
/// - a count toggling at rest passes through the 100 Hz position filter as a velocity of
///   about 0.2 mm/s, at the stuck threshold;
/// - an axis that stops abruptly (the end of a slip in stick-slip) rings through the filter
///   for some milliseconds after the reading has stopped.
///
/// In both the axis is stuck and friction holds whatever force is applied (measured on an
/// independent record in stick-slip: 480 N held where a model driven by the filtered motion
/// slides at 230 N). The threshold's equivalent speed (0.15 mm/s for a 1 um count) is below
/// [`STUCK_SPEED`], so steady slow motion is never taken for rest.
pub fn reading_at_rest(
    x: &[f64],
    segments: &[std::ops::Range<usize>],
    count: f64,
    dt: f64,
) -> Vec<bool> {
    still_reading(x, segments, count, dt, false)
}

/// Samples inside a rest of the reading: over both the [`REST_WINDOW_S`] before the sample and
/// the one after it the reading travels less than [`REST_COUNTS`] counts (where
/// [`reading_at_rest`] asks either). Only there is the body in equilibrium, its friction what
/// the actuator applies ([`AxisModel::simulate`]): a sample at rest by one window only may be
/// a departure's first milliseconds or a stop's last, and the holding force imposed there
/// cost the generator's own truth its breakaways (held-out dwell record 20704: 0.55 % ->
/// 4.79 %, 0.63 % inside rests only; session 24).
pub fn reading_inside_rest(
    x: &[f64],
    segments: &[std::ops::Range<usize>],
    count: f64,
    dt: f64,
) -> Vec<bool> {
    still_reading(x, segments, count, dt, true)
}

/// [`reading_at_rest`] (`both`: false) and [`reading_inside_rest`] (`both`: true).
fn still_reading(
    x: &[f64],
    segments: &[std::ops::Range<usize>],
    count: f64,
    dt: f64,
    both: bool,
) -> Vec<bool> {
    let mut out = vec![false; x.len()];
    if count <= 0.0 || !count.is_finite() {
        return out;
    }
    let w = ((REST_WINDOW_S / dt).round() as usize).max(1);
    for r in segments {
        let still = |a: usize, b: usize| (x[b] - x[a]).abs() < REST_COUNTS * count;
        for i in r.clone() {
            // a window cut by the segment's edge says nothing (a segment shorter than one
            // window is judged whole)
            let before = i >= r.start + w && still(i - w, i);
            let after = i + w < r.end && still(i, i + w);
            let short = r.len() <= w && still(r.start, r.end - 1);
            out[i] = short
                || if both {
                    before && after
                } else {
                    before || after
                };
        }
    }
    out
}

/// Minimum record length \[samples\].
pub const MIN_SAMPLES: usize = 500;

impl Prepared {
    /// Prepares a record; refuses records that are too short or without motion, naming the
    /// file. Irregular logger timing is repaired first (see [`crate::timing`]): the record is
    /// resampled onto a uniform grid and split at logger gaps, and [`Self::notes`] says so.
    pub fn new(rec: &Record, name: &str, protocol: Protocol) -> Result<Self> {
        let uniform = crate::timing::uniform(rec, name)?;
        let rec = &uniform.record;
        let n = rec.len();
        if n < MIN_SAMPLES {
            return Err(Error::data(
                name,
                DataProblem::TooShort {
                    samples: n,
                    needed: MIN_SAMPLES,
                },
            ));
        }
        let dt = uniform.period_s;
        let segments = uniform.segments.clone();
        let fs = 1.0 / dt;
        let position_cutoff_hz = protocol
            .position_cutoff_hz
            .min(MAX_POSITION_CUTOFF_SHARE_OF_RATE * fs);
        let pos = LowPass::butterworth4(position_cutoff_hz, fs);
        let parallel_hz = protocol.parallel_cutoff_hz.min(0.1 * fs);
        let parallel = LowPass::butterworth4(parallel_hz, fs);
        let by_segment = |f: &LowPass, x: &[f64]| -> Vec<f64> {
            segmented(f, &segments, &[x]).pop().unwrap_or_default()
        };
        let x = by_segment(&pos, &rec.x);
        let mut v = vec![0.0; n];
        let mut a = vec![0.0; n];
        let mut v_step = vec![0.0; n];
        for r in &segments {
            v[r.clone()].copy_from_slice(&central_difference(&x[r.clone()], dt));
            a[r.clone()].copy_from_slice(&central_difference(&v[r.clone()], dt));
            v_step[r.start] = v[r.start];
            for i in r.start + 1..r.end {
                v_step[i] = (x[i] - x[i - 1]) / dt;
            }
        }
        let stroke = x.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
            - x.iter().cloned().fold(f64::INFINITY, f64::min);
        let moving = v.iter().filter(|s| s.abs() > 1e-4).count();
        if stroke < 1e-5 || moving < n / 50 {
            return Err(Error::data(
                name,
                DataProblem::NoMotion {
                    stroke_m: stroke,
                    moving,
                    samples: n,
                },
            ));
        }
        let mut motion = segmented(&parallel, &segments, &[&a, &v]).into_iter();
        let mut next = || motion.next().unwrap_or_else(|| vec![0.0; n]);
        let (acceleration_filtered, velocity_filtered) = (next(), next());
        let mut weight: Vec<f64> = v
            .iter()
            .map(|s| if s.abs() >= STUCK_SPEED { 1.0 } else { 0.0 })
            .collect();
        // a reading at rest shows no motion the encoder resolves, however the filtered
        // velocity reads
        let count = crate::signal::encoder_resolution(&rec.x);
        let rest = reading_at_rest(&rec.x, &segments, count, dt);
        let inside_rest = reading_inside_rest(&rec.x, &segments, count, dt);
        for (w, r) in weight.iter_mut().zip(&rest) {
            if *r {
                *w = 0.0;
            }
        }
        // the ends of a segment carry the filters' edge transients, and a force at its last
        // samples whose motion the record no longer holds
        let edge = (EDGE_TRANSIENT_PERIODS / (parallel_hz * dt)).ceil() as usize;
        for r in &segments {
            let edge = edge.min(r.len() / 4);
            weight[r.start..r.start + edge].fill(0.0);
            weight[r.end - edge..r.end].fill(0.0);
        }
        // the force lined up with the motion (0: as logged)
        let force_skew_samples = protocol.force_skew_samples;
        let ReadForce {
            force,
            force_motion_band,
            force_norm,
            force_norm_all,
        } = ReadForce::new(
            &rec.force,
            force_skew_samples,
            [&parallel, &pos],
            &segments,
            &weight,
        );
        if force_norm <= 0.0 {
            return Err(Error::data(name, DataProblem::ZeroForce));
        }
        // the load signal: both chambers' sum, or the one chamber a single-acting cylinder has
        let pressure = match (&rec.p_a, &rec.p_b) {
            (Some(pa), Some(pb)) => Some(pa.iter().zip(pb).map(|(a, b)| a + b).collect()),
            (Some(p), None) | (None, Some(p)) => Some(p.clone()),
            (None, None) => None,
        };
        let pressure_sum = pressure.map(|s: Vec<f64>| by_segment(&pos, &s));
        let temperature = rec.temp.as_ref().map(|t| by_segment(&pos, t));
        let max_abs_force = rec.force.iter().fold(0.0f64, |m, f| m.max(f.abs()));
        let force_noise_n = crate::signal::force_noise_fourth_difference(&rec.force);
        let force_noise_in_band_n = force_noise_n * parallel.noise_gain();
        let max_abs_velocity = v.iter().fold(0.0f64, |m, s| m.max(s.abs()));
        let moving_speeds: Vec<f64> = v
            .iter()
            .zip(&weight)
            .filter(|(_, w)| **w > 0.0)
            .map(|(s, _)| s.abs())
            .collect();
        let top_speed = crate::stats::quantile(&moving_speeds, 0.99);
        Ok(Self {
            dt,
            t: rec.t.clone(),
            x,
            v,
            a,
            v_step,
            force,
            force_motion_band,
            acceleration_filtered,
            velocity_filtered,
            pressure_sum,
            temperature,
            parallel,
            weight,
            force_norm,
            force_norm_all,
            segments,
            notes: uniform
                .notes
                .into_iter()
                .chain((force_skew_samples != 0.0).then(|| {
                    format!(
                        "the force is read {force_skew_samples:+.2} samples ({:+.3} ms) later \
                         than logged, as asked",
                        1e3 * force_skew_samples * dt
                    )
                }))
                .collect(),
            max_abs_force,
            max_abs_velocity,
            top_speed,
            inside_rest,
            count_m: count,
            position_cutoff_hz,
            force_noise_n,
            force_noise_in_band_n,
            force_skew_samples,
            force_logged: rec.force.clone(),
        })
    }

    /// The record with its force read `skew` samples later than logged ([`read_later`]; the
    /// same motion, weights and notes): the force, its motion-band twin and their norms.
    pub fn with_force_read_later(&self, skew: f64) -> Self {
        let pos = LowPass::butterworth4(self.position_cutoff_hz, 1.0 / self.dt);
        let read = ReadForce::new(
            &self.force_logged,
            skew,
            [&self.parallel, &pos],
            &self.segments,
            &self.weight,
        );
        Self {
            force: read.force,
            force_motion_band: read.force_motion_band,
            force_norm: read.force_norm,
            force_norm_all: read.force_norm_all,
            force_skew_samples: skew,
            ..self.clone()
        }
    }

    /// The parallel (zero-phase) filter applied to a force column, segment by segment.
    pub fn filter(&self, x: &[f64]) -> Vec<f64> {
        self.filter_many(&[x]).pop().unwrap_or_default()
    }

    /// [`Self::filter`] of several columns at once.
    pub fn filter_many(&self, xs: &[&[f64]]) -> Vec<Vec<f64>> {
        segmented(&self.parallel, &self.segments, xs)
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// True when empty (never, after `new`).
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Relative force error `100 ||F - F_hat|| / ||F||` [%] over the samples where the axis
    /// moves, of a model force column (unfiltered; filtered here).
    pub fn rel_err_pct(&self, predicted: &[f64]) -> f64 {
        100.0 * self.weighted_rss(predicted).sqrt() / self.force_norm
    }

    /// Residual sum of squares over the scored samples [N^2].
    pub fn weighted_rss(&self, predicted: &[f64]) -> f64 {
        self.weighted_rss_filtered(&self.filter(predicted))
    }

    /// [`Self::weighted_rss`] of an already filtered prediction.
    pub fn weighted_rss_filtered(&self, filtered: &[f64]) -> f64 {
        self.force
            .iter()
            .zip(filtered)
            .zip(&self.weight)
            .map(|((f, q), w)| w * (f - q) * (f - q))
            .sum()
    }

    /// Relative force error over every sample, stuck ones included, of an already filtered
    /// prediction [%].
    pub fn rel_err_all_pct_filtered(&self, filtered: &[f64]) -> f64 {
        let r = self
            .force
            .iter()
            .zip(filtered)
            .map(|(f, q)| (f - q) * (f - q))
            .sum::<f64>()
            .sqrt();
        100.0 * r / self.force_norm_all
    }

    /// Leaves the samples `drop` marks out of the scores (their weight to zero) and recomputes
    /// the error's denominator. `false` everywhere changes nothing.
    pub fn leave_out(&mut self, drop: &[bool]) {
        for (w, d) in self.weight.iter_mut().zip(drop) {
            if *d {
                *w = 0.0;
            }
        }
        self.force_norm = scored_norm(&self.force, &self.weight);
    }

    /// The scored samples (weight above zero; [`Self::leave_out`] sets it to zero), in order.
    pub fn scored_samples(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.len()).filter(|&i| self.weight[i] > 0.0)
    }

    /// `100 sqrt(sum e_i) / sqrt(sum F_i^2)` over the scored samples counted alike (every
    /// weight above zero as 1, as before any [`Self::reweigh`]), for a squared force error
    /// `e_i = square(i)` \[N^2\] at each sample [%].
    pub fn plain_pct(&self, square: impl Fn(usize) -> f64) -> f64 {
        let (e, f) = self.scored_samples().fold((0.0, 0.0), |(e, f), i| {
            (e + square(i), f + self.force[i] * self.force[i])
        });
        100.0 * (e / f).sqrt()
    }

    /// Relative force error of an already filtered prediction over the scored samples counted
    /// alike ([`Self::plain_pct`]) [%].
    pub fn rel_err_plain_pct_filtered(&self, filtered: &[f64]) -> f64 {
        self.plain_pct(|i| (self.force[i] - filtered[i]).powi(2))
    }

    /// Multiplies each sample's weight by `factor` (in (0, 1]: a sample scored stays scored)
    /// and recomputes the error's denominator.
    pub fn reweigh(&mut self, factor: &[f64]) {
        for (w, f) in self.weight.iter_mut().zip(factor) {
            *w *= f.clamp(f64::MIN_POSITIVE, 1.0);
        }
        self.force_norm = scored_norm(&self.force, &self.weight);
    }

    /// The scored samples' total weight, `sum w` (what a residual sum of squares is summed
    /// over).
    pub fn scored_weight(&self) -> f64 {
        self.weight.iter().sum::<f64>()
    }

    /// Fraction of samples scored.
    pub fn scored_fraction(&self) -> f64 {
        self.scored_weight() / self.len().max(1) as f64
    }

    /// Operating conditions at sample `i` (missing channels at the model's reference).
    pub fn conditions(&self, i: usize, reference: &Conditions<f64>) -> Conditions<f64> {
        Conditions {
            position: self.x[i],
            pressure_sum: self
                .pressure_sum
                .as_ref()
                .map_or(reference.pressure_sum, |p| p[i]),
            temperature: self
                .temperature
                .as_ref()
                .map_or(reference.temperature, |t| t[i]),
        }
    }
}

/// A model of the axis: mass and friction (with effects).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisModel {
    /// Moving mass \[kg\].
    pub mass_kg: f64,
    /// Friction model.
    pub friction: FrictionModel<f64>,
}

/// Samples from which a segment is simulated as two halves side by side
/// (`AxisModel::simulate_segment`). A rayon job costs microseconds, a sample's step tens of
/// nanoseconds: shorter segments (a logger's fragments) are run whole, the split is for the
/// minute-long records a diagnosis fits hundreds of times. (Not tuned: the 60 s records split.)
const MIN_SPLIT_SAMPLES: usize = 4000;

/// The count [`simulated_samples`] reads.
static SIMULATED_SAMPLES: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// The samples every [`AxisModel`] simulation in this process has run so far: a diagnosis's
/// cost counted, not timed (read it before and after a diagnosis; the difference is that
/// diagnosis's count where nothing else runs). The same work gives the same count on any
/// machine under any load, where the wall clock of a shared machine moved by 20..50 % between
/// runs of one build (session 108); a simulation is most of a diagnosis's work.
pub fn simulated_samples() -> u64 {
    SIMULATED_SAMPLES.load(std::sync::atomic::Ordering::Relaxed)
}

/// What the friction model did along the measured motion (from
/// [`AxisModel::friction_with_decay`], the friction alone, the other fields empty).
#[derive(Clone, Debug, Default)]
pub struct Simulation {
    /// Friction force \[N\] (including the offset).
    pub friction: Vec<f64>,
    /// Normalised bristle state `s = sigma0 z / g(v)` (+-1 when sliding).
    pub bristle: Vec<f64>,
    /// Dwell time before the current motion \[s\].
    pub dwell: Vec<f64>,
    /// Bristle deflection rate dz/dt [m/s] (what sigma1 multiplies).
    pub deflection_rate: Vec<f64>,
}

/// What a simulation along the record keeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Outputs {
    /// Every [`Simulation`] field.
    All,
    /// The friction force alone (the other fields empty).
    FrictionOnly,
}

impl AxisModel {
    /// Runs the friction model (the core's exact step) along the measured motion. Inside a
    /// rest of the reading ([`Prepared::inside_rest`]) the bristle carries the measured force less
    /// `M a` and the offset, `z = (F - M a - F0) / sigma0`, bounded by the static level in each
    /// direction: a body at rest is in equilibrium, its friction is what is applied, and the
    /// deflection a quantised reading would leave (the last move's, carried through the rest,
    /// since `dz/dt = 0` at `v = 0`) is not the one the next departure starts from. With that
    /// stale deflection a dwell term absorbed up to 60 % of effect-free records' errors at
    /// their departures (calibration seeds 100..199, session 24; `docs/diagnosis-log.md`).
    pub fn simulate(&self, p: &Prepared) -> Simulation {
        self.simulate_given(p, None, Outputs::All)
    }

    /// The Stribeck decay `s(v)` of this model at each sample's step velocity (see
    /// `FrictionModel::stribeck_decay`): the same for every model with this one's `vs`,
    /// shape and temperature law, whatever its levels. A temperature dependence whose curve
    /// follows the viscosity (`q != 0`) takes it at each sample's oil temperature
    /// (`FrictionModel::stribeck_decay_at`: the reference temperature where the record has
    /// none).
    pub fn stribeck_decay(&self, p: &Prepared) -> Vec<f64> {
        self.along_step_velocity(p, |v, temperature| {
            self.friction.stribeck_decay_at(v, temperature)
        })
    }

    /// How a Stribeck tail's share moves this model's decay at each sample's step velocity
    /// (`FrictionModel::stribeck_tail_sensitivity_at`, the temperatures as
    /// [`Self::stribeck_decay`] takes them): zero without a `stribeck_shape`.
    pub fn stribeck_tail_sensitivity(&self, p: &Prepared) -> Vec<f64> {
        self.along_step_velocity(p, |v, temperature| {
            self.friction.stribeck_tail_sensitivity_at(v, temperature)
        })
    }

    /// `f(v, T)` at each sample's step velocity \[m/s\] and oil temperature \[degC\] (the
    /// model's reference temperature where the record has none).
    fn along_step_velocity(&self, p: &Prepared, f: impl Fn(f64, f64) -> f64) -> Vec<f64> {
        let reference = self.friction.effects.reference_conditions().temperature;
        let temperature = |i: usize| p.temperature.as_ref().map_or(reference, |t| t[i]);
        (p.v_step.iter().enumerate())
            .map(|(i, &v)| f(v, temperature(i)))
            .collect()
    }

    /// [`Self::simulate`] with the Stribeck decay given ([`Self::stribeck_decay`] of a model
    /// with the same `vs` and shape; the result is the same bit for bit): a fit that moves
    /// only the levels evaluates it once, not once per model.
    pub fn simulate_with_decay(&self, p: &Prepared, stribeck_decay: &[f64]) -> Simulation {
        self.simulate_given(p, Some(stribeck_decay), Outputs::All)
    }

    /// [`Self::simulate_with_decay`]'s friction force alone \[N\] (the same numbers bit for
    /// bit): what scoring a model needs. The bristle state, dwell time and deflection rate
    /// only a linearisation reads are neither computed nor stored (in a grid search's chord
    /// steps, 70 % of a diagnosis's simulations).
    pub fn friction_with_decay(&self, p: &Prepared, stribeck_decay: &[f64]) -> Vec<f64> {
        self.simulate_given(p, Some(stribeck_decay), Outputs::FrictionOnly)
            .friction
    }

    fn simulate_given(
        &self,
        p: &Prepared,
        stribeck_decay: Option<&[f64]>,
        outputs: Outputs,
    ) -> Simulation {
        let n = p.len();
        SIMULATED_SAMPLES.fetch_add(n as u64, std::sync::atomic::Ordering::Relaxed);
        let extra = match outputs {
            Outputs::All => n,
            Outputs::FrictionOnly => 0,
        };
        let mut out = Simulation {
            friction: vec![0.0; n],
            bristle: vec![0.0; extra],
            dwell: vec![0.0; extra],
            deflection_rate: vec![0.0; extra],
        };
        for r in &p.segments {
            // the outputs not asked for are empty, and so is each segment's share of them
            let within = |len: usize| r.start.min(len)..r.end.min(len);
            let out = [
                &mut out.friction[r.clone()],
                &mut out.bristle[within(extra)],
                &mut out.dwell[within(extra)],
                &mut out.deflection_rate[within(extra)],
            ];
            self.simulate_segment(p, stribeck_decay, r.clone(), out);
        }
        out
    }

    /// One segment of [`Self::simulate_given`] into `out` (friction, bristle, dwell, deflection
    /// rate: the segment's samples). The friction state restarts at the segment's first sample
    /// (nothing is known across a gap). Where the model's state after a rest sample is fixed by
    /// the record alone, whatever came before ([`Self::state_after_rest`]), a long segment is
    /// run as two halves side by side, split at such a sample near its middle (the same
    /// numbers bit for bit). Until session 98 a model with a dwell clock was never split; the
    /// clock on the body's speed whose age restarts at each stick is split now (on asymmetry
    /// timing record 1150 its close-call rival, searched again, took 0.91 s and takes 0.81 s,
    /// medians of 3).
    fn simulate_segment(
        &self,
        p: &Prepared,
        stribeck_decay: Option<&[f64]>,
        r: std::ops::Range<usize>,
        out: [&mut [f64]; 4],
    ) {
        // (the other dwell rules are never split: no rest sample is searched for them)
        let split = if r.len() >= MIN_SPLIT_SAMPLES && self.a_rest_can_fix_the_state() {
            let mid = r.start + r.len() / 2;
            (mid..r.end - 1).find_map(|i| self.state_after_rest(p, &r, i).map(|s| (i, s)))
        } else {
            None
        };
        let Some((at, start)) = split else {
            self.simulate_run(p, stribeck_decay, r, FrictionState::default(), out);
            return;
        };
        // the first half ends with the rest sample `at`, the second starts after it from the
        // state the rest fixes there
        let k = at + 1 - r.start;
        let [f, b, d, q] = out;
        // an output not asked for is empty: both its halves are
        let (f0, f1) = f.split_at_mut(k.min(f.len()));
        let (b0, b1) = b.split_at_mut(k.min(b.len()));
        let (d0, d1) = d.split_at_mut(k.min(d.len()));
        let (q0, q1) = q.split_at_mut(k.min(q.len()));
        rayon::join(
            || {
                self.simulate_run(
                    p,
                    stribeck_decay,
                    r.start..at + 1,
                    FrictionState::default(),
                    [f0, b0, d0, q0],
                )
            },
            || self.simulate_run(p, stribeck_decay, at + 1..r.end, start, [f1, b1, d1, q1]),
        );
    }

    /// Whether a rest of the reading can fix the model's state ([`Self::state_after_rest`]):
    /// a bristle that holds, and no dwell clock or the one a rest sets.
    fn a_rest_can_fix_the_state(&self) -> bool {
        self.friction.params.bristle_stiffness() > 0.0
            && self.friction.effects.dwell_stiction.is_none_or(|d| {
                d.clock == DwellClock::BodySpeed && d.age_at_stick == DwellAge::Restarts
            })
    }

    /// The model's state after sample `i` of segment `r`, where what came before cannot move
    /// it (`None` elsewhere): inside a rest of the reading the bristle carries the holding
    /// deflection, whatever came before; the dwell clock, where the model has one, must be
    /// read off the record alone too: a clock on the body's speed whose age restarts at each
    /// stick, stuck at `i` (its age is then the time since the stick began, summed step by
    /// step as [`Self::simulate_run`] sums it). The deflection rate is not part of it: with
    /// that clock no step reads the last one's.
    fn state_after_rest(
        &self,
        p: &Prepared,
        r: &std::ops::Range<usize>,
        i: usize,
    ) -> Option<FrictionState<f64>> {
        if !(self.a_rest_can_fix_the_state() && p.inside_rest[i]) {
            return None;
        }
        let mut dwell_time = 0.0;
        if let Some(d) = self.friction.effects.dwell_stiction {
            // the clock's own test (a NaN speed is not stuck)
            let stuck = |k: usize| p.v_step[k].abs() < d.stick_velocity;
            if !stuck(i) {
                return None;
            }
            let began = (r.start..=i).rev().take_while(|&k| stuck(k)).last()?;
            for _ in began..=i {
                dwell_time += p.dt;
            }
        }
        let reference = self.friction.effects.reference_conditions();
        let c = p.conditions(i, &reference);
        let levels = self.friction.levels_by_direction(&c, dwell_time);
        Some(FrictionState {
            z: self.holding_deflection(p, i, levels),
            dwell_time,
            ..FrictionState::default()
        })
    }

    /// Inside a rest at sample `i`: the deflection that carries what the actuator applies (the
    /// measured force less `M a` and the constant offset), up to the static level in that
    /// direction \[m\].
    fn holding_deflection(
        &self,
        p: &Prepared,
        i: usize,
        (fw, bw): (Levels<f64>, Levels<f64>),
    ) -> f64 {
        let sigma0 = self.friction.params.bristle_stiffness();
        let held = p.force_motion_band[i] - self.mass_kg * p.a[i] - self.friction.offset_force();
        // (a level that is not a positive number, from an effect's scaling far
        // outside its range, bounds at zero: `clamp` must never see min > max)
        let (up, down) = (fw.static_.max(0.0), bw.static_.max(0.0));
        // bounded in force, then one division (sigma0 > 0 keeps the order)
        held.clamp(-down, up) / sigma0
    }

    /// The model along samples `r` from state `st`, into `out` (as [`Self::simulate_segment`]).
    fn simulate_run(
        &self,
        p: &Prepared,
        stribeck_decay: Option<&[f64]>,
        r: std::ops::Range<usize>,
        mut st: FrictionState<f64>,
        out: [&mut [f64]; 4],
    ) {
        let reference = self.friction.effects.reference_conditions();
        let sigma0 = self.friction.params.bristle_stiffness();
        let holds = sigma0 > 0.0;
        // levels that no condition moves are evaluated once, not at every sample
        let constant = self.friction.constant_levels();
        let [fr, br, dw, dr] = out;
        // the bristle state, dwell time and deflection rate, unless they were not asked for
        let extras = !br.is_empty();
        for (k, i) in r.enumerate() {
            let v = p.v_step[i];
            let decay = stribeck_decay.map(|d| d[i]);
            let step = match &constant {
                Some(l) => self
                    .friction
                    .step_split_at_constant_levels(&mut st, v, p.v[i], p.dt, decay, l),
                None => self.friction.step_split_with_curve(
                    &mut st,
                    v,
                    p.v[i],
                    &p.conditions(i, &reference),
                    p.dt,
                    decay,
                ),
            };
            let mut f = step.force;
            if holds && p.inside_rest[i] {
                // at rest the contact carries what the actuator applies, up to its
                // static level in that direction (the levels the step used)
                let z = self.holding_deflection(p, i, (step.forward, step.backward));
                f += sigma0 * (z - st.z);
                st.z = z;
            }
            fr[k] = f;
            if extras {
                br[k] = (sigma0 * st.z / step.stribeck_level).clamp(-1.0, 1.0);
                dw[k] = st.dwell_time;
                dr[k] = st.deflection_rate;
            }
        }
    }

    /// Predicted actuator force `M a + F_friction` \[N\] along the measured motion.
    pub fn predict(&self, p: &Prepared) -> Vec<f64> {
        self.force_with(
            p,
            &self.simulate_given(p, None, Outputs::FrictionOnly).friction,
        )
    }

    /// The actuator force `M a + F_friction` \[N\] at each sample, from this model's friction
    /// along the record (a simulation's, [`Self::friction_with_decay`]'s).
    pub fn force_with(&self, p: &Prepared, friction: &[f64]) -> Vec<f64> {
        p.a.iter()
            .zip(friction)
            .map(|(a, f)| self.mass_kg * a + f)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lugre_servo::friction::effects::DwellStiction;
    use lugre_servo::friction::LugreParams;

    /// The velocity noise a count leaves through the position filter: a smooth motion over
    /// many counts (10 s at 1 kHz, up to 20 mm/s), read through count `q` and differentiated
    /// through a cutoff `fc` as [`Prepared::new`] does, against the same filter's velocity of
    /// the unquantised motion; rms over the record's inner 8 s \[m/s\].
    fn quantisation_velocity_noise(q: f64, fc: f64) -> f64 {
        let (dt, n) = (1e-3, 10_000);
        let x: Vec<f64> = (0..n)
            .map(|i| {
                let t = i as f64 * dt;
                4e-3 * (std::f64::consts::TAU * 0.3 * t).sin()
                    + 1e-3 * (std::f64::consts::TAU * 1.7 * t + 1.0).sin()
            })
            .collect();
        let xq: Vec<f64> = x.iter().map(|x| (x / q).round() * q).collect();
        let f = LowPass::butterworth4(fc, 1.0 / dt);
        let v = central_difference(&f.filtfilt(&x), dt);
        let vq = central_difference(&f.filtfilt(&xq), dt);
        let inner = 1000..n - 1000;
        let e2: f64 = inner.clone().map(|i| (vq[i] - v[i]).powi(2)).sum();
        (e2 / inner.len() as f64).sqrt()
    }

    /// The position cutoff keeps a coarse count's velocity noise at the reference count's: the
    /// formula of [`position_cutoff_for_count`] holds on a quantised motion, 100 Hz leaves a
    /// 5 um count's noise above [`STUCK_SPEED`], and the cutoff it gets brings it down.
    #[test]
    fn a_coarse_count_is_filtered_to_the_reference_velocity_noise() {
        let protocol = Protocol::default();
        let reference = quantisation_velocity_noise(1e-6, 100.0);
        let formula = std::f64::consts::TAU * 1e-6 * (100f64.powi(3) / (18.0 * 1000.0)).sqrt();
        assert!(
            (reference / formula - 1.0).abs() < 0.3,
            "{reference:e} against {formula:e}"
        );
        assert!(reference < 0.3 * STUCK_SPEED, "{reference:e}");
        // five times the count, five times the noise: as much as the stuck speed
        let noise5 = quantisation_velocity_noise(5e-6, 100.0);
        assert!((noise5 / reference / 5.0 - 1.0).abs() < 0.15, "{noise5:e}");
        assert!(noise5 > 0.9 * STUCK_SPEED, "{noise5:e}");
        // a 2 um count: the cutoff the rule gives, not clamped, keeps the reference's noise
        let fc2 = position_cutoff_for_count(&protocol, 2e-6);
        assert!((fc2 - 100.0 * 0.5f64.powf(2.0 / 3.0)).abs() < 1e-9, "{fc2}");
        let noise2 = quantisation_velocity_noise(2e-6, fc2);
        assert!(
            (noise2 / reference - 1.0).abs() < 0.25,
            "{noise2:e} vs {reference:e}"
        );
        // a 5 um count: clamped at half the cutoff, its noise below the stuck speed
        let fc5 = position_cutoff_for_count(&protocol, 5e-6);
        assert_eq!(fc5, MIN_POSITION_CUTOFF_SHARE * protocol.position_cutoff_hz);
        assert!(quantisation_velocity_noise(5e-6, fc5) < 0.6 * STUCK_SPEED);
        // the reference count (read within 1 %), a finer one, none, and no reference: unchanged
        for count in [1.005e-6, 1e-6, 1e-7, 0.0] {
            assert_eq!(position_cutoff_for_count(&protocol, count), 100.0);
        }
        let fixed = Protocol {
            reference_count_m: None,
            ..protocol
        };
        assert_eq!(position_cutoff_for_count(&fixed, 5e-6), 100.0);
    }

    /// 8 s at 1 kHz: moves of 0.4 s at 20 mm/s, back and forth, between rests of 0.3 s on a
    /// 1 um count, the force 200 N sliding and 60 N held.
    fn moves_and_rests() -> Record {
        let dt = 1e-3;
        let mut text = String::from("t,x,force\n");
        let (mut x, mut dir) = (0.0f64, 1.0f64);
        for i in 0..8000 {
            let moving = i % 700 < 400;
            if moving {
                x += dir * 0.02 * dt;
            } else if i % 700 == 699 {
                dir = -dir;
            }
            let f = if moving { dir * 200.0 } else { dir * 60.0 };
            let t = i as f64 * dt;
            text.push_str(&format!("{t:.3},{:.7},{f:.3}\n", (x * 1e6).round() * 1e-6));
        }
        Record::parse(&text, std::path::Path::new("r.csv")).unwrap()
    }

    /// A column read later: 0 is the column bit for bit; a fraction interpolates between
    /// neighbours of one segment; a whole sample moves it; a segment's ends are held, and no
    /// value crosses a logger gap.
    #[test]
    fn a_column_is_read_later_within_its_segments() {
        let u: Vec<f64> = (0..8).map(|i| (i * i) as f64).collect();
        let segs = [0..5, 5..8];
        let same = read_later(&u, &segs, 0.0);
        assert!(same.iter().zip(&u).all(|(a, b)| a.to_bits() == b.to_bits()));
        let half = read_later(&u, &segs, 0.5);
        assert_eq!(half[..4], [0.5, 2.5, 6.5, 12.5]);
        // the segment's last sample is held, not mixed with the next segment's first
        assert_eq!(half[4], 16.0);
        assert_eq!(half[5..], [30.5, 42.5, 49.0]);
        let back = read_later(&u, &segs, -1.0);
        assert_eq!(back, [0.0, 0.0, 1.0, 4.0, 9.0, 25.0, 25.0, 36.0]);
        // not a number: as logged
        assert_eq!(read_later(&u, &segs, f64::NAN), u);
    }

    /// The record with its force read later: 0 is the prepared force bit for bit; half a
    /// sample is the mean of neighbours through the same filter, the motion and weights
    /// untouched; the protocol's skew gives the same record as reading it later after.
    #[test]
    fn a_prepared_force_read_later_keeps_the_motion() {
        let rec = moves_and_rests();
        let p = Prepared::new(&rec, "r.csv", Protocol::default()).unwrap();
        let same = p.with_force_read_later(0.0);
        assert!(same
            .force
            .iter()
            .zip(&p.force)
            .all(|(a, b)| a.to_bits() == b.to_bits()));
        assert_eq!(same.force_norm.to_bits(), p.force_norm.to_bits());
        let later = p.with_force_read_later(0.5);
        assert_eq!(later.v, p.v);
        assert_eq!(later.weight, p.weight);
        let mean: Vec<f64> = (0..p.len())
            .map(|i| 0.5 * (rec.force[i] + rec.force[(i + 1).min(p.len() - 1)]))
            .collect();
        let expect = p.filter(&mean);
        assert!(later
            .force
            .iter()
            .zip(&expect)
            .all(|(a, b)| (a - b).abs() < 1e-9));
        // the step of the force at each reversal moves: the two differ
        assert!(later
            .force
            .iter()
            .zip(&p.force)
            .any(|(a, b)| (a - b).abs() > 1.0));
        let asked = Prepared::new(
            &rec,
            "r.csv",
            Protocol {
                force_skew_samples: 0.5,
                ..Protocol::default()
            },
        )
        .unwrap();
        assert!(asked
            .force
            .iter()
            .zip(&later.force)
            .all(|(a, b)| a.to_bits() == b.to_bits()));
        assert!(asked.notes.iter().any(|n| n.contains("+0.50 samples")));
    }

    /// The simulation run as two halves split at a rest sample is the one long run, bit for
    /// bit: without a dwell clock, and with the one clock a rest fixes (the body's speed, the
    /// age restarting at each stick); with the others (whose state a rest does not reset) it
    /// is not split at all. Either way the friction alone is the whole simulation's friction,
    /// bit for bit.
    #[test]
    fn a_simulation_split_at_a_rest_is_the_whole_run_bit_for_bit() {
        let rec = moves_and_rests();
        let p = Prepared::new(&rec, "r.csv", Protocol::default()).unwrap();
        let n = p.len();
        assert!(p.segments.len() == 1 && p.segments[0] == (0..n));
        assert!(n >= MIN_SPLIT_SAMPLES);
        // the test must exercise the split: a rest sample after the middle
        assert!((n / 2..n - 1).any(|i| p.inside_rest[i]));
        let plain = AxisModel {
            mass_kg: 200.0,
            friction: FrictionModel::plain(LugreParams::table2()),
        };
        let mut models = vec![(plain, true)];
        for age_at_stick in DwellAge::ALL {
            for clock in DwellClock::ALL {
                let mut dwell = plain;
                dwell.friction.effects.dwell_stiction = Some(DwellStiction {
                    max_increase: 80.0,
                    time_constant: 0.2,
                    stick_velocity: 1e-4,
                    renewal_distance: 1e-4,
                    age_at_stick,
                    clock,
                    growth: lugre_servo::friction::DwellGrowth::Exponential,
                });
                let fixed = age_at_stick == DwellAge::Restarts && clock == DwellClock::BodySpeed;
                models.push((dwell, fixed));
            }
        }
        for (m, splits) in models {
            // where the rest fixes the state, the run is split there; elsewhere never
            let at = (n / 2..n - 1).find_map(|i| m.state_after_rest(&p, &(0..n), i));
            assert_eq!(
                at.is_some(),
                splits,
                "{:?}",
                m.friction.effects.dwell_stiction
            );
            // the rest fixes an age that has grown since its stick began
            if let (Some(s), Some(_)) = (at, m.friction.effects.dwell_stiction) {
                assert!(
                    s.dwell_time > 0.0 && s.dwell_time < 0.31,
                    "{}",
                    s.dwell_time
                );
            }
            let split = m.simulate(&p);
            let mut whole = [vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]];
            let [a, b, c, d] = &mut whole;
            m.simulate_run(&p, None, 0..n, FrictionState::default(), [a, b, c, d]);
            let got = [
                &split.friction,
                &split.bristle,
                &split.dwell,
                &split.deflection_rate,
            ];
            for (k, (x, y)) in got.iter().zip(&whole).enumerate() {
                assert!(
                    x.iter().zip(y).all(|(u, v)| u.to_bits() == v.to_bits()),
                    "output {k} differs"
                );
            }
            // the rests carry the held force: the model's friction is not trivially zero
            assert!(split.friction.iter().any(|f| f.abs() > 10.0));
            // the friction alone (a chord step's score, a prediction) is the same numbers,
            // split or not, and nothing else is kept
            let decay = m.stribeck_decay(&p);
            let alone = m.friction_with_decay(&p, &decay);
            let full = m.simulate_with_decay(&p, &decay);
            assert!(alone.len() == n && full.bristle.len() == n);
            assert!(
                alone
                    .iter()
                    .zip(&full.friction)
                    .all(|(u, v)| u.to_bits() == v.to_bits()),
                "the friction alone differs"
            );
            let kept = m.simulate_given(&p, Some(&decay), Outputs::FrictionOnly);
            assert!(kept.bristle.is_empty() && kept.dwell.is_empty());
            assert!(kept.deflection_rate.is_empty());
            let predicted = m.predict(&p);
            assert!(predicted
                .iter()
                .zip(p.a.iter().zip(&full.friction))
                .all(|(y, (a, f))| y.to_bits() == (m.mass_kg * a + f).to_bits()));
        }
    }
}
