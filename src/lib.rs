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
//! Modules, one concept each:
//! * [`friction`]: parameters, the LuGre model and its exact zero-order-hold step, extra effects.
//! * [`identify`]: the two-stage identification costs and the genetic algorithms.
//! * [`axis`]: the cylinder's geometry (areas, stroke, mass), shared by plant, controller and
//!   firmware.
//! * [`control`]: the 1 kHz controller: estimator, observer, feed-forward, cascade,
//!   refinement, faults.
#![cfg_attr(not(feature = "std"), no_std)]

pub mod axis;
pub mod control;
pub mod friction;
pub mod identify;
