//! Experiments an engineer runs on a rig, run on the simulated axis.
//!
//! Each runs the plant at 1 kHz behind its sensors with a plain commissioning controller (not
//! the friction-compensating one: that is what the experiments are for) and returns a
//! [`Record`] in the common format, with the simulator's truth as extra columns
//! (`true_v`, `true_friction`).
//!
//! Commissioning controller: position loop `u = k_p (x_ref - x) + v_ref / v_full` (hydraulic
//! axes are naturally velocity-controlled: valve opening sets flow and so speed, so a P loop
//! with velocity feed-forward tracks ramps with zero steady velocity error), or a force loop
//! `u = k_f (F_ref - F)` on the force measured from the chamber pressures.

use crate::plant::{Measurement, Plant, PlantConfig, SensorConfig, Sensors};
use crate::record::Record;

/// Control period \[s\].
pub const PERIOD_S: f64 = 1e-3;

/// Valve command per velocity, approximate full-opening speed [m/s] of the default axis.
const FULL_OPENING_SPEED: f64 = 0.6;
/// Position loop gain [1/m]: about 40 1/s velocity loop gain, well inside the hydraulic
/// resonance (`~470 rad/s`, low damping).
const POSITION_GAIN: f64 = 40.0 / FULL_OPENING_SPEED;
/// Force loop gain [1/N].
const FORCE_GAIN: f64 = 4e-6;
/// Force loop integral time \[s\]: the integral cancels the internal leakage, which otherwise
/// holds a steady force error of ~170 N at a closed valve.
const FORCE_INTEGRAL_S: f64 = 0.05;

/// What the loop regulates at each tick.
#[derive(Clone, Copy, Debug)]
pub enum Setpoint {
    /// Position \[m\] and its velocity [m/s].
    Position {
        /// Reference position \[m\].
        x: f64,
        /// Reference velocity [m/s] (feed-forward).
        v: f64,
    },
    /// Actuator force \[N\].
    Force(f64),
}

/// A simulated rig: plant plus sensors, with a recorder.
pub struct Rig {
    /// The plant.
    pub plant: Plant,
    /// The sensors.
    pub sensors: Sensors,
    rec: Record,
    force_integral: f64,
    true_v: Vec<f64>,
    true_f: Vec<f64>,
}

impl Rig {
    /// A rig at rest at `x0` \[m\].
    pub fn new(config: PlantConfig, sensors: SensorConfig, x0: f64) -> Self {
        let mut rec = Record {
            x_ref: Some(Vec::new()),
            p_a: Some(Vec::new()),
            p_b: Some(Vec::new()),
            temp: Some(Vec::new()),
            ..Default::default()
        };
        rec.meta.push(("source".into(), "host-sim".into()));
        rec.meta.push((
            "moving_mass_kg".into(),
            config.cylinder.moving_mass_kg.to_string(),
        ));
        Self {
            plant: Plant::new(config, x0),
            sensors: Sensors::new(sensors),
            rec,
            force_integral: 0.0,
            true_v: Vec::new(),
            true_f: Vec::new(),
        }
    }

    /// Actuator force from measured pressures \[N\].
    pub fn measured_force(&self, m: &Measurement) -> f64 {
        let c = &self.plant.config.cylinder;
        m.p_a * c.piston_area_m2 - m.p_b * c.annulus_area_m2
    }

    /// One control period with the commissioning controller; records the sample.
    pub fn tick(&mut self, sp: Setpoint) {
        let m = self.sensors.sample(&self.plant);
        let f = self.measured_force(&m);
        let (u, x_ref) = match sp {
            Setpoint::Position { x, v } => (POSITION_GAIN * (x - m.x) + v / FULL_OPENING_SPEED, x),
            Setpoint::Force(fr) => {
                self.force_integral += (fr - f) * PERIOD_S / FORCE_INTEGRAL_S;
                (FORCE_GAIN * (fr - f + self.force_integral), f64::NAN)
            }
        };
        self.record(&m, f, x_ref);
        self.plant.advance(u, PERIOD_S);
    }

    /// Records one sample (used by external controllers too).
    pub fn record(&mut self, m: &Measurement, force: f64, x_ref: f64) {
        let r = &mut self.rec;
        r.t.push(m.t);
        r.x.push(m.x);
        r.force.push(force);
        push(&mut r.x_ref, if x_ref.is_finite() { x_ref } else { m.x });
        push(&mut r.p_a, m.p_a);
        push(&mut r.p_b, m.p_b);
        push(&mut r.temp, m.temperature_c);
        self.true_v.push(m.truth.v);
        self.true_f.push(m.truth.friction_force);
    }

    /// Ends the run and returns the record.
    pub fn finish(mut self, name: &str) -> Record {
        self.rec.meta.push(("experiment".into(), name.into()));
        self.rec.extra.push(("true_v".into(), self.true_v));
        self.rec.extra.push(("true_friction".into(), self.true_f));
        self.rec
    }
}

