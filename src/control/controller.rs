//! The 1 kHz servo controller: measurements -> fault check -> estimator -> observer and
//! feed-forward -> refinement -> cascade -> valve command.

use super::dob::DisturbanceObserver;
use super::estimator::{Estimator, EstimatorConfig};
use super::faults::{Faults, RECOVERY_TICKS};
use super::feedforward::{observer_weight, Feedforward};
use super::health::{HealthConfig, HealthEvent, HealthMonitor};
use super::observer::Observer;
use super::position::{Cascade, CascadeConfig};
use super::refine::{RefineConfig, Refiner};
use crate::axis::AxisGeometry;
use crate::friction::{Conditions, FrictionModel, LugreParams, ParamError, UnderConditions};

/// Which compensation parts run (the benchmark's configurations).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Features {
    /// Friction feed-forward from the reference (the LuGre model driven by it).
    pub feedforward: bool,
    /// LuGre observer blended into the compensation.
    pub observer: bool,
    /// Online refinement of Fc, Fs - Fc, sigma2.
    pub refinement: bool,
    /// Instead: the static friction map `Fc + (Fs - Fc) e^-(v/vs)^2 + sigma2 v` of the model
    /// on the reference velocity (the practitioners' table-based feed-forward).
    pub static_feedforward: bool,
    /// Instead: the model-free disturbance observer ([`super::dob`]).
    pub disturbance_observer: bool,
    /// On top of the model: a disturbance observer on what the model misses (the measured
    /// friction minus the model's compensation), bounded by the model's static force.
    pub residual_observer: bool,
}

impl Features {
    const NONE: Self = Self {
        feedforward: false,
        observer: false,
        refinement: false,
        static_feedforward: false,
        disturbance_observer: false,
        residual_observer: false,
    };
    /// Plain position loop.
    pub const PID: Self = Self::NONE;
    /// + feed-forward.
    pub const FEEDFORWARD: Self = Self {
        feedforward: true,
        ..Self::NONE
    };
    /// + observer.
    pub const FEEDFORWARD_OBSERVER: Self = Self {
        feedforward: true,
        observer: true,
        ..Self::NONE
    };
    /// Everything.
    pub const FULL: Self = Self {
        feedforward: true,
        observer: true,
        refinement: true,
        residual_observer: true,
        ..Self::NONE
    };
    /// Plain loop + static friction map on the reference velocity.
    pub const STATIC_FEEDFORWARD: Self = Self {
        static_feedforward: true,
        ..Self::NONE
    };
    /// Plain loop + disturbance observer.
    pub const DISTURBANCE_OBSERVER: Self = Self {
        disturbance_observer: true,
        ..Self::NONE
    };
}

/// Controller configuration (checked once, shared by any number of states).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ControllerConfig {
    /// Identified friction model.
    pub model: FrictionModel<f32>,
    /// Moving mass M \[kg\].
    pub mass_kg: f32,
    /// Piston-side area A_a [m^2].
    pub piston_area_m2: f32,
    /// Rod-side area A_b [m^2].
    pub annulus_area_m2: f32,
    /// Position range \[m\] (outside it, plus margin, is a fault).
    pub stroke_m: [f32; 2],
    /// Pressure transducer range \[Pa\].
    pub pressure_range_pa: [f32; 2],
    /// Largest reference speed the axis may be asked for [m/s] (beyond: a fault).
    pub max_speed_m_per_s: f32,
    /// Largest reference acceleration [m/s^2] (beyond: a fault).
    pub max_acceleration_m_per_s2: f32,
    /// Cascade gains.
    pub cascade: CascadeConfig,
    /// Observer correction gain k [1/s].
    pub observer_gain: f32,
    /// Speed at which the observer gets half its weight [m/s].
    pub blend_speed: f32,
    /// Maximum observer weight [-].
    pub blend_max: f32,
    /// Disturbance observer's filter cut-off f_Q \[Hz\] (see [`super::dob`]).
    pub dob_cutoff_hz: f32,
    /// The residual observer's filter cut-off \[Hz\].
    pub residual_cutoff_hz: f32,
    /// Reference speed at which the residual observer's weight has fallen to a half, as a
    /// fraction of the model's Stribeck velocity [-].
    pub residual_fade_fraction: f32,
    /// Estimator gains.
    pub estimator: EstimatorConfig,
    /// Refinement settings.
    pub refine: RefineConfig,
    /// Enabled parts.
    pub features: Features,
    /// Supervisor thresholds.
    pub supervisor: SupervisorConfig,
    /// Friction health monitor settings (see [`super::health`]).
    pub health: HealthConfig,
    /// Control period \[s\].
    pub period_s: f32,
    /// Periods over which new friction parameters ([`Controller::set_friction`]) are ramped
    /// in, so the compensation and the valve command do not jump (0: at once).
    pub settings_ramp_periods: u32,
}

