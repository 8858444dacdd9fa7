//! Extra physical effects a friction model can carry beyond plain LuGre.
//!
//! The simulator switches them on to make a plant, the diagnosis fits them to measurements, and
//! the compensator runs the ones it can afford at 1 kHz: all three use this code. Every effect
//! is off (`None`) by default. Each modifies the Coulomb level `Fc`, the static level `Fs`, the
//! viscous law or adds a force, as its equation says:
//!
//! | effect | equation |
//! | --- | --- |
//! | `asymmetry` | `Fc -> (1 ± rc) Fc`, `Fs -> (1 ± rs) Fs`, `sigma2 -> (1 ± rv) sigma2`, `vs -> (1 ± rvs) vs`, `+` for v >= 0 |
//! | `offset` | `F += F0` (constant external force, e.g. gravity on an inclined axis) |
//! | `load_dependence` | `Fc -> L Fc`, `Fs - Fc -> (1 + beta (L - 1)) (Fs - Fc)`, `L = 1 + dF(p) / Fs`, `dF = k p_ref ((p / p_ref)^gamma - 1) / gamma + sum c_j cos(j pi u(p))`, `p = p_a + p_b` (the seal's normal force: preload + pressure-energised; `k (p - p_ref)` at `gamma = 1`; the cosine series over the pressure sums a smooth response the data picks) |
//! | `position_dependence` | `Fc, Fs += k_x (x - x_c) + sum_j c_j cos(j pi u)`, `u = (x - x_c) / 2L + 1/2` in [0, 1] (friction varying along the stroke) |
//! | `temperature_dependence` | `sigma2 -> sigma2 eta`, `eta = exp(-k_v (T - T_ref))`, `Fc, Fs -> (1 + k_c (T - T_ref)) Fc, Fs`, `vs -> vs eta^-q` (the Stribeck curve a function of the Hersey number `eta v`) |
//! | `stribeck_shape` | `g(v) = Fc + (Fs - Fc) exp(-|v / vs|^delta)` with `delta != 2` |
//! | `viscous_power` | `F_visc = sigma2 v_r sign(v) |v / v_r|^delta` (equals `sigma2 v` at `v = v_r`) |
//! | `dwell_stiction` | `Fs += dF w(t_dwell)`, `w = 1 - exp(-t_dwell / tau)` or `t_dwell / (t_dwell + tau)` ([`DwellGrowth`]), `t_dwell` = time stuck (carried on from the last slide or restarted at each stick: [`DwellAge`]; stuck: the body's speed or the contact's slip under a threshold, [`DwellClock`]), forgotten as `exp(-s / D)` over the slid distance `s` |

use num_traits::Float;

/// Direction-dependent friction levels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Asymmetry<T> {
    /// `rc`: relative Coulomb level change, `+rc` moving in +x, `-rc` in -x [-].
    pub coulomb_ratio: T,
    /// `rs`: relative static (breakaway) level change, `+rs` moving in +x, `-rs` in -x [-].
    /// A seal's lip can hold differently from how it slides in each direction; `rs = rc`
    /// scales the whole Stribeck curve.
    pub static_ratio: T,
    /// `rv`: relative viscous change, `+rv` moving in +x, `-rv` in -x [-].
    pub viscous_ratio: T,
    /// `rvs`: relative Stribeck velocity change, `vs (1 + rvs)` moving in +x, `vs (1 - rvs)` in
    /// -x [-]: a seal's lip or a lubricating film can lift at another speed in each direction
    /// (0: the same both ways). The factor is held at 0.05 or more, so `vs` stays positive.
    pub stribeck_velocity_ratio: T,
}

/// A constant external force.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Offset<T> {
    /// `F0` \[N\], resisting +x motion when positive.
    pub force: T,
}

/// Most cosine terms a load dependence carries: the seal's response to pressure is smooth
/// (a lip that saturates, a seal energised above some pressure), four half-waves over the
/// record's pressure range follow it.
pub const LOAD_TERMS: usize = 4;

