//! The compensation robustness matrix (`host-sim track --robustness`): every plant the
//! simulator has, every controller model a user could end up with, every compensation
//! configuration, on three scenarios.
//!
//! * Plants: `plain` (Table 2) and each of the eight extra effects at strength 1
//!   ([`crate::scenarios::with_effect`]); `temperature_dependence` is the warming plant (the
//!   oil warms ~15-20 K over a minute).
//! * Controller models: `truth` (the plant's whole friction model, effects included),
//!   `identified` (the realistic identification run on that plant, as a user gets it: a plain
//!   LuGre model), `static_x0.7` .. `static_x1.3` (the truth with Fc, Fs and sigma2 scaled),
//!   `sigma0_x0.1` and `sigma0_x10`.
//! * Configurations: `pid` (the plain cascade), `static_ff` (the static friction map on the
//!   reference velocity), `dob` (the disturbance observer), `feedforward`,
//!   `feedforward_observer`, `full`. `pid` and `dob` use no friction model: they run once per
//!   plant and scenario and are reported under every model.
//! * Scenarios: `low_speed` (the `track` sine, 2 mm at 0.2 Hz, 20 s), `point_to_point`
//!   (+-20 mm minimum-jerk moves of 1.5 s with 1.5 s dwells, 18 s: settling time and creep),
//!   `creep` (0.5 mm/s for 10 s each way, a tenth of the Stribeck velocity: stick-slip
//!   territory).
//!
//! `settle_s` (point_to_point only): the mean over moves of the time from the end of the move
//! until the error stays within [`SETTLE_BAND_M`] for the rest of the dwell; `None` if a move
//! never settles.

use crate::identify::{self, Algorithm};
use crate::plant::{PlantConfig, SensorConfig};
use crate::scenarios;
use crate::track::{self, Run};
use lugre_servo::control::{ControllerConfig, Features};
use lugre_servo::friction::{EffectKind, FrictionModel, LugreParams};
use rayon::prelude::*;
use serde::Serialize;

/// Band within which a point-to-point move counts as settled: 0.1 % of the 20 mm move \[m\].
pub const SETTLE_BAND_M: f64 = 20e-6;

/// The scenarios.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Scenario {
    /// The `track` low-speed sine.
    LowSpeed,
    /// Moves with dwells.
    PointToPoint,
    /// Slow constant velocity each way.
    Creep,
}

/// Move length \[m\], move time \[s\] and dwell \[s\] of `point_to_point`.
const P2P: (f64, f64, f64) = (0.02, 1.5, 1.5);
/// Creep speed [m/s], time each way \[s\], acceleration ramp \[s\].
const CREEP: (f64, f64, f64) = (5e-4, 10.0, 0.2);

impl Scenario {
    /// All three.
    pub const ALL: [Scenario; 3] = [Self::LowSpeed, Self::PointToPoint, Self::Creep];

    /// Name in the JSON.
    pub fn name(self) -> &'static str {
        match self {
            Self::LowSpeed => "low_speed",
            Self::PointToPoint => "point_to_point",
            Self::Creep => "creep",
        }
    }

    /// Duration \[s\].
    pub fn duration_s(self) -> f64 {
        match self {
            Self::LowSpeed => 20.0,
            Self::PointToPoint => 6.0 * (P2P.1 + P2P.2),
            Self::Creep => 2.0 * CREEP.1,
        }
    }

    /// Reference `(x, v, a)` at time `t`.
    pub fn reference(self, t: f64) -> (f64, f64, f64) {
        match self {
            Self::LowSpeed => track::low_speed_reference(t),
            Self::PointToPoint => {
                let (d, tm, dwell) = P2P;
                let cycle = tm + dwell;
                let k = (t / cycle).floor().max(0.0);
                let tau = t - k * cycle;
                // alternate +d, -d around 0.25 m: moves start at 0.24 or 0.26
                let up = (k as i64) % 2 == 0;
                let (x0, dir) = if up {
                    (0.25 - d / 2.0, 1.0)
                } else {
                    (0.25 + d / 2.0, -1.0)
                };
                if tau >= tm {
                    return (x0 + dir * d, 0.0, 0.0);
                }
                let s = tau / tm;
                let p = 10.0 * s.powi(3) - 15.0 * s.powi(4) + 6.0 * s.powi(5);
                let dp = (30.0 * s.powi(2) - 60.0 * s.powi(3) + 30.0 * s.powi(4)) / tm;
                let ddp = (60.0 * s - 180.0 * s.powi(2) + 120.0 * s.powi(3)) / (tm * tm);
                (x0 + dir * d * p, dir * d * dp, dir * d * ddp)
            }
            Self::Creep => {
                let (v, leg, ramp) = CREEP;
                let a = v / ramp;
                // velocity profile: ramp up, hold, ramp through zero to -v at t = leg, hold
                let vel = |t: f64| -> f64 {
                    if t < ramp {
                        a * t
                    } else if t < leg - ramp {
                        v
                    } else if t < leg + ramp {
                        v - a * (t - (leg - ramp))
                    } else {
                        -v
                    }
                };
                let acc = if t < ramp {
                    a
                } else if (leg - ramp..leg + ramp).contains(&t) {
                    -a
                } else {
                    0.0
                };
                // position: the exact integral of the piecewise-linear velocity
                let p1 = 0.5 * v * ramp + v * (leg - 2.0 * ramp);
                let pos = if t < ramp {
                    0.5 * a * t * t
                } else if t < leg - ramp {
                    0.5 * v * ramp + v * (t - ramp)
                } else if t < leg + ramp {
                    let tau = t - (leg - ramp);
                    p1 + v * tau - 0.5 * a * tau * tau
                } else {
                    p1 - v * (t - (leg + ramp))
                };
                (0.245 + pos, vel(t), acc)
            }
        }
    }
}

