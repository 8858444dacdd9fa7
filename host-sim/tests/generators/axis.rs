//! A servo axis with friction, for the diagnosis benchmark, written from scratch: no code shared
//! with `host-sim`'s plant or the core's friction model.
//!
//! Two actuators:
//! - an **ideal force actuator** under a digital PID position loop at 1 kHz (force measured with
//!   0.2 % of full-scale noise), and
//! - a **differential hydraulic cylinder** (critically lapped 4-way valve with a first-order
//!   spool, orifice flow, chamber compressibility, internal leakage, a supply pressure that the
//!   operator changes now and then) under a proportional position loop with velocity
//!   feed-forward; the force is measured from the two chamber pressures.
//!
//! Friction (LuGre, from its equations; sub-steps of 20 us, the bristle state implicit Euler, the
//! mechanics semi-implicit Euler):
//!
//! ```text
//! dz/dt = v - sigma0 |v| z / g(v)
//! F = sigma0 z + sigma1 dz/dt + F_visc(v) + F_extra
//! ```
//!
//! or, on request ([`random_record_on`], `--contact maxwell`), a generalized Maxwell-slip contact
//! ([`Maxwell`]: elastic-slip elements with frictional lag, a model the diagnosis does not
//! contain) under the same axes, effects, schedules and noise,
//! with at most one hidden effect, whose **shape differs from the diagnosis's own**: asymmetry
//! with separate Coulomb, static and viscous ratios; a load dependence that is a power of the
//! pressure sum; position dependence as a linear gradient, a periodic ripple or a local wear
//! bump; temperature through an Andrade viscosity law and a linear Coulomb drift; a rational or
//! stretched-exponential Stribeck curve; a power-law viscous term; a Hill-type dwell stiction
//! whose age follows the aging law of rate-and-state friction in the benchmarks
//! ([`DwellLaw::Aging`]) or, in the tests written before session 100 and on request
//! (`--dwell-law restart`), restarts at a stick and is renewed by any slip.
//! Base parameters are drawn over wide ranges (soft and stiff contacts, light and heavy masses,
//! damped and undamped bristles); the excitation is a random schedule of moves (1..120 mm/s)
//! and sinusoids with reversals, each at most [`MAX_BURST_S`] long and followed by a dwell
//! (0.05..3 s). The encoder has 1 um resolution, the force and pressure noise is given above
//! ([`Sensors`]: a suite can coarsen or refine them, [`random_record_with`]).

use super::Rng;

/// The hidden effects, spelled as the diagnosis names them.
pub const EFFECTS: [&str; 8] = [
    "asymmetry",
    "offset",
    "load_dependence",
    "position_dependence",
    "temperature_dependence",
    "stribeck_shape",
    "viscous_power",
    "dwell_stiction",
];

/// The hidden effect of that name (`none`: effect-free), as the benchmarks take it on their
/// command lines; an unknown name is an error naming it.
#[allow(dead_code)]
pub fn effect_named(name: &str) -> Result<Option<&'static str>, String> {
    if name == "none" {
        return Ok(None);
    }
    EFFECTS
        .iter()
        .find(|e| **e == name)
        .map(|e| Some(*e))
        .ok_or_else(|| {
            format!(
                "unknown effect {name} (none or one of {})",
                EFFECTS.join(", ")
            )
        })
}

/// The records a benchmark's `EFFECT:SEED,...` list names (`EFFECT:A..B` for seeds A to B,
/// `none` for effect-free), in order; an unknown effect or a seed that is not a number is an
/// error naming the item.
#[allow(dead_code)]
pub fn seed_list(list: &str) -> Result<Vec<(Option<&'static str>, u64)>, String> {
    let mut records = Vec::new();
    for item in list.split(',').filter(|i| !i.is_empty()) {
        let (name, seeds) = item
            .split_once(':')
            .ok_or_else(|| format!("{item}: expected EFFECT:SEED or EFFECT:A..B"))?;
        let effect = effect_named(name)?;
        let seed = |s: &str| {
            s.parse::<u64>()
                .map_err(|_| format!("{item}: seed {s:?} is not a whole number"))
        };
        let (first, last) = match seeds.split_once("..") {
            Some((a, b)) => (seed(a)?, seed(b)?),
            None => (seed(seeds)?, seed(seeds)?),
        };
        records.extend((first..=last).map(|s| (effect, s)));
    }
    Ok(records)
}

/// Sample period of the record [s].
pub const DT: f64 = 1e-3;
/// Integration sub-steps per sample.
const SUB: usize = 50;
/// Longest move or sinusoid burst of the schedule [s]: a slow move across the stroke or one
/// slow sinusoid could otherwise fill a whole record, leaving it without the rests, reversals
/// and speed range a diagnosis record needs (and a dwell effect nothing to act on).
pub const MAX_BURST_S: f64 = 8.0;
/// Below this sliding speed the dwell clock runs [m/s]. Sliding, not the body's speed: a soft
/// contact holding a closed-loop axis deflects elastically by tens of micrometres at speeds
/// above this while its junctions stay put (see [`clock`]).
const STICK_SPEED: f64 = 5e-5;

/// Which actuator moves the axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Actuator {
    /// Ideal force actuator, force measured.
    Force,
    /// Differential hydraulic cylinder, force from the chamber pressures.
    Hydraulic,
}

/// How friction varies along the stroke.
#[derive(Clone, Copy, Debug)]
pub enum PositionShape {
    /// `dF = k (x - x_c)`.
    Linear { per_m: f64, centre_m: f64 },
    /// `dF = a sin(2 pi x / lambda + phi)`.
    Periodic {
        amplitude_n: f64,
        wavelength_m: f64,
        phase: f64,
    },
    /// `dF = a exp(-((x - x_b) / w)^2)` (a worn or tight spot).
    Bump {
        amplitude_n: f64,
        centre_m: f64,
        width_m: f64,
    },
    /// Family B: `dF = a tanh((x - x_s) / w)`, a step in the rod's finish (a chromed section
    /// ends, a seal crosses a port) a few millimetres wide.
    Step {
        amplitude_n: f64,
        centre_m: f64,
        width_m: f64,
    },
    /// Family B: two narrow spots of opposite sign, `a_1 exp(-((x - x_1) / w)^2) +
    /// a_2 exp(-((x - x_2) / w)^2)` (a scored patch beside a tight one).
    Pair {
        amplitudes_n: [f64; 2],
        centres_m: [f64; 2],
        width_m: f64,
    },
}

/// The hidden effect and its shape.
#[derive(Clone, Copy, Debug)]
pub enum Shape {
    /// Plain LuGre.
    None,
    /// Separate multipliers per direction (`+` = moving in +x).
    Asymmetry {
        coulomb: [f64; 2],
        static_: [f64; 2],
        viscous: [f64; 2],
    },
    /// Constant external force [N].
    Offset { force_n: f64 },
    /// `Fc, Fs -> (1 + s ((p_sum / p_ref)^gamma - 1)) Fc, Fs`.
    Load {
        strength: f64,
        exponent: f64,
        reference_pa: f64,
    },
    /// `Fc, Fs += dF(x)`.
    Position(PositionShape),
    /// `sigma2 -> sigma2 exp(B (1/T - 1/T0))` (Andrade), `Fc, Fs -> (1 + k (T - T0)) Fc, Fs`.
    Temperature { andrade_k: f64, coulomb_per_k: f64 },
    /// `g = Fc + (Fs - Fc) / (1 + |v/vs|^d)` (rational) or `exp(-|v/vs|^d)` (stretched).
    Stribeck { rational: bool, exponent: f64 },
    /// `F_visc = sigma2 v_r sign(v) |v / v_r|^d`.
    ViscousPower {
        exponent: f64,
        reference_m_per_s: f64,
    },
    /// `Fs += dF t^n / (t^n + tau^n)`, `t` = time stuck before the motion, forgotten over
    /// the sliding distance `renewal_m` once the contact slides (the junctions aged at rest are
    /// renewed: `t` decays as `e^(-s / renewal_m)` along the slid distance `s`). How a new
    /// stick and slow slip treat `t` is the axis's [`DwellLaw`].
    Dwell {
        increase_n: f64,
        tau_s: f64,
        hill: f64,
        renewal_m: f64,
    },
    /// Family B ([`Family::B`]): every level, the viscous coefficient and the Stribeck
    /// velocity per direction, each ratio drawn on its own (the static shift may oppose the
    /// Coulomb one).
    AsymmetryB {
        coulomb: [f64; 2],
        static_: [f64; 2],
        viscous: [f64; 2],
        stribeck: [f64; 2],
    },
    /// Family B: a seal energised by pressure that saturates, `Fc -> (1 + s tanh((p_sum -
    /// p_mid) / p_w)) Fc` and `Fs` by `static_share` of that change.
    LoadB {
        strength: f64,
        mid_pa: f64,
        width_pa: f64,
        static_share: f64,
    },
    /// Family B: the oil's viscosity by Vogel-Fulcher, `eta ~ exp(B / (T - T_v))`; the
    /// viscous coefficient follows eta, the Stribeck velocity `eta^(-1/2)` (a thinner film
    /// lifts later), and both levels `exp(-k (T - T0))`.
    TemperatureB {
        vogel_b_k: f64,
        vogel_tv_c: f64,
        levels_per_k: f64,
    },
    /// Family B: two lubrication scales, `g = Fc + (Fs - Fc) (w exp(-(v/vs)^2) + (1 - w)
    /// exp(-|v| / (r vs)))`: a boundary hump and a slow mixed-film decay.
    StribeckB { share: f64, scale: f64 },
    /// Family B: linear plus quadratic drag `sigma2 v (1 + |v| / v_q)` (`quadratic`) or a
    /// shear-thinning film that saturates, `sigma2 v_q tanh(v / v_q)`.
    ViscousB {
        quadratic: bool,
        velocity_m_per_s: f64,
    },
    /// Family B: logarithmic ageing (Rabinowicz, Dieterich), `Fs += A ln(1 + t / t0)` with no
    /// saturation, forgotten over `renewal_m` of sliding as [`Shape::Dwell`] is.
    DwellLog {
        per_e_fold_n: f64,
        t0_s: f64,
        renewal_m: f64,
    },
}

