//! Closed-loop tracking: the core's controller (f32, exactly as on the MCU) against the
//! hydraulic simulator, and the `track` benchmark scenarios.
//!
//! * `low_speed`: `x_ref = 0.25 m + 2 mm sin(2 pi 0.2 Hz t)` for 20 s (peak 2.5 mm/s, half the
//!   Stribeck velocity; 8 reversals), Table 2 plant, realistic sensors. Configurations: plain
//!   cascade (`pid`), + feed-forward, + observer, and everything (`full`: + the residual
//!   observer and the refinement).
//! * `drift`: `x_ref = 0.25 m + 50 mm sin(2 pi 0.4 Hz t)` for 60 s while the oil warms by
//!   ~18 K (plant `temperature_dependence`: sigma2 falls ~30 %, Fc rises ~18 %); the
//!   controller knows Table 2 only. `no_drift` (plant without the effect), `fixed`
//!   (refinement off) and `refined`.
//!
//! Errors are the true position's: `x_ref - x`. "Peak error at reversals" is the largest
//! |error| within 0.3 s after each reversal of the reference velocity (a change of its sign,
//! also across a dwell at rest).

use crate::plant::{Plant, PlantConfig, SensorConfig, Sensors};
use crate::scenarios;
use lugre_servo::control::{Controller, ControllerConfig, Features, Measurements, Reference};
use lugre_servo::friction::FrictionModel;
use serde::Serialize;

/// Time \[s\] and tracking error \[m\] per control period.
pub type ErrorTrace = Vec<(f64, f64)>;

/// Tracking figures of one run.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Tracking {
    /// RMS error \[m\].
    pub rms_err_m: f64,
    /// Maximum |error| \[m\].
    pub max_err_m: f64,
    /// Largest |error| within 0.3 s after a reversal \[m\].
    pub reversal_err_m: f64,
}

/// A run's figures, its error trace and the controller's final model.
#[derive(Clone, Debug)]
pub struct Run {
    /// Figures.
    pub tracking: Tracking,
    /// Time \[s\] and error \[m\] per period.
    pub trace: Vec<(f64, f64)>,
    /// The valve command per period [-].
    pub valve_command: Vec<f32>,
    /// The controller's friction model at the end (refined parameters).
    pub final_model: FrictionModel<f32>,
    /// Periods that raised a fault flag.
    pub fault_ticks: usize,
    /// Oil temperature at the end \[degC\].
    pub final_temperature_c: f64,
    /// When the friction health monitor first warned \[s\] (None: never).
    pub first_health_warning_s: Option<f64>,
}

/// Runs `ctrl` against `plant` following `reference(t) -> (x, v, a)` for `duration` s.
pub fn run(
    plant_cfg: &PlantConfig,
    sensors: SensorConfig,
    ctrl: ControllerConfig,
    reference: &dyn Fn(f64) -> (f64, f64, f64),
    duration: f64,
) -> Run {
    run_changing(
        plant_cfg,
        sensors,
        ctrl,
        reference,
        duration,
        &mut |_, _, _| {},
    )
}

/// As [`run`], with `change(t, plant, controller)` called before every period: a plant whose
/// friction drifts during the run (wear, contamination) for the health monitor's tests, or
/// new settings sent to the controller.
pub fn run_changing(
    plant_cfg: &PlantConfig,
    sensors: SensorConfig,
    ctrl: ControllerConfig,
    reference: &dyn Fn(f64) -> (f64, f64, f64),
    duration: f64,
    change: &mut dyn FnMut(f64, &mut Plant, &mut Controller),
) -> Run {
    let dt = 1e-3;
    let (x0, _, _) = reference(0.0);
    let mut plant = Plant::new(plant_cfg.clone(), x0);
    let mut sens = Sensors::new(sensors);
    let mut controller = Controller::new(ctrl);
    let n = (duration / dt).round() as usize;
    let mut trace = Vec::with_capacity(n);
    let mut valve_command = Vec::with_capacity(n);
    let mut fault_ticks = 0;
    let mut reversal_err: f64 = 0.0;
    let mut last_v = 0.0f64;
    let mut since_reversal = f64::INFINITY;
    let mut first_health_warning_s = None;
    for k in 0..n {
        let t = k as f64 * dt;
        change(t, &mut plant, &mut controller);
        let (m, r) = controller_inputs(&sens.sample(&plant), reference(t));
        let out = controller.tick(&m, &r);
        if out.health_warning && first_health_warning_s.is_none() {
            first_health_warning_s = Some(t);
        }
        if !out.faults.is_empty() {
            fault_ticks += 1;
            if std::env::var_os("LUGRE_DEBUG").is_some() {
                eprintln!("t {t:.3} faults {:?}", out.faults);
            }
        }
        valve_command.push(out.valve_command);
        plant.advance(out.valve_command as f64, dt);
        let (xr, vr, _) = reference(t + dt);
        let e = xr - plant.state.x;
        // a reversal: the reference velocity changes sign (also across a dwell at rest)
        if vr * last_v < 0.0 {
            since_reversal = 0.0;
        }
        if vr != 0.0 {
            last_v = vr;
        }
        since_reversal += dt;
        if since_reversal <= 0.3 && t > 0.5 {
            reversal_err = reversal_err.max(e.abs());
        }
        trace.push((t + dt, e));
    }
    // skip the first 0.5 s (the controller starts from rest)
    let steady: Vec<f64> = trace
        .iter()
        .filter(|(t, _)| *t > 0.5)
        .map(|(_, e)| *e)
        .collect();
    let rms = (steady.iter().map(|e| e * e).sum::<f64>() / steady.len().max(1) as f64).sqrt();
    let max = steady.iter().fold(0.0f64, |m, e| m.max(e.abs()));
    Run {
        tracking: Tracking {
            rms_err_m: rms,
            max_err_m: max,
            reversal_err_m: reversal_err,
        },
        trace,
        valve_command,
        final_model: *controller.model(),
        fault_ticks,
        final_temperature_c: plant.state.temperature_c,
        first_health_warning_s,
    }
}

