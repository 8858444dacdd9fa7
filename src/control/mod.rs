//! The 1 kHz servo control core, one concept per module:
//! [`estimator`] (velocity and acceleration), [`observer`] (LuGre friction observer),
//! [`feedforward`] (friction from the reference, blended with the observer), [`position`]
//! (position -> force -> valve cascade), [`refine`] (online RLS of Fc, Fs - Fc, sigma2),
//! [`dob`] (the model-free disturbance observer practitioners use, for comparison),
//! [`health`] (is the friction still the identified one?),
//! [`faults`], and [`controller`] which composes them.

pub mod controller;
pub mod dob;
pub mod estimator;
pub mod faults;
pub mod feedforward;
pub mod health;
pub mod observer;
pub mod position;
pub mod refine;

pub use controller::{Controller, ControllerConfig, Features, Measurements, Output, Reference};
pub use faults::Faults;