/// The disturbance observer's cut-off by the tuning rule of [`super::dob`] \[Hz\].
pub const DOB_CUTOFF_HZ: f32 = 400.0;

impl ControllerConfig {
    /// Defaults for the host simulator's axis ([`AxisGeometry::SIMULATED`]: 50/28 mm cylinder,
    /// 200 kg, 210 bar) with the given model.
    pub fn for_simulated_axis(model: FrictionModel<f32>, features: Features) -> Self {
        Self::for_axis(&AxisGeometry::SIMULATED, model, features)
    }

    /// Defaults for an axis of the given geometry: its mass and areas, its stroke with a 2 %
    /// margin each side before a position is a fault. The position-loop gains were tuned on
    /// [`AxisGeometry::SIMULATED`] and scale with the mass (the same closed-loop bandwidth
    /// `sqrt(K / M)`); the force-loop gains and the valve settings are the simulated axis's.
    pub fn for_axis(axis: &AxisGeometry, model: FrictionModel<f32>, features: Features) -> Self {
        let m = (axis.moving_mass_kg / AxisGeometry::SIMULATED.moving_mass_kg) as f32;
        let margin = 0.02 * axis.stroke_m;
        Self {
            model,
            mass_kg: axis.moving_mass_kg as f32,
            piston_area_m2: axis.piston_area_m2() as f32,
            annulus_area_m2: axis.annulus_area_m2() as f32,
            stroke_m: [-margin as f32, (axis.stroke_m + margin) as f32],
            pressure_range_pa: [-1e5, 300e5],
            // the valve's full opening moves the simulated axis at ~0.6 m/s; a reference twice
            // that, or 10 g, is a setpoint generator gone wrong
            max_speed_m_per_s: 1.2,
            max_acceleration_m_per_s2: 100.0,
            cascade: CascadeConfig {
                position_gain: 2.0e6 * m,
                velocity_gain: 2.0e4 * m,
                position_integral_gain: 2.0e7 * m,
                force_gain: 1.0e-5,
                force_integral_gain: 2.0e-4,
                full_opening_speed: 0.6,
                position_integral_limit: 1e-3,
            },
            observer_gain: 200.0,
            blend_speed: 5e-3,
            blend_max: 0.5,
            dob_cutoff_hz: DOB_CUTOFF_HZ,
            residual_cutoff_hz: 50.0,
            residual_fade_fraction: 0.5,
            estimator: EstimatorConfig::default(),
            refine: RefineConfig::default(),
            features,
            supervisor: SupervisorConfig::default(),
            health: HealthConfig::default(),
            period_s: 1e-3,
            // 0.2 s: a 20 % change of Fc (~100 N) becomes 0.5 N per period
            settings_ramp_periods: 200,
        }
    }
}

/// One period's measurements.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measurements {
    /// Encoder position \[m\].
    pub position_m: f32,
    /// Chamber A pressure \[Pa\].
    pub pressure_a_pa: f32,
    /// Chamber B pressure \[Pa\].
    pub pressure_b_pa: f32,
    /// Oil temperature \[degC\], if measured.
    pub temperature_c: Option<f32>,
}

