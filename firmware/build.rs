//! Puts the workspace's memory.x (STM32F405RG) where cortex-m-rt's link.x finds it, and turns
//! the parameter file the host tools write (`host-sim identify` / `diagnose --out-params`)
//! into the firmware's friction model: `LUGRE_PARAMS=path/to/file.toml`, default
//! `params.toml` here. The file is read and validated at build time by the same reader the
//! host tools use (the core's `params_file`: every section, every effect, the cosine terms of
//! position and load dependence included), then checked again as f32; a file a controller must
//! not get fails the build, naming the file and the field.
use lugre_servo::friction::{effects as fx, Effects, FrictionModel};
use lugre_servo::params_file::ParamFile;
use std::{
    env, fs,
    path::{Path, PathBuf},
};

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("OUT_DIR"));
    fs::copy("../memory.x", out.join("memory.x")).expect("copy ../memory.x");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=../memory.x");
    println!("cargo:rerun-if-changed=build.rs");
    if env::var_os("CARGO_FEATURE_DEFMT").is_some() {
        println!("cargo:rustc-link-arg=-Tdefmt.x");
    }
    println!("cargo:rerun-if-env-changed=LUGRE_PARAMS");
    let path = env::var("LUGRE_PARAMS").unwrap_or_else(|_| "params.toml".into());
    println!("cargo:rerun-if-changed={path}");
    match generate(&path) {
        Ok(code) => fs::write(out.join("params.rs"), code).expect("write params.rs"),
        // the reader's errors name the file (and the line and column, or the section and key)
        Err(e) => {
            eprintln!("error: {e}");
            panic!("{e}");
        }
    }
}

/// An f32 as a Rust literal (`Debug` prints the shortest string that reads back exactly).
fn lit(x: f32) -> String {
    format!("{x:?}")
}

/// A fixed array of f32 literals.
fn array(xs: &[f32]) -> String {
    let items: Vec<String> = xs.iter().map(|x| lit(*x)).collect();
    format!("[{}]", items.join(", "))
}

/// The effects as Rust field initialisers (`fx` is the core's `friction::effects`). Every
/// struct is destructured without `..`: a field added to the core fails this build instead of
/// being left at a default.
fn effects_code(e: &Effects<f32>) -> String {
    let Effects {
        asymmetry,
        offset,
        load_dependence,
        position_dependence,
        temperature_dependence,
        stribeck_shape,
        viscous_power,
        dwell_stiction,
    } = *e;
    let mut out = Vec::new();
    if let Some(fx::Asymmetry {
        coulomb_ratio,
        static_ratio,
        viscous_ratio,
        stribeck_velocity_ratio,
    }) = asymmetry
    {
        out.push(format!(
            "asymmetry: Some(fx::Asymmetry {{ coulomb_ratio: {}, static_ratio: {}, viscous_ratio: {}, stribeck_velocity_ratio: {} }}),",
            lit(coulomb_ratio), lit(static_ratio), lit(viscous_ratio), lit(stribeck_velocity_ratio)
        ));
    }
    if let Some(fx::Offset { force }) = offset {
        out.push(format!(
            "offset: Some(fx::Offset {{ force: {} }}),",
            lit(force)
        ));
    }
    if let Some(fx::LoadDependence {
        coefficient,
        reference_pressure_sum,
        exponent,
        half_span,
        cosine,
        terms,
        static_share,
    }) = load_dependence
    {
        out.push(format!(
            "load_dependence: Some(fx::LoadDependence {{ coefficient: {}, reference_pressure_sum: {}, exponent: {}, half_span: {}, cosine: {}, terms: {terms}, static_share: {} }}),",
            lit(coefficient), lit(reference_pressure_sum), lit(exponent), lit(half_span), array(&cosine), lit(static_share)
        ));
    }
    if let Some(fx::PositionDependence {
        gradient,
        center,
        half_span,
        cosine,
        terms,
    }) = position_dependence
    {
        out.push(format!(
            "position_dependence: Some(fx::PositionDependence {{ gradient: {}, center: {}, half_span: {}, cosine: {}, terms: {terms} }}),",
            lit(gradient), lit(center), lit(half_span), array(&cosine)
        ));
    }
    if let Some(fx::TemperatureDependence {
        viscous_per_kelvin,
        coulomb_per_kelvin,
        reference_temperature,
    }) = temperature_dependence
    {
        out.push(format!(
            "temperature_dependence: Some(fx::TemperatureDependence {{ viscous_per_kelvin: {}, coulomb_per_kelvin: {}, reference_temperature: {} }}),",
            lit(viscous_per_kelvin), lit(coulomb_per_kelvin), lit(reference_temperature)
        ));
    }
    if let Some(fx::StribeckShape { exponent }) = stribeck_shape {
        out.push(format!(
            "stribeck_shape: Some(fx::StribeckShape {{ exponent: {} }}),",
            lit(exponent)
        ));
    }
    if let Some(fx::ViscousPower {
        exponent,
        reference_velocity,
    }) = viscous_power
    {
        out.push(format!(
            "viscous_power: Some(fx::ViscousPower {{ exponent: {}, reference_velocity: {} }}),",
            lit(exponent),
            lit(reference_velocity)
        ));
    }
    if let Some(fx::DwellStiction {
        max_increase,
        time_constant,
        stick_velocity,
        renewal_distance,
    }) = dwell_stiction
    {
        out.push(format!(
            "dwell_stiction: Some(fx::DwellStiction {{ max_increase: {}, time_constant: {}, stick_velocity: {}, renewal_distance: {} }}),",
            lit(max_increase), lit(time_constant), lit(stick_velocity), lit(renewal_distance)
        ));
    }
    out.iter().map(|l| format!("            {l}\n")).collect()
}

