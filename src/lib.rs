//! # lugre-servo
//!
//! LuGre friction modelling, identification and compensation for servo axes, `no_std` and
//! heap-free so the same code runs in a 1 kHz loop on a Cortex-M4F and in the host tools.
//!
//! ```
//! use lugre_servo::friction::{LugreParams, LugreState};
//!
//! // The paper's Table 2 (sigma0 = 3.9e9 N/m: stiff; the exact step is stable at 1 ms).
//! let params = LugreParams::<f32>::table2();
//! let mut state = LugreState::new();
//! let mut force = 0.0;
//! for _ in 0..100 {
//!     force = state.step(&params, 0.01, 1e-3); // 10 mm/s held for 1 ms
//! }
//! // After sliding settles, the model sits on its steady-state curve.
//! let fss = params.steady_state_force(0.01);
//! assert!((force - fss).abs() < 1e-3 * fss);
//! ```
//!
//! The 1 kHz controller, from settings to a running loop (a toy axis stands in for the
//! hydraulics here: the valve sets the velocity, 0.6 m/s at full opening, and the chambers
//! deliver the demanded force one period later):
//!
//! ```
//! use lugre_servo::axis::AxisGeometry;
//! use lugre_servo::control::{ControllerConfig, Features, Measurements, Reference};
//! use lugre_servo::friction::{FrictionModel, LugreParams};
//!
//! // settings: the axis, the identified friction model, what compensation runs
//! let model = FrictionModel::plain(LugreParams::<f32>::table2());
//! let settings = ControllerConfig::for_axis(&AxisGeometry::SIMULATED, model, Features::FULL);
//! // build: every field checked once (a zero period or a negative mass is refused by name)
//! let mut controller = settings.build().expect("valid settings");
//! let (area_a, area_b) = (settings.piston_area_m2, settings.annulus_area_m2);
//! let (mut x, mut force, h) = (0.25_f32, 0.0_f32, 1e-3_f32);
//! let mut worst = 0.0_f32;
//! for k in 0..3000 {
//!     let t = k as f32 * h;
//!     let w = 2.0 * core::f32::consts::PI * 0.5;
//!     let reference = Reference {
//!         position_m: 0.25 + 0.01 * (w * t).sin(),
//!         velocity_m_per_s: 0.01 * w * (w * t).cos(),
//!         acceleration_m_per_s2: -0.01 * w * w * (w * t).sin(),
//!     };
//!     let measured = Measurements {
//!         position_m: x,
//!         pressure_a_pa: (force + 100e5 * area_b) / area_a,
//!         pressure_b_pa: 100e5,
//!         temperature_c: None,
//!     };
//!     // one period: supervise -> estimate -> compensate -> cascade -> supervise
//!     let out = controller.tick(&measured, &reference);
//!     assert!(out.faults.is_empty() && out.valve_command.abs() <= 1.0);
//!     x += 0.6 * out.valve_command * h; // the toy axis
//!     force = out.force_demand_n;
//!     if t > 1.0 {
//!         worst = worst.max((reference.position_m - x).abs());
//!     }
//! }
//! // the toy has no force loop to speak of: ~0.2 mm on a 10 mm, 31 mm/s sine
//! assert!(worst < 5e-4, "tracking error {worst} m");
//! ```
//!
//! Modules, one concept each:
//! * [`friction`]: parameters, the LuGre model and its exact zero-order-hold step, extra effects.
//! * [`identify`]: the two-stage identification costs and the genetic algorithms.
//! * [`axis`]: the cylinder's geometry (areas, stroke, mass), shared by plant, controller and
//!   firmware.
//! * [`control`]: the 1 kHz controller: estimator, observer, feed-forward, cascade,
//!   refinement, faults.
//! * `params_file` (feature `params-file`, with `std`): the TOML parameter file the host
//!   tools write and read, and the firmware's build script turns into its model.
#![cfg_attr(not(feature = "std"), no_std)]

pub mod axis;
pub mod control;
pub mod friction;
pub mod identify;
pub mod link;
pub mod math;
#[cfg(feature = "params-file")]
pub mod params_file;
