//! The servo board: the [`Board`] boundary on a real STM32F405, through the STM32F4 HAL.
//!
//! Peripheral and pin choices of a typical STM32F405 servo board (QEMU models none of the
//! encoder mode, the ADC's conversions as wired here, the DAC or GPIO, so this board is built,
//! not run, in CI: `cargo build --release --no-default-features --features board --bin board`):
//!
//! - **encoder**: TIM5 in quadrature mode 3 (both edges of both channels), 32-bit counter,
//!   channels on PA0/PA1 (AF2); the linear scale's resolution [`COUNT_M`] per count. TIM2 is
//!   the control period's timer (the HAL's 1 kHz counter, in `src/bin/board.rs`).
//! - **pressures**: ADC1 channels 10 and 11 (PC0/PC1, analog), 4..20 mA transmitters over a
//!   150 ohm shunt (0.6..3.0 V of the 3.3 V reference), [`PRESSURE_FULL_SCALE_PA`] at 20 mA;
//!   converted one after the other at the start of each period (~2 us at a 21 MHz ADC clock
//!   and 15-cycle sampling).
//! - **valve**: DAC channel 1 (PA4, analog) into a +-10 V valve amplifier; null = mid-scale.
//!
//! The clock tree (8 MHz crystal, PLL to a 168 MHz core, APB1 at 42 MHz so the timers count
//! at 84 MHz) is set by [`Stm32Board::clocks`]; after [`Stm32Board::new`] only this file
//! touches these peripherals. Everything goes through the STM32F4 HAL (`stm32f4xx-hal`) but
//! the panic handler's DAC write, which cannot own the peripheral.

use crate::board::{write_valve, Board};
use lugre_servo::control::Measurements;
use stm32f4xx_hal::{
    adc::{
        config::{AdcConfig, SampleTime},
        Adc,
    },
    dac::{DacExt, DacOut, DacPin, C1},
    gpio::{Analog, GpioExt, PC0, PC1},
    pac::{ADC1, DAC, GPIOA, GPIOC, RCC, TIM5},
    prelude::*,
    qei::Qei,
    rcc::{Clocks, RccExt},
};

/// Length of one encoder count \[m\] (a 0.1 um linear scale, counted on both edges).
pub const COUNT_M: f32 = 1e-7;
/// Pressure at 20 mA \[Pa\] (a 250 bar transmitter).
pub const PRESSURE_FULL_SCALE_PA: f32 = 250e5;
/// ADC counts at 4 mA and at 20 mA over the 150 ohm shunt (12 bits of 3.3 V).
const ADC_4MA: f32 = 0.6 / 3.3 * 4095.0;
const ADC_20MA: f32 = 3.0 / 3.3 * 4095.0;
/// DAC counts of the valve's null and of full opening either way (12 bits).
const DAC_NULL: f32 = 2048.0;
const DAC_SPAN: f32 = 2047.0;
/// The board's crystal \[MHz\].
const HSE_MHZ: u32 = 8;

/// The servo board's peripherals, configured.
pub struct Stm32Board {
    encoder: Qei<TIM5>,
    adc: Adc<ADC1>,
    pressure_a: PC0<Analog>,
    pressure_b: PC1<Analog>,
    valve: C1,
    /// Axis position at encoder count zero \[m\] (where the axis was at power-up or homing).
    origin_m: f32,
}

impl Stm32Board {
    /// The board's clock tree: the crystal through the PLL to a 168 MHz core; APB1 at 42 MHz,
    /// so its timers (TIM2, the period's, and TIM5) count at 84 MHz; APB2 at 84 MHz, which
    /// [`Stm32Board::new`] divides by 4 for the ADC (21 MHz, under its 36 MHz limit).
    pub fn clocks(rcc: RCC) -> Clocks {
        rcc.constrain()
            .cfgr
            .use_hse(HSE_MHZ.MHz())
            .sysclk(168.MHz())
            .pclk1(42.MHz())
            .pclk2(84.MHz())
            .freeze()
    }

    /// Configures the pins, the encoder timer, the ADC and the DAC; the valve starts at null.
    pub fn new(
        gpioa: GPIOA,
        gpioc: GPIOC,
        encoder: TIM5,
        adc: ADC1,
        dac: DAC,
        origin_m: f32,
    ) -> Self {
        let pa = gpioa.split();
        let pc = gpioc.split();
        // encoder: TIM5 CH1/CH2 on PA0/PA1, both edges of both channels, the whole 32 bits
        let encoder = Qei::new(encoder, (pa.pa0, pa.pa1));
        // ADC: single conversions on request, 21 MHz (APB2 / 4), 15-cycle sampling
        let adc = Adc::adc1(
            adc,
            true,
            AdcConfig::default()
                .clock(stm32f4xx_hal::adc::config::Clock::Pclk2_div_4)
                .default_sample_time(SampleTime::Cycles_15),
        );
        // DAC channel 1 on PA4, on, at null
        let mut valve = dac.constrain(pa.pa4.into_analog());
        valve.enable();
        let mut board = Self {
            encoder,
            adc,
            pressure_a: pc.pc0.into_analog(),
            pressure_b: pc.pc1.into_analog(),
            valve,
            origin_m,
        };
        board.null_valve();
        board
    }

    /// A transmitter's pressure from its ADC counts \[Pa\] (below 4 mA reads as a fault, NaN,
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
        use stm32f4xx_hal::hal_02::Qei as _;
        // the 32-bit count as a signed position (the axis may go below its origin)
        let counts = self.encoder.count() as i32;
        let a = self.adc.convert(&self.pressure_a, SampleTime::Cycles_15);
        let b = self.adc.convert(&self.pressure_b, SampleTime::Cycles_15);
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
        self.valve.set_value(counts.min(4095));
        write_valve(u);
    }

    fn null_valve(&mut self) {
        self.valve.set_value(DAC_NULL as u16);
        write_valve(0.0);
    }
}