/// Which family of effect shapes a record's hidden effect is drawn from. Family A is the
/// one every suite ran until session 45. Family B was written in session 45 before any
/// diagnosis ran on it, to measure how the diagnosis does on shapes nobody tuned it on: other
/// physical laws for the same eight effects (see each `*B` shape and [`PositionShape::Step`],
/// [`PositionShape::Pair`]). A seed's axis, schedule and noise are the same in both families
/// (family B draws its shape from a generator of its own): only the effect's shape differs.
/// An offset's form is fixed by physics; family B draws its size over a wider range.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Family {
    /// The shapes of sessions 1..44.
    #[default]
    A,
    /// Session 45's other laws.
    B,
}

/// The word after `flag` on a benchmark's command line: `None` without the flag, `Some(None)`
/// with nothing after it.
fn flag_value<'a>(args: &'a [String], flag: &str) -> Option<Option<&'a str>> {
    args.iter()
        .position(|a| a == flag)
        .map(|i| args.get(i + 1).map(String::as_str))
}

/// The choice named after `flag` among `choices` (the first without the flag); another value
/// is a panic that names the flag and its choices.
fn flag_choice<T: Copy>(args: &[String], flag: &str, choices: &[(&str, T)]) -> T {
    match flag_value(args, flag) {
        None => choices[0].1,
        Some(word) => choices
            .iter()
            .find(|(name, _)| Some(*name) == word)
            .map(|c| c.1)
            .unwrap_or_else(|| {
                let names: Vec<&str> = choices.iter().map(|c| c.0).collect();
                panic!(
                    "{flag} takes {}, not {}",
                    names.join(" or "),
                    word.unwrap_or("nothing")
                )
            }),
    }
}

impl Family {
    /// `--shapes a|b` (family A without it); another value is a panic that names it.
    #[allow(dead_code)]
    pub fn from_args(args: &[String]) -> Self {
        flag_choice(args, "--shapes", &[("a", Self::A), ("b", Self::B)])
    }
}

impl Shape {
    /// A family-B shape of `effect` for `axis` (whose base parameters it reads), from a
    /// generator of its own seeded by `seed`.
    pub fn random_b(effect: &str, axis: &Axis, seed: u64) -> Self {
        let mut rng = Rng::new(seed.wrapping_mul(0x9E37_79B9).wrapping_add(45));
        let sign = |rng: &mut Rng| if rng.uniform() < 0.5 { 1.0 } else { -1.0 };
        match effect {
            "asymmetry" => {
                let rc = rng.range(0.1, 0.3) * sign(&mut rng);
                let rs = rng.range(-0.3, 0.3);
                let rv = rng.range(-0.3, 0.3);
                let rvs = rng.range(-0.4, 0.4);
                Shape::AsymmetryB {
                    coulomb: [1.0 + rc, 1.0 - rc],
                    static_: [1.0 + rs, 1.0 - rs],
                    viscous: [1.0 + rv, 1.0 - rv],
                    stribeck: [1.0 + rvs, 1.0 - rvs],
                }
            }
            "offset" => Shape::Offset {
                force_n: axis.coulomb_n * rng.log_range(0.05, 0.6) * sign(&mut rng),
            },
            "load_dependence" => Shape::LoadB {
                strength: rng.range(0.3, 0.7),
                mid_pa: rng.range(100e5, 180e5),
                width_pa: rng.range(20e5, 60e5),
                static_share: rng.range(0.3, 1.0),
            },
            "position_dependence" => {
                let a = axis.coulomb_n * rng.range(0.15, 0.4) * sign(&mut rng);
                let stroke = axis.stroke_m;
                Shape::Position(if rng.uniform() < 0.5 {
                    PositionShape::Step {
                        amplitude_n: a,
                        centre_m: rng.range(-0.25, 0.25) * stroke,
                        width_m: rng.range(0.005, 0.03) * stroke,
                    }
                } else {
                    let c = rng.range(-0.25, 0.2) * stroke;
                    PositionShape::Pair {
                        amplitudes_n: [1.5 * a, -1.5 * a * rng.range(0.5, 1.0)],
                        centres_m: [c, c + rng.range(0.06, 0.15) * stroke],
                        width_m: rng.range(0.02, 0.05) * stroke,
                    }
                })
            }
            "temperature_dependence" => Shape::TemperatureB {
                vogel_b_k: rng.range(700.0, 1000.0),
                vogel_tv_c: rng.range(-100.0, -80.0),
                levels_per_k: rng.range(0.002, 0.008) * sign(&mut rng),
            },
            "stribeck_shape" => Shape::StribeckB {
                share: rng.range(0.3, 0.7),
                scale: rng.range(3.0, 8.0),
            },
            "viscous_power" => {
                let quadratic = rng.uniform() < 0.5;
                Shape::ViscousB {
                    quadratic,
                    velocity_m_per_s: if quadratic {
                        rng.log_range(0.02, 0.1)
                    } else {
                        rng.log_range(0.01, 0.05)
                    },
                }
            }
            "dwell_stiction" => Shape::DwellLog {
                per_e_fold_n: axis.static_n * rng.range(0.04, 0.1),
                t0_s: rng.log_range(0.005, 0.05),
                renewal_m: rng.log_range(2e-5, 2e-3),
            },
            other => panic!("unknown effect {other}"),
        }
    }
}

/// A random axis and its hidden effect: everything the record's truth is made of.
#[derive(Clone, Debug)]
pub struct Axis {
    /// The hidden effect's name (None: effect-free).
    pub effect: Option<&'static str>,
    /// Its shape.
    pub shape: Shape,
    /// Actuator.
    pub actuator: Actuator,
    /// Moving mass [kg].
    pub mass_kg: f64,
    /// Coulomb level [N].
    pub coulomb_n: f64,
    /// Static level [N].
    pub static_n: f64,
    /// Stribeck velocity [m/s].
    pub stribeck_m_per_s: f64,
    /// Bristle stiffness [N/m].
    pub sigma0: f64,
    /// Bristle damping [N s/m].
    pub sigma1: f64,
    /// Viscous coefficient [N s/m].
    pub sigma2: f64,
    /// Usable stroke [m].
    pub stroke_m: f64,
    /// Oil temperature at the start [degC] and its rise over the record [K] (None: no sensor).
    pub temperature: Option<(f64, f64, f64)>,
    /// Position-loop bandwidth [Hz].
    pub loop_hz: f64,
    /// Hydraulic cylinder: piston area A [m^2], rod-side ratio A_b / A_a.
    pub area_m2: f64,
    /// A_b / A_a.
    pub area_ratio: f64,
    /// Record length [s].
    pub duration_s: f64,
    /// The dwell clock of the record this axis made, per sample [s] ([`random_record`] keeps
    /// it): the truth along a measured motion reads its junctions' age here.
    pub dwell_trace: Option<DwellTrace>,
    /// What the record's sensors resolve.
    pub sensors: Sensors,
    /// The contact underneath: LuGre unless a suite asks for another ([`random_record_on`]).
    pub contact: Contact,
    /// How a dwell contact's junctions age ([`DwellLaw`]).
    pub dwell_law: DwellLaw,
}

