//! How many independent samples a correlated series holds.

/// Integrated autocorrelation time `tau_int = 1 + 2 sum_k rho_k` of a residual series (summed
/// until the autocorrelation first drops below 0.05): a series of `N` samples carries about
/// `N / tau_int` independent ones.
pub fn integrated_autocorrelation_time(r: &[f64]) -> f64 {
    let n = r.len();
    let var: f64 = r.iter().map(|x| x * x).sum();
    if var <= 0.0 {
        return 1.0;
    }
    let mut tau = 1.0;
    for lag in 1..n.min(2000) {
        let rho = r[lag..]
            .iter()
            .zip(&r[..n - lag])
            .map(|(a, b)| a * b)
            .sum::<f64>()
            / var;
        if rho < 0.05 {
            break;
        }
        tau += 2.0 * rho;
    }
    tau
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn white_noise_is_independent_and_a_smooth_series_is_not() {
        // a deterministic pseudo-random sequence: tau near 1
        let mut s = 1u64;
        let white: Vec<f64> = (0..5000)
            .map(|_| {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            })
            .collect();
        assert!(integrated_autocorrelation_time(&white) < 1.2);
        // a first-order low-pass of it with time constant 20 samples: tau near 2 x 20
        let mut y = 0.0;
        let smooth: Vec<f64> = white
            .iter()
            .map(|w| {
                y += (w - y) / 20.0;
                y
            })
            .collect();
        let tau = integrated_autocorrelation_time(&smooth);
        assert!((20.0..60.0).contains(&tau), "{tau}");
        assert_eq!(integrated_autocorrelation_time(&[0.0; 10]), 1.0);
    }
}
