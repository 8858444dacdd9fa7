//! The parameter file (TOML) that identification writes and every other tool reads.
//!
//! ```toml
//! [lugre]
//! bristle_stiffness_n_per_m = 3.9e9      # sigma0
//! bristle_damping_n_s_per_m = 200.0      # sigma1
//! viscous_coefficient_n_s_per_m = 48900  # sigma2
//! coulomb_force_n = 506.0                # Fc
//! static_force_n = 632.0                 # Fs
//! stribeck_velocity_m_per_s = 0.005      # vs
//!
//! [axis]
//! moving_mass_kg = 200.0
//!
//! [effects.asymmetry]                    # any of the eight effects, all optional
//! coulomb_ratio = 0.1
//! static_ratio = 0.05                    # optional: rc when absent (older files)
//! viscous_ratio = 0.2
//! stribeck_velocity_ratio = -0.1         # optional: 0 when absent
//!
//! [fit]                                  # optional: how the values were obtained
//! algorithm = "improved"
//! static_fitness = 1.2e-9
//! ```

use crate::friction::effects as fx;
use crate::friction::EffectKind;
use crate::friction::{Effects, FrictionModel, LugreParams};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// `[lugre]`: the six base parameters with their units in the key names.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LugreSection {
    /// sigma0 [N/m].
    pub bristle_stiffness_n_per_m: f64,
    /// sigma1 [N s/m].
    pub bristle_damping_n_s_per_m: f64,
    /// sigma2 [N s/m].
    pub viscous_coefficient_n_s_per_m: f64,
    /// Fc \[N\].
    pub coulomb_force_n: f64,
    /// Fs \[N\].
    pub static_force_n: f64,
    /// vs [m/s].
    pub stribeck_velocity_m_per_s: f64,
}

/// `[axis]`.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct AxisSection {
    /// Moving mass M \[kg\].
    pub moving_mass_kg: f64,
}

/// `[effects]`: the extra effects, each a table with its parameters (see the core's
/// `friction::effects` for the equations).
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)]
pub struct EffectsSection {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub asymmetry: Option<AsymmetryT>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub offset: Option<OffsetT>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub load_dependence: Option<LoadT>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub position_dependence: Option<PositionT>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub temperature_dependence: Option<TemperatureT>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stribeck_shape: Option<ShapeT>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub viscous_power: Option<PowerT>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dwell_stiction: Option<DwellT>,
}

