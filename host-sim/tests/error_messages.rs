//! The exact words of every refusal the host tools give, as users see them. Written against the
//! messages before the errors became typed (`host_sim::Error`): the types changed, the words did
//! not, and this file is what says so.

use host_sim::diagnose::{self, across, Options};
use host_sim::params_file::ParamFile;
use host_sim::record::Record;
use host_sim::{identify, scenarios, timing};
use lugre_servo::friction::{DwellAge, DwellClock, DwellGrowth, FrictionModel};
use std::path::Path;

const GOOD: &str = "[lugre]\nbristle_stiffness_n_per_m = 3.9e9\nbristle_damping_n_s_per_m = 200.0\nviscous_coefficient_n_s_per_m = 48900.0\ncoulomb_force_n = 506.0\nstatic_force_n = 632.0\nstribeck_velocity_m_per_s = 0.005\n[axis]\nmoving_mass_kg = 200.0\n";

fn record(n: usize, dt: f64, moving: bool) -> Record {
    let t: Vec<f64> = (0..n).map(|i| i as f64 * dt).collect();
    let x = t
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

fn csv_error(text: &str) -> String {
    Record::parse(text, Path::new("r.csv"))
        .unwrap_err()
        .to_string()
}

#[test]
fn record_file_messages() {
    let cases = [
        ("", "r.csv:1: empty file: no header row"),
        (
            "t,x,x\n",
            "r.csv:1:3: column 'x': duplicated column",
        ),
        (
            "t,x\n0,0\n",
            "r.csv:1: missing required column 'force' (header has: t,x); required: t [s], x [m], force [N]",
        ),
        (
            "t,x,force\n0,0\n",
            "r.csv:2: row has 2 fields, the header has 3",
        ),
        (
            "t,x,force\n0,0,1\n0.001,oops,2\n",
            "r.csv:3:2: column 'x': 'oops' is not a number",
        ),
        (
            "t,x,force\n0,0,inf\n",
            "r.csv:2:3: column 'force': value 'inf' is not finite (inf)",
        ),
        (
            "t,x,force\n0,0,1\n0,0,1\n",
            "r.csv:3:1: column 't': time does not increase (0 after 0)",
        ),
        ("t,x,force\n", "r.csv:1: no data rows after the header"),
    ];
    for (text, want) in cases {
        assert_eq!(csv_error(text), want, "for {text:?}");
    }
    let e = Record::read(Path::new("/nonexistent/r.csv"))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("/nonexistent/r.csv: cannot read: "), "{e}");
}

