//! Where a model fails: residual statistics per motion regime and per operating-condition bin,
//! and the worst ones in words.

use super::inverse::Prepared;
use serde::Serialize;

/// Residual statistics of one regime.
#[derive(Clone, Debug, Serialize)]
pub struct RegimeStat {
    /// Regime, in words.
    pub name: String,
    /// Samples in the regime.
    pub samples: usize,
    /// Mean of (measured - model) force \[N\].
    pub mean_residual_n: f64,
    /// Mean residual in the sense of friction, `(F - F_hat) sign(v)` \[N\]: positive means the
    /// model under-predicts the friction there (moving samples only; 0 when stuck).
    pub friction_bias_n: f64,
    /// RMS residual \[N\].
    pub rms_residual_n: f64,
}

/// The residual analysis of one model.
#[derive(Clone, Debug, Serialize)]
pub struct RegimeReport {
    /// Per regime and bin.
    pub regimes: Vec<RegimeStat>,
    /// The worst regimes, in words.
    pub findings: Vec<String>,
}

struct Acc {
    name: String,
    n: usize,
    sum: f64,
    sum_f: f64,
    sum_sq: f64,
    moving: bool,
}

impl Acc {
    fn new(name: String, moving: bool) -> Self {
        Self {
            name,
            n: 0,
            sum: 0.0,
            sum_f: 0.0,
            sum_sq: 0.0,
            moving,
        }
    }
    fn add(&mut self, r: f64, dir: f64) {
        self.n += 1;
        self.sum += r;
        self.sum_f += r * dir;
        self.sum_sq += r * r;
    }
    fn stat(&self) -> RegimeStat {
        let n = self.n.max(1) as f64;
        RegimeStat {
            name: self.name.clone(),
            samples: self.n,
            mean_residual_n: self.sum / n,
            friction_bias_n: if self.moving { self.sum_f / n } else { 0.0 },
            rms_residual_n: (self.sum_sq / n).sqrt(),
        }
    }
}

fn bins(values: &[f64], mask: &[bool], k: usize) -> Vec<f64> {
    let mut v: Vec<f64> = values
        .iter()
        .zip(mask)
        .filter(|(_, m)| **m)
        .map(|(x, _)| *x)
        .collect();
    if v.is_empty() {
        return vec![];
    }
    v.sort_by(f64::total_cmp);
    (0..=k).map(|i| v[((v.len() - 1) * i) / k]).collect()
}

/// Residual analysis of a model's (unfiltered) force prediction.
pub fn analyse(p: &Prepared, filtered: &[f64], stribeck_velocity: f64) -> RegimeReport {
    let pf = filtered;
    let r: Vec<f64> = p.force.iter().zip(pf).map(|(f, q)| f - q).collect();
    let n = p.len();
    let v_stick = (0.2 * stribeck_velocity).max(2e-4);
    let moving: Vec<bool> = p.v.iter().map(|v| v.abs() >= v_stick).collect();
    let dir: Vec<f64> = p.v.iter().map(|v| v.signum()).collect();
    let mut accs = vec![
        Acc::new("stuck / pre-sliding".into(), false),
        Acc::new("in the Stribeck region".into(), true),
        Acc::new("sliding in +x".into(), true),
        Acc::new("sliding in -x".into(), true),
        Acc::new("accelerating".into(), true),
        Acc::new("decelerating".into(), true),
    ];
    for i in 0..n {
        let sp = p.v[i].abs();
        if sp < v_stick {
            accs[0].add(r[i], 0.0);
            continue;
        }
        if sp < 3.0 * stribeck_velocity {
            accs[1].add(r[i], dir[i]);
        } else if p.v[i] > 0.0 {
            accs[2].add(r[i], dir[i]);
        } else {
            accs[3].add(r[i], dir[i]);
        }
        if p.a[i] * p.v[i] > 0.0 {
            accs[4].add(r[i], dir[i]);
        } else {
            accs[5].add(r[i], dir[i]);
        }
    }
    let binned = |label: &str, unit: &str, scale: f64, values: &[f64], accs: &mut Vec<Acc>| {
        let edges = bins(values, &moving, 5);
        if edges.len() < 2 || edges[edges.len() - 1] - edges[0] <= 0.0 {
            return;
        }
        let base = accs.len();
        for w in edges.windows(2) {
            accs.push(Acc::new(
                format!("at {label} {:.3}..{:.3} {unit}", w[0] * scale, w[1] * scale),
                true,
            ));
        }
        for i in 0..n {
            if !moving[i] {
                continue;
            }
            let b = edges[1..edges.len() - 1]
                .iter()
                .filter(|e| values[i] > **e)
                .count();
            accs[base + b].add(r[i], dir[i]);
        }
    };
    binned("position", "m", 1.0, &p.x, &mut accs);
    if let Some(ps) = &p.pressure_sum {
        binned("pressure sum", "bar", 1e-5, ps, &mut accs);
    }
    if let Some(t) = &p.temperature {
        binned("oil temperature", "degC", 1.0, t, &mut accs);
    }
    binned("time", "s", 1.0, &p.t, &mut accs);
    let regimes: Vec<RegimeStat> = accs.iter().filter(|a| a.n > 0).map(Acc::stat).collect();
    let mut ranked: Vec<&RegimeStat> = regimes.iter().filter(|s| s.samples >= n / 100).collect();
    let key = |s: &RegimeStat| {
        if s.name.starts_with("stuck") {
            s.mean_residual_n.abs()
        } else {
            s.friction_bias_n.abs()
        }
    };
    ranked.sort_by(|a, b| key(b).total_cmp(&key(a)));
    let findings = ranked
        .iter()
        .take(3)
        .map(|s| {
            if s.name.starts_with("stuck") {
                format!(
                    "while stuck or in pre-sliding, the measured force is {:.1} N {} the model on average",
                    s.mean_residual_n.abs(),
                    if s.mean_residual_n > 0.0 { "above" } else { "below" }
                )
            } else {
                let b = s.friction_bias_n;
                format!(
                    "the model {} friction by {:.1} N {}",
                    if b > 0.0 { "under-predicts" } else { "over-predicts" },
                    b.abs(),
                    describe(&s.name)
                )
            }
        })
        .collect();
    RegimeReport { regimes, findings }
}

fn describe(name: &str) -> String {
    match name {
        "sliding in +x" => "when moving in +x".into(),
        "sliding in -x" => "when moving in -x".into(),
        "accelerating" => "while accelerating".into(),
        "decelerating" => "while decelerating".into(),
        other => other.to_string(),
    }
}