/// One period's reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reference {
    /// Position \[m\].
    pub position_m: f32,
    /// Velocity [m/s].
    pub velocity_m_per_s: f32,
    /// Acceleration [m/s^2].
    pub acceleration_m_per_s2: f32,
}

/// What the controller did this period.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Output {
    /// Valve command in [-1, 1] (0 = null, the safe state).
    pub valve_command: f32,
    /// Force demand \[N\].
    pub force_demand_n: f32,
    /// Friction compensation used \[N\].
    pub friction_compensation_n: f32,
    /// Feed-forward friction \[N\].
    pub friction_feedforward_n: f32,
    /// Observer friction \[N\] (the LuGre observer's, or the disturbance observer's).
    pub friction_observer_n: f32,
    /// What the residual observer added to the model's compensation \[N\].
    pub friction_residual_n: f32,
    /// Fault flags of this period.
    pub faults: Faults,
    /// The friction has left the identified band (a warning, not a fault: the loop runs on;
    /// see [`super::health`]).
    pub health_warning: bool,
    /// True while in the safe state.
    pub safe: bool,
}

/// Thresholds of the supervisor (the safe-state machine).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SupervisorConfig {
    /// Consecutive sane periods before the loop closes again after a fault.
    pub recovery_ticks: u32,
    /// |Valve command| above which a motionless encoder counts towards a stuck fault [-].
    pub stuck_command: f32,
    /// Periods of a hard-pushed, motionless encoder before it is a fault (0.3 s at 1 kHz).
    pub stuck_ticks: u32,
}

impl Default for SupervisorConfig {
    fn default() -> Self {
        Self {
            recovery_ticks: RECOVERY_TICKS,
            stuck_command: 0.9,
            stuck_ticks: 300,
        }
    }
}

/// The safe-state machine: the valve is nulled in `Safe` and the loop closes in `Running`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Mode {
    /// Valve at null; the inputs have been sane for `sane_ticks` periods (the loop closes
    /// when that reaches the supervisor's `recovery_ticks`).
    Safe {
        /// Consecutive sane periods so far.
        sane_ticks: u32,
    },
    /// The loop is closed.
    Running,
}

/// A configuration value out of its range: which field, and what it must be.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ConfigError {
    /// The field, as named in [`ControllerConfig`].
    pub field: &'static str,
    /// What it must be.
    pub requirement: &'static str,
}

impl core::fmt::Display for ConfigError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "controller config: {} {}", self.field, self.requirement)
    }
}

#[cfg(feature = "std")]
impl std::error::Error for ConfigError {}

