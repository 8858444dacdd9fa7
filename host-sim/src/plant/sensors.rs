//! Sensors between the plant and the controller: an incremental encoder (quantised), two
//! chamber pressure transducers and an oil thermometer (Gaussian noise), all delivered with a
//! configurable delay in samples. Noise is seeded, so records reproduce.

use super::{Plant, PlantState};
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use rand_xoshiro::Xoshiro256PlusPlus;
use std::collections::VecDeque;

/// Sensor models.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SensorConfig {
    /// Encoder resolution \[m\] (0: ideal).
    pub encoder_resolution_m: f64,
    /// Pressure transducer noise, standard deviation \[Pa\].
    pub pressure_noise_pa: f64,
    /// Thermometer noise, standard deviation \[K\].
    pub temperature_noise_k: f64,
    /// Measurement delay \[samples\].
    pub delay_samples: usize,
    /// Noise seed.
    pub seed: u64,
}

impl SensorConfig {
    /// Realistic sensors: 0.1 um encoder, 0.1 bar pressure noise, 0.05 K, one-sample delay.
    pub fn realistic(seed: u64) -> Self {
        Self {
            encoder_resolution_m: 1e-7,
            pressure_noise_pa: 1e4,
            temperature_noise_k: 0.05,
            delay_samples: 1,
            seed,
        }
    }

    /// Perfect sensors (the paper's setting).
    pub fn ideal() -> Self {
        Self {
            encoder_resolution_m: 0.0,
            pressure_noise_pa: 0.0,
            temperature_noise_k: 0.0,
            delay_samples: 0,
            seed: 0,
        }
    }
}

impl Default for SensorConfig {
    fn default() -> Self {
        Self::realistic(1)
    }
}

/// One sample as the controller sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measurement {
    /// Sample time \[s\].
    pub t: f64,
    /// Encoder position \[m\].
    pub x: f64,
    /// Chamber A pressure \[Pa\].
    pub p_a: f64,
    /// Chamber B pressure \[Pa\].
    pub p_b: f64,
    /// Oil temperature \[degC\].
    pub temperature_c: f64,
    /// The true plant state this sample was taken from (for records' truth columns and tests;
    /// a controller must not look at it).
    pub truth: PlantState,
}

/// The sensor chain with its delay line and noise generator.
#[derive(Clone, Debug)]
pub struct Sensors {
    /// Configuration.
    pub config: SensorConfig,
    rng: Xoshiro256PlusPlus,
    pipeline: VecDeque<PlantState>,
}

impl Sensors {
    /// New sensors.
    pub fn new(config: SensorConfig) -> Self {
        Self {
            rng: Xoshiro256PlusPlus::seed_from_u64(config.seed),
            config,
            pipeline: VecDeque::new(),
        }
    }

    /// Samples the plant now; returns what the controller receives (delayed by the configured
    /// number of samples; the first samples repeat the initial state).
    pub fn sample(&mut self, plant: &Plant) -> Measurement {
        self.pipeline.push_back(plant.state);
        while self.pipeline.len() > self.config.delay_samples + 1 {
            self.pipeline.pop_front();
        }
        let s = self.pipeline[0];
        let c = self.config;
        let x = if c.encoder_resolution_m > 0.0 {
            (s.x / c.encoder_resolution_m).round() * c.encoder_resolution_m
        } else {
            s.x
        };
        let mut noise = |sd: f64| {
            if sd > 0.0 {
                Normal::new(0.0, sd).map_or(0.0, |n| n.sample(&mut self.rng))
            } else {
                0.0
            }
        };
        let p_a = s.p_a + noise(c.pressure_noise_pa);
        let p_b = s.p_b + noise(c.pressure_noise_pa);
        let temperature_c = s.temperature_c + noise(c.temperature_noise_k);
        Measurement {
            t: plant.state.t,
            x,
            p_a,
            p_b,
            temperature_c,
            truth: s,
        }
    }
}
