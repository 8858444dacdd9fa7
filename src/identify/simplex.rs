//! Nelder-Mead simplex search on the unit cube, heap-free: the local search the improved GA
//! hands its gathered population to (see [`super::ga`]).
//!
//! Standard coefficients (reflection 1, expansion 2, contraction 1/2, shrink 1/2); points are
//! clamped to `[0, 1]^N`. The start simplex is `x0` and `x0 + step_k e_k` (or `- step_k` where
//! that would leave the cube). A run ends when the simplex has collapsed (every vertex within
//! [`COLLAPSED`] of the best in every gene) or the budget is spent. [`polish`] restarts it from
//! its best point with the first step sizes as long as a restart still lowers the cost (a
//! collapsed simplex can stall on a valley's wall; a restart re-opens it).

/// A vertex spread below which the simplex counts as collapsed (gene units).
pub const COLLAPSED: f64 = 1e-10;

/// Largest dimension the fixed-size simplex holds.
pub const MAX_DIM: usize = 7;

/// Result of a search.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Polished<const N: usize> {
    /// Best point.
    pub best: [f64; N],
    /// Its cost.
    pub cost: f64,
    /// Cost evaluations used.
    pub evaluations: usize,
}

fn clamp01<const N: usize>(mut x: [f64; N]) -> [f64; N] {
    for v in x.iter_mut() {
        *v = if v.is_finite() {
            v.clamp(0.0, 1.0)
        } else {
            0.5
        };
    }
    x
}

fn finite(c: f64) -> f64 {
    if c.is_nan() {
        f64::MAX
    } else {
        c
    }
}

/// One Nelder-Mead run from `x0` with start steps `step` and at most `budget` evaluations
/// (the start simplex's `N + 1` whatever the budget).
pub fn nelder_mead<const N: usize, F: FnMut(&[f64; N]) -> f64>(
    cost: &mut F,
    x0: &[f64; N],
    step: &[f64; N],
    budget: usize,
) -> Polished<N> {
    assert!(N >= 1 && N <= MAX_DIM, "simplex dimension");
    let mut evals = 0usize;
    let mut eval = |x: &[f64; N], evals: &mut usize| {
        *evals += 1;
        finite(cost(x))
    };
    let mut v = [([0.0; N], f64::MAX); MAX_DIM + 1];
    let x0 = clamp01(*x0);
    v[0] = (x0, eval(&x0, &mut evals));
    for k in 0..N {
        let mut x = x0;
        let s = step[k].abs().max(1e-12);
        x[k] = if x[k] + s <= 1.0 { x[k] + s } else { x[k] - s };
        let x = clamp01(x);
        v[k + 1] = (x, eval(&x, &mut evals));
    }
    let m = N + 1;
    // an iteration costs at most N + 2 evaluations (reflection, contraction, N shrinks)
    while evals + N + 2 <= budget {
        v[..m].sort_unstable_by(|a, b| a.1.total_cmp(&b.1));
        let spread = v[1..m]
            .iter()
            .flat_map(|(x, _)| x.iter().zip(v[0].0.iter()).map(|(a, b)| (a - b).abs()))
            .fold(0.0f64, f64::max);
        if spread < COLLAPSED {
            break;
        }
        let worst = v[N];
        let mut centroid = [0.0; N];
        for (x, _) in &v[..N] {
            for k in 0..N {
                centroid[k] += x[k] / N as f64;
            }
        }
        // the point centroid + t (worst - centroid)
        let along = |t: f64| {
            let mut x = [0.0; N];
            for k in 0..N {
                x[k] = centroid[k] + t * (worst.0[k] - centroid[k]);
            }
            clamp01(x)
        };
        let xr = along(-1.0);
        let cr = eval(&xr, &mut evals);
        if cr < v[0].1 {
            let xe = along(-2.0);
            let ce = eval(&xe, &mut evals);
            v[N] = if ce < cr { (xe, ce) } else { (xr, cr) };
        } else if cr < v[N - 1].1 {
            v[N] = (xr, cr);
        } else {
            let xc = along(if cr < worst.1 { -0.5 } else { 0.5 });
            let cc = eval(&xc, &mut evals);
            if cc < worst.1.min(cr) {
                v[N] = (xc, cc);
            } else {
                let b = v[0].0;
                for vertex in v[1..m].iter_mut() {
                    let mut x = [0.0; N];
                    for k in 0..N {
                        x[k] = b[k] + 0.5 * (vertex.0[k] - b[k]);
                    }
                    *vertex = (x, eval(&x, &mut evals));
                }
            }
        }
    }
    v[..m].sort_unstable_by(|a, b| a.1.total_cmp(&b.1));
    Polished {
        best: v[0].0,
        cost: v[0].1,
        evaluations: evals,
    }
}

/// Nelder-Mead from `x0`, restarted from its best point with the same start steps while a
/// restart lowers the cost by more than a relative `1e-9`, within `budget` evaluations in all.
pub fn polish<const N: usize, F: FnMut(&[f64; N]) -> f64>(
    mut cost: F,
    x0: &[f64; N],
    step: &[f64; N],
    budget: usize,
) -> Polished<N> {
    let mut result = nelder_mead(&mut cost, x0, step, budget);
    let mut used = result.evaluations;
    while used + 2 * N + 3 <= budget {
        let next = nelder_mead(&mut cost, &result.best, step, budget - used);
        used += next.evaluations;
        let better = next.cost < result.cost - 1e-9 * result.cost.abs();
        if next.cost < result.cost {
            result.best = next.best;
            result.cost = next.cost;
        }
        if !better {
            break;
        }
    }
    result.evaluations = used;
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rosenbrock on [-2, 2]^2 mapped to the unit square: optimum at (0.75, 0.75).
    fn rosen(x: &[f64; 2]) -> f64 {
        let (a, b) = (4.0 * x[0] - 2.0, 4.0 * x[1] - 2.0);
        (1.0 - a) * (1.0 - a) + 100.0 * (b - a * a) * (b - a * a)
    }

    #[test]
    fn finds_the_rosenbrock_minimum_and_stays_in_the_cube() {
        let mut calls = 0;
        let r = polish(
            |x: &[f64; 2]| {
                calls += 1;
                assert!(x.iter().all(|v| (0.0..=1.0).contains(v)));
                rosen(x)
            },
            &[0.1, 0.9],
            &[0.05, 0.05],
            5000,
        );
        assert!(
            (r.best[0] - 0.75).abs() < 1e-5 && (r.best[1] - 0.75).abs() < 1e-5,
            "{r:?}"
        );
        assert_eq!(r.evaluations, calls);
        assert!(r.evaluations <= 5000);
    }

    #[test]
    fn respects_the_budget_and_survives_nan() {
        let r = polish(|_: &[f64; 3]| f64::NAN, &[0.5; 3], &[0.1; 3], 50);
        assert!(r.evaluations <= 50);
        let r = nelder_mead(
            &mut |x: &[f64; 3]| x[0] + x[1] + x[2],
            &[0.5; 3],
            &[0.1; 3],
            2000,
        );
        assert!(r.best.iter().all(|v| *v < 1e-6), "{r:?}");
    }
}
