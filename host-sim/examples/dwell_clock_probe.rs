//! What a dwell clock read off the measured motion can explain on the independent
//! generator's dwell records, against the floor that reads the record's own clock. Four
//! modes:
//!
//! - `truth [FIRST_SEED] [N]`: the generator's own shape with its clock replaced by a
//!   body-speed clock (stick under 0.05 mm/s; the speed over 1..100 ms; forgotten over a
//!   renewal distance or at once), scored like the floor (session 19: none comes near it);
//! - `fit [FIRST_SEED] [N]`: our dwell term refitted (linear parameters) at every point of a
//!   grid of time constant, renewal distance and stick speed, best point per stick speed, age
//!   rule and clock (the body's speed or the contact's slip);
//! - `gaps SEED [STICK] [WINDOW] [--restart]`: where one body-speed clock parts from the
//!   record's, the 25 stretches of 50 ms that differ most in the dwell force where the axis
//!   moves;
//! - `ages SEED [--resets]`: the diagnosis's own dwell candidate run along the record, its age
//!   at each departure from a rest against the record's clock there, and with `--resets` the
//!   motion where its age restarts while the record's runs on (session 91);
//! - `force [FIRST_SEED] [N]`: the generator's own shape on twelve slip clocks read off the
//!   measured motion and force (LuGre's `|v| |F| / F_s`, or the body's speed less the
//!   bristle's `dF/dt / sigma0`), each through the generator's own clock (the record's law),
//!   and last on the generator's aging law read off the body's filtered speed (session 97, issue's axes: on today's law the
//!   best of the twelve reaches 1.2x the floor on 4 of 20 records; on the aging law,
//!   `--dwell-law aging`, the aging clock on 19 of 20);
//! - `trace SEED FROM_S TO_S [EVERY]`: the record's age beside the measured motion and
//!   friction, every EVERY-th sample (default 5).
//!
//! `cargo run --release -p host-sim --example dwell_clock_probe -- MODE ...` (seeds default to
//! 1700 and 10: the first calibration dwell records); `--axes issue` draws the axes issue 9
//! describes (`generators::axis::Axes::Issue`); `--dwell-law aging` ages the records' contacts
//! by the aging law (`generators::axis::DwellLaw`).
#[path = "../tests/generators/mod.rs"]
mod generators;
use generators::axis::{Axes, Axis, DwellLaw, DwellTrace, Shape};
use host_sim::diagnose::fit::Fit;
use host_sim::diagnose::inverse::Prepared;
use host_sim::diagnose::{self, fit, Diagnosis, Options};
use host_sim::record::Record;
use lugre_servo::friction::effects::{DwellAge, DwellClock, DwellStiction};
use lugre_servo::friction::EffectKind;
use rayon::prelude::*;
use std::path::Path;

/// A dwell clock read off the measured motion [s per sample]: it runs while the body's speed
/// (over the last `window` samples; 1: the step's mean velocity) is under `stick` [m/s], and
/// once it moves is forgotten over `renewal` [m] of travel, or at once (`None`).
fn body_clock(p: &Prepared, stick: f64, window: usize, renewal: Option<f64>) -> Vec<f64> {
    let mut age = 0.0f64;
    (0..p.len())
        .map(|i| {
            let v = if window == 1 {
                p.v_step[i]
            } else {
                (p.x[i] - p.x[i.saturating_sub(window)]) / (window as f64 * p.dt)
            }
            .abs();
            age = if v < stick {
                age + p.dt
            } else {
                renewal.map_or(0.0, |d| age * (-v * p.dt / d).exp())
            };
            age
        })
        .collect()
}

/// The generator's renewal distance of a dwell axis [m].
fn renewal_of(axis: &Axis) -> f64 {
    match axis.shape {
        Shape::Dwell { renewal_m, .. } => renewal_m,
        _ => unreachable!("a dwell record"),
    }
}

/// Which records a study draws: the axes (`--axes`) and the dwell law (`--dwell-law`).
#[derive(Clone, Copy)]
struct Draw {
    axes: Axes,
    law: DwellLaw,
}

fn record(seed: u64, draw: Draw) -> (Record, Axis) {
    let (text, axis) = generators::axis::dwell_record(seed, draw.axes, draw.law);
    (Record::parse(&text, Path::new("x.csv")).unwrap(), axis)
}

