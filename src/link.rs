//! The processor-in-the-loop link: one binary frame each way per control period.
//!
//! The host simulates the axis and is the clock: each period it sends a [`SensorFrame`]
//! (measurements and reference), the controller ticks once and answers with an
//! [`ActuationFrame`] (valve command and telemetry). Frames are little-endian, start with a
//! two-byte sync word and end with a CRC-16 (CRC-16/IBM-3740, `crc` crate) over everything
//! between the sync word and the checksum. A [`Receiver`] takes bytes one at a time, hunts for
//! the sync word, and reports a frame or a checksum error; after garbage it resynchronises on
//! the next sync word.
//!
//! Between sensor frames the host may send a [`SettingsFrame`]: new friction parameters that
//! the MCU validates and applies between ticks (ramped, see
//! [`crate::control::Controller::set_friction`]). It shares the sensor frame's first sync byte,
//! so one receiver takes both.
//!
//! The same codec runs on the MCU and on the host, so the two sides cannot disagree on the
//! layout.

use crate::control::{Measurements, Reference};
use crc::{Crc, CRC_16_IBM_3740};

const CRC: Crc<u16> = Crc::<u16>::new(&CRC_16_IBM_3740);

/// Sync word of a sensor frame (host -> MCU).
pub const SENSOR_SYNC: [u8; 2] = [0xA5, 0x5A];
/// Sync word of an actuation frame (MCU -> host).
pub const ACTUATION_SYNC: [u8; 2] = [0x5A, 0xA5];
/// Sync word of a settings frame (host -> MCU, between sensor frames).
pub const SETTINGS_SYNC: [u8; 2] = [0xA5, 0xC3];
/// Bytes of a settings frame.
pub const SETTINGS_LEN: usize = 30;
/// Sync word of the hello frame (MCU -> host, once at boot).
pub const HELLO_SYNC: [u8; 2] = [0x5A, 0xC3];
/// Bytes of the hello frame.
pub const HELLO_LEN: usize = 34;
/// Version of the frame layout (the hello carries it; the host refuses another).
pub const PROTOCOL_VERSION: u8 = 2;
/// Bytes of a sensor frame.
pub const SENSOR_LEN: usize = 36;
/// Bytes of an actuation frame.
pub const ACTUATION_LEN: usize = 40;

/// Link faults the MCU reports (bits of [`ActuationFrame::link_faults`]).
pub mod link_faults {
    /// A frame failed its checksum since the last report.
    pub const BAD_CHECKSUM: u8 = 1;
    /// A sequence number was skipped: a frame was lost.
    pub const LOST_FRAME: u8 = 2;
    /// No frame arrived within the stall timeout: the valve was nulled while waiting.
    pub const STALL: u8 = 4;
    /// The loop is in its link-recovery hold (valve at null until enough good frames).
    pub const RECOVERING: u8 = 8;
}

/// Bits of [`ActuationFrame::status`].
pub mod status {
    /// The controller is in its safe state (valve at null).
    pub const SAFE: u8 = 1;
    /// The friction health monitor warns.
    pub const HEALTH_WARNING: u8 = 2;
    /// The last settings frame was accepted (its parameters are being ramped in or in use).
    pub const SETTINGS_APPLIED: u8 = 4;
    /// The last settings frame was refused (non-physical parameters); the model is unchanged.
    pub const SETTINGS_REFUSED: u8 = 8;
}

/// MCU -> host at boot: what the firmware runs with.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct HelloFrame {
    /// [`PROTOCOL_VERSION`] of the firmware.
    pub version: u8,
    /// Bit 0: the friction model came from a parameter file at build time.
    pub flags: u8,
    /// Moving mass \[kg\].
    pub mass_kg: f32,
    /// LuGre parameters: sigma0, sigma1, sigma2, Fc, Fs, vs (SI).
    pub lugre: [f32; 6],
}

/// Host -> MCU, between periods: friction parameters to run with from now on.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct SettingsFrame {
    /// Identifies the settings (the answer's status bits refer to the last one received).
    pub id: u16,
    /// LuGre parameters: sigma0, sigma1, sigma2, Fc, Fs, vs (SI), as in [`HelloFrame`].
    pub lugre: [f32; 6],
}

