//! Disturbance observer (DOB): the practitioners' model-free friction compensation.
//!
//! With the actuator force `F` measured (from the chamber pressures) and the acceleration `a`
//! estimated, everything that is not inertia is disturbance: `d = F - M a` (friction, load,
//! model error). The observer low-passes it, `d_hat = Q(s) (F - M a)` with
//! `Q(s) = 1 / (1 + s / (2 pi f_Q))`, and the cascade adds `d_hat` to its force demand. The
//! zero-order-hold step of the first-order filter is exact at any period:
//! `d_hat += (1 - exp(-2 pi f_Q h)) (d - d_hat)`.
//!
//! Tuning rule (stated, not hand-picked per plant): `f_Q` is the value of [`TUNING_GRID_HZ`]
//! whose worst RMS error over the three robustness scenarios (`low_speed`, `point_to_point`,
//! `creep`; as a fraction of the plain cascade's) is lowest on the plain simulated axis with
//! realistic sensors; `host-sim track --robustness` prints the sweep. A higher `f_Q` follows
//! friction faster but passes more of the acceleration estimate's noise into the force
//! demand, and with stiction it can hunt.

/// The cut-offs the tuning rule tries \[Hz\].
pub const TUNING_GRID_HZ: [f32; 8] = [2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0, 400.0];

/// Disturbance observer state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DisturbanceObserver {
    /// Disturbance estimate `d_hat` \[N\].
    pub estimate_n: f32,
}

impl DisturbanceObserver {
    /// The filter's step gain `1 - exp(-2 pi f_Q h)` for cut-off `cutoff_hz` \[Hz\] and period
    /// `period_s` \[s\]: computed once per configuration, not every period.
    pub fn gain(cutoff_hz: f32, period_s: f32) -> f32 {
        1.0 - libm::expf(-2.0 * core::f32::consts::PI * cutoff_hz * period_s)
    }

    /// One period: measured actuator force \[N\], mass \[kg\], estimated acceleration [m/s^2],
    /// the step gain of [`Self::gain`]. Returns the new estimate; a non-finite input leaves it
    /// unchanged.
    pub fn update(
        &mut self,
        measured_force_n: f32,
        mass_kg: f32,
        acceleration_m_per_s2: f32,
        gain: f32,
    ) -> f32 {
        let d = measured_force_n - mass_kg * acceleration_m_per_s2;
        let next = self.estimate_n + gain * (d - self.estimate_n);
        if next.is_finite() {
            self.estimate_n = next;
        }
        self.estimate_n
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn follows_a_constant_disturbance_with_its_time_constant() {
        let mut dob = DisturbanceObserver::default();
        let k = DisturbanceObserver::gain(10.0, 1e-3);
        // 500 N of friction, no acceleration: after one time constant 63 % of it
        let tau = 1.0 / (2.0 * core::f32::consts::PI * 10.0);
        let n = (tau / 1e-3).round() as usize;
        for _ in 0..n {
            dob.update(500.0, 200.0, 0.0, k);
        }
        assert!(
            (dob.estimate_n / 500.0 - 0.632).abs() < 0.02,
            "{}",
            dob.estimate_n
        );
        for _ in 0..2000 {
            dob.update(500.0, 200.0, 0.0, k);
        }
        assert!((dob.estimate_n - 500.0).abs() < 1e-2);
        // inertia is not disturbance
        dob.update(500.0 + 200.0 * 3.0, 200.0, 3.0, k);
        assert!((dob.estimate_n - 500.0).abs() < 1e-2);
        // a NaN leaves the estimate as it was
        dob.update(f32::NAN, 200.0, 0.0, k);
        assert!((dob.estimate_n - 500.0).abs() < 1e-2);
    }
}
