//! LuGre with extra effects: the one friction model the simulator, the diagnosis and the
//! compensator share.

use super::effects::{Conditions, Effects};
use super::lugre::driven_bristle_step;
use super::LugreParams;
use crate::math::{self, ModelFloat};
use num_traits::Float;

/// Friction levels in force at the current conditions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Levels<T> {
    /// Effective Coulomb force \[N\].
    pub coulomb: T,
    /// Effective static force \[N\] (>= coulomb).
    pub static_: T,
    /// Effective viscous coefficient [N s/m].
    pub viscous: T,
}

/// The levels of a model in which they do not depend on the conditions or the dwell time,
/// forward (v >= 0) and backward: only [`FrictionModel::constant_levels`] makes them, so a
/// step given them cannot be given the levels of some other conditions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConstantLevels<T> {
    forward: Levels<T>,
    backward: Levels<T>,
}

/// What one step of [`FrictionModel::step_split_with_curve`] did, for an inverse model that
/// reads more than the force: the levels it stepped at, so that nothing is evaluated twice.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveStep<T> {
    /// Friction force at the end of the step \[N\].
    pub force: T,
    /// The Stribeck level `g(v)` of the bristle step \[N\] (at the mean velocity, after the
    /// dwell clock moved): the bristle's loading is `sigma0 z / g`.
    pub stribeck_level: T,
    /// The levels forward (v >= 0) at the step's conditions and dwell time.
    pub forward: Levels<T>,
    /// The levels backward (v < 0) at the step's conditions and dwell time.
    pub backward: Levels<T>,
}

/// What one set of conditions (pressure, position, temperature) does to a model's levels,
/// whatever the direction and the dwell time ([`FrictionModel::under`]): evaluated once, it
/// serves every step and force taken at those conditions. It depends on the model's effects
/// only, not on its parameters, so models that differ in their levels alone share it (a
/// controller's refined model and the identified one its health monitor compares with). A
/// controller steps its feed-forward and its observer at one period's conditions; a position
/// dependence's cosine series (one `cos` whose libm kernel runs in double precision,
/// soft-float on a Cortex-M4F) is then evaluated once a period instead of once a use.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnderConditions<T> {
    /// `load_dependence`'s level shift `dF(p)` \[N\] (its scales depend on a model's `Fs`:
    /// each model takes them from this shift).
    load_shift: Option<T>,
    /// Added to both levels by `position_dependence` \[N\] (0 without it).
    position_shift: T,
    /// `temperature_dependence`'s scale of both levels and factor of the viscous coefficient.
    temperature: Option<(T, T)>,
    /// `temperature_dependence`'s factor of the Stribeck velocity, `eta^-q` (1 without it or
    /// with `q = 0`): formed here once, so a step pays one multiplication, not a power.
    stribeck_velocity_scale: T,
}

/// Mutable state of a [`FrictionModel`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrictionState<T> {
    /// Bristle deflection z \[m\].
    pub z: T,
    /// Time spent stuck before the current motion \[s\] (only used by `dwell_stiction`).
    pub dwell_time: T,
    /// Bristle deflection rate dz/dt at the end of the last step [m/s] (what `sigma1`
    /// multiplies; kept so an identification can regress on it).
    pub deflection_rate: T,
    /// Whether the dwell clock counted the last step as sliding: a stick that follows
    /// restarts a [`DwellAge::Restarts`](super::DwellAge::Restarts) age (false at the start,
    /// so a state's given dwell time carries into a first stick).
    pub sliding: bool,
}

/// A LuGre model with optional extra effects (configuration only; state is separate).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionModel<T> {
    /// Base LuGre parameters.
    pub params: LugreParams<T>,
    /// Extra effects (all off: plain LuGre).
    pub effects: Effects<T>,
}

impl<T: ModelFloat> FrictionModel<T> {
    /// The same model in another float type (the parameters validated again by
    /// [`LugreParams::cast`]).
    pub fn cast<U: Float>(&self) -> Result<FrictionModel<U>, crate::friction::ParamError> {
        Ok(FrictionModel {
            params: self.params.cast()?,
            effects: self.effects.cast(),
        })
    }

    /// A plain LuGre model.
    pub fn plain(params: LugreParams<T>) -> Self {
        Self {
            params,
            effects: Effects::none(),
        }
    }

    /// Coulomb, static and viscous levels at velocity `v`, conditions `c` and dwell time.
    pub fn levels(&self, velocity: T, c: &Conditions<T>, dwell_time: T) -> Levels<T> {
        self.levels_in(
            velocity >= T::zero(),
            &self.under(c),
            self.dwell_increase(dwell_time),
        )
    }

    /// The levels of both directions, forward (v >= 0) then backward, at conditions `c` and
    /// dwell time: the conditions' factors (a power, cosines, exponentials) are evaluated
    /// once for both.
    #[inline]
    pub fn levels_by_direction(&self, c: &Conditions<T>, dwell_time: T) -> (Levels<T>, Levels<T>) {
        self.levels_by_direction_under(&self.under(c), dwell_time)
    }

    /// [`Self::levels_by_direction`] at conditions already evaluated ([`Self::under`]).
    #[inline]
    pub fn levels_by_direction_under(
        &self,
        f: &UnderConditions<T>,
        dwell_time: T,
    ) -> (Levels<T>, Levels<T>) {
        let dwell_increase = self.dwell_increase(dwell_time);
        let forward = self.levels_in(true, f, dwell_increase);
        let backward = if self.effects.asymmetry.is_some() {
            self.levels_in(false, f, dwell_increase)
        } else {
            forward
        };
        (forward, backward)
    }

    /// `dwell_stiction`'s increase of the static level after `dwell_time` \[s\] at rest \[N\]
    /// (`None` without it).
    #[inline(always)]
    fn dwell_increase(&self, dwell_time: T) -> Option<T> {
        self.effects
            .dwell_stiction
            .map(|d| d.max_increase * d.grown_share(dwell_time))
    }

    /// What conditions `c` do to the levels of this model, and of every model with its effects,
    /// evaluated once for every step and force taken at them ([`UnderConditions`]).
    #[inline]
    pub fn under(&self, c: &Conditions<T>) -> UnderConditions<T> {
        let e = &self.effects;
        UnderConditions {
            // the seal's normal force grows with the pressure (the levels scale with it)
            load_shift: e.load_dependence.map(|l| l.shift(c.pressure_sum)),
            position_shift: e
                .position_dependence
                .map_or(T::zero(), |x| x.shift(c.position)),
            temperature: e.temperature_dependence.map(|t| {
                let dt = c.temperature - t.reference_temperature;
                (
                    T::one() + t.coulomb_per_kelvin * dt,
                    (-t.viscous_per_kelvin * dt).exp(),
                )
            }),
            stribeck_velocity_scale: e
                .temperature_dependence
                .map_or(T::one(), |t| t.stribeck_velocity_scale(c.temperature)),
        }
    }