#[test]
fn parameter_file_messages() {
    let dir = tempfile::tempdir().unwrap();
    let read = |text: &str| {
        let p = dir.path().join("p.toml");
        std::fs::write(&p, text).unwrap();
        ParamFile::read(&p)
            .unwrap_err()
            .to_string()
            .replace(&dir.path().display().to_string(), "DIR")
    };
    assert_eq!(
        read(&GOOD.replace("632.0", "400.0")),
        "DIR/p.toml: [lugre] static_force (Fs) [N] must be at least coulomb_force (Fc): the breakaway force cannot be below the sliding force"
    );
    assert_eq!(
        read(&GOOD.replace("moving_mass_kg = 200.0", "moving_mass_kg = 0")),
        "DIR/p.toml: [axis] moving_mass_kg must be a finite number greater than zero"
    );
    assert_eq!(
        read(&format!(
            "{GOOD}[effects.asymmetry]\ncoulomb_ratio = 1.5\nviscous_ratio = 0\n"
        )),
        "DIR/p.toml: [effects.asymmetry] ratios must be within (-1, 1)"
    );
    assert_eq!(
        read(&format!("{GOOD}[effects.stribeck_shape]\nexponent = -1\n")),
        "DIR/p.toml: [effects.stribeck_shape] exponent must be greater than zero"
    );
    assert_eq!(
        read(&format!(
            "{GOOD}[effects.position_dependence]\ngradient_n_per_m = 1\ncenter_m = 0\ncosine_n = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17]\nhalf_span_m = 0.1\n"
        )),
        "DIR/p.toml: [effects.position_dependence] cosine_n: at most 16 terms, got 17"
    );
    assert_eq!(
        read(&format!(
            "{GOOD}[effects.load_dependence]\ncoefficient_n_per_pa = 1e-6\nreference_pressure_sum_pa = 1e7\ncosine_n = [1, 2, 3, 4, 5]\nhalf_span_pa = 1e6\n"
        )),
        "DIR/p.toml: [effects.load_dependence] cosine_n: at most 4 terms, got 5"
    );
    assert_eq!(
        read(&format!(
            "{GOOD}[effects.load_dependence]\ncoefficient_n_per_pa = 1e-6\nreference_pressure_sum_pa = 1e7\ncosine_n = [1, 2]\n"
        )),
        "DIR/p.toml: [effects.load_dependence] half_span_pa must be greater than zero"
    );
    let dwell = "[effects.dwell_stiction]\nmax_increase_n = 50\ntime_constant_s = 0.5\nstick_velocity_m_per_s = 2e-4\n";
    assert_eq!(
        read(&format!("{GOOD}{dwell}renewal_distance_m = 0\n")),
        "DIR/p.toml: [effects.dwell_stiction] renewal_distance_m must be greater than zero"
    );
    // a file written before the renewal distance existed reads with the documented default
    let old = dir.path().join("old.toml");
    std::fs::write(&old, format!("{GOOD}{dwell}")).unwrap();
    let (_, m) = ParamFile::read(&old).unwrap();
    assert_eq!(
        m.effects.dwell_stiction.map(|d| d.renewal_distance),
        Some(host_sim::params_file::DEFAULT_RENEWAL_DISTANCE_M)
    );
    // ... and with the age rule it always had, which a written file names and reads back
    assert_eq!(
        m.effects.dwell_stiction.map(|d| d.age_at_stick),
        Some(DwellAge::Accumulates)
    );
    // a rule word of the dwell term (the age at a stick, the clock): a model that holds it is
    // written with it by name and reads back the same; a word the file does not know is an
    // error naming the file and the word, never a default
    let round_trip = |model: &FrictionModel<f64>, file: &str, line: &str, unknown: &str| {
        let written = dir.path().join(file);
        ParamFile::new(model, 200.0).write(&written).unwrap();
        let text = std::fs::read_to_string(&written).unwrap();
        assert!(text.contains(line), "{line} not in {text}");
        assert_eq!(ParamFile::read(&written).unwrap().1, *model);
        let key = line.split(" = ").next().unwrap();
        let refusal = read(&format!("{GOOD}{dwell}{key} = \"{unknown}\"\n"));
        assert!(
            refusal.starts_with("DIR/p.toml:") && refusal.contains(unknown),
            "{refusal}"
        );
    };
    let mut restarting = m;
    if let Some(d) = restarting.effects.dwell_stiction.as_mut() {
        d.age_at_stick = DwellAge::Restarts;
    }
    round_trip(
        &restarting,
        "restarts.toml",
        "age_at_stick = \"restarts\"",
        "resets",
    );
    // the clock: absent (files before session 89) the body's speed; the contact's slip
    // written by name and read back
    assert_eq!(
        m.effects.dwell_stiction.map(|d| d.clock),
        Some(DwellClock::BodySpeed)
    );
    let mut on_slip = restarting;
    if let Some(d) = on_slip.effects.dwell_stiction.as_mut() {
        d.clock = DwellClock::ContactSlip;
    }
    round_trip(&on_slip, "slip.toml", "clock = \"contact_slip\"", "wall");
    // the aging law (session 100), written and read back by its name
    let mut aging = m;
    if let Some(d) = aging.effects.dwell_stiction.as_mut() {
        d.age_at_stick = DwellAge::Aging;
    }
    round_trip(&aging, "aging.toml", "age_at_stick = \"aging\"", "ageing");
    // the growth's form (session 103): absent (older files) the exponential they were fitted
    // with; the hyperbolic written and read back by its name
    assert_eq!(
        m.effects.dwell_stiction.map(|d| d.growth),
        Some(DwellGrowth::Exponential)
    );
    let mut hyperbolic = aging;
    if let Some(d) = hyperbolic.effects.dwell_stiction.as_mut() {
        d.growth = DwellGrowth::Hyperbolic;
    }
    round_trip(
        &hyperbolic,
        "hyperbolic.toml",
        "growth = \"hyperbolic\"",
        "logarithmic",
    );
    // the static asymmetry ratio: checked like the others; absent (older files) it is rc
    assert_eq!(
        read(&format!(
            "{GOOD}[effects.asymmetry]\ncoulomb_ratio = 0.1\nstatic_ratio = -1.2\nviscous_ratio = 0\n"
        )),
        "DIR/p.toml: [effects.asymmetry] ratios must be within (-1, 1)"
    );
    std::fs::write(
        &old,
        format!("{GOOD}[effects.asymmetry]\ncoulomb_ratio = 0.1\nviscous_ratio = 0.2\n"),
    )
    .unwrap();
    let (_, m) = ParamFile::read(&old).unwrap();
    assert_eq!(m.effects.asymmetry.map(|a| a.static_ratio), Some(0.1));
    // the Stribeck velocity ratio: absent (older files) the same vs both ways; checked like
    // the others
    assert_eq!(
        m.effects.asymmetry.map(|a| a.stribeck_velocity_ratio),
        Some(0.0)
    );
    assert_eq!(
        read(&format!(
            "{GOOD}[effects.asymmetry]\ncoulomb_ratio = 0.1\nviscous_ratio = 0\nstribeck_velocity_ratio = 1.0\n"
        )),
        "DIR/p.toml: [effects.asymmetry] ratios must be within (-1, 1)"
    );
    // and one written now carries both and reads back unchanged
    let mut m2 = m;
    if let Some(a) = m2.effects.asymmetry.as_mut() {
        a.static_ratio = -0.05;
        a.stribeck_velocity_ratio = 0.35;
    }
    let f = ParamFile::new(&m2, 200.0);
    f.write_checked(&old).unwrap();
    let (_, back) = ParamFile::read(&old).unwrap();
    assert_eq!(back.effects.asymmetry, m2.effects.asymmetry);
    assert!(read("[lugre\n").starts_with("DIR/p.toml:1:"));
    let e = ParamFile::read(Path::new("/nonexistent/p.toml"))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("/nonexistent/p.toml: cannot read: "), "{e}");

    let model = lugre_servo::friction::FrictionModel::plain(
        lugre_servo::friction::LugreParams::new(1e6, 0.0, 100.0, 10.0, 12.0, 0.002).unwrap(),
    );
    let e = ParamFile::new(&model, 0.0)
        .write_checked(Path::new("out.toml"))
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "out.toml: not written: [axis] moving_mass_kg must be a finite number greater than zero"
    );
}