impl ControllerConfig {
    /// Checks every field once (the tick then never divides by a zero period or runs with a
    /// negative mass); the error names the first wrong field.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let err = |field, requirement| Err(ConfigError { field, requirement });
        let positive = |v: f32| v.is_finite() && v > 0.0;
        let non_negative = |v: f32| v.is_finite() && v >= 0.0;
        if !(positive(self.period_s) && self.period_s <= 0.1) {
            return err("period_s", "must be within (0, 0.1] s");
        }
        if !positive(self.mass_kg) {
            return err("mass_kg", "must be a finite number greater than zero");
        }
        if !positive(self.piston_area_m2) {
            return err(
                "piston_area_m2",
                "must be a finite number greater than zero",
            );
        }
        if !(positive(self.annulus_area_m2) && self.annulus_area_m2 <= self.piston_area_m2) {
            return err(
                "annulus_area_m2",
                "must be greater than zero and at most piston_area_m2",
            );
        }
        let [lo, hi] = self.stroke_m;
        if !(lo.is_finite() && hi.is_finite() && lo < hi) {
            return err("stroke_m", "must be finite with stroke_m[0] < stroke_m[1]");
        }
        let [plo, phi] = self.pressure_range_pa;
        if !(plo.is_finite() && phi.is_finite() && plo < phi) {
            return err("pressure_range_pa", "must be finite with [0] < [1]");
        }
        if !positive(self.max_speed_m_per_s) {
            return err(
                "max_speed_m_per_s",
                "must be a finite number greater than zero",
            );
        }
        if !positive(self.max_acceleration_m_per_s2) {
            return err(
                "max_acceleration_m_per_s2",
                "must be a finite number greater than zero",
            );
        }
        let g = &self.cascade;
        for (field, v) in [
            ("cascade.position_gain", g.position_gain),
            ("cascade.velocity_gain", g.velocity_gain),
            ("cascade.position_integral_gain", g.position_integral_gain),
            ("cascade.force_gain", g.force_gain),
            ("cascade.force_integral_gain", g.force_integral_gain),
            ("cascade.position_integral_limit", g.position_integral_limit),
            ("observer_gain", self.observer_gain),
        ] {
            if !non_negative(v) {
                return err(field, "must be a finite number, zero or greater");
            }
        }
        if !positive(g.full_opening_speed) {
            return err(
                "cascade.full_opening_speed",
                "must be a finite number greater than zero",
            );
        }
        if !positive(self.blend_speed) {
            return err("blend_speed", "must be a finite number greater than zero");
        }
        if !(self.blend_max.is_finite() && (0.0..=1.0).contains(&self.blend_max)) {
            return err("blend_max", "must be within [0, 1]");
        }
        let nyquist = 0.5 / self.period_s;
        for (field, v) in [
            ("dob_cutoff_hz", self.dob_cutoff_hz),
            ("residual_cutoff_hz", self.residual_cutoff_hz),
        ] {
            if !(positive(v) && v < nyquist) {
                return err(
                    field,
                    "must be greater than zero and below the Nyquist frequency",
                );
            }
        }
        if !positive(self.residual_fade_fraction) {
            return err(
                "residual_fade_fraction",
                "must be a finite number greater than zero",
            );
        }
        if self.model.params.check_physical().is_err() {
            return err("model", "must pass LugreParams::check_physical");
        }
        let s = &self.supervisor;
        if s.recovery_ticks == 0 || s.stuck_ticks == 0 {
            return err(
                "supervisor",
                "recovery_ticks and stuck_ticks must be at least 1",
            );
        }
        if !(s.stuck_command.is_finite() && s.stuck_command > 0.0 && s.stuck_command <= 1.0) {
            return err("supervisor.stuck_command", "must be within (0, 1]");
        }
        let h = &self.health;
        if h.block_samples == 0 || h.decimation == 0 {
            return err("health", "block_samples and decimation must be at least 1");
        }
        for (field, v) in [
            ("health.band", h.band),
            ("health.min_speed_factor", h.min_speed_factor),
            (
                "health.max_acceleration_m_per_s2",
                h.max_acceleration_m_per_s2,
            ),
        ] {
            if !positive(v) {
                return err(field, "must be a finite number greater than zero");
            }
        }
        Ok(())
    }

    /// Validates the configuration and builds a controller with it.
    pub fn build(self) -> Result<Controller, ConfigError> {
        self.validate()?;
        Ok(Controller::new(self))
    }
}

/// Per-period factors that depend only on the configuration: computed once in
/// [`Controller::new`], so the 1 kHz tick calls no `exp`.
#[derive(Clone, Copy, Debug)]
struct Gains {
    /// Disturbance observer's step gain.
    dob: f32,
    /// Residual observer's step gain.
    residual: f32,
    /// Feed-forward bristle relaxation per period at rest.
    rest_decay: f32,
}

/// The controller state.
#[derive(Clone, Debug)]
pub struct Controller {
    config: ControllerConfig,
    gains: Gains,
    model: FrictionModel<f32>,
    mode: Mode,
    estimator: Estimator,
    observer: Observer,
    feedforward: Feedforward,
    dob: DisturbanceObserver,
    residual: DisturbanceObserver,
    last_model_compensation: f32,
    refiner: Refiner,
    cascade: Cascade,
    last_ref: Option<f32>,
    stuck_ticks: u32,
    last_position: f32,
    health: HealthMonitor,
    ramp: Option<ParamRamp>,
}

