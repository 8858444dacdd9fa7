//! `host-sim demo`: the whole story on the simulated Table 2 cylinder.

use host_sim::diagnose::{self, inverse::AxisModel, Options};
use host_sim::experiments::{self, SteadyPoint};
use host_sim::plant::{PlantConfig, SensorConfig};
use host_sim::{Error, Result};
use std::path::{Path, PathBuf};

/// Options of `demo`.
#[derive(clap::Args)]
pub struct Args {
    /// Output folder for CSVs, parameter files and reports.
    #[arg(long, default_value = "demo-out")]
    out: PathBuf,
}

fn print_curve(points: &[SteadyPoint], cfg: &PlantConfig) {
    let model = &cfg.friction;
    let c = model.effects.reference_conditions();
    println!(
        "  {:>11}  {:>11}  {:>11}  {:>8}",
        "v [mm/s]", "F meas [N]", "Fss(v) [N]", "err [%]"
    );
    for p in points {
        let truth = model.steady_state_force(p.velocity, &c);
        println!(
            "  {:>11.3}  {:>11.2}  {:>11.2}  {:>8.3}",
            p.velocity * 1e3,
            p.force,
            truth,
            100.0 * (p.force - truth) / truth.abs()
        );
    }
}

/// Runs the demo into `--out`.
pub fn run(a: &Args) -> Result<()> {
    let out = a.out.as_path();
    std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
    let cfg = PlantConfig::default();
    let cyl = &cfg.cylinder;
    println!("== 1. The plant: electro-hydraulic position axis (Table 2 friction) ==");
    println!(
        "  cylinder {:.0} mm bore, {:.0} mm stroke, {} kg moving mass, supply {:.0} bar, valve {:.0} L/min @ {:.0} bar, {} Hz spool",
        lugre_servo::axis::AxisGeometry::SIMULATED.bore_m * 1e3,
        cyl.stroke_m * 1e3,
        cyl.moving_mass_kg,
        cfg.valve.supply_pressure_pa / 1e5,
        cfg.valve.rated_flow_m3_per_s * 60_000.0,
        cfg.valve.rated_pressure_drop_pa / 1e5,
        cfg.valve.natural_frequency_hz
    );
    let p = &cfg.friction.params;
    println!(
        "  LuGre: sigma0 {:.3e} N/m, sigma1 {} N s/m, sigma2 {} N s/m, Fc {} N, Fs {} N, vs {} m/s",
        p.bristle_stiffness(),
        p.bristle_damping(),
        p.viscous_coefficient(),
        p.coulomb_force(),
        p.static_force(),
        p.stribeck_velocity()
    );
    let sensors = SensorConfig::realistic(1);
    let wall = std::time::Instant::now();
    let (sweep, points) =
        experiments::velocity_sweep(&cfg, sensors, &experiments::log_speeds(5e-4, 0.1, 12));
    let sweep_s = sweep.t.last().copied().unwrap_or(0.0);
    println!("\n== 2. Steady-state friction curve (constant-velocity sweep, realistic sensors) ==");
    print_curve(&points, &cfg);
    let ramp = experiments::presliding_ramp(&cfg, sensors, 0.7, 8.0);
    let sine = experiments::sinusoid(&cfg, sensors, 0.01, 0.25, 20.0);
    let trap = experiments::trapezoid(&cfg, sensors, 0.05, 0.05, 0.5, 0.5, 20.0);
    let sim_s = sweep_s + 8.0 + 20.0 + 20.0;
    let wall_s = wall.elapsed().as_secs_f64();
    for (name, rec) in [
        ("sweep", &sweep),
        ("ramp", &ramp),
        ("sine", &sine),
        ("trapezoid", &trap),
    ] {
        let path = out.join(format!("{name}.csv"));
        rec.write(&path).map_err(|e| Error::io(&path, e))?;
        println!("  wrote {}", path.display());
    }
    let lo = ramp.x.iter().cloned().fold(f64::INFINITY, f64::min);
    let hi = ramp.x.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    println!(
        "  pre-sliding ramp between +-0.7 Fs: displacement range {:.2} um (LuGre predicts ~{:.2} um: \
         2 x 0.7 Fs / sigma0, a little more as the bristles yield; encoder steps of 0.1 um)",
        (hi - lo) * 1e6,
        2.0 * 0.7 * p.static_force() / p.bristle_stiffness() * 1e6
    );
    println!(
        "  simulated {sim_s:.1} s in {wall_s:.2} s wall ({:.0}x real time)",
        sim_s / wall_s
    );
    identification_chapter(out)?;
    closed_loop_chapter(out)?;
    diagnosis_chapter(out)
}

