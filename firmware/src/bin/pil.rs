//! Processor-in-the-loop: the controller on the STM32F405 (in QEMU) closes the loop around
//! `host-sim`'s hydraulic plant over USART1, one frame each way per period, the host being the
//! clock (`host-sim pil` starts QEMU with this binary and drives it).
//!
//! An RTIC 2 application. The sampling event is the arrival of the period's sensor frame, so
//! the control period is the top-priority task bound to USART1's receive interrupt: it takes
//! the byte, and when a [`SensorFrame`] completes it checks the link, ticks the controller
//! (its cost counted in instructions with SysTick under `-icount shift=0`), sets the valve and
//! answers with an [`ActuationFrame`]. TIM2's 1 kHz interrupt runs the link watchdog at the
//! same priority; friction health events go to a software task at the lowest priority. At
//! boot the firmware sends a [`HelloFrame`] with the model it runs (the parameter file of the
//! build). Link faults are handled like sensor faults, safely:
//!
//! - a frame that fails its checksum: valve to null, answered with a fault frame (the host
//!   keeps its clock);
//! - a skipped sequence number (a lost frame): valve to null;
//! - no byte for [`STALL_MS`] (a stalled host): valve to null while waiting;
//!
//! and after each, the loop holds the valve at null for [`RECOVERY_FRAMES`] good frames, then
//! starts a fresh controller from where the axis is. The panic handler nulls the valve too.
//!
//! [`SensorFrame`]: lugre_servo::link::SensorFrame
//! [`ActuationFrame`]: lugre_servo::link::ActuationFrame
//! [`HelloFrame`]: lugre_servo::link::HelloFrame
//!
//! A [`lugre_servo::link::SettingsFrame`] between sensor frames carries new friction
//! parameters: checked with the core's rules (`LugreParams::new`, `check_physical`) and, if
//! physical, ramped in by the controller between ticks (`Controller::set_friction`); every
//! answer's status bits then say whether the last settings were applied or refused.

#![no_std]
#![no_main]

use cortex_m_semihosting::{debug, hprintln};
use lugre_servo::control::Controller;
use lugre_servo::friction::LugreParams;
use lugre_servo::link::SettingsFrame;
use lugre_servo_firmware::board::write_valve;

/// Longest silence of the host before the valve goes to null [ms of the period timer].
pub const STALL_MS: u32 = 5;
/// Good frames with the valve held at null after a link fault.
pub const RECOVERY_FRAMES: u32 = 50;

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    write_valve(0.0);
    hprintln!("PANIC: valve set to null");
    debug::exit(debug::EXIT_FAILURE);
    loop {
        cortex_m::asm::wfi();
    }
}

/// Checks a settings frame's parameters with the core's rules and hands them to the
/// controller; the parameters if they were applied.
fn apply(ctrl: &mut Controller, set: &SettingsFrame) -> Option<LugreParams<f32>> {
    let p = LugreParams::from_array(set.lugre).ok()?;
    ctrl.set_friction(p).ok()?;
    Some(p)
}

#[rtic::app(device = stm32f4::stm32f405, peripherals = true, dispatchers = [EXTI0])]
mod app {
    use super::{apply, RECOVERY_FRAMES, STALL_MS};
    use lugre_servo::control::controller::Mode;
    use lugre_servo::control::health::HealthEvent;
    use lugre_servo::control::{Controller, ControllerConfig};
    use lugre_servo::link::{
        link_faults, status, ActuationFrame, HelloFrame, HostFrame, Received, SensorReceiver,
        PROTOCOL_VERSION,
    };
    use lugre_servo_firmware::board::write_valve;
    use lugre_servo_firmware::cycles::{self, Cycles};
    use lugre_servo_firmware::params;
    use lugre_servo_firmware::timer::PeriodTimer;
    use lugre_servo_firmware::usart::Usart;

    /// The link's state, shared by the period task and the watchdog.
    pub struct Link {
        rx: SensorReceiver,
        /// The sequence number the next sensor frame should carry.
        expected: Option<u16>,
        lost: u32,
        bad: u32,
        /// Link fault bits not reported yet.
        pending: u8,
        /// Good frames left with the valve held at null.
        hold: u32,
        /// Watchdog periods since the last byte.
        silent_ms: u32,
        stalled: bool,
        settings_status: u8,
    }

    #[shared]
    struct Shared {
        link: Link,
    }

    #[local]
    struct Local {
        usart: Usart,
        ctrl: Controller,
        config: ControllerConfig,
        cal: Cycles,
        timer: PeriodTimer,
    }

    #[init]
    fn init(cx: init::Context) -> (Shared, Local) {
        let mut core = cx.core;
        let cal = Cycles::calibrate(&mut core.SYST);
        let mut usart = Usart::new(cx.device.USART1, &cx.device.RCC);
        write_valve(0.0);
        let config = lugre_servo_firmware::controller_config();
        usart.write_all(
            &HelloFrame {
                version: PROTOCOL_VERSION,
                flags: 1,
                mass_kg: params::MOVING_MASS_KG,
                lugre: params::LUGRE,
            }
            .encode(),
        );
        let timer = PeriodTimer::start(cx.device.TIM2, &cx.device.RCC, 1000);
        (
            Shared {
                link: Link {
                    rx: SensorReceiver::sensors(),
                    expected: None,
                    lost: 0,
                    bad: 0,
                    pending: 0,
                    hold: 0,
                    silent_ms: 0,
                    stalled: false,
                    settings_status: 0,
                },
            },
            Local {
                usart,
                ctrl: Controller::new(config),
                config,
                cal,
                timer,
            },
        )
    }

