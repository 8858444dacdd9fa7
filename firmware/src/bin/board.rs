//! The firmware of a servo board: the controller at 1 kHz on the board's peripherals.
//!
//! The same RTIC shape as the self-test: TIM2's update interrupt runs the control period at
//! the top priority (sample the encoder and the pressures, tick, command the valve, through
//! [`Stm32Board`](lugre_servo_firmware::stm32_board::Stm32Board), on the STM32F4 HAL);
//! friction health events go to a software task at the lowest priority. The model is the parameter file's (build time). Built without the `qemu`
//! option, for the board's clock tree; not run in CI (in QEMU the HAL's clock setup waits
//! forever for RCC's ready bits, and QEMU models neither the encoder mode nor the DAC).
//! Settings at run time arrive as on the PIL link ([`lugre_servo::link::SettingsFrame`]) on a
//! board's serial port; that path is exercised by the PIL firmware.

#![no_std]
#![no_main]

#[cfg(feature = "qemu")]
compile_error!(
    "the board binary is built for the board's clock tree: --no-default-features --features board"
);

use lugre_servo_firmware::stm32_board::null_valve_from_panic;

#[cfg(feature = "defmt")]
use defmt_rtt as _;

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    // the safe state first: the DAC to the valve's null
    null_valve_from_panic();
    loop {
        cortex_m::asm::wfi();
    }
}

/// Where the axis is at power-up \[m\] (a homing routine would set it).
const ORIGIN_M: f32 = 0.25;

#[rtic::app(device = stm32f4xx_hal::pac, peripherals = true, dispatchers = [EXTI0])]
mod app {
    use super::ORIGIN_M;
    use lugre_servo::control::health::HealthEvent;
    use lugre_servo::control::{Controller, Reference};
    use lugre_servo_firmware::board::Board;
    use lugre_servo_firmware::stm32_board::Stm32Board;
    use stm32f4xx_hal::pac::TIM2;
    use stm32f4xx_hal::prelude::*;
    use stm32f4xx_hal::timer::{CounterHz, Event, Flag};

    #[shared]
    struct Shared {}

    #[local]
    struct Local {
        ctrl: Controller,
        board: Stm32Board,
        timer: CounterHz<TIM2>,
    }

    #[init]
    fn init(cx: init::Context) -> (Shared, Local) {
        let d = cx.device;
        let clocks = Stm32Board::clocks(d.RCC);
        let board = Stm32Board::new(d.GPIOA, d.GPIOC, d.TIM5, d.ADC1, d.DAC, ORIGIN_M);
        let config = lugre_servo_firmware::controller_config();
        // the period: TIM2's update event at the loop rate
        let mut timer = d.TIM2.counter_hz(&clocks);
        if timer.start(1.kHz()).is_err() {
            // a clock tree that cannot make 1 kHz: never start the loop (the valve stays null)
            panic!("TIM2 cannot count 1 kHz from this clock tree");
        }
        timer.listen(Event::Update);
        (
            Shared {},
            Local {
                ctrl: Controller::new(config),
                board,
                timer,
            },
        )
    }

    #[idle]
    fn idle(_: idle::Context) -> ! {
        loop {
            cortex_m::asm::wfi();
        }
    }

    /// The control period, at the top priority. The reference holds the axis where it is
    /// (a setpoint generator or a motion link would feed it).
    #[task(binds = TIM2, priority = 3, local = [ctrl, board, timer])]
    fn period(cx: period::Context) {
        let l = cx.local;
        l.timer.clear_flags(Flag::Update);
        let m = l.board.sample();
        let r = Reference {
            position_m: ORIGIN_M,
            velocity_m_per_s: 0.0,
            acceleration_m_per_s2: 0.0,
        };
        let out = l.ctrl.tick(&m, &r);
        l.board.actuate(&out);
        if let Some(ev) = l.ctrl.pop_health_event() {
            let _ = telemetry::spawn(ev);
        }
    }

    /// Friction health events, at the lowest priority.
    #[task(priority = 1)]
    async fn telemetry(_: telemetry::Context, _ev: HealthEvent) {
        #[cfg(feature = "defmt")]
        defmt::warn!("friction health: {}", defmt::Debug2Format(&_ev));
    }
}