#[allow(missing_docs)]
mod tables {
    use serde::{Deserialize, Serialize};
    #[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
    #[serde(deny_unknown_fields)]
    pub struct AsymmetryT {
        pub coulomb_ratio: f64,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub static_ratio: Option<f64>,
        pub viscous_ratio: f64,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub stribeck_velocity_ratio: Option<f64>,
    }
    #[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
    #[serde(deny_unknown_fields)]
    pub struct OffsetT {
        pub force_n: f64,
    }
    #[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
    #[serde(deny_unknown_fields)]
    pub struct LoadT {
        pub coefficient_n_per_pa: f64,
        pub reference_pressure_sum_pa: f64,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub exponent: Option<f64>,
        /// half the range of pressure sums the cosine terms span (absent: no cosine terms)
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub half_span_pa: Option<f64>,
        /// the cosine terms c_1.. \[N\] (at most `LOAD_TERMS`, 4)
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        pub cosine_n: Vec<f64>,
        /// the share of the scale's change the Stribeck hump takes (absent: 1, in proportion)
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub static_share: Option<f64>,
    }
    #[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
    #[serde(deny_unknown_fields)]
    pub struct PositionT {
        pub gradient_n_per_m: f64,
        pub center_m: f64,
        /// half the stroke the cosine terms span (absent: no cosine terms)
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub half_span_m: Option<f64>,
        /// the cosine terms c_1.. \[N\] (at most `POSITION_TERMS`, 16)
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        pub cosine_n: Vec<f64>,
    }
    #[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
    #[serde(deny_unknown_fields)]
    pub struct TemperatureT {
        pub viscous_per_kelvin: f64,
        pub coulomb_per_kelvin: f64,
        pub reference_temperature_c: f64,
        /// how the Stribeck curve follows the viscosity, `vs eta^-q` (absent: 0, the curve
        /// does not move with temperature, as files written before it was known)
        #[serde(default, skip_serializing_if = "is_zero")]
        pub stribeck_hersey_exponent: f64,
    }
    fn is_zero(x: &f64) -> bool {
        *x == 0.0
    }
    #[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
    #[serde(deny_unknown_fields)]
    pub struct ShapeT {
        pub exponent: f64,
        /// the share of the hump on the slow scale (absent: 0, one scale, as files written
        /// before the tail existed)
        #[serde(default, skip_serializing_if = "is_zero")]
        pub tail_share: f64,
        /// the slow scale over the Stribeck velocity (absent: 1; unused without a share)
        #[serde(default = "one", skip_serializing_if = "is_one")]
        pub tail_scale: f64,
    }
    fn one() -> f64 {
        1.0
    }
    fn is_one(x: &f64) -> bool {
        *x == 1.0
    }
    #[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
    #[serde(deny_unknown_fields)]
    pub struct PowerT {
        pub exponent: f64,
        pub reference_velocity_m_per_s: f64,
    }
    #[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
    #[serde(deny_unknown_fields)]
    pub struct DwellT {
        pub max_increase_n: f64,
        pub time_constant_s: f64,
        pub stick_velocity_m_per_s: f64,
        /// absent in files written before session 8 (their model forgot the dwell within the
        /// breakaway): [`DEFAULT_RENEWAL_DISTANCE_M`](super::DEFAULT_RENEWAL_DISTANCE_M)
        #[serde(default = "default_renewal")]
        pub renewal_distance_m: f64,
        /// absent in files written before session 67 (their age accumulated)
        #[serde(default)]
        pub age_at_stick: crate::friction::DwellAge,
        /// absent in files written before session 89 (their clock read the body's speed)
        #[serde(default)]
        pub clock: crate::friction::DwellClock,
        /// absent in files written before session 103 (their increase grew exponentially)
        #[serde(default)]
        pub growth: crate::friction::DwellGrowth,
    }
    fn default_renewal() -> f64 {
        super::DEFAULT_RENEWAL_DISTANCE_M
    }
}
pub use tables::*;

/// The dwell's renewal distance of a parameter file that has none (written before session 8,
/// when the model forgot the dwell within the breakaway): 0.1 mm \[m\].
pub const DEFAULT_RENEWAL_DISTANCE_M: f64 = 1e-4;

/// `[fit]`: provenance of the values.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[allow(missing_docs)]
pub struct FitSection {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub algorithm: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub static_fitness: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dynamic_fitness: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rel_err_pct: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
    /// Parameters the data could not determine (their value is then a prior: the posterior
    /// mean over the search range in `host_sim::identify`, a documented prior in
    /// `host_sim::diagnose`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub not_identifiable: Vec<String>,
    /// Parameters the data determined (the rest of the file is a prior or a user's value).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub identified: Vec<String>,
}

/// The whole file.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ParamFile {
    /// Base LuGre parameters.
    pub lugre: LugreSection,
    /// Axis data.
    pub axis: AxisSection,
    /// Extra effects.
    #[serde(default)]
    pub effects: EffectsSection,
    /// Provenance.
    #[serde(default)]
    pub fit: FitSection,
}