/// Seal friction that grows with chamber pressure: the pressure adds to the seal's normal
/// force, so the levels scale with it, `Fc -> L Fc` and the Stribeck hump `Fs - Fc -> (1 +
/// beta (L - 1)) (Fs - Fc)` with `L = 1 + dF(p) / Fs` (`beta = 1`: both levels in proportion,
/// `Fs -> L Fs`; a seal whose breakaway grows less or more than its sliding friction has
/// another share), with the static level's change a power of the pressure sum `p` plus a
/// smooth shape:
///
/// ```text
/// dF(p) = k p_ref ((p / p_ref)^gamma - 1) / gamma + sum_{j=1..n} c_j cos(j pi u),
///   u = clamp((p - p_ref) / (2 L) + 1/2, 0, 1)
/// ```
///
/// `k` is the static level's slope at the reference, whatever `gamma`; `gamma = 1` is the straight line
/// `k (p - p_ref)`, `gamma < 1` a seal whose lip saturates as it is pressed, `gamma > 1` one that
/// is energised progressively. The cosine series over the pressure sums `p_ref - L .. p_ref + L`
/// represents any smooth response there (a seal energised only above some pressure, one that
/// saturates), as [`PositionDependence`]'s does along the stroke; `n = 0` is the power law
/// alone. A pressure sum below zero counts as zero; a non-positive `p_ref` or `gamma` falls
/// back to the straight line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoadDependence<T> {
    /// `k` [N/Pa]: the static level's slope at the reference pressure sum.
    pub coefficient: T,
    /// `p_ref` \[Pa\]: the pressure sum at which the base Fc, Fs hold (without cosine terms).
    pub reference_pressure_sum: T,
    /// `gamma` [-]: the power of the pressure sum (1: linear).
    pub exponent: T,
    /// `L` \[Pa\] > 0: half the range of pressure sums the cosine series spans.
    pub half_span: T,
    /// `c_j` \[N\]: the cosine terms; only the first `terms` are used.
    pub cosine: [T; LOAD_TERMS],
    /// `n`: number of cosine terms in use (0..=[`LOAD_TERMS`]).
    pub terms: usize,
    /// `beta` [-]: the share of the scale's change the Stribeck hump takes (1: in proportion).
    pub static_share: T,
}

impl<T: Float> LoadDependence<T> {
    /// The power law alone (no cosine terms).
    pub fn power(coefficient: T, reference_pressure_sum: T, exponent: T) -> Self {
        Self {
            coefficient,
            reference_pressure_sum,
            exponent,
            half_span: T::one(),
            cosine: [T::zero(); LOAD_TERMS],
            terms: 0,
            static_share: T::one(),
        }
    }

    /// The regressor `dF / k` \[Pa\] at pressure sum `p` \[Pa\] (the power law's part).
    pub fn basis(&self, pressure_sum: T) -> T {
        let (r, g) = (self.reference_pressure_sum, self.exponent);
        if r > T::zero() && g > T::zero() && g.is_finite() && g != T::one() {
            let u = pressure_sum.max(T::zero()) / r;
            r * (u.powf(g) - T::one()) / g
        } else {
            pressure_sum - r
        }
    }

    /// The cosine basis at pressure sum `p`: `cos(j pi u)` for `j = 1..=terms`, zero beyond.
    pub fn cosine_basis(&self, pressure_sum: T) -> [T; LOAD_TERMS] {
        cosine_series(
            pressure_sum,
            self.reference_pressure_sum,
            self.half_span,
            self.terms,
        )
    }

    /// The scales for a level shift `dF` \[N\] ([`Self::shift`]) of a model whose static level
    /// is `Fs` \[N\] (> 0): the Coulomb level's `L = max(1 + dF / Fs, 0)` and the Stribeck
    /// hump's `1 + beta (L - 1)`. The static level, not the Coulomb one, is the reference: a
    /// fit whose Coulomb level sits at zero, its friction all in the hump, would make the
    /// scale singular.
    pub fn scales(&self, shift: T, static_force: T) -> (T, T) {
        let scale = (T::one() + shift / static_force).max(T::zero());
        (scale, T::one() + self.static_share * (scale - T::one()))
    }

    /// The shift of Fc and Fs, `dF(p)` \[N\].
    pub fn shift(&self, pressure_sum: T) -> T {
        if self.terms == 0 {
            return self.coefficient * self.basis(pressure_sum);
        }
        self.shift_from(self.basis(pressure_sum), &self.cosine_basis(pressure_sum))
    }

