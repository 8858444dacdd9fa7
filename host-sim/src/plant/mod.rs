//! The electro-hydraulic position axis that stands in for hardware.
//!
//! A 4-way critically lapped servo valve drives a double-acting single-rod cylinder that moves a
//! mass against LuGre friction (with the core's optional extra effects). Sensors (encoder,
//! pressure transducers, oil thermometer) sit between the plant and the controller.
//!
//! ## Integration
//! The plant is advanced in fixed sub-steps (default 20 us, 50 per 1 ms control period) with
//! the valve command held (zero-order hold, as a DAC does):
//! * friction: the core's exact zero-order-hold bristle step with the current velocity, so the
//!   stiff `sigma0 = 3.9e9 N/m` is stable at any sub-step;
//! * mass and spool: semi-implicit (symplectic) Euler, which keeps the lightly damped 700 Hz
//!   bristle-mass mode of Table 2 (`sqrt(sigma0 / M)`) bounded instead of pumping energy into it
//!   (`omega h = 0.09` at 20 us);
//! * chamber pressures: explicit Euler; the orifice law is regularised below 1 bar
//!   (laminar transition) so its slope is finite, giving `h * (beta / V) * dQ/dp < 0.1`.
//!
//! A 1 us-step run of the same plant agrees with the 20 us one (test `substep_convergence`).

mod cylinder;
mod sensors;
mod valve;

pub use cylinder::{Cylinder, CylinderConfig};
pub use sensors::{Measurement, SensorConfig, Sensors};
pub use valve::{ServoValve, ValveConfig};

use lugre_servo::friction::{Conditions, FrictionModel, FrictionState, LugreParams};

/// Oil temperature model: `C dT/dt = P_friction + P_extra - G (T - T_ambient)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThermalConfig {
    /// Heat capacity of the oil and steel that warm together, C [J/K].
    pub heat_capacity_j_per_k: f64,
    /// Thermal conductance to ambient, G [W/K].
    pub conductance_w_per_k: f64,
    /// Ambient temperature \[degC\].
    pub ambient_c: f64,
    /// Initial oil temperature \[degC\].
    pub initial_c: f64,
    /// Extra heat input, e.g. pump and valve throttling losses \[W\].
    pub extra_heat_w: f64,
}

impl Default for ThermalConfig {
    fn default() -> Self {
        Self {
            heat_capacity_j_per_k: 20_000.0,
            conductance_w_per_k: 20.0,
            ambient_c: 40.0,
            initial_c: 40.0,
            extra_heat_w: 0.0,
        }
    }
}

/// Everything that defines a simulated axis.
#[derive(Clone, Debug)]
pub struct PlantConfig {
    /// Servo valve.
    pub valve: ValveConfig,
    /// Cylinder, oil and moving mass.
    pub cylinder: CylinderConfig,
    /// Friction (Table 2 and no extra effect by default).
    pub friction: FrictionModel<f64>,
    /// Oil temperature model.
    pub thermal: ThermalConfig,
    /// Integration sub-step \[s\].
    pub substep_s: f64,
}

impl Default for PlantConfig {
    fn default() -> Self {
        Self {
            valve: ValveConfig::default(),
            cylinder: CylinderConfig::default(),
            friction: FrictionModel::plain(LugreParams::table2()),
            thermal: ThermalConfig::default(),
            substep_s: 20e-6,
        }
    }
}

/// True state of the plant (what the sensors look at).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PlantState {
    /// Time \[s\].
    pub t: f64,
    /// Spool position, normalised to [-1, 1].
    pub spool: f64,
    /// Spool velocity [1/s].
    pub spool_rate: f64,
    /// Chamber A (piston side) absolute pressure \[Pa\].
    pub p_a: f64,
    /// Chamber B (rod side) absolute pressure \[Pa\].
    pub p_b: f64,
    /// Piston position \[m\], 0 = fully retracted.
    pub x: f64,
    /// Piston velocity [m/s].
    pub v: f64,
    /// Piston acceleration at the last sub-step [m/s^2].
    pub a: f64,
    /// Friction state.
    pub friction: FrictionState<f64>,
    /// Friction force at the last sub-step \[N\] (including the offset force).
    pub friction_force: f64,
    /// Oil temperature \[degC\].
    pub temperature_c: f64,
}

/// Energy bookkeeping, integrated along with the state (for checks and reports).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EnergyLedger {
    /// Work done by the hydraulic force on the piston \[J\].
    pub hydraulic_work_j: f64,
    /// Work done against friction and offset \[J\].
    pub friction_work_j: f64,
    /// Work done by the end stops \[J\].
    pub end_stop_work_j: f64,
}

