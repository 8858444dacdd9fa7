//! Validated LuGre parameters.
//!
//! The LuGre model (Canudas de Wit et al., 1995) in the form used throughout this crate:
//!
//! ```text
//! g(v)  = Fc + (Fs - Fc) * exp(-(v / vs)^2)        Stribeck curve            [N]
//! dz/dt = v - sigma0 * |v| * z / g(v)              bristle deflection z      [m]
//! F     = sigma0 * z + sigma1 * dz/dt + sigma2 * v friction force            [N]
//! ```

use core::fmt;
use num_traits::Float;

/// The six LuGre parameters, validated on construction.
///
/// Fields are private so that a value of this type is always physically valid:
/// finite, `sigma0 > 0`, `sigma1 >= 0`, `sigma2 >= 0`, `Fc > 0`, `Fs >= Fc`, `vs > 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LugreParams<T> {
    bristle_stiffness: T,
    bristle_damping: T,
    viscous_coefficient: T,
    coulomb_force: T,
    static_force: T,
    stribeck_velocity: T,
}

/// Which parameter a validation error is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ParamField {
    /// sigma0, bristle stiffness [N/m].
    BristleStiffness,
    /// sigma1, bristle (micro) damping [N s/m].
    BristleDamping,
    /// sigma2, viscous coefficient [N s/m].
    ViscousCoefficient,
    /// Fc, Coulomb force \[N\].
    CoulombForce,
    /// Fs, static (breakaway) force \[N\].
    StaticForce,
    /// vs, Stribeck velocity [m/s].
    StribeckVelocity,
}

impl ParamField {
    /// The field's name with its symbol and unit, for messages.
    pub const fn describe(self) -> &'static str {
        match self {
            Self::BristleStiffness => "bristle_stiffness (sigma0) [N/m]",
            Self::BristleDamping => "bristle_damping (sigma1) [N s/m]",
            Self::ViscousCoefficient => "viscous_coefficient (sigma2) [N s/m]",
            Self::CoulombForce => "coulomb_force (Fc) [N]",
            Self::StaticForce => "static_force (Fs) [N]",
            Self::StribeckVelocity => "stribeck_velocity (vs) [m/s]",
        }
    }
}

/// Why a parameter set was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ParamErrorKind {
    /// NaN or infinite.
    NotFinite,
    /// Must be strictly positive.
    NotPositive,
    /// Must be zero or positive.
    Negative,
    /// The static force is below the Coulomb force (Fs < Fc).
    StaticBelowCoulomb,
    /// Valid numbers, but outside what any servo axis has (see [`LugreParams::check_physical`]).
    Implausible,
}

/// A refused parameter set: which field, and why.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ParamError {
    /// The offending field.
    pub field: ParamField,
    /// What is wrong with it.
    pub kind: ParamErrorKind,
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let why = match self.kind {
            ParamErrorKind::NotFinite => "must be a finite number",
            ParamErrorKind::NotPositive => "must be greater than zero",
            ParamErrorKind::Negative => "must not be negative",
            ParamErrorKind::StaticBelowCoulomb => {
                "must be at least coulomb_force (Fc): the breakaway force cannot be below the sliding force"
            }
            ParamErrorKind::Implausible => {
                "is outside the physical range of servo axes (see LugreParams::check_physical)"
            }
        };
        write!(f, "{} {}", self.field.describe(), why)
    }
}

#[cfg(feature = "std")]
extern crate std;
#[cfg(feature = "std")]
impl std::error::Error for ParamError {}

/// A valid but suspicious parameter set (reported, not refused).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ParamWarning {
    /// The passivity condition `sigma2 > sigma1 * (Fs - Fc) / Fc` fails: the model can
    /// generate energy (negative damping in the Stribeck region), a classic trap when
    /// identified parameters are used for compensation.
    NotDissipative,
}

impl fmt::Display for ParamWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NotDissipative => f.write_str(
                "not dissipative: sigma2 <= sigma1 * (Fs - Fc) / Fc, the model can inject energy \
                 in the Stribeck region",
            ),
        }
    }
}

