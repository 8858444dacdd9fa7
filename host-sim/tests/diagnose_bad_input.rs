//! Bad input is normal input: clear errors, never a panic.

use host_sim::diagnose::{self, Options};
use host_sim::record::Record;
use std::path::Path;

fn record(n: usize, moving: bool) -> Record {
    let t: Vec<f64> = (0..n).map(|i| i as f64 * 1e-3).collect();
    let x: Vec<f64> = t
        .iter()
        .map(|t| if moving { 0.01 * (2.0 * t).sin() } else { 0.1 })
        .collect();
    let force = t.iter().map(|t| 100.0 * (2.0 * t).cos()).collect();
    Record {
        t,
        x,
        force,
        ..Default::default()
    }
}

#[test]
fn too_short_record_is_refused() {
    let e = diagnose::diagnose(&record(100, true), "short.csv", &Options::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("short.csv") && e.contains("too short"), "{e}");
}

#[test]
fn record_without_motion_is_refused() {
    let e = diagnose::diagnose(&record(5000, false), "still.csv", &Options::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("still.csv") && e.contains("no motion"), "{e}");
}

#[test]
fn asking_for_a_missing_channel_names_it() {
    let opts = Options {
        add: vec!["load_dependence".into()],
        ..Default::default()
    };
    let e = diagnose::diagnose(&record(5000, true), "nopress.csv", &opts)
        .unwrap_err()
        .to_string();
    assert!(e.contains("no chamber pressure (p_a and/or p_b)"), "{e}");
    let opts = Options {
        add: vec!["temperature_dependence".into()],
        ..Default::default()
    };
    let e = diagnose::diagnose(&record(5000, true), "notemp.csv", &opts)
        .unwrap_err()
        .to_string();
    assert!(e.contains("no oil temperature"), "{e}");
}

#[test]
fn unknown_effect_lists_the_known_ones() {
    let opts = Options {
        add: vec!["gremlins".into()],
        ..Default::default()
    };
    let e = diagnose::diagnose(&record(5000, true), "r.csv", &opts)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("unknown effect 'gremlins'") && e.contains("asymmetry"),
        "{e}"
    );
}

#[test]
fn malformed_csv_reaches_the_user_with_line_and_column() {
    let e = Record::parse("t,x,force\n0,0,1\n0.001,oops,2\n", Path::new("bad.csv")).unwrap_err();
    assert_eq!(
        e.to_string(),
        "bad.csv:3:2: column 'x': 'oops' is not a number"
    );
}