    /// The levels in one direction (`forward`: v >= 0) at the conditions `f` and the dwell's
    /// increase.
    #[inline]
    fn levels_in(
        &self,
        forward: bool,
        f: &UnderConditions<T>,
        dwell_increase: Option<T>,
    ) -> Levels<T> {
        let p = &self.params;
        let mut coulomb = p.coulomb_force();
        let mut static_ = p.static_force();
        let mut viscous = p.viscous_coefficient();
        if let Some(a) = self.effects.asymmetry {
            let s = if forward { T::one() } else { -T::one() };
            coulomb = coulomb * (T::one() + s * a.coulomb_ratio);
            static_ = static_ * (T::one() + s * a.static_ratio);
            viscous = viscous * (T::one() + s * a.viscous_ratio);
        }
        if let (Some(l), Some(shift)) = (&self.effects.load_dependence, f.load_shift) {
            // the levels scale with the shift over Fs (> 0, a LugreParams invariant)
            let (scale, hump_scale) = l.scales(shift, p.static_force());
            // the hump by its own share of the change (a static level below the Coulomb one is
            // clamped below)
            let hump = static_ - coulomb;
            coulomb = coulomb * scale;
            static_ = coulomb + hump * hump_scale;
        }
        coulomb = coulomb + f.position_shift;
        static_ = static_ + f.position_shift;
        if let Some((scale, viscous_factor)) = f.temperature {
            coulomb = coulomb * scale;
            static_ = static_ * scale;
            viscous = viscous * viscous_factor;
        }
        if let Some(increase) = dwell_increase {
            static_ = static_ + increase;
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

    /// Stribeck level `g(v)` \[N\] for the given levels:
    /// `Fc + (Fs - Fc) s(v)`, `s` the [`Self::stribeck_decay`].
    pub fn stribeck_curve(&self, velocity: T, l: &Levels<T>) -> T {
        Self::curve_from_decay(l, self.stribeck_decay(velocity))
    }

    /// The Stribeck curve's decay `s(v) = e^{-(|v| / vs)^delta}` (`delta` = 2 without
    /// `stribeck_shape`; `vs` the direction's, `(1 ± rvs) vs` with `asymmetry`), in `[0, 1]`.
    /// It depends on the velocity, `vs`, `rvs` and `delta` only, not on the levels: a caller
    /// that steps many models sharing them along one velocity record computes it once per
    /// sample (see [`Self::step_split_with_curve`]).
    ///
    /// This is the decay at the reference conditions: with `temperature_dependence`'s
    /// `q != 0` the curve moves with the oil temperature, and [`Self::stribeck_decay_under`]
    /// gives it at a period's conditions.
    #[inline]
    pub fn stribeck_decay(&self, velocity: T) -> T {
        self.stribeck_decay_scaled(velocity, T::one())
    }

    /// [`Self::stribeck_decay`] at conditions already evaluated ([`Self::under`]): `vs` scaled
    /// by `temperature_dependence`'s `eta^-q` (the same, bit for bit, where that is 1).
    #[inline]
    pub fn stribeck_decay_under(&self, velocity: T, f: &UnderConditions<T>) -> T {
        self.stribeck_decay_scaled(velocity, f.stribeck_velocity_scale)
    }

    /// [`Self::stribeck_decay`] at oil temperature `temperature` \[degC\] alone: the one
    /// condition that moves the curve. A caller that needs the decay but not the levels
    /// (an inverse model's decay along a record) forms only its factor, not every factor
    /// [`Self::under`] evaluates. The same, bit for bit, as
    /// [`Self::stribeck_decay_under`] at conditions with that temperature.
    #[inline]
    pub fn stribeck_decay_at(&self, velocity: T, temperature: T) -> T {
        self.stribeck_decay_scaled(velocity, self.stribeck_velocity_scale_at(temperature))
    }

    /// The Stribeck velocity's factor at oil temperature `temperature` \[degC\]
    /// (`temperature_dependence`'s `eta^-q`; 1 without it).
    #[inline]
    fn stribeck_velocity_scale_at(&self, temperature: T) -> T {
        self.effects
            .temperature_dependence
            .map_or(T::one(), |t| t.stribeck_velocity_scale(temperature))
    }

    /// The decay with the Stribeck velocity scaled by `vs_scale` (> 0).
    #[inline(always)]
    fn stribeck_decay_scaled(&self, velocity: T, vs_scale: T) -> T {
        let r = self.stribeck_ratio(velocity, vs_scale);
        match self.effects.stribeck_shape {
            // a slow second scale: `(1 - w) exp(-r^delta) + w exp(-r / k)` (a share past 1 or
            // a scale not above 0, or either not a number, kept finite: never NaN at rest)
            Some(s) if s.tail_share > T::zero() => {
                let w = s.tail_share.min(T::one());
                (T::one() - w) * math::decay(r.powf(s.exponent))
                    + w * math::decay(r / s.tail_scale.max(T::epsilon()))
            }
            Some(s) => math::decay(r.powf(s.exponent)),
            None => math::decay(r * r),
        }
    }

    /// How a Stribeck tail's share moves the decay at `velocity` \[m/s\] and oil temperature
    /// `temperature` \[degC\]: `d(decay)/dw = exp(-r / k) - exp(-r^delta)`, `r = |v| / vs`
    /// (the Stribeck velocity as [`Self::stribeck_decay_at`] scales it). Zero without a
    /// `stribeck_shape`.
    pub fn stribeck_tail_sensitivity_at(&self, velocity: T, temperature: T) -> T {
        let Some(s) = self.effects.stribeck_shape else {
            return T::zero();
        };
        let r = self.stribeck_ratio(velocity, self.stribeck_velocity_scale_at(temperature));
        math::decay(r / s.tail_scale.max(T::epsilon())) - math::decay(r.powf(s.exponent))
    }

    /// `|v| / vs`, the Stribeck velocity scaled by `vs_scale` and by the direction's ratio.
    #[inline(always)]
    fn stribeck_ratio(&self, velocity: T, vs_scale: T) -> T {
        let mut vs = self.params.stribeck_velocity() * vs_scale;
        if let Some(a) = self.effects.asymmetry {
            let s = if velocity >= T::zero() {
                T::one()
            } else {
                -T::one()
            };
            // a ratio at or past 1 (or not a number) would stop one direction's hump
            let least = T::from(0.05).unwrap_or_else(T::epsilon);
            vs = vs * (T::one() + s * a.stribeck_velocity_ratio).max(least);
        }
        (velocity / vs).abs()
    }

    #[inline]
    fn curve_from_decay(l: &Levels<T>, decay: T) -> T {
        l.coulomb + (l.static_ - l.coulomb) * decay
    }

    /// Viscous force \[N\] for the given levels.
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

    /// Constant external force \[N\] (zero without `offset`).
    pub fn offset_force(&self) -> T {
        self.effects.offset.map_or(T::zero(), |o| o.force)
    }

    /// Steady-state friction at constant velocity (after a long slide: no dwell) \[N\],
    /// including the offset.
    pub fn steady_state_force(&self, velocity: T, c: &Conditions<T>) -> T {
        self.steady_state_force_under(velocity, &self.under(c))
    }

    /// [`Self::steady_state_force`] at conditions already evaluated ([`Self::under`]).
    pub fn steady_state_force_under(&self, velocity: T, f: &UnderConditions<T>) -> T {
        let l = self.levels_in(velocity >= T::zero(), f, self.dwell_increase(T::zero()));
        let dir = super::params::direction(velocity);
        Self::curve_from_decay(&l, self.stribeck_decay_under(velocity, f)) * dir
            + self.viscous_force(velocity, &l)
            + self.offset_force()
    }

    /// Advances the state by `dt` \[s\] with `velocity` [m/s] held (exact zero-order hold of the
    /// bristle equation, see [`crate::friction::lugre`]), returns the force \[N\] at the end of
    /// the step: `sigma0 z + sigma1 dz/dt + F_visc(v) + F0`.
    pub fn step(&self, s: &mut FrictionState<T>, velocity: T, c: &Conditions<T>, dt: T) -> T {
        self.step_split(s, velocity, velocity, c, dt)
    }

    /// As [`Self::step`], with the bristle state driven by the mean velocity over the step
    /// (displacement / dt, exact for the pre-sliding spring) and the viscous force taken at
    /// the velocity at the end of the step. With `mean_velocity` from backward differences,
    /// a single velocity would make the viscous term lag half a sample, which an inverse
    /// model reads as `sigma2 dt / 2` of extra mass (24.5 kg for Table 2 at 1 kHz).
    pub fn step_split(
        &self,
        s: &mut FrictionState<T>,
        mean_velocity: T,
        velocity: T,
        c: &Conditions<T>,
        dt: T,
    ) -> T {
        self.step_driven(s, mean_velocity, mean_velocity, velocity, c, dt)
    }

    /// As [`Self::step_split`], also returning the Stribeck level `g(v)` \[N\] and the levels
    /// the step used ([`CurveStep`]): an inverse model reads the bristle's loading
    /// `sigma0 z / g` and the static levels that bound a held force from it without
    /// evaluating the levels a second time.
    ///
    /// `stribeck_decay`, when given, is [`Self::stribeck_decay`]`(mean_velocity)` of a model
    /// with this one's `vs` and shape (then the result is the same, bit for bit; a value
    /// outside `[0, 1]`, NaN included, is not used: the step computes the decay itself). An
    /// inverse model that refits the levels many times along one record computes the decay
    /// once per sample instead of once per sample and model.
    pub fn step_split_with_curve(
        &self,
        s: &mut FrictionState<T>,
        mean_velocity: T,
        velocity: T,
        c: &Conditions<T>,
        dt: T,
        stribeck_decay: Option<T>,
    ) -> CurveStep<T> {
        let f = self.under(c);
        let (forward, backward) = self.clock_and_levels(s, mean_velocity, &f, dt);
        let (force, stribeck_level) = self.step_driven_at_levels(
            s,
            mean_velocity,
            mean_velocity,
            velocity,
            dt,
            stribeck_decay,
            f.stribeck_velocity_scale,
            forward,
            backward,
        );
        CurveStep {
            force,
            stribeck_level,
            forward,
            backward,
        }
    }

    /// As [`Self::step_split`], with the bristle equation driven by `drive`
    /// (`dz/dt = drive - sigma0 |v| z / g(v)`): the mean velocity itself in the model, the mean
    /// velocity plus an error correction in an observer. The state is projected onto
    /// `|z| <= Fs / sigma0` at the current levels, the invariant set of the true state: a
    /// no-op for the model (the exact step keeps `z` inside), and what keeps an observer bounded
    /// at standstill, where the decay vanishes and the correction keeps driving.
    pub fn step_driven(
        &self,
        s: &mut FrictionState<T>,
        drive: T,
        mean_velocity: T,
        velocity: T,
        c: &Conditions<T>,
        dt: T,
    ) -> T {
        self.step_driven_under(s, drive, mean_velocity, velocity, &self.under(c), dt)
    }

    /// [`Self::step_driven`] at conditions already evaluated ([`Self::under`]): the same result,
    /// bit for bit.
    pub fn step_driven_under(
        &self,
        s: &mut FrictionState<T>,
        drive: T,
        mean_velocity: T,
        velocity: T,
        f: &UnderConditions<T>,
        dt: T,
    ) -> T {
        let (forward, backward) = self.clock_and_levels(s, mean_velocity, f, dt);
        self.step_driven_at_levels(
            s,
            drive,
            mean_velocity,
            velocity,
            dt,
            None,
            f.stribeck_velocity_scale,
            forward,
            backward,
        )
        .0
    }

    /// Moves the dwell clock over a step at `mean_velocity` and returns the levels of both
    /// directions, forward then backward, at conditions `c` and the clock's new time: the
    /// levels depend on the velocity only through the direction of `asymmetry`, so one
    /// evaluation per direction serves the step, the bound and the viscous force.
    #[inline(always)]
    fn clock_and_levels(
        &self,
        s: &mut FrictionState<T>,
        mean_velocity: T,
        f: &UnderConditions<T>,
        dt: T,
    ) -> (Levels<T>, Levels<T>) {
        if let Some(d) = self.effects.dwell_stiction {
            // Timer runs while stuck (from zero at each stick when the age restarts) and is
            // forgotten over the renewal distance once the axis slides; under the aging law it
            // runs and is forgotten at once, at every speed (a distance that is zero, negative
            // or not a number forgets at once).
            let speed = match d.clock {
                super::DwellClock::BodySpeed => mean_velocity.abs(),
                super::DwellClock::ContactSlip => (mean_velocity - s.deflection_rate).abs(),
            };
            if d.age_at_stick == super::DwellAge::Aging {
                s.sliding = speed >= d.stick_velocity;
                s.dwell_time = share_of_renewal(speed, dt, d.renewal_distance)
                    .map_or(T::zero(), |slid| (s.dwell_time + dt) / (T::one() + slid));
            } else if speed < d.stick_velocity {
                if s.sliding && d.age_at_stick == super::DwellAge::Restarts {
                    s.dwell_time = T::zero();
                }
                s.sliding = false;
                s.dwell_time = s.dwell_time + dt;
            } else {
                s.sliding = true;
                s.dwell_time = share_of_renewal(speed, dt, d.renewal_distance)
                    .map_or(T::zero(), |slid| s.dwell_time * (-slid).exp());
            }
        }
        self.levels_by_direction_under(f, s.dwell_time)
    }

    /// The levels of both directions when nothing makes them depend on the conditions or
    /// the dwell time (no load, position, temperature or dwell effect): the same at every
    /// sample, so a caller stepping the model along a record evaluates them once. `None`
    /// otherwise.
    pub fn constant_levels(&self) -> Option<ConstantLevels<T>> {
        // every field named: an effect added later must be placed on one side or the other
        let Effects {
            asymmetry: _,
            offset: _,
            viscous_power: _,
            stribeck_shape: _,
            load_dependence,
            position_dependence,
            temperature_dependence,
            dwell_stiction,
        } = self.effects;
        if load_dependence.is_some()
            || position_dependence.is_some()
            || temperature_dependence.is_some()
            || dwell_stiction.is_some()
        {
            return None;
        }
        let anywhere = Conditions {
            position: T::zero(),
            pressure_sum: T::zero(),
            temperature: T::zero(),
        };
        let (forward, backward) = self.levels_by_direction(&anywhere, T::zero());
        Some(ConstantLevels { forward, backward })
    }

    /// [`Self::step_split_with_curve`] of a model whose levels are constant, given them
    /// (from this model's [`Self::constant_levels`]): the same result, bit for bit, without
    /// evaluating them at each step.
    pub fn step_split_at_constant_levels(
        &self,
        s: &mut FrictionState<T>,
        mean_velocity: T,
        velocity: T,
        dt: T,
        stribeck_decay: Option<T>,
        levels: &ConstantLevels<T>,
    ) -> CurveStep<T> {
        // constant levels: no temperature dependence, the Stribeck velocity unscaled
        let (force, stribeck_level) = self.step_driven_at_levels(
            s,
            mean_velocity,
            mean_velocity,
            velocity,
            dt,
            stribeck_decay,
            T::one(),
            levels.forward,
            levels.backward,
        );
        CurveStep {
            force,
            stribeck_level,
            forward: levels.forward,
            backward: levels.backward,
        }
    }

    /// The step once the dwell clock has moved and the levels of both directions are known
    /// ([`Self::clock_and_levels`]): the force \[N\] and the Stribeck level `g(v)` \[N\] of the
    /// bristle step, the Stribeck decay at the mean velocity given, or computed here with the
    /// Stribeck velocity scaled by the conditions' `vs_scale` (see
    /// [`Self::step_split_with_curve`]).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn step_driven_at_levels(
        &self,
        s: &mut FrictionState<T>,
        drive: T,
        mean_velocity: T,
        velocity: T,
        dt: T,
        stribeck_decay: Option<T>,
        vs_scale: T,
        forward: Levels<T>,
        backward: Levels<T>,
    ) -> (T, T) {
        let at = |v: T| if v >= T::zero() { forward } else { backward };
        let l = at(mean_velocity);
        // a given decay outside [0, 1] (NaN included) breaks the contract: computed instead
        let decay = match stribeck_decay {
            Some(d) if (T::zero()..=T::one()).contains(&d) => d,
            _ => self.stribeck_decay_scaled(mean_velocity, vs_scale),
        };
        let g = Self::curve_from_decay(&l, decay);
        let sigma0 = self.params.bristle_stiffness();
        let b = driven_bristle_step(s.z, drive, mean_velocity, sigma0, g, dt);
        // The invariant set is sign-wise: z grows positive only while moving in +x, where the
        // forward levels hold, so `-Fs(-x) / sigma0 <= z <= Fs(+x) / sigma0`. Bounding by the
        // current direction's Fs alone snapped a bristle loaded forward to the backward static
        // level the moment the axis crept back (an independent record with 23 % asymmetry held
        // 469 N at rest where the model dropped to 322 N).
        // max/min rather than clamp: no panic even for a non-finite bound
        let z = b
            .deflection
            .max(-backward.static_ / sigma0)
            .min(forward.static_ / sigma0);
        s.z = z;
        s.deflection_rate = b.deflection_rate;
        let l = at(velocity);
        let force = sigma0 * z
            + self.params.bristle_damping() * b.deflection_rate
            + self.viscous_force(velocity, &l)
            + self.offset_force();
        (force, g)
    }
}

/// The share of the renewal distance `distance` \[m\] a dwell clock slides over a step of `dt`
/// \[s\] at `speed` \[m/s\], `speed dt / D`; `None` where it is not a finite, non-negative number
/// (a distance that is zero, negative or not a number), and the age is then forgotten at once.
#[inline(always)]
fn share_of_renewal<T: ModelFloat>(speed: T, dt: T, distance: T) -> Option<T> {
    let slid = speed * dt / distance;
    (slid.is_finite() && slid >= T::zero()).then_some(slid)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::friction::effects::*;

    const REF: Conditions<f64> = Conditions {
        position: 0.0,
        pressure_sum: 0.0,
        temperature: 0.0,
    };

    fn base() -> FrictionModel<f64> {
        FrictionModel::plain(LugreParams::table2())
    }

    fn fss(m: &FrictionModel<f64>, v: f64, c: &Conditions<f64>) -> f64 {
        m.steady_state_force(v, c)
    }

    #[test]
    fn plain_model_matches_the_lugre_curve() {
        let m = base();
        for v in [-0.05, -0.003, 0.001, 0.02] {
            assert_eq!(fss(&m, v, &REF), m.params.steady_state_force(v));
        }
    }

    #[test]
    fn a_bristle_loaded_forward_is_not_snapped_to_the_backward_level() {
        // soft contact, 25 % asymmetry: load the bristle forward to its static level, then
        // creep back at 10 um/s; the held force unloads continuously (it was clamped at once
        // to the backward Fs when the bound followed the current direction)
        let mut m =
            FrictionModel::plain(LugreParams::new(3e6, 0.0, 0.0, 300.0, 400.0, 0.008).unwrap());
        m.effects.asymmetry = Some(Asymmetry {
            coulomb_ratio: 0.25,
            static_ratio: 0.25,
            viscous_ratio: 0.0,
            stribeck_velocity_ratio: 0.0,
        });
        let mut s = FrictionState::default();
        let dt = 1e-3;
        let mut f = 0.0;
        // a slow push over two pre-sliding lengths: the bristle heads for g(1 mm/s) = 498 N,
        // well above the backward static level
        for _ in 0..300 {
            f = m.step(&mut s, 1e-3, &REF, dt);
        }
        assert!(f > 400.0 && f <= 500.0 + 1e-9, "{f}");
        let back = m.step(&mut s, -1e-5, &REF, dt);
        // backward Fs is 300 N; a 10 nm step back unloads the spring by sigma0 dx = 30 mN
        assert!((back - f).abs() < 1.0, "{f} -> {back}");
        // and the sign-wise bounds still hold: backward sliding ends at -Fc(-x) = -225 N
        for _ in 0..2000 {
            f = m.step(&mut s, -0.05, &REF, dt);
        }
        assert!((f + 225.0).abs() < 1.0, "{f}");
    }

    #[test]
    fn a_given_stribeck_decay_changes_no_bit() {
        // a model with every effect that touches the step (shape, asymmetry, dwell clock),
        // driven through rests, creep, reversals and sliding: the step with the decay given
        // equals the step that computes it, bit for bit, in force, g and state
        let mut m =
            FrictionModel::plain(LugreParams::new(2e7, 800.0, 150.0, 300.0, 420.0, 0.004).unwrap());
        m.effects.stribeck_shape = Some(StribeckShape::with_exponent(1.3));
        m.effects.asymmetry = Some(Asymmetry {
            coulomb_ratio: 0.2,
            static_ratio: -0.1,
            viscous_ratio: 0.05,
            stribeck_velocity_ratio: 0.3,
        });
        m.effects.dwell_stiction = Some(DwellStiction {
            max_increase: 120.0,
            time_constant: 0.3,
            stick_velocity: 1e-4,
            renewal_distance: 1e-3,
            age_at_stick: crate::friction::DwellAge::Accumulates,
            clock: crate::friction::DwellClock::BodySpeed,
            growth: crate::friction::DwellGrowth::Exponential,
        });
        let (mut a, mut b) = (FrictionState::default(), FrictionState::default());
        for i in 0..4000 {
            let t = i as f64 * 1e-3;
            let v_mean = if i % 700 < 200 {
                0.0
            } else {
                0.03 * (3.0 * t).sin()
            };
            let v_end = v_mean * 1.01;
            let c = Conditions {
                position: 0.01 * t,
                ..REF
            };
            let fa = m.step_split_with_curve(&mut a, v_mean, v_end, &c, 1e-3, None);
            let d = m.stribeck_decay(v_mean);
            let fb = m.step_split_with_curve(&mut b, v_mean, v_end, &c, 1e-3, Some(d));
            assert_eq!(fa.force.to_bits(), fb.force.to_bits(), "force at {i}");
            assert_eq!(
                fa.stribeck_level.to_bits(),
                fb.stribeck_level.to_bits(),
                "g at {i}"
            );
            assert_eq!(a, b, "state at {i}");
        }
        // a decay that breaks the contract (NaN, out of [0, 1]) is computed instead, never used
        for bad in [f64::NAN, 1.5, -0.2, f64::INFINITY] {
            let (mut a, mut b) = (FrictionState::default(), FrictionState::default());
            let fa = m.step_split_with_curve(&mut a, 0.001, 0.001, &REF, 1e-3, None);
            let fb = m.step_split_with_curve(&mut b, 0.001, 0.001, &REF, 1e-3, Some(bad));
            assert_eq!(fa.force.to_bits(), fb.force.to_bits(), "decay {bad}");
            assert_eq!(a, b, "decay {bad}");
        }
        // and the decay is the curve's: g = Fc + (Fs - Fc) s(v) at the levels
        let l = m.levels(0.002, &REF, 0.0);
        let g = m.stribeck_curve(0.002, &l);
        let s = m.stribeck_decay(0.002);
        assert!((0.0..=1.0).contains(&s));
        assert_eq!(g, l.coulomb + (l.static_ - l.coulomb) * s);
    }

    #[test]
    fn asymmetry_scales_levels_per_direction() {
        let mut m = base();
        m.effects.asymmetry = Some(Asymmetry {
            coulomb_ratio: 0.1,
            static_ratio: -0.05,
            viscous_ratio: 0.2,
            stribeck_velocity_ratio: 0.0,
        });
        let v = 0.05; // far past vs: g = Fc
        let p = m.params;
        let up = p.coulomb_force() * 1.1 + p.viscous_coefficient() * 1.2 * v;
        let down = -(p.coulomb_force() * 0.9 + p.viscous_coefficient() * 0.8 * v);
        assert!((fss(&m, v, &REF) - up).abs() < 1e-9);
        assert!((fss(&m, -v, &REF) - down).abs() < 1e-9);
        // the breakaway levels follow rs, not rc
        let l_up = m.levels(1e-9, &REF, 0.0);
        let l_down = m.levels(-1e-9, &REF, 0.0);
        assert!((l_up.static_ - p.static_force() * 0.95).abs() < 1e-9);
        assert!((l_down.static_ - p.static_force() * 1.05).abs() < 1e-9);
        assert!((l_up.coulomb - p.coulomb_force() * 1.1).abs() < 1e-9);
    }

    #[test]
    fn the_stribeck_velocity_differs_per_direction() {
        let mut m = base();
        let vs = m.params.stribeck_velocity();
        m.effects.asymmetry = Some(Asymmetry {
            coulomb_ratio: 0.0,
            static_ratio: 0.0,
            viscous_ratio: 0.0,
            stribeck_velocity_ratio: 0.25,
        });
        // at v = ±vs: exp(-(1 / 1.25)^2) forward, exp(-(1 / 0.75)^2) backward
        assert!((m.stribeck_decay(vs) - (-(0.8f64).powi(2)).exp()).abs() < 1e-12);
        assert!((m.stribeck_decay(-vs) - (-(1.0 / 0.75f64).powi(2)).exp()).abs() < 1e-12);
        // a ratio of 1 or more, or not a number, keeps a positive vs and a finite decay
        for r in [1.0, 3.0, -5.0, f64::NAN, f64::INFINITY] {
            m.effects
                .asymmetry
                .as_mut()
                .unwrap()
                .stribeck_velocity_ratio = r;
            for v in [-vs, 0.0, vs] {
                let d = m.stribeck_decay(v);
                assert!((0.0..=1.0).contains(&d), "{r} {v} {d}");
            }
        }
    }

    #[test]
    fn offset_adds_a_constant_force_even_at_rest() {
        let mut m = base();
        m.effects.offset = Some(Offset { force: 42.0 });
        let mut s = FrictionState::default();
        assert_eq!(m.step(&mut s, 0.0, &REF, 1e-3), 42.0);
        assert!((fss(&m, 0.01, &REF) - base().steady_state_force(0.01, &REF) - 42.0).abs() < 1e-9);
    }

    #[test]
    fn load_dependence_shifts_coulomb_and_static_with_pressure() {
        let mut m = base();
        m.effects.load_dependence = Some(LoadDependence::power(2e-5, 100e5, 1.0));
        let c = Conditions {
            pressure_sum: 150e5,
            ..REF
        };
        let l = m.levels(0.01, &c, 0.0);
        assert!((l.static_ - (632.0 + 2e-5 * 50e5)).abs() < 1e-9);
        // the Coulomb level in proportion: 506 (1 + 100 / 632)
        assert!((l.coulomb - 506.0 * (1.0 + 100.0 / 632.0)).abs() < 1e-9);
        // a power law: k p_ref ((1.5)^2 - 1) / 2 = 2e-5 * 100e5 * 0.625 = 125 N, and the same
        // slope k at the reference
        let mut q = m.effects.load_dependence.unwrap();
        q.exponent = 2.0;
        m.effects.load_dependence = Some(q);
        let l = m.levels(0.01, &c, 0.0);
        assert!((l.static_ - (632.0 + 125.0)).abs() < 1e-6, "{}", l.static_);
        assert!((l.coulomb - 506.0 * (1.0 + 125.0 / 632.0)).abs() < 1e-6);
        let h = 1e3;
        let slope = (q.shift(100e5 + h) - q.shift(100e5 - h)) / (2.0 * h);
        assert!((slope - 2e-5).abs() < 1e-12, "{slope}");
    }

    /// Under pressure the Coulomb level scales by `L = 1 + dF / Fs` and the Stribeck hump by
    /// `1 + beta (L - 1)`: `beta = 1` keeps both levels in proportion, `beta = 0` a breakaway
    /// that rises only by the Coulomb level's change, and a hump that would turn negative
    /// leaves the static level at the Coulomb one.
    #[test]
    fn load_dependence_scales_the_hump_by_its_static_share() {
        let mut m = base();
        let c = Conditions {
            pressure_sum: 150e5,
            ..REF
        };
        // dF = 2e-5 * 50e5 = 100 N, L = 1 + 100 / 632
        let scale = 1.0 + 100.0 / 632.0;
        for (beta, hump) in [(1.0, 126.0 * scale), (0.0, 126.0), (-20.0, 0.0)] {
            let mut q = LoadDependence::power(2e-5, 100e5, 1.0);
            q.static_share = beta;
            m.effects.load_dependence = Some(q);
            let l = m.levels(0.01, &c, 0.0);
            assert!((l.coulomb - 506.0 * scale).abs() < 1e-9, "{beta}");
            let want = (126.0 * (1.0 + beta * (scale - 1.0))).max(0.0);
            assert!((want - hump).abs() < 1e-9);
            assert!(
                (l.static_ - l.coulomb - want).abs() < 1e-9,
                "{beta}: {}",
                l.static_
            );
        }
    }

    /// The cosine series over the pressure sums adds `sum c_j cos(j pi u)` to the static
    /// level's shift, u running 0..1 over `p_ref - L .. p_ref + L` and held at the ends
    /// beyond: a seal energised only above some pressure is a shape the power law cannot
    /// follow.
    #[test]
    fn load_dependence_follows_a_cosine_series_over_the_pressure_sums() {
        let mut m = base();
        let mut q = LoadDependence::power(1e-5, 100e5, 1.0);
        q.half_span = 50e5;
        q.terms = 2;
        q.cosine = [30.0, -10.0, 99.0, 99.0];
        m.effects.load_dependence = Some(q);
        // (p, u): the span's ends, its centre, and beyond the top
        for (p, u) in [(50e5, 0.0), (100e5, 0.5), (150e5, 1.0), (300e5, 1.0)] {
            let pi = core::f64::consts::PI;
            let series = 30.0 * (pi * u).cos() - 10.0 * (2.0 * pi * u).cos();
            let line = 1e-5 * (p.min(300e5) - 100e5);
            let want = line + series;
            assert!(
                (q.shift(p) - want).abs() < 1e-9,
                "{p}: {} vs {want}",
                q.shift(p)
            );
            let c = Conditions {
                pressure_sum: p,
                ..REF
            };
            let l = m.levels(0.01, &c, 0.0);
            assert!((l.static_ - (632.0 + want)).abs() < 1e-9, "{p}");
        }
        // the unused terms (99 N) take no part
        q.terms = 0;
        assert!((q.shift(150e5) - 50.0).abs() < 1e-9);
    }

    #[test]
    fn position_dependence_is_linear_along_the_stroke() {
        let mut m = base();
        m.effects.position_dependence = Some(PositionDependence::linear(1000.0, 0.2));
        let at = |x| {
            m.levels(0.01, &Conditions { position: x, ..REF }, 0.0)
                .coulomb
        };
        assert!((at(0.3) - 606.0).abs() < 1e-9);
        assert!((at(0.1) - 406.0).abs() < 1e-9);
    }

    /// Conditions evaluated once ([`FrictionModel::under`]) step a model exactly as the
    /// conditions themselves do, bit for bit, with every effect that reads them (and the rest)
    /// switched on; they serve a model with other levels and the same effects as well (the
    /// controller evaluates them once a period for its refined model and the health monitor's
    /// identified one: a load's scale, which depends on `Fs`, must not be frozen in them); and
    /// each condition reaches the step through them.
    #[test]
    fn conditions_evaluated_once_step_bit_for_bit_as_the_conditions() {
        let mut m = base();
        let mut ld = LoadDependence::power(3e-6, 1.2e7, 0.8);
        (ld.half_span, ld.terms, ld.static_share) = (1e7, 3, 0.5);
        ld.cosine[..3].copy_from_slice(&[8.0, -4.0, 2.0]);
        let mut pd = PositionDependence::linear(60.0, 0.2);
        (pd.half_span, pd.terms) = (0.2, 16);
        for (j, c) in pd.cosine.iter_mut().enumerate() {
            *c = 9.0 * (1.7 * j as f64).sin();
        }
        m.effects = Effects {
            asymmetry: Some(Asymmetry {
                coulomb_ratio: 0.1,
                static_ratio: -0.05,
                viscous_ratio: 0.2,
                stribeck_velocity_ratio: 0.1,
            }),
            offset: Some(Offset { force: 12.0 }),
            load_dependence: Some(ld),
            position_dependence: Some(pd),
            temperature_dependence: Some(TemperatureDependence {
                viscous_per_kelvin: 0.02,
                coulomb_per_kelvin: 0.004,
                reference_temperature: 40.0,
                stribeck_hersey_exponent: 0.6,
            }),
            stribeck_shape: Some(StribeckShape::with_exponent(1.3)),
            viscous_power: Some(ViscousPower {
                exponent: 0.7,
                reference_velocity: 0.05,
            }),
            dwell_stiction: Some(DwellStiction {
                max_increase: 40.0,
                time_constant: 0.5,
                stick_velocity: 1e-4,
                renewal_distance: 1e-4,
                age_at_stick: crate::friction::DwellAge::Accumulates,
                clock: crate::friction::DwellClock::BodySpeed,
                growth: crate::friction::DwellGrowth::Exponential,
            }),
        };
        // the same effects at other levels (a refined model)
        let mut refined = m;
        refined.params = LugreParams::new(3.9e9, 200.0, 40_000.0, 560.0, 720.0, 0.005).unwrap();
        let (mut a, mut b) = (FrictionState::default(), FrictionState::default());
        let (h, mut longest_rest) = (1e-3, 0.0f64);
        for k in 0..4000 {
            let t = k as f64 * h;
            // reversals, rests and a sweep of every condition
            let v = 0.03 * (2.0 * t).sin().powi(3);
            let c = Conditions {
                position: 0.2 + 0.15 * (0.7 * t).sin(),
                pressure_sum: 1.2e7 + 8e6 * (1.3 * t).cos(),
                temperature: 40.0 + 10.0 * (0.4 * t).sin(),
            };
            let drive = v + 1e-4 * (31.0 * t).sin();
            let fa = m.step_driven(&mut a, drive, v, v, &c, h);
            let fb = m.step_driven_under(&mut b, drive, v, v, &m.under(&c), h);
            assert_eq!((fa, a), (fb, b), "step {k}");
            longest_rest = longest_rest.max(a.dwell_time);
            for model in [&m, &refined] {
                assert_eq!(
                    model.steady_state_force(v, &c),
                    model.steady_state_force_under(v, &m.under(&c))
                );
            }
            // while sliding, every condition moves the step through what `under` evaluated
            if v.abs() < 1e-3 {
                continue;
            }
            let at = |c: &Conditions<f64>| {
                m.step_driven_under(&mut a.clone(), drive, v, v, &m.under(c), h)
            };
            let here = at(&c);
            for moved in [
                Conditions {
                    position: c.position + 0.05,
                    ..c
                },
                Conditions {
                    pressure_sum: c.pressure_sum + 2e6,
                    ..c
                },
                Conditions {
                    temperature: c.temperature + 5.0,
                    ..c
                },
            ] {
                assert_ne!(
                    here,
                    at(&moved),
                    "step {k}: {moved:?} did not move the force"
                );
            }
        }
        // the trajectory rested long enough for the dwell clock to matter
        assert!(longest_rest > 0.1, "{longest_rest}");
    }

    #[test]
    fn position_dependence_cosine_terms_follow_their_formula() {
        let mut m = base();
        let mut pd = PositionDependence::linear(0.0, 0.2);
        pd.half_span = 0.1;
        let c = [
            20.0, -10.0, 5.0, 7.0, -3.0, 2.0, 1.5, -4.0, 3.0, -2.5, 1.0, 0.5, -1.5, 2.5, -0.5, 6.0,
        ];
        pd.cosine = c;
        // the sixteenth term is ignored: the basis carries the terms in use only
        pd.terms = 15;
        assert_eq!(pd.basis(0.13)[15], 0.0);
        assert!((pd.basis(0.13)[14] - (15.0 * core::f64::consts::PI * 0.15).cos()).abs() < 1e-12);
        m.effects.position_dependence = Some(pd);
        let at = |x| {
            m.levels(0.01, &Conditions { position: x, ..REF }, 0.0)
                .coulomb
        };
        for x in [0.1, 0.13, 0.2, 0.27, 0.3] {
            let u: f64 = (x - 0.2) / 0.2 + 0.5;
            let pi = core::f64::consts::PI;
            let expect = 506.0
                + (1..=15)
                    .map(|j| c[j - 1] * (j as f64 * pi * u).cos())
                    .sum::<f64>();
            assert!(
                (at(x) - expect).abs() < 1e-9,
                "x {x}: {} vs {expect}",
                at(x)
            );
        }
        // beyond the span the shape holds its end value
        assert!((at(0.5) - at(0.3)).abs() < 1e-9);
    }

    #[test]
    fn temperature_thins_viscous_and_raises_coulomb() {
        let mut m = base();
        m.effects.temperature_dependence = Some(TemperatureDependence {
            viscous_per_kelvin: 0.02,
            coulomb_per_kelvin: 0.01,
            reference_temperature: 40.0,
            stribeck_hersey_exponent: 0.0,
        });
        let l = m.levels(
            0.01,
            &Conditions {
                temperature: 60.0,
                ..REF
            },
            0.0,
        );
        assert!((l.viscous - 48_900.0 * (-0.4f64).exp()).abs() < 1e-6);
        assert!((l.coulomb - 506.0 * 1.2).abs() < 1e-9);
    }

    /// `q = 0` is the law before it existed, bit for bit, at every temperature; `q != 0` takes
    /// the curve at `v eta^q` (the Hersey number), for the decay, the steady state and the
    /// step; a temperature that is not a number leaves the curve where it was.
    #[test]
    fn the_stribeck_curve_follows_the_viscosity_by_its_hersey_exponent() {
        let law = |q: f64| TemperatureDependence {
            viscous_per_kelvin: 0.02,
            coulomb_per_kelvin: 0.003,
            reference_temperature: 40.0,
            stribeck_hersey_exponent: q,
        };
        let (mut fixed, mut moving, mut plain) = (base(), base(), base());
        fixed.effects.temperature_dependence = Some(law(0.0));
        moving.effects.temperature_dependence = Some(law(0.8));
        plain.effects.stribeck_shape = Some(StribeckShape::with_exponent(1.4));
        fixed.effects.stribeck_shape = plain.effects.stribeck_shape;
        moving.effects.stribeck_shape = plain.effects.stribeck_shape;
        let (mut a, mut b) = (FrictionState::default(), FrictionState::default());
        for k in 0..3000 {
            let t = k as f64 * 1e-3;
            let v = 0.02 * (3.0 * t).sin();
            let temperature = 40.0 + 25.0 * (0.9 * t).sin();
            let c = Conditions { temperature, ..REF };
            let f = fixed.under(&c);
            // q = 0: the curve at the reference, bit for bit (the decay and the step)
            assert_eq!(
                fixed.stribeck_decay_under(v, &f).to_bits(),
                plain.stribeck_decay(v).to_bits()
            );
            let step = fixed.step_split_with_curve(&mut a, v, v, &c, 1e-3, None);
            let given =
                fixed.step_split_with_curve(&mut b, v, v, &c, 1e-3, Some(plain.stribeck_decay(v)));
            assert_eq!(step, given, "step {k}");
            assert_eq!(a, b, "step {k}");
            // q = 0.8: the decay at v eta^q
            let eta = (-0.02 * (temperature - 40.0)).exp();
            let g = moving.under(&c);
            let want = plain.stribeck_decay(v * eta.powf(0.8));
            assert_eq!(
                moving.stribeck_decay_at(v, temperature).to_bits(),
                moving.stribeck_decay_under(v, &g).to_bits()
            );
            assert!(
                (moving.stribeck_decay_under(v, &g) - want).abs() < 1e-12,
                "step {k}"
            );
            if (temperature - 40.0).abs() > 5.0 && v.abs() > 1e-3 {
                assert_ne!(moving.stribeck_decay_under(v, &g), plain.stribeck_decay(v));
            }
            // the steady state takes the same curve
            let l = moving.levels(v, &c, 0.0);
            let curve = l.coulomb + (l.static_ - l.coulomb) * want;
            let viscous = l.viscous * v;
            let steady = moving.steady_state_force(v, &c);
            assert!(
                (steady - (curve * crate::friction::params::direction(v) + viscous)).abs() < 1e-6,
                "step {k}: {steady}"
            );
        }
        // a bad temperature reading: the curve stays at the reference, nothing is NaN
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 1e30] {
            let c = Conditions {
                temperature: bad,
                ..REF
            };
            let d = moving.stribeck_decay_under(0.01, &moving.under(&c));
            assert_eq!(d.to_bits(), plain.stribeck_decay(0.01).to_bits(), "{bad}");
        }
    }