/// The friction contact under the effects: what the force does between the Stribeck curve
/// `g(v)` (with any hidden effect applied) and the body's motion.
#[derive(Clone, Debug)]
pub enum Contact {
    /// LuGre: one bristle deflection z (the module's equations).
    LuGre,
    /// Generalized Maxwell-slip ([`Maxwell`]), a model our diagnosis does not contain.
    Maxwell(Maxwell),
}

/// Generalized Maxwell-slip contact (Lampaert, Al-Bender and Swevers' structure, written from
/// its description): elastic-slip elements in parallel, element i with stiffness `k_i` and a
/// share `a_i` of the curve (`sum a_i = 1`). A sticking element's force follows the motion,
/// `dF_i/dt = k_i v`, until it reaches `a_i g(v)`; then it slips, its force drawn towards
/// `a_i g(v) sign(v)` at a finite rate (frictional lag in time),
/// `dF_i/dt = C (a_i g(v) sign(v) - F_i)`, and sticks again when the motion reverses or stops.
///
/// ```text
/// F = sum F_i + sigma1 v (share of elements sticking) + F_visc(v) + F_extra
/// ```
///
/// Unlike LuGre, its presliding hysteresis has nonlocal memory (each element remembers where it
/// last slipped) and its sliding force lags speed changes by `1/C` seconds: the diagnosis's
/// baseline is a wrong model for it.
#[derive(Clone, Debug)]
pub struct Maxwell {
    /// Per element: stiffness [N/m] and share of the curve (the shares sum to 1).
    pub elements: Vec<(f64, f64)>,
    /// Rate C at which a slipping element's force follows the curve [1/s].
    pub lag_rate_per_s: f64,
}

impl Maxwell {
    /// Elements for `axis`, drawn from their own generator seeded by `seed` (the axis's own
    /// draws are untouched, so a seed's LuGre and Maxwell records share everything else): 3..8
    /// elements, each breaking away after 0.1..3 times the LuGre draw's presliding length
    /// `Fs / sigma0`, and a lag rate of 30..1000 1/s.
    pub fn random(axis: &Axis, seed: u64) -> Self {
        let mut rng = Rng::new(seed ^ 0x6D61_7877_656C_6C53);
        let n = 3 + (rng.uniform() * 6.0) as usize;
        let raw: Vec<f64> = (0..n).map(|_| rng.range(0.2, 1.0)).collect();
        let total: f64 = raw.iter().sum();
        let presliding_m = axis.static_n / axis.sigma0;
        let elements = raw
            .iter()
            .map(|r| {
                let share = r / total;
                let break_m = presliding_m * rng.log_range(0.1, 3.0);
                (share * axis.static_n / break_m, share)
            })
            .collect();
        Self {
            elements,
            lag_rate_per_s: rng.log_range(30.0, 1000.0),
        }
    }
}

/// Which contact a suite's records have (`--contact maxwell` on a benchmark's command line).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum ContactKind {
    /// LuGre (every suite until session 42).
    #[default]
    LuGre,
    /// Generalized Maxwell-slip.
    Maxwell,
}

impl ContactKind {
    /// `--contact lugre|maxwell` (LuGre without it); another value is a panic that names it.
    #[allow(dead_code)]
    pub fn from_args(args: &[String]) -> Self {
        flag_choice(
            args,
            "--contact",
            &[("lugre", Self::LuGre), ("maxwell", Self::Maxwell)],
        )
    }
}

/// How a dwell contact's junctions age and renew (`--dwell-law restart|aging` on a
/// benchmark's command line). The two differ in what renews the age: the first renews it
/// after any slip, the second only over the shape's renewal distance of slip.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum DwellLaw {
    /// The age is the time since the contact last slid faster than [`STICK_SPEED`] and the
    /// renewal distance acts only while it slides ([`Axis::clock`]; every suite until session
    /// 97). A slide of one sub-step renews it: 5e-5 m/s for 20 us is 1 nm of slip, against
    /// renewal distances of 20 um..2 mm. On the issue's axes, whose contacts creep under a
    /// closed loop, the age at a breakaway then hangs on slips no measurement resolves
    /// (session 97: `dwell_clock_probe trace 35270 8.9 9.4 --axes issue`, an age of 1.32 s
    /// and +118 N renewed in a 4 um creep under a rising force, the reading still at rest).
    RestartAtStick,
    /// Dieterich and Ruina's aging law, written from its textbook form: the age `theta` grows
    /// with time and is forgotten over the renewal distance `D` of slip,
    /// `d theta/dt = 1 - theta |slip| / D`, with no threshold; a nanometre of slip takes a
    /// nanometre's share of it. The benchmarks' law since session 100 (the age of the law
    /// above hangs on slips no measurement resolves, so its records could not show their
    /// effect to any method: session 99's never-run dwell misses all had a truth on the
    /// measured motion no better than the truth without the effect).
    #[default]
    Aging,
}

impl DwellLaw {
    /// `--dwell-law aging|restart` (aging without it, since session 100); another value is a
    /// panic that names it.
    #[allow(dead_code)]
    pub fn from_args(args: &[String]) -> Self {
        flag_choice(
            args,
            "--dwell-law",
            &[("aging", Self::Aging), ("restart", Self::RestartAtStick)],
        )
    }
}

/// Which axes a suite draws (`--axes wide|issue` on a benchmark's command line).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Axes {
    /// The wide ranges of [`Axis::random`] (every suite until session 66): force actuators
    /// and hydraulic cylinders, 20..500 kg, pre-sliding lengths of 1..200 um, damped and
    /// undamped bristles.
    #[default]
    Wide,
    /// The axes issue 9 describes its own check on ([`Axes::narrow`]): an ideal force
    /// actuator (a hydraulic cylinder where the effect needs chamber pressures), 100..400 kg,
    /// soft contacts (sigma0 5e6..5e7 N/m) with well-damped bristles (sigma1 0.2..1.0 of
    /// `sqrt(sigma0 M)`). Everything else as [`Axes::Wide`] draws it.
    Issue,
}

impl Axes {
    /// `--axes wide|issue` (wide without it); another value is a panic that names it.
    #[allow(dead_code)]
    pub fn from_args(args: &[String]) -> Self {
        flag_choice(
            args,
            "--axes",
            &[("wide", Self::Wide), ("issue", Self::Issue)],
        )
    }

    /// `axis` redrawn into these axes' ranges, from a generator of its own seeded by `seed`:
    /// [`Axes::Wide`] leaves it as drawn; [`Axes::Issue`] draws the actuator, the mass, the
    /// bristle stiffness and damping again (the levels, curve, effect, schedule and noise
    /// stay those of the seed's wide axis).
    pub fn narrow(self, mut axis: Axis, seed: u64) -> Axis {
        if self == Self::Wide {
            return axis;
        }
        let mut rng = Rng::new(seed.wrapping_mul(0xD6E8_FEB8_6659_FD93).wrapping_add(66));
        // load dependence lives in the chamber pressures: only a cylinder has them
        axis.actuator = if axis.effect == Some("load_dependence") {
            Actuator::Hydraulic
        } else {
            Actuator::Force
        };
        axis.mass_kg = rng.log_range(100.0, 400.0);
        axis.sigma0 = rng.log_range(5e6, 5e7);
        axis.sigma1 = rng.range(0.2, 1.0) * (axis.sigma0 * axis.mass_kg).sqrt();
        axis
    }
}

/// The contact's state: the LuGre bristle deflection [m], or per Maxwell element its force
/// [N] and slip direction (0: sticking).
#[derive(Clone, Debug, Default)]
pub struct ContactState {
    z: f64,
    elements: Vec<(f64, i8)>,
}

/// The sensors of a record: every suite so far ran with the default (1 um encoder, force
/// noise 0.2 % of full scale, pressure noise 0.05 bar); [`random_record_with`] changes them
/// without changing anything else the seed draws (axis, schedule, noise sequence), so a
/// record's variants differ only in what the sensors resolve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sensors {
    /// Encoder resolution [m].
    pub encoder_m: f64,
    /// Force sensor noise (ideal force actuator), rms, as a fraction of full scale.
    pub force_noise: f64,
    /// Pressure transducer noise (hydraulic axis), rms [Pa].
    pub pressure_noise_pa: f64,
    /// The logger keeps every `log_every`-th sample of the 1 kHz loop (2: a 500 Hz record),
    /// without an anti-alias filter, as a loop's logger samples its variables.
    pub log_every: usize,
}

