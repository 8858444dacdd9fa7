//! Parameter validation names the field and refuses what physics forbids.

use lugre_servo::friction::{LugreParams, ParamErrorKind, ParamField, ParamWarning};

#[test]
fn table2_is_the_default_and_dissipative() {
    let p = LugreParams::<f64>::default();
    assert_eq!(p.bristle_stiffness(), 3.9e9);
    assert_eq!(p.static_force() - p.coulomb_force(), 126.0);
    assert_eq!(p.warning(), None);
}

#[test]
fn each_invalid_field_is_named() {
    let ok = [3.9e9, 200.0, 48_900.0, 506.0, 632.0, 0.005];
    let bad = [
        (
            0,
            f64::NAN,
            ParamField::BristleStiffness,
            ParamErrorKind::NotFinite,
        ),
        (
            0,
            0.0,
            ParamField::BristleStiffness,
            ParamErrorKind::NotPositive,
        ),
        (
            1,
            -1.0,
            ParamField::BristleDamping,
            ParamErrorKind::Negative,
        ),
        (
            2,
            f64::INFINITY,
            ParamField::ViscousCoefficient,
            ParamErrorKind::NotFinite,
        ),
        (
            3,
            -5.0,
            ParamField::CoulombForce,
            ParamErrorKind::NotPositive,
        ),
        (
            4,
            400.0,
            ParamField::StaticForce,
            ParamErrorKind::StaticBelowCoulomb,
        ),
        (
            5,
            0.0,
            ParamField::StribeckVelocity,
            ParamErrorKind::NotPositive,
        ),
    ];
    for (i, value, field, kind) in bad {
        let mut v = ok;
        v[i] = value;
        let e = LugreParams::new(v[0], v[1], v[2], v[3], v[4], v[5]).unwrap_err();
        assert_eq!((e.field, e.kind), (field, kind), "field {i} = {value}");
    }
    let e = LugreParams::new(3.9e9, 200.0, 48_900.0, 506.0, 400.0, 0.005).unwrap_err();
    assert!(e.to_string().contains("static_force (Fs)"), "{e}");
}

#[test]
fn anti_damping_set_is_flagged_not_refused() {
    // sigma1 (Fs - Fc) / Fc = 1e5 * 126 / 506 = 24 900 > sigma2 = 1000
    let p = LugreParams::new(3.9e9, 1e5, 1000.0, 506.0, 632.0, 0.005).unwrap();
    assert_eq!(p.warning(), Some(ParamWarning::NotDissipative));
}

#[test]
fn cast_to_f32_keeps_values() {
    let p = LugreParams::<f64>::table2().cast::<f32>().unwrap();
    assert_eq!(p.coulomb_force(), 506.0f32);
}

/// The `[lugre]` and `[axis]` tables the effect-file tests share (levels near Table 2's, a
/// contact a little softer), ending with a newline.
const LUGRE_AND_AXIS: &str = "[lugre]
bristle_stiffness_n_per_m = 2.97e9
bristle_damping_n_s_per_m = 500.0
viscous_coefficient_n_s_per_m = 48900.0
coulomb_force_n = 505.7
static_force_n = 631.9
stribeck_velocity_m_per_s = 0.005
[axis]
moving_mass_kg = 200.0
";

