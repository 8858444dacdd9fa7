//! The lugre-servo controller at 1 kHz on an STM32F405, in QEMU: the self-test.
//!
//! An RTIC 2 application shaped as a servo board's firmware: TIM2's update interrupt at 1 kHz
//! runs the control period at the top priority (sample -> tick -> valve, through the hardware
//! boundary of [`board`]); friction health events and the final report go to software tasks
//! at the lowest priority, which the period preempts. The panic handler and the safe state
//! null the valve.
//!
//! It runs 4 s of a low-speed sinusoid (2 mm, 0.5 Hz) with the full controller (feed-forward,
//! observer, residual observer, refinement) and the friction model of the parameter file the
//! host tools wrote (`params.toml`, or `LUGRE_PARAMS`; validated at build time) against an
//! on-target plant model with the true Table 2 friction (the QEMU board), measures the
//! controller's cost per tick with SysTick under `-icount shift=0` (calibrated against a block
//! of 1000 `nop`s), prints the figures over semihosting and exits with success only if the
//! axis tracked.

#![no_std]
#![no_main]

use cortex_m_semihosting::{debug, hprintln};
use lugre_servo_firmware::board;

#[cfg(feature = "defmt")]
use defmt_rtt as _;

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    // the safe state first: valve to null, then report
    board::write_valve(0.0);
    hprintln!("PANIC: valve set to null");
    debug::exit(debug::EXIT_FAILURE);
    loop {
        cortex_m::asm::wfi();
    }
}

/// What the self-test measured.
#[derive(Clone, Copy, Debug, Default)]
pub struct Stats {
    periods: u32,
    sum_sq: f32,
    max_err: f32,
    count: u32,
    worst_instr: u32,
    total_instr: u64,
    faults: u32,
    /// SysTick counts between the first two period interrupts (the timer's period).
    period_counts: u32,
}

/// Periods of the run (4 s at 1 kHz).
const PERIODS: u32 = 4000;

#[rtic::app(device = stm32f4::stm32f405, peripherals = true, dispatchers = [EXTI0])]
mod app {
    use super::{Stats, PERIODS};
    use cortex_m_semihosting::{debug, hprintln};
    use lugre_servo::control::health::HealthEvent;
    use lugre_servo::control::{Controller, Reference};
    use lugre_servo_firmware::board::{Board, QemuBoard};
    use lugre_servo_firmware::cycles::{self, Cycles};
    use lugre_servo_firmware::params;
    use lugre_servo_firmware::timer::PeriodTimer;

    #[shared]
    struct Shared {}

    #[local]
    struct Local {
        ctrl: Controller,
        board: QemuBoard,
        timer: PeriodTimer,
        cal: Cycles,
        stats: Stats,
        last_interrupt: Option<u32>,
    }

    #[init]
    fn init(cx: init::Context) -> (Shared, Local) {
        let mut core = cx.core;
        let cal = Cycles::calibrate(&mut core.SYST);
        // the identified model from the parameter file, on the simulated axis's geometry
        let config = lugre_servo_firmware::controller_config();
        let board = QemuBoard::new(0.25);
        let timer = PeriodTimer::start(cx.device.TIM2, &cx.device.RCC, 1000);
        (
            Shared {},
            Local {
                ctrl: Controller::new(config),
                board,
                timer,
                cal,
                stats: Stats::default(),
                last_interrupt: None,
            },
        )
    }

    #[idle]
    fn idle(_: idle::Context) -> ! {
        loop {
            cortex_m::asm::wfi();
        }
    }

    /// The control period, at the top priority: sample, tick, command the valve.
    #[task(binds = TIM2, priority = 3, local = [ctrl, board, timer, cal, stats, last_interrupt])]
    fn period(cx: period::Context) {
        let entered = cycles::now();
        let l = cx.local;
        l.timer.acknowledge();
        let s = l.stats;
        if s.period_counts == 0 {
            if let Some(prev) = *l.last_interrupt {
                s.period_counts = cycles::elapsed(prev, entered);
            }
            *l.last_interrupt = Some(entered);
        }
        let (amp, w) = (0.002f32, 2.0 * core::f32::consts::PI * 0.5);
        let t = s.periods as f32 * 1e-3;
        let (sn, cs) = (libm::sinf(w * t), libm::cosf(w * t));
        let r = Reference {
            position_m: 0.25 + amp * sn,
            velocity_m_per_s: amp * w * cs,
            acceleration_m_per_s2: -amp * w * w * sn,
        };
        let m = l.board.sample();
        let t0 = cycles::now();
        let out = l.ctrl.tick(&m, &r);
        let t1 = cycles::now();
        l.board.actuate(&out);
        let instructions = l.cal.instructions(t0, t1);
        s.worst_instr = s.worst_instr.max(instructions);
        s.total_instr += u64::from(instructions);
        if !out.faults.is_empty() {
            s.faults += 1;
            #[cfg(feature = "defmt")]
            defmt::warn!("faults {}", out.faults);
        }
        // the on-target plant stands in for the hardware: it moves over the period
        l.board.advance();
        if s.periods >= 500 {
            let tn = (s.periods + 1) as f32 * 1e-3;
            let e = 0.25 + amp * libm::sinf(w * tn) - l.board.true_position();
            s.sum_sq += e * e;
            s.max_err = s.max_err.max(e.abs());
            s.count += 1;
        }
        s.periods += 1;
        // telemetry at low priority: one event at a time (a busy task leaves it queued)
        if let Some(ev) = l.ctrl.pop_health_event() {
            let _ = telemetry::spawn(ev);
        }
        if s.periods == PERIODS {
            l.timer.stop();
            l.board.null_valve();
            let _ = report::spawn(*s);
        }
    }

    /// Friction health events, at the lowest priority.
    #[task(priority = 1)]
    async fn telemetry(_: telemetry::Context, ev: HealthEvent) {
        lugre_servo_firmware::telemetry::health(ev);
    }

    /// The figures, once the run is over; the exit status says whether the axis tracked.
    #[task(priority = 1)]
    async fn report(_: report::Context, s: Stats) {
        let rms = libm::sqrtf(s.sum_sq / s.count.max(1) as f32);
        hprintln!(
            "parameters: {} (sigma0 {} N/m, Fc {} N, Fs {} N)",
            params::SOURCE,
            params::LUGRE[0],
            params::LUGRE[3],
            params::LUGRE[4]
        );
        hprintln!(
            "period: TIM2 interrupt every {} SysTick counts (168 000 = 1 ms at 168 MHz)",
            s.period_counts
        );
        hprintln!(
            "controller tick: mean {} instructions, worst {}",
            s.total_instr / u64::from(s.periods.max(1)),
            s.worst_instr
        );
        hprintln!(
            "tracking 2 mm / 0.5 Hz: rms {} um, max {} um, fault periods {}",
            (rms * 1e6) as u32,
            (s.max_err * 1e6) as u32,
            s.faults
        );
        let ok = rms < 20e-6 && s.max_err < 80e-6 && s.faults == 0;
        hprintln!("{}", if ok { "PASS" } else { "FAIL" });
        debug::exit(if ok {
            debug::EXIT_SUCCESS
        } else {
            debug::EXIT_FAILURE
        });
    }
}
