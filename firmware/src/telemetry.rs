//! Telemetry at low priority: what the control period hands over and may wait. In QEMU it
//! goes to the semihosting console; a board would send it over its telemetry link.

use cortex_m_semihosting::hprintln;
use lugre_servo::control::health::HealthEvent;

/// Reports a friction health event. Integers only: float formatting would cost ~20 KB of
/// flash.
pub fn health(ev: HealthEvent) {
    let (what, ratio, tick) = match ev {
        HealthEvent::Warning { ratio, tick } => ("warning", ratio, tick),
        HealthEvent::Cleared { ratio, tick } => ("cleared", ratio, tick),
    };
    hprintln!(
        "health {} at period {}: friction {} per mille of the identified model",
        what,
        tick,
        (ratio * 1000.0) as i32
    );
}