/// What the host sends: a sensor frame each period, settings now and then.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HostFrame {
    /// Measurements and reference for one tick.
    Sensor(SensorFrame),
    /// New friction parameters.
    Settings(SettingsFrame),
}

/// Host -> MCU, once per period.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SensorFrame {
    /// Sequence number (wraps).
    pub seq: u16,
    /// The measurements.
    pub measurements: Measurements,
    /// The reference.
    pub reference: Reference,
}

/// MCU -> host, once per period.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct ActuationFrame {
    /// Sequence number of the sensor frame answered.
    pub seq: u16,
    /// Valve command in [-1, 1].
    pub valve_command: f32,
    /// Force demand \[N\].
    pub force_demand_n: f32,
    /// Friction compensation \[N\].
    pub friction_compensation_n: f32,
    /// The controller's fault bits ([`crate::control::Faults`]).
    pub faults: u16,
    /// Link fault bits ([`link_faults`]).
    pub link_faults: u8,
    /// Bits: [`status`].
    pub status: u8,
    /// Instructions the controller tick took (SysTick under `-icount`).
    pub tick_instructions: u32,
    /// Friction health ratio (0 until known) [-].
    pub health_ratio: f32,
    /// Frames lost so far (sequence gaps).
    pub frames_lost: u32,
    /// Frames with a bad checksum so far.
    pub frames_bad: u32,
}

fn put(buf: &mut [u8], at: &mut usize, bytes: &[u8]) {
    buf[*at..*at + bytes.len()].copy_from_slice(bytes);
    *at += bytes.len();
}

