//! `host-sim diagnose`.

use host_sim::diagnose::{self, inverse::AxisModel, Diagnosis, Options};
use host_sim::params_file::ParamFile;
use host_sim::record::Record;
use host_sim::{Error, Result};
use lugre_servo::friction::EffectKind;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Options of `diagnose`.
#[derive(clap::Args)]
pub struct Args {
    /// The measured record (CSV). Give it several times (or a folder of CSVs) for records of
    /// one axis under different conditions: friction levels against pressure, temperature
    /// and numeric `# key=value` metadata, across records.
    #[arg(long, required = true)]
    data: Vec<PathBuf>,
    /// A parameter file: mass and friction are used as given for the comparison.
    #[arg(long)]
    params: Option<PathBuf>,
    /// Moving mass [kg] (identified from the record when neither this nor --params is given).
    #[arg(long)]
    mass: Option<f64>,
    /// Effects to add to the model, in order (comma separated).
    #[arg(long, value_delimiter = ',')]
    add: Vec<String>,
    /// Then add the suggested effects: the first significant candidate, again and again,
    /// until none is significant (at most three).
    #[arg(long)]
    auto: bool,
    /// Another record to test the fitted model on (no refit).
    #[arg(long)]
    validate: Option<PathBuf>,
    /// Writes a self-contained HTML report.
    #[arg(long)]
    report: Option<PathBuf>,
    /// Writes the results as JSON.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Writes the final (extended) model as a parameter file.
    #[arg(long)]
    out_params: Option<PathBuf>,
    /// Score every moving sample alike, without the motion weights (which discount the
    /// samples whose force the measured motion does not resolve: abrupt stops, stick-slip).
    /// The fitted model then answers for every sample, at the price of the diagnosis's
    /// calibration, which was set with the weights.
    #[arg(long)]
    unweighted: bool,
    /// The true model of a simulated record (`simulate` writes FILE.truth.toml beside the CSV):
    /// gives the noise floor.
    #[arg(long)]
    truth: Option<PathBuf>,
    /// Read the force this many samples later than logged, to line it up with the motion
    /// (-2..2): +0.5 for a logger that writes beside each position the force held over the
    /// period before it, -0.5 for one that writes the force just commanded for the period
    /// after it. Without it the force is read as logged unless reading it half a sample
    /// later or earlier cuts the baseline's error by 25 % or more
    /// (`diagnose::FORCE_READING_MIN_CUT`; said in the output); the logger's documentation is
    /// the better source.
    #[arg(long, value_parser = force_skew, allow_hyphen_values = true)]
    force_skew: Option<f64>,
}

/// `--force-skew`: a number of samples within `-2..=2`.
fn force_skew(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .parse()
        .map_err(|_| format!("`{s}` is not a number of samples"))?;
    if v.is_finite() && v.abs() <= 2.0 {
        Ok(v)
    } else {
        Err(format!("{s} samples is outside -2..2"))
    }
}

