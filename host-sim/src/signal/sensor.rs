//! What a record's sensors resolve, measured on the record itself: the position reading's count
//! ([`encoder_resolution`]) and the force's white noise ([`force_noise`]). Identification
//! weighs its residuals with them; diagnosis tells a count toggling at rest from motion.

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
    let mut d: Vec<f64> = force
        .windows(3)
        .map(|w| (w[2] - 2.0 * w[1] + w[0]).abs())
        .filter(|d| d.is_finite())
        .collect();
    if d.is_empty() {
        return 0.0;
    }
    let mid = d.len() / 2;
    let (_, median, _) = d.select_nth_unstable_by(mid, f64::total_cmp);
    *median / 0.6745 / 6f64.sqrt()
}