    /// The shift `dF(p)` \[N\] from an already evaluated [`Self::basis`] and
    /// [`Self::cosine_basis`] at `p` (a fit that needs them for its regressors evaluates
    /// them once).
    pub fn shift_from(&self, basis: T, cosine_basis: &[T; LOAD_TERMS]) -> T {
        let mut d = self.coefficient * basis;
        for (c, q) in self.cosine.iter().zip(cosine_basis.iter()).take(self.terms) {
            d = d + *c * *q;
        }
        d
    }
}

/// The half-range cosine basis of a condition `s` over `centre - half_span .. centre +
/// half_span`: `cos(j pi u)`, `u = clamp((s - centre) / (2 half_span) + 1/2, 0, 1)`, for
/// `j = 1..=terms`, zero beyond (Chebyshev recurrence: one cosine evaluation, and on the loop's
/// path only the terms in use).
fn cosine_series<T: Float, const N: usize>(s: T, centre: T, half_span: T, terms: usize) -> [T; N] {
    let two = T::one() + T::one();
    let half = T::one() / two;
    let span = half_span.max(T::min_positive_value());
    let u = ((s - centre) / (two * span) + half)
        .max(T::zero())
        .min(T::one());
    let c1 = (T::from(core::f64::consts::PI).unwrap_or_else(T::one) * u).cos();
    let mut out = [T::zero(); N];
    let (mut prev, mut cur) = (T::one(), c1);
    for o in out.iter_mut().take(terms) {
        *o = cur;
        let next = two * c1 * cur - prev;
        prev = cur;
        cur = next;
    }
    out
}

/// Most cosine terms a position dependence carries: sixteen half-waves over the span resolve a
/// wear spot or a ripple down to about a twentieth of the stroke (four left a 5 cm spot on a
/// 30 cm stroke at 1.7x the noise floor; eight left spots 4..7 cm wide on 34..47 cm strokes at
/// 1.4..1.6x, every one at the eighth term).
pub const POSITION_TERMS: usize = 16;

/// Friction that varies along the stroke: a gradient plus a smooth shape,
///
/// ```text
/// dF(x) = k_x (x - x_c) + sum_{j=1..n} c_j cos(j pi u),   u = clamp((x - x_c) / (2 L) + 1/2, 0, 1)
/// ```
///
/// a cosine series over the stroke `x_c - L .. x_c + L` (no periodicity assumed: the half-range
/// cosine basis represents any smooth function of the position there, a local wear spot, a
/// ripple, a bent rod). `n = 0` is the plain linear gradient.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PositionDependence<T> {
    /// `k_x` [N/m].
    pub gradient: T,
    /// `x_c` \[m\]: the position at which the base Fc, Fs hold (without cosine terms).
    pub center: T,
    /// `L` \[m\] > 0: half the stroke the cosine series spans.
    pub half_span: T,
    /// `c_j` \[N\]: the cosine terms; only the first `terms` are used.
    pub cosine: [T; POSITION_TERMS],
    /// `n`: number of cosine terms in use (0..=[`POSITION_TERMS`]).
    pub terms: usize,
}

impl<T: Float> PositionDependence<T> {
    /// A linear gradient `k_x (x - x_c)` only.
    pub fn linear(gradient: T, center: T) -> Self {
        Self {
            gradient,
            center,
            half_span: T::one(),
            cosine: [T::zero(); POSITION_TERMS],
            terms: 0,
        }
    }

    /// The cosine basis at position `x`: `cos(j pi u)` for `j = 1..=terms`, zero beyond
    /// (Chebyshev recurrence: one cosine evaluation, and on the loop's path only the terms in
    /// use).
    pub fn basis(&self, x: T) -> [T; POSITION_TERMS] {
        cosine_series(x, self.center, self.half_span, self.terms)
    }

    /// The level shift `dF(x)` \[N\].
    pub fn shift(&self, x: T) -> T {
        if self.terms == 0 {
            return self.gradient * (x - self.center);
        }
        self.shift_from(x, &self.basis(x))
    }

    /// The level shift `dF(x)` \[N\] from an already evaluated [`Self::basis`] at `x` (a fit that
    /// needs the basis for its regressors evaluates it once).
    pub fn shift_from(&self, x: T, basis: &[T; POSITION_TERMS]) -> T {
        let mut d = self.gradient * (x - self.center);
        for (c, q) in self.cosine.iter().zip(basis.iter()).take(self.terms) {
            d = d + *c * *q;
        }
        d
    }
}