/// What the controller gets in a period (f32, as on the MCU): the sensors' measurement and the
/// reference `(x, v, a)`.
pub fn controller_inputs(
    m: &crate::plant::Measurement,
    (x, v, a): (f64, f64, f64),
) -> (Measurements, Reference) {
    (
        Measurements {
            position_m: m.x as f32,
            pressure_a_pa: m.p_a as f32,
            pressure_b_pa: m.p_b as f32,
            temperature_c: Some(m.temperature_c as f32),
        },
        Reference {
            position_m: x as f32,
            velocity_m_per_s: v as f32,
            acceleration_m_per_s2: a as f32,
        },
    )
}

/// The largest change of a per-period signal `u` (a valve command) from one period to the
/// next, over the steps into periods `from..to` (clipped to the signal).
pub fn largest_step(u: &[f32], from: usize, to: usize) -> f32 {
    let to = to.min(u.len());
    let from = from.saturating_sub(1).min(to);
    u[from..to]
        .windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .fold(0.0, f32::max)
}

/// The low-speed reference.
pub fn low_speed_reference(t: f64) -> (f64, f64, f64) {
    let (a, w) = (0.002, 2.0 * std::f64::consts::PI * 0.2);
    (
        0.25 + a * (w * t).sin(),
        a * w * (w * t).cos(),
        -a * w * w * (w * t).sin(),
    )
}

/// The drift scenario's reference.
pub fn drift_reference(t: f64) -> (f64, f64, f64) {
    let (a, w) = (0.05, 2.0 * std::f64::consts::PI * 0.4);
    (
        0.25 + a * (w * t).sin(),
        a * w * (w * t).cos(),
        -a * w * w * (w * t).sin(),
    )
}

/// The controller configuration for the simulated axis with Table 2 identified parameters.
pub fn controller_config(features: Features) -> ControllerConfig {
    let model = FrictionModel::plain(lugre_servo::friction::LugreParams::<f32>::table2());
    ControllerConfig::for_simulated_axis(model, features)
}

/// Results of the `track` benchmark, as its JSON.
#[derive(Clone, Debug, Serialize)]
pub struct TrackReport {
    /// Low-speed scenario.
    pub low_speed: LowSpeed,
    /// Drift scenario.
    pub drift: Drift,
}

/// Low-speed configurations.
#[derive(Clone, Debug, Serialize)]
#[allow(missing_docs)]
pub struct LowSpeed {
    pub pid: Tracking,
    pub feedforward: Tracking,
    pub feedforward_observer: Tracking,
    pub full: Tracking,
}

/// Drift configurations.
#[derive(Clone, Debug, Serialize)]
#[allow(missing_docs)]
pub struct Drift {
    pub no_drift: Tracking,
    pub fixed: Tracking,
    pub refined: Tracking,
    /// Refined [Fc, Fs - Fc, sigma2] at the end, and the plant's drifted truth at the end.
    pub refined_params: [f64; 3],
    pub drifted_truth: [f64; 3],
}

/// Runs every scenario (in parallel) and returns the report plus the low-speed traces of
/// `pid` and `full` for plotting.
pub fn benchmark(seed: u64) -> (TrackReport, ErrorTrace, ErrorTrace) {
    use rayon::prelude::*;
    let sensors = SensorConfig::realistic(seed);
    let plain = PlantConfig::default();
    let mut warming = PlantConfig::default();
    scenarios::with_effect(&mut warming, "temperature_dependence", 1.0).unwrap_or(());
    let jobs: Vec<(PlantConfig, Features, bool)> = vec![
        (plain.clone(), Features::PID, false),
        (plain.clone(), Features::FEEDFORWARD, false),
        (plain.clone(), Features::FEEDFORWARD_OBSERVER, false),
        (plain.clone(), Features::FULL, false),
        (plain.clone(), Features::FULL, true),
        (warming.clone(), Features::FEEDFORWARD_OBSERVER, true),
        (warming.clone(), Features::FULL, true),
    ];
    let runs: Vec<Run> = jobs
        .par_iter()
        .map(|(p, f, drift)| {
            if *drift {
                run(p, sensors, controller_config(*f), &drift_reference, 60.0)
            } else {
                run(
                    p,
                    sensors,
                    controller_config(*f),
                    &low_speed_reference,
                    20.0,
                )
            }
        })
        .collect();
    // the plant's drifted parameters at the end of the refined run
    let end_temp = runs[6].final_temperature_c;
    let c = lugre_servo::friction::Conditions {
        position: 0.25,
        pressure_sum: 0.0,
        temperature: end_temp,
    };
    let l = warming.friction.levels(0.1, &c, 0.0);
    let drifted = [l.coulomb, l.static_ - l.coulomb, l.viscous];
    let fm = &runs[6].final_model.params;
    let refined = [
        fm.coulomb_force() as f64,
        (fm.static_force() - fm.coulomb_force()) as f64,
        fm.viscous_coefficient() as f64,
    ];
    let report = TrackReport {
        low_speed: LowSpeed {
            pid: runs[0].tracking,
            feedforward: runs[1].tracking,
            feedforward_observer: runs[2].tracking,
            full: runs[3].tracking,
        },
        drift: Drift {
            no_drift: runs[4].tracking,
            fixed: runs[5].tracking,
            refined: runs[6].tracking,
            refined_params: refined,
            drifted_truth: drifted,
        },
    };
    (report, runs[0].trace.clone(), runs[3].trace.clone())
}
