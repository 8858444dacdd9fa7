//! Friction feed-forward from the reference motion, blended with the observer.
//!
//! The reference is noise-free and known a period ahead, so a LuGre model driven by the
//! reference velocity gives a friction prediction that does not chatter at standstill
//! (compensating Coulomb friction from a noisy, delayed measured velocity makes real axes
//! vibrate at rest). The observer, driven by the measured motion, corrects it once the axis
//! moves clearly:
//!
//! ```text
//! F_comp = F_ff + w (F_obs - F_ff),   w = w_max s^2 / (1 + s^2),   s = |v_ref| / v_blend
//! ```
//!
//! so the blend is exactly the feed-forward at standstill and fades in smoothly with speed.
//!
//! While the reference holds still, the model's bristle deflection relaxes to zero with time
//! constant [`REST_RELAXATION_S`]: at rest the friction is whatever the position loop leaves
//! on the bristles, not the last sliding level. Without it the model kept feeding the last
//! move's Coulomb force through a whole dwell, the position integral wound up against it, and
//! the next move started with a kick (point-to-point moves ran up to 80 um ahead).

/// Time constant of the bristle relaxation while the reference is at rest \[s\].
pub const REST_RELAXATION_S: f32 = 0.05;

use crate::friction::{FrictionModel, FrictionState, UnderConditions};

/// Feed-forward state: the LuGre model along the reference.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Feedforward {
    /// Model state along the reference.
    pub state: FrictionState<f32>,
    /// Predicted friction \[N\].
    pub force: f32,
}

impl Feedforward {
    /// The bristle relaxation factor per period at rest, `exp(-h / REST_RELAXATION_S)` for
    /// period `h` \[s\]: computed once per configuration.
    pub fn rest_decay(period_s: f32) -> f32 {
        libm::expf(-period_s / REST_RELAXATION_S)
    }

    /// One step along the reference: mean reference velocity over the period and the
    /// reference velocity now [m/s], at the period's conditions evaluated for `model`
    /// ([`FrictionModel::under`]); `rest_decay` from [`Self::rest_decay`].
    pub fn update(
        &mut self,
        model: &FrictionModel<f32>,
        v_ref_mean: f32,
        v_ref: f32,
        c: &UnderConditions<f32>,
        h: f32,
        rest_decay: f32,
    ) -> f32 {
        if v_ref == 0.0 && v_ref_mean == 0.0 {
            self.state.z *= rest_decay;
        }
        // the model's own step: its bristle driven by the mean velocity itself
        self.force = model.step_driven_under(&mut self.state, v_ref_mean, v_ref_mean, v_ref, c, h);
        if !self.force.is_finite() {
            *self = Self::default();
        }
        self.force
    }
}

/// Blend weight of the observer (see the module docs).
pub fn observer_weight(v_ref: f32, v_blend: f32, w_max: f32) -> f32 {
    let s = v_ref / v_blend.max(1e-9);
    w_max * s * s / (1.0 + s * s)
}