/// Friction that changes with oil temperature.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TemperatureDependence<T> {
    /// `k_v` [1/K]: viscous friction falls as the oil thins.
    pub viscous_per_kelvin: T,
    /// `k_c` [1/K]: Coulomb level change per kelvin.
    pub coulomb_per_kelvin: T,
    /// `T_ref` \[degC\]: the temperature at which the base parameters hold.
    pub reference_temperature: T,
    /// `q` [-] >= 0: how the Stribeck curve follows the oil's viscosity. The lubricating film
    /// that lifts the contact grows with the Hersey number `eta v / p` (`eta = exp(-k_v dT)`
    /// the viscosity ratio the viscous term uses), so the curve is taken at `v eta^q`: the
    /// Stribeck velocity becomes `vs eta^-q` (thinner oil needs more speed to lift). 0: the
    /// curve does not move with temperature (the law before session 74); 1: it is a function
    /// of `eta v` alone.
    pub stribeck_hersey_exponent: T,
}

impl<T: Float> TemperatureDependence<T> {
    /// The factor `eta^-q = exp(q k_v (T - T_ref))` of the Stribeck velocity at oil temperature
    /// `temperature` \[degC\]: exactly 1 at `q = 0` (no power evaluated), and 1 where the
    /// factor would not be a positive finite number (a temperature that is not a number), so
    /// that a bad reading leaves the curve where it was instead of making it NaN.
    pub fn stribeck_velocity_scale(&self, temperature: T) -> T {
        if self.stribeck_hersey_exponent == T::zero() {
            return T::one();
        }
        let dt = temperature - self.reference_temperature;
        let scale = (self.stribeck_hersey_exponent * self.viscous_per_kelvin * dt).exp();
        if scale.is_finite() && scale > T::zero() {
            scale
        } else {
            T::one()
        }
    }
}

/// A Stribeck curve other than the standard `exp(-(|v|/vs)^2)`: another exponent, and a second,
/// slower lubrication scale the data can add (a boundary hump near rest and a mixed-film decay
/// that lasts to higher speeds):
///
/// `g(v) = Fc + (Fs - Fc) [(1 - w) exp(-(|v|/vs)^delta) + w exp(-|v| / (k vs))]`
///
/// with `w` = [`Self::tail_share`] and `k` = [`Self::tail_scale`]. `w = 0` is the one-scale
/// curve, evaluated as it was before the tail existed (bit for bit).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StribeckShape<T> {
    /// `delta` [-], > 0.
    pub exponent: T,
    /// `w` [-] in 0..=1: the share of the hump that decays on the slow scale.
    pub tail_share: T,
    /// `k` [-] > 0: the slow scale's velocity over the Stribeck velocity.
    pub tail_scale: T,
}

impl<T: Float> StribeckShape<T> {
    /// The one-scale curve `exp(-(|v|/vs)^delta)` (no tail).
    pub fn with_exponent(exponent: T) -> Self {
        Self {
            exponent,
            tail_share: T::zero(),
            tail_scale: T::one(),
        }
    }
}

/// Viscous force proportional to `|v|^delta`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViscousPower<T> {
    /// `delta` [-], > 0.
    pub exponent: T,
    /// `v_r` [m/s] > 0: the velocity at which the power law equals `sigma2 v`.
    pub reference_velocity: T,
}

/// Breakaway force that grows with time at rest.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DwellStiction<T> {
    /// `dF` \[N\]: the increase of Fs after a long dwell.
    pub max_increase: T,
    /// `tau` \[s\] > 0.
    pub time_constant: T,
    /// Below this speed \[m/s\] (the body's or the contact's slip, as `clock` says) the axis
    /// counts as stuck and the dwell timer runs.
    pub stick_velocity: T,
    /// `D` \[m\] > 0: once the axis slides, the aged time is forgotten over this distance
    /// (`t_dwell` decays as `exp(-s / D)` along the slid distance `s`): the junctions that grew
    /// at rest are renewed by sliding, as in rate-and-state friction's state variable. A few
    /// micrometres forget it within the breakaway; millimetres carry it into the motion.
    pub renewal_distance: T,
    /// What a new stick does to the age: carry on from what the last slide left of it, or
    /// start again at zero.
    pub age_at_stick: DwellAge,
    /// Whose speed tells a stick, and how far the contact slid: the body's or the contact's.
    pub clock: DwellClock,
    /// How the increase grows with the age: the share `w(t_dwell)` of `dF` it has reached.
    pub growth: DwellGrowth,
}

