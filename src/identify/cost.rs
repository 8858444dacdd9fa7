//! The identification model: two stages, each with a normalised cost (lower is better,
//! 0 = perfect fit).
//!
//! **Static stage** (Fc, Fs - Fc, sigma2, vs) from the steady-state friction measured at
//! constant velocities `v_i` in both directions:
//!
//! ```text
//! J_s = (1/n) sum_i ((Fss(v_i) - F_i) / F_ref)^2,   Fss(v) = g(v) sign(v) + sigma2 v,
//! F_ref = rms(F_i)
//! ```
//!
//! **Dynamic stage** (sigma0, sigma1), with the static part fixed: the friction model is run
//! with the exact zero-order-hold step (the firmware's integrator) along the recorded mean
//! velocity of each sample period, and compared with the recorded friction force:
//!
//! ```text
//! J_d = (1/n) sum_k ((F_model,k - F_k) / F_ref)^2
//! ```
//!
//! Both are dimensionless; a cost that is not finite (a degenerate individual) becomes
//! `f64::MAX` so it simply loses.

use crate::friction::{LugreParams, LugreState};

/// One measured steady-state point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SteadyPoint {
    /// Constant velocity [m/s].
    pub velocity: f64,
    /// Mean friction force at that velocity \[N\].
    pub force: f64,
}

/// Builds the full parameter set from static genes' physical values
/// `[Fc, Fs - Fc, sigma2, vs]` and dynamic `[sigma0, sigma1]` (None if invalid).
pub fn params(static_values: &[f64; 4], dynamic_values: &[f64; 2]) -> Option<LugreParams<f64>> {
    let [fc, dfs, s2, vs] = *static_values;
    let [s0, s1] = *dynamic_values;
    // sigma0 = 0 and Fc = 0 are on Table 1's boundary but not physical: keep them just inside
    LugreParams::new(s0.max(1.0), s1, s2, fc.max(1e-6), fc.max(1e-6) + dfs, vs).ok()
}

fn rms(f: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = f.fold((0.0, 0usize), |(s, n), x| (s + x * x, n + 1));
    if n == 0 {
        1.0
    } else {
        libm::sqrt(s / n as f64).max(1e-12)
    }
}

/// Static-stage cost of `[Fc, Fs - Fc, sigma2, vs]` on the measured points.
pub fn static_cost(values: &[f64; 4], points: &[SteadyPoint]) -> f64 {
    let Some(p) = params(values, &[1e9, 0.0]) else {
        return f64::MAX;
    };
    let f_ref = rms(points.iter().map(|q| q.force));
    let mut sum = 0.0;
    for q in points {
        let e = (p.steady_state_force(q.velocity) - q.force) / f_ref;
        sum += e * e;
    }
    let c = sum / points.len().max(1) as f64;
    if c.is_finite() {
        c
    } else {
        f64::MAX
    }
}

/// A recorded dynamic response: mean velocity over each period [m/s] and friction force at
/// the end of it \[N\], sampled every `dt` seconds.
#[derive(Clone, Copy, Debug)]
pub struct DynamicRecord<'a> {
    /// Mean velocity over each sample period [m/s].
    pub velocity: &'a [f64],
    /// Friction force at the end of each period \[N\].
    pub force: &'a [f64],
    /// Sample period \[s\].
    pub dt: f64,
}

/// Residuals `F_model,k - F_k` of the dynamic stage (None if the parameters are invalid).
pub fn dynamic_residuals<'a>(
    static_values: &[f64; 4],
    values: &[f64; 2],
    rec: &'a DynamicRecord<'a>,
) -> Option<impl Iterator<Item = f64> + 'a> {
    let p = params(static_values, values)?;
    let mut s = LugreState::new();
    Some(
        rec.velocity
            .iter()
            .zip(rec.force)
            .map(move |(&v, &f)| s.step(&p, v, rec.dt) - f),
    )
}

/// Dynamic-stage cost of `[sigma0, sigma1]` with the static part fixed.
pub fn dynamic_cost(static_values: &[f64; 4], values: &[f64; 2], rec: &DynamicRecord<'_>) -> f64 {
    let Some(residuals) = dynamic_residuals(static_values, values, rec) else {
        return f64::MAX;
    };
    let n = rec.velocity.len().min(rec.force.len());
    let f_ref = rms(rec.force[..n].iter().copied());
    let sum: f64 = residuals.map(|r| (r / f_ref) * (r / f_ref)).sum();
    let c = sum / n.max(1) as f64;
    if c.is_finite() {
        c
    } else {
        f64::MAX
    }
}