    /// Waits for the interrupts by polling: under `-icount` the virtual clock then advances
    /// with the instructions executed while the host is away (the watchdog's 5 ms are ~5
    /// million of them), as a board's clock would, rather than with the wall clock of a busy
    /// host machine (WFI).
    #[idle]
    fn idle(_: idle::Context) -> ! {
        loop {
            cortex_m::asm::nop();
        }
    }

    /// The link watchdog: a host silent for [`STALL_MS`] nulls the valve. It keeps a partly
    /// received frame: its remaining bytes may only be late (QEMU hands the guest one byte per
    /// main-loop pass, and a starved host delays them while the emulated clock runs on); were
    /// it dropped, the frame's tail would be hunted as garbage and the host would wait for an
    /// answer that never comes. A host that restarts mid-frame gets a checksum fault answered.
    #[task(binds = TIM2, priority = 3, local = [timer], shared = [link])]
    fn watchdog(mut cx: watchdog::Context) {
        cx.local.timer.acknowledge();
        cx.shared.link.lock(|l| {
            l.silent_ms = l.silent_ms.saturating_add(1);
            if l.silent_ms > STALL_MS && l.expected.is_some() && !l.stalled {
                write_valve(0.0);
                l.stalled = true;
                l.pending |= link_faults::STALL;
                l.hold = RECOVERY_FRAMES;
            }
        });
    }

    /// The control period: bound to the receive interrupt, it runs when the period's sensor
    /// frame completes (the host is the clock).
    #[task(binds = USART1, priority = 3, local = [usart, ctrl, config, cal], shared = [link])]
    fn period(mut cx: period::Context) {
        let (usart, ctrl, config, cal) =
            (cx.local.usart, cx.local.ctrl, cx.local.config, cx.local.cal);
        let Some(byte) = usart.read() else {
            return;
        };
        cx.shared.link.lock(|l| {
            // a byte: the host is alive
            l.silent_ms = 0;
            let (seq, tick) = match l.rx.push_host(byte) {
                Received::Pending => return,
                Received::Frame(HostFrame::Settings(set)) => {
                    // between ticks; not answered (the host does not wait for it)
                    l.settings_status = match apply(ctrl, &set) {
                        Some(p) => {
                            // a fresh controller after a link fault starts from them too
                            config.model.params = p;
                            status::SETTINGS_APPLIED
                        }
                        None => status::SETTINGS_REFUSED,
                    };
                    return;
                }
                Received::BadChecksum => {
                    l.bad += 1;
                    l.pending |= link_faults::BAD_CHECKSUM;
                    l.hold = RECOVERY_FRAMES;
                    write_valve(0.0);
                    // answered all the same: the host keeps one frame per period
                    let seq = l.expected.unwrap_or(0);
                    l.expected = Some(seq.wrapping_add(1));
                    (seq, None)
                }
                Received::Frame(HostFrame::Sensor(f)) => {
                    if let Some(e) = l.expected {
                        if f.seq != e {
                            l.lost += u32::from(f.seq.wrapping_sub(e));
                            l.pending |= link_faults::LOST_FRAME;
                            l.hold = RECOVERY_FRAMES;
                        }
                    }
                    l.expected = Some(f.seq.wrapping_add(1));
                    (f.seq, Some(f))
                }
            };
            l.stalled = false;
            let mut reply = ActuationFrame {
                seq,
                frames_lost: l.lost,
                frames_bad: l.bad,
                ..Default::default()
            };
            match tick {
                Some(f) if l.hold == 0 => {
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
                    // telemetry at low priority: one event at a time
                    if let Some(ev) = ctrl.pop_health_event() {
                        let _ = telemetry::spawn(ev);
                    }
                }
                Some(_) => {
                    // recovering from a link fault: valve at null, then a fresh controller
                    write_valve(0.0);
                    l.hold -= 1;
                    if l.hold == 0 {
                        *ctrl = Controller::new(*config);
                    }
                    reply.status = status::SAFE;
                    reply.link_faults |= link_faults::RECOVERING;
                }
                None => {
                    reply.status = status::SAFE;
                    reply.link_faults |= link_faults::RECOVERING;
                }
            }
            reply.status |= l.settings_status;
            reply.link_faults |= l.pending;
            l.pending = 0;
            usart.write_all(&reply.encode());
        });
    }

    /// Friction health events, at the lowest priority (QEMU's console; a board's telemetry
    /// link).
    #[task(priority = 1)]
    async fn telemetry(_: telemetry::Context, ev: HealthEvent) {
        lugre_servo_firmware::telemetry::health(ev);
    }
}
