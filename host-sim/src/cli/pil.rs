//! `host-sim pil`: the firmware in QEMU closes the loop around the simulated axis.

use host_sim::params_file::ParamFile;
use host_sim::pil::{self, Session};
use host_sim::{Error, Result};
use std::path::PathBuf;

/// Arguments of `pil`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scenario: low_speed (2 mm, 0.2 Hz, 20 s) or drift (50 mm, 0.4 Hz, 20 s).
    #[arg(long, default_value = "low_speed")]
    scenario: String,
    /// The firmware's PIL image (built with `cd firmware && cargo build --release --bin pil`;
    /// this command builds nothing).
    #[arg(long, default_value = concat!(env!("CARGO_MANIFEST_DIR"), "/../firmware/target/thumbv7em-none-eabihf/release/pil"))]
    elf: PathBuf,
    /// The parameter file the firmware was built with (its `LUGRE_PARAMS`).
    #[arg(long, default_value = concat!(env!("CARGO_MANIFEST_DIR"), "/../firmware/params.toml"))]
    params: PathBuf,
    /// The QEMU binary.
    #[arg(long, default_value = "qemu-system-arm")]
    qemu: String,
    /// Run only the first SECONDS of the scenario (the host run too).
    #[arg(long)]
    seconds: Option<f64>,
    /// Raise the plant's friction levels by this fraction 8 s into the run (0.3: +30 %), to see
    /// the firmware's health monitor warn.
    #[arg(long)]
    friction_rise: Option<f64>,
    /// Send this parameter file's friction parameters to the firmware as a settings frame 5 s
    /// into the run (the host run gets them at the same period): the firmware must apply them
    /// and ramp them in.
    #[arg(long)]
    send_params: Option<PathBuf>,
    /// Sensor noise seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Also corrupt a frame, drop one and stall the host, and check that the firmware nulls
    /// the valve, flags the fault and closes the loop again (fails otherwise).
    #[arg(long)]
    inject_faults: bool,
    /// Writes the figures as JSON.
    #[arg(long)]
    json: Option<PathBuf>,
}

/// PIL tracking must be within this fraction of the host's figure.
pub const AGREEMENT: f64 = 0.10;

/// Runs the subcommand.
pub fn run(a: &Args) -> Result<()> {
    let (file, model) = ParamFile::read(&a.params)?;
    let model = model
        .cast()
        .map_err(|_| Error::Pil(format!("{}: not representable in f32", a.params.display())))?;
    let settings =
        match &a.send_params {
            Some(path) => {
                let (_, m) = ParamFile::read(path)?;
                Some(m.params.cast().map_err(|_| {
                    Error::Pil(format!("{}: not representable in f32", path.display()))
                })?)
            }
            None => None,
        };
    let session = Session {
        elf: a.elf.clone(),
        qemu: a.qemu.clone(),
        model,
        mass_kg: file.axis.moving_mass_kg,
        scenario: a.scenario.clone(),
        seed: a.seed,
        inject: a.inject_faults,
        seconds: a.seconds,
        friction_rise: a.friction_rise,
        settings,
    };
    let r = pil::run(&session)?;
    println!(
        "{}: firmware in QEMU rms {:.3} um, the same controller on the host {:.3} um ({:+.2} %)",
        r.scenario,
        r.rms_err_m * 1e6,
        r.host_rms_err_m * 1e6,
        100.0 * (r.rms_err_m / r.host_rms_err_m - 1.0)
    );
    println!(
        "tick: mean {:.0} instructions, worst {}; image: flash {} B, static RAM {} B",
        r.tick_instructions_mean, r.tick_instructions_worst, r.flash_bytes, r.ram_bytes
    );
    println!(
        "parameters from {}: {}; frames lost {}, bad {}; fault periods {}; health ratio {:.3}{}",
        a.params.display(),
        r.params_from_file,
        r.frames_lost,
        r.frames_bad,
        r.fault_periods,
        r.health_ratio,
        r.first_health_warning_s.map_or(String::new(), |t| format!(
            " (warned at {t:.2} s; host run {})",
            r.host_first_health_warning_s
                .map_or("never".into(), |h| format!("{h:.2} s"))
        ))
    );
    for c in &r.fault_checks {
        println!(
            "injected {}: flagged with the valve at null: {}; loop closed again after {}",
            c.fault,
            c.flagged_with_valve_null,
            c.periods_to_recover
                .map_or("never".into(), |p| format!("{p} periods"))
        );
    }
    if let Some(c) = &r.settings {
        println!(
            "settings sent at {:.1} s: {}; largest valve step in the 0.3 s after {:.2e} (before {:.2e}; host run after {:.2e})",
            pil::SETTINGS_AT_S,
            c.status,
            c.valve_step_after,
            c.valve_step_before,
            c.host_valve_step_after
        );
    }
    println!("({:.1} s)", r.wall_s);
    if let Some(path) = &a.json {
        super::write_json(path, &r)?;
    }
    // the health monitor: a warning within 10 s of a rise of the friction levels, none without
    match (a.friction_rise, r.first_health_warning_s) {
        (None, Some(t)) => {
            return Err(Error::Pil(format!(
                "the health monitor warned at {t:.2} s on a run without drift"
            )))
        }
        (Some(_), None) => {
            return Err(Error::Pil(
                "the health monitor did not warn after the friction rise".into(),
            ))
        }
        (Some(_), Some(t)) if t > pil::RISE_AT_S + 10.0 => {
            return Err(Error::Pil(format!(
                "the health monitor warned {:.2} s after the friction rise (more than 10 s)",
                t - pil::RISE_AT_S
            )))
        }
        _ => {}
    }
    if let Some(c) = &r.settings {
        if c.status != "applied" {
            return Err(Error::Pil(format!(
                "the firmware did not apply the settings ({})",
                c.status
            )));
        }
    }
    if a.inject_faults {
        let ok = r.fault_checks.len() == 3
            && r.fault_checks
                .iter()
                .all(|c| c.flagged_with_valve_null && c.periods_to_recover.is_some());
        if !ok {
            return Err(Error::Pil(
                "an injected link fault was not handled safely (see above)".into(),
            ));
        }
    } else if (r.rms_err_m / r.host_rms_err_m - 1.0).abs() > AGREEMENT || !r.params_from_file {
        return Err(Error::Pil(format!(
            "the firmware's loop does not reproduce the host's (rms {:.3} vs {:.3} um, params from file: {})",
            r.rms_err_m * 1e6,
            r.host_rms_err_m * 1e6,
            r.params_from_file
        )));
    }
    Ok(())
}