impl<T: Float> DwellStiction<T> {
    /// The share of `dF` reached at the age `age` \[s\] (in `[0, 1)`; a negative age counts as
    /// zero): `1 - exp(-t / tau)` or `t / (t + tau)` as [`Self::growth`] says.
    #[inline(always)]
    pub fn grown_share(&self, age: T) -> T {
        let tau = self.time_constant.max(T::min_positive_value());
        let t = age.max(T::zero());
        match self.growth {
            DwellGrowth::Exponential => -(-t / tau).exp_m1(),
            DwellGrowth::Hyperbolic => t / (t + tau),
        }
    }
}

/// How `dwell_stiction`'s increase grows with the age `t_dwell` (no law fixes the form, so
/// the data choose it). Contact strength grows with the logarithm of the contact time over
/// decades (Rabinowicz; Dieterich), slower than any exponential; the hyperbolic form is a
/// bounded growth with that slow tail, half-grown at `tau` as the exponential is at
/// `0.69 tau`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(
    feature = "params-file",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "snake_case")
)]
pub enum DwellGrowth {
    /// `w = 1 - exp(-t_dwell / tau)`: grown within a few `tau` (the only form before
    /// session 103).
    #[default]
    Exponential,
    /// `w = t_dwell / (t_dwell + tau)`: a tail that falls as `tau / t_dwell`, still growing
    /// at ten times `tau` (by 8 % of `dF` from `10 tau` to `100 tau`).
    Hyperbolic,
}

impl DwellGrowth {
    /// Both forms, the long-standing one first.
    pub const ALL: [DwellGrowth; 2] = [DwellGrowth::Exponential, DwellGrowth::Hyperbolic];

    /// The form's name in parameter files and reports.
    pub const fn name(self) -> &'static str {
        match self {
            DwellGrowth::Exponential => "exponential",
            DwellGrowth::Hyperbolic => "hyperbolic",
        }
    }
}

/// What `dwell_stiction`'s clock reads as the speed that tells a stick from a slide, and
/// integrates as the slid distance that renews the junctions.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(
    feature = "params-file",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "snake_case")
)]
pub enum DwellClock {
    /// The body's speed (the step's mean velocity): a stick is a stop of the axis (the law
    /// before session 89).
    #[default]
    BodySpeed,
    /// The contact's slip `|v - dz/dt|`, the part of the body's speed the bristle does not
    /// take up by deflecting (the last step's deflection rate: the step's own is not known
    /// before its levels are). A reversal the bristle rides through in pre-sliding is a
    /// stick of the contact while the body moves: the junctions age there as at a stop.
    ContactSlip,
}

impl DwellClock {
    /// Both clocks, the long-standing one first.
    pub const ALL: [DwellClock; 2] = [DwellClock::BodySpeed, DwellClock::ContactSlip];

    /// The clock's name in parameter files and reports.
    pub const fn name(self) -> &'static str {
        match self {
            DwellClock::BodySpeed => "body_speed",
            DwellClock::ContactSlip => "contact_slip",
        }
    }
}

/// What a new stick does to `dwell_stiction`'s age `t_dwell` (the rule the contact's junctions
/// follow; the data choose it, since no law fixes it).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(
    feature = "params-file",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "snake_case")
)]
pub enum DwellAge {
    /// The age grows on from what the last slide left of it: junctions a short slide only
    /// partly renewed keep growing (the model's law before session 67).
    #[default]
    Accumulates,
    /// Each stick starts a new age at zero: the junctions of a stick are new ones. While the
    /// axis slides, the age the stick reached is forgotten over the renewal distance as with
    /// [`DwellAge::Accumulates`], so the breakaway peak fades the same way.
    Restarts,
    /// Dieterich and Ruina's aging law: no stick threshold, the age grows with time and is
    /// forgotten over the renewal distance `D` of the clock's slip `s`,
    /// `d t_dwell/dt = 1 - t_dwell |ds/dt| / D` (implicit Euler, stable for any slip). A creep
    /// of a nanometre takes a nanometre's share of it, and a steady slide at speed `v` holds the
    /// age at `D / v`: the junctions a slow slide leaves time to grow strengthen it.
    Aging,
}