impl ParamFile {
    /// A file for a model and a mass.
    pub fn new(model: &FrictionModel<f64>, moving_mass_kg: f64) -> Self {
        let p = &model.params;
        let e = &model.effects;
        Self {
            lugre: LugreSection {
                bristle_stiffness_n_per_m: p.bristle_stiffness(),
                bristle_damping_n_s_per_m: p.bristle_damping(),
                viscous_coefficient_n_s_per_m: p.viscous_coefficient(),
                coulomb_force_n: p.coulomb_force(),
                static_force_n: p.static_force(),
                stribeck_velocity_m_per_s: p.stribeck_velocity(),
            },
            axis: AxisSection { moving_mass_kg },
            effects: EffectsSection {
                asymmetry: e.asymmetry.map(|a| AsymmetryT {
                    coulomb_ratio: a.coulomb_ratio,
                    static_ratio: Some(a.static_ratio),
                    viscous_ratio: a.viscous_ratio,
                    stribeck_velocity_ratio: (a.stribeck_velocity_ratio != 0.0)
                        .then_some(a.stribeck_velocity_ratio),
                }),
                offset: e.offset.map(|o| OffsetT { force_n: o.force }),
                load_dependence: e.load_dependence.map(|l| LoadT {
                    coefficient_n_per_pa: l.coefficient,
                    reference_pressure_sum_pa: l.reference_pressure_sum,
                    exponent: Some(l.exponent),
                    half_span_pa: (l.terms > 0).then_some(l.half_span),
                    cosine_n: l.cosine[..l.terms.min(l.cosine.len())].to_vec(),
                    static_share: (l.static_share != 1.0).then_some(l.static_share),
                }),
                position_dependence: e.position_dependence.map(|x| PositionT {
                    gradient_n_per_m: x.gradient,
                    center_m: x.center,
                    half_span_m: (x.terms > 0).then_some(x.half_span),
                    cosine_n: x.cosine[..x.terms.min(x.cosine.len())].to_vec(),
                }),
                temperature_dependence: e.temperature_dependence.map(|t| TemperatureT {
                    viscous_per_kelvin: t.viscous_per_kelvin,
                    coulomb_per_kelvin: t.coulomb_per_kelvin,
                    reference_temperature_c: t.reference_temperature,
                    stribeck_hersey_exponent: t.stribeck_hersey_exponent,
                }),
                stribeck_shape: e.stribeck_shape.map(|s| ShapeT {
                    exponent: s.exponent,
                    tail_share: s.tail_share,
                    tail_scale: if s.tail_share == 0.0 {
                        1.0
                    } else {
                        s.tail_scale
                    },
                }),
                viscous_power: e.viscous_power.map(|v| PowerT {
                    exponent: v.exponent,
                    reference_velocity_m_per_s: v.reference_velocity,
                }),
                dwell_stiction: e.dwell_stiction.map(|d| DwellT {
                    max_increase_n: d.max_increase,
                    time_constant_s: d.time_constant,
                    stick_velocity_m_per_s: d.stick_velocity,
                    renewal_distance_m: d.renewal_distance,
                    age_at_stick: d.age_at_stick,
                    clock: d.clock,
                    growth: d.growth,
                }),
            },
            fit: FitSection::default(),
        }
    }

