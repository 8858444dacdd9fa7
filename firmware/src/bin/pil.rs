//! Processor-in-the-loop: the controller on the STM32F405 (in QEMU) closes the loop around
//! `host-sim`'s hydraulic plant over USART1, one frame each way per period, the host being the
//! clock (`host-sim pil` starts QEMU with this binary and drives it).
//!
//! At boot the firmware sends a [`HelloFrame`] with the model it runs (the parameter file of
//! the build). Then, for every [`SensorFrame`]: check the link, tick the controller (its cost
//! counted in instructions with SysTick under `-icount shift=0`), set the valve, answer with an
//! [`ActuationFrame`]. Link faults are handled like sensor faults, safely:
//!
//! - a frame that fails its checksum: valve to null, answered with a fault frame (the host
//!   keeps its clock);
//! - a skipped sequence number (a lost frame): valve to null;
//! - no frame for [`STALL_S`] (a stalled host): valve to null while waiting;
//!
//! and after each, the loop holds the valve at null for [`RECOVERY_FRAMES`] good frames, then
//! starts a fresh controller from where the axis is. The panic handler nulls the valve too.
//!
//! A [`lugre_servo::link::SettingsFrame`] between sensor frames carries new friction
//! parameters: checked with the core's rules (`LugreParams::new`, `check_physical`) and, if
//! physical, ramped in by the controller between ticks (`Controller::set_friction`); every
//! answer's status bits then say whether the last settings were applied or refused.

#![no_std]
#![no_main]

use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use lugre_servo::axis::AxisGeometry;
use lugre_servo::control::controller::Mode;
use lugre_servo::control::{Controller, ControllerConfig, Features};
use lugre_servo::friction::LugreParams;
use lugre_servo::link::{
    link_faults, status, ActuationFrame, HelloFrame, HostFrame, Received, SensorReceiver,
    SettingsFrame, PROTOCOL_VERSION,
};
use lugre_servo_firmware::board::write_valve;
use lugre_servo_firmware::cycles::{self, Cycles};
use lugre_servo_firmware::params;
use lugre_servo_firmware::usart::Usart;

/// Longest silence of the host before the valve goes to null [s].
pub const STALL_S: f32 = 5e-3;
/// Good frames with the valve held at null after a link fault.
pub const RECOVERY_FRAMES: u32 = 50;
/// Core clock [Hz] (SysTick's clock; QEMU's netduinoplus2 models the same 168 MHz).
const CORE_HZ: f32 = 168e6;

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    write_valve(0.0);
    hprintln!("PANIC: valve set to null");
    debug::exit(debug::EXIT_FAILURE);
    loop {
        cortex_m::asm::wfi();
    }
}

fn halt() -> ! {
    write_valve(0.0);
    debug::exit(debug::EXIT_FAILURE);
    loop {
        cortex_m::asm::wfi();
    }
}