/// The scripting contract of `--json`.
#[derive(Serialize)]
pub struct JsonOut<'a> {
    /// Error of the starting model [%] (as given, or the refitted symmetric baseline).
    pub baseline_rel_err_pct: f64,
    /// Candidates for the next effect on top of the final model, best first.
    pub candidates: &'a [diagnose::Candidate],
    /// Effects added (when --add was given).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub added: Option<Vec<String>>,
    /// Error after adding them [%].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rel_err_pct: Option<f64>,
    /// Error of the final model on the --validate record [%].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub validation_rel_err_pct: Option<f64>,
    /// The refitted symmetric baseline's error [%].
    pub refit_baseline_rel_err_pct: f64,
    /// The true model's error along the measured motion [%] (with --truth).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub noise_floor_pct: Option<f64>,
    /// Error after each stage [%], baseline first (the errors above and here weigh each moving
    /// sample by how well the measured motion resolves its force: `diagnose::motion_weights`).
    pub history: Vec<(String, f64)>,
    /// Error after each stage over the moving samples counted alike [%], baseline first: the
    /// yardstick of `validation_rel_err_pct`.
    pub plain_history: Vec<(String, f64)>,
    /// Where a stage's model was replaced by a better start a candidate revealed: (stage,
    /// `diagnose::Restart`).
    pub restarts: Vec<(&'a str, &'a diagnose::Restart)>,
    /// How much the first baseline's force moves with the position filter's bandwidth [%]
    /// (`Diagnosis::motion_spread_pct`).
    pub motion_spread_pct: f64,
    /// The force reading's white noise measured on the record, rms \[N\]
    /// (`inverse::Prepared::force_noise_n`).
    pub force_noise_n: f64,
    /// What it leaves in the scored band, rms \[N\]: the scale of a candidate's
    /// `explained_rms_n`.
    pub force_noise_in_band_n: f64,
    /// What each stage's model leaves against what the measurement accounts for, baseline
    /// first (`diagnose::Unexplained`; beyond `diagnose::UNEXPLAINED_RATIO` the record shows
    /// something the model does not describe, or a motion read worse than its spread over
    /// filters shows: `diagnose::BEYOND_THE_EIGHT`).
    pub unexplained: Vec<(String, diagnose::Unexplained)>,
    /// Where the final model fails.
    pub regimes: &'a diagnose::regimes::RegimeReport,
    /// Departures from rest: breakaway peaks, holding forces, the dwell trend.
    pub breakaway: &'a diagnose::breakaway::Breakaway,
    /// The position filter the record was read through \[Hz\] (`diagnose::prepare`; a slow
    /// logger's record at most 0.4 of its rate, `inverse::MAX_POSITION_CUTOFF_SHARE_OF_RATE`).
    pub position_cutoff_hz: f64,
    /// How much later than logged the force was read \[samples\]: `--force-skew`, or where
    /// none was given the diagnosis's choice (0, +0.5 or -0.5; a note says why).
    pub force_skew_samples: f64,
    /// What the preparation says of the record (timing repaired, the filter a coarse count
    /// chose).
    pub notes: &'a [String],
    /// The final model's effect parameters that ended at an edge of their search range
    /// (`diagnose::effect_search_edges`): the fit may want a value beyond it.
    pub search_edges: Vec<diagnose::SearchEdge>,
    /// The final model with a Maxwell-slip contact in its bristle's place
    /// (`diagnose::contact::ContactCheck`): whether a contact with presliding memory and
    /// frictional lag describes what the model leaves (null where it was not tried:
    /// `contact_not_tried` says why).
    pub contact: Option<&'a diagnose::contact::ContactCheck>,
    /// Why the contact was not tried (`Diagnosis::contact_not_tried`; null where it was).
    pub contact_not_tried: Option<String>,
    /// Where the diagnosis spent its time \[s\] (`diagnose::PhaseTimes`).
    pub times: diagnose::PhaseTimes,
}

