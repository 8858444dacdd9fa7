//! What a record's sensors resolve, measured on the record itself: the position reading's count
//! ([`encoder_resolution`]) and the force's white noise ([`force_noise`],
//! [`force_noise_fourth_difference`]). Identification weighs its residuals with them;
//! diagnosis tells a count toggling at rest from motion, and reports the force noise beside the
//! force each candidate effect explains.

/// Share of a reading's nonzero steps that must be whole multiples of the smallest one for
/// the reading to count as quantised.
const QUANTISED_SHARE: f64 = 0.95;

/// The resolution of a position reading \[m\]: the largest of its smallest nonzero step and
/// that step's whole fractions down to a tenth of which at least 95 % of the nonzero steps
/// are whole multiples (within 1 %); 0 when none is (an unquantised
/// or resampled reading, whose staircase the dynamic stage then does not look for).
pub fn encoder_resolution(x: &[f64]) -> f64 {
    let steps: Vec<f64> = x
        .windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .filter(|d| *d > 0.0 && d.is_finite())
        .collect();
    let Some(smallest) = steps.iter().copied().reduce(f64::min) else {
        return 0.0;
    };
    // the count may be a fraction of the smallest step taken (a reference rounded to 0.1 um
    // moving 0.5 um per period): the largest whole fraction that fits
    (1..=10)
        .map(|k| smallest / k as f64)
        .find(|&q| {
            let whole = steps
                .iter()
                .filter(|d| {
                    let n = *d / q;
                    (n - n.round()).abs() <= 0.01
                })
                .count();
            whole as f64 >= QUANTISED_SHARE * steps.len() as f64
        })
        .unwrap_or(0.0)
}

/// The standard deviation of a force's white measurement noise \[N\], from its second
/// differences (`F[k+1] - 2 F[k] + F[k-1]` has variance `6 sigma^2` for white noise and
/// next to none from a force that changes smoothly over several periods), robustly: the
/// median absolute value over 0.6745.
pub fn force_noise(force: &[f64]) -> f64 {
    robust_sigma(force.windows(3).map(|w| w[2] - 2.0 * w[1] + w[0]), 6.0)
}

/// The standard deviation of a force's white measurement noise \[N\] from its fourth
/// differences (`F[k+2] - 4 F[k+1] + 6 F[k] - 4 F[k-1] + F[k-2]`, variance `70 sigma^2` for white
/// noise), robustly: the median absolute value over 0.6745. A force's own fast dynamics leak
/// into second differences ([`force_noise`]): on the independent generator's hydraulic records
/// (the oil column ringing) those read 1.02..3.09x the pressure transducers' true noise, the
/// fourth differences 0.99..1.04x (records 550..579, test
/// `the_force_noise_is_measured_on_the_record`).
pub fn force_noise_fourth_difference(force: &[f64]) -> f64 {
    robust_sigma(
        force
            .windows(5)
            .map(|w| w[4] - 4.0 * w[3] + 6.0 * w[2] - 4.0 * w[1] + w[0]),
        70.0,
    )
}

/// The white noise's standard deviation from differences whose variance is `gain sigma^2`:
/// the median absolute difference over 0.6745 (a normal's), over `sqrt(gain)`; 0 without a
/// finite difference.
fn robust_sigma(differences: impl Iterator<Item = f64>, gain: f64) -> f64 {
    let mut d: Vec<f64> = differences
        .map(f64::abs)
        .filter(|d| d.is_finite())
        .collect();
    if d.is_empty() {
        return 0.0;
    }
    let mid = d.len() / 2;
    let (_, median, _) = d.select_nth_unstable_by(mid, f64::total_cmp);
    *median / 0.6745 / gain.sqrt()
}

/// A quantised position reading reconstructed from its count edges \[m\]: where the reading
/// changes between two samples the true position crossed the middle of the change during
/// that period (taken at its middle); between such crossings the position is interpolated
/// linearly in time, and before the first and after the last one it holds the reading.
/// Unlike the staircase, whose error is up to half a count and jumps at every edge, this
/// error is small wherever the axis crosses edges often, and it is smooth.
pub fn edge_interpolated(x: &[f64]) -> Vec<f64> {
    let n = x.len();
    // anchors: (sample time as a fractional index, position)
    let anchors: Vec<(f64, f64)> = (1..n)
        .filter(|&k| x[k] != x[k - 1] && x[k].is_finite() && x[k - 1].is_finite())
        .map(|k| (k as f64 - 0.5, 0.5 * (x[k] + x[k - 1])))
        .collect();
    if anchors.is_empty() {
        return x.to_vec();
    }
    let mut out = x.to_vec();
    let mut a = 0;
    for (k, y) in out.iter_mut().enumerate() {
        let t = k as f64;
        while a + 1 < anchors.len() && anchors[a + 1].0 <= t {
            a += 1;
        }
        if t <= anchors[0].0 || t >= anchors[anchors.len() - 1].0 {
            continue; // holds the reading
        }
        let ((t0, y0), (t1, y1)) = (anchors[a], anchors[a + 1]);
        *y = y0 + (y1 - y0) * (t - t0) / (t1 - t0);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rms difference between a reconstruction and the truth \[m\].
    fn rms_error(y: &[f64], truth: &[f64]) -> f64 {
        (y.iter()
            .zip(truth)
            .map(|(a, b)| (a - b) * (a - b))
            .sum::<f64>()
            / y.len() as f64)
            .sqrt()
    }

    #[test]
    fn edges_interpolated_follow_motion_better_than_the_staircase() {
        let q = 1e-6;
        let round = |x: &f64| (x / q).round() * q;
        // a slow creep, 0.05 count per period: between edges the motion is linear, and the
        // edges' interpolation is exact but for the crossing's time within its period
        let creep: Vec<f64> = (0..4000).map(|k| 0.3e-6 + 5e-8 * k as f64).collect();
        let reading: Vec<f64> = creep.iter().map(round).collect();
        let (stairs, edges) = (
            rms_error(&reading, &creep),
            rms_error(&edge_interpolated(&reading), &creep),
        );
        // the staircase's error is that of rounding, q / sqrt(12)
        assert!(
            (stairs / (q / 12f64.sqrt()) - 1.0).abs() < 0.1,
            "{stairs:e}"
        );
        assert!(edges < 0.15 * stairs, "{edges:e} vs {stairs:e}");
        // a sinusoid up to 1.5 counts per period, with turning points inside one count: the
        // timing within the period and the corners cut at reversals remain
        let sine: Vec<f64> = (0..4000)
            .map(|k| 2e-4 * (k as f64 * 1e-3 * std::f64::consts::TAU * 1.2).sin() + 0.3e-6)
            .collect();
        let reading: Vec<f64> = sine.iter().map(round).collect();
        let (stairs, edges) = (
            rms_error(&reading, &sine),
            rms_error(&edge_interpolated(&reading), &sine),
        );
        assert!(edges < 0.75 * stairs, "{edges:e} vs {stairs:e}");
        // before the first edge and after the last the reading is held
        let still = [5e-6, 5e-6, 5e-6, 6e-6, 6e-6];
        let e = edge_interpolated(&still);
        assert_eq!(&e[..3], &still[..3]);
        assert_eq!(e[4], 6e-6);
    }
}