#[entry]
fn main() -> ! {
    let Some(mut cp) = cortex_m::Peripherals::take() else {
        halt()
    };
    let Some(dp) = stm32f4::stm32f405::Peripherals::take() else {
        halt()
    };
    let cal = Cycles::calibrate(&mut cp.SYST);
    let mut usart = Usart::new(dp.USART1, &dp.RCC);
    write_valve(0.0);

    let axis = AxisGeometry {
        moving_mass_kg: params::MOVING_MASS_KG as f64,
        ..AxisGeometry::SIMULATED
    };
    let mut config = ControllerConfig::for_axis(&axis, params::model(), Features::FULL);
    let mut ctrl = Controller::new(config);
    usart.write_all(
        &HelloFrame {
            version: PROTOCOL_VERSION,
            flags: 1,
            mass_kg: params::MOVING_MASS_KG,
            lugre: params::LUGRE,
        }
        .encode(),
    );

    let stall_counts = (STALL_S * CORE_HZ) as u32;
    let mut rx = SensorReceiver::sensors();
    let mut expected: Option<u16> = None;
    let (mut lost, mut bad) = (0u32, 0u32);
    let mut pending = 0u8;
    let mut hold = 0u32;
    let mut idle = 0u32;
    let mut last = cycles::now();
    let mut stalled = false;
    let mut settings_status = 0u8;
    loop {
        let now = cycles::now();
        idle = idle.saturating_add(cycles::elapsed(last, now));
        last = now;
        if idle > stall_counts && expected.is_some() && !stalled {
            // the host went quiet: null the valve and wait for it
            write_valve(0.0);
            rx.reset();
            stalled = true;
            pending |= link_faults::STALL;
            hold = RECOVERY_FRAMES;
        }
        // a busy poll: in QEMU it measured faster than yielding with WFE (1.7 against 3.3 ms
        // of wall time per frame), and on a board the period's timer would pace the loop
        let Some(byte) = usart.read() else {
            continue;
        };
        let (seq, tick) = match rx.push_host(byte) {
            Received::Pending => continue,
            Received::Frame(HostFrame::Settings(set)) => {
                // between ticks; not answered (the host does not wait for it)
                settings_status = match apply(&mut ctrl, &set) {
                    Some(p) => {
                        // a fresh controller after a link fault starts from them too
                        config.model.params = p;
                        status::SETTINGS_APPLIED
                    }
                    None => status::SETTINGS_REFUSED,
                };
                continue;
            }
            Received::BadChecksum => {
                bad += 1;
                pending |= link_faults::BAD_CHECKSUM;
                hold = RECOVERY_FRAMES;
                write_valve(0.0);
                // answered all the same: the host keeps one frame per period
                let seq = expected.unwrap_or(0);
                expected = Some(seq.wrapping_add(1));
                (seq, None)
            }
            Received::Frame(HostFrame::Sensor(f)) => {
                if let Some(e) = expected {
                    if f.seq != e {
                        lost += u32::from(f.seq.wrapping_sub(e));
                        pending |= link_faults::LOST_FRAME;
                        hold = RECOVERY_FRAMES;
                    }
                }
                expected = Some(f.seq.wrapping_add(1));
                (f.seq, Some(f))
            }
        };
        idle = 0;
        stalled = false;
        let mut reply = ActuationFrame {
            seq,
            frames_lost: lost,
            frames_bad: bad,
            ..Default::default()
        };
        match tick {
            Some(f) if hold == 0 => {
                let t0 = cycles::now();
                let out = ctrl.tick(&f.measurements, &f.reference);
                let t1 = cycles::now();
                let u = if out.safe { 0.0 } else { out.valve_command };
                write_valve(u);
                reply.valve_command = u;
                reply.force_demand_n = out.force_demand_n;
                reply.friction_compensation_n = out.friction_compensation_n;
                reply.faults = u16::from(out.faults.0);
                reply.tick_instructions = cal.instructions(t0, t1);
                if ctrl.mode() != Mode::Running {
                    reply.status |= status::SAFE;
                }
                if out.health_warning {
                    reply.status |= status::HEALTH_WARNING;
                }
                reply.health_ratio = ctrl.health().ratio().unwrap_or(0.0);
                // telemetry's share of the period: health events leave the queue here
                while ctrl.pop_health_event().is_some() {}
            }
            Some(_) => {
                // recovering from a link fault: valve at null, then a fresh controller
                write_valve(0.0);
                hold -= 1;
                if hold == 0 {
                    ctrl = Controller::new(config);
                }
                reply.status = status::SAFE;
                reply.link_faults |= link_faults::RECOVERING;
            }
            None => {
                reply.status = status::SAFE;
                reply.link_faults |= link_faults::RECOVERING;
            }
        }
        reply.status |= settings_status;
        reply.link_faults |= pending;
        pending = 0;
        usart.write_all(&reply.encode());
        last = cycles::now();
    }
}

/// Checks a settings frame's parameters with the core's rules and hands them to the
/// controller; the parameters if they were applied.
fn apply(ctrl: &mut Controller, set: &SettingsFrame) -> Option<LugreParams<f32>> {
    let [s0, s1, s2, fc, fs, vs] = set.lugre;
    let p = LugreParams::new(s0, s1, s2, fc, fs, vs).ok()?;
    ctrl.set_friction(p).ok()?;
    Some(p)
}