impl DwellAge {
    /// Every rule, the long-standing one first.
    pub const ALL: [DwellAge; 3] = [DwellAge::Accumulates, DwellAge::Restarts, DwellAge::Aging];

    /// The rule's name in parameter files and reports.
    pub const fn name(self) -> &'static str {
        match self {
            DwellAge::Accumulates => "accumulates",
            DwellAge::Restarts => "restarts",
            DwellAge::Aging => "aging",
        }
    }
}

/// The set of extra effects a model carries (all `None`: plain LuGre).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Effects<T> {
    /// See [`Asymmetry`].
    pub asymmetry: Option<Asymmetry<T>>,
    /// See [`Offset`].
    pub offset: Option<Offset<T>>,
    /// See [`LoadDependence`].
    pub load_dependence: Option<LoadDependence<T>>,
    /// See [`PositionDependence`].
    pub position_dependence: Option<PositionDependence<T>>,
    /// See [`TemperatureDependence`].
    pub temperature_dependence: Option<TemperatureDependence<T>>,
    /// See [`StribeckShape`].
    pub stribeck_shape: Option<StribeckShape<T>>,
    /// See [`ViscousPower`].
    pub viscous_power: Option<ViscousPower<T>>,
    /// See [`DwellStiction`].
    pub dwell_stiction: Option<DwellStiction<T>>,
}

/// The eight extra effects, by kind: the one vocabulary the simulator's switches, the
/// diagnosis, the parameter files and the command line share.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum EffectKind {
    /// [`Asymmetry`].
    Asymmetry,
    /// [`Offset`].
    Offset,
    /// [`LoadDependence`].
    LoadDependence,
    /// [`PositionDependence`].
    PositionDependence,
    /// [`TemperatureDependence`].
    TemperatureDependence,
    /// [`StribeckShape`].
    StribeckShape,
    /// [`ViscousPower`].
    ViscousPower,
    /// [`DwellStiction`].
    DwellStiction,
}

impl EffectKind {
    /// Every effect, in the documented order.
    pub const ALL: [EffectKind; 8] = [
        EffectKind::Asymmetry,
        EffectKind::Offset,
        EffectKind::LoadDependence,
        EffectKind::PositionDependence,
        EffectKind::TemperatureDependence,
        EffectKind::StribeckShape,
        EffectKind::ViscousPower,
        EffectKind::DwellStiction,
    ];

    /// The name users write (`snake_case`, as in the parameter file's `[effects.NAME]`).
    pub const fn name(self) -> &'static str {
        match self {
            EffectKind::Asymmetry => "asymmetry",
            EffectKind::Offset => "offset",
            EffectKind::LoadDependence => "load_dependence",
            EffectKind::PositionDependence => "position_dependence",
            EffectKind::TemperatureDependence => "temperature_dependence",
            EffectKind::StribeckShape => "stribeck_shape",
            EffectKind::ViscousPower => "viscous_power",
            EffectKind::DwellStiction => "dwell_stiction",
        }
    }

    /// The kind of a name; an unknown name is an error that lists the known ones.
    pub fn parse(name: &str) -> Result<Self, UnknownEffect> {
        Self::ALL
            .iter()
            .copied()
            .find(|k| k.name() == name)
            .ok_or(UnknownEffect)
    }
}

impl core::fmt::Display for EffectKind {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        // `pad`, not `write_str`: column widths such as `{:<24}` apply
        f.pad(self.name())
    }
}

impl core::str::FromStr for EffectKind {
    type Err = UnknownEffect;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::parse(s)
    }
}

/// A name that is none of the eight effects.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UnknownEffect;

impl core::fmt::Display for UnknownEffect {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("unknown effect; known: ")?;
        for (i, k) in EffectKind::ALL.iter().enumerate() {
            if i > 0 {
                f.write_str(", ")?;
            }
            f.write_str(k.name())?;
        }
        Ok(())
    }
}

#[cfg(feature = "std")]
impl std::error::Error for UnknownEffect {}

/// Operating conditions some effects depend on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conditions<T> {
    /// Piston position x \[m\].
    pub position: T,
    /// Chamber pressure sum `p_a + p_b` \[Pa\].
    pub pressure_sum: T,
    /// Oil temperature \[degC\].
    pub temperature: T,
}

