//! Friction health monitor: is the axis's friction still the friction that was identified?
//!
//! Friction drifts in service: seals wear, the oil warms, dirt gets in. The monitor compares
//! the friction the axis shows with the identified model, on the target, in fixed memory.
//!
//! Every `decimation`-th period (10: the statistic is a 5 s average, and one sample per 10 ms
//! carries what the 1 kHz periods in between would repeat, at a tenth of the cost: the model's
//! steady-state friction costs an exponential), while the axis slides steadily (`|v| >
//! min_speed_factor vs` and `|a_ref| < max_acceleration`), a sample contributes, with
//! `d = sign(v)`:
//!
//! ```text
//! measured  d (F_actuator - M a)        the force balance: what friction took
//! model     d F_ss(v)                   the identified model's steady-state friction
//! ```
//!
//! Samples are summed in blocks of `block_samples`; the last [`WINDOW_BLOCKS`] blocks live in a
//! `heapless::HistoryBuffer` (a ring that overwrites the oldest), and the health ratio is
//! `rho = sum measured / sum model` over them, once they hold `min_window_samples` sliding
//! samples. Noise in `a` and in the pressures averages out over thousands of periods; a change
//! of the friction levels does not. The monitor **warns** when `rho` leaves
//! `[1 - band, 1 + band]` and clears when it is back within half the band (hysteresis: no
//! chatter at the edge). Each change is a [`HealthEvent`] in a `heapless::Deque` that telemetry
//! drains at low priority; when nobody drains it, the oldest event is dropped, never the tick.

use heapless::{Deque, HistoryBuffer};

/// Blocks in the sliding window (5 s at the defaults: 10 samples of every 10th period per
/// block, 1 kHz).
pub const WINDOW_BLOCKS: usize = 50;
/// Events kept until telemetry drains them.
pub const EVENT_QUEUE: usize = 8;

/// Settings of the monitor.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct HealthConfig {
    /// The monitor samples every `decimation`-th period.
    pub decimation: u32,
    /// Samples per block.
    pub block_samples: u32,
    /// Sliding samples the window needs before `rho` is judged.
    pub min_window_samples: u32,
    /// Half-width of the healthy band of `rho` [-] (0.2: within +-20 % of the model).
    pub band: f32,
    /// The axis slides steadily above this multiple of the Stribeck velocity [-].
    pub min_speed_factor: f32,
    /// ... and below this reference acceleration [m/s^2].
    pub max_acceleration_m_per_s2: f32,
}

impl Default for HealthConfig {
    fn default() -> Self {
        Self {
            decimation: 10,
            block_samples: 10,
            min_window_samples: 100,
            band: 0.2,
            min_speed_factor: 3.0,
            max_acceleration_m_per_s2: 1.0,
        }
    }
}

/// What changed.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum HealthEvent {
    /// `rho` left the band.
    Warning {
        /// The ratio when it left [-].
        ratio: f32,
        /// Periods counted by [`HealthMonitor::sample_due`] when it left.
        tick: u32,
    },
    /// `rho` came back within half the band.
    Cleared {
        /// The ratio when it came back [-].
        ratio: f32,
        /// Periods counted by [`HealthMonitor::sample_due`] when it came back.
        tick: u32,
    },
}

#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Block {
    measured_n: f32,
    model_n: f32,
    samples: u32,
}

/// The monitor's state.
#[derive(Clone, Debug)]
pub struct HealthMonitor {
    blocks: HistoryBuffer<Block, WINDOW_BLOCKS>,
    open: Block,
    open_samples: u32,
    phase: u32,
    ticks: u32,
    ratio: Option<f32>,
    warning: bool,
    events: Deque<HealthEvent, EVENT_QUEUE>,
}

impl Default for HealthMonitor {
    fn default() -> Self {
        Self {
            blocks: HistoryBuffer::new(),
            open: Block::default(),
            open_samples: 0,
            phase: 0,
            ticks: 0,
            ratio: None,
            warning: false,
            events: Deque::new(),
        }
    }
}

impl HealthMonitor {
    /// Counts a period; true on the periods the monitor samples (every `decimation`-th).
    pub fn sample_due(&mut self, c: &HealthConfig) -> bool {
        self.ticks = self.ticks.wrapping_add(1);
        self.phase += 1;
        if self.phase >= c.decimation.max(1) {
            self.phase = 0;
            true
        } else {
            false
        }
    }

    /// One sample. `sliding` says whether the axis slides steadily (see the module docs);
    /// `measured_n` is `F_actuator - M a` and `model_n` the model's steady-state friction at the
    /// same velocity \[N\]. Non-finite inputs are skipped.
    pub fn update(
        &mut self,
        c: &HealthConfig,
        sliding: bool,
        velocity_m_per_s: f32,
        measured_n: f32,
        model_n: f32,
    ) {
        if sliding && measured_n.is_finite() && model_n.is_finite() {
            let d = if velocity_m_per_s >= 0.0 { 1.0 } else { -1.0 };
            self.open.measured_n += d * measured_n;
            self.open.model_n += d * model_n;
            self.open.samples += 1;
        }
        self.open_samples += 1;
        if self.open_samples < c.block_samples.max(1) {
            return;
        }
        self.blocks.write(self.open);
        self.open = Block::default();
        self.open_samples = 0;
        self.judge(c);
    }

