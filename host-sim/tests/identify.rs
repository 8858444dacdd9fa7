//! Identification: determinism, the improved GA against the traditional one, bad files.

use host_sim::identify::{self, Algorithm};
use host_sim::params_file::ParamFile;
use host_sim::record::Record;
use lugre_servo::friction::LugreParams;
use lugre_servo::identify::cost::SteadyPoint;
use std::path::Path;

#[test]
fn deterministic_for_a_seed() {
    let truth = LugreParams::table2();
    let data = identify::ideal_data(&truth);
    let a = identify::identify(Algorithm::Improved, &data, 5, Some(&truth));
    let b = identify::identify(Algorithm::Improved, &data, 5, Some(&truth));
    assert_eq!(a.values, b.values);
    let c = identify::identify(Algorithm::Improved, &data, 6, Some(&truth));
    assert_ne!(a.values, c.values);
}

#[test]
fn improved_beats_traditional_on_the_objective() {
    let truth = LugreParams::table2();
    let data = identify::ideal_data(&truth);
    let (mut imp_w, mut tra_w) = (Vec::new(), Vec::new());
    for seed in 1..=5 {
        let imp = identify::identify(Algorithm::Improved, &data, seed, Some(&truth));
        let tra = identify::identify(Algorithm::Traditional, &data, seed, Some(&truth));
        println!(
            "seed {seed}: static cost improved {:.2e} traditional {:.2e}",
            imp.costs.0, tra.costs.0
        );
        // each stage's own objective: the static stage sees the same data for both
        assert!(
            imp.costs.0 < tra.costs.0,
            "seed {seed}: static {} vs {}",
            imp.costs.0,
            tra.costs.0
        );
        let (i, t) = (imp.errors_pct.unwrap(), tra.errors_pct.unwrap());
        // the paper's claim, on every seed: all six within 1 %
        assert!(i.worst() < 1.0, "seed {seed}: {i:?}");
        assert!(imp.at_bound.is_empty(), "seed {seed}: {:?}", imp.at_bound);
        imp_w.push(i.worst());
        tra_w.push(t.worst());
    }
    imp_w.sort_by(f64::total_cmp);
    tra_w.sort_by(f64::total_cmp);
    println!(
        "median worst error of six: improved {} %, traditional {} %",
        imp_w[2], tra_w[2]
    );
    assert!(imp_w[2] < 0.1, "median worst {} %", imp_w[2]);
    assert!(10.0 * imp_w[2] < tra_w[2]);
}