/// Chapter: the paper's identification, improved GA against CMA-ES, on the ideal experiments.
fn identification_chapter(out: &Path) -> Result<()> {
    use host_sim::identify::{self, Algorithm};
    println!("\n== Identification (the paper's setting: noise-free experiments, Table 2 truth) ==");
    let truth = lugre_servo::friction::LugreParams::table2();
    let data = identify::ideal_data(&truth);
    let runs: Vec<_> = [Algorithm::Improved, Algorithm::Cmaes]
        .iter()
        .map(|&a| identify::identify(a, &data, 1, Some(&truth)))
        .collect();
    super::identify::print_table(&runs.iter().collect::<Vec<_>>(), Some(&truth));
    for r in &runs {
        println!(
            "  {}: {} evaluations, all six within 1 % after {}, {:.2} s",
            r.algorithm.name(),
            r.evaluations,
            r.evaluations_to_1pct
                .map_or("never".to_string(), |e| e.to_string()),
            r.wall_s
        );
    }
    println!("\n  The same on the simulated hydraulic axis behind realistic sensors (seed 1):");
    let real = identify::realistic_data(&host_sim::plant::PlantConfig::default(), 1);
    let r = identify::identify(Algorithm::Improved, &real, 1, Some(&truth));
    super::identify::print_table(&[&r], Some(&truth));
    super::identify::print_identifiability(&r);
    println!(
        "  The 0.1 um encoder counts a reversal's pre-sliding travel (~0.3 um) in three steps: sigma0\n  is read at the counts' edges, which leaves its interval wide; sigma1's force (< 0.1 N at\n  1 kHz) is far below the pressure noise: see README, Identification."
    );
    let params = identify::params_of(&runs[0]).ok_or(Error::InvalidIdentifiedSet)?;
    super::identify::write_params(
        &params,
        200.0,
        &runs[0],
        "ideal",
        &out.join("identified.toml"),
    )
}

/// Chapter: the 1 kHz controller (the firmware's code, f32) on the simulated axis.
fn closed_loop_chapter(out: &Path) -> Result<()> {
    println!("\n== Closed loop: the firmware's controller against the simulated axis ==");
    let plot = out.join("tracking.svg");
    let json = out.join("track.json");
    super::track::benchmark(Some(&json), Some(&plot), 1)?;
    // a user's model is never exact: friction levels 30 % too high
    use host_sim::robustness::{model, Scenario};
    use lugre_servo::control::{ControllerConfig, Features};
    let plant = PlantConfig::default();
    let table2 = lugre_servo::friction::LugreParams::table2();
    let wrong = model("static_x1.3", &plant, &table2)
        .and_then(|m| m.cast().ok())
        .ok_or(Error::InvalidIdentifiedSet)?;
    let s = Scenario::LowSpeed;
    let rms = |f| {
        let cfg = ControllerConfig::for_simulated_axis(wrong, f);
        let r = host_sim::track::run(
            &plant,
            SensorConfig::realistic(1),
            cfg,
            &|t| s.reference(t),
            s.duration_s(),
        );
        r.tracking.rms_err_m * 1e6
    };
    let without = Features {
        residual_observer: false,
        ..Features::FULL
    };
    println!(
        "  with Fc, Fs and sigma2 30 % too high in the controller: low_speed rms {:.1} um without the residual observer, {:.1} um with it (full); `track --robustness` runs the whole matrix",
        rms(without),
        rms(Features::FULL)
    );
    println!("  (the same controller runs on the STM32F405 in QEMU: see firmware/ and .ci/run)");
    Ok(())
}