impl<T: Float> LugreParams<T> {
    /// Builds a validated parameter set.
    ///
    /// * `bristle_stiffness` sigma0 [N/m], > 0
    /// * `bristle_damping` sigma1 [N s/m], >= 0
    /// * `viscous_coefficient` sigma2 [N s/m], >= 0
    /// * `coulomb_force` Fc \[N\], > 0
    /// * `static_force` Fs \[N\], >= Fc
    /// * `stribeck_velocity` vs [m/s], > 0
    pub fn new(
        bristle_stiffness: T,
        bristle_damping: T,
        viscous_coefficient: T,
        coulomb_force: T,
        static_force: T,
        stribeck_velocity: T,
    ) -> Result<Self, ParamError> {
        use ParamField::*;
        check_fields(&[
            (BristleStiffness, bristle_stiffness, true),
            (BristleDamping, bristle_damping, false),
            (StribeckVelocity, stribeck_velocity, true),
        ])?;
        Self {
            bristle_stiffness,
            bristle_damping,
            viscous_coefficient: T::zero(),
            coulomb_force: T::one(),
            static_force: T::one(),
            stribeck_velocity,
        }
        .with_levels(viscous_coefficient, coulomb_force, static_force)
    }

    /// The same set with new friction levels (sigma2, Fc, Fs), validated as in
    /// [`LugreParams::new`]; the bristle and Stribeck parameters are already valid, so only the
    /// levels are checked (the online refinement changes them every period).
    pub fn with_levels(
        &self,
        viscous_coefficient: T,
        coulomb_force: T,
        static_force: T,
    ) -> Result<Self, ParamError> {
        use ParamField::*;
        check_fields(&[
            (ViscousCoefficient, viscous_coefficient, false),
            (CoulombForce, coulomb_force, true),
            (StaticForce, static_force, true),
        ])?;
        if static_force < coulomb_force {
            return Err(ParamError {
                field: StaticForce,
                kind: ParamErrorKind::StaticBelowCoulomb,
            });
        }
        Ok(Self {
            viscous_coefficient,
            coulomb_force,
            static_force,
            ..*self
        })
    }

    /// [`LugreParams::new`] from the six values in the order of [`LugreParams::to_array`].
    pub fn from_array(v: [T; 6]) -> Result<Self, ParamError> {
        Self::new(v[0], v[1], v[2], v[3], v[4], v[5])
    }

    /// The six values in the order of the link frames and Table 2:
    /// `[sigma0, sigma1, sigma2, Fc, Fs, vs]`.
    pub fn to_array(&self) -> [T; 6] {
        [
            self.bristle_stiffness,
            self.bristle_damping,
            self.viscous_coefficient,
            self.coulomb_force,
            self.static_force,
            self.stribeck_velocity,
        ]
    }

    /// The paper's Table 2 (Liao et al. 2023): sigma0 = 3.9e9 N/m, sigma1 = 200 N s/m,
    /// sigma2 = 48 900 N s/m, Fc = 506 N, Fs = 632 N, vs = 0.005 m/s.
    pub fn table2() -> Self {
        let c = |x: f64| T::from(x).unwrap_or_else(T::zero);
        Self {
            bristle_stiffness: c(3.9e9),
            bristle_damping: c(200.0),
            viscous_coefficient: c(48_900.0),
            coulomb_force: c(506.0),
            static_force: c(632.0),
            stribeck_velocity: c(0.005),
        }
    }

    /// sigma0, bristle stiffness [N/m].
    pub fn bristle_stiffness(&self) -> T {
        self.bristle_stiffness
    }
    /// sigma1, bristle damping [N s/m].
    pub fn bristle_damping(&self) -> T {
        self.bristle_damping
    }
    /// sigma2, viscous coefficient [N s/m].
    pub fn viscous_coefficient(&self) -> T {
        self.viscous_coefficient
    }
    /// Fc, Coulomb force \[N\].
    pub fn coulomb_force(&self) -> T {
        self.coulomb_force
    }
    /// Fs, static (breakaway) force \[N\].
    pub fn static_force(&self) -> T {
        self.static_force
    }
    /// vs, Stribeck velocity [m/s].
    pub fn stribeck_velocity(&self) -> T {
        self.stribeck_velocity
    }

