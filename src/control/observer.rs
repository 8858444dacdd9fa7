//! LuGre friction observer (Canudas de Wit, Olsson, Astrom, Lischinsky 1995).
//!
//! ```text
//! dz^/dt = v - sigma0 |v| z^ / g(v) - k e        e = x - x_ref (tracking error)
//! F^     = sigma0 z^ + sigma1 dz^/dt + sigma2 v
//! ```
//!
//! The correction `-k e` makes the estimate error passive together with a PD position loop
//! (the paper's Lyapunov argument); it is discretised with the same exact zero-order-hold
//! step as the model ([`crate::friction::driven_bristle_step`]), so the observer is stable at
//! 1 kHz for any stiffness. Near standstill the decay `sigma0 |v| / g` vanishes while the
//! correction keeps driving, so `z^` is projected onto the physical set `|z| <= Fs / sigma0`
//! (the invariant set of the true state); only a non-finite state counts as divergence: the
//! observer then resets and reports it.

use crate::friction::{driven_bristle_step, Conditions, FrictionModel};

/// Observer state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Observer {
    /// Estimated bristle deflection z^ [m].
    pub z: f32,
    /// Estimated friction force F^ [N].
    pub force: f32,
}

impl Observer {
    /// One step: `mean_velocity` [m/s] over the period, `velocity` [m/s] now, tracking error
    /// `error` [m], gain `k` [1/s]. Returns false (and resets) on divergence.
    pub fn update(
        &mut self,
        model: &FrictionModel<f32>,
        mean_velocity: f32,
        velocity: f32,
        error: f32,
        k: f32,
        c: &Conditions<f32>,
        h: f32,
    ) -> bool {
        let l = model.levels(mean_velocity, c, 0.0);
        let g = model.stribeck_curve(mean_velocity, &l);
        let sigma0 = model.params.bristle_stiffness();
        let b = driven_bristle_step(
            self.z,
            mean_velocity - k * error,
            mean_velocity,
            sigma0,
            g,
            h,
        );
        let force = sigma0 * b.deflection
            + model.params.bristle_damping() * b.deflection_rate
            + model.viscous_force(velocity, &model.levels(velocity, c, 0.0));
        if !(b.deflection.is_finite() && force.is_finite()) {
            *self = Self::default();
            return false;
        }
        let bound = l.static_ / sigma0;
        let z = b.deflection.clamp(-bound, bound);
        // the force follows the projected state
        self.force = force + sigma0 * (z - b.deflection);
        self.z = z;
        true
    }
}