    /// The validated model (the error names the section and field and says what is wrong).
    pub fn model(&self) -> Result<FrictionModel<f64>, InvalidParams> {
        use crate::friction::EffectKind as K;
        let l = &self.lugre;
        let params = LugreParams::new(
            l.bristle_stiffness_n_per_m,
            l.bristle_damping_n_s_per_m,
            l.viscous_coefficient_n_s_per_m,
            l.coulomb_force_n,
            l.static_force_n,
            l.stribeck_velocity_m_per_s,
        )
        .map_err(InvalidParams::Lugre)?;
        params.check_physical().map_err(InvalidParams::Lugre)?;
        if !(self.axis.moving_mass_kg.is_finite() && self.axis.moving_mass_kg > 0.0) {
            return Err(InvalidParams::Mass);
        }
        let e = &self.effects;
        let finite = |effect: K, vals: &[f64]| {
            if vals.iter().all(|v| v.is_finite()) {
                Ok(())
            } else {
                Err(InvalidParams::NotFinite { effect })
            }
        };
        let positive = |effect: K, field: &'static str, v: f64| {
            if v > 0.0 {
                Ok(())
            } else {
                Err(InvalidParams::NotPositive { effect, field })
            }
        };
        // a cosine series' terms and the half span they cover, checked (`None`: no terms)
        fn series<const N: usize>(
            effect: K,
            cosine_n: &[f64],
            half_span: Option<f64>,
            span_field: &'static str,
        ) -> Result<Option<(f64, [f64; N], usize)>, InvalidParams> {
            if cosine_n.is_empty() {
                return Ok(None);
            }
            if cosine_n.len() > N {
                return Err(InvalidParams::TooManyCosineTerms {
                    effect,
                    max: N,
                    got: cosine_n.len(),
                });
            }
            let span = half_span.unwrap_or(f64::NAN);
            if span.is_nan() || span <= 0.0 {
                return Err(InvalidParams::NotPositive {
                    effect,
                    field: span_field,
                });
            }
            let mut c = [0.0; N];
            c[..cosine_n.len()].copy_from_slice(cosine_n);
            Ok(Some((span, c, cosine_n.len())))
        }
        let mut effects = Effects::none();
        if let Some(a) = e.asymmetry {
            // a file without `static_ratio` (written before it existed) scales Fs with rc
            let rs = a.static_ratio.unwrap_or(a.coulomb_ratio);
            // absent: the same Stribeck velocity both ways
            let rvs = a.stribeck_velocity_ratio.unwrap_or(0.0);
            finite(K::Asymmetry, &[a.coulomb_ratio, rs, a.viscous_ratio, rvs])?;
            if [a.coulomb_ratio, rs, a.viscous_ratio, rvs]
                .iter()
                .any(|r| r.abs() >= 1.0)
            {
                return Err(InvalidParams::AsymmetryRatio);
            }
            effects.asymmetry = Some(fx::Asymmetry {
                coulomb_ratio: a.coulomb_ratio,
                static_ratio: rs,
                viscous_ratio: a.viscous_ratio,
                stribeck_velocity_ratio: rvs,
            });
        }
        if let Some(o) = e.offset {
            finite(K::Offset, &[o.force_n])?;
            effects.offset = Some(fx::Offset { force: o.force_n });
        }
        if let Some(l) = &e.load_dependence {
            // a file without `exponent` (written before it existed) is linear
            let exponent = l.exponent.unwrap_or(1.0);
            finite(
                K::LoadDependence,
                &[
                    l.coefficient_n_per_pa,
                    l.reference_pressure_sum_pa,
                    exponent,
                ],
            )?;
            positive(K::LoadDependence, "exponent", exponent)?;
            finite(K::LoadDependence, &l.cosine_n)?;
            let static_share = l.static_share.unwrap_or(1.0);
            finite(K::LoadDependence, &[static_share])?;
            let mut ld = fx::LoadDependence::power(
                l.coefficient_n_per_pa,
                l.reference_pressure_sum_pa,
                exponent,
            );
            if let Some((span, c, n)) = series::<{ fx::LOAD_TERMS }>(
                K::LoadDependence,
                &l.cosine_n,
                l.half_span_pa,
                "half_span_pa",
            )? {
                (ld.half_span, ld.cosine, ld.terms) = (span, c, n);
            }
            ld.static_share = static_share;
            effects.load_dependence = Some(ld);
        }
        if let Some(x) = &e.position_dependence {
            finite(K::PositionDependence, &[x.gradient_n_per_m, x.center_m])?;
            finite(K::PositionDependence, &x.cosine_n)?;
            let mut pd = fx::PositionDependence::linear(x.gradient_n_per_m, x.center_m);
            if let Some((span, c, n)) = series::<{ fx::POSITION_TERMS }>(
                K::PositionDependence,
                &x.cosine_n,
                x.half_span_m,
                "half_span_m",
            )? {
                (pd.half_span, pd.cosine, pd.terms) = (span, c, n);
            }
            effects.position_dependence = Some(pd);
        }
        if let Some(t) = e.temperature_dependence {
            finite(
                K::TemperatureDependence,
                &[
                    t.viscous_per_kelvin,
                    t.coulomb_per_kelvin,
                    t.reference_temperature_c,
                    t.stribeck_hersey_exponent,
                ],
            )?;
            // a curve that lifts sooner as the oil thins has no physical reading
            if t.stribeck_hersey_exponent < 0.0 {
                return Err(InvalidParams::Negative {
                    effect: K::TemperatureDependence,
                    field: "stribeck_hersey_exponent",
                });
            }
            effects.temperature_dependence = Some(fx::TemperatureDependence {
                viscous_per_kelvin: t.viscous_per_kelvin,
                coulomb_per_kelvin: t.coulomb_per_kelvin,
                reference_temperature: t.reference_temperature_c,
                stribeck_hersey_exponent: t.stribeck_hersey_exponent,
            });
        }
        if let Some(s) = e.stribeck_shape {
            finite(K::StribeckShape, &[s.exponent, s.tail_share, s.tail_scale])?;
            positive(K::StribeckShape, "exponent", s.exponent)?;
            positive(K::StribeckShape, "tail_scale", s.tail_scale)?;
            if !(0.0..=1.0).contains(&s.tail_share) {
                return Err(InvalidParams::ShareOutOfRange {
                    effect: K::StribeckShape,
                    field: "tail_share",
                });
            }
            effects.stribeck_shape = Some(fx::StribeckShape {
                exponent: s.exponent,
                tail_share: s.tail_share,
                tail_scale: s.tail_scale,
            });
        }
        if let Some(v) = e.viscous_power {
            finite(K::ViscousPower, &[v.exponent, v.reference_velocity_m_per_s])?;
            positive(K::ViscousPower, "exponent", v.exponent)?;
            positive(
                K::ViscousPower,
                "reference_velocity_m_per_s",
                v.reference_velocity_m_per_s,
            )?;
            effects.viscous_power = Some(fx::ViscousPower {
                exponent: v.exponent,
                reference_velocity: v.reference_velocity_m_per_s,
            });
        }
        if let Some(d) = e.dwell_stiction {
            finite(
                K::DwellStiction,
                &[
                    d.max_increase_n,
                    d.time_constant_s,
                    d.stick_velocity_m_per_s,
                    d.renewal_distance_m,
                ],
            )?;
            positive(K::DwellStiction, "renewal_distance_m", d.renewal_distance_m)?;
            positive(K::DwellStiction, "time_constant_s", d.time_constant_s)?;
            positive(
                K::DwellStiction,
                "stick_velocity_m_per_s",
                d.stick_velocity_m_per_s,
            )?;
            effects.dwell_stiction = Some(fx::DwellStiction {
                max_increase: d.max_increase_n,
                time_constant: d.time_constant_s,
                stick_velocity: d.stick_velocity_m_per_s,
                renewal_distance: d.renewal_distance_m,
                age_at_stick: d.age_at_stick,
                clock: d.clock,
                growth: d.growth,
            });
        }
        Ok(FrictionModel { params, effects })
    }

    /// Reads, parses and validates a parameter file; errors name the file (and line/column for
    /// syntax errors, the section and field for invalid values).
    pub fn read(path: &Path) -> Result<(Self, FrictionModel<f64>), ParamFileError> {
        let text = std::fs::read_to_string(path).map_err(|source| ParamFileError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        Self::parse(&text, path)
    }

    /// Parses and validates parameter-file text (`path` is only used in errors).
    pub fn parse(text: &str, path: &Path) -> Result<(Self, FrictionModel<f64>), ParamFileError> {
        let file: ParamFile = toml::from_str(text).map_err(|e| ParamFileError::Syntax {
            path: path.to_path_buf(),
            at: e.span().map(|s| {
                let start = (0..=s.start.min(text.len()))
                    .rev()
                    .find(|&i| text.is_char_boundary(i))
                    .unwrap_or(0);
                let before = &text[..start];
                let line = before.matches('\n').count() + 1;
                let column = start - before.rfind('\n').map_or(0, |i| i + 1) + 1;
                (line, column)
            }),
            message: e.message().to_string(),
        })?;
        let model = file.model().map_err(|problem| ParamFileError::Invalid {
            path: path.to_path_buf(),
            problem,
        })?;
        Ok((file, model))
    }

    /// Validates (as [`Self::read`] would) and writes the file: a set that would put a
    /// non-physical value into a controller is refused, naming the field, and nothing is written.
    pub fn write_checked(&self, path: &Path) -> Result<(), ParamFileError> {
        self.model().map_err(|problem| ParamFileError::NotWritten {
            path: path.to_path_buf(),
            problem,
        })?;
        self.write(path).map_err(|source| ParamFileError::Write {
            path: path.to_path_buf(),
            source,
        })
    }

    /// Writes the file with a header comment (unchecked: see [`Self::write_checked`]).
    pub fn write(&self, path: &Path) -> std::io::Result<()> {
        let body = toml::to_string_pretty(self).map_err(std::io::Error::other)?;
        let text = format!(
            "# lugre-servo parameter file. SI units, in the key names.\n\
             # sigma0 = bristle_stiffness, sigma1 = bristle_damping, sigma2 = viscous_coefficient,\n\
             # Fc = coulomb_force, Fs = static_force, vs = stribeck_velocity.\n\n{body}"
        );
        std::fs::write(path, text)
    }
}

