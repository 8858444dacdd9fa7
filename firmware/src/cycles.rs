//! Instruction counting with SysTick. Under QEMU's `-icount shift=0` every instruction advances
//! the virtual clock by the same amount, so SysTick counts are proportional to instructions;
//! [`Cycles::calibrate`] measures the ratio on a block of 1000 `nop`s.

use cortex_m::peripheral::{syst::SystClkSource, SYST};

/// SysTick as a free-running 24-bit down-counter, calibrated in instructions.
pub struct Cycles {
    /// Counts of an empty measurement (subtracted from every measurement).
    pub empty: u32,
    /// SysTick counts per 1000 instructions.
    pub per_1000: u32,
}

/// SysTick counts elapsed from `start` to `end` (it counts down, 24 bits).
pub fn elapsed(start: u32, end: u32) -> u32 {
    start.wrapping_sub(end) & 0x00FF_FFFF
}

/// The counter now.
pub fn now() -> u32 {
    SYST::get_current()
}

#[inline(always)]
fn nop10() {
    cortex_m::asm::nop();
    cortex_m::asm::nop();
    cortex_m::asm::nop();
    cortex_m::asm::nop();
    cortex_m::asm::nop();
    cortex_m::asm::nop();
    cortex_m::asm::nop();
    cortex_m::asm::nop();
    cortex_m::asm::nop();
    cortex_m::asm::nop();
}

/// Exactly 100 `nop`s, unrolled (no loop overhead in the calibration block).
#[inline(always)]
fn nop100() {
    nop10();
    nop10();
    nop10();
    nop10();
    nop10();
    nop10();
    nop10();
    nop10();
    nop10();
    nop10();
}

impl Cycles {
    /// Starts SysTick free-running on the core clock and calibrates it.
    pub fn calibrate(syst: &mut SYST) -> Self {
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(0x00FF_FFFF);
        syst.clear_current();
        syst.enable_counter();
        let t0 = now();
        let t1 = now();
        let empty = elapsed(t0, t1);
        let t0 = now();
        nop100();
        nop100();
        nop100();
        nop100();
        nop100();
        nop100();
        nop100();
        nop100();
        nop100();
        nop100();
        let t1 = now();
        let per_1000 = elapsed(t0, t1).saturating_sub(empty).max(1);
        Self { empty, per_1000 }
    }

    /// Instructions of a measurement from `start` to `end`.
    pub fn instructions(&self, start: u32, end: u32) -> u32 {
        let counts = elapsed(start, end).saturating_sub(self.empty);
        ((counts as u64 * 1000) / self.per_1000 as u64) as u32
    }
}