    #[test]
    fn stribeck_shape_changes_the_decay_exponent() {
        let mut m = base();
        m.effects.stribeck_shape = Some(StribeckShape::with_exponent(1.0));
        let l = m.levels(0.01, &REF, 0.0);
        let g = m.stribeck_curve(0.01, &l);
        assert!((g - (506.0 + 126.0 * (-2.0f64).exp())).abs() < 1e-9);
    }

    /// A Stribeck tail: the curve is `(1 - w) exp(-r^delta) + w exp(-r / k)`; its share's
    /// sensitivity is the derivative of the decay (a central difference); a share of 0 is the
    /// one-scale curve bit for bit; bad values give a finite decay, 1 at rest.
    #[test]
    fn a_stribeck_tail_adds_a_slow_scale_to_the_curve() {
        let mut m = base();
        let one = StribeckShape::with_exponent(1.0);
        let tailed = StribeckShape {
            tail_share: 0.4,
            tail_scale: 3.0,
            ..one
        };
        m.effects.stribeck_shape = Some(tailed);
        let l = m.levels(0.01, &REF, 0.0);
        // r = 0.01 / 0.005 = 2
        let want = 506.0 + 126.0 * (0.6 * (-2.0f64).exp() + 0.4 * (-2.0f64 / 3.0).exp());
        assert!((m.stribeck_curve(0.01, &l) - want).abs() < 1e-9);
        assert!((m.stribeck_curve(-0.01, &l) - want).abs() < 1e-9);
        for v in [0.0, 1e-4, 0.003, -0.01, 0.05] {
            let sens = m.stribeck_tail_sensitivity_at(v, 40.0);
            let at = |w: f64| {
                let mut n = m;
                n.effects.stribeck_shape = Some(StribeckShape {
                    tail_share: w,
                    ..tailed
                });
                n.stribeck_decay(v)
            };
            let fd = (at(0.4 + 1e-6) - at(0.4 - 1e-6)) / 2e-6;
            assert!((sens - fd).abs() < 1e-6, "{v}: {sens} against {fd}");
        }
        // no share: the one-scale curve, bit for bit
        let mut plain = base();
        plain.effects.stribeck_shape = Some(one);
        m.effects.stribeck_shape = Some(StribeckShape {
            tail_share: 0.0,
            ..tailed
        });
        for v in [0.0, 0.002, -0.02] {
            assert_eq!(
                m.stribeck_decay(v).to_bits(),
                plain.stribeck_decay(v).to_bits()
            );
        }
        // bad values: finite, and 1 at rest
        for (w, k) in [(f64::NAN, 3.0), (0.5, 0.0), (0.5, f64::NAN), (2.0, -1.0)] {
            m.effects.stribeck_shape = Some(StribeckShape {
                tail_share: w,
                tail_scale: k,
                ..one
            });
            for v in [0.0, 0.01] {
                let d = m.stribeck_decay(v);
                assert!(
                    d.is_finite() && (0.0..=1.0).contains(&d),
                    "{w} {k} {v}: {d}"
                );
            }
            assert_eq!(m.stribeck_decay(0.0), 1.0, "{w} {k}");
        }
    }

