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
        "[lugre]\n\
         bristle_stiffness_n_per_m = 2.97e9\n\
         bristle_damping_n_s_per_m = 500.0\n\
         viscous_coefficient_n_s_per_m = 48900.0\n\
         coulomb_force_n = 505.7\n\
         static_force_n = 631.9\n\
         stribeck_velocity_m_per_s = 0.005\n\
         [axis]\n\
         moving_mass_kg = 200.0\n\
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
