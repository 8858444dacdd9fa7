//! Processor-in-the-loop: the firmware's controller, running on the STM32F405 in QEMU, closes
//! the loop around this crate's hydraulic plant over the emulated USART.
//!
//! The host is the clock. Each period it samples the plant's sensors, sends one
//! [`SensorFrame`], waits for the [`ActuationFrame`] and applies its valve command for one
//! period. QEMU runs with `-icount shift=0` (instruction counting for the tick's cost) and its
//! first serial port on a TCP socket this process listens on. The same scenario and the same
//! controller (built from the same parameter file) also run on the host, as `track` runs them,
//! for comparison.
//!
//! With [`Injection`], the host also hurts the link on purpose (a corrupted frame, a lost
//! frame, a stall) and checks the firmware's answer: valve at null with the fault flagged, a
//! hold, and the loop closed again.

use crate::error::{Error, Result};
use crate::plant::{Plant, PlantConfig, SensorConfig, Sensors};
use crate::track;
use lugre_servo::axis::AxisGeometry;
use lugre_servo::control::{ControllerConfig, Features};
use lugre_servo::friction::{FrictionModel, LugreParams};
use lugre_servo::link::{
    link_faults, status, ActuationFrame, ActuationReceiver, HelloFrame, Received, SensorFrame,
    SettingsFrame, HELLO_LEN, PROTOCOL_VERSION,
};
use serde::Serialize;
use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// What to run.
#[derive(Clone, Debug)]
pub struct Session {
    /// The firmware's `pil` ELF.
    pub elf: PathBuf,
    /// The QEMU binary.
    pub qemu: String,
    /// The friction model and mass the firmware was built with (its parameter file).
    pub model: FrictionModel<f32>,
    /// Moving mass of that file \[kg\].
    pub mass_kg: f64,
    /// Scenario name (`low_speed` or `drift`).
    pub scenario: String,
    /// Sensor noise seed.
    pub seed: u64,
    /// Hurt the link on purpose and check the answers.
    pub inject: bool,
    /// Run only this long instead of the whole scenario \[s\].
    pub seconds: Option<f64>,
    /// Raise the plant's friction levels (Fc, Fs, sigma2) by this fraction at
    /// [`RISE_AT_S`] (wear, contamination), in both runs: the health monitor must warn.
    pub friction_rise: Option<f64>,
    /// Friction parameters sent to the firmware as a settings frame at [`SETTINGS_AT_S`]
    /// (the host run gets them at the same period).
    pub settings: Option<LugreParams<f32>>,
}

/// When `settings` are sent \[s\].
pub const SETTINGS_AT_S: f64 = 5.0;

/// What became of the settings sent, and how the valve moved around them.
#[derive(Clone, Debug, Serialize)]
pub struct SettingsCheck {
    /// The firmware's answer: "applied", "refused" or "no answer".
    pub status: String,
    /// Largest change of the valve command from one period to the next in the 0.3 s after
    /// the settings arrived [-].
    pub valve_step_after: f32,
    /// The same in the 0.3 s before [-].
    pub valve_step_before: f32,
    /// The same after, on the host run [-].
    pub host_valve_step_after: f32,
}

/// When `friction_rise` steps the plant's friction up \[s\].
pub const RISE_AT_S: f64 = 8.0;

/// The faults injected, and when \[s\].
#[derive(Clone, Copy, Debug)]
pub struct Injection;

impl Injection {
    /// One byte of this period's frame is flipped.
    pub const CORRUPT_AT_S: f64 = 4.0;
    /// This period's frame is not sent (its sequence number is skipped).
    pub const DROP_AT_S: f64 = 7.0;
    /// The host stops for [`Self::STALL_WALL_S`] of wall time before this period's frame.
    pub const STALL_AT_S: f64 = 10.0;
    /// Length of the stall in wall-clock time \[s\]. The emulated MCU counts virtual time
    /// (one nanosecond per instruction under `-icount shift=0`), and its polling loop, with an
    /// emulated register read per pass, covers its 5 ms timeout in well under this.
    pub const STALL_WALL_S: f64 = 2.0;
}