/// The simulated axis.
#[derive(Clone, Debug)]
pub struct Plant {
    /// Configuration.
    pub config: PlantConfig,
    /// True state.
    pub state: PlantState,
    /// Energy bookkeeping.
    pub energy: EnergyLedger,
    valve: ServoValve,
    cylinder: Cylinder,
}

impl Plant {
    /// A plant at rest at position `x0` \[m\], with chamber pressures balanced at rest.
    pub fn new(config: PlantConfig, x0: f64) -> Self {
        let cylinder = Cylinder::new(config.cylinder);
        let valve = ServoValve::new(config.valve);
        let (p_a, p_b) = cylinder.rest_pressures(&valve);
        let state = PlantState {
            p_a,
            p_b,
            x: x0,
            temperature_c: config.thermal.initial_c,
            ..Default::default()
        };
        Self {
            config,
            state,
            energy: EnergyLedger::default(),
            valve,
            cylinder,
        }
    }

    /// Conditions the friction effects see now.
    pub fn conditions(&self) -> Conditions<f64> {
        Conditions {
            position: self.state.x,
            pressure_sum: self.state.p_a + self.state.p_b,
            temperature: self.state.temperature_c,
        }
    }

    /// Actuator force `p_a A_a - p_b A_b` \[N\] (true).
    pub fn actuator_force(&self) -> f64 {
        self.cylinder.force(self.state.p_a, self.state.p_b)
    }

    /// Advances by `duration` \[s\] with the valve command `u` (normalised, clamped to [-1, 1])
    /// held.
    pub fn advance(&mut self, u: f64, duration: f64) {
        let u = if u.is_finite() {
            u.clamp(-1.0, 1.0)
        } else {
            0.0
        };
        let n = (duration / self.config.substep_s).round().max(1.0) as usize;
        let h = duration / n as f64;
        for _ in 0..n {
            self.substep(u, h);
        }
    }

    fn substep(&mut self, u: f64, h: f64) {
        let s = &mut self.state;
        // Valve spool (2nd order), semi-implicit.
        let (spool, spool_rate) = self.valve.spool_step(s.spool, s.spool_rate, u, h);
        s.spool = spool;
        s.spool_rate = spool_rate;

        // Friction with the exact bristle step at the current velocity.
        let c = Conditions {
            position: s.x,
            pressure_sum: s.p_a + s.p_b,
            temperature: s.temperature_c,
        };
        let f_fric = self.config.friction.step(&mut s.friction, s.v, &c, h);
        s.friction_force = f_fric;

        let f_hyd = self.cylinder.force(s.p_a, s.p_b);
        let f_stop = self.cylinder.end_stop_force(s.x, s.v);
        let m = self.config.cylinder.moving_mass_kg;
        let a = (f_hyd - f_fric + f_stop) / m;
        let v_old = s.v;
        s.v += a * h;
        s.a = a;
        let v_mid = 0.5 * (v_old + s.v);
        s.x += s.v * h;

        // Energy bookkeeping with the mid-step velocity (trapezoid on the power).
        self.energy.hydraulic_work_j += f_hyd * v_mid * h;
        self.energy.friction_work_j += f_fric * v_mid * h;
        self.energy.end_stop_work_j += f_stop * v_mid * h;

        // Chambers: flows from the valve, motion and leakage.
        let (q_a, q_b) = self.valve.flows(s.spool, s.p_a, s.p_b);
        let (dp_a, dp_b) = self
            .cylinder
            .pressure_rates(s.p_a, s.p_b, s.x, s.v, q_a, q_b);
        let (p_a, p_b) = self
            .cylinder
            .clamp_pressures(s.p_a + dp_a * h, s.p_b + dp_b * h);
        s.p_a = p_a;
        s.p_b = p_b;

        // Oil temperature.
        let th = &self.config.thermal;
        let p_heat = (f_fric * s.v).abs() + th.extra_heat_w;
        s.temperature_c += h * (p_heat - th.conductance_w_per_k * (s.temperature_c - th.ambient_c))
            / th.heat_capacity_j_per_k;
        s.t += h;
    }

    /// Kinetic energy of the moving mass plus the potential energy in the bristles and end
    /// stops \[J\].
    pub fn mechanical_energy(&self) -> f64 {
        let m = self.config.cylinder.moving_mass_kg;
        let sigma0 = self.config.friction.params.bristle_stiffness();
        0.5 * m * self.state.v * self.state.v
            + 0.5 * sigma0 * self.state.friction.z * self.state.friction.z
            + self.cylinder.end_stop_energy(self.state.x)
    }
}