/// The controller configurations.
pub const CONFIGS: [(&str, Features); 6] = [
    ("pid", Features::PID),
    ("static_ff", Features::STATIC_FEEDFORWARD),
    ("dob", Features::DISTURBANCE_OBSERVER),
    ("feedforward", Features::FEEDFORWARD),
    ("feedforward_observer", Features::FEEDFORWARD_OBSERVER),
    ("full", Features::FULL),
];

/// The controller models, by name.
pub const MODELS: [&str; 8] = [
    "truth",
    "identified",
    "static_x0.7",
    "static_x0.8",
    "static_x1.2",
    "static_x1.3",
    "sigma0_x0.1",
    "sigma0_x10",
];

/// The models within +-30 % static mismatch (the targets' set): the first six of [`MODELS`].
pub const WITHIN_30_PERCENT: &[&str] = MODELS.split_at(6).0;

/// One case of the matrix (the JSON contract).
#[derive(Clone, Debug, Serialize)]
pub struct Case {
    /// Plant name.
    pub plant: String,
    /// Controller model name.
    pub model: String,
    /// Configuration name.
    pub config: String,
    /// Scenario name.
    pub scenario: String,
    /// RMS of `x_ref - x` after the first 0.5 s \[m\].
    pub rms_err_m: f64,
    /// Largest |error| \[m\].
    pub max_err_m: f64,
    /// Largest |error| within 0.3 s after a reversal of the reference \[m\].
    pub reversal_err_m: f64,
    /// Mean settling time after a move \[s\] (point_to_point; `None` elsewhere or never).
    pub settle_s: Option<f64>,
    /// Periods that raised a fault flag.
    pub fault_ticks: usize,
}

/// The matrix, as written by `--json`.
#[derive(Clone, Debug, Serialize)]
pub struct Matrix {
    /// Every case.
    pub cases: Vec<Case>,
}

impl Matrix {
    /// The case with these names.
    pub fn get(&self, plant: &str, model: &str, config: &str, scenario: &str) -> Option<&Case> {
        self.cases.iter().find(|c| {
            c.plant == plant && c.model == model && c.config == config && c.scenario == scenario
        })
    }
}

/// The plants: `plain` and one per effect.
pub fn plants() -> Vec<(String, PlantConfig)> {
    let mut v = vec![("plain".to_string(), PlantConfig::default())];
    for k in EffectKind::ALL {
        let mut cfg = PlantConfig::default();
        scenarios::with_effect(&mut cfg, k.name(), 1.0).unwrap_or(());
        v.push((k.name().to_string(), cfg));
    }
    v
}

/// The controller's friction model `name` for a plant (`identified`: the given result).
pub fn model(
    name: &str,
    plant: &PlantConfig,
    identified: &LugreParams<f64>,
) -> Option<FrictionModel<f64>> {
    let truth = plant.friction;
    let p = truth.params;
    let scaled = |k: f64, s0: f64| {
        LugreParams::new(
            p.bristle_stiffness() * s0,
            p.bristle_damping(),
            p.viscous_coefficient() * k,
            p.coulomb_force() * k,
            p.static_force() * k,
            p.stribeck_velocity(),
        )
        .ok()
        .map(|params| FrictionModel { params, ..truth })
    };
    match name {
        "truth" => Some(truth),
        "identified" => Some(FrictionModel::plain(*identified)),
        "static_x0.7" => scaled(0.7, 1.0),
        "static_x0.8" => scaled(0.8, 1.0),
        "static_x1.2" => scaled(1.2, 1.0),
        "static_x1.3" => scaled(1.3, 1.0),
        "sigma0_x0.1" => scaled(1.0, 0.1),
        "sigma0_x10" => scaled(1.0, 10.0),
        _ => None,
    }
}

/// Identification as a user runs it on a plant (realistic sensors, improved GA); Table 2 if
/// it fails.
pub fn identified(plant: &PlantConfig, seed: u64) -> LugreParams<f64> {
    let data = identify::realistic_data(plant, seed);
    let r = identify::identify(Algorithm::Improved, &data, seed, None);
    identify::params_of(&r).unwrap_or_else(LugreParams::table2)
}