/// New friction parameters being ramped in: linear in every parameter from the set in use to
/// the new one (a convex combination of two valid sets is valid: Fs >= Fc holds along it).
#[derive(Clone, Copy, Debug)]
struct ParamRamp {
    from: LugreParams<f32>,
    to: LugreParams<f32>,
    done: u32,
    total: u32,
}

impl ParamRamp {
    /// One period further; the parameters to use now.
    fn advance(&mut self) -> LugreParams<f32> {
        self.done = (self.done + 1).min(self.total);
        let s = self.done as f32 / self.total.max(1) as f32;
        let (a, b) = (self.from.to_array(), self.to.to_array());
        LugreParams::from_array(core::array::from_fn(|i| a[i] + s * (b[i] - a[i])))
            // rounding could put Fs a hair below Fc mid-ramp: then the target at once
            .unwrap_or(self.to)
    }

    fn finished(&self) -> bool {
        self.done >= self.total
    }
}

impl Controller {
    /// A controller at rest with the valve at null; it closes the loop on the first sane
    /// measurements (see [`ControllerConfig::build`] for a validated start).
    pub fn new(config: ControllerConfig) -> Self {
        let p = &config.model.params;
        let nominal = [
            p.coulomb_force(),
            p.static_force() - p.coulomb_force(),
            p.viscous_coefficient(),
        ];
        Self {
            model: config.model,
            mode: Mode::Safe {
                sane_ticks: config.supervisor.recovery_ticks,
            },
            estimator: Estimator::default(),
            observer: Observer::default(),
            feedforward: Feedforward::default(),
            dob: DisturbanceObserver::default(),
            residual: DisturbanceObserver::default(),
            last_model_compensation: 0.0,
            refiner: Refiner::new(nominal),
            cascade: Cascade::default(),
            last_ref: None,
            stuck_ticks: 0,
            last_position: 0.0,
            health: HealthMonitor::default(),
            ramp: None,
            gains: Gains {
                dob: DisturbanceObserver::gain(config.dob_cutoff_hz, config.period_s),
                residual: DisturbanceObserver::gain(config.residual_cutoff_hz, config.period_s),
                rest_decay: Feedforward::rest_decay(config.period_s),
            },
            config,
        }
    }

    /// The model in use (with refined parameters).
    pub fn model(&self) -> &FrictionModel<f32> {
        &self.model
    }

    /// Runs with new identified friction parameters from now on (a settings message between
    /// ticks). They are checked as a parameter file is (`check_physical`); a refused set
    /// leaves the controller unchanged. The set becomes the identified model the refinement
    /// and the health monitor refer to at once, and the model in use moves to it linearly
    /// over `settings_ramp_periods` periods (the refinement pauses meanwhile), so the
    /// compensation, and with it the valve command, does not jump.
    pub fn set_friction(&mut self, params: LugreParams<f32>) -> Result<(), ParamError> {
        params.check_physical()?;
        self.config.model.params = params;
        self.refiner = Refiner::new([
            params.coulomb_force(),
            params.static_force() - params.coulomb_force(),
            params.viscous_coefficient(),
        ]);
        // its statistic was gathered against the old model
        self.health = HealthMonitor::default();
        let ramp = ParamRamp {
            from: self.model.params,
            to: params,
            done: 0,
            total: self.config.settings_ramp_periods,
        };
        if ramp.total == 0 {
            self.model.params = params;
            self.ramp = None;
        } else {
            self.ramp = Some(ramp);
        }
        Ok(())
    }

    /// True while new friction parameters are being ramped in.
    pub fn settings_ramping(&self) -> bool {
        self.ramp.is_some()
    }

    /// The safe-state machine's mode.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// The friction health monitor (its ratio and warning).
    pub fn health(&self) -> &HealthMonitor {
        &self.health
    }

    /// The oldest undelivered health event, for telemetry at low priority.
    pub fn pop_health_event(&mut self) -> Option<HealthEvent> {
        self.health.pop_event()
    }