impl<T: Float> Effects<T> {
    /// The same effects in another float type (f64 on the host -> f32 on the MCU); a value the
    /// target type cannot hold becomes NaN, which the model's checks then refuse.
    pub fn cast<U: Float>(&self) -> Effects<U> {
        let c = |x: T| U::from(x).unwrap_or_else(U::nan);
        Effects {
            asymmetry: self.asymmetry.map(|a| Asymmetry {
                coulomb_ratio: c(a.coulomb_ratio),
                static_ratio: c(a.static_ratio),
                viscous_ratio: c(a.viscous_ratio),
                stribeck_velocity_ratio: c(a.stribeck_velocity_ratio),
            }),
            offset: self.offset.map(|o| Offset { force: c(o.force) }),
            load_dependence: self.load_dependence.map(|l| LoadDependence {
                coefficient: c(l.coefficient),
                reference_pressure_sum: c(l.reference_pressure_sum),
                exponent: c(l.exponent),
                half_span: c(l.half_span),
                cosine: l.cosine.map(c),
                terms: l.terms,
                static_share: c(l.static_share),
            }),
            position_dependence: self.position_dependence.map(|p| PositionDependence {
                gradient: c(p.gradient),
                center: c(p.center),
                half_span: c(p.half_span),
                cosine: p.cosine.map(c),
                terms: p.terms,
            }),
            temperature_dependence: self.temperature_dependence.map(|t| TemperatureDependence {
                viscous_per_kelvin: c(t.viscous_per_kelvin),
                coulomb_per_kelvin: c(t.coulomb_per_kelvin),
                reference_temperature: c(t.reference_temperature),
                stribeck_hersey_exponent: c(t.stribeck_hersey_exponent),
            }),
            stribeck_shape: self.stribeck_shape.map(|s| StribeckShape {
                exponent: c(s.exponent),
                tail_share: c(s.tail_share),
                tail_scale: c(s.tail_scale),
            }),
            viscous_power: self.viscous_power.map(|v| ViscousPower {
                exponent: c(v.exponent),
                reference_velocity: c(v.reference_velocity),
            }),
            dwell_stiction: self.dwell_stiction.map(|d| DwellStiction {
                max_increase: c(d.max_increase),
                time_constant: c(d.time_constant),
                stick_velocity: c(d.stick_velocity),
                renewal_distance: c(d.renewal_distance),
                age_at_stick: d.age_at_stick,
                clock: d.clock,
                growth: d.growth,
            }),
        }
    }

    /// No effect switched on.
    pub const fn none() -> Self {
        Self {
            asymmetry: None,
            offset: None,
            load_dependence: None,
            position_dependence: None,
            temperature_dependence: None,
            stribeck_shape: None,
            viscous_power: None,
            dwell_stiction: None,
        }
    }

    /// True when the effect of this kind is switched on.
    pub fn has(&self, kind: EffectKind) -> bool {
        match kind {
            EffectKind::Asymmetry => self.asymmetry.is_some(),
            EffectKind::Offset => self.offset.is_some(),
            EffectKind::LoadDependence => self.load_dependence.is_some(),
            EffectKind::PositionDependence => self.position_dependence.is_some(),
            EffectKind::TemperatureDependence => self.temperature_dependence.is_some(),
            EffectKind::StribeckShape => self.stribeck_shape.is_some(),
            EffectKind::ViscousPower => self.viscous_power.is_some(),
            EffectKind::DwellStiction => self.dwell_stiction.is_some(),
        }
    }

    /// The same effects with the one of this kind as it is in `other` (switched off where
    /// `other` has it off).
    pub fn with_kind_of(mut self, kind: EffectKind, other: &Self) -> Self {
        match kind {
            EffectKind::Asymmetry => self.asymmetry = other.asymmetry,
            EffectKind::Offset => self.offset = other.offset,
            EffectKind::LoadDependence => self.load_dependence = other.load_dependence,
            EffectKind::PositionDependence => self.position_dependence = other.position_dependence,
            EffectKind::TemperatureDependence => {
                self.temperature_dependence = other.temperature_dependence
            }
            EffectKind::StribeckShape => self.stribeck_shape = other.stribeck_shape,
            EffectKind::ViscousPower => self.viscous_power = other.viscous_power,
            EffectKind::DwellStiction => self.dwell_stiction = other.dwell_stiction,
        }
        self
    }

