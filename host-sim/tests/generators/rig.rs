//! A seal-friction test rig, as labs build them: a cylinder whose rod is moved back and forth by
//! an external drive (a spindle or a linear motor) at a few mm/s, a load cell between drive and
//! rod, one chamber held at a regulated pressure, and a PC logger sampling on a software timer.
//!
//! Physics (LuGre of elastomer seals, written here from its equations, not the project's code):
//!
//! ```text
//! dz/dt = v - sigma0 |v| z / g(v),   g(v) = Fc + (Fs - Fc) exp(-(v/vs)^2)
//! F_seal = sigma0 z + sigma1 dz/dt + sigma2 v
//! Fc = Fc0 + k_p p   (pressure-energised seal),  Fs = ratio Fc
//! F_cell = m a + F_seal + dA p + noise    (dA: the piston-area error of the pressure balance)
//! ```
//!
//! integrated with RK4 at 10 kHz along the drive's motion (trapezoidal velocity, smooth ramps,
//! short dwells at the stroke ends). The logger stamps samples at jittered instants (10..17 ms
//! at a nominal 100 Hz, or about 60 Hz), stalls now and then (gaps up to 0.3 s), and records
//! position (1 um resolution), force and the chamber pressure.

use super::Rng;

/// The true values behind a generated rig record.
#[derive(Clone, Debug)]
pub struct RigTruth {
    /// Chamber pressure [bar].
    pub pressure_bar: f64,
    /// Coulomb level at this pressure [N].
    pub coulomb_n: f64,
    /// Coulomb level at zero pressure [N].
    pub coulomb0_n: f64,
    /// Pressure coefficient of the Coulomb level [N/bar].
    pub coulomb_per_bar: f64,
    /// Static level [N].
    pub static_n: f64,
    /// Viscous coefficient [N s/m].
    pub viscous: f64,
    /// Stribeck velocity [m/s].
    pub stribeck_velocity: f64,
    /// Bristle stiffness [N/m].
    pub sigma0: f64,
    /// Bristle damping [N s/m].
    pub sigma1: f64,
    /// Moving mass [kg].
    pub mass_kg: f64,
    /// Offset per bar from the area error [N/bar].
    pub offset_per_bar: f64,
    /// Nominal logger rate [Hz].
    pub logger_hz: f64,
}

/// One rig's seal (what stays the same across its records).
#[derive(Clone, Debug)]
pub struct Seal {
    /// Coulomb level at zero pressure [N].
    pub coulomb0_n: f64,
    /// Pressure coefficient [N/bar].
    pub coulomb_per_bar: f64,
    /// Fs / Fc.
    pub static_ratio: f64,
    /// sigma2 [N s/m].
    pub viscous: f64,
    /// vs [m/s].
    pub stribeck_velocity: f64,
    /// Pre-sliding length Fs / sigma0 [m].
    pub presliding_m: f64,
    /// sigma1 as a fraction of critical damping sqrt(sigma0 m).
    pub damping_fraction: f64,
    /// Moving mass [kg].
    pub mass_kg: f64,
    /// Area-error offset [N/bar].
    pub offset_per_bar: f64,
}

impl Seal {
    /// A random seal over wide physical ranges; `pressure_dependent` false sets k_p = 0.
    pub fn random(rng: &mut Rng, pressure_dependent: bool) -> Self {
        Self {
            coulomb0_n: rng.range(3.0, 10.0),
            coulomb_per_bar: if pressure_dependent {
                rng.range(0.4, 1.5)
            } else {
                0.0
            },
            static_ratio: rng.range(1.05, 1.6),
            viscous: rng.log_range(100.0, 800.0),
            stribeck_velocity: rng.log_range(0.8e-3, 4e-3),
            presliding_m: rng.log_range(20e-6, 200e-6),
            damping_fraction: rng.range(0.1, 1.0),
            mass_kg: rng.range(1.0, 5.0),
            offset_per_bar: rng.range(-0.6, 0.6),
        }
    }
}

/// How the logger behaves.
#[derive(Clone, Copy, Debug)]
pub struct Logger {
    /// Nominal rate [Hz].
    pub nominal_hz: f64,
    /// Jitter: each interval is nominal * (1 + U(0, jitter)).
    pub jitter: f64,
    /// Number of stalls.
    pub stalls: usize,
}

impl Logger {
    /// A random logger like the rigs': 100 Hz with 10..17 ms intervals, or about 60 Hz.
    pub fn random(rng: &mut Rng) -> Self {
        if rng.uniform() < 0.3 {
            Self {
                nominal_hz: 60.0,
                jitter: 0.25,
                stalls: (rng.uniform() * 3.0) as usize,
            }
        } else {
            Self {
                nominal_hz: 100.0,
                jitter: 0.7,
                stalls: (rng.uniform() * 4.0) as usize,
            }
        }
    }
}

