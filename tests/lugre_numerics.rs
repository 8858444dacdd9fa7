//! The exact zero-order-hold LuGre step against a fine-step f64 reference, its steady state,
//! its pre-sliding stiffness, its stability, and its f32 error.

use lugre_servo::friction::{bristle_step, LugreParams, LugreState};
use proptest::prelude::*;

const DT: f64 = 1e-3;

/// Fine-step reference: classic RK4 of dz/dt = v(t) - sigma0 |v(t)| z / g(v(t)) at 0.5 us
/// (a*h < 0.2 for |v| <= 0.05 m/s), force with the exact velocity at the sample instant.
fn reference(p: &LugreParams<f64>, vel: &dyn Fn(f64) -> f64, t_end: f64) -> Vec<f64> {
    let h = 0.5e-6;
    let per = (DT / h).round() as usize;
    let f = |t: f64, z: f64| {
        let v = vel(t);
        v - p.bristle_stiffness() * v.abs() * z / p.stribeck_curve(v)
    };
    let mut z = 0.0;
    let mut t = 0.0;
    let mut out = Vec::new();
    for _ in 0..(t_end / DT).round() as usize {
        for _ in 0..per {
            let k1 = f(t, z);
            let k2 = f(t + h / 2.0, z + h / 2.0 * k1);
            let k3 = f(t + h / 2.0, z + h / 2.0 * k2);
            let k4 = f(t + h, z + h * k3);
            z += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
            t += h;
        }
        let v = vel(t);
        out.push(
            p.bristle_stiffness() * z + p.bristle_damping() * f(t, z) + p.viscous_coefficient() * v,
        );
    }
    out
}

/// Mean velocity over `[t0, t0 + DT]` (Simpson, 16 panels): displacement / DT, which is what
/// encoder differences give a controller.
fn mean_velocity(vel: &dyn Fn(f64) -> f64, t0: f64) -> f64 {
    let n = 16;
    let h = DT / n as f64;
    let mut acc = vel(t0) + vel(t0 + DT);
    for i in 1..n {
        acc += if i % 2 == 1 { 4.0 } else { 2.0 } * vel(t0 + i as f64 * h);
    }
    acc * h / 3.0 / DT
}

/// The 1 ms model driven by the mean velocity over each step.
fn stepped(p: &LugreParams<f64>, vel: &dyn Fn(f64) -> f64, t_end: f64) -> Vec<f64> {
    let mut s = LugreState::new();
    (0..(t_end / DT).round() as usize)
        .map(|k| s.step(p, mean_velocity(vel, k as f64 * DT), DT))
        .collect()
}

/// The same model driven by the velocity at the end of each step (a wrong input: it misstates
/// the displacement by a h^2 / 2, which sigma0 turns into a large force error).
fn stepped_end_velocity(p: &LugreParams<f64>, vel: &dyn Fn(f64) -> f64, t_end: f64) -> Vec<f64> {
    let mut s = LugreState::new();
    (1..=(t_end / DT).round() as usize)
        .map(|k| s.step(p, vel(k as f64 * DT), DT))
        .collect()
}

fn max_err(p: &LugreParams<f64>, vel: &dyn Fn(f64) -> f64, t_end: f64) -> f64 {
    let r = reference(p, vel, t_end);
    let s = stepped(p, vel, t_end);
    r.iter()
        .zip(&s)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
}

#[test]
fn matches_fine_reference_on_sinusoid_ramp_and_reversal() {
    let p = LugreParams::<f64>::table2();
    let fs = p.static_force();
    // Sinusoid: 10 mm amplitude at 0.5 Hz (peak 31 mm/s), 4 reversals.
    let sine = |t: f64| 0.01 * std::f64::consts::PI * (std::f64::consts::PI * t).cos();
    // Ramp in velocity through the Stribeck region: 0 -> 20 mm/s in 1 s.
    let ramp = |t: f64| 0.02 * t;
    // Slow reversal: v = 2 mm/s * cos(2 pi 0.5 t), long time in pre-sliding around reversals.
    let rev = |t: f64| 0.002 * (std::f64::consts::PI * t).cos();
    let e_sine = max_err(&p, &sine, 2.0);
    let e_ramp = max_err(&p, &ramp, 1.0);
    let e_rev = max_err(&p, &rev, 2.0);
    let r = reference(&p, &sine, 2.0);
    let e_end = r
        .iter()
        .zip(&stepped_end_velocity(&p, &sine, 2.0))
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    println!("sinusoid driven by the end-of-step velocity instead: {e_end:.1} N");
    assert!(
        e_end > 10.0 * e_sine,
        "the mean-velocity input should matter"
    );
    println!(
        "max |F - F_ref|: sinusoid {e_sine:.3} N, ramp {e_ramp:.3} N, reversal {e_rev:.3} N (Fs = {fs} N)"
    );
    // The only error left is holding v over 1 ms; measured: see the printout and the README.
    // Measured 2.43 N, 0.49 N, 0.16 N: the residual is sigma2 times (mean - instant) velocity.
    assert!(e_sine < 0.006 * fs, "sinusoid error {e_sine} N");
    assert!(e_ramp < 0.002 * fs, "ramp error {e_ramp} N");
    assert!(e_rev < 0.001 * fs, "reversal error {e_rev} N");
}

