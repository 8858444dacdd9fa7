//! Online refinement of the identified parameters: recursive least squares with forgetting on
//! the part of the steady friction that is linear in the parameters, with `vs` fixed:
//!
//! ```text
//! F_fric = Fc d + (Fs - Fc) s(v) d + sigma2 v = phi' theta,   d = sign(v)
//! phi = [d, s(v) d, v],   theta = [Fc, Fs - Fc, sigma2]
//! K = P phi / (lambda + phi' P phi),  theta += K (y - phi' theta),  P = (P - K phi' P) / lambda
//! ```
//!
//! `s(v)` is the model's own Stribeck decay ([`crate::friction::FrictionModel::stribeck_decay`]:
//! `exp(-(v/vs)^2)`, or its shape's exponent, with the direction's `vs` under asymmetry).
//! `y` is the friction the axis felt, `F_measured - M a`. Both `y` and `phi` pass through the
//! same first-order low-pass (the acceleration estimate is noisy). Updates happen only when the
//! motion excites the parameters: clear sliding (`|v| > v_min`, default 15 mm/s = 3 vs of
//! Table 2: inside the Stribeck region Fc and Fs - Fc are nearly collinear and a slow
//! oscillation through it made the estimate wander and the tracking worse), not accelerating
//! hard, and not in a fault. Consequently Fs - Fc, whose regressor has died out by then, stays
//! close to its identified value: drift shows in Fc and sigma2. Each update is rate limited, and `theta` is projected onto physical bounds
//! (`Fc, Fs - Fc, sigma2` within `[lo, hi]` around the identified values). sigma0 and sigma1
//! stay as identified: they act only in microsecond bristle transients that 1 kHz data cannot
//! resolve, so adapting them online would chase noise.

use nalgebra::{Matrix2, Vector2};

/// Refinement settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RefineConfig {
    /// Forgetting factor lambda (0.9995 at 1 kHz: memory ~2 s).
    pub forgetting: f32,
    /// Minimum speed for an update [m/s].
    pub min_speed: f32,
    /// Maximum |acceleration| for an update [m/s^2].
    pub max_acceleration: f32,
    /// Maximum parameter change per update, relative to the identified value [-].
    pub max_step: f32,
    /// Bounds, relative to the identified values: `[lo, hi]` factors.
    pub bounds: [f32; 2],
    /// Low-pass coefficient of `y` and `phi` per sample (0..1).
    pub smoothing: f32,
}

impl Default for RefineConfig {
    fn default() -> Self {
        Self {
            forgetting: 0.9995,
            min_speed: 1.5e-2,
            max_acceleration: 0.5,
            max_step: 2e-3,
            bounds: [0.5, 2.0],
            smoothing: 0.05,
        }
    }
}

/// RLS state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Refiner {
    /// Current estimate `[Fc, Fs - Fc, sigma2]` (Fs - Fc = rho Fc).
    pub theta: [f32; 3],
    /// Identified values (the centre of the bounds).
    pub nominal: [f32; 3],
    /// `(Fs - Fc) / Fc` of the identified values, held.
    rho: f32,
    /// The identified `[Fc, sigma2]`: the centre of the bounds and of the step limits.
    centre: Vector2<f32>,
    /// `(0.1 max(|centre_i|, 1))^2`: the prior variances (a 10 % standard deviation), the
    /// covariance's start and the cap of its diagonal against wind-up.
    prior_variance: Vector2<f32>,
    /// `[Fc, sigma2]`: what the least squares estimates.
    est: Vector2<f32>,
    /// Its covariance.
    p: Matrix2<f32>,
    y_f: f32,
    phi_f: Vector2<f32>,
}

impl Refiner {
    /// Starts at the identified values `[Fc, Fs - Fc, sigma2]`.
    pub fn new(nominal: [f32; 3]) -> Self {
        let centre = Vector2::new(nominal[0], nominal[2]);
        let prior_variance = centre.map(|e| 1e-2 * e.abs().max(1.0) * e.abs().max(1.0));
        Self {
            theta: nominal,
            nominal,
            rho: nominal[1] / nominal[0].max(1e-6),
            centre,
            prior_variance,
            est: centre,
            p: Matrix2::from_diagonal(&prior_variance),
            y_f: 0.0,
            phi_f: Vector2::zeros(),
        }
    }

    /// Resets to the identified values.
    pub fn reset(&mut self) {
        *self = Self::new(self.nominal);
    }

    /// One sample: measured friction `y` \[N\], velocity [m/s], acceleration [m/s^2], and the
    /// model's Stribeck decay at that velocity, `s(v)` in [0, 1]. Returns true if the
    /// estimate was updated.
    pub fn update(
        &mut self,
        c: &RefineConfig,
        y: f32,
        v: f32,
        a: f32,
        stribeck_decay: f32,
    ) -> bool {
        let d = if v >= 0.0 { 1.0 } else { -1.0 };
        let phi = Vector2::new(d * (1.0 + self.rho * stribeck_decay), v);
        let s = c.smoothing;
        self.y_f += s * (y - self.y_f);
        self.phi_f += (phi - self.phi_f) * s;
        let excited = v.abs() > c.min_speed && a.abs() < c.max_acceleration && y.is_finite();
        if !excited {
            return false;
        }
        let ph = self.phi_f;
        let pp = self.p * ph;
        let denom = c.forgetting + ph.dot(&pp);
        if !(denom.is_finite() && denom > 0.0) {
            self.reset();
            return false;
        }
        let err = self.y_f - ph.dot(&self.est);
        let gain = pp / denom;
        let centre = self.centre;
        for i in 0..2 {
            let limit = c.max_step * centre[i].abs();
            let step = (gain[i] * err).clamp(-limit, limit);
            self.est[i] =
                (self.est[i] + step).clamp(c.bounds[0] * centre[i], c.bounds[1] * centre[i]);
        }
        // pp pp' / denom, not gain pp': the product of a vector with itself is exactly
        // symmetric in floating point, and a covariance that drifts from symmetry made the
        // estimate run to its bound in the warming-oil test (Fc 253 N against 608)
        let mut next = (self.p - pp * pp.transpose() / denom) / c.forgetting;
        // covariance wind-up guard: cap the diagonal at its initial size
        for i in 0..2 {
            next[(i, i)] = next[(i, i)].clamp(0.0, self.prior_variance[i]);
        }
        if next.iter().all(|x| x.is_finite()) && self.est.iter().all(|x| x.is_finite()) {
            self.p = next;
            self.theta = [self.est[0], self.rho * self.est[0], self.est[1]];
            true
        } else {
            self.reset();
            false
        }
    }
}