/// The record's first stage, its candidates ranked but not settled (the probe reads the
/// baseline and the dwell candidate as the search left them).
fn first_stage(rec: &Record) -> Diagnosis {
    let opts = Options {
        skip_final_ranking: true,
        ..Default::default()
    };
    diagnose::diagnose(rec, "x.csv", &opts).unwrap()
}

/// The first stage's dwell candidate's fit (`None` where it was skipped).
fn dwell_candidate(d: &Diagnosis) -> Option<&Fit> {
    d.stages[0]
        .candidates
        .iter()
        .find(|c| c.kind == EffectKind::DwellStiction)
        .and_then(|c| c.fit.as_ref())
}

/// The generator's dwell force at an age \[N\] (its Hill law, [`Shape::Dwell`]).
fn generator_dwell_force(axis: &Axis) -> impl Fn(f64) -> f64 {
    let Shape::Dwell {
        increase_n,
        tau_s,
        hill,
        ..
    } = axis.shape
    else {
        unreachable!("a dwell record")
    };
    move |age: f64| {
        let t = age.max(0.0).powf(hill);
        increase_n * t / (t + tau_s.powf(hill))
    }
}

/// `truth` and `fit`: per record, a header (floor, baseline, our dwell candidate) and the
/// mode's lines.
fn per_record(seed: u64, fit_mode: bool, draw: Draw) -> String {
    let (rec, axis) = record(seed, draw);
    let d = first_stage(&rec);
    let p = &d.prepared;
    let base = &d.stages[0].fit;
    let cand = dwell_candidate(&d).map_or(f64::NAN, |f| f.rel_err_pct);
    let mut s = format!(
        "{seed} {:?} {:?}\n  floor {:.2} %, baseline {:.2} %, dwell candidate {cand:.2} %\n",
        axis.actuator,
        axis.shape,
        generators::axis::truth_error_pct(&axis, p),
        base.rel_err_pct
    );
    if !fit_mode {
        let stick = 5e-5;
        let own = renewal_of(&axis);
        let clocks = [
            (1, own),
            (20, 1e-5),
            (20, 1e-4),
            (50, 1e-6),
            (50, 1e-5),
            (50, 1e-4),
            (100, 1e-5),
            (100, 1e-4),
        ];
        for (window, renewal) in clocks {
            let with = |trace: Vec<f64>| {
                let a = Axis {
                    dwell_trace: Some(DwellTrace(std::sync::Arc::new(trace))),
                    ..axis.clone()
                };
                generators::axis::truth_error_pct(&a, p)
            };
            s += &format!(
                "  truth with a body-speed clock (stick {stick:.0e}, window {window} ms, renewal {renewal:.0e}): decaying {:.2} %, restarting {:.2} %\n",
                with(body_clock(p, stick, window, Some(renewal))),
                with(body_clock(p, stick, window, None))
            );
        }
        return s;
    }
    let n_eff = fit::effective_samples(p, 20.0);
    for (stick, age_at_stick, clock) in [2e-5, 5e-5, 2e-4]
        .into_iter()
        .flat_map(|v| DwellAge::ALL.map(|a| (v, a)))
        .flat_map(|(v, a)| DwellClock::ALL.map(|c| (v, a, c)))
    {
        let mut best = (f64::INFINITY, 0.0, 0.0, 0.0);
        for tau in [0.05, 0.1, 0.2, 0.35, 0.5, 1.0, 2.0, 5.0] {
            for renewal in [1e-5, 1e-4, 3e-4, 1e-3, 3e-3, 1e-2] {
                let mut m = base.model;
                m.friction.effects.dwell_stiction = Some(DwellStiction {
                    max_increase: 0.0,
                    time_constant: tau,
                    stick_velocity: stick,
                    renewal_distance: renewal,
                    age_at_stick,
                    clock,
                    growth: lugre_servo::friction::DwellGrowth::Exponential,
                });
                let f = fit::refit(&m, p, None, n_eff);
                if f.rel_err_pct < best.0 {
                    let dwell = f.model.friction.effects.dwell_stiction;
                    best = (
                        f.rel_err_pct,
                        tau,
                        renewal,
                        dwell.map_or(0.0, |d| d.max_increase),
                    );
                }
            }
        }
        let (err, tau, renewal, increase) = best;
        s += &format!(
            "  stick {stick:.0e}, age {}, clock {}: best {err:.2} % at tau {tau} s, renewal \
             {renewal:.0e} m, dF {increase:.0} N\n",
            age_at_stick.name(),
            clock.name()
        );
    }
    s
}