fn push(c: &mut Option<Vec<f64>>, v: f64) {
    if let Some(c) = c {
        c.push(v);
    }
}

/// One point of the measured steady-state friction curve: the core's type, which the static
/// identification stage consumes.
pub use lugre_servo::identify::cost::SteadyPoint;

/// Log-spaced sweep velocities [m/s], `n` points from `v_min` to `v_max`.
pub fn log_speeds(v_min: f64, v_max: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| v_min * (v_max / v_min).powf(i as f64 / (n.max(2) - 1) as f64))
        .collect()
}

/// Constant-velocity sweep in both directions: for each speed, a ramp out at `+v` and back at
/// `-v`; the friction in the last 60 % of each constant-velocity leg is averaged (force minus
/// `M` times the mean acceleration over the window). Returns the record and the curve
/// (both directions, in run order).
pub fn velocity_sweep(
    config: &PlantConfig,
    sensors: SensorConfig,
    speeds: &[f64],
) -> (Record, Vec<SteadyPoint>) {
    let x0 = 0.05;
    let mass = config.cylinder.moving_mass_kg;
    let mut rig = Rig::new(config.clone(), sensors, x0);
    let mut points = Vec::new();
    let mut x_ref = x0;
    let settle = 0.3;
    for &v in speeds {
        let leg = (0.12 / v).clamp(0.8, 2.5);
        for dir in [1.0, -1.0] {
            let start = rig.rec.len();
            let n = ((leg + settle) / PERIOD_S).round() as usize;
            for _ in 0..n {
                x_ref += dir * v * PERIOD_S;
                rig.tick(Setpoint::Position {
                    x: x_ref,
                    v: dir * v,
                });
            }
            let end = rig.rec.len();
            let w0 = start + ((settle + 0.4 * leg) / PERIOD_S) as usize;
            points.push(steady_point(&rig.rec, w0, end, mass));
            // short rest between legs
            for _ in 0..100 {
                rig.tick(Setpoint::Position { x: x_ref, v: 0.0 });
            }
        }
    }
    (rig.finish("velocity_sweep"), points)
}

/// Mean friction in samples `[i0, i1)` of a record at roughly constant velocity.
pub fn steady_point(r: &Record, i0: usize, i1: usize, mass: f64) -> SteadyPoint {
    let i1 = i1.min(r.len());
    let i0 = i0.min(i1.saturating_sub(3));
    let n = (i1 - i0) as f64;
    let dt = r.t[i1 - 1] - r.t[i0];
    let velocity = (r.x[i1 - 1] - r.x[i0]) / dt;
    // mean acceleration from the velocity at both ends of the window (5-sample differences)
    let k = 5.min((i1 - i0) / 4).max(1);
    let v_start = (r.x[i0 + k] - r.x[i0]) / (r.t[i0 + k] - r.t[i0]);
    let v_end = (r.x[i1 - 1] - r.x[i1 - 1 - k]) / (r.t[i1 - 1] - r.t[i1 - 1 - k]);
    let mean_acc = (v_end - v_start) / dt;
    let mean_f = r.force[i0..i1].iter().sum::<f64>() / n;
    SteadyPoint {
        velocity,
        force: mean_f - mass * mean_acc,
        force_std_error: mean_force_error(&r.force[i0..i1]),
    }
}

/// Blocks a leg's force is split into for its mean's standard error.
pub const ERROR_BLOCKS: usize = 8;

/// How much a leg's force moved over it \[N\]: the mean of its last third less the mean of its
/// first third (a force still settling; 0 for fewer than three samples).
pub fn settling_drift(f: &[f64]) -> f64 {
    let third = f.len() / 3;
    if third == 0 {
        return 0.0;
    }
    crate::stats::mean(&f[f.len() - third..]) - crate::stats::mean(&f[..third])
}

/// The standard error of a leg's mean force \[N\]: the scatter of the means of
/// [`ERROR_BLOCKS`] consecutive blocks (blocks of tens of milliseconds average out white
/// sensor noise but not a servo's ringing or a slow drift, which move the mean as much), and
/// half the [`settling_drift`] (what a force still settling leaves in the mean), added in
/// quadrature.
pub fn mean_force_error(f: &[f64]) -> f64 {
    if f.len() < 3 * ERROR_BLOCKS {
        return 0.0;
    }
    let blocks: Vec<f64> = f
        .chunks_exact(f.len() / ERROR_BLOCKS)
        .take(ERROR_BLOCKS)
        .map(crate::stats::mean)
        .collect();
    let scatter = crate::stats::std_dev(&blocks);
    let drift = 0.5 * settling_drift(f);
    (scatter * scatter / ERROR_BLOCKS as f64 + drift * drift).sqrt()
}