#[test]
fn cli_reports_errors_without_panicking() {
    let exe = env!("CARGO_BIN_EXE_host-sim");
    let dir = std::env::temp_dir().join(format!("lugre-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.csv");
    std::fs::write(&bad, "t,x,force\n0,0,1\n0.001,0,NaN\n").unwrap();
    let out = std::process::Command::new(exe)
        .args(["diagnose", "--data"])
        .arg(&bad)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("bad.csv:3:3: column 'force'") && !err.contains("panicked"),
        "{err}"
    );
    let params = dir.join("p.toml");
    std::fs::write(&params, "[lugre]\nbristle_stiffness_n_per_m = 3.9e9\nbristle_damping_n_s_per_m = 200.0\nviscous_coefficient_n_s_per_m = 48900.0\ncoulomb_force_n = 506.0\nstatic_force_n = 400.0\nstribeck_velocity_m_per_s = 0.005\n[axis]\nmoving_mass_kg = 200.0\n").unwrap();
    let good = dir.join("good.csv");
    let rec = record(3000, true);
    rec.write(&good).unwrap();
    let out = std::process::Command::new(exe)
        .args(["diagnose", "--data"])
        .arg(&good)
        .arg("--params")
        .arg(&params)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("p.toml") && err.contains("static_force (Fs)"),
        "{err}"
    );
    std::fs::write(&params, "[lugre]\nbristle_stiffness_n_per_m = \"stiff\"\n").unwrap();
    let out = std::process::Command::new(exe)
        .args(["diagnose", "--data"])
        .arg(&good)
        .arg("--params")
        .arg(&params)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("p.toml:2:"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The report is one self-contained page: every chart inline, the zoom script inline, nothing
/// fetched from a network; the final model table names each added effect's parameters.
#[test]
fn the_report_is_self_contained_and_lists_the_whole_model() {
    let rec = asymmetric_record();
    let opts = Options {
        add: vec!["asymmetry".into()],
        ..Default::default()
    };
    let d = diagnose::diagnose(&rec, "r.csv", &opts).unwrap();
    let html = diagnose::report::html(&d, "r.csv", None);
    // error history, force over time, residual vs velocity (two panels), regime bias, the
    // breakaway peaks and holding forces (three panels)
    assert_eq!(html.matches("<svg").count(), 5);
    assert!(html.contains("Breakaway and standstill"));
    assert!(
        !d.breakaway.departures.is_empty(),
        "the record rests and starts again"
    );
    assert_eq!(html.matches("class=\"zoom\"").count(), 2);
    assert!(html.contains("addEventListener('wheel'"));
    // a number keeps its unit on its line in the candidate table (a narrow column broke
    // "1.30 %" into "1.30" above "%")
    assert!(html.contains("\u{a0}%</td>") && !html.contains(" %</td>"));
    for remote in ["src=\"http", "href=\"http", "@import", "<link"] {
        assert!(!html.contains(remote), "{remote}");
    }
    for entry in [
        "effects.asymmetry",
        "coulomb_ratio",
        "viscous_ratio",
        "bristle_stiffness_n_per_m",
        "moving_mass_kg",
    ] {
        assert!(html.contains(entry), "{entry}");
    }
}

/// With one model (nothing added) the report lists where it fails once, not once as the
/// "first" and again as the "final" model.
#[test]
fn a_single_model_lists_where_it_fails_once() {
    let rec = asymmetric_record();
    let d = diagnose::diagnose(&rec, "r.csv", &Options::default()).unwrap();
    assert_eq!(d.stages.len(), 1);
    let findings = &d.stages[0].regimes.findings;
    assert!(
        !findings.is_empty(),
        "the premise: the baseline fails somewhere"
    );
    let html = diagnose::report::html(&d, "r.csv", None);
    assert!(!html.contains("<li>first model:") && !html.contains("<li>final model:"));
    let listed = html
        .split("<h2>Where the model fails</h2><ul>")
        .nth(1)
        .and_then(|s| s.split("</ul>").next())
        .expect("the list");
    assert_eq!(listed.matches("<li>").count(), findings.len(), "{listed}");
}

/// 12 s of the plant with an asymmetric friction, realistic sensors.
fn asymmetric_record() -> host_sim::record::Record {
    let mut cfg = host_sim::plant::PlantConfig::default();
    host_sim::scenarios::with_effect(&mut cfg, "asymmetry", 1.0).unwrap();
    host_sim::scenarios::diagnosis_run(&cfg, host_sim::plant::SensorConfig::realistic(3), 12.0)
}

/// Where an effect is added (`--add`), the text output lists each stage's candidates, the
/// earlier one saying which effect was added next: the ranking it was chosen from (until
/// session 69 only the last stage's list was printed, and with `--auto` the user could not
/// see why an effect had been added).
#[test]
fn cli_lists_the_ranking_each_added_effect_was_chosen_from() {
    let exe = env!("CARGO_BIN_EXE_host-sim");
    let dir = std::env::temp_dir().join(format!("lugre-stages-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let data = dir.join("r.csv");
    record(3000, true).write(&data).unwrap();
    let out = std::process::Command::new(exe)
        .args(["diagnose", "--data"])
        .arg(&data)
        .args(["--add", "offset"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let chosen = text
        .find("candidate effects (best first; offset was added next):")
        .expect(&text);
    let last = text.find("candidate effects (best first):").expect(&text);
    assert!(chosen < last, "{text}");
    // the earlier list holds the offset it chose, the last one no longer does
    let offset_rows = |list: &str| {
        list.lines()
            .filter(|l| l.trim_start().starts_with("offset "))
            .count()
    };
    assert_eq!(offset_rows(&text[chosen..last]), 1, "{text}");
    assert_eq!(offset_rows(&text[last..]), 0, "{text}");
    std::fs::remove_dir_all(&dir).ok();
}