/// How the firmware answered one injected fault.
#[derive(Clone, Debug, Serialize)]
pub struct FaultCheck {
    /// Which fault.
    pub fault: String,
    /// The answer flagged it and had the valve at null.
    pub flagged_with_valve_null: bool,
    /// Periods until the loop ran again (None: it did not within the run).
    pub periods_to_recover: Option<u32>,
}

/// The result, as `host-sim pil --json` writes it.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// Scenario.
    pub scenario: String,
    /// Tracking RMS error of the firmware's loop (true position) \[m\].
    pub rms_err_m: f64,
    /// The same scenario and controller run on the host \[m\].
    pub host_rms_err_m: f64,
    /// Mean instructions of the controller tick.
    pub tick_instructions_mean: f64,
    /// Largest instructions of a tick.
    pub tick_instructions_worst: u32,
    /// Flash the firmware occupies (text, rodata, data initialisers, vectors) \[bytes\].
    pub flash_bytes: u64,
    /// Static RAM (data, bss) \[bytes\].
    pub ram_bytes: u64,
    /// The firmware reported running the model of the parameter file given here.
    pub params_from_file: bool,
    /// Frames the firmware counted as lost.
    pub frames_lost: u32,
    /// Frames the firmware counted with a bad checksum.
    pub frames_bad: u32,
    /// Periods whose answer raised a controller fault.
    pub fault_periods: u32,
    /// The friction health monitor's ratio at the end (0: undecided).
    pub health_ratio: f32,
    /// Any period with the health warning.
    pub health_warned: bool,
    /// When the firmware first reported the health warning \[s\] (None: never).
    pub first_health_warning_s: Option<f64>,
    /// The same on the host run \[s\].
    pub host_first_health_warning_s: Option<f64>,
    /// The injected link faults and the firmware's answers (with --inject-faults).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub fault_checks: Vec<FaultCheck>,
    /// The settings sent (with --send-params) and the firmware's answer.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub settings: Option<SettingsCheck>,
    /// Wall time of the session \[s\].
    pub wall_s: f64,
}

fn pil(msg: impl Into<String>) -> Error {
    Error::Pil(msg.into())
}

/// A reference trajectory: time \[s\] -> position \[m\], velocity [m/s], acceleration [m/s^2].
type Trajectory = fn(f64) -> (f64, f64, f64);

/// The scenario's reference and duration.
fn scenario(name: &str) -> Result<(Trajectory, f64)> {
    match name {
        "low_speed" => Ok((track::low_speed_reference, 20.0)),
        "drift" => Ok((track::drift_reference, 20.0)),
        other => Err(Error::Argument {
            flag: "--scenario",
            problem: format!("must be low_speed or drift, got '{other}'"),
        }),
    }
}

/// The controller both sides run: the firmware's `for_axis` with the file's mass and model.
pub fn controller_config(model: FrictionModel<f32>, mass_kg: f64) -> ControllerConfig {
    let axis = AxisGeometry {
        moving_mass_kg: mass_kg,
        ..AxisGeometry::SIMULATED
    };
    ControllerConfig::for_axis(&axis, model, Features::FULL)
}

/// Flash and static RAM of an ELF, as `size` counts them: allocated sections that occupy the
/// image (text, rodata, vectors, data) for flash; writable allocated ones (data, bss) for RAM.
pub fn image_size(elf: &Path) -> Result<(u64, u64)> {
    use object::{Object, ObjectSection, SectionFlags, SectionKind};
    let bytes = std::fs::read(elf).map_err(|e| Error::io(elf, e))?;
    let file = object::File::parse(&*bytes)
        .map_err(|e| pil(format!("{}: not an ELF file: {e}", elf.display())))?;
    let (mut flash, mut ram) = (0u64, 0u64);
    for s in file.sections() {
        let SectionFlags::Elf { sh_flags } = s.flags() else {
            continue;
        };
        let alloc = sh_flags & u64::from(object::elf::SHF_ALLOC) != 0;
        let write = sh_flags & u64::from(object::elf::SHF_WRITE) != 0;
        if !alloc {
            continue;
        }
        let in_image = !matches!(s.kind(), SectionKind::UninitializedData);
        if in_image {
            flash += s.size();
        }
        if write {
            ram += s.size();
        }
    }
    Ok((flash, ram))
}