/// `gaps`: where one body-speed clock parts from the record's.
fn gaps(args: &[String], draw: Draw) {
    let seed: u64 = args.first().and_then(|s| s.parse().ok()).unwrap_or(1700);
    let stick: f64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(5e-5);
    let window: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(1);
    let restart = args.iter().any(|a| a == "--restart");
    let (rec, axis) = record(seed, draw);
    let p = Prepared::new(&rec, "x.csv", Default::default()).unwrap();
    let w = generator_dwell_force(&axis);
    let truth = axis.dwell_trace.clone().expect("random_record keeps it").0;
    let renewal = (!restart).then(|| renewal_of(&axis));
    let body = body_clock(&p, stick, window, renewal);
    println!("{axis:?}");
    // per 50 ms block: start, mean |v|, moving share, true and body-clock dwell force
    let mut rows: Vec<(usize, f64, f64, f64, f64)> = (0..p.len())
        .step_by(50)
        .map(|b| {
            let e = (b + 50).min(p.len());
            let mean = |f: &dyn Fn(usize) -> f64| (b..e).map(f).sum::<f64>() / (e - b) as f64;
            (
                b,
                mean(&|i| p.v[i].abs()),
                mean(&|i| p.weight[i]),
                mean(&|i| w(truth[i])),
                mean(&|i| w(body[i])),
            )
        })
        .collect();
    let gap = |r: &(usize, f64, f64, f64, f64)| r.2 * (r.3 - r.4).powi(2);
    let total: f64 = rows.iter().map(gap).sum();
    println!("scored squared gap {total:.0} N^2 (per block means)");
    rows.sort_by(|a, b| gap(b).total_cmp(&gap(a)));
    for &(b, v, moving, wt, wb) in rows.iter().take(25) {
        let mid = (b + 25).min(p.len() - 1);
        println!(
            "t {:7.2} s |v| {v:8.5} m/s moving {moving:.2} true +{wt:6.1} N body-clock +{wb:6.1} N  true age {:.3} body age {:.3}",
            b as f64 * p.dt,
            truth[mid],
            body[mid]
        );
    }
}