    #[test]
    fn viscous_power_follows_the_power_law() {
        let mut m = base();
        m.effects.viscous_power = Some(ViscousPower {
            exponent: 0.5,
            reference_velocity: 0.01,
        });
        let l = m.levels(0.04, &REF, 0.0);
        // sigma2 * v_r * (v / v_r)^0.5 = 48900 * 0.01 * 2
        assert!((m.viscous_force(0.04, &l) - 978.0).abs() < 1e-9);
        assert!((m.viscous_force(-0.04, &l) + 978.0).abs() < 1e-9);
        assert!((m.viscous_force(0.01, &l) - 489.0).abs() < 1e-9);
    }

    /// Table 2 with a dwell term: 200 N after a long rest, tau 1 s, stuck below 0.1 mm/s,
    /// forgotten over 1 mm, the age accumulating.
    fn dwell_at_rest_model() -> FrictionModel<f64> {
        let mut m = base();
        m.effects.dwell_stiction = Some(DwellStiction {
            max_increase: 200.0,
            time_constant: 1.0,
            stick_velocity: 1e-4,
            renewal_distance: 1e-3,
            age_at_stick: crate::friction::DwellAge::Accumulates,
            clock: crate::friction::DwellClock::BodySpeed,
            growth: crate::friction::DwellGrowth::Exponential,
        });
        m
    }

