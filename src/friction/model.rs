//! LuGre with extra effects: the one friction model the simulator, the diagnosis and the
//! compensator share.

use super::effects::{Conditions, Effects};
use super::lugre::bristle_step;
use super::LugreParams;
use num_traits::Float;

/// Friction levels in force at the current conditions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Levels<T> {
    /// Effective Coulomb force [N].
    pub coulomb: T,
    /// Effective static force [N] (>= coulomb).
    pub static_: T,
    /// Effective viscous coefficient [N s/m].
    pub viscous: T,
}

/// Mutable state of a [`FrictionModel`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrictionState<T> {
    /// Bristle deflection z [m].
    pub z: T,
    /// Time spent stuck before the current motion [s] (only used by `dwell_stiction`).
    pub dwell_time: T,
}

/// A LuGre model with optional extra effects (configuration only; state is separate).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionModel<T> {
    /// Base LuGre parameters.
    pub params: LugreParams<T>,
    /// Extra effects (all off: plain LuGre).
    pub effects: Effects<T>,
}

impl<T: Float> FrictionModel<T> {
    /// A plain LuGre model.
    pub fn plain(params: LugreParams<T>) -> Self {
        Self {
            params,
            effects: Effects::none(),
        }
    }

    /// Coulomb, static and viscous levels at velocity `v`, conditions `c` and dwell time.
    pub fn levels(&self, velocity: T, c: &Conditions<T>, dwell_time: T) -> Levels<T> {
        let p = &self.params;
        let e = &self.effects;
        let mut coulomb = p.coulomb_force();
        let mut static_ = p.static_force();
        let mut viscous = p.viscous_coefficient();
        if let Some(a) = e.asymmetry {
            let s = if velocity >= T::zero() { T::one() } else { -T::one() };
            coulomb = coulomb * (T::one() + s * a.coulomb_ratio);
            static_ = static_ * (T::one() + s * a.coulomb_ratio);
            viscous = viscous * (T::one() + s * a.viscous_ratio);
        }
        let mut shift = T::zero();
        if let Some(l) = e.load_dependence {
            shift = shift + l.coefficient * (c.pressure_sum - l.reference_pressure_sum);
        }
        if let Some(x) = e.position_dependence {
            shift = shift + x.gradient * (c.position - x.center);
        }
        coulomb = coulomb + shift;
        static_ = static_ + shift;
        if let Some(t) = e.temperature_dependence {
            let dt = c.temperature - t.reference_temperature;
            let scale = T::one() + t.coulomb_per_kelvin * dt;
            coulomb = coulomb * scale;
            static_ = static_ * scale;
            viscous = viscous * (-t.viscous_per_kelvin * dt).exp();
        }
        if let Some(d) = e.dwell_stiction {
            let tau = d.time_constant.max(T::min_positive_value());
            static_ = static_ + d.max_increase * (-(-dwell_time / tau).exp_m1());
        }
        // A seal never pushes: keep levels physical whatever the conditions.
        let tiny = T::from(1e-6).unwrap_or_else(T::epsilon);
        let coulomb = coulomb.max(tiny);
        Levels {
            coulomb,
            static_: static_.max(coulomb),
            viscous: viscous.max(T::zero()),
        }
    }

    /// Stribeck level `g(v)` [N] for the given levels.
    pub fn stribeck_curve(&self, velocity: T, l: &Levels<T>) -> T {
        let r = (velocity / self.params.stribeck_velocity()).abs();
        let shape = match self.effects.stribeck_shape {
            Some(s) => r.powf(s.exponent),
            None => r * r,
        };
        l.coulomb + (l.static_ - l.coulomb) * (-shape).exp()
    }

    /// Viscous force [N] for the given levels.
    pub fn viscous_force(&self, velocity: T, l: &Levels<T>) -> T {
        match self.effects.viscous_power {
            Some(p) => {
                let vr = p.reference_velocity.max(T::min_positive_value());
                let mag = l.viscous * vr * (velocity.abs() / vr).powf(p.exponent);
                if velocity < T::zero() {
                    -mag
                } else {
                    mag
                }
            }
            None => l.viscous * velocity,
        }
    }

    /// Constant external force [N] (zero without `offset`).
    pub fn offset_force(&self) -> T {
        self.effects.offset.map_or(T::zero(), |o| o.force)
    }

    /// Steady-state friction at constant velocity (after a long slide: no dwell) [N],
    /// including the offset.
    pub fn steady_state_force(&self, velocity: T, c: &Conditions<T>) -> T {
        let l = self.levels(velocity, c, T::zero());
        let dir = if velocity > T::zero() {
            T::one()
        } else if velocity < T::zero() {
            -T::one()
        } else {
            T::zero()
        };
        self.stribeck_curve(velocity, &l) * dir + self.viscous_force(velocity, &l) + self.offset_force()
    }

    /// Advances the state by `dt` [s] with `velocity` [m/s] held (exact zero-order hold of the
    /// bristle equation, see [`crate::friction::lugre`]), returns the force [N] at the end of
    /// the step: `sigma0 z + sigma1 dz/dt + F_visc(v) + F0`.
    pub fn step(&self, s: &mut FrictionState<T>, velocity: T, c: &Conditions<T>, dt: T) -> T {
        if let Some(d) = self.effects.dwell_stiction {
            // Timer runs while stuck, is frozen through the Stribeck region (so the breakaway
            // sees the full dwell), and resets once the axis slides.
            let speed = velocity.abs();
            let three = T::from(3.0).unwrap_or_else(T::one);
            if speed < d.stick_velocity {
                s.dwell_time = s.dwell_time + dt;
            } else if speed > three * self.params.stribeck_velocity() {
                s.dwell_time = T::zero();
            }
        }
        let l = self.levels(velocity, c, s.dwell_time);
        let g = self.stribeck_curve(velocity, &l);
        let sigma0 = self.params.bristle_stiffness();
        let b = bristle_step(s.z, velocity, sigma0, g, dt);
        s.z = b.deflection;
        sigma0 * b.deflection
            + self.params.bristle_damping() * b.deflection_rate
            + self.viscous_force(velocity, &l)
            + self.offset_force()
    }
}
