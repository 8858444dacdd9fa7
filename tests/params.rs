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
