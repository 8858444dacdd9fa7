//! The control period's clock: TIM2's update interrupt at the loop rate.
//!
//! TIM2 counts a 1 MHz tick (the prescaler divides the timer clock) up to the period and
//! raises its update interrupt; the control task, bound to that interrupt at the top priority,
//! acknowledges it. On a board the timer clock is APB1's x2 (84 MHz at a 168 MHz core clock);
//! QEMU's `netduinoplus2` models TIM2 but not RCC, and counts the timer in virtual time.

use stm32f4::stm32f405::{RCC, TIM2};

/// TIM2's clock \[Hz\]. On a board APB1 x2 at a 168 MHz core clock; QEMU's timer model counts a
/// fixed 1 GHz whatever RCC says (the `qemu` build option, on by default).
#[cfg(feature = "qemu")]
pub const TIMER_CLOCK_HZ: u32 = 1_000_000_000;
/// TIM2's clock \[Hz\]: APB1 x2 at a 168 MHz core clock.
#[cfg(not(feature = "qemu"))]
pub const TIMER_CLOCK_HZ: u32 = 84_000_000;

/// TIM2 as the period clock.
pub struct PeriodTimer {
    tim: TIM2,
}

impl PeriodTimer {
    /// Starts TIM2 with an update interrupt every `period_us` microseconds (its clock is
    /// [`TIMER_CLOCK_HZ`]).
    pub fn start(tim: TIM2, rcc: &RCC, period_us: u32) -> Self {
        rcc.apb1enr.modify(|_, w| w.tim2en().enabled());
        tim.cr1.write(|w| w.cen().disabled());
        tim.psc
            .write(|w| w.psc().bits((TIMER_CLOCK_HZ / 1_000_000 - 1) as u16));
        tim.arr.write(|w| w.arr().bits(period_us - 1));
        // load the prescaler now (an update event), then clear the flag it sets
        tim.egr.write(|w| w.ug().set_bit());
        tim.sr.modify(|_, w| w.uif().clear_bit());
        tim.dier.write(|w| w.uie().enabled());
        tim.cr1.write(|w| w.cen().enabled());
        Self { tim }
    }

    /// Acknowledges the update interrupt (first thing in the period task).
    pub fn acknowledge(&mut self) {
        self.tim.sr.modify(|_, w| w.uif().clear_bit());
    }

    /// Stops the timer and its interrupt.
    pub fn stop(&mut self) {
        self.tim.dier.write(|w| w.uie().disabled());
        self.tim.cr1.write(|w| w.cen().disabled());
    }
}