impl Sensors {
    /// The sensors a benchmark's command line asks for: `--encoder-um R` (an R um count) and
    /// `--noise-x K` (force and pressure noise K times the default) and `--log-hz F` (a
    /// logger at F Hz, which must divide the loop's 1 kHz); the default without them. A flag
    /// without a positive number after it, or a rate that does not divide 1 kHz, is a panic
    /// that names it.
    #[allow(dead_code)]
    pub fn from_args(args: &[String]) -> Self {
        let value = |flag: &str| {
            let i = args.iter().position(|a| a == flag)?;
            Some(
                args.get(i + 1)
                    .and_then(|s| s.parse::<f64>().ok())
                    .filter(|v| v.is_finite() && *v > 0.0)
                    .unwrap_or_else(|| panic!("{flag} takes a positive number")),
            )
        };
        let mut s = Self::default();
        if let Some(um) = value("--encoder-um") {
            s.encoder_m = um * 1e-6;
        }
        if let Some(k) = value("--noise-x") {
            s.force_noise *= k;
            s.pressure_noise_pa *= k;
        }
        if let Some(hz) = value("--log-hz") {
            let every = (1.0 / (hz * DT)).round();
            assert!(
                every >= 1.0 && (every * hz * DT - 1.0).abs() < 1e-9,
                "--log-hz {hz}: the logger must keep every n-th sample of the 1 kHz loop"
            );
            s.log_every = every as usize;
        }
        s
    }

    /// The flags [`Self::from_args`] reads, each followed by its value.
    #[allow(dead_code)]
    pub const FLAGS: [&'static str; 3] = ["--encoder-um", "--noise-x", "--log-hz"];
}

impl Default for Sensors {
    fn default() -> Self {
        Self {
            encoder_m: 1e-6,
            force_noise: 0.002,
            pressure_noise_pa: 5e3,
            log_every: 1,
        }
    }
}

/// The true dwell clock of a record, one value per sample [s]. The truth along the measured
/// motion ([`Axis::friction_along`]) cannot run the clock itself: the clock restarts whenever
/// the contact slides faster than [`STICK_SPEED`], and a measured position moves by whole
/// 1 um encoder counts, each a sliding speed of ~1 mm/s over its sample that the resting
/// contact never had. Driven that way (until session 19) the truth kept almost none of its
/// dwell effect (rms 1.6 N of 132 N at the peaks of held-out record 20706) and the noise
/// floor of dwell records was the floor of a model without it.
#[derive(Clone)]
pub struct DwellTrace(pub std::sync::Arc<Vec<f64>>);

impl std::fmt::Debug for DwellTrace {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "DwellTrace({} samples)", self.0.len())
    }
}

impl Axis {
    /// A random axis with `effect` hidden (None: none), seeded.
    pub fn random(effect: Option<&'static str>, seed: u64) -> Self {
        let mut rng = Rng::new(seed.wrapping_mul(0x2545_F491_4F6C_DD1D).wrapping_add(17));
        let actuator = if effect == Some("load_dependence") || rng.uniform() < 0.5 {
            Actuator::Hydraulic
        } else {
            Actuator::Force
        };
        let mass_kg = match actuator {
            Actuator::Force => rng.log_range(20.0, 500.0),
            Actuator::Hydraulic => rng.log_range(100.0, 400.0),
        };
        let coulomb_n = rng.log_range(50.0, 800.0);
        let hump = if effect == Some("stribeck_shape") {
            rng.range(1.4, 2.0)
        } else {
            rng.range(1.1, 1.6)
        };
        let static_n = coulomb_n * hump;
        // pre-sliding length 1 um (stiff metal contact) .. 200 um (soft seal)
        let sigma0 = static_n / rng.log_range(1e-6, 200e-6);
        let critical = (sigma0 * mass_kg).sqrt();
        let sigma1 = if rng.uniform() < 0.5 {
            rng.range(0.2, 1.0) * critical
        } else {
            rng.range(0.0, 0.05) * critical
        };
        // viscous force at 0.1 m/s: 0.2..2 Fc
        let sigma2 = coulomb_n * rng.log_range(0.2, 2.0) / 0.1;
        let stribeck_m_per_s = rng.log_range(1e-3, 15e-3);
        let stroke_m = rng.range(0.2, 0.5);
        let temperature = match effect {
            Some("temperature_dependence") => Some((
                rng.range(25.0, 45.0),
                rng.range(10.0, 30.0),
                rng.range(8.0, 40.0),
            )),
            _ if rng.uniform() < 0.7 => Some((
                rng.range(25.0, 45.0),
                rng.range(0.0, 15.0),
                rng.range(8.0, 40.0),
            )),
            _ => None,
        };
        let shape = match effect {
            None => Shape::None,
            Some("asymmetry") => {
                let r = rng.range(0.1, 0.3) * if rng.uniform() < 0.5 { 1.0 } else { -1.0 };
                let rs = r * rng.range(0.6, 1.4);
                let rv = rng.range(-0.3, 0.3);
                Shape::Asymmetry {
                    coulomb: [1.0 + r, 1.0 - r],
                    static_: [1.0 + rs, 1.0 - rs],
                    viscous: [1.0 + rv, 1.0 - rv],
                }
            }
            Some("offset") => Shape::Offset {
                force_n: coulomb_n
                    * rng.range(0.1, 0.4)
                    * if rng.uniform() < 0.5 { 1.0 } else { -1.0 },
            },
            Some("load_dependence") => Shape::Load {
                strength: rng.range(0.4, 1.0),
                exponent: rng.range(0.7, 1.5),
                reference_pa: 200e5,
            },
            Some("position_dependence") => {
                let a = coulomb_n * rng.range(0.15, 0.4);
                let sign = if rng.uniform() < 0.5 { 1.0 } else { -1.0 };
                Shape::Position(match (rng.uniform() * 3.0) as u32 {
                    0 => PositionShape::Linear {
                        per_m: sign * a / (0.4 * stroke_m),
                        centre_m: rng.range(-0.1, 0.1) * stroke_m,
                    },
                    1 => PositionShape::Periodic {
                        amplitude_n: a,
                        wavelength_m: rng.range(0.25, 0.8) * stroke_m,
                        phase: rng.range(0.0, std::f64::consts::TAU),
                    },
                    _ => PositionShape::Bump {
                        amplitude_n: sign * a * 1.5,
                        centre_m: rng.range(-0.25, 0.25) * stroke_m,
                        width_m: rng.range(0.08, 0.2) * stroke_m,
                    },
                })
            }
            Some("temperature_dependence") => Shape::Temperature {
                andrade_k: rng.range(1500.0, 3000.0),
                coulomb_per_k: rng.range(-0.008, 0.008),
            },
            Some("stribeck_shape") => {
                let rational = rng.uniform() < 0.5;
                let exponent = if rational {
                    rng.range(1.0, 1.6)
                } else if rng.uniform() < 0.5 {
                    rng.range(0.6, 1.1)
                } else {
                    rng.range(3.5, 6.0)
                };
                Shape::Stribeck { rational, exponent }
            }
            Some("viscous_power") => Shape::ViscousPower {
                exponent: if rng.uniform() < 0.5 {
                    rng.range(0.35, 0.7)
                } else {
                    rng.range(1.4, 2.0)
                },
                reference_m_per_s: rng.range(0.02, 0.08),
            },
            Some("dwell_stiction") => Shape::Dwell {
                increase_n: static_n * rng.range(0.2, 0.6),
                tau_s: rng.log_range(0.1, 1.0),
                hill: rng.range(0.7, 1.5),
                renewal_m: rng.log_range(2e-5, 2e-3),
            },
            Some(other) => panic!("unknown effect {other}"),
        };
        let area_m2 = (6.0 * static_n).max(2000.0) / 100e5 * rng.range(1.0, 2.0);
        Self {
            effect,
            shape,
            actuator,
            mass_kg,
            coulomb_n,
            static_n,
            stribeck_m_per_s,
            sigma0,
            sigma1,
            sigma2,
            stroke_m,
            temperature,
            loop_hz: rng.range(8.0, 20.0),
            area_m2,
            area_ratio: rng.range(0.5, 0.9),
            duration_s: 60.0,
            dwell_trace: None,
            sensors: Sensors::default(),
            contact: Contact::LuGre,
            dwell_law: DwellLaw::RestartAtStick,
        }
    }

