//! Diagnosis across records: how friction changes with the conditions a rig varies
//! (chamber pressure, oil temperature, load, day), which no single record can show because
//! each holds one condition.
//!
//! Data path: each record -> its own LuGre fit (baseline plus a constant offset, which a
//! piston-area error makes proportional to pressure on a pressure-balanced rig) -> its friction
//! levels `Fc`, `sigma2` with honest intervals -> each level regressed on each condition across
//! records -> a trend with its interval and a verdict.
//!
//! **Per-record intervals** come from a block jackknife: the record is cut into
//! [`BLOCKS`] stretches of consecutive samples, the linear parameters are refitted with each
//! stretch left out, and `se^2 = (B - 1) / B sum (theta_k - theta_mean)^2`. Slow drifts and
//! correlated noise inside a record widen it, unlike the least-squares interval, which assumes
//! independent samples.
//!
//! **Trends** are weighted least squares of a level on a condition with random effects: each
//! record weighs `1 / (se_i^2 + tau^2)`, where `tau^2` is the scatter between records beyond
//! their own intervals (model error that differs from record to record, which no interval from
//! within one record can see), chosen by the Paule-Mandel rule: the weighted residuals of the
//! line must scatter as their weights say (`Q(tau^2) = n - 2`). The slope's 95 % interval uses
//! Student's t with `n - 2` degrees of freedom; a trend is **significant** when that interval
//! excludes zero. The `across_records` benchmark measures how often that is right.

use super::fit::{self, Param};
use super::inverse::{AxisModel, Prepared};
use super::{baseline, fit::add_effect, Options};
use crate::record::Record;
use rayon::prelude::*;
use serde::Serialize;

/// Blocks of the jackknife.
pub const BLOCKS: usize = 8;

/// One record's friction levels and conditions.
#[derive(Clone, Debug, Serialize)]
pub struct RecordLevels {
    /// The record's name.
    pub name: String,
    /// Conditions (name, value): `pressure_bar` and `temperature_c` from the data, numeric
    /// `# key=value` metadata.
    pub conditions: Vec<(String, f64)>,
    /// The levels: (name, value, standard error).
    pub levels: Vec<(String, f64, f64)>,
    /// The record's fit error [%].
    pub rel_err_pct: f64,
}

impl RecordLevels {
    /// A level's (value, standard error).
    pub fn level(&self, name: &str) -> Option<(f64, f64)> {
        self.levels.iter().find(|l| l.0 == name).map(|l| (l.1, l.2))
    }
    /// A condition's value.
    pub fn condition(&self, name: &str) -> Option<f64> {
        self.conditions.iter().find(|c| c.0 == name).map(|c| c.1)
    }
}

/// A friction level against a condition, across records.
#[derive(Clone, Debug, Serialize)]
pub struct Trend {
    /// The level ("coulomb_force_n", "viscous_coefficient_n_s_per_m").
    pub level: String,
    /// The condition ("pressure_bar", ...).
    pub condition: String,
    /// Slope [level unit per condition unit].
    pub slope: f64,
    /// 95 % interval of the slope.
    pub ci_low: f64,
    /// 95 % interval of the slope.
    pub ci_high: f64,
    /// Level at the records' mean condition.
    pub mean_level: f64,
    /// Run-to-run scatter beyond each record's interval (standard deviation).
    pub scatter: f64,
    /// The interval excludes zero.
    pub significant: bool,
}

impl Trend {
    /// The verdict in words, e.g. "Coulomb friction rises 0.4 N per bar (0.3..0.5)".
    pub fn sentence(&self) -> String {
        let (what, unit) = match self.level.as_str() {
            "coulomb_force_n" => ("Coulomb friction", "N"),
            "viscous_coefficient_n_s_per_m" => ("viscous friction", "N s/m"),
            other => (other, ""),
        };
        let per = self
            .condition
            .rsplit('_')
            .next()
            .filter(|u| ["bar", "c", "n", "kg", "day"].contains(u))
            .map(|u| if u == "c" { "degC" } else { u })
            .unwrap_or("unit of ");
        let per = if per == "unit of " {
            format!("unit of {}", self.condition)
        } else {
            per.to_string()
        };
        if self.significant {
            format!(
                "{what} {} {} {unit} per {per} (95 %: {}..{})",
                if self.slope > 0.0 { "rises" } else { "falls" },
                crate::timing::sig3(self.slope.abs()),
                crate::timing::sig3(self.ci_low),
                crate::timing::sig3(self.ci_high)
            )
        } else {
            format!(
                "{what} shows no significant dependence on {} (slope {} {unit} per {per}, 95 %: {}..{})",
                self.condition,
                crate::timing::sig3(self.slope),
                crate::timing::sig3(self.ci_low),
                crate::timing::sig3(self.ci_high)
            )
        }
    }
}

/// The analysis across records.
#[derive(Clone, Debug, Serialize)]
pub struct Across {
    /// Each record's levels.
    pub records: Vec<RecordLevels>,
    /// Each level against each condition that varies.
    pub trends: Vec<Trend>,
}