#[test]
fn record_analysis_messages() {
    let opts = Options::default();
    let e = |r: Record, o: &Options| {
        diagnose::diagnose(&r, "r.csv", o)
            .map(|_| ())
            .unwrap_err()
            .to_string()
    };
    assert_eq!(
        e(record(1, 1e-3, true), &opts),
        "r.csv: a record needs at least 2 samples, has 1"
    );
    assert_eq!(
        e(record(100, 1e-3, true), &opts),
        "r.csv: record too short for diagnosis: 100 samples, need at least 500"
    );
    assert_eq!(
        e(record(5000, 0.1, true), &opts),
        "r.csv: sampled at 10 Hz (median interval 100 ms), too slow for friction dynamics; at least 20 Hz is needed"
    );
    assert!(e(record(5000, 1e-3, false), &opts)
        .starts_with("r.csv: no motion to diagnose: the position spans 0.000e0 m"));
    let mut zero = record(5000, 1e-3, true);
    zero.force.fill(0.0);
    assert_eq!(
        e(zero, &opts),
        "r.csv: the force column is zero wherever the axis moves"
    );
    let add = |name: &str| Options {
        add: vec![name.into()],
        ..Default::default()
    };
    assert_eq!(
        e(record(5000, 1e-3, true), &add("load_dependence")),
        "r.csv: cannot add 'load_dependence': the record has no chamber pressure (p_a and/or p_b)"
    );
    assert_eq!(
        e(record(5000, 1e-3, true), &add("gremlins")),
        "unknown effect 'gremlins'; known: asymmetry, offset, load_dependence, position_dependence, temperature_dependence, stribeck_shape, viscous_power, dwell_stiction"
    );
    let mut back = record(10, 1e-3, true);
    back.t[5] = back.t[3];
    assert_eq!(
        timing::uniform(&back, "b.csv")
            .map(|_| ())
            .unwrap_err()
            .to_string(),
        "b.csv: time does not increase at sample 6 (0.003 after 0.004)"
    );
    let three = vec![("a.csv".to_string(), record(5000, 1e-3, true))];
    assert_eq!(
        across::analyse(&three, &opts)
            .map(|_| ())
            .unwrap_err()
            .to_string(),
        "diagnosis across records needs at least 3 records, got 1"
    );
    let mut cfg = host_sim::plant::PlantConfig::default();
    assert_eq!(
        scenarios::with_effect(&mut cfg, "gremlins", 1.0)
            .unwrap_err()
            .to_string(),
        "unknown effect 'gremlins'; known: asymmetry, offset, load_dependence, position_dependence, temperature_dependence, stribeck_shape, viscous_power, dwell_stiction"
    );
}

