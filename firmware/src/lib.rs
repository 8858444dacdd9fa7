//! The lugre-servo controller on an STM32F405: what the firmware's binaries share.
//!
//! - `lugre-servo-firmware` (`src/main.rs`): the self-test. The controller against an
//!   on-target plant model ([`plant`]) through the QEMU board ([`board`]), with the tick's
//!   instruction count.
//! - `pil` (`src/bin/pil.rs`): processor-in-the-loop. The controller closes the loop around
//!   `host-sim`'s hydraulic plant over USART1 ([`usart`], frames of `lugre_servo::link`), the
//!   host being the clock.

#![no_std]
#![deny(unsafe_code)]

pub mod board;
pub mod cycles;
pub mod plant;
pub mod stm32_board;
pub mod telemetry;
pub mod timer;
pub mod usart;

/// The friction model and mass of the parameter file (see build.rs: `LUGRE_PARAMS`).
pub mod params {
    include!(concat!(env!("OUT_DIR"), "/params.rs"));
}
