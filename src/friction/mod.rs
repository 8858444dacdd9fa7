//! Friction physics: validated parameters, the LuGre model with its exact discretisation, and
//! the extra physical effects.

pub mod effects;
pub mod lugre;
pub mod model;
pub mod params;

pub use effects::{
    Conditions, DwellAge, DwellClock, DwellGrowth, EffectKind, Effects, UnknownEffect,
};
pub use lugre::{bristle_step, driven_bristle_step, BristleStep, LugreState};
pub use model::{ConstantLevels, CurveStep, FrictionModel, FrictionState, Levels, UnderConditions};
pub use params::{LugreParams, ParamError, ParamErrorKind, ParamField, ParamWarning};