    /// A body that oscillates inside the bristle's pre-sliding range (50 um against a
    /// deflection at breakaway of 4 mm, up to 1 mm/s, twelve reversals in 2 s) never stops,
    /// yet its contact never slides: the contact's clock ages the junctions through the whole
    /// oscillation, the body's restarts at every reversal.
    #[test]
    fn the_contact_slip_clock_ages_through_reversals_ridden_in_pre_sliding() {
        use crate::friction::{DwellAge, DwellClock};
        let age_on = |clock: DwellClock| {
            let mut m =
                FrictionModel::plain(LugreParams::new(1e5, 0.0, 0.0, 300.0, 400.0, 0.01).unwrap());
            m.effects.dwell_stiction = Some(DwellStiction {
                max_increase: 100.0,
                time_constant: 1.0,
                stick_velocity: 1e-4,
                renewal_distance: 1e-3,
                age_at_stick: DwellAge::Restarts,
                clock,
                growth: crate::friction::DwellGrowth::Exponential,
            });
            let (amplitude, omega, dt) = (5e-5, 20.0, 1e-3);
            let mut s = FrictionState::default();
            let mut oldest: f64 = 0.0;
            for k in 0..2000 {
                let v = amplitude * omega * (omega * k as f64 * dt).cos();
                m.step(&mut s, v, &REF, dt);
                oldest = oldest.max(s.dwell_time);
            }
            (s.dwell_time, oldest)
        };
        let (slip_end, _) = age_on(DwellClock::ContactSlip);
        let (body_end, body_oldest) = age_on(DwellClock::BodySpeed);
        // stuck from the second step on (the first reads the slip of a bristle at rest)
        assert!((slip_end - 1.999).abs() < 1e-9, "{slip_end}");
        // the body's speed is under 0.1 mm/s for 5 ms about each reversal only
        assert!(
            body_oldest < 0.02 && body_end < 0.02,
            "{body_oldest} {body_end}"
        );
    }

