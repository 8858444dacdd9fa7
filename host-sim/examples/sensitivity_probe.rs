//! How much of each sample's predicted force the measured motion leaves uncertain, on the
//! independent generator's records (session 21; see `Options::leave_out_unresolved`).
//!
//! The fitted baseline is driven by other readings of the same record: with `MODE=bw` (the
//! default) the position filtered at 0.4, 0.6, 1.6 and 2.5x its cutoff, with `MODE=q` the
//! filtered position quantised again with the encoder's grid shifted by 1/8..7/8 of a count.
//! `s_i^2`, the mean square of those predictions less the baseline's, averaged over 20 ms, is
//! the pipeline's own uncertainty at sample `i`. Per record it prints the floor (the true
//! model's error) and the baseline's, the same weighted by `1 / (1 + s_i^2 / mse)`, the share
//! of scored samples with `s_i^2 > K mse` (`K`, default 1) and how many of those are slower
//! than 5 mm/s, both errors over the samples left, and the four leading candidates' error cut
//! (plain / weighted; `*` where significant).
//!
//! `cargo run --release -p host-sim --example sensitivity_probe -- EFFECT|none FIRST N`
#[path = "../tests/generators/mod.rs"]
mod generators;
use generators::axis::random_record;
use host_sim::diagnose::{self, inverse::Prepared, Options};
use host_sim::record::Record;
use rayon::prelude::*;
use std::path::Path;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let eff = args.get(1).cloned().unwrap_or("none".into());
    let s0: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(500);
    let n: u64 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1);
    let effect = generators::axis::effect_named(&eff).unwrap_or_else(|e| panic!("{e}"));
    let out: Vec<String> = (s0..s0 + n)
        .collect::<Vec<_>>()
        .par_iter()
        .map(|&seed| probe(effect, seed))
        .collect();
    for s in out {
        print!("{s}");
    }
}

fn werr(p: &Prepared, w: &[f64], pred: &[f64]) -> f64 {
    let (mut r, mut f) = (0.0, 0.0);
    for i in 0..p.len() {
        r += w[i] * (p.force[i] - pred[i]).powi(2);
        f += w[i] * p.force[i].powi(2);
    }
    100.0 * (r / f).sqrt()
}

fn probe(effect: Option<&'static str>, seed: u64) -> String {
    let (text, axis) = random_record(effect, seed);
    let rec = Record::parse(&text, Path::new("probe.csv")).expect("generated record");
    // the probe weighs the plain baseline's spread itself (it is what the weights came from)
    let opts = Options {
        unweighted: true,
        ..Default::default()
    };
    let d = diagnose::diagnose(&rec, "probe.csv", &opts).expect("diagnosis");
    let p = &d.prepared;
    let base = &d.stages[0].fit;
    let q = host_sim::signal::encoder_resolution(&rec.x);
    let sm: Vec<f64> = if std::env::var("MODE").is_ok_and(|m| m == "q") {
        // the filtered motion quantised again with the encoder's grid shifted by 1/8..7/8 count
        let k = 4;
        let mut s2 = vec![0.0; p.len()];
        for j in 0..k {
            let off = (j as f64 + 0.5) / k as f64 * q;
            let mut alt = rec.clone();
            alt.x =
                p.x.iter()
                    .map(|x| ((x + off) / q).round() * q - off)
                    .collect();
            let pa = Prepared::new(&alt, "alt", Default::default()).expect("alt");
            let pred = p.filter(&base.model.predict(&pa));
            for (s, (a, b)) in s2.iter_mut().zip(pred.iter().zip(&base.prediction)) {
                *s += (a - b).powi(2) / k as f64;
            }
        }
        // smoothed over 20 ms
        let h = 10;
        (0..p.len())
            .map(|i| {
                let (a, b) = (i.saturating_sub(h), (i + h + 1).min(p.len()));
                s2[a..b].iter().sum::<f64>() / (b - a) as f64
            })
            .collect()
    } else {
        diagnose::prediction_spread(&rec, "probe.csv", Default::default(), p, &base.model).1
    };
    let m: f64 = p.weight.iter().sum();
    let mse = base.rss / m;
    // the diagnosis's weights without their floor, on the scored samples
    let w: Vec<f64> = diagnose::motion_weights(p, &base.prediction, &sm, 0.0)
        .iter()
        .zip(&p.weight)
        .map(|(f, w)| f * w)
        .collect();
    let truth = p.filter(&generators::axis::truth_force(&axis, p));
    let kk: f64 = std::env::var("K")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.0);
    let mask: Vec<f64> = (0..p.len())
        .map(|i| if sm[i] > kk * mse { 0.0 } else { p.weight[i] })
        .collect();
    let slow_out = (0..p.len())
        .filter(|&i| mask[i] == 0.0 && p.weight[i] > 0.0 && p.v[i].abs() < 5e-3)
        .count() as f64;
    let out = (0..p.len())
        .filter(|&i| mask[i] == 0.0 && p.weight[i] > 0.0)
        .count() as f64;
    let mask_line = format!(
        " out {:.0}% (slow {:.0}%) mfloor {:.2} mbase {:.2} |",
        100.0 * out / m,
        100.0 * slow_out / out.max(1.0),
        werr(p, &mask, &truth),
        werr(p, &mask, &base.prediction)
    );
    let wb = werr(p, &w, &base.prediction);
    let wt = werr(p, &w, &truth);
    let mut line = format!(
        "{seed:>6} q {:.1e} floor {:.2} base {:.2} | weighted floor {:.2} base {:.2} | wsum {:.2} |",
        q,
        p.rel_err_pct(&generators::axis::truth_force(&axis, p)),
        base.rel_err_pct,
        wt,
        wb,
        w.iter().sum::<f64>() / m
    );
    let mut cands: Vec<_> = d.stages[0]
        .candidates
        .iter()
        .filter_map(|c| c.fit.as_ref().map(|f| (c, f)))
        .collect();
    cands.sort_by(|a, b| {
        b.0.delta_bic
            .unwrap_or(f64::NEG_INFINITY)
            .total_cmp(&a.0.delta_bic.unwrap_or(f64::NEG_INFINITY))
    });
    line += &mask_line;
    for (c, f) in cands.iter().take(4) {
        let cut = 1.0 - f.rel_err_pct / base.rel_err_pct;
        let wc = 1.0 - werr(p, &w, &f.prediction) / wb;
        line += &format!(
            " {} {:.2}/{:.2}{}",
            &c.kind.name()[..6],
            cut,
            wc,
            if c.significant { "*" } else { "" }
        );
    }
    line + "\n"
}