/// A record as CSV text, and its truth.
pub fn record(seal: &Seal, pressure_bar: f64, logger: Logger, seed: u64) -> (String, RigTruth) {
    let mut rng = Rng::new(seed);
    let fc = seal.coulomb0_n + seal.coulomb_per_bar * pressure_bar;
    let fs = fc * seal.static_ratio;
    let sigma0 = fs / seal.presliding_m;
    let sigma1 = seal.damping_fraction * (sigma0 * seal.mass_kg).sqrt();
    let vs = seal.stribeck_velocity;
    let g = |v: f64| fc + (fs - fc) * (-(v / vs) * (v / vs)).exp();
    // the drive: back and forth over the stroke at a constant speed with smooth ramps
    let speed = rng.range(6e-3, 15e-3);
    let stroke = rng.range(0.02, 0.06);
    let ramp_s = rng.range(0.05, 0.3); // time to reach speed (raised-cosine acceleration)
    let dwell_s = rng.range(0.0, 0.5);
    let duration = rng.range(40.0, 80.0);
    let cruise_s = stroke / speed - ramp_s;
    let leg = 2.0 * ramp_s + cruise_s.max(0.0) + dwell_s;
    let vel = |t: f64| -> f64 {
        let k = (t / leg).floor();
        let tau = t - k * leg;
        let dir = if (k as i64) % 2 == 0 { 1.0 } else { -1.0 };
        let prof = if tau < ramp_s {
            0.5 * (1.0 - (std::f64::consts::PI * tau / ramp_s).cos())
        } else if tau < ramp_s + cruise_s {
            1.0
        } else if tau < 2.0 * ramp_s + cruise_s {
            0.5 * (1.0 + (std::f64::consts::PI * (tau - ramp_s - cruise_s) / ramp_s).cos())
        } else {
            0.0
        };
        dir * speed * prof
    };
    // RK4 on a 10 kHz grid
    let h = 1e-4;
    let n = (duration / h) as usize;
    let dz = |z: f64, v: f64| v - sigma0 * v.abs() * z / g(v);
    let mut z = 0.0;
    let mut x = 0.0;
    let mut xs = Vec::with_capacity(n + 1);
    let mut fs_cell = Vec::with_capacity(n + 1);
    let p_pa = pressure_bar * 1e5;
    for i in 0..=n {
        let t = i as f64 * h;
        let v = vel(t);
        let a = (vel(t + 1e-6) - vel(t - 1e-6)) / 2e-6;
        let f = sigma0 * z + sigma1 * dz(z, v) + seal.viscous * v;
        xs.push(x);
        fs_cell.push(seal.mass_kg * a + f + seal.offset_per_bar * pressure_bar);
        // advance z (RK4) and x (Simpson on the analytic velocity)
        let (v0, vm, v1) = (v, vel(t + h / 2.0), vel(t + h));
        let k1 = dz(z, v0);
        let k2 = dz(z + h / 2.0 * k1, vm);
        let k3 = dz(z + h / 2.0 * k2, vm);
        let k4 = dz(z + h * k3, v1);
        z += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        x += h / 6.0 * (v0 + 4.0 * vm + v1);
    }
    // the logger
    let nominal = 1.0 / logger.nominal_hz;
    let stall_at: Vec<f64> = (0..logger.stalls)
        .map(|_| rng.range(0.1, 0.9) * duration)
        .collect();
    let mut out = String::new();
    out.push_str(&format!(
        "# rig=seal friction test rig (generated)\n# pressure_bar={pressure_bar}\n# logger_hz={}\nt,x,force,p_a\n",
        logger.nominal_hz
    ));
    let mut t = rng.range(0.0, nominal); // a non-uniform first sample
    let mut stalls = stall_at.clone();
    while t < duration - 2.0 * h {
        let i = (t / h) as usize;
        let w = t / h - i as f64;
        let xi = xs[i] + w * (xs[i + 1] - xs[i]);
        let fi = fs_cell[i] + w * (fs_cell[i + 1] - fs_cell[i]);
        let xq = (xi / 1e-6).round() * 1e-6;
        let fq = fi + 0.03 * rng.normal();
        let pq = p_pa + 500.0 * rng.normal();
        out.push_str(&format!("{t:.6},{xq:.7},{fq:.5},{pq:.1}\n"));
        let mut step = nominal * (1.0 + logger.jitter * rng.uniform());
        if let Some(k) = stalls.iter().position(|s| *s <= t) {
            stalls.remove(k);
            step += rng.range(0.1, 0.3);
        }
        t += step;
    }
    let truth = RigTruth {
        pressure_bar,
        coulomb_n: fc,
        coulomb0_n: seal.coulomb0_n,
        coulomb_per_bar: seal.coulomb_per_bar,
        static_n: fs,
        viscous: seal.viscous,
        stribeck_velocity: vs,
        sigma0,
        sigma1,
        mass_kg: seal.mass_kg,
        offset_per_bar: seal.offset_per_bar,
        logger_hz: logger.nominal_hz,
    };
    (out, truth)
}

/// A random rig record: a random seal (pressure-energised on 70 % of seeds), logger and
/// chamber pressure (1..7 bar).
pub fn random_record(seed: u64) -> (String, RigTruth) {
    let mut rng = Rng::new(seed);
    let dependent = rng.uniform() < 0.7;
    let seal = Seal::random(&mut rng, dependent);
    let logger = Logger::random(&mut rng);
    let bar = rng.range(1.0, 7.0);
    record(&seal, bar, logger, seed.wrapping_mul(31).wrapping_add(7))
}

/// Records of one seal at several chamber pressures, each with its own random logger:
/// (name, CSV text) per pressure.
pub fn series(seal: &Seal, bars: &[f64], seed: u64) -> Vec<(String, String)> {
    bars.iter()
        .enumerate()
        .map(|(k, bar)| {
            let logger = Logger::random(&mut Rng::new(seed * 10 + k as u64));
            let (text, _) = record(seal, *bar, logger, seed * 100 + k as u64);
            (format!("p{k}.csv"), text)
        })
        .collect()
}