    /// The two growth forms (session 103) reach the same share where they should and part
    /// where they should: the exponential `1 - e^-1` at `tau` as before, the hyperbolic a half
    /// at `tau` and 10/11 at `10 tau` (the exponential is grown there); both hold at zero for a
    /// negative age and below one for any age, f32 as f64, with no NaN at a huge age or a zero
    /// time constant.
    #[test]
    fn the_dwell_growth_forms_reach_their_shares() {
        use crate::friction::DwellGrowth;
        let mut d = dwell_at_rest_model().effects.dwell_stiction.unwrap();
        let tau = d.time_constant;
        assert!((d.grown_share(tau) - (1.0 - (-1.0f64).exp())).abs() < 1e-15);
        assert!((d.grown_share(10.0 * tau) - (1.0 - (-10.0f64).exp())).abs() < 1e-15);
        d.growth = DwellGrowth::Hyperbolic;
        assert!((d.grown_share(tau) - 0.5).abs() < 1e-15);
        assert!((d.grown_share(10.0 * tau) - 10.0 / 11.0).abs() < 1e-15);
        for growth in DwellGrowth::ALL {
            d.growth = growth;
            assert_eq!(d.grown_share(-1.0), 0.0);
            assert_eq!(d.grown_share(0.0), 0.0);
            let mut f32_term = crate::friction::Effects::<f64>::none();
            f32_term.dwell_stiction = Some(d);
            let d32 = f32_term.cast::<f32>().dwell_stiction.unwrap();
            for age in [1e-3, 0.3, 3.0, 1e30] {
                let (s64, s32) = (d.grown_share(age), d32.grown_share(age as f32));
                assert!((0.0..=1.0).contains(&s64) && (0.0..=1.0).contains(&s32));
                assert!((s64 - s32 as f64).abs() < 1e-6, "{growth:?} {age}");
            }
            let mut instant = d;
            instant.time_constant = 0.0;
            assert_eq!(instant.grown_share(0.5), 1.0);
        }
        // the levels carry it: a hyperbolic term half-grown at tau
        let mut m = dwell_at_rest_model();
        if let Some(t) = m.effects.dwell_stiction.as_mut() {
            t.growth = DwellGrowth::Hyperbolic;
        }
        let l = m.levels(0.0, &REF, tau);
        assert!((l.static_ - (632.0 + 100.0)).abs() < 1e-9, "{}", l.static_);
    }

