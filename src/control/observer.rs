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
//! 1 kHz for any stiffness; it is the model's own [`FrictionModel::step_driven`], which
//! projects `z^` onto the physical set `|z| <= Fs / sigma0` (near standstill the decay
//! `sigma0 |v| / g` vanishes while the correction keeps driving). Only a non-finite state counts
//! as divergence: the observer then resets and reports it.

use crate::friction::{FrictionModel, FrictionState, UnderConditions};

/// Observer state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Observer {
    /// Estimated bristle state (z^ \[m\]).
    pub state: FrictionState<f32>,
    /// Estimated friction force F^ \[N\].
    pub force: f32,
}

impl Observer {
    /// One step: `mean_velocity` [m/s] over the period, `velocity` [m/s] now, tracking error
    /// `error` \[m\], gain `k` [1/s], at the period's conditions evaluated for `model`
    /// ([`FrictionModel::under`]). Returns false (and resets) on divergence.
    pub fn update(
        &mut self,
        model: &FrictionModel<f32>,
        mean_velocity: f32,
        velocity: f32,
        error: f32,
        k: f32,
        c: &UnderConditions<f32>,
        h: f32,
    ) -> bool {
        // the model's own step, driven by the corrected velocity and projected onto
        // |z| <= Fs / sigma0 (see FrictionModel::step_driven)
        let force = model.step_driven_under(
            &mut self.state,
            mean_velocity - k * error,
            mean_velocity,
            velocity,
            c,
            h,
        );
        if !(force.is_finite() && self.state.z.is_finite()) {
            *self = Self::default();
            return false;
        }
        self.force = force;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::friction::LugreParams;

    /// Whatever the tracking error drives, the estimated bristle deflection stays within the
    /// physical set |z| <= Fs / sigma0, so the estimated friction at standstill stays within
    /// Fs plus the damping of the corrected bristle velocity, sigma1 k |e|.
    #[test]
    fn the_estimate_stays_within_the_physical_bound() {
        let model = FrictionModel::plain(LugreParams::<f32>::table2());
        let p = model.params;
        let c = model.under(&model.effects.reference_conditions());
        let mut o = Observer::default();
        for k in 0..20_000 {
            // at standstill with a large, alternating error: the correction drives hard
            let error = if (k / 3000) % 2 == 0 { 1e-3 } else { -1e-3 };
            assert!(o.update(&model, 0.0, 0.0, error, 200.0, &c, 1e-3));
            assert!(o.state.z.abs() <= p.static_force() / p.bristle_stiffness() * 1.0001);
            let bound = p.static_force() + p.bristle_damping() * 200.0 * 1e-3;
            assert!(o.force.abs() <= bound * 1.0001, "{} > {bound}", o.force);
        }
        // a NaN is divergence: reported and reset
        assert!(!o.update(&model, f32::NAN, 0.0, 0.0, 200.0, &c, 1e-3));
        assert_eq!(o, Observer::default());
    }
}
