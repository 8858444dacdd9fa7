//! How visible a hidden effect is at the breakaway peaks of the independent generator's
//! records, departure by departure: the measured peak, the generator's true model and the
//! same without its effect (both driven by the measured motion through the pipeline, as the
//! noise floor is), the diagnosis's baseline and its fitted `dwell_stiction` candidate, and
//! that candidate's dwell clock against the rest the record shows. Per record: the rms
//! differences, and the rank correlation of the residual peaks (measured minus baseline,
//! signed by direction) with the rest time, and the three trends' evidence and growth: the
//! measured peaks' (`raw`), the baseline's residual peaks' (`resid`, what the decision asks
//! along with `raw`) and the friction peaks' (force less the baseline's inertia, `friction`);
//! on the line `FEAT`, the trends of other per-departure features tried: the residual's own
//! peak over the window (`rpeak`), the force, the friction and the residual up to 20 ms after
//! the axis reaches the departure speed (`early_*`), and the truth's dwell force along the
//! measured motion (`oracle`: what a perfect feature would show).
//!
//! `cargo run --release -p host-sim --example dwell_probe -- [EFFECT|none] [FIRST_SEED] [N] [-v]`
//! (defaults `dwell_stiction 20700 10`: the held-out dwell records; `-v` lists departures).
#[path = "../tests/generators/mod.rs"]
mod generators;
use generators::axis::{random_record, Axis, Shape};
use host_sim::diagnose::{self, Options};
use host_sim::record::Record;
use rayon::prelude::*;
use std::path::Path;

fn rms(a: &[f64], b: &[f64]) -> f64 {
    (a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>() / a.len().max(1) as f64).sqrt()
}

