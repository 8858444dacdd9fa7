//! Puts the workspace's memory.x (STM32F405RG) where cortex-m-rt's link.x finds it, and turns
//! the parameter file the host tools write (`host-sim identify` / `diagnose --out-params`)
//! into the firmware's friction model: `LUGRE_PARAMS=path/to/file.toml`, default
//! `params.toml` here. The file is validated at build time with the core's own checks
//! (`LugreParams::new`, `check_physical`, f64 -> f32 without loss of validity); a file a
//! controller must not get fails the build, naming the field.
use lugre_servo::friction::LugreParams;
use std::{env, fmt::Write as _, fs, path::PathBuf};

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
        Err(e) => {
            eprintln!("error: {path}: {e}");
            panic!("{path}: {e}");
        }
    }
}

fn number(t: &toml::Table, section: &str, key: &str) -> Result<f64, String> {
    match t.get(key) {
        Some(toml::Value::Float(f)) => Ok(*f),
        Some(toml::Value::Integer(i)) => Ok(*i as f64),
        Some(_) => Err(format!("[{section}] {key} must be a number")),
        None => Err(format!("[{section}] {key} is missing")),
    }
}

fn table<'a>(root: &'a toml::Table, name: &str) -> Result<&'a toml::Table, String> {
    root.get(name)
        .and_then(toml::Value::as_table)
        .ok_or_else(|| format!("[{name}] is missing"))
}

/// Rust code for the model and the mass.
fn generate(path: &str) -> Result<String, String> {
    let text = fs::read_to_string(path).map_err(|e| format!("cannot read: {e}"))?;
    let root: toml::Table = text.parse().map_err(|e| format!("{e}"))?;
    let l = table(&root, "lugre")?;
    let keys = [
        "bristle_stiffness_n_per_m",
        "bristle_damping_n_s_per_m",
        "viscous_coefficient_n_s_per_m",
        "coulomb_force_n",
        "static_force_n",
        "stribeck_velocity_m_per_s",
    ];
    let v: Vec<f64> = keys
        .iter()
        .map(|k| number(l, "lugre", k))
        .collect::<Result<_, _>>()?;
    let p =
        LugreParams::new(v[0], v[1], v[2], v[3], v[4], v[5]).map_err(|e| format!("[lugre] {e}"))?;
    p.check_physical().map_err(|e| format!("[lugre] {e}"))?;
    let p32: LugreParams<f32> = p.cast().map_err(|e| format!("[lugre] as f32: {e}"))?;
    p32.check_physical()
        .map_err(|e| format!("[lugre] as f32: {e}"))?;
    let mass = number(table(&root, "axis")?, "axis", "moving_mass_kg")?;
    if !(mass.is_finite() && mass > 0.0) {
        return Err("[axis] moving_mass_kg must be a finite number greater than zero".into());
    }
    // effects: the keys of the parameter file, as the core's fields
    let mut effects = String::new();
    if let Some(e) = root.get("effects").and_then(toml::Value::as_table) {
        for (name, fields) in e {
            let f = fields
                .as_table()
                .ok_or_else(|| format!("[effects.{name}] must be a table"))?;
            let n = |k: &str| number(f, &format!("effects.{name}"), k);
            let code = match name.as_str() {
                "asymmetry" => format!(
                    "asymmetry: Some(fx::Asymmetry {{ coulomb_ratio: {:?}, static_ratio: {:?}, viscous_ratio: {:?}, stribeck_velocity_ratio: {:?} }}),",
                    n("coulomb_ratio")? as f32,
                    // files written before the static ratio existed scale Fs with rc
                    if f.contains_key("static_ratio") { n("static_ratio")? } else { n("coulomb_ratio")? } as f32,
                    n("viscous_ratio")? as f32,
                    // and before the Stribeck velocity ratio existed, the same vs both ways
                    if f.contains_key("stribeck_velocity_ratio") { n("stribeck_velocity_ratio")? } else { 0.0 } as f32
                ),
                "offset" => format!("offset: Some(fx::Offset {{ force: {:?} }}),", n("force_n")? as f32),
                "load_dependence" => format!(
                    "load_dependence: Some(fx::LoadDependence {{ static_share: {:?}, ..fx::LoadDependence::power({:?}, {:?}, {:?}) }}),",
                    // files without it scale both levels in proportion
                    if f.contains_key("static_share") { n("static_share")? } else { 1.0 } as f32,
                    n("coefficient_n_per_pa")? as f32,
                    n("reference_pressure_sum_pa")? as f32,
                    // files written before the exponent existed are linear
                    if f.contains_key("exponent") { n("exponent")? } else { 1.0 } as f32
                ),
                "temperature_dependence" => format!(
                    "temperature_dependence: Some(fx::TemperatureDependence {{ viscous_per_kelvin: {:?}, coulomb_per_kelvin: {:?}, reference_temperature: {:?} }}),",
                    n("viscous_per_kelvin")? as f32,
                    n("coulomb_per_kelvin")? as f32,
                    n("reference_temperature_c")? as f32
                ),
                "stribeck_shape" => format!(
                    "stribeck_shape: Some(fx::StribeckShape {{ exponent: {:?} }}),",
                    n("exponent")? as f32
                ),
                "viscous_power" => format!(
                    "viscous_power: Some(fx::ViscousPower {{ exponent: {:?}, reference_velocity: {:?} }}),",
                    n("exponent")? as f32,
                    n("reference_velocity_m_per_s")? as f32
                ),
                "dwell_stiction" => format!(
                    "dwell_stiction: Some(fx::DwellStiction {{ max_increase: {:?}, time_constant: {:?}, stick_velocity: {:?}, renewal_distance: {:?} }}),",
                    n("max_increase_n")? as f32,
                    n("time_constant_s")? as f32,
                    n("stick_velocity_m_per_s")? as f32,
                    // files written before session 8 have none: the host's default
                    f.get("renewal_distance_m").and_then(toml::Value::as_float).unwrap_or(1e-4) as f32
                ),
                "position_dependence" => format!(
                    "position_dependence: Some(fx::PositionDependence::linear({:?}, {:?})),",
                    n("gradient_n_per_m")? as f32,
                    n("center_m")? as f32
                ),
                other => return Err(format!("[effects.{other}] is not an effect the firmware knows")),
            };
            if matches!(name.as_str(), "position_dependence" | "load_dependence")
                && f.get("cosine_n").is_some()
            {
                return Err(format!(
                    "[effects.{name}] cosine terms are not carried to the firmware yet"
                ));
            }
            writeln!(effects, "        {code}").ok();
        }
    }
    let source = root
        .get("fit")
        .and_then(|f| f.get("source"))
        .and_then(toml::Value::as_str)
        .unwrap_or("unknown");
    Ok(format!(
        "// Generated by build.rs from {path} ({source}); validated with LugreParams::check_physical.\n\
         /// Where the parameters come from.\n\
         pub const SOURCE: &str = {path:?};\n\
         /// Moving mass \\[kg\\].\n\
         pub const MOVING_MASS_KG: f32 = {mass:?};\n\
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
        mass = mass as f32,
    ))
}