/// Chapter: a record with a hidden effect, diagnosed without being told which.
fn diagnosis_chapter(out: &Path) -> Result<()> {
    println!("\n== Diagnosis: a cylinder with a hidden effect ==");
    let mut cfg = PlantConfig::default();
    // the hidden effect: pressure-energised seals (the diagnosis is not told)
    host_sim::scenarios::with_effect(&mut cfg, "load_dependence", 0.6)?;
    let rec = host_sim::scenarios::diagnosis_run(&cfg, SensorConfig::realistic(7), 40.0);
    let path = out.join("hidden.csv");
    rec.write(&path).map_err(|e| Error::io(&path, e))?;
    println!(
        "  recorded 40 s of moves and dwells on a rig whose friction hides an effect -> {}",
        path.display()
    );
    let name = path.display().to_string();
    let blind = diagnose::diagnose(&rec, &name, &Options::default())?;
    let base = &blind.stages[0];
    println!(
        "  1. compare: symmetric LuGre fitted to the record, relative force error {:.2} %",
        base.fit.rel_err_pct
    );
    println!("  2. where it fails:");
    for f in &base.regimes.findings {
        println!("     - {f}");
    }
    let Some(top) = base.first_significant() else {
        println!("  3. no candidate effect is significant");
        return Ok(());
    };
    println!("  3. missing effect, best first:");
    for c in base.candidates.iter().take(3) {
        if let (Some(e), Some(b)) = (c.rel_err_pct, c.delta_bic) {
            println!(
                "     {:<24} {:>6.2} %  dBIC {:>8.1}  {}",
                c.kind,
                e,
                b,
                if c.significant {
                    "significant"
                } else {
                    "not significant"
                }
            );
        }
    }
    println!("     -> {}: {}", top.kind, top.meaning);
    let truth = AxisModel {
        mass_kg: cfg.cylinder.moving_mass_kg,
        friction: cfg.friction,
    };
    let opts = Options {
        add: vec![top.kind.to_string()],
        truth: Some(truth),
        ..Default::default()
    };
    let d = diagnose::diagnose(&rec, &name, &opts)?;
    let after = &d.stages[1];
    println!(
        "  4. add it: relative force error {:.2} % -> {:.2} % (noise floor {:.2} %: the true model along the measured motion)",
        d.stages[0].fit.rel_err_pct,
        after.fit.rel_err_pct,
        d.noise_floor_pct.unwrap_or(f64::NAN)
    );
    let (was, now) = (d.unexplained(&d.stages[0]), d.unexplained(after));
    println!(
        "     what the model leaves: {:.1}x -> {:.1}x what the measurement accounts for (force noise and motion reading; above {}x the record shows something the model does not contain)",
        was.ratio(),
        now.ratio(),
        diagnose::UNEXPLAINED_RATIO
    );
    let next = after.candidates.iter().filter(|c| c.significant).count();
    println!("     significant effects left: {next}");
    match &d.contact {
        Some(c) => println!(
            "     a contact that is not LuGre (Maxwell-slip: presliding memory, frictional lag) in the bristle's place errs {:.2} %: {}",
            c.rel_err_pct,
            if c.describes {
                "it describes what LuGre's contact leaves"
            } else {
                "no better; LuGre's contact stays"
            }
        ),
        None => println!("     {}", d.contact_not_tried().unwrap_or_default()),
    }
    let report = out.join("diagnosis.html");
    std::fs::write(&report, diagnose::report::html(&d, &name, None))
        .map_err(|e| Error::io(&report, e))?;
    super::diagnose::write_params(&d, &out.join("extended.toml"), None)?;
    println!("  5. report: {}", report.display());
    println!("     (the hidden effect was load_dependence)");
    Ok(())
}