/// `ages SEED [--resets]`: the diagnosis's own dwell candidate (its rule, time constant and renewal
/// distance as searched) run along the record, its age at each departure from a rest against
/// the record's own clock there, and the dwell force each age gives.
fn ages(args: &[String], draw: Draw) {
    let seed: u64 = args.first().and_then(|s| s.parse().ok()).unwrap_or(1700);
    let (rec, axis) = record(seed, draw);
    let d = first_stage(&rec);
    let p = &d.prepared;
    let cand = dwell_candidate(&d).expect("a dwell candidate");
    let dw = (cand.model.friction.effects.dwell_stiction).expect("the dwell term");
    let ours = cand.model.simulate(p).dwell;
    let truth = axis.dwell_trace.clone().expect("random_record keeps it").0;
    let w_true = generator_dwell_force(&axis);
    // the candidate's own law, read off the core: its static level at an age less at none
    let reference = cand.model.friction.effects.reference_conditions();
    let static_at = |age: f64| {
        (cand.model.friction)
            .levels_by_direction(&reference, age)
            .0
            .static_
    };
    let w_ours = |age: f64| static_at(age) - static_at(0.0);
    println!("{seed} {axis:?}");
    if args.iter().any(|a| a == "--resets") {
        // where the model's age falls to under half in a step while the record's is over
        // 0.2 s: the motion, position [um] and rest flags about it
        for i in 1..p.len() {
            if ours[i] < 0.5 * ours[i - 1] && truth[i] > 0.2 {
                let w = i.saturating_sub(3)..(i + 2).min(p.len());
                let v: Vec<String> = p.v_step[w.clone()]
                    .iter()
                    .map(|v| format!("{v:.1e}"))
                    .collect();
                let x: Vec<String> = p.x[w.clone()]
                    .iter()
                    .map(|x| format!("{:.1}", x * 1e6))
                    .collect();
                println!(
                    "  restart at {:.3} s (record's age {:.3} s): v_step {v:?} m/s, x {x:?} um, at rest {:?}",
                    i as f64 * p.dt,
                    truth[i],
                    &p.inside_rest[w]
                );
            }
        }
    }
    println!(
        "  candidate {:.2} %: dF {:.1} N, tau {:.3} s, renewal {:.1e} m, {:?} {:?}",
        cand.rel_err_pct,
        dw.max_increase,
        dw.time_constant,
        dw.renewal_distance,
        dw.age_at_stick,
        dw.clock
    );
    // the last sample of each rest before the body moves again (the age a breakaway meets)
    let (mut n, mut sum_t, mut sum_o, mut short) = (0, 0.0, 0.0, 0);
    for i in 1..p.len() {
        let departs = p.inside_rest[i - 1] && !p.inside_rest[i];
        if !departs {
            continue;
        }
        let (t, o) = (truth[i - 1], ours[i - 1]);
        n += 1;
        sum_t += w_true(t);
        sum_o += w_ours(o);
        if o < 0.5 * t {
            short += 1;
        }
        if n <= 40 {
            println!(
                "  t {:7.3} s: true age {t:6.3} s (+{:6.1} N), ours {o:6.3} s (+{:6.1} N)",
                i as f64 * p.dt,
                w_true(t),
                w_ours(o)
            );
        }
    }
    println!(
        "  {n} departures: mean dwell force true {:.1} N, ours {:.1} N; ours under half the true age at {short}",
        sum_t / n.max(1) as f64,
        sum_o / n.max(1) as f64
    );
}

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let draw = Draw {
        axes: Axes::from_args(&args),
        law: DwellLaw::from_args(&args),
    };
    for flag in ["--axes", "--dwell-law"] {
        if let Some(i) = args.iter().position(|a| a == flag) {
            args.drain(i..(i + 2).min(args.len()));
        }
    }
    let mode = args.first().map(String::as_str).unwrap_or("truth");
    match mode {
        "gaps" => return gaps(&args[1..], draw),
        "ages" => return ages(&args[1..], draw),
        "force" => return force_clocks(&args[1..], draw),
        "trace" => return trace(&args[1..], draw),
        "truth" | "fit" => {}
        other => panic!("unknown mode {other}: truth, fit, gaps, ages, force or trace"),
    }
    let s0: u64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(1700);
    let n: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(10);
    let out: Vec<String> = (s0..s0 + n)
        .collect::<Vec<_>>()
        .par_iter()
        .map(|&seed| per_record(seed, mode == "fit", draw))
        .collect();
    for s in out {
        print!("{s}");
    }
}

/// A contact-slip clock read off the measured motion and force (study, session 97): the
/// body's speed over a centred window of `window` samples, and the contact's slip either by
/// LuGre's `|v| |F| / F_s` (`formula`) or as the body's speed less the bristle's,
/// `|v - dF/dt / sigma0|`, the force's derivative over the same window, run through the
/// generator's own clock with a stick under `stick` [m/s] ([`Axis::clock_at`]: the record's
/// law).
fn force_clock(p: &Prepared, axis: &Axis, window: usize, stick: f64, formula: bool) -> Vec<f64> {
    let f = generators::axis::measured_friction(axis, p);
    let n = p.len();
    // a column's rate over samples a..b [per s]
    let rate = |u: &[f64], (a, b): (usize, usize)| (u[b] - u[a]) / ((b - a).max(1) as f64 * p.dt);
    let around = |i: usize, half: usize| (i.saturating_sub(half), (i + half).min(n - 1));
    let slip = (0..n).map(|i| {
        // the body's speed: the filtered velocity, or the travel over the window; the force's
        // rate over the same window (at least the two neighbours)
        let (v, over) = if window <= 1 {
            (p.v[i], around(i, 1))
        } else {
            let w = around(i, window / 2);
            (rate(&p.x, w), w)
        };
        if formula {
            v.abs() * (f[i].abs() / axis.static_n).min(1.0)
        } else {
            (v - rate(&f, over) / axis.sigma0).abs()
        }
    });
    ages_along(axis, slip, stick, p.dt)
}