/// Mean settling time of the point-to-point moves in `run` \[s\]: from the end of each move
/// until the error stays within [`SETTLE_BAND_M`] for the rest of its dwell; `None` when a
/// move never does.
pub fn settle_time(run: &Run) -> Option<f64> {
    let (_, tm, dwell) = P2P;
    let cycle = tm + dwell;
    let moves = (Scenario::PointToPoint.duration_s() / cycle).round() as usize;
    let mut total = 0.0;
    for k in 0..moves {
        let (end, next) = (k as f64 * cycle + tm, (k + 1) as f64 * cycle);
        let dwell: Vec<&(f64, f64)> = run
            .trace
            .iter()
            .filter(|(t, _)| *t >= end && *t < next)
            .collect();
        let last_out = dwell.iter().rposition(|(_, e)| e.abs() > SETTLE_BAND_M);
        match last_out {
            None => {}
            Some(i) if i + 1 < dwell.len() => total += dwell[i + 1].0 - end,
            Some(_) => return None,
        }
    }
    Some(total / moves as f64)
}

/// Runs one case.
pub fn run_case(
    plant: &PlantConfig,
    model: &FrictionModel<f64>,
    features: Features,
    scenario: Scenario,
    sensors: SensorConfig,
) -> Option<(track::Tracking, Option<f64>, usize)> {
    let ctrl = ControllerConfig::for_simulated_axis(model.cast().ok()?, features);
    let r = track::run(
        plant,
        sensors,
        ctrl,
        &|t| scenario.reference(t),
        scenario.duration_s(),
    );
    let settle = (scenario == Scenario::PointToPoint)
        .then(|| settle_time(&r))
        .flatten();
    Some((r.tracking, settle, r.fault_ticks))
}

/// The whole matrix (in parallel); `progress` is called once per simulated run.
pub fn matrix(seed: u64, progress: &(dyn Fn() + Sync)) -> Matrix {
    let sensors = SensorConfig::realistic(seed);
    let plants = plants();
    let ids: Vec<LugreParams<f64>> = plants
        .par_iter()
        .map(|(_, p)| identified(p, seed))
        .collect();
    // model-free configurations once per plant and scenario, the others per model
    let mut jobs: Vec<(usize, Option<&str>, usize, Scenario)> = Vec::new();
    for pi in 0..plants.len() {
        for s in Scenario::ALL {
            for (ci, (name, _)) in CONFIGS.iter().enumerate() {
                if matches!(*name, "pid" | "dob") {
                    jobs.push((pi, None, ci, s));
                } else {
                    for m in MODELS {
                        jobs.push((pi, Some(m), ci, s));
                    }
                }
            }
        }
    }
    let results: Vec<Vec<Case>> = jobs
        .par_iter()
        .map(|&(pi, m, ci, s)| {
            let (pname, plant) = &plants[pi];
            let (cname, features) = CONFIGS[ci];
            let model_for_run = model(m.unwrap_or("truth"), plant, &ids[pi]);
            let out = model_for_run.and_then(|fm| run_case(plant, &fm, features, s, sensors));
            progress();
            let Some((t, settle, faults)) = out else {
                return Vec::new();
            };
            let names: Vec<&str> = m.map_or(MODELS.to_vec(), |m| vec![m]);
            names
                .into_iter()
                .map(|mn| Case {
                    plant: pname.clone(),
                    model: mn.to_string(),
                    config: cname.to_string(),
                    scenario: s.name().to_string(),
                    rms_err_m: t.rms_err_m,
                    max_err_m: t.max_err_m,
                    reversal_err_m: t.reversal_err_m,
                    settle_s: settle,
                    fault_ticks: faults,
                })
                .collect()
        })
        .collect();
    Matrix {
        cases: results.into_iter().flatten().collect(),
    }
}

/// Number of simulated runs [`matrix`] makes.
pub fn runs() -> usize {
    let per_scenario = 2 + (CONFIGS.len() - 2) * MODELS.len();
    (1 + EffectKind::ALL.len()) * Scenario::ALL.len() * per_scenario
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn references_are_consistent() {
        for s in Scenario::ALL {
            let h = 1e-4;
            let n = (s.duration_s() / h) as usize;
            let mut worst_v: f64 = 0.0;
            for k in 1..n - 1 {
                let t = k as f64 * h;
                let (x0, _, _) = s.reference(t - h);
                let (_, v, _) = s.reference(t);
                let (x1, _, _) = s.reference(t + h);
                worst_v = worst_v.max(((x1 - x0) / (2.0 * h) - v).abs());
            }
            assert!(worst_v < 1e-5, "{}: v inconsistent by {worst_v}", s.name());
            let (x, _, _) = s.reference(0.0);
            assert!((0.2..0.3).contains(&x));
        }
    }
}