    /// The contact at rest, unloaded.
    /// The six LuGre parameters of the contact without any effect, as the core's validated set
    /// (the truth an identification or a fit is held against).
    #[allow(dead_code)]
    pub fn lugre_params(&self) -> lugre_servo::friction::LugreParams<f64> {
        lugre_servo::friction::LugreParams::new(
            self.sigma0,
            self.sigma1,
            self.sigma2,
            self.coulomb_n,
            self.static_n,
            self.stribeck_m_per_s,
        )
        .expect("the generator draws physical parameters")
    }

    pub fn contact_state(&self) -> ContactState {
        ContactState {
            z: 0.0,
            elements: match &self.contact {
                Contact::LuGre => Vec::new(),
                Contact::Maxwell(m) => vec![(0.0, 0); m.elements.len()],
            },
        }
    }

    /// Oil temperature at the record's start [degC] (the reference 40 degC without a sensor):
    /// where the temperature laws' levels hold.
    fn start_temperature(&self) -> f64 {
        self.temperature.map_or(40.0, |t| t.0)
    }

    /// Oil temperature at time t [degC] (the reference 40 degC without a sensor).
    fn temperature_at(&self, t: f64) -> f64 {
        self.temperature
            .map_or(40.0, |(t0, rise, tau)| t0 + rise * (1.0 - (-t / tau).exp()))
    }

    /// Friction terms at a state: (Stribeck curve g(v) > 0 [N], viscous force [N], extra force
    /// [N]). `dwell_s` is the time stuck before the current motion.
    fn terms(&self, v: f64, x: f64, p_sum: f64, temp: f64, dwell_s: f64) -> (f64, f64, f64) {
        let (mut fc, mut fs, mut s2) = (self.coulomb_n, self.static_n, self.sigma2);
        let dir = usize::from(v < 0.0);
        let mut visc = s2 * v;
        let mut extra = 0.0;
        // the Gaussian Stribeck curve at velocity scale vs, and at the axis's own
        let hump_at = |fc: f64, fs: f64, vs: f64| fc + (fs - fc) * (-(v / vs).powi(2)).exp();
        let hump = |fc: f64, fs: f64| hump_at(fc, fs, self.stribeck_m_per_s);
        let g = match self.shape {
            Shape::None => hump(fc, fs),
            Shape::Asymmetry {
                coulomb,
                static_,
                viscous,
            } => {
                visc = s2 * viscous[dir] * v;
                hump(fc * coulomb[dir], fs * static_[dir])
            }
            Shape::Offset { force_n } => {
                extra = force_n;
                hump(fc, fs)
            }
            Shape::Load {
                strength,
                exponent,
                reference_pa,
            } => {
                let k = 1.0 + strength * ((p_sum.max(1e5) / reference_pa).powf(exponent) - 1.0);
                hump(fc * k.max(0.05), fs * k.max(0.05))
            }
            Shape::Position(ps) => {
                let d = match ps {
                    PositionShape::Linear { per_m, centre_m } => per_m * (x - centre_m),
                    PositionShape::Periodic {
                        amplitude_n,
                        wavelength_m,
                        phase,
                    } => amplitude_n * (std::f64::consts::TAU * x / wavelength_m + phase).sin(),
                    PositionShape::Bump {
                        amplitude_n,
                        centre_m,
                        width_m,
                    } => amplitude_n * (-((x - centre_m) / width_m).powi(2)).exp(),
                    PositionShape::Step {
                        amplitude_n,
                        centre_m,
                        width_m,
                    } => amplitude_n * ((x - centre_m) / width_m).tanh(),
                    PositionShape::Pair {
                        amplitudes_n,
                        centres_m,
                        width_m,
                    } => amplitudes_n
                        .iter()
                        .zip(centres_m)
                        .map(|(a, c)| a * (-((x - c) / width_m).powi(2)).exp())
                        .sum(),
                };
                let d = d.max(-0.9 * fc);
                hump(fc + d, fs + d)
            }
            Shape::Temperature {
                andrade_k,
                coulomb_per_k,
            } => {
                let t0 = self.start_temperature();
                s2 *= (andrade_k * (1.0 / (temp + 273.15) - 1.0 / (t0 + 273.15))).exp();
                visc = s2 * v;
                let k = (1.0 + coulomb_per_k * (temp - t0)).max(0.1);
                fc *= k;
                fs *= k;
                hump(fc, fs)
            }
            Shape::Stribeck { rational, exponent } => {
                let r = (v / self.stribeck_m_per_s).abs().powf(exponent);
                fc + (fs - fc)
                    * if rational {
                        1.0 / (1.0 + r)
                    } else {
                        (-r).exp()
                    }
            }
            Shape::ViscousPower {
                exponent,
                reference_m_per_s,
            } => {
                visc = s2
                    * reference_m_per_s
                    * v.signum()
                    * (v / reference_m_per_s).abs().powf(exponent);
                hump(fc, fs)
            }
            Shape::Dwell {
                increase_n,
                tau_s,
                hill,
                ..
            } => {
                let t = dwell_s.max(0.0).powf(hill);
                hump(fc, fs + increase_n * t / (t + tau_s.powf(hill)))
            }
            Shape::AsymmetryB {
                coulomb,
                static_,
                viscous,
                stribeck,
            } => {
                visc = s2 * viscous[dir] * v;
                hump_at(
                    fc * coulomb[dir],
                    fs * static_[dir],
                    self.stribeck_m_per_s * stribeck[dir],
                )
            }
            Shape::LoadB {
                strength,
                mid_pa,
                width_pa,
                static_share,
            } => {
                let change = strength * ((p_sum - mid_pa) / width_pa).tanh();
                hump(fc * (1.0 + change), fs * (1.0 + static_share * change))
            }
            Shape::TemperatureB {
                vogel_b_k,
                vogel_tv_c,
                levels_per_k,
            } => {
                let t0 = self.start_temperature();
                let eta = (vogel_b_k / (temp - vogel_tv_c) - vogel_b_k / (t0 - vogel_tv_c)).exp();
                visc = s2 * eta * v;
                let k = (-levels_per_k * (temp - t0)).exp();
                // (not `hump_at`: kept as first run, bit for bit, for the registered records)
                let vs = self.stribeck_m_per_s / eta.sqrt();
                fc * k + (fs - fc) * k * (-(v / vs).powi(2)).exp()
            }
            Shape::StribeckB { share, scale } => {
                let vs = self.stribeck_m_per_s;
                fc + (fs - fc)
                    * (share * (-(v / vs).powi(2)).exp()
                        + (1.0 - share) * (-v.abs() / (scale * vs)).exp())
            }
            Shape::ViscousB {
                quadratic,
                velocity_m_per_s,
            } => {
                visc = if quadratic {
                    s2 * v * (1.0 + v.abs() / velocity_m_per_s)
                } else {
                    s2 * velocity_m_per_s * (v / velocity_m_per_s).tanh()
                };
                hump(fc, fs)
            }
            Shape::DwellLog {
                per_e_fold_n, t0_s, ..
            } => hump(fc, fs + per_e_fold_n * (dwell_s.max(0.0) / t0_s).ln_1p()),
        };
        (g.max(1e-6), visc, extra)
    }

    /// One friction sub-step of length h at velocity v: advances the contact (the LuGre
    /// bristle by implicit Euler, stable for any stiffness; a slipping Maxwell element's lag
    /// likewise) and returns the friction force and the sliding speed, the part of v that is
    /// not elastic deflection (LuGre: `|v - dz/dt| = sigma0 |v| |z| / g`; Maxwell: `|v|` times
    /// the share of elements slipping) [m/s].
    fn friction_step(
        &self,
        st: &mut ContactState,
        v: f64,
        x: f64,
        p_sum: f64,
        temp: f64,
        dwell: f64,
        h: f64,
    ) -> (f64, f64) {
        let (g, visc, extra) = self.terms(v, x, p_sum, temp, dwell);
        match &self.contact {
            Contact::LuGre => {
                let rate = self.sigma0 * v.abs() / g;
                st.z = (st.z + h * v) / (1.0 + h * rate);
                let zdot = v - rate * st.z;
                (
                    self.sigma0 * st.z + self.sigma1 * zdot + visc + extra,
                    (rate * st.z).abs(),
                )
            }
            Contact::Maxwell(m) => {
                let dir: i8 = if v > 0.0 {
                    1
                } else if v < 0.0 {
                    -1
                } else {
                    0
                };
                let (mut elastic, mut slipping) = (0.0, 0.0);
                for (&(k, share), (f, mode)) in m.elements.iter().zip(st.elements.iter_mut()) {
                    // a reversal or a stop ends a slip
                    if *mode != dir {
                        *mode = 0;
                    }
                    let cap = share * g;
                    if *mode == 0 {
                        *f += k * v * h;
                        if dir != 0 && *f * f64::from(dir) >= cap {
                            *mode = dir;
                        }
                    }
                    if *mode != 0 {
                        let target = f64::from(*mode) * cap;
                        let ch = h * m.lag_rate_per_s;
                        *f = (*f + ch * target) / (1.0 + ch);
                        slipping += share;
                    }
                    elastic += *f;
                }
                (
                    elastic + self.sigma1 * v * (1.0 - slipping) + visc + extra,
                    v.abs() * slipping,
                )
            }
        }
    }