/// Runs the subcommand.
pub fn run(a: &Args) -> Result<()> {
    let files = expand(&a.data)?;
    if files.len() > 1 {
        return run_across(a, &files);
    }
    let rec = Record::read(&files[0])?;
    let name = files[0].display().to_string();
    let given = match &a.params {
        Some(p) => {
            let (file, model) = ParamFile::read(p)?;
            Some(AxisModel {
                mass_kg: a.mass.unwrap_or(file.axis.moving_mass_kg),
                friction: model,
            })
        }
        None => None,
    };
    if let Some(m) = a.mass {
        if !(m.is_finite() && m > 0.0) {
            return Err(Error::Argument {
                flag: "--mass",
                problem: format!("must be a positive number of kilograms, got {m}"),
            });
        }
    }
    let truth = match &a.truth {
        Some(t) => {
            let (file, model) = ParamFile::read(t)?;
            Some(AxisModel {
                mass_kg: file.axis.moving_mass_kg,
                friction: model,
            })
        }
        None => None,
    };
    let opts = Options {
        given,
        mass_kg: a.mass,
        add: a.add.clone(),
        auto: if a.auto { 3 } else { 0 },
        truth,
        unweighted: a.unweighted,
        protocol: diagnose::inverse::Protocol {
            force_skew_samples: a.force_skew.unwrap_or(0.0),
            ..Default::default()
        },
        keep_force_reading: a.force_skew.is_some(),
        ..Default::default()
    };
    let wall = std::time::Instant::now();
    let d = diagnose::diagnose(&rec, &name, &opts)?;
    let validation = match &a.validate {
        Some(v) => {
            let other = Record::read(v)?;
            Some(diagnose::validate(
                d.model(),
                &other,
                &v.display().to_string(),
                d.protocol,
            )?)
        }
        None => None,
    };
    print_text(&d, validation, wall.elapsed().as_secs_f64());
    if let Some(path) = &a.json {
        let last = d.last_stage();
        let out = JsonOut {
            baseline_rel_err_pct: d.given_rel_err_pct.unwrap_or(d.stages[0].fit.rel_err_pct),
            candidates: &last.candidates,
            added: (!a.add.is_empty()).then(|| a.add.clone()),
            rel_err_pct: (!a.add.is_empty()).then_some(last.fit.rel_err_pct),
            validation_rel_err_pct: validation,
            refit_baseline_rel_err_pct: d.stages[0].fit.rel_err_pct,
            noise_floor_pct: d.noise_floor_pct,
            history: d
                .stages
                .iter()
                .map(|s| (s.label.clone(), s.fit.rel_err_pct))
                .collect(),
            plain_history: d
                .stages
                .iter()
                .map(|s| (s.label.clone(), s.plain_rel_err_pct))
                .collect(),
            restarts: d
                .stages
                .iter()
                .flat_map(|s| s.restarts.iter().map(|r| (s.label.as_str(), r)))
                .collect(),
            motion_spread_pct: d.motion_spread_pct,
            force_noise_n: d.prepared.force_noise_n,
            force_noise_in_band_n: d.prepared.force_noise_in_band_n,
            unexplained: d
                .stages
                .iter()
                .map(|s| (s.label.clone(), d.unexplained(s)))
                .collect(),
            regimes: &last.regimes,
            breakaway: &d.breakaway,
            position_cutoff_hz: d.prepared.position_cutoff_hz,
            force_skew_samples: d.prepared.force_skew_samples,
            notes: &d.prepared.notes,
            search_edges: diagnose::effect_search_edges(&last.fit.model),
            contact: d.contact.as_ref(),
            contact_not_tried: d.contact_not_tried(),
            times: d.times,
        };
        super::write_json(path, &out)?;
    }
    if let Some(path) = &a.out_params {
        write_params(&d, path, a.mass)?;
    }
    if let Some(path) = &a.report {
        super::write_text(path, &diagnose::report::html(&d, &name, validation))?;
    }
    Ok(())
}

/// The record files: each `--data` file, and the CSVs in each `--data` folder (sorted).
fn expand(data: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for d in data {
        if d.is_dir() {
            let mut v: Vec<PathBuf> = std::fs::read_dir(d)
                .map_err(|e| Error::io(d, e))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "csv"))
                .collect();
            v.sort();
            if v.is_empty() {
                return Err(Error::NoRecordsInFolder(d.clone()));
            }
            out.extend(v);
        } else {
            out.push(d.clone());
        }
    }
    Ok(out)
}

/// Several records of one axis: friction levels against the conditions (see
/// [`diagnose::across`]).
fn run_across(a: &Args, files: &[PathBuf]) -> Result<()> {
    let records: Vec<(String, Record)> = files
        .iter()
        .map(|f| Record::read(f).map(|r| (f.display().to_string(), r)))
        .collect::<Result<_, _>>()?;
    let opts = Options {
        mass_kg: a.mass,
        ..Default::default()
    };
    let wall = std::time::Instant::now();
    let across = diagnose::across::analyse(&records, &opts)?;
    println!("{} records of one axis:", across.records.len());
    for r in &across.records {
        let conds: Vec<String> = r
            .conditions
            .iter()
            .map(|(k, v)| format!("{k} {}", host_sim::timing::sig3(*v)))
            .collect();
        let levels: Vec<String> = r
            .levels
            .iter()
            .map(|(k, v, se)| {
                let half = diagnose::across::half_width95(*se);
                format!("{k} {v:.4} +- {half:.2e}")
            })
            .collect();
        println!(
            "  {}: {} | {} | error {:.2} %",
            r.name,
            conds.join(", "),
            levels.join(", "),
            r.rel_err_pct
        );
    }
    println!("\nacross records:");
    for t in &across.trends {
        println!("  {}", t.sentence());
    }
    if across.trends.is_empty() {
        println!("  no condition varies across these records");
    }
    if let Some(pv) = across.pooled_viscous {
        println!("  {}", diagnose::across::pooled_sentence(pv));
    }
    println!("({:.2} s)", wall.elapsed().as_secs_f64());
    if let Some(path) = &a.json {
        super::write_json(path, &across)?;
    }
    if let Some(path) = &a.report {
        super::write_text(path, &diagnose::report::across_html(&across))?;
    }
    Ok(())
}

