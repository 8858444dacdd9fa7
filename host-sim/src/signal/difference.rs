//! Numerical differentiation of sampled signals.

/// Central difference `(x[i+1] - x[i-1]) / 2 dt`, one-sided at both ends.
pub fn central_difference(x: &[f64], dt: f64) -> Vec<f64> {
    let n = x.len();
    let mut d = vec![0.0; n];
    for i in 1..n - 1 {
        d[i] = (x[i + 1] - x[i - 1]) / (2.0 * dt);
    }
    d[0] = (x[1] - x[0]) / dt;
    d[n - 1] = (x[n - 1] - x[n - 2]) / dt;
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_on_a_parabola_inside() {
        let x: Vec<f64> = (0..10).map(|i| (i as f64 * 0.1).powi(2)).collect();
        let d = central_difference(&x, 0.1);
        for (i, v) in d.iter().enumerate().take(9).skip(1) {
            assert!((v - 2.0 * i as f64 * 0.1).abs() < 1e-12);
        }
    }
}
