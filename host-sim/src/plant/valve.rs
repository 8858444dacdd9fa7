//! 4-way critically lapped servo valve.
//!
//! Spool: `x'' = w^2 (u - x) - 2 zeta w x'` (normalised spool position, `u` the command).
//! Flow (critically lapped, positive spool connects P->A and B->T):
//! ```text
//! x >= 0:  Q_a =  K x sqrt(p_s - p_a),  Q_b = -K x sqrt(p_b - p_t)
//! x <  0:  Q_a =  K x sqrt(p_a - p_t),  Q_b = -K x sqrt(p_s - p_b)
//! K = Q_rated / sqrt(dp_rated / 2)     (rated flow at the rated total drop, half per land)
//! ```
//! `sqrt(dp)` is replaced by `dp / (dp^2 + p_l^2)^(1/4)` with `p_l` = 1 bar: identical above a
//! few bar, sign-correct for reverse flow, and of finite slope at zero drop (a real orifice goes
//! laminar there), which keeps the chamber equations integrable.

/// Servo valve configuration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ValveConfig {
    /// Spool natural frequency \[Hz\].
    pub natural_frequency_hz: f64,
    /// Spool damping ratio [-].
    pub damping_ratio: f64,
    /// Rated flow at full opening and the rated pressure drop [m^3/s].
    pub rated_flow_m3_per_s: f64,
    /// Rated total pressure drop across both lands \[Pa\].
    pub rated_pressure_drop_pa: f64,
    /// Supply pressure (absolute) \[Pa\].
    pub supply_pressure_pa: f64,
    /// Tank pressure (absolute) \[Pa\].
    pub tank_pressure_pa: f64,
}

impl Default for ValveConfig {
    fn default() -> Self {
        Self {
            natural_frequency_hz: 100.0,
            damping_ratio: 0.7,
            rated_flow_m3_per_s: 40.0 / 60_000.0, // 40 L/min
            rated_pressure_drop_pa: 70e5,
            supply_pressure_pa: 210e5,
            tank_pressure_pa: 1e5,
        }
    }
}

/// A servo valve (stateless apart from its configuration; the spool state is in the plant).
#[derive(Clone, Copy, Debug)]
pub struct ServoValve {
    /// Configuration.
    pub config: ValveConfig,
    gain: f64,
    omega: f64,
}

const LAMINAR_PRESSURE_PA: f64 = 1e5;

/// `sqrt(dp)` with a laminar region around zero (see the module docs).
fn orifice(dp: f64) -> f64 {
    dp / (dp * dp + LAMINAR_PRESSURE_PA * LAMINAR_PRESSURE_PA)
        .sqrt()
        .sqrt()
}

impl ServoValve {
    /// Builds the valve.
    pub fn new(config: ValveConfig) -> Self {
        Self {
            gain: config.rated_flow_m3_per_s / (config.rated_pressure_drop_pa / 2.0).sqrt(),
            omega: 2.0 * std::f64::consts::PI * config.natural_frequency_hz,
            config,
        }
    }

    /// One semi-implicit step of the spool dynamics, returns (position, rate).
    pub fn spool_step(&self, x: f64, xd: f64, u: f64, h: f64) -> (f64, f64) {
        let w = self.omega;
        let acc = w * w * (u - x) - 2.0 * self.config.damping_ratio * w * xd;
        let xd = xd + acc * h;
        let x = (x + xd * h).clamp(-1.0, 1.0);
        (x, xd)
    }

    /// Flows into chamber A and chamber B [m^3/s] for spool `x` and chamber pressures.
    pub fn flows(&self, x: f64, p_a: f64, p_b: f64) -> (f64, f64) {
        let (ps, pt) = (self.config.supply_pressure_pa, self.config.tank_pressure_pa);
        let k = self.gain * x;
        if x >= 0.0 {
            (k * orifice(ps - p_a), -k * orifice(p_b - pt))
        } else {
            (k * orifice(p_a - pt), -k * orifice(ps - p_b))
        }
    }
}