struct Qemu {
    child: Child,
}

impl Drop for Qemu {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Qemu {
    /// What QEMU printed, for an error message.
    fn output(mut self) -> String {
        let _ = self.child.kill();
        let mut text = String::new();
        if let Some(mut o) = self.child.stdout.take() {
            let _ = o.read_to_string(&mut text);
        }
        if let Some(mut e) = self.child.stderr.take() {
            let _ = e.read_to_string(&mut text);
        }
        text
    }
}

fn start(s: &Session) -> Result<(Qemu, TcpStream)> {
    if !s.elf.is_file() {
        return Err(pil(format!(
            "{}: no firmware image; build it first: (cd firmware && cargo build --release --bin pil)",
            s.elf.display()
        )));
    }
    let listener = TcpListener::bind("127.0.0.1:0").map_err(|e| pil(format!("listen: {e}")))?;
    let port = listener
        .local_addr()
        .map_err(|e| pil(format!("listen: {e}")))?
        .port();
    let child = Command::new(&s.qemu)
        .args([
            "-cpu",
            "cortex-m4",
            "-machine",
            "netduinoplus2",
            "-display",
            "none",
            "-monitor",
            "none",
            "-semihosting-config",
            "enable=on,target=native",
            "-icount",
            "shift=0",
            "-serial",
            // nodelay: each answer leaves at once (Nagle would hold it for the host's ACK)
            &format!("tcp:127.0.0.1:{port},nodelay=on"),
            "-kernel",
        ])
        .arg(&s.elf)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| {
            pil(format!(
                "cannot start {}: {e} (install it: apt-get install qemu-system-arm)",
                s.qemu
            ))
        })?;
    let mut qemu = Qemu { child };
    listener
        .set_nonblocking(true)
        .map_err(|e| pil(format!("listen: {e}")))?;
    let deadline = Instant::now() + Duration::from_secs(20);
    let stream = loop {
        match listener.accept() {
            Ok((stream, _)) => break stream,
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {
                if let Ok(Some(status)) = qemu.child.try_wait() {
                    return Err(pil(format!(
                        "QEMU exited ({status}) before connecting: {}",
                        qemu.output()
                    )));
                }
                if Instant::now() > deadline {
                    return Err(pil(format!(
                        "QEMU did not connect within 20 s: {}",
                        qemu.output()
                    )));
                }
                std::thread::sleep(Duration::from_millis(10));
            }
            Err(e) => return Err(pil(format!("accept: {e}"))),
        }
    };
    stream
        .set_nonblocking(false)
        .and_then(|_| stream.set_nodelay(true))
        .and_then(|_| stream.set_read_timeout(Some(Duration::from_secs(10))))
        .map_err(|e| pil(format!("socket: {e}")))?;
    Ok((qemu, stream))
}

fn read_hello(stream: &mut TcpStream) -> Result<HelloFrame> {
    let mut b = [0u8; HELLO_LEN];
    stream
        .read_exact(&mut b)
        .map_err(|e| pil(format!("no hello from the firmware: {e}")))?;
    let h =
        HelloFrame::decode(&b).ok_or_else(|| pil("the firmware's hello failed its checksum"))?;
    if h.version != PROTOCOL_VERSION {
        return Err(pil(format!(
            "the firmware speaks link version {}, this host {PROTOCOL_VERSION}: rebuild one of them",
            h.version
        )));
    }
    Ok(h)
}