    /// One control period: supervise inputs -> estimate -> compensate -> cascade ->
    /// supervise output; then the refinement adapts the model for the next period.
    pub fn tick(&mut self, m: &Measurements, r: &Reference) -> Output {
        let mut out = Output::default();
        // 1. supervise inputs: a bad measurement or reference nulls the valve
        let faults = self.input_faults(m, r);
        if !faults.is_empty() {
            return self.enter_safe(faults);
        }
        if !self.ready(m, r) {
            out.safe = true;
            return out;
        }
        // new settings move in by one period's step
        if let Some(ramp) = &mut self.ramp {
            self.model.params = ramp.advance();
            if ramp.finished() {
                self.ramp = None;
            }
        }
        // 2. estimate
        self.estimator
            .update(&self.config.estimator, m.position_m, self.config.period_s);
        // the period's conditions, evaluated once: feed-forward, observer, the static
        // fall-back and the health monitor's identified model (the same effects) use them
        let cond = self.model.under(&self.conditions(m));
        // 3. compensate
        let measured_force = self.compensate(m, r, &cond, &mut out);
        // 4. cascade
        let c = &self.config;
        let est = self.estimator;
        let co = self.cascade.update(
            &c.cascade,
            c.mass_kg,
            r.position_m - est.position,
            r.velocity_m_per_s - est.velocity,
            r.velocity_m_per_s,
            r.acceleration_m_per_s2,
            out.friction_compensation_n,
            measured_force,
            c.period_s,
        );
        out.force_demand_n = co.force_demand;
        // 5. supervise output
        if let Some(fault) = self.output_fault(m, co.command, co.force_demand) {
            let mut safe = self.enter_safe(fault);
            safe.faults.insert(out.faults);
            return safe;
        }
        out.valve_command = co.command;
        // 6. health: the friction the force balance shows against the identified model
        if self.health.sample_due(&self.config.health) {
            self.monitor_health(r, &cond, measured_force);
        }
        out.health_warning = self.health.warning();
        // 7. refinement, after the output: it adapts the model the next period uses
        if self.config.features.refinement
            && self.ramp.is_none()
            && !self.refine(&cond, measured_force)
        {
            out.faults.insert(Faults::REFINEMENT_RESET);
        }
        out
    }

    fn input_faults(&self, m: &Measurements, r: &Reference) -> Faults {
        let mut f = Faults::default();
        let finite = m.position_m.is_finite()
            && m.pressure_a_pa.is_finite()
            && m.pressure_b_pa.is_finite()
            && m.temperature_c.is_none_or(f32::is_finite)
            && r.position_m.is_finite()
            && r.velocity_m_per_s.is_finite()
            && r.acceleration_m_per_s2.is_finite();
        if !finite {
            f.insert(Faults::NON_FINITE);
            return f;
        }
        let [lo, hi] = self.config.stroke_m;
        if m.position_m < lo || m.position_m > hi {
            f.insert(Faults::POSITION_RANGE);
        }
        let [plo, phi] = self.config.pressure_range_pa;
        let bad = |p: f32| p < plo || p > phi;
        if bad(m.pressure_a_pa) || bad(m.pressure_b_pa) {
            f.insert(Faults::PRESSURE_RANGE);
        }
        if r.position_m < lo
            || r.position_m > hi
            || r.velocity_m_per_s.abs() > self.config.max_speed_m_per_s
            || r.acceleration_m_per_s2.abs() > self.config.max_acceleration_m_per_s2
        {
            f.insert(Faults::REFERENCE_RANGE);
        }
        f
    }

    /// Counts sane periods in `Safe`; on leaving it, every integrator and observer starts
    /// from where the axis is. True when the loop is closed this period.
    fn ready(&mut self, m: &Measurements, r: &Reference) -> bool {
        let Mode::Safe { sane_ticks } = self.mode else {
            return true;
        };
        if sane_ticks < self.config.supervisor.recovery_ticks {
            self.mode = Mode::Safe {
                sane_ticks: sane_ticks + 1,
            };
            self.estimator.reset(m.position_m);
            self.last_ref = Some(r.position_m);
            return false;
        }
        self.mode = Mode::Running;
        self.cascade.reset();
        self.estimator.reset(m.position_m);
        self.observer = Observer::default();
        self.feedforward = Feedforward::default();
        self.dob = DisturbanceObserver::default();
        self.residual = DisturbanceObserver::default();
        self.last_model_compensation = 0.0;
        self.stuck_ticks = 0;
        true
    }

