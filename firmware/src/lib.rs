//! The lugre-servo controller on an STM32F405: what the firmware's binaries share.
//!
//! - `lugre-servo-firmware` (`src/main.rs`): the self-test. The controller against an
//!   on-target plant model ([`plant`]) through the QEMU board ([`board`]), with the tick's
//!   instruction count.
//! - `pil` (`src/bin/pil.rs`): processor-in-the-loop. The controller closes the loop around
//!   `host-sim`'s hydraulic plant over USART1 ([`usart`], frames of `lugre_servo::link`), the
//!   host being the clock.
//! - `board` (`src/bin/board.rs`): a servo board's firmware on the real peripherals
//!   (`stm32_board`, on the STM32F4 HAL, with the `board` feature), built without the `qemu`
//!   option.

#![no_std]
#![deny(unsafe_code)]

pub mod board;
pub mod cycles;
pub mod plant;
#[cfg(feature = "board")]
pub mod stm32_board;
pub mod telemetry;
pub mod timer;
pub mod usart;

/// The friction model and mass of the parameter file (see build.rs: `LUGRE_PARAMS`).
pub mod params {
    include!(concat!(env!("OUT_DIR"), "/params.rs"));
}

/// The controller's settings every binary runs with: the parameter file's model and moving
/// mass on the simulated axis's geometry, full compensation.
pub fn controller_config() -> lugre_servo::control::ControllerConfig {
    use lugre_servo::axis::AxisGeometry;
    let axis = AxisGeometry {
        moving_mass_kg: params::MOVING_MASS_KG as f64,
        ..AxisGeometry::SIMULATED
    };
    lugre_servo::control::ControllerConfig::for_axis(
        &axis,
        params::model(),
        lugre_servo::control::Features::FULL,
    )
}