/// Rust code for the model and the mass: the file read and validated by the host's own reader
/// (`ParamFile::read`: syntax with line and column, every section and effect checked), cast
/// to f32 and checked again as a file of those f32 values would be (a value f32 cannot hold,
/// or one that rounds out of its range, is refused the same way).
fn generate(path: &str) -> Result<String, String> {
    let (file, model) = ParamFile::read(Path::new(path)).map_err(|e| e.to_string())?;
    let mass = file.axis.moving_mass_kg;
    let m32: FrictionModel<f32> = model
        .cast()
        .map_err(|e| format!("{path}: as f32: [lugre] {e}"))?;
    let back: FrictionModel<f64> = m32
        .cast()
        .map_err(|e| format!("{path}: as f32: [lugre] {e}"))?;
    ParamFile::new(&back, f64::from(mass as f32))
        .model()
        .map_err(|e| format!("{path}: as f32: {e}"))?;
    let p32 = m32.params;
    let effects = effects_code(&m32.effects);
    let source = file.fit.source.as_deref().unwrap_or("unknown");
    Ok(format!(
        "// Generated by build.rs from {path} ({source}); read and validated by the parameter file's reader, as f64 and as f32.\n\
         /// Where the parameters come from.\n\
         pub const SOURCE: &str = {path:?};\n\
         /// Moving mass \\[kg\\].\n\
         pub const MOVING_MASS_KG: f32 = {mass};\n\
         /// Base LuGre parameters: sigma0, sigma1, sigma2, Fc, Fs, vs (SI).\n\
         pub const LUGRE: [f32; 6] = [{:?}, {:?}, {:?}, {:?}, {:?}, {:?}];\n\
         /// The identified friction model (validated at build time; Table 2 if the f32 set were\n\
         /// ever refused at run time, which the build's own check rules out).\n\
         pub fn model() -> lugre_servo::friction::FrictionModel<f32> {{\n\
         \x20   #[allow(unused_imports)]\n\
         \x20   use lugre_servo::friction::effects as fx;\n\
         \x20   let [s0, s1, s2, fc, fs, vs] = LUGRE;\n\
         \x20   let params = lugre_servo::friction::LugreParams::new(s0, s1, s2, fc, fs, vs)\n\
         \x20       .unwrap_or_else(|_| lugre_servo::friction::LugreParams::table2());\n\
         \x20   lugre_servo::friction::FrictionModel {{\n\
         \x20       params,\n\
         \x20       effects: lugre_servo::friction::Effects {{\n\
         {effects}\
         \x20           ..lugre_servo::friction::Effects::none()\n\
         \x20       }},\n\
         \x20   }}\n\
         }}\n",
        p32.bristle_stiffness(),
        p32.bristle_damping(),
        p32.viscous_coefficient(),
        p32.coulomb_force(),
        p32.static_force(),
        p32.stribeck_velocity(),
        mass = lit(mass as f32),
    ))
}