#[test]
fn identification_data_messages() {
    let rec = Record::parse("t,x,force\n0,0,1\n0.001,0,1\n", Path::new("s.csv")).unwrap();
    assert_eq!(
        identify::steady_points_from_record(&rec, 200.0, "s.csv")
            .map(|_| ())
            .unwrap_err()
            .to_string(),
        "s.csv: the sweep record needs an x_ref column to find its constant-velocity legs"
    );
    let mut rec = record(1000, 1e-3, false);
    rec.x_ref = Some((0..1000).map(|i| 0.1 + 1e-5 * i as f64).collect());
    assert_eq!(
        identify::steady_points_from_record(&rec, 200.0, "s.csv")
            .map(|_| ())
            .unwrap_err()
            .to_string(),
        // the record's axis does not follow its reference: the one leg is not sliding
        "s.csv: found 0 steady constant-velocity legs of at least 0.4 s, need 6 or more for \
         the static stage; left out: 1 in stick-slip (the axis stuck for part of the leg; \
         slower legs are where it sets in, so raise the slowest speed or the loop's stiffness)"
    );
}

/// What the command line prints (`error: ` and the message) for mistakes in its arguments.
#[test]
fn command_line_messages() {
    let exe = env!("CARGO_BIN_EXE_host-sim");
    let dir = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| {
        let out = std::process::Command::new(exe)
            .args(args)
            .current_dir(dir.path())
            .output()
            .unwrap();
        assert!(!out.status.success(), "{args:?} succeeded");
        String::from_utf8_lossy(&out.stderr).trim_end().to_string()
    };
    assert_eq!(
        run(&["simulate", "sine", "--out", "s.csv", "--duration", "0"]),
        "error: --duration must be a positive number of seconds"
    );
    assert_eq!(
        run(&["simulate", "sine", "--out", "s.csv", "--effect", "gremlins"]),
        "error: unknown effect 'gremlins'; known: asymmetry, offset, load_dependence, position_dependence, temperature_dependence, stribeck_shape, viscous_power, dwell_stiction"
    );
    assert_eq!(
        run(&["identify", "--sweep", "s.csv"]),
        "error: give both --sweep FILE and --dynamic FILE, or neither (simulated data)"
    );
    std::fs::create_dir(dir.path().join("empty")).unwrap();
    assert_eq!(
        run(&["diagnose", "--data", "empty"]),
        "error: empty: no .csv records in this folder"
    );
    std::fs::write(
        dir.path().join("bad.csv"),
        "t,x,force\n0,0,1\n0.001,0,NaN\n",
    )
    .unwrap();
    assert_eq!(
        run(&["diagnose", "--data", "bad.csv"]),
        "error: bad.csv:3:3: column 'force': value 'NaN' is not finite (NaN)"
    );
}