/// The firmware's path for a parameter file (its build script: `ParamFile::read`, the model
/// cast to f32, checked again): a position dependence of sixteen cosine terms and a load
/// dependence of four survive it, and the f32 levels along the stroke and the pressure range
/// stay within the single-precision error of the f64 ones: measured 9.3e-5 N on levels of
/// ~500 N (f32's relative step is 6e-8; the recurrence and the sixteen-term sum add a little),
/// asserted at 5e-4 N.
#[test]
fn a_file_with_cosine_terms_reaches_f32_within_its_rounding() {
    use lugre_servo::friction::{Conditions, FrictionModel};
    use lugre_servo::params_file::ParamFile;
    let cosine: Vec<String> = (1..=16)
        .map(|j| {
            format!(
                "{:.3}",
                12.0 * (1.3 * j as f64).cos() / (1.0 + 0.15 * j as f64)
            )
        })
        .collect();
    let text = format!(
        "{LUGRE_AND_AXIS}\
         [effects.position_dependence]\n\
         gradient_n_per_m = 40.0\n\
         center_m = 0.25\n\
         half_span_m = 0.25\n\
         cosine_n = [{}]\n\
         [effects.load_dependence]\n\
         coefficient_n_per_pa = 2e-6\n\
         reference_pressure_sum_pa = 1.2e7\n\
         exponent = 0.8\n\
         half_span_pa = 1e7\n\
         cosine_n = [6.0, -3.0, 1.5, -0.7]\n\
         static_share = 0.6\n",
        cosine.join(", ")
    );
    let (file, model) = ParamFile::parse(&text, std::path::Path::new("cosine.toml")).unwrap();
    let pd = model.effects.position_dependence.unwrap();
    assert_eq!(
        (pd.terms, model.effects.load_dependence.unwrap().terms),
        (16, 4)
    );
    let m32: FrictionModel<f32> = model.cast().unwrap();
    let back: FrictionModel<f64> = m32.cast().unwrap();
    ParamFile::new(&back, file.axis.moving_mass_kg)
        .model()
        .expect("the f32 set passes the file's checks");
    let mut worst = 0.0f64;
    for i in 0..=500 {
        for p in [2e6, 1.2e7, 2.2e7] {
            let x = 0.5 * i as f64 / 500.0;
            let c = Conditions {
                position: x,
                pressure_sum: p,
                temperature: 40.0,
            };
            let c32 = Conditions {
                position: x as f32,
                pressure_sum: p as f32,
                temperature: 40.0,
            };
            for v in [1e-3, -1e-3] {
                let l = model.levels(v, &c, 0.0);
                let l32 = m32.levels(v as f32, &c32, 0.0);
                worst = worst
                    .max((f64::from(l32.coulomb) - l.coulomb).abs())
                    .max((f64::from(l32.static_) - l.static_).abs());
            }
        }
    }
    println!("largest f32 - f64 level difference along the stroke: {worst:.2e} N");
    assert!(worst < 5e-4, "f32 levels {worst} N from f64");
    // and the position shape is really there: the levels move by tens of newtons
    let at = |x: f64| {
        model
            .levels(
                1e-3,
                &Conditions {
                    position: x,
                    ..model.effects.reference_conditions()
                },
                0.0,
            )
            .coulomb
    };
    assert!((at(0.1) - at(0.4)).abs() > 5.0);
}

/// The temperature law's Hersey exponent `q` travels through the parameter file and the f32
/// cast: written only when not 0, read back as written, 0 where a file written before it
/// lacks it, refused when negative (with the key named); the f32 model's steady-state force
/// under a warm oil stays within single precision of the f64 one (the curve moved by
/// `eta^-q` in both).
#[test]
fn the_hersey_exponent_round_trips_and_a_negative_one_is_refused() {
    use lugre_servo::friction::{Conditions, FrictionModel};
    use lugre_servo::params_file::ParamFile;
    let text = |q: Option<f64>| {
        format!(
            "{LUGRE_AND_AXIS}\
             [effects.temperature_dependence]\n\
             viscous_per_kelvin = 0.02\n\
             coulomb_per_kelvin = 0.002\n\
             reference_temperature_c = 40.0\n{}",
            q.map_or(String::new(), |q| format!(
                "stribeck_hersey_exponent = {q}\n"
            ))
        )
    };
    let path = std::path::Path::new("warm.toml");
    let (_, old) = ParamFile::parse(&text(None), path).unwrap();
    assert_eq!(
        old.effects
            .temperature_dependence
            .unwrap()
            .stribeck_hersey_exponent,
        0.0
    );
    let written = toml::to_string_pretty(&ParamFile::new(&old, 200.0)).unwrap();
    assert!(!written.contains("stribeck_hersey_exponent"), "{written}");
    let (_, model) = ParamFile::parse(&text(Some(0.7)), path).unwrap();
    let t = model.effects.temperature_dependence.unwrap();
    assert_eq!(t.stribeck_hersey_exponent, 0.7);
    let written = toml::to_string_pretty(&ParamFile::new(&model, 200.0)).unwrap();
    let (_, back) = ParamFile::parse(&written, path).unwrap();
    assert_eq!(back, model);
    let err = ParamFile::parse(&text(Some(-0.1)), path).unwrap_err();
    let msg = err.to_string();
    assert!(
        msg.contains("temperature_dependence") && msg.contains("stribeck_hersey_exponent"),
        "{msg}"
    );
    let m32: FrictionModel<f32> = model.cast().unwrap();
    let warm = Conditions {
        position: 0.0,
        pressure_sum: 0.0,
        temperature: 65.0,
    };
    let warm32 = Conditions {
        position: 0.0,
        pressure_sum: 0.0,
        temperature: 65.0f32,
    };
    let worst = worst_f32_steady_state(&model, &m32, &warm, &warm32, 0.03);
    // the curve did move: at the reference velocity it differs from the fixed curve's
    let mut fixed = model;
    fixed.effects.temperature_dependence =
        Some(lugre_servo::friction::effects::TemperatureDependence {
            stribeck_hersey_exponent: 0.0,
            ..t
        });
    assert!(
        (fixed.steady_state_force(0.005, &warm) - model.steady_state_force(0.005, &warm)).abs()
            > 1.0
    );
    println!("largest f32 - f64 steady-state difference, warm oil: {worst:.2e} (relative)");
    assert!(worst < 1e-5, "f32 {worst} from f64");
}