    /// Refuses a valid set that no real axis has, before it reaches a controller:
    ///
    /// * sigma0 in [1e3, 1e11] N/m, and a pre-sliding length `Fs / sigma0` in [1 nm, 10 mm];
    /// * vs in [1 um/s, 1 m/s];
    /// * `Fs <= 20 Fc` (a breakaway twenty times the sliding level is an identification
    ///   artefact, typically a hump fitted to a few noisy samples);
    /// * sigma1 at most 100 times sigma0 x 1 s (a bristle time constant sigma1 / sigma0 of
    ///   more than 100 s is not a contact).
    ///
    /// An identification tool checks the same against the record (forces above several times
    /// the largest measured force); this check needs no record and runs on the target too.
    pub fn check_physical(&self) -> Result<(), ParamError> {
        use ParamField::*;
        let c = |x: f64| T::from(x).unwrap_or_else(T::nan);
        let bad = |field| {
            Err(ParamError {
                field,
                kind: ParamErrorKind::Implausible,
            })
        };
        let within = |x: T, lo: f64, hi: f64| x >= c(lo) && x <= c(hi);
        if !within(self.bristle_stiffness, 1e3, 1e11)
            || !within(self.static_force / self.bristle_stiffness, 1e-9, 1e-2)
        {
            return bad(BristleStiffness);
        }
        if !within(self.stribeck_velocity, 1e-6, 1.0) {
            return bad(StribeckVelocity);
        }
        if self.static_force > c(20.0) * self.coulomb_force {
            return bad(StaticForce);
        }
        if self.bristle_damping > c(100.0) * self.bristle_stiffness {
            return bad(BristleDamping);
        }
        Ok(())
    }

    /// `Some(warning)` when the set is valid but suspicious (see [`ParamWarning`]).
    ///
    /// Passivity (Barabanov and Ortega, 2000): the map v -> F is dissipative when
    /// `sigma2 > sigma1 * (Fs - Fc) / Fc`.
    pub fn warning(&self) -> Option<ParamWarning> {
        let bound =
            self.bristle_damping * (self.static_force - self.coulomb_force) / self.coulomb_force;
        (self.viscous_coefficient <= bound).then_some(ParamWarning::NotDissipative)
    }

    /// Converts to another float type (f64 identification -> f32 firmware), re-validating.
    pub fn cast<U: Float>(&self) -> Result<LugreParams<U>, ParamError> {
        let c = |x: T| U::from(x).unwrap_or_else(U::nan);
        LugreParams::new(
            c(self.bristle_stiffness),
            c(self.bristle_damping),
            c(self.viscous_coefficient),
            c(self.coulomb_force),
            c(self.static_force),
            c(self.stribeck_velocity),
        )
    }

    /// Stribeck curve `g(v) = Fc + (Fs - Fc) exp(-(v/vs)^2)` \[N\].
    pub fn stribeck_curve(&self, velocity: T) -> T {
        let r = velocity / self.stribeck_velocity;
        self.coulomb_force + (self.static_force - self.coulomb_force) * (-(r * r)).exp()
    }

    /// Steady-state friction at constant velocity, `Fss(v) = g(v) sign(v) + sigma2 v` \[N\]
    /// (zero at v = 0).
    pub fn steady_state_force(&self, velocity: T) -> T {
        let dir = direction(velocity);
        self.stribeck_curve(velocity) * dir + self.viscous_coefficient * velocity
    }
}

/// `sign(v)` with `sign(0) = 0` (friction at exact rest is not a sliding force).
/// Each value finite, and positive (`true`) or not negative (`false`); the first that is not
/// is the error.
fn check_fields<T: Float>(checks: &[(ParamField, T, bool)]) -> Result<(), ParamError> {
    use ParamErrorKind::*;
    for &(field, value, strictly) in checks {
        let kind = if !value.is_finite() {
            Some(NotFinite)
        } else if strictly && value <= T::zero() {
            Some(NotPositive)
        } else if value < T::zero() {
            Some(Negative)
        } else {
            None
        };
        if let Some(kind) = kind {
            return Err(ParamError { field, kind });
        }
    }
    Ok(())
}

pub(crate) fn direction<T: Float>(velocity: T) -> T {
    if velocity > T::zero() {
        T::one()
    } else if velocity < T::zero() {
        -T::one()
    } else {
        T::zero()
    }
}

impl<T: Float> Default for LugreParams<T> {
    /// The paper's Table 2.
    fn default() -> Self {
        Self::table2()
    }
}