#[test]
fn steady_state_equals_fss_within_0p1_percent() {
    let p = LugreParams::<f64>::table2();
    for i in 0..25 {
        let v = 1e-4 * (1e3f64).powf(i as f64 / 24.0); // 0.1 mm/s .. 0.1 m/s
        for v in [v, -v] {
            let mut s = LugreState::new();
            let mut f = 0.0;
            // long enough to slide past the bristle transient (z settles within a few um)
            let steps = ((20e-6 / v.abs()) / DT).ceil() as usize + 50;
            for _ in 0..steps {
                f = s.step(&p, v, DT);
            }
            let fss = p.steady_state_force(v);
            assert!(
                ((f - fss) / fss).abs() < 1e-3,
                "v = {v}: F = {f}, Fss = {fss}"
            );
        }
    }
}

#[test]
fn presliding_stiffness_equals_sigma0() {
    let p = LugreParams::<f64>::table2();
    let mut s = LugreState::new();
    // 1 nm of displacement at 0.1 um/s: the initial slope of the pre-sliding curve
    // (Fs / sigma0 = 162 nm; the slope falls by a*t/2 = 0.3 % over this move).
    let v = 1e-7;
    let mut f = 0.0;
    for _ in 0..10 {
        f = s.step(&p, v, DT);
    }
    let dx = 10.0 * v * DT;
    let k = (f - (p.bristle_damping() + p.viscous_coefficient()) * v) / dx;
    let rel = (k - p.bristle_stiffness()).abs() / p.bristle_stiffness();
    assert!(
        rel < 0.01,
        "stiffness {k:.4e} vs sigma0 {:.4e}",
        p.bristle_stiffness()
    );
}

#[test]
fn explicit_euler_diverges_where_the_exact_step_does_not() {
    // Documents why the exact step exists: at 1 ms and 1 mm/s, a*h = sigma0|v|h/g ~ 6 > 2.
    let p = LugreParams::<f64>::table2();
    let v = 1e-3;
    let (mut z_euler, mut s) = (0.0f64, LugreState::new());
    for _ in 0..50 {
        let g = p.stribeck_curve(v);
        z_euler += DT * (v - p.bristle_stiffness() * v.abs() * z_euler / g);
        s.step(&p, v, DT);
    }
    assert!(
        !z_euler.is_finite() || z_euler.abs() > 1.0,
        "Euler z = {z_euler}"
    );
    assert!(s.z.abs() <= p.static_force() / p.bristle_stiffness());
}

#[test]
fn f32_tracks_f64_within_bound() {
    let p64 = LugreParams::<f64>::table2();
    let p32 = p64.cast::<f32>().unwrap();
    let (mut s64, mut s32) = (LugreState::<f64>::new(), LugreState::<f32>::new());
    let mut worst = 0.0f64;
    for k in 0..20_000 {
        let t = k as f64 * DT;
        let v = 0.02 * (2.0 * std::f64::consts::PI * 0.3 * t).sin()
            + 0.003 * (2.0 * std::f64::consts::PI * 2.1 * t).sin();
        let f64_ = s64.step(&p64, v, DT);
        let f32_ = s32.step(&p32, v as f32, 1e-3f32);
        worst = worst.max((f64_ - f32_ as f64).abs());
    }
    println!("max |F_f32 - F_f64| over 20 s of reversals: {worst:.4} N");
    // Measured 0.0002 N with libm's expf; 0.84 N with the `micromath` feature's exponential
    // (relative error 2.4e-3), the reason the firmware keeps libm.
    let bound = if cfg!(feature = "micromath") {
        1.0
    } else {
        0.005
    };
    assert!(worst < bound, "f32 error {worst} N");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// For any valid parameter set and any bounded velocity sequence, the state stays in the
    /// invariant set |z| <= Fs / sigma0 and the force stays finite.
    #[test]
    fn never_diverges_for_random_valid_sets(
        sigma0 in 1e3f64..1e11,
        sigma1 in 0.0f64..1e4,
        sigma2 in 0.0f64..1e5,
        fc in 1e-2f64..5e3,
        dfs in 0.0f64..5e3,
        vs in 1e-5f64..1.0,
        vels in proptest::collection::vec(-1.0f64..1.0, 1..300),
    ) {
        let p = LugreParams::new(sigma0, sigma1, sigma2, fc, fc + dfs, vs).unwrap();
        let bound = p.static_force() / p.bristle_stiffness() * (1.0 + 1e-9);
        let mut s = LugreState::new();
        for v in vels {
            let f = s.step(&p, v, DT);
            prop_assert!(f.is_finite());
            prop_assert!(s.z.abs() <= bound, "z = {} > {}", s.z, bound);
        }
    }

    /// The bristle step is exact for constant velocity: two half steps equal one full step.
    #[test]
    fn bristle_step_has_the_semigroup_property(
        z0 in -1e-6f64..1e-6, v in -0.1f64..0.1, g in 10.0f64..1000.0,
    ) {
        let sigma0 = 3.9e9;
        let full = bristle_step(z0, v, sigma0, g, DT);
        let half = bristle_step(z0, v, sigma0, g, DT / 2.0);
        let two = bristle_step(half.deflection, v, sigma0, g, DT / 2.0);
        let scale = g / sigma0;
        prop_assert!((full.deflection - two.deflection).abs() <= 1e-9 * scale + 1e-18);
    }
}