/// Slow force ramp below breakaway (pre-sliding): force-controlled, `0 -> +frac Fs -> -frac Fs
/// -> 0` over `duration` seconds. The displacement stays in the sub-micrometre bristle range.
pub fn presliding_ramp(
    config: &PlantConfig,
    sensors: SensorConfig,
    fraction_of_fs: f64,
    duration: f64,
) -> Record {
    let peak = fraction_of_fs * config.friction.params.static_force();
    let mut rig = Rig::new(config.clone(), sensors, 0.25);
    let n = (duration / PERIOD_S).round() as usize;
    for i in 0..n {
        let s = i as f64 / n as f64; // 0..1: triangle 0 -> +1 -> -1 -> 0
        let shape = if s < 0.25 {
            4.0 * s
        } else if s < 0.75 {
            1.0 - 4.0 * (s - 0.25)
        } else {
            -1.0 + 4.0 * (s - 0.75)
        };
        rig.tick(Setpoint::Force(peak * shape));
    }
    rig.finish("presliding_ramp")
}

/// Sinusoidal position trajectory `x = x0 + A sin(2 pi f t)`.
pub fn sinusoid(
    config: &PlantConfig,
    sensors: SensorConfig,
    amplitude: f64,
    freq_hz: f64,
    duration: f64,
) -> Record {
    let x0 = 0.25;
    let mut rig = Rig::new(config.clone(), sensors, x0);
    let w = 2.0 * std::f64::consts::PI * freq_hz;
    let n = (duration / PERIOD_S).round() as usize;
    for i in 0..n {
        let t = i as f64 * PERIOD_S;
        rig.tick(Setpoint::Position {
            x: x0 + amplitude * (w * t).sin(),
            v: amplitude * w * (w * t).cos(),
        });
    }
    rig.finish("sinusoid")
}

/// A point-to-point move with a trapezoidal velocity profile (triangular when too short to
/// reach the top speed).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Move {
    /// Distance \[m\] (> 0).
    pub distance: f64,
    /// Acceleration [m/s^2].
    pub accel: f64,
    t_acc: f64,
    v_peak: f64,
    t_flat: f64,
}

impl Move {
    /// A move over `distance` \[m\] at up to `v_max` [m/s] with `accel` [m/s^2].
    pub fn new(distance: f64, v_max: f64, accel: f64) -> Self {
        let t_acc = v_max / accel;
        let d_acc = 0.5 * accel * t_acc * t_acc;
        let (t_acc, v_peak, t_flat) = if 2.0 * d_acc >= distance {
            let t_acc = (distance / accel).sqrt();
            (t_acc, accel * t_acc, 0.0)
        } else {
            (t_acc, v_max, (distance - 2.0 * d_acc) / v_max)
        };
        Self {
            distance,
            accel,
            t_acc,
            v_peak,
            t_flat,
        }
    }

    /// Duration \[s\].
    pub fn duration(&self) -> f64 {
        2.0 * self.t_acc + self.t_flat
    }

    /// (position from the start \[m\], velocity [m/s]) at time `s` into the move.
    pub fn at(&self, s: f64) -> (f64, f64) {
        let (a, t_acc, t_move) = (self.accel, self.t_acc, self.duration());
        if s < t_acc {
            (0.5 * a * s * s, a * s)
        } else if s < t_acc + self.t_flat {
            (
                0.5 * a * t_acc * t_acc + self.v_peak * (s - t_acc),
                self.v_peak,
            )
        } else if s < t_move {
            let r = t_move - s;
            (self.distance - 0.5 * a * r * r, a * r)
        } else {
            (self.distance, 0.0)
        }
    }
}

/// Trapezoidal moves between `x0` and `x0 + distance` and back, with dwells at both ends:
/// (position from `x0`, velocity) at time `t` within the period `2 (move + dwell)`.
pub fn trapezoid_reference(
    t: f64,
    distance: f64,
    v_max: f64,
    accel: f64,
    dwell: f64,
) -> (f64, f64) {
    let mv = Move::new(distance, v_max, accel);
    let t_move = mv.duration();
    let tau = t.rem_euclid(2.0 * (t_move + dwell));
    if tau < t_move + dwell {
        mv.at(tau)
    } else {
        let (x, v) = mv.at(tau - t_move - dwell);
        (distance - x, -v)
    }
}

/// Trapezoidal moves with dwells, tracked by the commissioning loop.
pub fn trapezoid(
    config: &PlantConfig,
    sensors: SensorConfig,
    distance: f64,
    v_max: f64,
    accel: f64,
    dwell: f64,
    duration: f64,
) -> Record {
    let x0 = 0.1;
    let mut rig = Rig::new(config.clone(), sensors, x0);
    let n = (duration / PERIOD_S).round() as usize;
    for i in 0..n {
        let (x, v) = trapezoid_reference(i as f64 * PERIOD_S, distance, v_max, accel, dwell);
        rig.tick(Setpoint::Position { x: x0 + x, v });
    }
    rig.finish("trapezoid")
}
