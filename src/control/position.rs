//! The cascade a hydraulics engineer builds:
//!
//! ```text
//! F_d = M a_ref + F_comp + Kx e + Kv (v_ref - v) + Ki int(e)            position -> force demand
//! u   = v_ref / v_full + KF (F_d - F) + KFi int(F_d - F)                 force loop -> valve
//! ```
//!
//! `e = x_ref - x`, `F = p_a A_a - p_b A_b` from the chamber pressures. The valve flow sets
//! the speed, so `v_ref / v_full` carries the motion and the force loop shapes the pressure
//! that moves the mass against friction. `u` is saturated to [-1, 1]; both integrators stop
//! while the output is saturated in their direction (conditional-integration anti-windup).

/// Cascade gains and limits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CascadeConfig {
    /// Kx [N/m].
    pub position_gain: f32,
    /// Kv [N s/m].
    pub velocity_gain: f32,
    /// Ki [N/(m s)].
    pub position_integral_gain: f32,
    /// KF [1/N] (valve command per newton of force error).
    pub force_gain: f32,
    /// KFi [1/(N s)].
    pub force_integral_gain: f32,
    /// Speed at full valve opening [m/s] (velocity feed-forward scale).
    pub full_opening_speed: f32,
    /// |integral of e| limit [m s].
    pub position_integral_limit: f32,
}

/// Cascade state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Cascade {
    /// Integral of the position error [m s].
    pub position_integral: f32,
    /// Integral of the force error (already times KFi) [-].
    pub force_integral: f32,
    /// Last valve command.
    pub command: f32,
}

/// One cascade evaluation's terms.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CascadeOut {
    /// Force demand \[N\].
    pub force_demand: f32,
    /// Valve command in [-1, 1].
    pub command: f32,
}

impl Cascade {
    /// Clears the integrators.
    pub fn reset(&mut self) {
        *self = Self::default();
    }

    /// One step.
    pub fn update(
        &mut self,
        c: &CascadeConfig,
        mass: f32,
        e: f32,
        v_err: f32,
        v_ref: f32,
        a_ref: f32,
        friction_compensation: f32,
        measured_force: f32,
        h: f32,
    ) -> CascadeOut {
        let force_demand = mass * a_ref
            + friction_compensation
            + c.position_gain * e
            + c.velocity_gain * v_err
            + c.position_integral_gain * self.position_integral;
        let f_err = force_demand - measured_force;
        let raw = v_ref / c.full_opening_speed + c.force_gain * f_err + self.force_integral;
        let command = raw.clamp(-1.0, 1.0);
        let saturated_up = raw > 1.0;
        let saturated_down = raw < -1.0;
        let pushes_up = |x: f32| x > 0.0;
        if !(saturated_up && pushes_up(f_err) || saturated_down && !pushes_up(f_err)) {
            self.force_integral += c.force_integral_gain * f_err * h;
        }
        if !(saturated_up && pushes_up(e) || saturated_down && !pushes_up(e)) {
            self.position_integral = (self.position_integral + e * h)
                .clamp(-c.position_integral_limit, c.position_integral_limit);
        }
        self.command = command;
        CascadeOut {
            force_demand,
            command,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn config() -> CascadeConfig {
        CascadeConfig {
            position_gain: 2.0e6,
            velocity_gain: 2.0e4,
            position_integral_gain: 2.0e7,
            force_gain: 1.0e-5,
            force_integral_gain: 2.0e-4,
            full_opening_speed: 0.6,
            position_integral_limit: 1e-3,
        }
    }

    /// Anti-windup: once the valve is saturated by an error that pushes further into
    /// saturation, neither integrator moves; the position integral never leaves its limit;
    /// and the command leaves saturation on the first period the error reverses.
    #[test]
    fn integrators_do_not_wind_up_in_saturation() {
        let c = config();
        let mut k = Cascade::default();
        // 10 mm behind and nothing moves: the command saturates at +1
        let mut out = k.update(&c, 200.0, 0.01, 0.0, 0.0, 0.0, 0.0, 0.0, 1e-3);
        let mut n = 0;
        while out.command < 1.0 {
            out = k.update(&c, 200.0, 0.01, 0.0, 0.0, 0.0, 0.0, 0.0, 1e-3);
            n += 1;
            assert!(n < 100_000, "never saturated");
        }
        let frozen = (k.position_integral, k.force_integral);
        for _ in 0..10_000 {
            let out = k.update(&c, 200.0, 0.01, 0.0, 0.0, 0.0, 0.0, 0.0, 1e-3);
            assert_eq!(out.command, 1.0);
        }
        assert_eq!((k.position_integral, k.force_integral), frozen);
        assert!(k.position_integral.abs() <= c.position_integral_limit);
        let out = k.update(&c, 200.0, -0.01, 0.0, 0.0, 0.0, 0.0, 0.0, 1e-3);
        assert!(out.command < 1.0, "still saturated: {}", out.command);
    }
}
