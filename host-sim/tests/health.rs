//! The on-target friction health monitor against the hydraulic simulator: it warns within
//! 10 s when the plant's friction levels rise 30 % during a run, and never on runs without
//! drift (with the Table 2 model and with the model `identify --noise realistic` wrote for
//! the firmware).

use host_sim::params_file::ParamFile;
use host_sim::plant::{Plant, PlantConfig, SensorConfig};
use host_sim::scenarios::scale_friction_levels;
use host_sim::track::{self, drift_reference, low_speed_reference};
use lugre_servo::control::{ControllerConfig, Features};
use lugre_servo::friction::{FrictionModel, LugreParams};

/// The model the firmware runs with (identified from realistic sensors).
fn firmware_model() -> FrictionModel<f32> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../firmware/params.toml");
    let (_, model) = ParamFile::read(std::path::Path::new(path)).expect("firmware/params.toml");
    model.cast().expect("representable in f32")
}

fn config(model: FrictionModel<f32>) -> ControllerConfig {
    ControllerConfig::for_simulated_axis(model, Features::FULL)
}

/// First warning of a 60 s drift-scenario run whose friction levels follow `scale(t)`.
fn first_warning(model: FrictionModel<f32>, scale: &dyn Fn(f64) -> f64) -> Option<f64> {
    let base = PlantConfig::default().friction.params;
    let run = track::run_changing(
        &PlantConfig::default(),
        SensorConfig::realistic(3),
        config(model),
        &drift_reference,
        60.0,
        &mut |t, plant: &mut Plant, _| {
            plant.config.friction.params =
                scale_friction_levels(&base, scale(t)).expect("scaled Table 2 is physical")
        },
    );
    assert_eq!(run.fault_ticks, 0);
    run.first_health_warning_s
}

#[test]
fn a_30_percent_rise_of_the_friction_levels_warns_within_10_s() {
    let table2 = FrictionModel::plain(LugreParams::<f32>::table2());
    for model in [table2, firmware_model()] {
        // a step at 20 s
        let step = first_warning(model, &|t| if t < 20.0 { 1.0 } else { 1.3 });
        let t = step.expect("the step was not reported");
        eprintln!("step warned at {t:.2} s");
        assert!((20.0..30.0).contains(&t), "step: warned at {t:.2} s");
        // a ramp over 20..30 s: reported within 10 s of reaching +30 %
        let ramp = first_warning(model, &|t| 1.0 + 0.3 * ((t - 20.0) / 10.0).clamp(0.0, 1.0));
        let t = ramp.expect("the ramp was not reported");
        eprintln!("ramp warned at {t:.2} s");
        assert!((20.0..40.0).contains(&t), "ramp: warned at {t:.2} s");
    }
}

#[test]
fn runs_without_drift_never_warn() {
    let table2 = FrictionModel::plain(LugreParams::<f32>::table2());
    for model in [table2, firmware_model()] {
        assert_eq!(first_warning(model, &|_| 1.0), None);
        for seed in [1, 2] {
            let run = track::run(
                &PlantConfig::default(),
                SensorConfig::realistic(seed),
                config(model),
                &low_speed_reference,
                20.0,
            );
            assert_eq!(run.first_health_warning_s, None);
        }
    }
}