fn read_reply(stream: &mut TcpStream, rx: &mut ActuationReceiver) -> Result<ActuationFrame> {
    let mut buf = [0u8; 256];
    loop {
        let n = stream
            .read(&mut buf)
            .map_err(|e| pil(format!("the firmware stopped answering: {e}")))?;
        if n == 0 {
            return Err(pil("QEMU closed the link"));
        }
        // frames arrive whole, one per request: the receiver sees every byte in order
        for (i, b) in buf[..n].iter().enumerate() {
            match rx.push_actuation(*b) {
                Received::Frame(f) => {
                    if i + 1 != n {
                        return Err(pil("the firmware sent more than one answer to a frame"));
                    }
                    return Ok(f);
                }
                Received::BadChecksum => {
                    return Err(pil("an answer from the firmware failed its checksum"))
                }
                Received::Pending => {}
            }
        }
    }
}

/// Runs a session: the firmware in QEMU against the plant, then the host run, and the report.
pub fn run(s: &Session) -> Result<Report> {
    let (reference, duration) = scenario(&s.scenario)?;
    let duration = s.seconds.map_or(duration, |d| d.clamp(1.0, duration));
    let (flash_bytes, ram_bytes) = image_size(&s.elf)?;
    let wall = Instant::now();
    let (qemu, mut stream) = start(s)?;
    let hello = read_hello(&mut stream)?;

    let expected = s.model.params.to_array();
    let params_from_file =
        hello.flags & 1 == 1 && hello.lugre == expected && hello.mass_kg == s.mass_kg as f32;

    let plant_cfg = PlantConfig::default();
    let sensors = SensorConfig::realistic(s.seed);
    let (x0, _, _) = reference(0.0);
    let mut plant = Plant::new(plant_cfg.clone(), x0);
    let mut sens = Sensors::new(sensors);
    let dt = 1e-3;
    let n = (duration / dt).round() as usize;
    let mut rx = ActuationReceiver::actuation();
    let (mut sum_sq, mut count) = (0.0f64, 0usize);
    let (mut instr_sum, mut instr_n, mut instr_worst) = (0u64, 0u64, 0u32);
    let mut fault_periods = 0u32;
    let mut last = ActuationFrame::default();
    let mut first_warning = None;
    let at = |t: f64, when: f64| (t - when).abs() < 0.5 * dt;
    // the plant's friction after the rise, computed once
    let risen = s
        .friction_rise
        .and_then(|r| crate::scenarios::scale_friction_levels(&plant_cfg.friction.params, 1.0 + r));
    let rise = |t: f64, plant: &mut Plant| {
        if let (Some(q), true) = (risen, at(t, RISE_AT_S)) {
            plant.config.friction.params = q;
        }
    };
    let mut checks: Vec<FaultCheck> = Vec::new();
    // (fault, the period it was injected, its answer checked, periods since)
    let mut open: Option<(String, bool, u32)> = None;
    let mut seq: u16 = 0;
    let mut valve: Vec<f32> = Vec::with_capacity(n);
    let bar = indicatif::ProgressBar::new(n as u64).with_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} periods in QEMU, {elapsed}")
            .expect("style"),
    );
    for k in 0..n {
        if k % 100 == 0 {
            bar.set_position(k as u64);
        }
        let t = k as f64 * dt;
        rise(t, &mut plant);
        let (measurements, r) = track::controller_inputs(&sens.sample(&plant), reference(t));
        let frame = SensorFrame {
            seq,
            measurements,
            reference: r,
        };
        if let (Some(p), true) = (s.settings, at(t, SETTINGS_AT_S)) {
            let set = SettingsFrame {
                id: 1,
                lugre: p.to_array(),
            };
            stream
                .write_all(&set.encode())
                .map_err(|e| pil(format!("sending settings to the firmware: {e}")))?;
        }
        let mut bytes = frame.encode();
        let mut injected = None;
        if s.inject && at(t, Injection::CORRUPT_AT_S) {
            bytes[10] ^= 0x40;
            injected = Some(("corrupted frame", link_faults::BAD_CHECKSUM));
        }
        if s.inject && at(t, Injection::DROP_AT_S) {
            // the frame of this period never arrives: the next one carries seq + 1
            seq = seq.wrapping_add(1);
            bytes = SensorFrame { seq, ..frame }.encode();
            injected = Some(("lost frame", link_faults::LOST_FRAME));
        }
        if s.inject && at(t, Injection::STALL_AT_S) {
            std::thread::sleep(Duration::from_secs_f64(Injection::STALL_WALL_S));
            injected = Some(("stalled host", link_faults::STALL));
        }
        stream
            .write_all(&bytes)
            .map_err(|e| pil(format!("sending to the firmware: {e}")))?;
        let reply = read_reply(&mut stream, &mut rx)?;
        if reply.seq != seq {
            return Err(pil(format!(
                "answer to frame {seq} carries sequence number {}",
                reply.seq
            )));
        }
        seq = seq.wrapping_add(1);
        if let Some((name, bit)) = injected {
            let flagged = reply.link_faults & bit != 0 && reply.valve_command == 0.0;
            open = Some((name.to_string(), flagged, 0));
        } else if let Some((name, flagged, since)) = open.take() {
            if reply.status & status::SAFE == 0 {
                checks.push(FaultCheck {
                    fault: name,
                    flagged_with_valve_null: flagged,
                    periods_to_recover: Some(since + 1),
                });
            } else {
                open = Some((name, flagged, since + 1));
            }
        }
        if reply.tick_instructions > 0 {
            instr_sum += u64::from(reply.tick_instructions);
            instr_n += 1;
            instr_worst = instr_worst.max(reply.tick_instructions);
        }
        if reply.faults != 0 {
            fault_periods += 1;
        }
        if reply.status & status::HEALTH_WARNING != 0 && first_warning.is_none() {
            first_warning = Some(t);
        }
        last = reply;
        valve.push(reply.valve_command);
        plant.advance(f64::from(reply.valve_command), dt);
        let (xr, _, _) = reference(t + dt);
        if t + dt > 0.5 {
            let e = xr - plant.state.x;
            sum_sq += e * e;
            count += 1;
        }
    }
    bar.finish_and_clear();
    if let Some((name, flagged, _)) = open {
        checks.push(FaultCheck {
            fault: name,
            flagged_with_valve_null: flagged,
            periods_to_recover: None,
        });
    }
    drop(stream);
    drop(qemu);
    let host = track::run_changing(
        &plant_cfg,
        sensors,
        controller_config(s.model, s.mass_kg),
        &reference,
        duration,
        &mut |t, plant, ctl| {
            rise(t, plant);
            if let (Some(p), true) = (s.settings, at(t, SETTINGS_AT_S)) {
                // the firmware validated them the same way; a refusal shows in its answer
                let _ = ctl.set_friction(p);
            }
        },
    );
    let settings = s.settings.map(|_| {
        let k = (SETTINGS_AT_S / dt).round() as usize;
        SettingsCheck {
            status: if last.status & status::SETTINGS_APPLIED != 0 {
                "applied"
            } else if last.status & status::SETTINGS_REFUSED != 0 {
                "refused"
            } else {
                "no answer"
            }
            .into(),
            valve_step_after: track::largest_step(&valve, k, k + 300),
            valve_step_before: track::largest_step(&valve, k.saturating_sub(300), k),
            host_valve_step_after: track::largest_step(&host.valve_command, k, k + 300),
        }
    });
    Ok(Report {
        scenario: s.scenario.clone(),
        rms_err_m: (sum_sq / count.max(1) as f64).sqrt(),
        host_rms_err_m: host.tracking.rms_err_m,
        tick_instructions_mean: instr_sum as f64 / instr_n.max(1) as f64,
        tick_instructions_worst: instr_worst,
        flash_bytes,
        ram_bytes,
        params_from_file,
        frames_lost: last.frames_lost,
        frames_bad: last.frames_bad,
        fault_periods,
        health_ratio: last.health_ratio,
        health_warned: first_warning.is_some(),
        first_health_warning_s: first_warning,
        host_first_health_warning_s: host.first_health_warning_s,
        fault_checks: checks,
        settings,
        wall_s: wall.elapsed().as_secs_f64(),
    })
}