fn f32_at(b: &[u8], at: usize) -> f32 {
    f32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

/// The six LuGre parameters from `at` on (hello and settings frames carry them alike).
fn lugre_at(b: &[u8], at: usize) -> [f32; 6] {
    core::array::from_fn(|i| f32_at(b, at + 4 * i))
}

fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

fn u16_at(b: &[u8], at: usize) -> u16 {
    u16::from_le_bytes([b[at], b[at + 1]])
}

fn seal(buf: &mut [u8]) {
    let n = buf.len();
    let crc = CRC.checksum(&buf[2..n - 2]);
    buf[n - 2..].copy_from_slice(&crc.to_le_bytes());
}

fn sealed(buf: &[u8]) -> bool {
    let n = buf.len();
    CRC.checksum(&buf[2..n - 2]) == u16_at(buf, n - 2)
}

impl HelloFrame {
    /// The frame's bytes.
    pub fn encode(&self) -> [u8; HELLO_LEN] {
        let mut b = [0u8; HELLO_LEN];
        let mut at = 0;
        put(&mut b, &mut at, &HELLO_SYNC);
        put(&mut b, &mut at, &[self.version, self.flags]);
        put(&mut b, &mut at, &self.mass_kg.to_le_bytes());
        for v in self.lugre {
            put(&mut b, &mut at, &v.to_le_bytes());
        }
        seal(&mut b);
        b
    }

    /// The frame of bytes received whole; `None` when the checksum fails.
    pub fn decode(b: &[u8; HELLO_LEN]) -> Option<Self> {
        if b[..2] != HELLO_SYNC || !sealed(b) {
            return None;
        }
        Some(Self {
            version: b[2],
            flags: b[3],
            mass_kg: f32_at(b, 4),
            lugre: lugre_at(b, 8),
        })
    }
}

impl SettingsFrame {
    /// The frame's bytes.
    pub fn encode(&self) -> [u8; SETTINGS_LEN] {
        let mut b = [0u8; SETTINGS_LEN];
        let mut at = 0;
        put(&mut b, &mut at, &SETTINGS_SYNC);
        put(&mut b, &mut at, &self.id.to_le_bytes());
        for v in self.lugre {
            put(&mut b, &mut at, &v.to_le_bytes());
        }
        seal(&mut b);
        b
    }

    fn decode(b: &[u8]) -> Self {
        Self {
            id: u16_at(b, 2),
            lugre: lugre_at(b, 4),
        }
    }
}

impl SensorFrame {
    /// The frame's bytes.
    pub fn encode(&self) -> [u8; SENSOR_LEN] {
        let mut b = [0u8; SENSOR_LEN];
        let mut at = 0;
        let m = &self.measurements;
        let r = &self.reference;
        put(&mut b, &mut at, &SENSOR_SYNC);
        put(&mut b, &mut at, &self.seq.to_le_bytes());
        for v in [
            m.position_m,
            m.pressure_a_pa,
            m.pressure_b_pa,
            m.temperature_c.unwrap_or(0.0),
            r.position_m,
            r.velocity_m_per_s,
            r.acceleration_m_per_s2,
        ] {
            put(&mut b, &mut at, &v.to_le_bytes());
        }
        put(&mut b, &mut at, &[u8::from(m.temperature_c.is_some()), 0]);
        seal(&mut b);
        b
    }

    /// The frame of checked bytes (see [`Receiver`]).
    fn decode(b: &[u8]) -> Self {
        let temp = (b[32] & 1 == 1).then(|| f32_at(b, 16));
        Self {
            seq: u16_at(b, 2),
            measurements: Measurements {
                position_m: f32_at(b, 4),
                pressure_a_pa: f32_at(b, 8),
                pressure_b_pa: f32_at(b, 12),
                temperature_c: temp,
            },
            reference: Reference {
                position_m: f32_at(b, 20),
                velocity_m_per_s: f32_at(b, 24),
                acceleration_m_per_s2: f32_at(b, 28),
            },
        }
    }
}

impl ActuationFrame {
    /// The frame's bytes.
    pub fn encode(&self) -> [u8; ACTUATION_LEN] {
        let mut b = [0u8; ACTUATION_LEN];
        let mut at = 0;
        put(&mut b, &mut at, &ACTUATION_SYNC);
        put(&mut b, &mut at, &self.seq.to_le_bytes());
        put(&mut b, &mut at, &self.valve_command.to_le_bytes());
        put(&mut b, &mut at, &self.force_demand_n.to_le_bytes());
        put(&mut b, &mut at, &self.friction_compensation_n.to_le_bytes());
        put(&mut b, &mut at, &self.faults.to_le_bytes());
        put(&mut b, &mut at, &[self.link_faults, self.status]);
        put(&mut b, &mut at, &self.tick_instructions.to_le_bytes());
        put(&mut b, &mut at, &self.health_ratio.to_le_bytes());
        put(&mut b, &mut at, &self.frames_lost.to_le_bytes());
        put(&mut b, &mut at, &self.frames_bad.to_le_bytes());
        seal(&mut b);
        b
    }

    fn decode(b: &[u8]) -> Self {
        Self {
            seq: u16_at(b, 2),
            valve_command: f32_at(b, 4),
            force_demand_n: f32_at(b, 8),
            friction_compensation_n: f32_at(b, 12),
            faults: u16_at(b, 16),
            link_faults: b[18],
            status: b[19],
            tick_instructions: u32_at(b, 20),
            health_ratio: f32_at(b, 24),
            frames_lost: u32_at(b, 28),
            frames_bad: u32_at(b, 32),
        }
    }
}

/// What a byte completed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Received<F> {
    /// Nothing yet.
    Pending,
    /// A frame that passed its checksum.
    Frame(F),
    /// A frame-sized run of bytes after a sync word whose checksum failed.
    BadChecksum,
}

impl<F> Received<F> {
    /// The same outcome with the frame turned into another type.
    pub fn map<G>(self, f: impl FnOnce(F) -> G) -> Received<G> {
        match self {
            Received::Frame(x) => Received::Frame(f(x)),
            Received::BadChecksum => Received::BadChecksum,
            Received::Pending => Received::Pending,
        }
    }
}

/// Byte-at-a-time frame receiver: up to two frame kinds, each a sync word and a length (at
/// most `N` bytes). Both kinds' sync words share their first byte, so a receiver hunting for
/// either is never fooled into reading a frame of the other kind as garbage.
#[derive(Clone, Debug)]
pub struct Receiver<const N: usize> {
    kinds: [([u8; 2], usize); 2],
    kind: usize,
    buf: [u8; N],
    len: usize,
}

