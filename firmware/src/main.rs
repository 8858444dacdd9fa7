//! The lugre-servo controller at 1 kHz on an STM32F405, in QEMU.
//!
//! Runs 4 s of a low-speed sinusoid (2 mm, 0.5 Hz) with the full controller (feed-forward,
//! observer, residual observer, refinement) and the friction model of the parameter file the
//! host tools wrote (`params.toml`, or `LUGRE_PARAMS`; validated at build time) against an
//! on-target plant model with the true Table 2 friction, through the hardware boundary of
//! [`board`] (the QEMU board), measures the controller's cost per
//! tick with SysTick under `-icount shift=0` (calibrated against a block of 1000 `nop`s), prints
//! the figures over semihosting and exits with success only if the axis tracked.

#![no_std]
#![no_main]

use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use lugre_servo::axis::AxisGeometry;
use lugre_servo::control::{Controller, ControllerConfig, Features, Reference};
use lugre_servo_firmware::board::{self, Board, QemuBoard};
use lugre_servo_firmware::cycles::{self, Cycles};
use lugre_servo_firmware::params;
// the register blocks' interrupt vectors
use stm32f4 as _;

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

#[entry]
fn main() -> ! {
    let mut cp = cortex_m::Peripherals::take().unwrap_or_else(|| {
        debug::exit(debug::EXIT_FAILURE);
        loop {
            cortex_m::asm::wfi();
        }
    });
    let cal = Cycles::calibrate(&mut cp.SYST);

    // the identified model from the parameter file, on the simulated axis's geometry
    let axis = AxisGeometry {
        moving_mass_kg: params::MOVING_MASS_KG as f64,
        ..AxisGeometry::SIMULATED
    };
    let config = ControllerConfig::for_axis(&axis, params::model(), Features::FULL);
    let mut ctrl = Controller::new(config);
    let mut board = QemuBoard::new(0.25);
    let (amp, w) = (0.002f32, 2.0 * core::f32::consts::PI * 0.5);
    let n = 4000;
    let (mut sum_sq, mut max_err, mut count) = (0.0f32, 0.0f32, 0u32);
    let (mut worst_instr, mut total_instr) = (0u32, 0u64);
    let mut faults = 0u32;
    for k in 0..n {
        let t = k as f32 * 1e-3;
        let (s, c) = (libm::sinf(w * t), libm::cosf(w * t));
        let r = Reference {
            position_m: 0.25 + amp * s,
            velocity_m_per_s: amp * w * c,
            acceleration_m_per_s2: -amp * w * w * s,
        };
        let m = board.sample();
        let t0 = cycles::now();
        let out = ctrl.tick(&m, &r);
        let t1 = cycles::now();
        let instructions = cal.instructions(t0, t1);
        worst_instr = worst_instr.max(instructions);
        total_instr += instructions as u64;
        if !out.faults.is_empty() {
            faults += 1;
            #[cfg(feature = "defmt")]
            defmt::warn!("faults {}", out.faults);
        }
        if out.safe {
            board.null_valve();
        } else {
            board.command_valve(out.valve_command);
        }
        board.advance();
        if k >= 500 {
            let tn = (k + 1) as f32 * 1e-3;
            let e = 0.25 + amp * libm::sinf(w * tn) - board.true_position();
            sum_sq += e * e;
            max_err = max_err.max(e.abs());
            count += 1;
        }
    }
    let rms = libm::sqrtf(sum_sq / count as f32);
    let mean_instr = total_instr / n as u64;
    hprintln!(
        "parameters: {} (sigma0 {} N/m, Fc {} N, Fs {} N)",
        params::SOURCE,
        params::LUGRE[0],
        params::LUGRE[3],
        params::LUGRE[4]
    );
    hprintln!(
        "calibration: {} SysTick counts per 1000 instructions",
        cal.per_1000
    );
    hprintln!(
        "controller tick: mean {} instructions, worst {}",
        mean_instr,
        worst_instr
    );
    hprintln!(
        "tracking 2 mm / 0.5 Hz: rms {} um, max {} um, fault periods {}",
        (rms * 1e6) as u32,
        (max_err * 1e6) as u32,
        faults
    );
    let ok = rms < 20e-6 && max_err < 80e-6 && faults == 0;
    hprintln!("{}", if ok { "PASS" } else { "FAIL" });
    debug::exit(if ok {
        debug::EXIT_SUCCESS
    } else {
        debug::EXIT_FAILURE
    });
    loop {
        cortex_m::asm::wfi();
    }
}
