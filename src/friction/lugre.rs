//! The LuGre state and its exact zero-order-hold step.
//!
//! With the velocity `v` held over a step of length `h`, the bristle equation
//! `dz/dt = v - a z` with `a = sigma0 |v| / g(v)` is linear with constant coefficients, and has
//! the exact solution
//!
//! ```text
//! z(h)     = z0 e^{-a h} + v h phi(a h),     phi(x) = (1 - e^{-x}) / x  (phi(0) = 1)
//! dz/dt(h) = (v - a z0) e^{-a h}
//! ```
//!
//! It is unconditionally stable (`e^{-a h}` is in (0, 1] for every step and velocity) and exact
//! for piecewise-constant velocity, so the only discretisation error is the one of holding `v`.
//! Explicit Euler, `z + h (v - a z)`, diverges once `a h > 2`, i.e. for Table 2 at 1 ms once
//! `|v| > 2 g / (sigma0 h) ~ 0.26 mm/s`. `phi` is evaluated with `expm1` so it keeps full
//! precision when `a h` is tiny (sticking, reversals).
//!
//! **Which velocity to hold.** Pass the *mean* velocity over the step, i.e. the displacement
//! divided by `dt` (what encoder differences give). In pre-sliding the force is
//! `sigma0 * displacement`, so holding the end-of-step velocity instead misstates the
//! displacement by `a_x h^2 / 2` and, with sigma0 = 3.9e9 N/m, costs ~245 N at the reversals of
//! a 10 mm, 0.5 Hz sinusoid. With the mean velocity the error against a fine-step RK4
//! reference is 2.4 N there, 0.5 N on a velocity ramp through the Stribeck region and 0.16 N on
//! slow reversals (test `lugre_numerics`).

use crate::math::{self, ModelFloat};

/// Result of one exact step of the bristle equation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BristleStep<T> {
    /// Deflection at the end of the step, z \[m\].
    pub deflection: T,
    /// Deflection rate at the end of the step, dz/dt [m/s].
    pub deflection_rate: T,
}

/// Exact zero-order-hold step of `dz/dt = v - sigma0 |v| z / g` over `dt` seconds.
///
/// `g` is the Stribeck level \[N\] (clamped to a tiny positive value), `sigma0` [N/m].
pub fn bristle_step<T: ModelFloat>(z: T, velocity: T, sigma0: T, g: T, dt: T) -> BristleStep<T> {
    driven_bristle_step(z, velocity, velocity, sigma0, g, dt)
}

/// Exact zero-order-hold step of `dz/dt = u - sigma0 |v| z / g`: the bristle equation driven
/// by `u` (the velocity itself in the model; velocity plus an error correction in an
/// observer) with the decay set by `v`.
pub fn driven_bristle_step<T: ModelFloat>(
    z: T,
    drive: T,
    velocity: T,
    sigma0: T,
    g: T,
    dt: T,
) -> BristleStep<T> {
    let g = g.max(T::min_positive_value());
    let rate = sigma0 * velocity.abs() / g; // a [1/s]
    let x = rate * dt;
    let decay = math::decay(x);
    // phi(x) = (1 - e^-x) / x from the one exponential: one exp per step instead of exp and
    // exp_m1 (the MCU's tick runs two steps). The subtraction loses about eps / x; below the
    // switch the series 1 - x/2 + x^2/6 - x^3/24 (exact to x^4/120) takes over. The switch,
    // (120 eps)^(1/4), balances the two: 0.06 in f32 (both errors ~2e-6), 4e-4 in f64 (~6e-13).
    let one = T::one();
    let two = one + one;
    let six = two * (two + one);
    let switch = if T::epsilon() > T::from(1e-10).unwrap_or_else(T::zero) {
        T::from(0.06)
    } else {
        T::from(4e-4)
    }
    .unwrap_or_else(T::epsilon);
    let phi = if x > switch {
        (one - decay) / x
    } else {
        one - x / two + x * x / six - x * x * x / (six * two * two)
    };
    BristleStep {
        deflection: z * decay + drive * dt * phi,
        deflection_rate: (drive - rate * z) * decay,
    }
}

/// Bristle state of a plain LuGre model (see [`crate::friction::FrictionModel`] for the model
/// with extra effects).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LugreState<T> {
    /// Average bristle deflection z \[m\].
    pub z: T,
}

impl<T: ModelFloat> LugreState<T> {
    /// A relaxed state (z = 0).
    pub fn new() -> Self {
        Self { z: T::zero() }
    }

    /// Advances by `dt` \[s\] with `velocity` [m/s] held, returns the friction force \[N\] at the
    /// end of the step: `sigma0 z + sigma1 dz/dt + sigma2 v`.
    pub fn step(&mut self, params: &super::LugreParams<T>, velocity: T, dt: T) -> T {
        let s = bristle_step(
            self.z,
            velocity,
            params.bristle_stiffness(),
            params.stribeck_curve(velocity),
            dt,
        );
        self.z = s.deflection;
        params.bristle_stiffness() * s.deflection
            + params.bristle_damping() * s.deflection_rate
            + params.viscous_coefficient() * velocity
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The step's deflection against the closed form `z e^-x + v dt (-expm1(-x) / x)` in f64,
    /// for `x` from 1e-7 to 30, across the switch to the series (4e-4 in f64, 0.06 in f32): f64
    /// to 1e-12 relative, f32 to 5e-6.
    #[test]
    fn one_exponential_gives_the_exact_step_on_both_sides_of_the_series_switch() {
        let (sigma0, g, dt, z0) = (1.0e6f64, 500.0, 1e-3, 2.0e-4);
        let mut x = 1e-7;
        while x < 30.0 {
            let v = x * g / (sigma0 * dt);
            let reference = z0 * (-x).exp() + v * dt * (-(-x).exp_m1() / x);
            let d64 = bristle_step(z0, v, sigma0, g, dt).deflection;
            assert!(
                (d64 - reference).abs() <= 1e-12 * reference.abs(),
                "f64 x {x}: {d64} vs {reference}"
            );
            let d32 =
                bristle_step(z0 as f32, v as f32, sigma0 as f32, g as f32, dt as f32).deflection;
            assert!(
                (f64::from(d32) - reference).abs() <= 5e-6 * reference.abs(),
                "f32 x {x}: {d32} vs {reference}"
            );
            x *= 1.37;
        }
    }
}
