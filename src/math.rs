//! The exponential of the per-period code, and which implementation the build uses.
//!
//! Every period the tick evaluates a handful of exponentials: the exact bristle step's decay
//! `e^{-sigma0 |v| h / g}` (twice: model and observer), the Stribeck curve
//! `e^{-(v/vs)^2}` (model, feed-forward, refinement). The generic model code calls them
//! through [`ModelFloat::model_exp`], so the f32 build for the MCU can choose its
//! implementation without touching the model:
//!
//! - default: `libm` (`expf`, `exp`), correctly rounded to within 1 ulp;
//! - feature `micromath`, f32 only: `micromath`'s approximation, cheaper on the Cortex-M4F
//!   and less accurate. What it costs in the tick and in friction force is measured in the
//!   README (firmware section);
//! - f64: `libm`'s `exp`, or with the `std` feature (the host) the platform's, as accurate
//!   and faster (measured: one realistic identification run 1.37 -> 1.16 s).
//!
//! Contract: for `x <= 0` the result is in `[0, 1]`, as the exact function's; the bristle step's
//! stability rests on it (its decay factor must not exceed one). `libm` keeps it by being
//! correctly rounded and monotone; the approximation is clamped.

use num_traits::Float;

/// Beyond this argument `e^{-x}` is below `2e-22`, under the rounding of every term it
/// multiplies in the model (f64's relative rounding is 1.1e-16): the per-period code skips the
/// exponential there and uses zero. It matters for the cost: while the axis slides, the
/// bristle step's `x = sigma0 |v| h / g` is in the hundreds and the Stribeck term
/// `(v / vs)^2` passes 50 at 7 vs.
pub const NEGLIGIBLE_DECAY_ARG: f64 = 50.0;

/// `e^{-x}` for `x >= 0`, zero where it is negligible (see [`NEGLIGIBLE_DECAY_ARG`]).
#[inline]
pub fn decay<T: ModelFloat>(x: T) -> T {
    // the constant converts exactly in both float types
    match T::from(NEGLIGIBLE_DECAY_ARG) {
        Some(limit) if x > limit => T::zero(),
        _ => (-x).model_exp(),
    }
}

/// A float type the model code runs on: [`Float`] plus the per-period exponential.
pub trait ModelFloat: Float {
    /// `e^self`, by the implementation this build chose (see the module docs).
    fn model_exp(self) -> Self;
}

impl ModelFloat for f64 {
    #[cfg(not(feature = "std"))]
    fn model_exp(self) -> Self {
        libm::exp(self)
    }

    /// On the host, the platform's exponential (glibc's, within 1 ulp as `libm`'s, and
    /// faster: the identification's cost evaluations spend a third of their time here).
    #[cfg(feature = "std")]
    fn model_exp(self) -> Self {
        self.exp()
    }
}

impl ModelFloat for f32 {
    #[cfg(not(feature = "micromath"))]
    fn model_exp(self) -> Self {
        libm::expf(self)
    }

    #[cfg(feature = "micromath")]
    fn model_exp(self) -> Self {
        let e = micromath::F32(self).exp().0;
        if self <= 0.0 {
            e.clamp(0.0, 1.0)
        } else {
            e
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The chosen f32 exponential against f64 over the range the tick uses (`-40..0`):
    /// relative error within 1e-6 with libm; micromath's is reported by the README's
    /// measurement and bounded here loosely enough to hold for an approximation of its class.
    #[test]
    fn f32_exponential_is_close_to_f64_over_the_ticks_range() {
        let mut worst = 0.0f64;
        for k in 0..=4000 {
            // the argument as f32 holds it: its own rounding is not the function's error
            let x = -40.0 * k as f32 / 4000.0;
            let exact = libm::exp(f64::from(x));
            let got = f64::from(x.model_exp());
            worst = worst.max(((got - exact) / exact).abs());
        }
        let bound = if cfg!(feature = "micromath") {
            1e-2
        } else {
            1e-6
        };
        println!("f32 model_exp relative error over -40..0: {worst:.2e}");
        assert!(worst < bound, "relative error {worst}");
        // beyond the cut the skipped value is below f64's rounding against one
        assert!(libm::exp(-NEGLIGIBLE_DECAY_ARG) < 1e-21);
        assert_eq!(decay(50.5f32), 0.0);
        assert_eq!(decay(1.0f64), libm::exp(-1.0));
        // the contract the bristle step relies on
        for k in 0..=100_000 {
            let x = -100.0 * k as f32 / 100_000.0;
            assert!((0.0..=1.0).contains(&x.model_exp()), "e^{x} out of [0, 1]");
        }
    }
}