/// The levels reported per record.
const LEVELS: [Param; 2] = [Param::Coulomb, Param::Viscous];

/// Fits one record: baseline, plus an offset, levels with block-jackknife errors.
pub fn record_levels(rec: &Record, name: &str, opts: &Options) -> Result<RecordLevels, String> {
    let p = Prepared::new(rec, name, opts.protocol)?;
    let n_eff = fit::effective_samples(&p, opts.protocol.parallel_cutoff_hz);
    let fixed_mass = opts.mass_kg;
    let base = baseline(&p, opts, n_eff);
    let with_offset = fit::refit(
        &add_effect(&base.model, "offset", &p, 0.0),
        &p,
        fixed_mass,
        n_eff,
    );
    let f = if with_offset.rss < base.rss {
        with_offset
    } else {
        base
    };
    let model: AxisModel = f.model;
    // block jackknife over stretches of the record
    let n = p.len();
    let fits: Vec<Vec<f64>> = (0..BLOCKS)
        .into_par_iter()
        .map(|k| {
            let mut q = p.clone();
            let (a, b) = (k * n / BLOCKS, (k + 1) * n / BLOCKS);
            q.weight[a..b].fill(0.0);
            let g = fit::refit(
                &model,
                &q,
                fixed_mass,
                n_eff * (BLOCKS - 1) as f64 / BLOCKS as f64,
            );
            LEVELS.iter().map(|l| fit::value_of(&g.model, *l)).collect()
        })
        .collect();
    let levels = LEVELS
        .iter()
        .enumerate()
        .map(|(j, l)| {
            let vals: Vec<f64> = fits.iter().map(|v| v[j]).collect();
            let m = crate::stats::mean(&vals);
            let b = BLOCKS as f64;
            let jackknife =
                ((b - 1.0) / b * vals.iter().map(|v| (v - m).powi(2)).sum::<f64>()).sqrt();
            // never narrower than the least-squares interval (a block refit that does not move
            // would otherwise claim a zero error)
            let ls = f.estimate(*l).map_or(0.0, |e| e.std_error);
            let value = fit::value_of(&model, *l);
            let floor = 1e-9 * value.abs().max(1e-12);
            (l.label().to_string(), value, jackknife.max(ls).max(floor))
        })
        .collect();
    let mut conditions = Vec::new();
    if let Some(s) = &p.pressure_sum {
        conditions.push(("pressure_bar".to_string(), crate::stats::mean(s) / 1e5));
    }
    if let Some(t) = &p.temperature {
        conditions.push(("temperature_c".to_string(), crate::stats::mean(t)));
    }
    for (k, v) in &rec.meta {
        if let Ok(x) = v.parse::<f64>() {
            if x.is_finite() && !conditions.iter().any(|c| &c.0 == k) {
                conditions.push((k.clone(), x));
            }
        }
    }
    Ok(RecordLevels {
        name: name.to_string(),
        conditions,
        levels,
        rel_err_pct: f.rel_err_pct,
    })
}

/// Analyses records of one axis taken under different conditions.
pub fn analyse(records: &[(String, Record)], opts: &Options) -> Result<Across, String> {
    if records.len() < 3 {
        return Err(format!(
            "diagnosis across records needs at least 3 records, got {}",
            records.len()
        ));
    }
    let levels: Vec<RecordLevels> = records
        .iter()
        .map(|(name, rec)| record_levels(rec, name, opts))
        .collect::<Result<_, _>>()?;
    Ok(Across {
        trends: trends(&levels),
        records: levels,
    })
}

/// Every level against every condition that all records carry and that varies.
pub fn trends(levels: &[RecordLevels]) -> Vec<Trend> {
    let mut names: Vec<String> = levels[0].conditions.iter().map(|c| c.0.clone()).collect();
    names.retain(|c| {
        let vals: Vec<f64> = levels.iter().filter_map(|r| r.condition(c)).collect();
        if vals.len() != levels.len() {
            return false;
        }
        let lo = vals.iter().cloned().fold(f64::INFINITY, f64::min);
        let hi = vals.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        hi - lo > 1e-9 * hi.abs().max(1.0) && hi - lo > 0.05 * hi.abs().max(lo.abs())
    });
    let mut out = Vec::new();
    for c in &names {
        for l in LEVELS {
            let pts: Vec<(f64, f64, f64)> = levels
                .iter()
                .filter_map(|r| {
                    let (y, se) = r.level(l.label())?;
                    Some((r.condition(c)?, y, se))
                })
                .collect();
            if let Some(t) = random_effects_slope(&pts) {
                out.push(Trend {
                    level: l.label().to_string(),
                    condition: c.clone(),
                    slope: t.0,
                    ci_low: t.1,
                    ci_high: t.2,
                    mean_level: t.3,
                    scatter: t.4,
                    significant: t.1 > 0.0 || t.2 < 0.0,
                });
            }
        }
    }
    out
}

