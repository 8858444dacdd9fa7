//! The practitioners' table: static friction fitted in closed form, the baseline every LuGre
//! fit must beat.
//!
//! On the samples where the axis moves, the measured force is regressed on
//!
//! ```text
//! symmetric:   F = M a + Fc sign(v) + sigma2 v
//! asymmetric:  F = M a + Fc+ [v > 0] - Fc- [v < 0] + sigma2+ v+ + sigma2- v-
//! ```
//!
//! (the asymmetric table spans a constant offset too, since `[v > 0] + [v < 0] = 1` while
//! moving). Every column goes through the same parallel filter as the measured force, so the
//! tables are scored exactly like the dynamic models; `M >= 0` (or the user's mass).

use super::fit::box_solve;
use super::inverse::Prepared;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// One static table.
#[derive(Clone, Debug, Serialize)]
pub struct StaticFit {
    /// "static Coulomb + viscous" or "static asymmetric + offset".
    pub label: &'static str,
    /// Moving mass \[kg\].
    pub mass_kg: f64,
    /// Coulomb level moving forward (positive velocity) \[N\].
    pub coulomb_forward_n: f64,
    /// Coulomb level moving backward \[N\].
    pub coulomb_backward_n: f64,
    /// Viscous coefficient forward [N s/m].
    pub viscous_forward_n_s_per_m: f64,
    /// Viscous coefficient backward [N s/m].
    pub viscous_backward_n_s_per_m: f64,
    /// Relative force error over the moving samples [%].
    pub rel_err_pct: f64,
    /// Weighted residual sum of squares [N^2].
    #[serde(skip)]
    pub rss: f64,
}

/// Both tables.
#[derive(Clone, Debug, Serialize)]
pub struct StaticTables {
    /// Coulomb + viscous, one level for both directions.
    pub symmetric: StaticFit,
    /// Coulomb and viscous per direction (spans an offset).
    pub asymmetric: StaticFit,
}

/// Fits both tables to a prepared record.
pub fn fit(p: &Prepared, fixed_mass: Option<f64>) -> StaticTables {
    let sign: Vec<f64> = p.v.iter().map(|v| v.signum()).collect();
    let fwd: Vec<f64> = p.v.iter().map(|v| f64::from(u8::from(*v > 0.0))).collect();
    let bwd: Vec<f64> = p.v.iter().map(|v| -f64::from(u8::from(*v < 0.0))).collect();
    let v_fwd: Vec<f64> = p.v.iter().map(|v| v.max(0.0)).collect();
    let v_bwd: Vec<f64> = p.v.iter().map(|v| v.min(0.0)).collect();
    // the acceleration and the velocity come filtered with the record
    let f = p.filter_many(&[&sign, &fwd, &bwd, &v_fwd, &v_bwd]);
    let (a_f, v_f) = (&p.acceleration_filtered, &p.velocity_filtered);
    let target: Vec<f64> = match fixed_mass {
        Some(m) => p.force.iter().zip(a_f).map(|(y, a)| y - m * a).collect(),
        None => p.force.clone(),
    };
    let solve = |cols: &[&Vec<f64>]| -> (Vec<f64>, f64) {
        let with_mass = fixed_mass.is_none();
        let mut all: Vec<&Vec<f64>> = Vec::new();
        if with_mass {
            all.push(a_f);
        }
        all.extend_from_slice(cols);
        let k = all.len();
        let mut a = DMatrix::<f64>::zeros(k, k);
        let mut b = DVector::<f64>::zeros(k);
        let scale: Vec<f64> = all
            .iter()
            .map(|c| {
                (c.iter().zip(&p.weight).map(|(x, w)| w * x * x).sum::<f64>())
                    .sqrt()
                    .max(1e-300)
            })
            .collect();
        for i in 0..k {
            for j in i..k {
                let s: f64 = (0..p.len())
                    .map(|n| p.weight[n] * all[i][n] * all[j][n])
                    .sum::<f64>()
                    / (scale[i] * scale[j]);
                a[(i, j)] = s;
                a[(j, i)] = s;
            }
            b[i] = (0..p.len())
                .map(|n| p.weight[n] * all[i][n] * target[n])
                .sum::<f64>()
                / scale[i];
        }
        let lo: Vec<f64> = (0..k)
            .map(|i| {
                if with_mass && i == 0 {
                    0.0
                } else {
                    f64::NEG_INFINITY
                }
            })
            .collect();
        let hi = vec![f64::INFINITY; k];
        let x = box_solve(&a, &b, &lo, &hi);
        let theta: Vec<f64> = (0..k).map(|i| x[i] / scale[i]).collect();
        let rss: f64 = (0..p.len())
            .map(|n| {
                let pred: f64 = (0..k).map(|i| theta[i] * all[i][n]).sum();
                p.weight[n] * (target[n] - pred).powi(2)
            })
            .sum();
        let mut out = theta;
        if !with_mass {
            out.insert(0, fixed_mass.unwrap_or(0.0));
        }
        (out, rss)
    };
    let pct = |rss: f64| 100.0 * rss.sqrt() / p.force_norm;
    let (s, rss_s) = solve(&[&f[0], v_f]);
    let (a, rss_a) = solve(&[&f[1], &f[2], &f[3], &f[4]]);
    StaticTables {
        symmetric: StaticFit {
            label: "static Coulomb + viscous",
            mass_kg: s[0],
            coulomb_forward_n: s[1],
            coulomb_backward_n: s[1],
            viscous_forward_n_s_per_m: s[2],
            viscous_backward_n_s_per_m: s[2],
            rel_err_pct: pct(rss_s),
            rss: rss_s,
        },
        asymmetric: StaticFit {
            label: "static asymmetric + offset",
            mass_kg: a[0],
            coulomb_forward_n: a[1],
            coulomb_backward_n: a[2],
            viscous_forward_n_s_per_m: a[3],
            viscous_backward_n_s_per_m: a[4],
            rel_err_pct: pct(rss_a),
            rss: rss_a,
        },
    }
}