impl<const N: usize> Receiver<N> {
    /// A receiver hunting for `sync`, frames of `N` bytes.
    pub const fn new(sync: [u8; 2]) -> Self {
        Self {
            kinds: [(sync, N), (sync, N)],
            kind: 0,
            buf: [0; N],
            len: 0,
        }
    }

    /// Also accepts frames with `sync` (its first byte the same as the first kind's) of `len`
    /// bytes (`<= N`); they are reported as kind 1.
    pub const fn with_second_kind(mut self, sync: [u8; 2], len: usize) -> Self {
        assert!(len <= N && len > 4 && sync[0] == self.kinds[0].0[0]);
        self.kinds[1] = (sync, len);
        self
    }

    /// Takes one byte; returns the frame's kind and its checked bytes (the first
    /// `len` of the buffer) when it completes one.
    pub fn push(&mut self, byte: u8) -> Received<(usize, [u8; N])> {
        let first = self.kinds[0].0[0];
        match self.len {
            0 => {
                self.len = usize::from(byte == first);
                self.buf[0] = byte;
                return Received::Pending;
            }
            1 => {
                match self.kinds.iter().position(|(sync, _)| sync[1] == byte) {
                    Some(k) => {
                        self.kind = k;
                        self.buf[1] = byte;
                        self.len = 2;
                    }
                    // a first sync byte may start over
                    None => self.len = usize::from(byte == first),
                }
                return Received::Pending;
            }
            _ => {}
        }
        self.buf[self.len] = byte;
        self.len += 1;
        let want = self.kinds[self.kind].1;
        if self.len < want {
            return Received::Pending;
        }
        self.len = 0;
        if sealed(&self.buf[..want]) {
            Received::Frame((self.kind, self.buf))
        } else {
            Received::BadChecksum
        }
    }
}

/// The MCU's receiver of host frames (sensor and settings).
pub type SensorReceiver = Receiver<SENSOR_LEN>;
/// The host's receiver of actuation frames.
pub type ActuationReceiver = Receiver<ACTUATION_LEN>;

impl SensorReceiver {
    /// A receiver of sensor and settings frames.
    pub const fn sensors() -> Self {
        Self::new(SENSOR_SYNC).with_second_kind(SETTINGS_SYNC, SETTINGS_LEN)
    }

    /// Takes one byte; a decoded host frame when it completes one.
    pub fn push_host(&mut self, byte: u8) -> Received<HostFrame> {
        self.push(byte).map(|(kind, b)| match kind {
            0 => HostFrame::Sensor(SensorFrame::decode(&b)),
            _ => HostFrame::Settings(SettingsFrame::decode(&b)),
        })
    }
}

impl ActuationReceiver {
    /// A receiver of actuation frames.
    pub const fn actuation() -> Self {
        Self::new(ACTUATION_SYNC)
    }

