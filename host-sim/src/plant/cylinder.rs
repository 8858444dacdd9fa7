//! Double-acting single-rod cylinder with compressible oil, internal leakage and end stops.
//!
//! ```text
//! V_a = V_a0 + A_a x                V_b = V_b0 + A_b (L - x)
//! Q_l = C_l (p_a - p_b)             (internal leakage across the piston seal, A -> B when p_a > p_b)
//! dp_a/dt = beta / V_a (Q_a - A_a v - Q_l)
//! dp_b/dt = beta / V_b (Q_b + A_b v + Q_l)
//! F_hyd   = p_a A_a - p_b A_b
//! ```
//! Cavitation: a chamber pressure never goes below the oil's vapour pressure (the chamber would
//! fill with vapour instead); relief valves cap each chamber at 1.3 p_s. End stops are stiff
//! one-sided spring-dampers.

use super::valve::ServoValve;
use lugre_servo::axis::AxisGeometry;

/// Cylinder, oil and load configuration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CylinderConfig {
    /// Piston-side area A_a [m^2] (50 mm bore).
    pub piston_area_m2: f64,
    /// Rod-side annulus area A_b [m^2] (28 mm rod).
    pub annulus_area_m2: f64,
    /// Stroke L \[m\].
    pub stroke_m: f64,
    /// Dead volume of chamber A (lines, valve ports) [m^3].
    pub dead_volume_a_m3: f64,
    /// Dead volume of chamber B [m^3].
    pub dead_volume_b_m3: f64,
    /// Effective oil bulk modulus beta \[Pa\].
    pub bulk_modulus_pa: f64,
    /// Internal leakage coefficient C_l [m^3/(s Pa)].
    pub leakage_m3_per_s_pa: f64,
    /// Moving mass (piston, rod, load) \[kg\].
    pub moving_mass_kg: f64,
    /// Oil vapour pressure (absolute) \[Pa\].
    pub vapour_pressure_pa: f64,
    /// Relief pressure (absolute) \[Pa\].
    pub relief_pressure_pa: f64,
    /// End stop stiffness [N/m].
    pub end_stop_stiffness_n_per_m: f64,
    /// End stop damping [N s/m].
    pub end_stop_damping_n_s_per_m: f64,
}

impl Default for CylinderConfig {
    fn default() -> Self {
        let axis = AxisGeometry::SIMULATED;
        Self {
            piston_area_m2: axis.piston_area_m2(),
            annulus_area_m2: axis.annulus_area_m2(),
            stroke_m: axis.stroke_m,
            dead_volume_a_m3: 5e-5,
            dead_volume_b_m3: 5e-5,
            bulk_modulus_pa: 1.4e9,
            leakage_m3_per_s_pa: 2e-13,
            moving_mass_kg: axis.moving_mass_kg,
            vapour_pressure_pa: 2e3,
            relief_pressure_pa: 1.3 * 210e5,
            end_stop_stiffness_n_per_m: 1e9,
            end_stop_damping_n_s_per_m: 2e5,
        }
    }
}

/// The cylinder's equations (configuration only; pressures live in the plant state).
#[derive(Clone, Copy, Debug)]
pub struct Cylinder {
    /// Configuration.
    pub config: CylinderConfig,
}

impl Cylinder {
    /// Builds the cylinder.
    pub fn new(config: CylinderConfig) -> Self {
        Self { config }
    }

    /// Hydraulic force on the piston \[N\], positive towards +x.
    pub fn force(&self, p_a: f64, p_b: f64) -> f64 {
        p_a * self.config.piston_area_m2 - p_b * self.config.annulus_area_m2
    }

    /// Chamber pressures at rest with the valve closed: force balance and `p_a + p_b = p_s`.
    pub fn rest_pressures(&self, valve: &ServoValve) -> (f64, f64) {
        let ps = valve.config.supply_pressure_pa;
        let (a, b) = (self.config.piston_area_m2, self.config.annulus_area_m2);
        let p_a = ps * b / (a + b);
        (p_a, ps - p_a)
    }

    /// (dp_a/dt, dp_b/dt) [Pa/s].
    pub fn pressure_rates(
        &self,
        p_a: f64,
        p_b: f64,
        x: f64,
        v: f64,
        q_a: f64,
        q_b: f64,
    ) -> (f64, f64) {
        let c = &self.config;
        let xc = x.clamp(0.0, c.stroke_m);
        let v_a = c.dead_volume_a_m3 + c.piston_area_m2 * xc;
        let v_b = c.dead_volume_b_m3 + c.annulus_area_m2 * (c.stroke_m - xc);
        let q_leak = c.leakage_m3_per_s_pa * (p_a - p_b);
        (
            c.bulk_modulus_pa / v_a * (q_a - c.piston_area_m2 * v - q_leak),
            c.bulk_modulus_pa / v_b * (q_b + c.annulus_area_m2 * v + q_leak),
        )
    }

    /// Cavitation floor and relief ceiling.
    pub fn clamp_pressures(&self, p_a: f64, p_b: f64) -> (f64, f64) {
        let (lo, hi) = (
            self.config.vapour_pressure_pa,
            self.config.relief_pressure_pa,
        );
        (p_a.clamp(lo, hi), p_b.clamp(lo, hi))
    }

    fn penetration(&self, x: f64) -> f64 {
        if x < 0.0 {
            x
        } else if x > self.config.stroke_m {
            x - self.config.stroke_m
        } else {
            0.0
        }
    }

    /// End-stop force \[N\] (pushes back only).
    pub fn end_stop_force(&self, x: f64, v: f64) -> f64 {
        let d = self.penetration(x);
        let f = -self.config.end_stop_stiffness_n_per_m * d
            - self.config.end_stop_damping_n_s_per_m * v;
        if d < 0.0 {
            f.max(0.0)
        } else if d > 0.0 {
            f.min(0.0)
        } else {
            0.0
        }
    }

    /// Elastic energy stored in an end stop \[J\].
    pub fn end_stop_energy(&self, x: f64) -> f64 {
        let d = self.penetration(x);
        0.5 * self.config.end_stop_stiffness_n_per_m * d * d
    }
}