    /// The same effects with the one of this kind switched off.
    pub fn without(self, kind: EffectKind) -> Self {
        self.with_kind_of(kind, &Self::none())
    }

    /// The kinds switched on, in [`EffectKind::ALL`] order.
    pub fn kinds(&self) -> impl Iterator<Item = EffectKind> + '_ {
        EffectKind::ALL.into_iter().filter(|k| self.has(*k))
    }

    /// Conditions at which every effect is neutral (reference pressure, centre, reference
    /// temperature): a model fed these behaves like its base parameters.
    pub fn reference_conditions(&self) -> Conditions<T> {
        Conditions {
            position: self.position_dependence.map_or(T::zero(), |p| p.center),
            pressure_sum: self
                .load_dependence
                .map_or(T::zero(), |l| l.reference_pressure_sum),
            temperature: self
                .temperature_dependence
                .map_or(T::zero(), |t| t.reference_temperature),
        }
    }
}

/// A set with every effect on, each with a value of its own (for tests).
#[cfg(test)]
pub(crate) fn every_effect() -> Effects<f64> {
    let mut all = Effects::<f64>::none();
    all.asymmetry = Some(Asymmetry {
        coulomb_ratio: 0.1,
        static_ratio: 0.2,
        viscous_ratio: 0.3,
        stribeck_velocity_ratio: 0.15,
    });
    all.offset = Some(Offset { force: 1.0 });
    all.load_dependence = Some(LoadDependence::power(1e-6, 1e7, 1.0));
    all.position_dependence = Some(PositionDependence::linear(2.0, 0.0));
    all.temperature_dependence = Some(TemperatureDependence {
        viscous_per_kelvin: 0.01,
        coulomb_per_kelvin: 0.001,
        reference_temperature: 40.0,
        stribeck_hersey_exponent: 0.3,
    });
    all.stribeck_shape = Some(StribeckShape::with_exponent(1.5));
    all.viscous_power = Some(ViscousPower {
        exponent: 0.7,
        reference_velocity: 0.01,
    });
    all.dwell_stiction = Some(DwellStiction {
        max_increase: 1.0,
        time_constant: 1.0,
        stick_velocity: 1e-4,
        renewal_distance: 1e-4,
        age_at_stick: DwellAge::Accumulates,
        clock: DwellClock::BodySpeed,
        growth: crate::friction::DwellGrowth::Exponential,
    });
    all
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_round_trips_through_its_name_and_an_unknown_name_is_refused() {
        for k in EffectKind::ALL {
            assert_eq!(EffectKind::parse(k.name()), Ok(k));
        }
        assert_eq!(EffectKind::parse("gremlins"), Err(UnknownEffect));
        assert_eq!(EffectKind::parse("Asymmetry"), Err(UnknownEffect));
        let mut e = Effects::<f64>::none();
        assert_eq!(e.kinds().count(), 0);
        e.offset = Some(Offset { force: 1.0 });
        e.dwell_stiction = every_effect().dwell_stiction;
        let on: [EffectKind; 2] = [EffectKind::Offset, EffectKind::DwellStiction];
        assert!(e.kinds().eq(on));
        assert!(EffectKind::ALL.iter().all(|k| e.has(*k) == on.contains(k)));
    }

    /// `with_kind_of` takes exactly one kind from the other set, on or off, for every kind.
    #[test]
    fn with_kind_of_takes_one_kind_only() {
        let all = every_effect();
        assert_eq!(all.kinds().count(), EffectKind::ALL.len(), "the premise");
        let none = Effects::<f64>::none();
        for k in EffectKind::ALL {
            let on = none.with_kind_of(k, &all);
            assert!(on.kinds().eq([k]), "{k:?}");
            assert_eq!(on.without(k), none, "{k:?}");
            // switched off, that kind alone: every other one keeps its value
            let off = all.without(k);
            assert!(off
                .kinds()
                .eq(EffectKind::ALL.into_iter().filter(|j| *j != k)));
            assert_eq!(off.with_kind_of(k, &all), all, "{k:?}");
            assert_eq!(off, all.with_kind_of(k, &none), "{k:?}");
        }
    }
}