/// A parameter file refused.
#[derive(Debug, thiserror::Error)]
pub enum ParamFileError {
    /// The file cannot be read.
    #[error("{}: cannot read: {source}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// Not TOML, or not the parameter file's shape (unknown or missing key, wrong type).
    #[error("{}{}: {message}", path.display(), at.map_or(String::new(), |(l, c)| format!(":{l}:{c}")))]
    Syntax {
        /// The file.
        path: PathBuf,
        /// 1-based line and column, when the parser gives them.
        at: Option<(usize, usize)>,
        /// The parser's words.
        message: String,
    },
    /// Read, but a value is invalid or non-physical.
    #[error("{}: {problem}", path.display())]
    Invalid {
        /// The file.
        path: PathBuf,
        /// Which section and field, and why.
        problem: InvalidParams,
    },
    /// Not written: a value is invalid or non-physical (nothing was written).
    #[error("{}: not written: {problem}", path.display())]
    NotWritten {
        /// The file.
        path: PathBuf,
        /// Which section and field, and why.
        problem: InvalidParams,
    },
    /// Writing failed.
    #[error("{}: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },
}

/// A parameter set a controller must not get: which section and field, and why.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum InvalidParams {
    /// `[lugre]`: the core's own check (finite, signs, Fs >= Fc, the physical range).
    #[error("[lugre] {0}")]
    Lugre(crate::friction::ParamError),
    /// `[axis] moving_mass_kg`.
    #[error("[axis] moving_mass_kg must be a finite number greater than zero")]
    Mass,
    /// An effect's value is NaN or infinite.
    #[error("[effects.{effect}] every value must be finite")]
    NotFinite {
        /// The effect's table.
        effect: EffectKind,
    },
    /// An effect's field must be positive.
    #[error("[effects.{effect}] {field} must be greater than zero")]
    NotPositive {
        /// The effect's table.
        effect: EffectKind,
        /// The key.
        field: &'static str,
    },
    /// An effect's field must be zero or more.
    #[error("[effects.{effect}] {field} must be zero or greater")]
    Negative {
        /// The effect's table.
        effect: EffectKind,
        /// The key.
        field: &'static str,
    },
    /// A share outside 0..=1.
    #[error("[effects.{effect}] {field} must be within 0..=1")]
    ShareOutOfRange {
        /// The effect's table.
        effect: EffectKind,
        /// The key.
        field: &'static str,
    },
    /// `[effects.asymmetry]` ratios outside (-1, 1) would reverse a direction's friction.
    #[error("[effects.asymmetry] ratios must be within (-1, 1)")]
    AsymmetryRatio,
    /// `[effects.position_dependence]` or `[effects.load_dependence]` `cosine_n` longer than
    /// the core holds.
    #[error("[effects.{effect}] cosine_n: at most {max} terms, got {got}")]
    TooManyCosineTerms {
        /// The effect whose terms they are.
        effect: EffectKind,
        /// The core's limit.
        max: usize,
        /// Terms in the file.
        got: usize,
    },
}