    #[test]
    fn dwell_raises_breakaway_with_time_at_rest() {
        let m = dwell_at_rest_model();
        let mut s = FrictionState::default();
        for _ in 0..1000 {
            m.step(&mut s, 0.0, &REF, 1e-3);
        }
        assert!((s.dwell_time - 1.0).abs() < 1e-9);
        let l = m.levels(0.0, &REF, s.dwell_time);
        assert!((l.static_ - (632.0 + 200.0 * (1.0 - (-1.0f64).exp()))).abs() < 1e-9);
        // forgotten over the renewal distance: 5 um slid keep e^-0.005 of it, 1 mm more e^-1
        m.step(&mut s, 0.005, &REF, 1e-3);
        assert!((s.dwell_time - (-0.005f64).exp()).abs() < 1e-9);
        for _ in 0..20 {
            m.step(&mut s, 0.05, &REF, 1e-3);
        }
        assert!(
            (s.dwell_time - (-1.005f64).exp()).abs() < 1e-9,
            "{}",
            s.dwell_time
        );
        a_bad_renewal_distance_forgets_at_once(m);
    }

    /// Under `m`'s dwell rule, a renewal distance of zero, NaN or below zero forgets the age
    /// at once when the axis slides, and never makes a NaN.
    fn a_bad_renewal_distance_forgets_at_once(m: FrictionModel<f64>) {
        for bad in [0.0, f64::NAN, -1.0] {
            let mut m = m;
            if let Some(d) = m.effects.dwell_stiction.as_mut() {
                d.renewal_distance = bad;
            }
            let mut s = FrictionState::default();
            m.step(&mut s, 0.0, &REF, 1e-3);
            let f = m.step(&mut s, 0.05, &REF, 1e-3);
            assert_eq!(s.dwell_time, 0.0, "{bad}");
            assert!(f.is_finite());
        }
    }

    #[test]
    fn a_restarting_age_starts_at_zero_at_each_stick_and_an_accumulating_one_carries_on() {
        use crate::friction::DwellAge;
        // 1 s stuck, 0.1 mm slid (renewal distance 1 mm: e^-0.1 of the age left), 0.5 s stuck
        let age_after = |age_at_stick: DwellAge, start: f64| {
            let mut m = dwell_at_rest_model();
            if let Some(d) = m.effects.dwell_stiction.as_mut() {
                d.age_at_stick = age_at_stick;
            }
            let mut s = FrictionState {
                dwell_time: start,
                ..FrictionState::default()
            };
            let mut ages = [0.0; 3];
            for _ in 0..1000 {
                m.step(&mut s, 0.0, &REF, 1e-3);
            }
            ages[0] = s.dwell_time;
            for _ in 0..10 {
                m.step(&mut s, 0.01, &REF, 1e-3);
            }
            ages[1] = s.dwell_time;
            for _ in 0..500 {
                m.step(&mut s, 0.0, &REF, 1e-3);
            }
            ages[2] = s.dwell_time;
            ages
        };
        let close = |a: f64, b: f64| (a - b).abs() < 1e-9;
        let acc = age_after(DwellAge::Accumulates, 0.0);
        let res = age_after(DwellAge::Restarts, 0.0);
        // the same first stick and the same fading while sliding
        assert!(close(acc[0], 1.0) && close(res[0], 1.0), "{acc:?} {res:?}");
        assert!(close(acc[1], (-0.1f64).exp()) && close(res[1], acc[1]));
        // the second stick: on from e^-0.1 s, or from zero
        assert!(close(acc[2], (-0.1f64).exp() + 0.5), "{acc:?}");
        assert!(close(res[2], 0.5), "{res:?}");
        // a state's given age carries into a first stick under either rule
        assert!(close(age_after(DwellAge::Restarts, 2.0)[0], 3.0));
        assert!(close(age_after(DwellAge::Accumulates, 2.0)[0], 3.0));
    }

