//! Named plant variants: each extra physical effect switched on at a chosen strength, and the
//! composite experiment used to diagnose them.

use crate::experiments::{Move, Rig, Setpoint, PERIOD_S};
use crate::plant::{PlantConfig, SensorConfig};
use crate::record::Record;
use lugre_servo::friction::effects as fx;

/// Switches effect `name` on in `cfg`; `strength` 1.0 is clearly visible, 0.3 subtle.
pub fn with_effect(cfg: &mut PlantConfig, name: &str, strength: f64) -> crate::Result<()> {
    use lugre_servo::friction::EffectKind as K;
    let kind = crate::diagnose::parse_effect(name)?;
    let e = &mut cfg.friction.effects;
    let s = strength;
    match kind {
        K::Asymmetry => {
            e.asymmetry = Some(fx::Asymmetry {
                coulomb_ratio: 0.15 * s,
                static_ratio: 0.15 * s,
                viscous_ratio: 0.25 * s,
                stribeck_velocity_ratio: 0.0,
            })
        }
        K::Offset => e.offset = Some(fx::Offset { force: 150.0 * s }),
        K::LoadDependence => {
            e.load_dependence = Some(fx::LoadDependence::power(
                4e-5 * s,
                cfg.valve.supply_pressure_pa,
                1.0,
            ))
        }
        K::PositionDependence => {
            e.position_dependence = Some(fx::PositionDependence::linear(1000.0 * s, 0.25))
        }
        K::TemperatureDependence => {
            e.temperature_dependence = Some(fx::TemperatureDependence {
                viscous_per_kelvin: 0.02 * s,
                coulomb_per_kelvin: 0.01 * s,
                reference_temperature: cfg.thermal.initial_c,
                // host-sim's plant keeps the Stribeck curve fixed (its law before session 74)
                stribeck_hersey_exponent: 0.0,
            });
            // warm the oil by ~15-20 K over a minute (pump and throttling losses)
            cfg.thermal.heat_capacity_j_per_k = 4_000.0;
            cfg.thermal.extra_heat_w = 1_200.0;
        }
        K::StribeckShape => {
            // strong: 0.5 (a sharp fall from breakaway), subtle (0.4): 1.4
            e.stribeck_shape = Some(fx::StribeckShape::with_exponent(2.0 - 1.5 * s))
        }
        K::ViscousPower => {
            e.viscous_power = Some(fx::ViscousPower {
                exponent: 1.0 - 0.4 * s,
                reference_velocity: 0.02,
            })
        }
        K::DwellStiction => {
            e.dwell_stiction = Some(fx::DwellStiction {
                max_increase: 300.0 * s,
                time_constant: 1.0,
                stick_velocity: 2e-4,
                renewal_distance: crate::params_file::DEFAULT_RENEWAL_DISTANCE_M,
                age_at_stick: fx::DwellAge::Accumulates,
                clock: fx::DwellClock::BodySpeed,
                growth: lugre_servo::friction::DwellGrowth::Exponential,
            })
        }
    }
    Ok(())
}

/// A deterministic pseudo-random sequence in [0, 1) (no RNG state needed for a schedule).
fn unit(i: u64) -> f64 {
    let mut z = i
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(0x6A09_E667_F3BC_C909);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    (z ^ (z >> 31)) as f64 / u64::MAX as f64
}

/// The composite commissioning record for diagnosis: point-to-point moves across the stroke
/// (0.06 .. 0.44 m) at speeds from 1 mm/s to 100 mm/s (log-spread), with dwells from 0.05 s to
/// 3 s, so that every effect has something to show: both directions, the Stribeck region,
/// fast sliding, long and short rests, the whole stroke, varying pressures and (with the
/// temperature effect) warming oil. The schedule is fixed; `sensors.seed` only changes noise.
pub fn diagnosis_run(cfg: &PlantConfig, sensors: SensorConfig, duration: f64) -> Record {
    let mut x = 0.25;
    let mut rig = Rig::new(cfg.clone(), sensors, x);
    let n = (duration / PERIOD_S).round() as usize;
    let mut k = 0u64;
    let accel = 0.5;
    while rig.plant.state.t < duration - 0.5 * PERIOD_S && rig_len(&rig) < n {
        let target = 0.06 + 0.38 * unit(3 * k);
        let speed = 1e-3 * 100f64.powf(unit(3 * k + 1));
        let dwell = 0.05 * 60f64.powf(unit(3 * k + 2));
        k += 1;
        // at most ~2.5 s per move, so slow speeds make short moves
        let dist = (target - x).clamp(-(speed * 2.5 + 0.002), speed * 2.5 + 0.002);
        let target = x + dist;
        let dir = dist.signum();
        let mv = Move::new(dist.abs().max(1e-9), speed, accel);
        let steps = (mv.duration() / PERIOD_S).ceil() as usize;
        for i in 0..steps {
            let (d, v) = mv.at((i + 1) as f64 * PERIOD_S);
            rig.tick(Setpoint::Position {
                x: x + dir * d,
                v: dir * v,
            });
            if rig_len(&rig) >= n {
                break;
            }
        }
        x = target;
        for _ in 0..(dwell / PERIOD_S) as usize {
            if rig_len(&rig) >= n {
                break;
            }
            rig.tick(Setpoint::Position { x, v: 0.0 });
        }
    }
    rig.finish("diagnosis_run")
}

fn rig_len(rig: &Rig) -> usize {
    (rig.plant.state.t / PERIOD_S).round() as usize
}

/// The plant's friction levels (Fc, Fs, sigma2) scaled by `k` (other parameters kept).
pub fn scale_friction_levels(
    base: &lugre_servo::friction::LugreParams<f64>,
    k: f64,
) -> Option<lugre_servo::friction::LugreParams<f64>> {
    base.with_levels(
        k * base.viscous_coefficient(),
        k * base.coulomb_force(),
        k * base.static_force(),
    )
    .ok()
}