    /// At rest the contact carries the applied elastic force `target`, up to the static levels
    /// `g_fw` forwards and `g_bw` backwards [N]; returns the change of its elastic force [N].
    fn hold(&self, st: &mut ContactState, target: f64, g_fw: f64, g_bw: f64) -> f64 {
        match &self.contact {
            Contact::LuGre => {
                let zn = (target / self.sigma0).clamp(-g_bw / self.sigma0, g_fw / self.sigma0);
                let change = self.sigma0 * (zn - st.z);
                st.z = zn;
                change
            }
            Contact::Maxwell(m) => {
                // the body moved by a shift d under one count that brings the elements, each
                // loaded from where it was up to its share of the static level, to the force
                // at rest: each element keeps its memory (a bisection on d, monotone)
                let held = target.clamp(-g_bw, g_fw);
                let before: f64 = st.elements.iter().map(|e| e.0).sum();
                let loaded = |d: f64| {
                    m.elements
                        .iter()
                        .zip(&st.elements)
                        .map(|(&(k, share), &(f, _))| {
                            (f + k * d).clamp(-share * g_bw, share * g_fw)
                        })
                        .sum::<f64>()
                };
                let softest = m.elements.iter().map(|e| e.0).fold(f64::INFINITY, f64::min);
                let reach = 2.0 * (g_fw + g_bw) / softest;
                let (mut lo, mut hi) = (-reach, reach);
                for _ in 0..100 {
                    let mid = 0.5 * (lo + hi);
                    if loaded(mid) < held {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                let d = 0.5 * (lo + hi);
                for (&(k, share), e) in m.elements.iter().zip(st.elements.iter_mut()) {
                    *e = ((e.0 + k * d).clamp(-share * g_bw, share * g_fw), 0);
                }
                st.elements.iter().map(|e| e.0).sum::<f64>() - before
            }
        }
    }

    /// The dwell clock: time stuck so far while stuck. Stuck means the contact does not slide
    /// (`slip`, the sliding speed of the last sub-step, under [`STICK_SPEED`]): the junctions
    /// age while the bristles only deflect. Once it slides, the aged time is forgotten over
    /// the shape's renewal distance. (Until session 8 the clock ran on the body's speed and
    /// froze through the whole next move: on soft contacts under a closed loop it restarted at
    /// every elastic creep and reached 0.0..0.5 s during rests of 1..3 s, so most
    /// `dwell_stiction` records held a few newtons of their effect at the departures.)
    /// Under [`DwellLaw::Aging`] the age follows the aging law instead (implicit Euler, stable
    /// for any slip).
    fn clock(&self, slip: f64, h: f64, stuck: &mut f64, dwell: &mut f64) {
        self.clock_at(slip, STICK_SPEED, h, stuck, dwell);
    }

    /// [`Self::clock`] with a stick under `stick_speed` [m/s] in place of [`STICK_SPEED`]
    /// (the aging law has no threshold): the dwell studies run the generator's own law on
    /// clocks read off a record.
    #[allow(dead_code)]
    pub fn clock_at(&self, slip: f64, stick_speed: f64, h: f64, stuck: &mut f64, dwell: &mut f64) {
        if self.dwell_law == DwellLaw::Aging {
            if let Shape::Dwell { renewal_m, .. } | Shape::DwellLog { renewal_m, .. } = self.shape {
                *dwell = (*dwell + h) / (1.0 + h * slip / renewal_m);
                return;
            }
        }
        if slip < stick_speed {
            *stuck += h;
            *dwell = *stuck;
        } else {
            *stuck = 0.0;
            if let Shape::Dwell { renewal_m, .. } | Shape::DwellLog { renewal_m, .. } = self.shape {
                *dwell *= (-slip * h / renewal_m).exp();
            }
        }
    }

    /// The true friction along a given motion (for the noise floor: the true model driven by
    /// the measured motion): per sample the mean velocity `v_step[i]` over the interval ending
    /// at sample i, restarted at each segment's first sample. The dwell clock is the record's
    /// own ([`Axis::dwell_trace`]) where it is known. `held`: where the first is true the reading
    /// is at rest, and the bristle carries the second (the force less `M a` \[N\]) up to the
    /// static level in each direction, as the diagnosis's model does (so the floor is the
    /// truth given the same information).
    pub fn friction_along(
        &self,
        t: &[f64],
        x: &[f64],
        v_step: &[f64],
        p_sum: Option<&[f64]>,
        temp: Option<&[f64]>,
        segments: &[std::ops::Range<usize>],
        dt: f64,
        held: Option<(&[bool], &[f64])>,
    ) -> Vec<f64> {
        let mut out = vec![0.0; x.len()];
        let h = dt / SUB as f64;
        for r in segments {
            let mut st = self.contact_state();
            let (mut stuck, mut dwell, mut slip) = (0.0, 0.0, 0.0);
            for i in r.clone() {
                let v = v_step[i];
                let ps = p_sum.map_or(200e5, |p| p[i]);
                let tc = temp.map_or(self.temperature_at(t[i]), |q| q[i]);
                let mut f = 0.0;
                // the record's own clock where it is known (samples line up with the record's
                // rows: the generator's records are uniform and gap-free)
                let true_age = self.dwell_trace.as_ref().and_then(|d| d.0.get(i).copied());
                for k in 0..SUB {
                    let xi = x[i] - v * (dt - (k as f64 + 1.0) * h);
                    match true_age {
                        Some(age) => dwell = age,
                        None => self.clock(slip, h, &mut stuck, &mut dwell),
                    }
                    (f, slip) = self.friction_step(&mut st, v, xi, ps, tc, dwell, h);
                }
                if let Some((_, force)) = held.filter(|(rest, _)| rest[i]) {
                    // at rest the contact carries what is applied, up to its static level in
                    // each direction (the diagnosis's model is treated alike)
                    let (g_fw, _, extra) = self.terms(1e-12, x[i], ps, tc, dwell);
                    let (g_bw, _, _) = self.terms(-1e-12, x[i], ps, tc, dwell);
                    f += self.hold(&mut st, force[i] - extra, g_fw, g_bw);
                }
                out[i] = f;
            }
        }
        out
    }
}

/// The friction the record measures with this axis's mass: the force in the motion's band
/// less `M a` (at rest, the holding force) \[N\].
pub fn measured_friction(axis: &Axis, p: &host_sim::diagnose::inverse::Prepared) -> Vec<f64> {
    p.force_motion_band
        .iter()
        .zip(&p.a)
        .map(|(f, a)| f - axis.mass_kg * a)
        .collect()
}

/// The force of this axis's true model driven by the measured motion (`M a + friction` along
/// the prepared record, unfiltered) \[N\]. The physics stays the generator's own; only the
/// measured motion is the pipeline's.
pub fn truth_force(axis: &Axis, p: &host_sim::diagnose::inverse::Prepared) -> Vec<f64> {
    let held = measured_friction(axis, p);
    let friction = axis.friction_along(
        &p.t,
        &p.x,
        &p.v_step,
        p.pressure_sum.as_deref(),
        p.temperature.as_deref(),
        &p.segments,
        p.dt,
        Some((&p.inside_rest[..], &held[..])),
    );
    p.a.iter()
        .zip(&friction)
        .map(|(a, f)| axis.mass_kg * a + f)
        .collect()
}

/// The error [%] of [`truth_force`], scored like any model: the noise floor.
pub fn truth_error_pct(axis: &Axis, p: &host_sim::diagnose::inverse::Prepared) -> f64 {
    p.rel_err_pct(&truth_force(axis, p))
}

/// `--force-skew S` among `args`: the force read `S` samples later than logged
/// (`Protocol::force_skew_samples`; without it 0, as logged); a value that is not a number is
/// a panic that says what is expected.
#[allow(dead_code)]
pub fn force_skew_from_args(args: &[String]) -> f64 {
    args.iter()
        .position(|a| a == "--force-skew")
        .map_or(0.0, |i| {
            args.get(i + 1)
                .and_then(|s| s.parse().ok())
                .expect("--force-skew SAMPLES (e.g. 0.5)")
        })
}

/// Reference position at 1 kHz \[m\]: the random schedule of moves, sinusoids and dwells.
fn schedule(axis: &Axis, rng: &mut Rng) -> Vec<f64> {
    let n = (axis.duration_s / DT) as usize;
    let half = 0.45 * axis.stroke_m;
    let mut xr: Vec<f64> = Vec::with_capacity(n + 8000);
    let mut x = 0.0;
    let push_move = |xr: &mut Vec<f64>, from: f64, to: f64, speed: f64, accel: f64| {
        let d = (to - from).abs();
        let s = (to - from).signum();
        let (ta, vp) = if speed * speed / accel > d {
            ((d / accel).sqrt(), (d * accel).sqrt())
        } else {
            (speed / accel, speed)
        };
        let tc = (d - vp * ta) / vp;
        let total = 2.0 * ta + tc.max(0.0);
        let steps = (total / DT).ceil() as usize;
        for k in 1..=steps {
            let t = (k as f64 * DT).min(total);
            let p = if t < ta {
                0.5 * accel * t * t
            } else if t < ta + tc {
                0.5 * accel * ta * ta + vp * (t - ta)
            } else {
                let u = total - t;
                d - 0.5 * accel * u * u
            };
            xr.push(from + s * p);
        }
    };
    while xr.len() < n {
        if rng.uniform() < 0.6 {
            // a move, then a dwell
            let mut to = rng.range(-half, half);
            if (to - x).abs() < 2e-3 {
                to = if x > 0.0 { x - 5e-3 } else { x + 5e-3 };
            }
            let speed = rng.log_range(1e-3, 0.12);
            let accel = rng.log_range(0.2, 3.0);
            // at most MAX_BURST_S of travel
            let reach = (speed * MAX_BURST_S).max(2e-3);
            let to = x + (to - x).clamp(-reach, reach);
            push_move(&mut xr, x, to, speed, accel);
            x = to;
        } else {
            // a sinusoid with reversals, its amplitude rising and falling over one period
            let speed = rng.log_range(2e-3, 0.12);
            let mut amp = rng.log_range(1e-3, 20e-3).min(half * 0.5);
            // two periods at least, within MAX_BURST_S (the speed kept, the amplitude cut)
            amp = amp.min(speed * MAX_BURST_S / (2.0 * std::f64::consts::TAU));
            let omega = speed / amp;
            let period = std::f64::consts::TAU / omega;
            let cycles = rng
                .range(2.0, 6.0)
                .round()
                .min((MAX_BURST_S / period).floor())
                .max(2.0);
            let centre = x.clamp(-half + amp, half - amp);
            if (centre - x).abs() > 1e-9 {
                push_move(&mut xr, x, centre, 0.05, 1.0);
            }
            let total = cycles * period;
            let steps = (total / DT) as usize;
            for k in 1..=steps {
                let t = k as f64 * DT;
                let w = if t < period {
                    0.5 * (1.0 - (std::f64::consts::PI * t / period).cos())
                } else if t > total - period {
                    0.5 * (1.0 - (std::f64::consts::PI * (total - t) / period).cos())
                } else {
                    1.0
                };
                xr.push(centre + amp * w * (omega * t).sin());
            }
            x = centre;
            xr.push(x);
        }
        let dwell = (rng.log_range(0.05, 3.0) / DT) as usize;
        xr.extend(std::iter::repeat_n(x, dwell));
    }
    xr.truncate(n);
    xr
}

/// Signed square root, regularised below 1 bar (laminar flow at small pressure drops).
fn sqrt_flow(dp: f64) -> f64 {
    dp / (dp * dp + 1e10).sqrt().sqrt()
}

/// Simulates the axis and returns the record as CSV text (t, x, force, x_ref, and p_a, p_b
/// for the hydraulic axis, temp when it has a thermometer) and the hidden effect's visibility:
/// along the true motion, where the axis moves (|v| >= 0.2 mm/s), the rms of the effect's force
/// (friction with it minus friction without it) after removing what a Coulomb and a viscous
/// level could absorb (least squares on sign(v) and v), over the rms of the measured force.
pub fn record(axis: &Axis, seed: u64) -> (String, f64) {
    let (text, visibility, _) = record_traced(axis, seed);
    (text, visibility)
}

/// [`record`] and the record's dwell clock, one value per row [s].
fn record_traced(axis: &Axis, seed: u64) -> (String, f64, Vec<f64>) {
    let mut rng = Rng::new(seed);
    let xr = schedule(axis, &mut rng);
    simulate(axis, &mut rng, &xr)
}

/// The axis run along a reference position `xr` (one value per sample) \[m\] of the caller's
/// design, as [`record`] runs it along its random schedule: the CSV text and the hidden
/// effect's visibility.
#[allow(dead_code)]
pub fn record_along(axis: &Axis, seed: u64, xr: &[f64]) -> (String, f64) {
    let mut rng = Rng::new(seed);
    let (text, visibility, _) = simulate(axis, &mut rng, xr);
    (text, visibility)
}

/// Reference velocity and acceleration of a reference position, by central differences.
fn derivatives(xr: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let n = xr.len();
    let mut vr = vec![0.0; n];
    let mut ar = vec![0.0; n];
    for i in 1..n.saturating_sub(1) {
        vr[i] = (xr[i + 1] - xr[i - 1]) / (2.0 * DT);
    }
    for i in 1..n.saturating_sub(1) {
        ar[i] = (vr[i + 1] - vr[i - 1]) / (2.0 * DT);
    }
    (vr, ar)
}

/// The axis run along the reference position `xr`, its velocity and acceleration
/// feed-forward from central differences.
fn simulate(axis: &Axis, rng: &mut Rng, xr: &[f64]) -> (String, f64, Vec<f64>) {
    let n = xr.len();
    let (vr, ar) = derivatives(xr);
    let h = DT / SUB as f64;
    let m = axis.mass_kg;
    let omega = std::f64::consts::TAU * axis.loop_hz;
    // force actuator: PID; full scale for the 0.2 % noise
    let (kp, kd, ki) = (
        m * omega * omega,
        1.4 * m * omega,
        m * omega * omega * omega / 10.0,
    );
    let full_scale = 2.0 * axis.static_n + m * 3.0;
    // hydraulic: areas, valve sized for 0.25 m/s, 0.2 L dead volumes
    let (aa, ab) = (axis.area_m2, axis.area_m2 * axis.area_ratio);
    let beta = 1.4e9;
    // dead volume: 5 cm of bore on each side
    let v0 = 0.05 * aa;
    let q_max = aa * 0.25;
    // loop gain [1/s]: a quarter of the hydraulic natural frequency at mid stroke, at most 40
    let omega_h = (beta * aa / ((0.05 + 0.5 * axis.stroke_m) * m)).sqrt();
    let k_loop = (0.25 * omega_h).min(40.0);
    let kv = q_max / (50e5f64).sqrt();
    let leak = 2e-13;
    let mut supply = 160e5;
    let mut next_supply_change = rng.range(8.0, 20.0);
    // the chambers balanced at rest: pa aa = pb ab
    let mut pb = 0.5 * supply;
    let mut pa = pb * ab / aa;
    let mut spool = 0.0;
    let (mut x, mut v) = (0.0f64, 0.0f64);
    let mut contact = axis.contact_state();
    let (mut stuck, mut dwell, mut slip) = (0.0, 0.0, 0.0);
    let mut integral = 0.0;
    let mut x_prev_meas = 0.0;
    let mut v_est = 0.0;
    let mut out = String::with_capacity(n * 60);
    let mut trace = Vec::with_capacity(n);
    let hyd = axis.actuator == Actuator::Hydraulic;
    let temp_col = axis.temperature.is_some();
    out.push_str(&format!(
        "# generator=independent servo axis ({})\n# hidden={}\n",
        if hyd {
            "hydraulic cylinder"
        } else {
            "ideal force actuator"
        },
        axis.effect.unwrap_or("none")
    ));
    if let Contact::Maxwell(m) = &axis.contact {
        out.push_str(&format!(
            "# contact=generalized Maxwell-slip, {} elements, lag {:.0} 1/s\n",
            m.elements.len(),
            m.lag_rate_per_s
        ));
    }
    out.push_str("t,x,force,x_ref");
    if hyd {
        out.push_str(",p_a,p_b");
    }
    if temp_col {
        out.push_str(",temp");
    }
    let dbg = std::env::var("AXIS_DEBUG").is_ok();
    if dbg {
        out.push_str(",effect_dbg,dwell_dbg");
    }
    out.push('\n');
    let mut force_cmd = 0.0;
    let mut u_cmd = 0.0;
    let plain = Axis {
        shape: Shape::None,
        ..axis.clone()
    };
    let (mut contact_plain, mut effect_force) = (plain.contact_state(), 0.0);
    // (sign v, v, effect force, measured force) where the axis moves
    let mut seen: Vec<[f64; 4]> = Vec::with_capacity(n);
    for i in 0..n {
        let t = i as f64 * DT;
        // sample the sensors
        let enc = axis.sensors.encoder_m;
        let xq = (x / enc).round() * enc;
        let p_noise = axis.sensors.pressure_noise_pa;
        let (pa_m, pb_m) = (pa + p_noise * rng.normal(), pb + p_noise * rng.normal());
        let f_meas = if hyd {
            aa * pa_m - ab * pb_m
        } else {
            force_cmd + axis.sensors.force_noise * full_scale * rng.normal()
        };
        let temp = axis.temperature_at(t);
        // the noise is drawn at every loop sample whatever the logger keeps, so a record's
        // variants share their noise sequence; only a kept sample is written
        let temp_meas = temp_col.then(|| temp + 0.05 * rng.normal());
        if i % axis.sensors.log_every.max(1) == 0 {
            let mut line = format!("{t:.3},{xq:.7},{f_meas:.4},{:.7}", xr[i]);
            if hyd {
                line.push_str(&format!(",{pa_m:.1},{pb_m:.1}"));
            }
            if let Some(tm) = temp_meas {
                line.push_str(&format!(",{tm:.3}"));
            }
            if dbg {
                line.push_str(&format!(",{effect_force:.2},{dwell:.3}"));
            }
            line.push('\n');
            out.push_str(&line);
            trace.push(dwell);
        }
        if v.abs() >= 2e-4 {
            seen.push([v.signum(), v, effect_force, f_meas]);
        }
        // the controller, from the measurements
        let e = xr[i] - xq;
        v_est += 0.3 * ((xq - x_prev_meas) / DT - v_est);
        x_prev_meas = xq;
        if hyd {
            let v_full = q_max / aa;
            u_cmd = ((vr[i] + k_loop * e) / v_full).clamp(-1.0, 1.0);
        } else {
            integral = (integral + e * DT).clamp(-1e3, 1e3);
            force_cmd = m * ar[i] + kp * e + kd * (vr[i] - v_est) + ki * integral;
        }
        if hyd && t >= next_supply_change {
            supply = rng.range(100e5, 210e5);
            next_supply_change += rng.range(8.0, 20.0);
        }
        // the plant, in sub-steps
        for _ in 0..SUB {
            let actuator = if hyd {
                spool += h / 3e-3 * (u_cmd - spool);
                let (qa, qb) = if spool >= 0.0 {
                    (
                        kv * spool * sqrt_flow(supply - pa),
                        -kv * spool * sqrt_flow(pb),
                    )
                } else {
                    (
                        kv * spool * sqrt_flow(pa),
                        -kv * spool * sqrt_flow(supply - pb),
                    )
                };
                let ql = leak * (pa - pb);
                let va = v0 + aa * (x + 0.5 * axis.stroke_m);
                let vb = v0 + ab * (0.5 * axis.stroke_m - x);
                pa = (pa + h * beta / va * (qa - aa * v - ql)).clamp(1e4, 400e5);
                pb = (pb + h * beta / vb * (qb + ab * v + ql)).clamp(1e4, 400e5);
                aa * pa - ab * pb
            } else {
                force_cmd
            };
            axis.clock(slip, h, &mut stuck, &mut dwell);
            let friction;
            (friction, slip) = axis.friction_step(&mut contact, v, x, pa + pb, temp, dwell, h);
            effect_force = friction
                - plain
                    .friction_step(&mut contact_plain, v, x, pa + pb, temp, dwell, h)
                    .0;
            v += h * (actuator - friction) / m;
            x += h * v;
        }
    }
    (out, visibility(&seen), trace)
}

/// The part of the effect's force that sign(v) and v cannot absorb, rms, over the force rms.
fn visibility(seen: &[[f64; 4]]) -> f64 {
    let (mut a11, mut a12, mut a22, mut b1, mut b2, mut ff) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for [s, v, d, f] in seen {
        a11 += s * s;
        a12 += s * v;
        a22 += v * v;
        b1 += s * d;
        b2 += v * d;
        ff += f * f;
    }
    let det = a11 * a22 - a12 * a12;
    let (c1, c2) = if det.abs() > 1e-300 {
        ((a22 * b1 - a12 * b2) / det, (a11 * b2 - a12 * b1) / det)
    } else {
        (0.0, 0.0)
    };
    let rr: f64 = seen
        .iter()
        .map(|[s, v, d, _]| (d - c1 * s - c2 * v).powi(2))
        .sum();
    (rr / ff.max(1e-300)).sqrt()
}

/// Smallest visibility of a hidden effect (see [`record`]): a drawn effect that leaves less
/// than this in the force where the axis moves is drawn again (up to 20 times), because no
/// method can find an effect the record does not show.
pub const MIN_VISIBILITY: f64 = 0.03;

/// A record (CSV text) and its axis for `effect` (None: effect-free), seeded. An effect whose
/// visibility is below [`MIN_VISIBILITY`] is drawn again (new axis, new excitation).
pub fn random_record(effect: Option<&'static str>, seed: u64) -> (String, Axis) {
    random_record_with(effect, seed, Sensors::default())
}

/// [`random_record`] with other sensors: the same axis, schedule and noise sequence, measured
/// through `sensors` (the effect's visibility, and so the redraws, is judged on what they
/// measure).
pub fn random_record_with(
    effect: Option<&'static str>,
    seed: u64,
    sensors: Sensors,
) -> (String, Axis) {
    random_record_on(effect, seed, sensors, ContactKind::LuGre)
}

/// [`random_record_with`] on another contact: the same axis, effect, schedule and noise
/// sequence, with the friction of `contact` underneath ([`Maxwell::random`] draws its elements
/// from a generator of their own).
pub fn random_record_on(
    effect: Option<&'static str>,
    seed: u64,
    sensors: Sensors,
    contact: ContactKind,
) -> (String, Axis) {
    random_record_of(
        effect,
        seed,
        sensors,
        contact,
        Family::A,
        Axes::Wide,
        DwellLaw::RestartAtStick,
    )
}

/// A family-A record through the default sensors on a LuGre contact, on the axes `axes` draws
/// ([`random_record_of`] with every other choice at its default).
pub fn record_on_axes(effect: Option<&'static str>, seed: u64, axes: Axes) -> (String, Axis) {
    random_record_of(
        effect,
        seed,
        Sensors::default(),
        ContactKind::LuGre,
        Family::A,
        axes,
        DwellLaw::RestartAtStick,
    )
}

/// A family-A dwell-stiction record through the default sensors on a LuGre contact, on the axes
/// `axes` draws, its contact aged by `law` (the dwell studies' and tests' record).
pub fn dwell_record(seed: u64, axes: Axes, law: DwellLaw) -> (String, Axis) {
    random_record_of(
        Some("dwell_stiction"),
        seed,
        Sensors::default(),
        ContactKind::LuGre,
        Family::A,
        axes,
        law,
    )
}

/// [`random_record_on`] with the hidden effect's shape drawn from `family` ([`Family::B`]:
/// [`Shape::random_b`]; an effect-free record is the same in both), on the axes `axes` draws
/// ([`Axes::narrow`]).
pub fn random_record_of(
    effect: Option<&'static str>,
    seed: u64,
    sensors: Sensors,
    contact: ContactKind,
    family: Family,
    axes: Axes,
    law: DwellLaw,
) -> (String, Axis) {
    let mut last = None;
    for attempt in 0..20u64 {
        let s = seed.wrapping_add(attempt.wrapping_mul(1_000_003));
        let mut axis = Axis {
            sensors,
            dwell_law: law,
            ..axes.narrow(Axis::random(effect, s), s)
        };
        if let (Family::B, Some(e)) = (family, effect) {
            axis.shape = Shape::random_b(e, &axis, s);
        }
        if contact == ContactKind::Maxwell {
            axis.contact = Contact::Maxwell(Maxwell::random(&axis, s));
        }
        let (text, vis, trace) = record_traced(&axis, s.wrapping_mul(7919).wrapping_add(3));
        axis.dwell_trace = Some(DwellTrace(std::sync::Arc::new(trace)));
        if effect.is_none() || vis >= MIN_VISIBILITY {
            return (text, axis);
        }
        last = Some((text, axis));
    }
    last.expect("at least one attempt")
}