/// Random-effects weighted regression `y = a + b x` over points (x, y, se): returns
/// (b, b_low, b_high, mean y, tau). `tau^2` by Paule-Mandel: the root of `Q(tau^2) = n - 2`
/// (Q falls as tau^2 grows; bisection on a log scale), zero when the points already scatter
/// no more than their intervals say.
fn random_effects_slope(pts: &[(f64, f64, f64)]) -> Option<(f64, f64, f64, f64, f64)> {
    let n = pts.len();
    if n < 3 {
        return None;
    }
    let wls = |tau2: f64| {
        let w: Vec<f64> = pts
            .iter()
            .map(|(_, _, se)| 1.0 / (se * se + tau2).max(1e-300))
            .collect();
        let sw: f64 = w.iter().sum();
        let xm = pts.iter().zip(&w).map(|(p, w)| w * p.0).sum::<f64>() / sw;
        let ym = pts.iter().zip(&w).map(|(p, w)| w * p.1).sum::<f64>() / sw;
        let sxx: f64 = pts
            .iter()
            .zip(&w)
            .map(|(p, w)| w * (p.0 - xm).powi(2))
            .sum();
        let sxy: f64 = pts
            .iter()
            .zip(&w)
            .map(|(p, w)| w * (p.0 - xm) * (p.1 - ym))
            .sum();
        let b = sxy / sxx;
        let q: f64 = pts
            .iter()
            .zip(&w)
            .map(|(p, w)| w * (p.1 - ym - b * (p.0 - xm)).powi(2))
            .sum();
        (b, ym, sxx, q, w, sw)
    };
    let dof = n as f64 - 2.0;
    let q_of = |tau2: f64| wls(tau2).3;
    let tau2 = if q_of(0.0) <= dof {
        0.0
    } else {
        // bracket: Q(hi) < dof once tau^2 exceeds the spread of the levels themselves
        let spread = pts.iter().map(|p| p.1 * p.1).sum::<f64>().max(1e-300);
        let (mut lo, mut hi) = (1e-12 * spread, spread);
        while q_of(hi) > dof && hi < 1e12 * spread {
            hi *= 10.0;
        }
        for _ in 0..100 {
            let mid = (lo * hi).sqrt();
            if q_of(mid) > dof {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        hi
    };
    let (b, ym, sxx, q, _, _) = wls(tau2);
    if !(sxx > 0.0 && b.is_finite()) {
        return None;
    }
    // the slope's standard error: from the weights, inflated when the points scatter more
    // than their weights say (Knapp-Hartung; 1 once tau^2 solves Q = n - 2)
    let scale = (q / (n as f64 - 2.0)).max(1.0);
    let se_b = (scale / sxx).sqrt();
    let t = student_t95(n - 2);
    Some((b, b - t * se_b, b + t * se_b, ym, tau2.sqrt()))
}

/// Two-sided 95 % quantile of Student's t with `df` degrees of freedom (infinite for none).
pub fn student_t95(df: usize) -> f64 {
    use statrs::distribution::{ContinuousCDF, StudentsT};
    StudentsT::new(0.0, 1.0, df as f64).map_or(f64::INFINITY, |t| t.inverse_cdf(0.975))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_and_interval_of_a_clean_line() {
        let pts: Vec<(f64, f64, f64)> = (0..6)
            .map(|i| {
                (
                    i as f64,
                    2.0 + 0.5 * i as f64 + 0.01 * ((i * 7 % 3) as f64 - 1.0),
                    0.01,
                )
            })
            .collect();
        let (b, lo, hi, _, _) = random_effects_slope(&pts).unwrap();
        assert!(
            (b - 0.5).abs() < 0.02 && lo < 0.5 && hi > 0.5 && lo > 0.4,
            "{b} {lo} {hi}"
        );
    }

    #[test]
    fn scatter_beyond_the_intervals_widens_the_slope_interval() {
        // the points scatter by ~1 while claiming 0.01: tau absorbs it, no false trend
        let ys = [3.0, 1.5, 2.8, 1.2, 2.9, 1.4];
        let pts: Vec<(f64, f64, f64)> = ys
            .iter()
            .enumerate()
            .map(|(i, y)| (i as f64, *y, 0.01))
            .collect();
        let (_, lo, hi, _, tau) = random_effects_slope(&pts).unwrap();
        assert!(tau > 0.5 && lo < 0.0 && hi > 0.0, "{lo} {hi} {tau}");
    }

    #[test]
    fn student_quantiles_match_the_tables() {
        assert!((student_t95(1) - 12.706).abs() < 1e-3);
        assert!((student_t95(3) - 3.182).abs() < 1e-3);
        assert!((student_t95(30) - 2.042).abs() < 1e-3);
        assert!(student_t95(0).is_infinite());
    }

    #[test]
    fn sentences_read_like_an_engineer_would_say_them() {
        let t = Trend {
            level: "coulomb_force_n".into(),
            condition: "pressure_bar".into(),
            slope: 0.4,
            ci_low: 0.3,
            ci_high: 0.5,
            mean_level: 10.0,
            scatter: 0.0,
            significant: true,
        };
        assert_eq!(
            t.sentence(),
            "Coulomb friction rises 0.4 N per bar (95 %: 0.3..0.5)"
        );
    }
}
