//! The hardware boundary: everything the controller's caller needs from a servo board, and
//! nothing else. The control loop in `main.rs` talks only to this trait, so the same loop runs
//! against the QEMU board here and against a real board's peripherals.
//!
//! Two implementations: `crate::stm32_board::Stm32Board` (the `board` feature), a real
//! STM32F405 servo board (encoder on TIM5, pressures on ADC1, valve on the DAC; the control
//! period from TIM2's interrupt; see that module for pins and scaling), and [`QemuBoard`]
//! here. QEMU's
//! `netduinoplus2` has no DAC and no GPIO, so the QEMU board keeps the valve command in memory
//! and closes the loop through an on-target plant model.

use lugre_servo::control::{Measurements, Output};

/// A servo board as the control loop sees it.
pub trait Board {
    /// Samples the sensors for this period.
    fn sample(&mut self) -> Measurements;
    /// Commands the valve: `u` in [-1, 1] (the controller clamps it).
    fn command_valve(&mut self, u: f32);
    /// Puts the valve to null, the safe state.
    fn null_valve(&mut self);
    /// Acts on the controller's output for this period: the valve to null in the safe state,
    /// else to its command.
    fn actuate(&mut self, out: &Output) {
        if out.safe {
            self.null_valve();
        } else {
            self.command_valve(out.valve_command);
        }
    }
}

/// The valve command register of the QEMU board (a DAC on real hardware), as f32 bits: a
/// static, so the panic handler can null it without the board.
pub static VALVE: core::sync::atomic::AtomicU32 = core::sync::atomic::AtomicU32::new(0);

/// Writes the valve register.
pub fn write_valve(u: f32) {
    VALVE.store(u.to_bits(), core::sync::atomic::Ordering::SeqCst);
}

/// The QEMU board: an on-target hydraulic plant (true Table 2 friction) behind a 0.1 um
/// encoder; the valve register is read back by the plant each period.
pub struct QemuBoard {
    plant: crate::plant::Plant,
}

impl QemuBoard {
    /// The axis at rest at `x` \[m\].
    pub fn new(x: f32) -> Self {
        write_valve(0.0);
        Self {
            plant: crate::plant::Plant::new(x),
        }
    }

    /// The plant's true position \[m\] (for the tracking figures, not for the controller).
    pub fn true_position(&self) -> f32 {
        self.plant.x
    }

    /// Advances the plant by one period with the valve as commanded.
    pub fn advance(&mut self) {
        let u = f32::from_bits(VALVE.load(core::sync::atomic::Ordering::SeqCst));
        self.plant.advance(u);
    }
}

impl Board for QemuBoard {
    fn sample(&mut self) -> Measurements {
        Measurements {
            position_m: libm::roundf(self.plant.x * 1e7) * 1e-7,
            pressure_a_pa: self.plant.pa,
            pressure_b_pa: self.plant.pb,
            temperature_c: None,
        }
    }

    fn command_valve(&mut self, u: f32) {
        write_valve(u);
    }

    fn null_valve(&mut self) {
        write_valve(0.0);
    }
}
