//! Parameter identification: the two-stage LuGre identification model and the genetic
//! algorithms that solve it, without heap or threads.
//!
//! * [`cost`]: the normalised fitness of the static stage (steady-state friction curve) and of
//!   the dynamic stage (a simulated dynamic response, same exact step as the firmware).
//! * [`ga`]: a real-coded genetic algorithm on the unit cube with three strategies
//!   (traditional, adaptive, improved adaptive), driven in ask/tell style so that the caller
//!   evaluates each generation however it likes (the host in parallel, the MCU in a loop).
//!
//! Genes live in `[0, 1]^N`; [`Bounds`] maps them to physical values.

pub mod cost;
pub mod ga;
pub mod simplex;

/// Search ranges: gene `g` in [0, 1] maps to `lo + g (hi - lo)` (or log-uniformly).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds<const N: usize> {
    /// Lower bounds (physical units).
    pub lo: [f64; N],
    /// Upper bounds.
    pub hi: [f64; N],
}

impl<const N: usize> Bounds<N> {
    /// Physical values of a gene vector (genes are clamped to [0, 1]).
    pub fn decode(&self, genes: &[f64; N]) -> [f64; N] {
        let mut out = [0.0; N];
        for i in 0..N {
            let g = genes[i].clamp(0.0, 1.0);
            out[i] = self.lo[i] + g * (self.hi[i] - self.lo[i]);
        }
        out
    }

    /// Genes of physical values (clamped into the range).
    pub fn encode(&self, values: &[f64; N]) -> [f64; N] {
        let mut out = [0.0; N];
        for i in 0..N {
            let span = self.hi[i] - self.lo[i];
            out[i] = if span > 0.0 {
                ((values[i] - self.lo[i]) / span).clamp(0.0, 1.0)
            } else {
                0.0
            };
        }
        out
    }
}

/// Table 1 search ranges of the static stage, in gene order
/// `[Fc [N], Fs - Fc [N], sigma2 [N s/m], vs [m/s]]`.
///
/// Table 1 bounds Fs itself by [0, 1000] N; we search the difference `Fs - Fc` (the quantity
/// the paper reports) over the same [0, 1000] N so every individual satisfies `Fs >= Fc`.
pub const STATIC_BOUNDS: Bounds<4> = Bounds {
    lo: [0.0, 0.0, 0.0, 0.001],
    hi: [1000.0, 1000.0, 50_000.0, 0.1],
};

/// Table 1 search ranges of the dynamic stage, `[sigma0 [N/m], sigma1 [N s/m]]`.
pub const DYNAMIC_BOUNDS: Bounds<2> = Bounds {
    lo: [0.0, 0.0],
    hi: [5e9, 1000.0],
};