    /// The friction compensation \[N\] into `out` (with its parts), by the enabled features;
    /// returns the actuator force measured from the chamber pressures \[N\].
    fn compensate(
        &mut self,
        m: &Measurements,
        r: &Reference,
        cond: &UnderConditions<f32>,
        out: &mut Output,
    ) -> f32 {
        let c = &self.config;
        let h = c.period_s;
        let est = self.estimator;
        let measured_force =
            m.pressure_a_pa * c.piston_area_m2 - m.pressure_b_pa * c.annulus_area_m2;
        let v_ref_mean = match self.last_ref {
            Some(prev) => (r.position_m - prev) / h,
            None => r.velocity_m_per_s,
        };
        self.last_ref = Some(r.position_m);
        let e = r.position_m - est.position;

        // friction: feed-forward along the reference, observer along the measured motion
        let mut compensation = 0.0;
        if c.features.feedforward {
            out.friction_feedforward_n = self.feedforward.update(
                &self.model,
                v_ref_mean,
                r.velocity_m_per_s,
                cond,
                h,
                self.gains.rest_decay,
            );
            compensation = out.friction_feedforward_n;
        }
        if c.features.observer {
            let ok = self.observer.update(
                &self.model,
                est.mean_velocity,
                est.velocity,
                -e,
                c.observer_gain,
                cond,
                h,
            );
            if ok {
                out.friction_observer_n = self.observer.force;
                let w = observer_weight(r.velocity_m_per_s, c.blend_speed, c.blend_max);
                compensation += w * (self.observer.force - compensation);
            } else {
                out.faults.insert(Faults::OBSERVER_DIVERGED);
                // fall back to the static model along the reference
                compensation = self
                    .model
                    .steady_state_force_under(r.velocity_m_per_s, cond);
            }
        }
        if c.features.static_feedforward {
            compensation = self
                .model
                .steady_state_force_under(r.velocity_m_per_s, cond);
            out.friction_feedforward_n = compensation;
        }
        if c.features.disturbance_observer {
            compensation =
                self.dob
                    .update(measured_force, c.mass_kg, est.acceleration, self.gains.dob);
            out.friction_observer_n = compensation;
        }
        let at_rest = r.velocity_m_per_s == 0.0 && v_ref_mean == 0.0;
        if c.features.residual_observer && at_rest {
            // while the reference holds still the friction is reactive: there is no level to
            // learn, and feeding the measured force back would soften the hold. The estimate
            // relaxes so the next move starts from the model alone.
            self.residual.update(0.0, 0.0, 0.0, self.gains.residual);
            self.last_model_compensation = compensation;
        } else if c.features.residual_observer && compensation.is_finite() {
            // the friction that acted over the last period (force minus inertia) minus what
            // the model compensated then: the model's error, low-passed and bounded
            let missed = self.residual.update(
                measured_force - self.last_model_compensation,
                c.mass_kg,
                est.acceleration,
                self.gains.residual,
            );
            // it works where the levels decide the error: in the Stribeck region, where the
            // friction is its levels Fs and Fc. Above it the friction follows the velocity,
            // the observer's lag costs more than it gains, and the refinement owns the levels.
            let fade = c.residual_fade_fraction * self.model.params.stribeck_velocity();
            let s = r.velocity_m_per_s / fade.max(1e-6);
            let weight = 1.0 / (1.0 + s * s);
            let bound = self.model.params.static_force();
            out.friction_residual_n = weight * missed.clamp(-bound, bound);
            self.last_model_compensation = compensation;
            compensation += out.friction_residual_n;
        }
        if !compensation.is_finite() {
            compensation = 0.0;
            out.faults.insert(Faults::OBSERVER_DIVERGED);
            self.observer = Observer::default();
            self.residual = DisturbanceObserver::default();
        }
        out.friction_compensation_n = compensation;
        measured_force
    }