fn ranks(x: &[f64]) -> Vec<f64> {
    let mut idx: Vec<usize> = (0..x.len()).collect();
    idx.sort_by(|a, b| x[*a].total_cmp(&x[*b]));
    let mut r = vec![0.0; x.len()];
    for (k, i) in idx.iter().enumerate() {
        r[*i] = k as f64;
    }
    r
}
fn spearman(x: &[f64], y: &[f64]) -> f64 {
    let (a, b) = (ranks(x), ranks(y));
    let n = a.len() as f64;
    let ma = a.iter().sum::<f64>() / n;
    let mb = b.iter().sum::<f64>() / n;
    let c: f64 = a.iter().zip(&b).map(|(p, q)| (p - ma) * (q - mb)).sum();
    let va: f64 = a.iter().map(|p| (p - ma).powi(2)).sum();
    let vb: f64 = b.iter().map(|q| (q - mb).powi(2)).sum();
    c / (va * vb).sqrt()
}
/// r = a + dF (1 - exp(-t/tau)) best tau; dBIC vs r = a
fn rtrend(t: &[f64], r: &[f64]) -> (f64, f64) {
    let n = r.len() as f64;
    if r.len() < 3 {
        return (f64::NAN, f64::NAN);
    }
    let m = r.iter().sum::<f64>() / n;
    let rss0: f64 = r.iter().map(|x| (x - m).powi(2)).sum();
    let mut best = (f64::INFINITY, 0.0);
    for tau in [
        0.02, 0.04, 0.07, 0.1, 0.15, 0.2, 0.3, 0.5, 0.8, 1.2, 2.0, 4.0,
    ] {
        let g: Vec<f64> = t.iter().map(|x| 1.0 - (-x / tau).exp()).collect();
        let mg = g.iter().sum::<f64>() / n;
        let sgg: f64 = g.iter().map(|x| (x - mg).powi(2)).sum();
        let sgr: f64 = g.iter().zip(r).map(|(x, y)| (x - mg) * (y - m)).sum();
        let b = sgr / sgg.max(1e-12);
        let rss = rss0 - b * sgr;
        if rss < best.0 {
            best = (rss, b);
        }
    }
    (n * (rss0 / best.0).ln() - 2.0 * n.ln(), best.1)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let eff = args.get(1).cloned().unwrap_or("dwell_stiction".into());
    let s0: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(20700);
    let n: u64 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(10);
    let verbose = args.iter().any(|a| a == "-v");
    let effect = generators::axis::effect_named(&eff).unwrap_or_else(|e| panic!("{e}"));
    let out: Vec<String> = (s0..s0 + n).collect::<Vec<_>>().par_iter().map(|&seed| {
        let (text, axis) = random_record(effect, seed);
        let rec = Record::parse(&text, Path::new("x.csv")).unwrap();
        let opts = Options { skip_final_ranking: true, ..Default::default() };
        let d = diagnose::diagnose(&rec, "x.csv", &opts).unwrap();
        let p = &d.prepared;
        // the record's dwell clock lines up with the prepared samples
        assert_eq!(axis.dwell_trace.as_ref().map(|d| d.0.len()), Some(p.len()));
        let truth = |ax: &Axis| p.filter(&generators::axis::truth_force(ax, p));
        let tr = truth(&axis);
        let nod = truth(&Axis { shape: Shape::None, ..axis.clone() });
        let brk = &d.breakaway;
        let meas: Vec<f64> = brk.departures.iter().map(|e| e.peak_n).collect();
        let pt = brk.model_peaks(&tr);
        let pn = brk.model_peaks(&nod);
        let base = &d.stages[0];
        let pb = brk.model_peaks(&base.fit.prediction);
        let dw = base.candidates.iter().find(|c| c.kind == lugre_servo::friction::EffectKind::DwellStiction);
        let pd = dw.and_then(|c| c.fit.as_ref()).map(|f| brk.model_peaks(&f.prediction)).unwrap_or_default();
        // residual peak trend: r = d (meas - base) against the rest
        let r: Vec<f64> = brk.departures.iter().zip(&pb).map(|(e, b)| e.direction * (e.peak_n - b)).collect();
        let rests: Vec<f64> = brk.departures.iter().map(|e| e.rest_s).collect();
        let sp = spearman(&rests, &r);
        let (tb, tdf) = rtrend(&rests, &r);
        let mut s = format!(
            "{seed} {:?} M={:.0} s0={:.1e} Fs={:.0} {:?}\n  deps={} noise(meas-truth)={:.1} effect(truth-nodwell)={:.1} meas-base={:.1} meas-dwellfit={:.1} trend={:?} caution={:?}\n",
            axis.actuator, axis.mass_kg, axis.sigma0, axis.static_n, axis.shape, meas.len(), rms(&meas, &pt), rms(&pt, &pn), rms(&meas, &pb), rms(&meas, &pd),
            brk.trend.as_ref().map(|t| (t.increase_n, t.delta_bic)), dw.and_then(|c| c.caution.clone()));
        s += &format!("  residual peaks against the rest: rank correlation {sp:.2}, trend dBIC {tb:.1}, dF {tdf:.1} N\n");
        // the residual trend (its windows on the baseline's prediction; a gate of the decision
        // until session 25), and
        // the same trend on the friction: the force less the baseline's inertia, in the band
        let rt = brk.unexplained_trend(&base.fit.prediction);
        let inertia = p.filter(&p.a);
        let friction: Vec<f64> = p.force.iter().zip(&inertia).map(|(f, a)| f - base.fit.model.mass_kg * a).collect();
        let ft = brk.trend_of(&brk.model_peaks(&friction));
        s += &format!("  TRENDS raw={:.1} resid={:.1} (dF {:.1}+-{:.1}) friction={:.1} (dF {:.1}+-{:.1})\n",
            brk.trend.as_ref().map_or(f64::NAN, |t| t.delta_bic),
            rt.as_ref().map_or(f64::NAN, |t| t.delta_bic), rt.as_ref().map_or(f64::NAN, |t| t.increase_n), rt.as_ref().map_or(f64::NAN, |t| t.increase_ci_n),
            ft.as_ref().map_or(f64::NAN, |t| t.delta_bic), ft.as_ref().map_or(f64::NAN, |t| t.increase_n), ft.as_ref().map_or(f64::NAN, |t| t.increase_ci_n));
        let clock: Vec<f64> = match dw.and_then(|c| c.fit.as_ref()) {
            Some(f) => {
                let sim = f.model.simulate(p);
                brk.departures.iter().map(|e| sim.dwell[e.index.saturating_sub(40)..=e.index].iter().cloned().fold(0.0, f64::max)).collect()
            }
            None => vec![f64::NAN; brk.departures.len()],
        };
        if let Some(f) = dw.and_then(|c| c.fit.as_ref()) { s += &format!("  dwfit {:?}\n", f.model.friction.effects.dwell_stiction); }
        {
            // candidate per-departure features and their dwell trends
            use host_sim::diagnose::breakaway::DEPARTURE_SPEED;
            let fb = &base.fit.prediction;
            let mk = base.fit.model.mass_kg;
            let early = |e: &host_sim::diagnose::breakaway::Departure| {
                let fast = (e.index..e.window.end).find(|&k| p.v[k].abs() >= DEPARTURE_SPEED).unwrap_or(e.window.end);
                e.window.start..(fast + 20).min(e.window.end)
            };
            // a series' peaks over each departure's early window (signed like the peaks)
            let early_peaks = |f: &[f64]| -> Vec<f64> {
                brk.departures.iter().map(|e| e.direction * early(e).map(|k| e.direction * f[k]).fold(f64::NEG_INFINITY, f64::max)).collect()
            };
            let diff = |a: &[f64], b: &[f64]| -> Vec<f64> { a.iter().zip(b).map(|(x, y)| x - y).collect() };
            let residual = diff(&p.force, fb);
            let inertial: Vec<f64> = inertia.iter().map(|a| mk * a).collect();
            let feats: Vec<(&str, Vec<f64>)> = vec![
                ("rpeak", brk.model_peaks(&residual)),
                ("early_raw", early_peaks(&p.force)),
                ("early_fric", early_peaks(&diff(&p.force, &inertial))),
                ("early_resid", early_peaks(&residual)),
                ("oracle", brk.model_peaks(&diff(&tr, &nod))),
            ];
            s += "  FEAT";
            for (name, v) in &feats {
                let t = brk.trend_of(v);
                s += &format!(" {name}={:.1}/{:.0}", t.as_ref().map_or(f64::NAN, |t| t.delta_bic), t.as_ref().map_or(f64::NAN, |t| t.increase_n));
            }
            s += "\n";
        }
        if verbose {
            for (k, e) in brk.departures.iter().enumerate() {
                s += &format!("    clock={:6.3} rest={:6.3}", clock[k], e.rest_s);
                s += &format!(" dir={:+} meas={:8.1} truth={:8.1} nodwell={:8.1} base={:8.1} dwfit={:8.1}\n", e.direction, e.peak_n, pt[k], pn[k], pb[k], pd.get(k).copied().unwrap_or(f64::NAN));
            }
        }
        s
    }).collect();
    for s in out {
        print!("{s}");
    }
}