/// The generator's own clock ([`Axis::clock_at`], the record's law, a stick under `stick`
/// [m/s]) run along a slip series [m/s] sampled every `dt` \[s\]: the age at each sample \[s\].
fn ages_along(axis: &Axis, slip: impl Iterator<Item = f64>, stick: f64, dt: f64) -> Vec<f64> {
    let (mut stuck_s, mut age) = (0.0f64, 0.0f64);
    slip.map(|s| {
        axis.clock_at(s, stick, dt, &mut stuck_s, &mut age);
        age
    })
    .collect()
}

/// `force [FIRST_SEED] [N]`: the generator's truth on force-read slip clocks.
fn force_clocks(args: &[String], draw: Draw) {
    let s0: u64 = args.first().and_then(|s| s.parse().ok()).unwrap_or(1700);
    let n: u64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(10);
    let out: Vec<String> = (s0..s0 + n)
        .collect::<Vec<_>>()
        .par_iter()
        .map(|&seed| {
            let (rec, axis) = record(seed, draw);
            let p = Prepared::new(&rec, "x.csv", Default::default()).unwrap();
            let with = |trace: Option<Vec<f64>>| {
                let a = Axis {
                    dwell_trace: trace.map(|t| DwellTrace(std::sync::Arc::new(t))),
                    ..axis.clone()
                };
                generators::axis::truth_error_pct(&a, &p)
            };
            let no = Axis {
                shape: Shape::None,
                ..axis.clone()
            };
            let mut s = format!(
                "{seed} s0 {:.1e} floor {:.2} motion-clock {:.2} no-effect {:.2} |",
                axis.sigma0,
                generators::axis::truth_error_pct(&axis, &p),
                with(None),
                generators::axis::truth_error_pct(&no, &p),
            );
            for formula in [true, false] {
                for window in [1usize, 10, 30] {
                    for stick in [5e-5, 1e-4] {
                        s += &format!(
                            " {:.2}",
                            with(Some(force_clock(&p, &axis, window, stick, formula)))
                        );
                    }
                }
                s += " |";
            }
            // the generator's aging law on the body's filtered speed, whatever the record's law
            let aging_axis = Axis {
                dwell_law: DwellLaw::Aging,
                ..axis.clone()
            };
            let aging = ages_along(&aging_axis, p.v.iter().map(|v| v.abs()), 0.0, p.dt);
            s += &format!(" {:.2}", with(Some(aging)));
            s + "\n"
        })
        .collect();
    println!(
        "columns: [formula |v||F|/Fs | |v - dF/dt/sigma0|] x window 1,10,30 x stick 5e-5,1e-4 \
         | the aging law on the body's filtered speed"
    );
    for s in out {
        print!("{s}");
    }
}

/// `trace SEED FROM_S TO_S [EVERY]`: the record's age and the measured motion and friction.
fn trace(args: &[String], draw: Draw) {
    let usage = "trace SEED FROM_S TO_S [EVERY]";
    let arg = |i: usize| {
        args.get(i)
            .and_then(|s| s.parse::<f64>().ok())
            .expect(usage)
    };
    let (seed, from, to) = (arg(0) as u64, arg(1), arg(2));
    let every: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(5);
    let (rec, axis) = record(seed, draw);
    let p = Prepared::new(&rec, "x.csv", Default::default()).unwrap();
    let truth = axis.dwell_trace.clone().unwrap().0;
    let fc = force_clock(&p, &axis, 1, 5e-5, true);
    let friction = generators::axis::measured_friction(&axis, &p);
    for i in ((from / p.dt) as usize..(to / p.dt) as usize).step_by(every) {
        let f = friction[i];
        println!(
            "{:.3} age {:.3} fc {:.3} x {:.1} um v {:.1e} vstep {:.1e} F {:.1} N raw {:.1} rest {}",
            p.t[i],
            truth[i],
            fc[i],
            p.x[i] * 1e6,
            p.v[i],
            p.v_step[i],
            f,
            rec.force[i],
            p.inside_rest[i] as u8
        );
    }
}
