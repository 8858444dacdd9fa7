//! The servo board: the [`Board`] boundary on a real STM32F405, through the register crate.
//!
//! Peripheral and pin choices of a typical STM32F405 servo board (QEMU models none of the
//! encoder mode, the ADC's conversions as wired here, the DAC or GPIO, so this board is built,
//! not run, in CI: `cargo build --release --no-default-features --features board --bin board`):
//!
//! - **encoder**: TIM5 in quadrature mode 3 (both edges of both channels), 32-bit counter,
//!   channels on PA0/PA1 (AF2); the linear scale's resolution [`COUNT_M`] per count. TIM2 is
//!   the control period's timer (see [`crate::timer`]).
//! - **pressures**: ADC1 channels 10 and 11 (PC0/PC1, analog), 4..20 mA transmitters over a
//!   150 ohm shunt (0.6..3.0 V of the 3.3 V reference), [`PRESSURE_FULL_SCALE_PA`] at 20 mA;
//!   converted one after the other at the start of each period (~2 us at a 21 MHz ADC clock
//!   and 15-cycle sampling).
//! - **valve**: DAC channel 1 (PA4, analog) into a +-10 V valve amplifier; null = mid-scale.
//!
//! Clock tree (RCC, PLL to 168 MHz) and the amplifier's enable line are the board support's
//! job before [`Stm32Board::new`]; after it, only this file touches these peripherals.

use crate::board::{write_valve, Board};
use lugre_servo::control::Measurements;
use stm32f4::stm32f405::{ADC1, DAC, GPIOA, GPIOC, RCC, TIM5};

/// Length of one encoder count [m] (a 0.1 um linear scale, counted on both edges).
pub const COUNT_M: f32 = 1e-7;
/// Pressure at 20 mA [Pa] (a 250 bar transmitter).
pub const PRESSURE_FULL_SCALE_PA: f32 = 250e5;
/// ADC counts at 4 mA and at 20 mA over the 150 ohm shunt (12 bits of 3.3 V).
const ADC_4MA: f32 = 0.6 / 3.3 * 4095.0;
const ADC_20MA: f32 = 3.0 / 3.3 * 4095.0;
/// DAC counts of the valve's null and of full opening either way (12 bits).
const DAC_NULL: f32 = 2048.0;
const DAC_SPAN: f32 = 2047.0;

/// The servo board's peripherals, configured.
pub struct Stm32Board {
    encoder: TIM5,
    adc: ADC1,
    dac: DAC,
    /// Axis position at encoder count zero [m] (where the axis was at power-up or homing).
    origin_m: f32,
}

impl Stm32Board {
    /// Configures the pins, the encoder timer, the ADC and the DAC; the valve starts at null.
    pub fn new(
        rcc: &RCC,
        gpioa: GPIOA,
        gpioc: GPIOC,
        encoder: TIM5,
        adc: ADC1,
        dac: DAC,
        origin_m: f32,
    ) -> Self {
        rcc.ahb1enr
            .modify(|_, w| w.gpioaen().enabled().gpiocen().enabled());
        rcc.apb1enr
            .modify(|_, w| w.tim5en().enabled().dacen().enabled());
        rcc.apb2enr.modify(|_, w| w.adc1en().enabled());
        // PA0/PA1: TIM5 CH1/CH2 (AF2); PA4: DAC out (analog); PC0/PC1: ADC in (analog)
        gpioa.afrl.modify(|_, w| w.afrl0().af2().afrl1().af2());
        gpioa.moder.modify(|_, w| {
            w.moder0()
                .alternate()
                .moder1()
                .alternate()
                .moder4()
                .analog()
        });
        gpioc
            .moder
            .modify(|_, w| w.moder0().analog().moder1().analog());
        // encoder: TI1 and TI2 as inputs, both edges of both (mode 3), the whole 32 bits
        encoder.ccmr1_input().write(|w| w.cc1s().ti1().cc2s().ti2());
        encoder.smcr.write(|w| w.sms().encoder_mode_3());
        encoder.arr.write(|w| w.arr().bits(u32::MAX));
        encoder.cnt.write(|w| w.cnt().bits(0));
        encoder.cr1.write(|w| w.cen().enabled());
        // ADC: on, one conversion at a time, 15-cycle sampling on both channels
        adc.smpr1
            .modify(|_, w| w.smp10().cycles15().smp11().cycles15());
        adc.cr2.write(|w| w.adon().enabled());
        // DAC channel 1 on, at null
        dac.cr.write(|w| w.en1().enabled());
        let mut board = Self {
            encoder,
            adc,
            dac,
            origin_m,
        };
        board.null_valve();
        board
    }

    /// One conversion of ADC1 channel `channel` [counts].
    #[allow(unsafe_code)]
    fn convert(&mut self, channel: u8) -> u16 {
        // SAFETY: the register crate marks SQ1 unsafe because it does not know the valid
        // channel numbers; 10 and 11 (the only values passed) are ADC1 inputs.
        self.adc.sqr3.write(|w| unsafe { w.sq1().bits(channel) });
        self.adc.cr2.modify(|_, w| w.swstart().start());
        while self.adc.sr.read().eoc().bit_is_clear() {}
        self.adc.dr.read().data().bits()
    }

    /// A transmitter's pressure from its ADC counts [Pa] (below 4 mA reads as a fault, NaN,
    /// which the controller's input supervision turns into the safe state).
    fn pressure(counts: u16) -> f32 {
        let c = f32::from(counts);
        if c < 0.5 * ADC_4MA {
            // a broken wire or a dead transmitter: the current has fallen well below 4 mA
            return f32::NAN;
        }
        (c - ADC_4MA) / (ADC_20MA - ADC_4MA) * PRESSURE_FULL_SCALE_PA
    }
}

/// Nulls the valve from the panic handler, where the board object is out of reach: the DAC's
/// data register written directly.
#[allow(unsafe_code)]
pub fn null_valve_from_panic() {
    write_valve(0.0);
    // SAFETY: called only from the panic handler, after which no other code touches the DAC;
    // the write is the safe state (mid-scale: the valve at null).
    let dac = unsafe { &*DAC::ptr() };
    dac.dhr12r1.write(|w| w.dacc1dhr().bits(DAC_NULL as u16));
}

impl Board for Stm32Board {
    fn sample(&mut self) -> Measurements {
        let counts = self.encoder.cnt.read().cnt().bits() as i32;
        let (a, b) = (self.convert(10), self.convert(11));
        Measurements {
            position_m: self.origin_m + counts as f32 * COUNT_M,
            pressure_a_pa: Self::pressure(a),
            pressure_b_pa: Self::pressure(b),
            temperature_c: None,
        }
    }

    fn command_valve(&mut self, u: f32) {
        let u = if u.is_finite() {
            u.clamp(-1.0, 1.0)
        } else {
            0.0
        };
        let counts = (DAC_NULL + u * DAC_SPAN) as u16;
        self.dac
            .dhr12r1
            .write(|w| w.dacc1dhr().bits(counts.min(4095)));
        write_valve(u);
    }

    fn null_valve(&mut self) {
        self.dac
            .dhr12r1
            .write(|w| w.dacc1dhr().bits(DAC_NULL as u16));
        write_valve(0.0);
    }
}