/// Writes the final model as a parameter file (see [`diagnose::parameter_file`]): refused,
/// with the reason and nothing written, when a value would be non-physical for a controller.
pub fn write_params(d: &Diagnosis, path: &Path, user_mass: Option<f64>) -> Result<()> {
    let file = diagnose::parameter_file(d, user_mass).map_err(|e| Error::NotWritten {
        path: path.to_path_buf(),
        source: Box::new(e),
    })?;
    file.write_checked(path)?;
    println!("wrote {}", path.display());
    Ok(())
}

/// Prints the story of a diagnosis.
/// The evidence beyond sliding, in a few lines.
fn print_breakaway(b: &diagnose::breakaway::Breakaway) {
    let n = b.departures.len();
    println!("departures from rest: {n}");
    if n == 0 {
        return;
    }
    for (d, word) in [(1.0, "forward"), (-1.0, "backward")] {
        let sel: Vec<&diagnose::breakaway::Departure> =
            b.departures.iter().filter(|e| e.direction == d).collect();
        if sel.is_empty() {
            continue;
        }
        let peaks: Vec<f64> = sel.iter().map(|e| e.peak_n).collect();
        let holding: Vec<f64> = sel.iter().map(|e| e.holding_n).collect();
        println!(
            "   {word:<8}: {:>3} breakaways, peak force median {:.3} N, holding force before them median {:.3} N",
            sel.len(),
            host_sim::stats::median(&peaks),
            host_sim::stats::median(&holding)
        );
    }
    match (&b.trend, &b.untestable) {
        (_, Some(why)) => println!("   dwell stiction cannot be tested: {why}"),
        (Some(t), None) => println!(
            "   breakaway peak against rest time: grows by {:.3} +- {:.3} N (time constant {:.2} s), evidence dBIC {:.1}{}",
            t.increase_n, t.increase_ci_n, t.time_constant_s, t.delta_bic, t.kinematics_note()
        ),
        (None, None) => {}
    }
}

