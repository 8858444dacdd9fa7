//! The 1 kHz controller tick on any inputs: any f32 bit pattern for every measurement and
//! reference (NaN, infinities, 3e38, subnormals), any of the feature sets, and a friction
//! model drawn from the bytes when it is a valid one. Every period: the valve command is
//! finite and within [-1, 1], and every output is finite.
#![no_main]

use libfuzzer_sys::fuzz_target;
use lugre_servo::control::{Controller, ControllerConfig, Features, Measurements, Reference};
use lugre_servo::friction::{FrictionModel, LugreParams};

fn f32_at(b: &[u8]) -> f32 {
    f32::from_le_bytes([b[0], b[1], b[2], b[3]])
}

fuzz_target!(|data: &[u8]| {
    if data.len() < 25 {
        return;
    }
    let (head, ticks) = data.split_at(25);
    let features = [
        Features::PID,
        Features::FEEDFORWARD,
        Features::FEEDFORWARD_OBSERVER,
        Features::FULL,
        Features::STATIC_FEEDFORWARD,
        Features::DISTURBANCE_OBSERVER,
    ][usize::from(head[0] % 6)];
    let p: Vec<f32> = head[1..].chunks_exact(4).map(f32_at).collect();
    let params = LugreParams::new(p[0], p[1], p[2], p[3], p[4], p[5])
        .ok()
        .filter(|q| q.check_physical().is_ok())
        .unwrap_or_else(LugreParams::table2);
    let config = ControllerConfig::for_simulated_axis(FrictionModel::plain(params), features);
    let mut c = Controller::new(config);
    // one period = 7 f32: position, p_a, p_b, temperature, reference x, v, a
    for t in ticks.chunks_exact(28) {
        let v: Vec<f32> = t.chunks_exact(4).map(f32_at).collect();
        let o = c.tick(
            &Measurements {
                position_m: v[0],
                pressure_a_pa: v[1],
                pressure_b_pa: v[2],
                temperature_c: (!v[3].is_nan()).then_some(v[3]),
            },
            &Reference {
                position_m: v[4],
                velocity_m_per_s: v[5],
                acceleration_m_per_s2: v[6],
            },
        );
        assert!(
            o.valve_command.is_finite() && o.valve_command.abs() <= 1.0,
            "valve {}",
            o.valve_command
        );
        for (name, x) in [
            ("force_demand_n", o.force_demand_n),
            ("friction_compensation_n", o.friction_compensation_n),
            ("friction_feedforward_n", o.friction_feedforward_n),
            ("friction_observer_n", o.friction_observer_n),
            ("friction_residual_n", o.friction_residual_n),
        ] {
            assert!(x.is_finite(), "{name} = {x}");
        }
        if o.safe {
            assert_eq!(o.valve_command, 0.0);
        }
    }
});