    /// A fault of the cascade's output: a non-finite command or force demand, or the valve
    /// pushed hard while the encoder does not move at all (stuck encoder).
    fn output_fault(
        &mut self,
        m: &Measurements,
        command: f32,
        force_demand: f32,
    ) -> Option<Faults> {
        let s = self.config.supervisor;
        if command.abs() > s.stuck_command && m.position_m == self.last_position {
            self.stuck_ticks += 1;
        } else {
            self.stuck_ticks = 0;
        }
        self.last_position = m.position_m;
        if !(command.is_finite() && force_demand.is_finite()) {
            Some(Faults::NON_FINITE)
        } else if self.stuck_ticks > s.stuck_ticks {
            Some(Faults::STUCK_ENCODER)
        } else {
            None
        }
    }

    /// The conditions the friction model sees this period: the estimated position, the
    /// chamber pressures' sum, the oil temperature (the model's reference when not measured).
    fn conditions(&self, m: &Measurements) -> Conditions<f32> {
        Conditions {
            position: self.estimator.position,
            pressure_sum: m.pressure_a_pa + m.pressure_b_pa,
            temperature: m
                .temperature_c
                .unwrap_or(self.model.effects.reference_conditions().temperature),
        }
    }

    /// Feeds the health monitor: while the axis slides steadily, the friction of the force
    /// balance against the identified model's (not the refined one's: the refinement follows
    /// the drift the monitor is there to report).
    fn monitor_health(&mut self, r: &Reference, cond: &UnderConditions<f32>, measured_force: f32) {
        let c = &self.config;
        // `cond` was evaluated for the model in use, whose effects are the identified model's
        // (refinement, ramps and settings change the parameters only)
        debug_assert!(
            self.model.effects == c.model.effects,
            "the model in use carries other effects than the identified one"
        );
        let est = &self.estimator;
        let vs = c.model.params.stribeck_velocity();
        let sliding = est.velocity.abs() > c.health.min_speed_factor * vs
            && r.acceleration_m_per_s2.abs() < c.health.max_acceleration_m_per_s2;
        let model_n = if sliding {
            c.model.steady_state_force_under(est.velocity, cond)
        } else {
            0.0
        };
        let measured_n = measured_force - c.mass_kg * est.acceleration;
        self.health
            .update(&c.health, sliding, est.velocity, measured_n, model_n);
    }

    /// Online refinement of Fc, Fs - Fc and sigma2 from the measured friction; false when it
    /// diverged and was reset to the identified parameters.
    fn refine(&mut self, cond: &UnderConditions<f32>, measured_force: f32) -> bool {
        let c = &self.config;
        let est = self.estimator;
        let y = measured_force - c.mass_kg * est.acceleration;
        // the model's own decay: its shape, the direction's vs under asymmetry, and the
        // period's oil temperature's under a Stribeck curve that follows the viscosity
        let decay = self.model.stribeck_decay_under(est.velocity, cond);
        if !self
            .refiner
            .update(&c.refine, y, est.velocity, est.acceleration, decay)
        {
            return true;
        }
        let [fc, dfs, s2] = self.refiner.theta;
        match self.model.params.with_levels(s2, fc, fc + dfs) {
            Ok(q) => {
                self.model.params = q;
                true
            }
            Err(_) => {
                self.refiner.reset();
                self.model.params = c.model.params;
                false
            }
        }
    }

    /// Nulls the valve and enters `Safe`.
    fn enter_safe(&mut self, faults: Faults) -> Output {
        self.mode = Mode::Safe { sane_ticks: 0 };
        self.stuck_ticks = 0;
        self.cascade.reset();
        Output {
            faults,
            safe: true,
            ..Output::default()
        }
    }
}