#[test]
fn realistic_data_degrades_gracefully_and_says_what_it_cannot_see() {
    let truth = LugreParams::table2();
    let cfg = host_sim::plant::PlantConfig::default();
    let data = identify::realistic_data(&cfg, 3);
    let r = identify::identify(Algorithm::Improved, &data, 3, Some(&truth));
    let e = r.errors_pct.unwrap();
    println!("{e:?}, at bound {:?}", r.at_bound);
    // the static four come from averaged steady-state forces: pressure noise costs < 1 %
    for (name, err) in [
        ("sigma2", e.sigma2),
        ("Fc", e.fc),
        ("Fs - Fc", e.fs_minus_fc),
        ("vs", e.vs),
    ] {
        assert!(err < 1.0, "{name}: {err} %");
    }
    // sigma0: the 0.1 um encoder spans a third of the pre-sliding travel; read at its
    // counts' edges (errors in variables) it is found without the staircase's -24 % bias,
    // and its 95 % interval, from the chi-square of known variances, holds the truth
    assert!(e.sigma0 < 20.0, "sigma0 {} %", e.sigma0);
    let s0 = r.identifiability[0].expect("noisy data is scanned");
    let truth_s0 = truth.bristle_stiffness();
    assert!(
        s0.interval95[0] <= truth_s0 && truth_s0 <= s0.interval95[1],
        "{:?}",
        s0.interval95
    );
    assert!(s0.interval95[0] > 0.5 * truth_s0, "{:?}", s0.interval95);
    // sigma1 is invisible at 1 kHz behind these sensors: flagged, and not left at a bound
    let s1 = r.identifiability[1].expect("noisy data is scanned");
    assert!(!s1.identifiable);
    assert!(r.at_bound.is_empty(), "{:?}", r.at_bound);
}

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn bad_parameter_files_are_refused_with_the_field() {
    let dir = std::env::temp_dir().join(format!("lugre-params-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let good = "[lugre]\nbristle_stiffness_n_per_m = 3.9e9\nbristle_damping_n_s_per_m = 200.0\nviscous_coefficient_n_s_per_m = 48900.0\ncoulomb_force_n = 506.0\nstatic_force_n = 632.0\nstribeck_velocity_m_per_s = 0.005\n[axis]\nmoving_mass_kg = 200.0\n";
    assert!(ParamFile::read(&write(&dir, "good.toml", good)).is_ok());
    let cases = [
        (
            good.replace("static_force_n = 632.0", "static_force_n = 400.0"),
            "static_force (Fs)",
        ),
        (
            good.replace("coulomb_force_n = 506.0", "coulomb_force_n = nan"),
            "coulomb_force (Fc) [N] must be a finite number",
        ),
        (
            good.replace(
                "stribeck_velocity_m_per_s = 0.005",
                "stribeck_velocity_m_per_s = -1",
            ),
            "stribeck_velocity",
        ),
        (
            good.replace("moving_mass_kg = 200.0", "moving_mass_kg = 0"),
            "moving_mass_kg",
        ),
        (
            good.replace("coulomb_force_n = 506.0\n", ""),
            "coulomb_force_n",
        ),
        (
            good.replace("[axis]", "[axis]\nmoving_mass_lb = 3"),
            "moving_mass_lb",
        ),
        (
            format!("{good}[effects.asymmetry]\ncoulomb_ratio = 1.5\nviscous_ratio = 0\n"),
            "[effects.asymmetry] ratios",
        ),
        ("[lugre\n".to_string(), "bad.toml:1:"),
    ];
    for (text, want) in cases {
        let e = ParamFile::read(&write(&dir, "bad.toml", &text))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("bad.toml") && e.contains(want),
            "want '{want}' in '{e}'"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_identification_data_is_refused() {
    // a sweep without x_ref cannot be cut into constant-velocity legs
    let rec = Record::parse("t,x,force\n0,0,1\n0.001,0,1\n", Path::new("s.csv")).unwrap();
    let e = identify::steady_points_from_record(&rec, 200.0, "s.csv")
        .unwrap_err()
        .to_string();
    assert!(e.contains("s.csv") && e.contains("x_ref"), "{e}");
    // a sweep with x_ref but too few legs
    let mut text = String::from("t,x,force,x_ref\n");
    for i in 0..1000 {
        text += &format!(
            "{},{},{},{}\n",
            i as f64 * 1e-3,
            0.1,
            500.0,
            0.1 + 1e-5 * i as f64
        );
    }
    let rec = Record::parse(&text, Path::new("s.csv")).unwrap();
    let e = identify::steady_points_from_record(&rec, 200.0, "s.csv")
        .unwrap_err()
        .to_string();
    assert!(e.contains("need 6 or more"), "{e}");
    // a dynamic record without motion
    let rec = Record::parse(&text, Path::new("d.csv")).unwrap();
    let e = identify::dynamic_from_record(&rec, 200.0, "d.csv")
        .unwrap_err()
        .to_string();
    assert!(e.contains("no motion"), "{e}");
}

fn host_sim(dir: &Path, args: &[&str]) -> String {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_host-sim"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(
        out.status.success(),
        "{args:?}: {}{text}",
        String::from_utf8_lossy(&out.stderr)
    );
    text
}

/// `simulate sweep` and `simulate ident-sine` (realistic sensors, noise seed `seed`) into
/// `s.csv` and `d.csv` in `dir`: the realistic identification's two experiments.
fn simulate_identification_records(dir: &Path, seed: &str) {
    for (experiment, out) in [("sweep", "s.csv"), ("ident-sine", "d.csv")] {
        let args = [
            "simulate",
            experiment,
            "--out",
            out,
            "--noise",
            "realistic",
            "--seed",
            seed,
        ];
        host_sim(dir, &args);
    }
}

/// The measured-data path end to end: the realistic identification's two experiments written
/// as CSV by `simulate`, read back by `identify --sweep --dynamic`, give the same data and the
/// same parameters as the in-memory run.
#[test]
fn simulated_records_through_files_give_the_in_memory_result() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    simulate_identification_records(d, "3");
    let sweep = Record::read(&d.join("s.csv")).unwrap();
    let dynamic = Record::read(&d.join("d.csv")).unwrap();
    let mut from_files = identify::dynamic_from_record(&dynamic, 200.0, "d.csv").unwrap();
    from_files.points = identify::steady_points_from_record(&sweep, 200.0, "s.csv").unwrap();
    let in_memory = identify::realistic_data(&host_sim::plant::PlantConfig::default(), 3);
    assert_eq!(from_files.points, in_memory.points);
    assert_eq!(from_files.velocity, in_memory.velocity);
    assert_eq!(from_files.force, in_memory.force);
    assert_eq!(from_files.dt, in_memory.dt);
    host_sim(
        d,
        &[
            "identify",
            "--sweep",
            "s.csv",
            "--dynamic",
            "d.csv",
            "--out",
            "p.toml",
        ],
    );
    let (file, _) = ParamFile::read(&d.join("p.toml")).unwrap();
    let r = identify::identify(Algorithm::Improved, &in_memory, 1, None);
    let p = identify::params_of(&r).unwrap();
    let l = file.lugre;
    assert_eq!(
        [
            l.bristle_stiffness_n_per_m,
            l.viscous_coefficient_n_s_per_m,
            l.coulomb_force_n,
            l.static_force_n,
            l.stribeck_velocity_m_per_s
        ],
        [
            p.bristle_stiffness(),
            p.viscous_coefficient(),
            p.coulomb_force(),
            p.static_force(),
            p.stribeck_velocity()
        ]
    );
}

/// A record with a rig logger's habits goes through: a header with extra columns (one of them
/// text), optional channels missing, and a first sample off the grid.
#[test]
fn records_with_rig_habits_go_through_identification() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    simulate_identification_records(d, "4");
    host_sim(
        d,
        &[
            "identify",
            "--sweep",
            "s.csv",
            "--dynamic",
            "d.csv",
            "--out",
            "clean.toml",
        ],
    );
    for name in ["s.csv", "d.csv"] {
        let rec = Record::read(&d.join(name)).unwrap();
        let mut text = String::from("# logger=rig-pc v2.1\nstatus,t,x,force,valve_cmd");
        let x_ref = rec.x_ref.as_ref().filter(|_| name == "s.csv");
        if x_ref.is_some() {
            text += ",x_ref";
        }
        text += "\n";
        for i in 0..rec.len() {
            // the logger's first interval is 1.4 periods, the second 0.6
            let t = if i == 1 { rec.t[1] + 0.4e-3 } else { rec.t[i] };
            text += &format!("OK,{t},{},{},{}", rec.x[i], rec.force[i], 0.01 * i as f64);
            if let Some(r) = x_ref {
                text += &format!(",{}", r[i]);
            }
            text += "\n";
        }
        std::fs::write(d.join(format!("rig-{name}")), text).unwrap();
    }
    let out = host_sim(
        d,
        &[
            "identify",
            "--sweep",
            "rig-s.csv",
            "--dynamic",
            "rig-d.csv",
            "--out",
            "rig.toml",
        ],
    );
    assert!(out.contains("wrote rig.toml"), "{out}");
    let (clean, _) = ParamFile::read(&d.join("clean.toml")).unwrap();
    let (rig, _) = ParamFile::read(&d.join("rig.toml")).unwrap();
    let close = |a: f64, b: f64, tol: f64| (a - b).abs() <= tol * b.abs();
    let (c, r) = (clean.lugre, rig.lugre);
    assert!(
        close(r.coulomb_force_n, c.coulomb_force_n, 1e-3),
        "{r:?} vs {c:?}"
    );
    assert!(
        close(r.static_force_n, c.static_force_n, 1e-3),
        "{r:?} vs {c:?}"
    );
    assert!(
        close(
            r.viscous_coefficient_n_s_per_m,
            c.viscous_coefficient_n_s_per_m,
            1e-3
        ),
        "{r:?} vs {c:?}"
    );
    assert!(
        close(
            r.bristle_stiffness_n_per_m,
            c.bristle_stiffness_n_per_m,
            0.1
        ),
        "{r:?} vs {c:?}"
    );
}

/// The reading's count and the force's noise are measured from the record: a 0.1 um count
/// even where every step is several counts (a reference rounded to 0.1 um moving 0.5 um a
/// period), none for an unquantised reading, and white noise's standard deviation under a
/// smooth force.
#[test]
fn count_and_force_noise_are_measured_from_the_record() {
    let rounded: Vec<f64> = (0..500)
        .map(|k| (0.05 + 4.7e-7 * k as f64 / 1e-7).round() * 1e-7)
        .collect();
    let q = identify::encoder_resolution(&rounded);
    assert!((q / 1e-7 - 1.0).abs() < 1e-6, "{q:e}");
    let smooth: Vec<f64> = (0..500).map(|k| 1e-3 * (k as f64 * 0.01).sin()).collect();
    assert_eq!(identify::encoder_resolution(&smooth), 0.0);
    // a smooth force plus a deterministic white-ish sequence of standard deviation 10 N
    let mut state = 12345u64;
    let force: Vec<f64> = (0..20_000)
        .map(|k| {
            let mut sum = 0.0;
            for _ in 0..12 {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                sum += (state >> 11) as f64 / (1u64 << 53) as f64;
            }
            300.0 * (k as f64 * 1e-3).sin() + 10.0 * (sum - 6.0)
        })
        .collect();
    let sigma = identify::force_noise(&force);
    assert!((sigma / 10.0 - 1.0).abs() < 0.05, "{sigma}");
}

/// A sweep as a rig logs it: eight legs out and back (0.5..100 mm/s, 0.8 s each, 0.3 s
/// rests) with a reference rounded to 0.1 um, and a friction force of `F(v) = 300 sign(v) +
/// 1000 v`; `stick_slip` makes the slowest leg out move in jumps (still for 45 ms, then a
/// 5 ms slide) with a force whose mean is 100 N below the steady friction.
fn logged_sweep(stick_slip: bool) -> Record {
    let dt = 1e-3;
    let speeds = host_sim::experiments::log_speeds(5e-4, 0.1, 8);
    let (mut x_ref, mut x, mut force) = (vec![0.0; 300], vec![0.0; 300], vec![0.0; 300]);
    for (leg, &v) in speeds.iter().enumerate() {
        for dir in [1.0, -1.0] {
            let (r0, x0) = (*x_ref.last().unwrap(), *x.last().unwrap());
            let jumpy = stick_slip && leg == 0 && dir > 0.0;
            for k in 1..=800 {
                x_ref.push(r0 + dir * v * k as f64 * dt);
                let (pos, f) = if jumpy {
                    // 50 ms cycles: still for 45 ms, then the whole cycle's travel in 5 ms
                    let cycle = (k / 50) as f64;
                    let within = (k % 50) as f64;
                    let slid = ((within - 45.0) / 5.0).clamp(0.0, 1.0);
                    let p = x0 + v * 50.0 * dt * (cycle + slid);
                    (p, 300.0 + 1000.0 * v - 100.0)
                } else {
                    (x0 + dir * v * k as f64 * dt, dir * 300.0 + 1000.0 * dir * v)
                };
                x.push(pos);
                force.push(f);
            }
            let (r1, x1) = (*x_ref.last().unwrap(), *x.last().unwrap());
            x_ref.extend(std::iter::repeat_n(r1, 300));
            x.extend(std::iter::repeat_n(x1, 300));
            force.extend(std::iter::repeat_n(0.0, 300));
        }
    }
    Record {
        t: (0..x.len()).map(|k| k as f64 * dt).collect(),
        x_ref: Some(x_ref.iter().map(|r| (r / 1e-7).round() * 1e-7).collect()),
        x,
        force,
        ..Default::default()
    }
}

/// The sweep's legs are found under a reference rounded to 0.1 um (every step of a leg
/// jitters by one unit), each point at its leg's speed and force; a leg in stick-slip is
/// left out, because its mean force is not the steady friction at its mean speed.
#[test]
fn sweep_legs_survive_a_rounded_reference_and_stick_slip_legs_are_left_out() {
    let points = identify::steady_points_from_record(&logged_sweep(false), 100.0, "s.csv")
        .expect("a clean sweep");
    assert_eq!(points.len(), 16, "{points:?}");
    for p in &points {
        let expected = 300.0 * p.velocity.signum() + 1000.0 * p.velocity;
        assert!((p.force - expected).abs() < 1.0, "{p:?} vs {expected}");
    }
    points_without_the_first_leg(&logged_sweep(true), "a sweep with one leg in stick-slip");
}

/// The points of a [`logged_sweep`] whose first leg out (0.5 mm/s) must be the one left out:
/// fifteen, none at that speed.
fn points_without_the_first_leg(rec: &Record, what: &str) -> Vec<SteadyPoint> {
    let points = identify::steady_points_from_record(rec, 100.0, "s.csv").expect(what);
    assert_eq!(points.len(), 15, "{points:?}");
    assert!(
        points.iter().all(|p| (p.velocity - 5e-4).abs() > 1e-4),
        "{points:?}"
    );
    points
}

/// A leg on which a quantised reading does not move at all (the axis stuck for the whole
/// leg) is left out, not divided by its zero travel.
#[test]
fn a_leg_without_motion_is_left_out() {
    let mut rec = logged_sweep(false);
    // the first leg out: samples 301..=1100; the axis stays where it started
    let start = rec.x[300];
    for x in &mut rec.x[301..=1100] {
        *x = start;
    }
    for x in &mut rec.x {
        *x = (*x / 1e-7).round() * 1e-7;
    }
    points_without_the_first_leg(&rec, "fifteen steady legs remain");
}

/// A leg whose force is still settling (the bristles of a soft contact take many pre-sliding
/// travels to reach their steady deflection) averages a force that is not the steady-state
/// friction: it is left out, and a sweep of such legs is refused with the reason.
#[test]
fn a_leg_still_settling_is_left_out() {
    let mut rec = logged_sweep(false);
    // the first leg out (samples 301..=1100) approaches its force over 0.3 s
    for (k, f) in rec.force[301..=1100].iter_mut().enumerate() {
        *f *= 1.0 - 0.5 * (-(k as f64) / 300.0).exp();
    }
    let points = points_without_the_first_leg(&rec, "fifteen settled legs remain");
    // each point carries its standard error, here next to nothing (a noise-free record)
    assert!(
        points.iter().all(|p| p.force_std_error < 0.05),
        "{points:?}"
    );
    // every leg settling: refused, and the message says why
    let mut rec = logged_sweep(false);
    let mut k = 0.0f64;
    for (f, r) in rec
        .force
        .iter_mut()
        .zip(rec.x_ref.clone().unwrap().windows(2))
    {
        k = if r[1] == r[0] { 0.0 } else { k + 1.0 };
        *f *= 1.0 - 0.5 * (-k / 300.0).exp();
    }
    let e = identify::steady_points_from_record(&rec, 100.0, "s.csv").unwrap_err();
    assert!(e.to_string().contains("16 still settling"), "{e}");
}

/// A sweep without slow legs cannot tell the Stribeck level from its speed well: the
/// identifiability scan must not call them identified with an interval that misses the truth.
/// It profiles them (the other levels and the speed refitted at each value); a slice through
/// the optimum, as before, called Fs - Fc identified at [119.75, 123.25] N with the legs from
/// 0.8 vs up and at [32.5, 37.25] N from 1.5 vs up (truth 126 N).
#[test]
fn a_sweep_without_slow_legs_leaves_the_stribeck_hump_open() {
    let truth = LugreParams::table2();
    let cfg = host_sim::plant::PlantConfig::default();
    let all = identify::realistic_data(&cfg, 3);
    let hump = truth.static_force() - truth.coulomb_force();
    for cut in [0.8, 1.5] {
        let mut data = all.clone();
        // only legs faster than `cut` vs: at 1.5 vs the hump is 126 exp(-2.25) = 13 N
        data.points
            .retain(|p| p.velocity.abs() > cut * truth.stribeck_velocity());
        assert!(data.points.len() >= 8, "{}", data.points.len());
        let r = identify::identify(Algorithm::Improved, &data, 3, Some(&truth));
        for (k, name, t) in [(4, "Fs - Fc", hump), (5, "vs", truth.stribeck_velocity())] {
            let id = r.identifiability[k].expect("noisy data is scanned");
            println!("legs from {cut} vs, {name}: value {} {id:?}", r.values[k]);
            assert!(
                !id.identifiable || (id.interval95[0] <= t && t <= id.interval95[1]),
                "legs from {cut} vs: {name} called identified, {:?}, truth {t}",
                id.interval95
            );
        }
        // the Coulomb level and the viscous slope stay well determined
        let e = r.errors_pct.unwrap();
        assert!(e.fc < 1.0 && e.sigma2 < 1.0, "{e:?}");
    }
}

/// A force actuator on a 100 kg mass with LuGre friction (sigma0 1e6 N/m, sigma1 2e3 N s/m),
/// driven open loop by a smooth force that makes it stick and slip, 4 s at 1 kHz, position
/// logged exactly; the plant is integrated in 100 sub-steps per period. `held`: the force is
/// a drive's set-point, constant over each period and logged with the sample that ends it;
/// otherwise it is smooth and logged at the sample instant.
fn force_actuator_record(truth: &LugreParams<f64>, held: bool) -> Record {
    use lugre_servo::friction::LugreState;
    let (mass, dt, sub) = (100.0, 1e-3, 100);
    let command = |t: f64| {
        250.0 * (std::f64::consts::TAU * 0.5 * t).sin()
            + 60.0 * (std::f64::consts::TAU * 3.1 * t).sin()
            + 40.0 * (std::f64::consts::TAU * 17.0 * t).sin()
    };
    let (mut x, mut v) = (0.0f64, 0.0f64);
    let mut s = LugreState::new();
    let mut rec = Record::default();
    for i in 0..4000 {
        let t = i as f64 * dt;
        let logged = if held && i > 0 {
            command(t - dt)
        } else {
            command(t)
        };
        rec.t.push(t);
        rec.x.push(x);
        rec.force.push(logged);
        let h = dt / sub as f64;
        for j in 0..sub {
            let applied = if held {
                command(t)
            } else {
                command(t + j as f64 * h)
            };
            let friction = s.step(truth, v, h);
            v += h * (applied - friction) / mass;
            x += h * v;
        }
    }
    rec
}

#[test]
fn how_the_force_was_logged_is_read_from_the_record() {
    let truth = LugreParams::new(1e6, 2e3, 300.0, 100.0, 150.0, 5e-3).unwrap();
    let points = identify::model_points(&truth, 0.01);
    for held in [true, false] {
        let rec = force_actuator_record(&truth, held);
        let mut data = identify::dynamic_from_record(&rec, 100.0, "actuator").unwrap();
        data.points = points.clone();
        let r = identify::identify(Algorithm::Improved, &data, 1, Some(&truth));
        let e = r.errors_pct.unwrap();
        println!(
            "logged {}: read {:?}, sigma0 {:.2} %, sigma1 {:.1} %",
            if held { "held" } else { "sampled" },
            r.force_timing,
            e.sigma0,
            e.sigma1
        );
        let expected = if held {
            identify::ForceTiming::Held
        } else {
            identify::ForceTiming::Sampled
        };
        assert_eq!(r.force_timing, expected);
        assert!(e.sigma0 < 3.0 && e.sigma1 < 15.0, "{e:?}");
    }
}

/// The steady points of independent axis 1007's sweep (`examples/identify_independent.rs`;
/// velocity [m/s], force \[N\], standard error \[N\]; the legs below 5 mm/s were left out):
/// with seed 1 the improved GA's static stage ended with Fs - Fc at its 1000 N bound, where
/// the truth is 33.7 N and the exact optimum 31.6 N.
const AXIS_1007_POINTS: [(f64, f64, f64); 10] = [
    (
        4.9561586638830896e-3,
        7.918762791666717e1,
        4.4975146323572124e-1,
    ),
    (
        -4.943632567849695e-3,
        -7.943892270605899e1,
        3.140496426438092e-1,
    ),
    (
        1.041127348643008e-2,
        7.019212770378269e1,
        6.270413095368464e-2,
    ),
    (
        -1.0402922755741143e-2,
        -7.00486387477247e1,
        1.2429118699382088e-1,
    ),
    (
        2.209185803757824e-2,
        7.225658062044954e1,
        1.140217983510153e-1,
    ),
    (
        -2.208977035490601e-2,
        -7.21818691643913e1,
        4.656348486459127e-2,
    ),
    (
        4.700208768267231e-2,
        7.755302374773366e1,
        6.341090119097074e-2,
    ),
    (
        -4.700208768267231e-2,
        -7.741170770378278e1,
        1.1518887038956532e-1,
    ),
    (
        1.0010855949895557e-1,
        8.833300270378216e1,
        1.427588305262993e-1,
    ),
    (
        -1.001252609603342e-1,
        -8.831027249544965e1,
        1.367715624604803e-1,
    ),
];

#[test]
fn the_improved_static_stage_ends_at_its_exact_optimum_whatever_the_seed() {
    let mut data = identify::ideal_data(&LugreParams::table2());
    data.points = AXIS_1007_POINTS
        .iter()
        .map(|&(velocity, force, force_std_error)| SteadyPoint {
            velocity,
            force,
            force_std_error,
        })
        .collect();
    let runs: Vec<_> = (1..=4)
        .map(|seed| identify::identify(Algorithm::Improved, &data, seed, None))
        .collect();
    for r in &runs {
        let [_, _, sigma2, fc, dfs, vs] = r.values;
        println!(
            "seed {}: Fc {fc:.3} Fs-Fc {dfs:.3} sigma2 {sigma2:.2} vs {vs:.3e}, static cost {:.4e}, at bound {:?}",
            r.seed, r.costs.0, r.at_bound
        );
        assert!((dfs - 31.6).abs() < 0.5, "Fs - Fc {dfs}");
        assert!(!r.at_bound.contains(&"Fs - Fc"), "{:?}", r.at_bound);
        // one optimum: the same cost from every seed
        assert!((r.costs.0 / runs[0].costs.0 - 1.0).abs() < 1e-6);
    }
}