    fn judge(&mut self, c: &HealthConfig) {
        let (mut meas, mut model, mut n) = (0.0f32, 0.0f32, 0u32);
        for b in self.blocks.as_slice() {
            meas += b.measured_n;
            model += b.model_n;
            n += b.samples;
        }
        // a NaN sum fails `model > 0` and is skipped
        if n < c.min_window_samples || model.partial_cmp(&0.0) != Some(core::cmp::Ordering::Greater)
        {
            return;
        }
        let rho = meas / model;
        if !rho.is_finite() {
            return;
        }
        self.ratio = Some(rho);
        let off = (rho - 1.0).abs();
        let tick = self.ticks;
        if !self.warning && off > c.band {
            self.warning = true;
            self.push(HealthEvent::Warning { ratio: rho, tick });
        } else if self.warning && off < 0.5 * c.band {
            self.warning = false;
            self.push(HealthEvent::Cleared { ratio: rho, tick });
        }
    }

    fn push(&mut self, e: HealthEvent) {
        if self.events.is_full() {
            self.events.pop_front();
        }
        // cannot fail: a slot was freed above
        let _ = self.events.push_back(e);
    }

    /// The latest health ratio `rho` [-] (None until the window holds enough sliding periods).
    pub fn ratio(&self) -> Option<f32> {
        self.ratio
    }

    /// True while the friction is outside the identified band.
    pub fn warning(&self) -> bool {
        self.warning
    }

    /// The oldest undelivered event, for telemetry.
    pub fn pop_event(&mut self) -> Option<HealthEvent> {
        self.events.pop_front()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs `seconds` of steady sliding at 50 mm/s (1 kHz periods, sampled as the controller
    /// samples) with friction `scale` times the model's 1000 N and deterministic noise of
    /// +-300 N on the measurement.
    fn run(m: &mut HealthMonitor, c: &HealthConfig, seconds: f32, scale: f32) {
        for k in 0..(seconds * 1000.0) as u32 {
            if !m.sample_due(c) {
                continue;
            }
            let noise = 300.0 * libm::sinf(k as f32 * 1.3);
            let v = if (k / 2000) % 2 == 0 { 0.05 } else { -0.05 };
            let d = if v > 0.0 { 1.0 } else { -1.0 };
            m.update(c, true, v, d * 1000.0 * scale + noise, d * 1000.0);
        }
    }

    #[test]
    fn a_30_percent_rise_warns_once_and_a_return_clears() {
        let c = HealthConfig::default();
        let mut m = HealthMonitor::default();
        run(&mut m, &c, 20.0, 1.0);
        assert!(!m.warning());
        assert!((m.ratio().unwrap() - 1.0).abs() < 0.02, "{:?}", m.ratio());
        assert_eq!(m.pop_event(), None);
        // friction 30 % up: warns within the window (5 s)
        let mut warned_after = None;
        for s in 0..100 {
            run(&mut m, &c, 0.1, 1.3);
            if m.warning() {
                warned_after = Some(s as f32 * 0.1);
                break;
            }
        }
        let t = warned_after.expect("no warning");
        assert!(t < 5.0, "warned after {t} s");
        assert!(matches!(m.pop_event(), Some(HealthEvent::Warning { ratio, .. }) if ratio > 1.2));
        // staying high raises no second event
        run(&mut m, &c, 10.0, 1.3);
        assert_eq!(m.pop_event(), None);
        // back to normal: cleared
        run(&mut m, &c, 10.0, 1.0);
        assert!(!m.warning());
        assert!(matches!(m.pop_event(), Some(HealthEvent::Cleared { .. })));
    }

    #[test]
    fn standstill_and_bad_inputs_leave_it_undecided() {
        let c = HealthConfig::default();
        let mut m = HealthMonitor::default();
        for _ in 0..20_000 {
            m.update(&c, false, 0.0, 5000.0, 1000.0);
            m.update(&c, true, 0.05, f32::NAN, 1000.0);
            m.update(&c, true, 0.05, 1000.0, f32::INFINITY);
        }
        assert_eq!(m.ratio(), None);
        assert!(!m.warning());
    }

    #[test]
    fn a_full_queue_drops_the_oldest_event() {
        let c = HealthConfig {
            min_window_samples: 1,
            block_samples: 1,
            ..Default::default()
        };
        let mut m = HealthMonitor::default();
        for i in 0..3 * EVENT_QUEUE {
            // alternate far above and at the model: a warning, then a clearing, ...
            let scale = if i % 2 == 0 { 3.0 } else { 1.0 };
            m.blocks = HistoryBuffer::new();
            m.update(&c, true, 0.05, 1000.0 * scale, 1000.0);
        }
        let mut n = 0;
        while m.pop_event().is_some() {
            n += 1;
        }
        assert_eq!(n, EVENT_QUEUE);
    }
}