/// A Stribeck tail travels through the parameter file and the f32 cast: written only where
/// its share is not 0, read back as written, one scale where a file written before it lacks
/// it, refused with the key named where the share leaves 0..=1 or the scale is not above 0;
/// the f32 model's steady-state force stays within single precision of the f64 one.
#[test]
fn a_stribeck_tail_round_trips_and_a_bad_share_is_refused() {
    use lugre_servo::friction::FrictionModel;
    use lugre_servo::params_file::ParamFile;
    let text =
        |tail: &str| format!("{LUGRE_AND_AXIS}[effects.stribeck_shape]\nexponent = 2.2\n{tail}");
    let path = std::path::Path::new("tail.toml");
    let (_, old) = ParamFile::parse(&text(""), path).unwrap();
    let s = old.effects.stribeck_shape.unwrap();
    assert_eq!((s.exponent, s.tail_share), (2.2, 0.0));
    let written = toml::to_string_pretty(&ParamFile::new(&old, 200.0)).unwrap();
    assert!(!written.contains("tail_"), "{written}");
    let (_, model) =
        ParamFile::parse(&text("tail_share = 0.45\ntail_scale = 4.0\n"), path).unwrap();
    let s = model.effects.stribeck_shape.unwrap();
    assert_eq!((s.tail_share, s.tail_scale), (0.45, 4.0));
    let written = toml::to_string_pretty(&ParamFile::new(&model, 200.0)).unwrap();
    assert!(written.contains("tail_share"), "{written}");
    let (_, back) = ParamFile::parse(&written, path).unwrap();
    assert_eq!(back, model);
    // the tail moves the curve
    let c = model.effects.reference_conditions();
    assert!((old.steady_state_force(0.02, &c) - model.steady_state_force(0.02, &c)).abs() > 1.0);
    for (bad, key) in [
        ("tail_share = 1.5\ntail_scale = 4.0\n", "tail_share"),
        ("tail_share = -0.1\ntail_scale = 4.0\n", "tail_share"),
        ("tail_share = 0.3\ntail_scale = 0.0\n", "tail_scale"),
    ] {
        let msg = ParamFile::parse(&text(bad), path).unwrap_err().to_string();
        assert!(msg.contains("stribeck_shape") && msg.contains(key), "{msg}");
    }
    let m32: FrictionModel<f32> = model.cast().unwrap();
    let c32 = m32.effects.reference_conditions();
    let worst = worst_f32_steady_state(&model, &m32, &c, &c32, 0.05);
    println!("largest f32 - f64 steady-state difference, Stribeck tail: {worst:.2e} (relative)");
    assert!(worst < 1e-5, "f32 {worst} from f64");
}

/// The largest relative difference of the f32 model's steady-state force from the f64 one's,
/// over 200 speeds up to `v_max` \[m/s\] each way.
fn worst_f32_steady_state(
    model: &lugre_servo::friction::FrictionModel<f64>,
    m32: &lugre_servo::friction::FrictionModel<f32>,
    c: &lugre_servo::friction::Conditions<f64>,
    c32: &lugre_servo::friction::Conditions<f32>,
    v_max: f64,
) -> f64 {
    let mut worst = 0.0f64;
    for i in 1..=200 {
        let v = v_max * i as f64 / 200.0;
        for v in [v, -v] {
            let f64_force = model.steady_state_force(v, c);
            let f32_force = f64::from(m32.steady_state_force(v as f32, c32));
            worst = worst.max((f32_force - f64_force).abs() / f64_force.abs());
        }
    }
    worst
}