    /// Takes one byte; a decoded actuation frame when it completes one.
    pub fn push_actuation(&mut self, byte: u8) -> Received<ActuationFrame> {
        self.push(byte).map(|(_, b)| ActuationFrame::decode(&b))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sensor() -> SensorFrame {
        SensorFrame {
            seq: 513,
            measurements: Measurements {
                position_m: 0.25,
                pressure_a_pa: 81e5,
                pressure_b_pa: 97e5,
                temperature_c: Some(41.5),
            },
            reference: Reference {
                position_m: 0.2512,
                velocity_m_per_s: -2.5e-3,
                acceleration_m_per_s2: 0.3,
            },
        }
    }

    fn feed_sensor(rx: &mut SensorReceiver, bytes: &[u8]) -> heapless::Vec<Received<HostFrame>, 8> {
        let mut out = heapless::Vec::new();
        for &b in bytes {
            let r = rx.push_host(b);
            if r != Received::Pending {
                let _ = out.push(r);
            }
        }
        out
    }

    #[test]
    fn frames_round_trip_both_ways() {
        let s = sensor();
        let mut rx = SensorReceiver::sensors();
        assert_eq!(
            feed_sensor(&mut rx, &s.encode()).as_slice(),
            &[Received::Frame(HostFrame::Sensor(s))]
        );
        let no_temp = SensorFrame {
            measurements: Measurements {
                temperature_c: None,
                ..s.measurements
            },
            ..s
        };
        assert_eq!(
            feed_sensor(&mut rx, &no_temp.encode()).as_slice(),
            &[Received::Frame(HostFrame::Sensor(no_temp))]
        );
        let a = ActuationFrame {
            seq: 7,
            valve_command: -0.125,
            force_demand_n: 1234.5,
            friction_compensation_n: -640.0,
            faults: 0x0104,
            link_faults: link_faults::LOST_FRAME,
            status: 3,
            tick_instructions: 1642,
            health_ratio: 1.03,
            frames_lost: 2,
            frames_bad: 1,
        };
        let mut rx = ActuationReceiver::actuation();
        let got: heapless::Vec<_, 2> = a
            .encode()
            .iter()
            .map(|&b| rx.push_actuation(b))
            .filter(|r| *r != Received::Pending)
            .collect();
        assert_eq!(got.as_slice(), &[Received::Frame(a)]);
        let h = HelloFrame {
            version: PROTOCOL_VERSION,
            flags: 1,
            mass_kg: 200.0,
            lugre: [3.9e9, 1e4, 2e3, 500.0, 630.0, 5e-3],
        };
        let mut b = h.encode();
        assert_eq!(HelloFrame::decode(&b), Some(h));
        b[9] ^= 4;
        assert_eq!(HelloFrame::decode(&b), None);
    }

    #[test]
    fn every_single_bit_flip_is_caught() {
        let bytes = sensor().encode();
        for i in 2..SENSOR_LEN {
            for bit in 0..8 {
                let mut b = bytes;
                b[i] ^= 1 << bit;
                let mut rx = SensorReceiver::sensors();
                let got = feed_sensor(&mut rx, &b);
                assert_eq!(
                    got.as_slice(),
                    &[Received::BadChecksum],
                    "byte {i} bit {bit}"
                );
            }
        }
    }

    #[test]
    fn resynchronises_after_garbage_and_a_torn_frame() {
        let s = sensor();
        let mut rx = SensorReceiver::sensors();
        let mut stream: heapless::Vec<u8, 160> = heapless::Vec::new();
        // noise with false sync starts, half a frame, then two whole ones: the torn frame
        // swallows the first whole one (one checksum error), the second gets through
        stream.extend_from_slice(&[0x00, 0xA5, 0x13, 0xA5]).unwrap();
        stream.extend_from_slice(&s.encode()[..10]).unwrap();
        stream.extend_from_slice(&s.encode()).unwrap();
        stream.extend_from_slice(&s.encode()).unwrap();
        let got = feed_sensor(&mut rx, &stream);
        assert_eq!(
            got.as_slice(),
            &[Received::BadChecksum, Received::Frame(HostFrame::Sensor(s))]
        );
    }

    #[test]
    fn settings_and_sensor_frames_share_one_receiver() {
        let s = sensor();
        let set = SettingsFrame {
            id: 3,
            lugre: [3.9e9, 200.0, 48_900.0, 506.0, 632.0, 5e-3],
        };
        let mut rx = SensorReceiver::sensors();
        let mut stream: heapless::Vec<u8, 160> = heapless::Vec::new();
        stream.extend_from_slice(&s.encode()).unwrap();
        stream.extend_from_slice(&set.encode()).unwrap();
        stream.extend_from_slice(&s.encode()).unwrap();
        assert_eq!(
            feed_sensor(&mut rx, &stream).as_slice(),
            &[
                Received::Frame(HostFrame::Sensor(s)),
                Received::Frame(HostFrame::Settings(set)),
                Received::Frame(HostFrame::Sensor(s)),
            ]
        );
        // a corrupted settings frame is a checksum error, and the next sensor frame gets through
        let mut bad = set.encode();
        bad[10] ^= 0x20;
        stream.clear();
        stream.extend_from_slice(&bad).unwrap();
        stream.extend_from_slice(&s.encode()).unwrap();
        assert_eq!(
            feed_sensor(&mut rx, &stream).as_slice(),
            &[Received::BadChecksum, Received::Frame(HostFrame::Sensor(s))]
        );
    }
}