pub fn print_text(d: &Diagnosis, validation: Option<f64>, wall_s: f64) {
    for n in &d.prepared.notes {
        println!("warning: {n}");
    }
    for t in [&d.tables.symmetric, &d.tables.asymmetric] {
        println!(
            "{:<27}: relative force error {:.2} %  (M {:.2} kg, Fc {:.3} / {:.3} N, sigma2 {:.1} / {:.1} N s/m, forward / backward)",
            t.label,
            t.rel_err_pct,
            t.mass_kg,
            t.coulomb_forward_n,
            t.coulomb_backward_n,
            t.viscous_forward_n_s_per_m,
            t.viscous_backward_n_s_per_m
        );
    }
    if let Some(g) = d.given_rel_err_pct {
        println!("model as given: relative force error {g:.2} %");
    }
    print_breakaway(&d.breakaway);
    println!("motion reading: {}", d.motion_note());
    println!(
        "force reading: white noise {:.3} N rms, {:.3} N rms in the scored band",
        d.prepared.force_noise_n, d.prepared.force_noise_in_band_n
    );
    for (i, s) in d.stages.iter().enumerate() {
        let m = &s.fit.model;
        println!(
            "\n-- {} : relative force error {:.2} % (every moving sample alike {:.2} %) --",
            s.label, s.fit.rel_err_pct, s.plain_rel_err_pct
        );
        if i == 0 {
            println!("   {}", diagnose::contact_values(m));
        }
        // the dwell term a stage added: its rule may be the stage's own (the aging law), which
        // no candidate line shows
        if let (Some(EffectKind::DwellStiction), Some(t)) =
            (s.effect, m.friction.effects.dwell_stiction.as_ref())
        {
            println!(
                "   dwell term: rises by {:.3} N, time constant {:.3} s, renewal distance {:.3} mm, age rule {}, clock {}, growth {}",
                t.max_increase,
                t.time_constant,
                t.renewal_distance * 1e3,
                t.age_at_stick.name(),
                t.clock.name(),
                t.growth.name()
            );
        }
        for r in &s.restarts {
            println!("   {r}");
        }
        for q in &s.fit.at_bound {
            println!(
                "   note: {} ended at the edge of its physical range",
                q.label()
            );
        }
        for (name, edge) in &s.fit.flags.at_search_edge {
            println!("   note: {name} ended at the edge of its search range ({edge:.3e})");
        }
        for e in diagnose::effect_search_edges(&s.fit.model) {
            println!(
                "   note: {} {} ended at the edge of its search range ({:.3e}, searched {:.3e}..{:.3e})",
                e.effect, e.name, e.value, e.range.0, e.range.1
            );
        }
        for (name, why) in &s.fit.flags.priors {
            println!("   not identifiable: {name}: {why}");
        }
        println!("   the model {}", d.unexplained(s));
        println!("   where it fails:");
        for f in &s.regimes.findings {
            println!("   - {f}");
        }
        let last = i + 1 == d.stages.len();
        if last || !s.candidates.is_empty() {
            // an earlier stage's ranking is the one the next stage's effect was chosen from
            match d.stages.get(i + 1).and_then(|next| next.effect) {
                Some(next) => {
                    println!("   candidate effects (best first; {next} was added next):")
                }
                None => println!("   candidate effects (best first):"),
            }
            print_candidates(s);
        }
        if last {
            if !s.candidates.iter().any(|c| c.significant) {
                let beyond = d.beyond_the_eight(s);
                match s.near_miss() {
                    Some((c, why)) => println!(
                        "   no candidate effect is significant; the leading one, {}, is {why}",
                        c.kind
                    ),
                    None if beyond => println!("   no candidate effect is significant"),
                    None => println!(
                        "   no candidate effect is significant: the model explains what this record shows"
                    ),
                }
                if beyond {
                    println!("   {}", diagnose::BEYOND_THE_EIGHT);
                }
            }
            match &d.contact {
                Some(c) => println!("   a Maxwell-slip contact in the bristle's place {c}"),
                None => println!("   {}", d.contact_not_tried().unwrap_or_default()),
            }
        }
    }
    if let Some(n) = d.noise_floor_pct {
        println!(
            "\nnoise floor (the true model driven by the measured motion, same pipeline): {n:.2} %"
        );
    }
    if let Some(v) = validation {
        println!("validation record: relative force error {v:.2} %");
    }
    println!(
        "({} samples, N_eff {:.0}, {:.2} s)",
        d.prepared.len(),
        d.effective_samples,
        wall_s
    );
    println!("(where the diagnosis's time went: {})", d.times);
}

/// A stage's candidate list for [`print_text`]: each candidate's error, dBIC, the force it
/// explains, its verdict and parameters, then one line for each way some candidates were
/// fitted, naming them.
fn print_candidates(s: &diagnose::Stage) {
    for c in &s.candidates {
        match (&c.skipped, c.rel_err_pct, c.delta_bic) {
            (Some(why), _, _) => println!("   {:<24} skipped: {why}", c.kind),
            (None, Some(e), Some(b)) => {
                let params = c.parameter_texts();
                println!(
                    "   {:<24} {:>6.2} %  dBIC {:>8.1}  explains {:>7.3} N  {}  {}",
                    c.kind,
                    e,
                    b,
                    c.explained_rms_n,
                    if c.significant {
                        "SIGNIFICANT"
                    } else {
                        "not significant"
                    },
                    params.join(", ")
                );
                if c.significant {
                    println!("   {:<24} -> {}", "", c.meaning);
                    if let Some(n) = &c.kept_over_larger {
                        println!("   {:<24} -> {n}", "");
                    }
                    if let Some(why) = c.beyond_note() {
                        println!("   {:<24} -> {why}", "");
                    }
                }
                if let Some(why) = c.held_note() {
                    println!("   {:<24} -> {why}", "");
                }
                if let Some(what) = c.saturated_note() {
                    println!("   {:<24} -> {what}", "");
                }
                if let Some(why) = &c.caution {
                    println!("   {:<24} -> cannot be significant: {why}", "");
                }
            }
            _ => {}
        }
    }
    // how some candidates were fitted: one line each, naming them
    for how in diagnose::HOW_FITTED {
        let named = s.named_where(how.flag);
        if !named.is_empty() {
            println!("   {}: {}", named.join(", "), how.sentence);
        }
    }
}
