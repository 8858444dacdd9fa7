//! What the measured motion resolves: the spread of a model's prediction when the position is
//! filtered at other cutoffs ([`prediction_spread`], [`RESOLVE_BANDWIDTHS`]), the samples it
//! leaves unresolved ([`unresolved`]) and the motion weights that discount them
//! ([`motion_weights`]).

use super::*;

/// Position filter cutoffs, relative to the protocol's, over which [`unresolved`] reads the
/// spread of a model's prediction.
pub const RESOLVE_BANDWIDTHS: [f64; 4] = [0.4, 0.6, 1.6, 2.5];

/// The highest cutoff a motion-reading probe above the record's own reads, as a fraction of
/// the sample rate, unless the record's own cutoff is higher: the motion weights were
/// calibrated with the 2.5x probe of a 1 kHz record at 200 Hz, and read at 250 Hz (session 32)
/// the default calibration suite named one effect fewer (72 of 80). A slow logger's record,
/// filtered up to [`inverse::MAX_POSITION_CUTOFF_SHARE_OF_RATE`] of its rate, reads its probes
/// up to its own cutoff.
pub const MAX_PROBE_CUTOFF_SHARE_OF_RATE: f64 = 0.2;

/// Samples whose predicted force the measured motion does not resolve. The same model is
/// driven by the same reading filtered at other bandwidths ([`RESOLVE_BANDWIDTHS`]). A sample
/// is unresolved where the mean square of those predictions less the model's own, averaged
/// over 20 ms, exceeds the model's mean square residual, or `floor^2` times the scored force's
/// mean square where that is larger (`floor`: a fraction; near the sensor noise a model's
/// residual is too small a yardstick). The generator's true model misses most at such samples
/// (stick-slip, abrupt stops: `examples/sensitivity_probe.rs`); re-reading the motion with the
/// encoder's grid a fraction of a count away hardly changes a prediction.
pub fn unresolved(
    rec: &Record,
    name: &str,
    protocol: Protocol,
    p: &Prepared,
    model: &AxisModel,
    floor: f64,
) -> Vec<bool> {
    let (own, spread) = prediction_spread(rec, name, protocol, p, model);
    unresolved_by_spread(p, &own, &spread, floor)
}

/// [`unresolved`] from a model's filtered prediction `own` and its spread
/// ([`prediction_spread`]).
pub(super) fn unresolved_by_spread(
    p: &Prepared,
    own: &[f64],
    spread: &[f64],
    floor: f64,
) -> Vec<bool> {
    let threshold = residual_yardstick(p, own, floor);
    spread.iter().map(|s| *s > threshold).collect()
}

/// A model's mean square residual over the scored samples, `own` its filtered prediction, at
/// least `floor^2` times the scored force's mean square \[N^2\]: what [`unresolved`] and
/// [`motion_weights`] hold a prediction's spread against.
fn residual_yardstick(p: &Prepared, own: &[f64], floor: f64) -> f64 {
    let scored = p.scored_weight().max(1.0);
    (p.weighted_rss_filtered(own) / scored).max((floor * p.force_norm).powi(2) / scored)
}

/// Floor under the model's part of [`motion_weights`]' residual variance, a fraction of the
/// scored force rms: near the sensor noise a fitted model's residual is too small a yardstick
/// (session 22, on the calibration seeds: without a floor, three effect-free records whose
/// baseline sat at 0.13..0.36 % got a false effect).
pub const MOTION_WEIGHT_FLOOR: f64 = 0.01;

/// Each sample's weight in the fits and scores: `mse / (mse + s_i)`, with `s_i` the spread the
/// motion reading leaves in a model's prediction there ([`prediction_spread`], `own` that
/// model's filtered prediction) and `mse` the model's mean square residual, at least `floor^2`
/// times the scored force's mean square. These are the least-squares weights of a residual
/// whose variance is the model's plus the motion reading's: where the reading cannot tell
/// how the axis moved (abrupt stops, stick-slip, creep), no model driven by it predicts the
/// force, the generator's own true model least of all (session 17: 67..99 % of its squared
/// error below 5 mm/s on the held-out misses), and an effect's evidence elsewhere drowns.
/// Measured against scoring every sample alike on the calibration seeds (session 23): more
/// effects right and fewer false positives at every error cut from 0 to 0.30.
pub fn motion_weights(p: &Prepared, own: &[f64], spread: &[f64], floor: f64) -> Vec<f64> {
    let mse = residual_yardstick(p, own, floor);
    spread.iter().map(|s| mse / (mse + s)).collect()
}

/// A model's filtered prediction along the record, and at each sample the mean square of the
/// same model's predictions with the position filtered at [`RESOLVE_BANDWIDTHS`] less its own,
/// averaged over 20 ms \[N^2\]: the part of the prediction the measured motion leaves open.
pub fn prediction_spread(
    rec: &Record,
    name: &str,
    protocol: Protocol,
    p: &Prepared,
    model: &AxisModel,
) -> (Vec<f64>, Vec<f64>) {
    let n = p.len();
    let own = p.filter(&model.predict(p));
    let mut spread = vec![0.0; n];
    let ceiling = p
        .position_cutoff_hz
        .max(MAX_PROBE_CUTOFF_SHARE_OF_RATE / p.dt);
    for r in RESOLVE_BANDWIDTHS {
        let alt = Protocol {
            position_cutoff_hz: (r * protocol.position_cutoff_hz).min(ceiling),
            ..protocol
        };
        let Ok(pa) = Prepared::new(rec, name, alt) else {
            continue;
        };
        if pa.len() != n {
            continue;
        }
        let pred = p.filter(&model.predict(&pa));
        for (s, (a, b)) in spread.iter_mut().zip(pred.iter().zip(&own)) {
            *s += (a - b).powi(2) / RESOLVE_BANDWIDTHS.len() as f64;
        }
    }
    let half = ((0.01 / p.dt).round() as usize).max(1);
    let mut prefix = vec![0.0; n + 1];
    for i in 0..n {
        prefix[i + 1] = prefix[i] + spread[i];
    }
    let smoothed = (0..n)
        .map(|i| {
            let (a, b) = (i.saturating_sub(half), (i + half + 1).min(n));
            (prefix[b] - prefix[a]) / (b - a) as f64
        })
        .collect();
    (own, smoothed)
}
