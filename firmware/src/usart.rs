//! USART1 as the processor-in-the-loop link: its receive interrupt (RXNE) starts the control
//! period when a frame completes; transmission is polled (one frame per period). QEMU's `netduinoplus2` connects USART1 to its first
//! `-serial` backend; on a board it is PA9/PA10 at any baud rate the host side matches.
//!
//! The clock is enabled in RCC (a no-op in QEMU, which does not model RCC) and the baud rate
//! register is left to the board's clock tree: QEMU delivers bytes as fast as the host sends
//! them whatever BRR holds.

use stm32f4::stm32f405::{RCC, USART1};

/// USART1, polled.
pub struct Usart {
    usart: USART1,
}

impl Usart {
    /// Enables USART1 (transmitter and receiver, 8N1) with its receive interrupt.
    pub fn new(usart: USART1, rcc: &RCC) -> Self {
        rcc.apb2enr.modify(|_, w| w.usart1en().enabled());
        usart.cr1.write(|w| {
            w.ue()
                .enabled()
                .te()
                .enabled()
                .re()
                .enabled()
                .rxneie()
                .enabled()
        });
        Self { usart }
    }

    /// A received byte, if one is waiting (an overrun is cleared by the same read).
    pub fn read(&mut self) -> Option<u8> {
        let sr = self.usart.sr.read();
        if sr.rxne().bit_is_set() || sr.ore().bit_is_set() {
            Some(self.usart.dr.read().dr().bits() as u8)
        } else {
            None
        }
    }

    /// Sends bytes, waiting for the transmit register each time.
    pub fn write_all(&mut self, bytes: &[u8]) {
        for &b in bytes {
            while self.usart.sr.read().txe().bit_is_clear() {}
            self.usart.dr.write(|w| w.dr().bits(u16::from(b)));
        }
    }
}
