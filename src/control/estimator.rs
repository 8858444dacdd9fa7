//! Velocity and acceleration from a quantised encoder: an alpha-beta-gamma tracking filter.
//!
//! ```text
//! predict:  x- = x + v h + a h^2 / 2,   v- = v + a h,   a- = a
//! correct:  r = x_meas - x-
//!           x = x- + alpha r,  v = v- + beta r / h,  a = a- + 2 gamma r / h^2
//! ```
//!
//! With the default `alpha = 0.4, beta = 0.06, gamma = 0.002` (a critically damped
//! steady-state Kalman design for a random-jerk model), a 0.1 um encoder at 1 kHz gives a
//! velocity noise of ~10 um/s rms and the velocity lags a ramp by about `(1 - alpha) / beta`
//! ~ 10 samples' worth of position innovation at constant acceleration, i.e. ~4 ms of delay
//! for slow motions. The mean velocity over the last period (`displacement / h` of the
//! filtered position) is also kept: the LuGre observer's exact step needs it.

/// Filter gains.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EstimatorConfig {
    /// Position gain alpha [-].
    pub alpha: f32,
    /// Velocity gain beta [-].
    pub beta: f32,
    /// Acceleration gain gamma [-].
    pub gamma: f32,
}

impl Default for EstimatorConfig {
    fn default() -> Self {
        Self {
            alpha: 0.4,
            beta: 0.06,
            gamma: 0.002,
        }
    }
}

/// Filter state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Estimator {
    /// Filtered position \[m\].
    pub position: f32,
    /// Velocity [m/s].
    pub velocity: f32,
    /// Acceleration [m/s^2].
    pub acceleration: f32,
    /// Mean velocity over the last period [m/s].
    pub mean_velocity: f32,
    initialised: bool,
}

impl Estimator {
    /// Starts at rest at `x` \[m\].
    pub fn reset(&mut self, x: f32) {
        *self = Self {
            position: x,
            initialised: true,
            ..Default::default()
        };
    }

    /// One update with the measured position `x` \[m\] after `h` seconds.
    pub fn update(&mut self, c: &EstimatorConfig, x: f32, h: f32) {
        if !self.initialised {
            self.reset(x);
            return;
        }
        let old = self.position;
        let xp = self.position + self.velocity * h + 0.5 * self.acceleration * h * h;
        let vp = self.velocity + self.acceleration * h;
        let r = x - xp;
        self.position = xp + c.alpha * r;
        self.velocity = vp + c.beta * r / h;
        self.acceleration += 2.0 * c.gamma * r / (h * h);
        self.mean_velocity = (self.position - old) / h;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On a ramp (constant velocity) the alpha-beta-gamma filter has no steady-state lag in
    /// position or velocity; on a parabola its velocity settles without lag either (a type-3
    /// tracker); a step of the measurement is followed within the filter's settling time.
    #[test]
    fn tracks_ramps_and_parabolas_without_lag() {
        let c = EstimatorConfig::default();
        let h = 1e-3;
        let mut e = Estimator::default();
        for k in 0..2000 {
            e.update(&c, 0.1 + 0.02 * k as f32 * h, h);
        }
        assert!((e.velocity - 0.02).abs() < 1e-4, "{}", e.velocity);
        assert!((e.position - (0.1 + 0.02 * 1999.0 * h)).abs() < 1e-6);
        assert!(e.acceleration.abs() < 1e-2);
        let mut e = Estimator::default();
        for k in 0..3000 {
            let t = k as f32 * h;
            e.update(&c, 0.1 + 0.5 * 0.4 * t * t, h);
        }
        assert!((e.velocity - 0.4 * 2.999).abs() < 2e-3, "{}", e.velocity);
        assert!((e.acceleration - 0.4).abs() < 2e-2, "{}", e.acceleration);
    }
}