    /// The aging law: the age grows as the time at rest, a steady slide holds it at `D / v`
    /// (the implicit step's fixed point is exact), it renews over the renewal distance slid
    /// whatever the speed (no stick threshold: a creep under it still renews), and a distance
    /// that is not a positive number forgets at once.
    #[test]
    fn an_aging_age_grows_at_rest_and_a_steady_slide_holds_it_at_d_over_v() {
        use crate::friction::DwellAge;
        let mut m = dwell_at_rest_model();
        if let Some(d) = m.effects.dwell_stiction.as_mut() {
            d.age_at_stick = DwellAge::Aging;
        }
        let mut s = FrictionState::default();
        for _ in 0..1000 {
            m.step(&mut s, 0.0, &REF, 1e-3);
        }
        assert!((s.dwell_time - 1.0).abs() < 1e-9, "{}", s.dwell_time);
        // 10 mm/s over a renewal distance of 1 mm: the age settles at 0.1 s
        for _ in 0..5000 {
            m.step(&mut s, 0.01, &REF, 1e-3);
        }
        assert!((s.dwell_time - 0.1).abs() < 1e-9, "{}", s.dwell_time);
        // a creep at 0.05 mm/s, under the stick threshold of 0.1 mm/s, renews all the same:
        // it settles at 20 s, not at the 20 s + the time spent (a stuck clock's)
        let mut creep = FrictionState::default();
        for _ in 0..200_000 {
            m.step(&mut creep, 5e-5, &REF, 1e-3);
        }
        assert!(
            (creep.dwell_time - 20.0).abs() < 0.01,
            "{}",
            creep.dwell_time
        );
        // one step's update is (t + h) / (1 + h |v| / D), whatever the speed's sign
        let mut one = FrictionState {
            dwell_time: 0.5,
            ..FrictionState::default()
        };
        m.step(&mut one, -0.02, &REF, 1e-3);
        assert!(
            (one.dwell_time - 0.501 / 1.02).abs() < 1e-12,
            "{}",
            one.dwell_time
        );
        a_bad_renewal_distance_forgets_at_once(m);
    }

    /// Only effects that leave the levels alone make them constant, and a step at those
    /// constant levels is the step itself, bit for bit, along moves, reversals and rests at
    /// changing conditions (the decay given or not).
    #[test]
    fn a_step_at_constant_levels_is_the_step_bit_for_bit() {
        let all = every_effect();
        let moving = [
            EffectKind::LoadDependence,
            EffectKind::PositionDependence,
            EffectKind::TemperatureDependence,
            EffectKind::DwellStiction,
        ];
        for k in EffectKind::ALL {
            let mut m = base();
            m.effects = Effects::none().with_kind_of(k, &all);
            assert_eq!(m.constant_levels().is_none(), moving.contains(&k), "{k:?}");
        }
        let mut m = base();
        m.effects = moving.iter().fold(all, |e, k| e.without(*k));
        assert_eq!(
            m.effects.kinds().count(),
            EffectKind::ALL.len() - moving.len()
        );
        let levels = m
            .constant_levels()
            .expect("no effect that moves the levels");
        let (mut stepped, mut at_levels) = (FrictionState::default(), FrictionState::default());
        for i in 0..3000 {
            let t = i as f64 * 1e-3;
            // 0.3 s moves at up to 40 mm/s, each direction in turn, between 0.2 s rests
            let v = if i % 500 < 300 {
                0.04 * (t * 7.0).sin()
            } else {
                0.0
            };
            let c = Conditions {
                position: 0.1 * t,
                pressure_sum: 1e7 * (1.0 + t),
                temperature: 30.0 + 5.0 * t,
            };
            let decay = (i % 2 == 0).then(|| m.stribeck_decay(v));
            let a = m.step_split_with_curve(&mut stepped, v, 1.01 * v, &c, 1e-3, decay);
            let b =
                m.step_split_at_constant_levels(&mut at_levels, v, 1.01 * v, 1e-3, decay, &levels);
            assert_eq!(
                (a.force.to_bits(), a.stribeck_level.to_bits()),
                (b.force.to_bits(), b.stribeck_level.to_bits()),
                "{i}"
            );
            // the levels it reports are the model's, wherever it is
            assert_eq!((a.forward, a.backward), (b.forward, b.backward), "{i}");
            assert_eq!(
                (b.forward, b.backward),
                m.levels_by_direction(&c, 0.0),
                "{i}"
            );
            assert_eq!(stepped.z.to_bits(), at_levels.z.to_bits(), "{i}");
            assert_eq!(
                stepped.deflection_rate.to_bits(),
                at_levels.deflection_rate.to_bits(),
                "{i}"
            );
        }
    }

    #[test]
    fn the_step_reports_the_stribeck_level_and_the_levels_it_used() {
        // what an inverse model reads instead of evaluating the levels again: the same force
        // as step_split and, bit for bit, g(v) at the mean velocity's direction and the
        // dwell time after the step, with direction-dependent and dwell-dependent levels
        let mut m = base();
        m.effects.asymmetry = Some(Asymmetry {
            coulomb_ratio: 0.2,
            static_ratio: 0.1,
            viscous_ratio: 0.05,
            stribeck_velocity_ratio: -0.2,
        });
        m.effects.dwell_stiction = Some(DwellStiction {
            max_increase: 150.0,
            time_constant: 0.3,
            stick_velocity: 1e-4,
            renewal_distance: 1e-3,
            age_at_stick: crate::friction::DwellAge::Accumulates,
            clock: crate::friction::DwellClock::BodySpeed,
            growth: crate::friction::DwellGrowth::Exponential,
        });
        let (mut a, mut b) = (FrictionState::default(), FrictionState::default());
        let mut longest_rest: f64 = 0.0;
        for i in 0..3000 {
            let t = i as f64 * 1e-3;
            // rests, creep and reversals
            let v_mean = 0.004 * (6.0 * t).sin().powi(3);
            let v_now = 0.004 * (6.0 * (t + 1e-3)).sin().powi(3);
            let f = m.step_split(&mut a, v_mean, v_now, &REF, 1e-3);
            let step = m.step_split_with_curve(&mut b, v_mean, v_now, &REF, 1e-3, None);
            assert_eq!(f.to_bits(), step.force.to_bits(), "step {i}");
            assert_eq!(a, b);
            let expected = m.stribeck_curve(v_mean, &m.levels(v_mean, &REF, b.dwell_time));
            assert_eq!(
                step.stribeck_level.to_bits(),
                expected.to_bits(),
                "step {i}"
            );
            // and the levels of both directions at the dwell time after the step
            let levels = m.levels_by_direction(&REF, b.dwell_time);
            assert_eq!((step.forward, step.backward), levels, "step {i}");
            longest_rest = longest_rest.max(b.dwell_time);
        }
        // the clock ran through the slow reversals (|v| under the stick velocity for 0.17 s),
        // so the check covered a static level that moved by tens of newtons
        assert!(longest_rest > 0.1, "{longest_rest}");
        let moved = m.levels(0.0, &REF, longest_rest).static_ - m.levels(0.0, &REF, 0.0).static_;
        assert!(moved > 30.0, "{moved}");
    }

    #[test]
    fn levels_stay_physical_for_extreme_conditions() {
        let mut m = base();
        m.effects.load_dependence = Some(LoadDependence::power(1.0, 0.0, 1.0));
        let l = m.levels(
            0.01,
            &Conditions {
                pressure_sum: -1e9,
                ..REF
            },
            0.0,
        );
        assert!(l.coulomb > 0.0 && l.static_ >= l.coulomb);
    }
}
