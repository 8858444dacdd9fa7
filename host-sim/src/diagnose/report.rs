//! The self-contained HTML report: SVG plots (plotters) and the story in words.
//!
//! 1. measured vs model force over time (first and final model);
//! 2. residual vs velocity, coloured by direction (first and final model);
//! 3. the friction bias per regime (first and final model);
//! 4. the error after each added effect, against the noise floor.

use super::contact::{self, ContactCheck};
use super::{Candidate, Diagnosis, HowFitted, Stage, BEYOND_THE_EIGHT};
use crate::chart::{self, Bars, Frame, Line, Panel, FINAL_MODEL, FIRST_MODEL};
use crate::error::Result;

const H: u32 = 300;

/// The error chart's bar for the final model with the contact in its bristle's place.
const CONTACT_BAR: &str = "Maxwell-slip contact in the bristle's place";

/// The heading of the report's section on the Maxwell-slip contact, where it was tried.
pub const CONTACT_HEADING: &str = "The Maxwell-slip contact tried in the bristle's place";

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// The measured force and each model's along the record; with the Maxwell-slip contact's where
/// the diagnosis tried it.
fn force_over_time(d: &Diagnosis, first: &[f64], last: &[f64]) -> Result<String> {
    let p = &d.prepared;
    let idx: Vec<usize> = chart::thin(p.len(), 4000).collect();
    let line = |label, color, data: &[f64]| Line {
        label,
        color,
        points: idx.iter().map(|&i| (p.t[i], data[i])).collect(),
    };
    let mut lines = vec![
        line("measured", chart::MEASURED, &p.force),
        line("first model", FIRST_MODEL, first),
        line("final model", FINAL_MODEL, last),
    ];
    if let Some(c) = &d.contact {
        lines.push(line(
            "Maxwell-slip contact",
            chart::ALTERNATIVE,
            &c.prediction,
        ));
    }
    chart::lines(
        H,
        &Frame {
            title: "Measured vs model force",
            x_desc: "time [s]",
            y_desc: "force [N]",
            x: (p.t[0], p.t[p.len() - 1]),
            y: chart::range(p.force.iter().chain(last).copied()),
        },
        &lines,
    )
}

/// The Maxwell-slip contact tried in the final model's bristle's place: a table of its
/// elements, then one of every parameter fitted with them.
fn contact_tables(c: &ContactCheck) -> String {
    let elements: Vec<Vec<String>> = c
        .elements
        .iter()
        .enumerate()
        .map(|(j, e)| {
            vec![
                format!("{}", j + 1),
                quantity(e.break_distance_m * 1e6, "um"),
                quantity(e.level_n, "N"),
                quantity(e.stiffness_n_per_m(), "N/m"),
            ]
        })
        .collect();
    // (name, value, the searched coordinate's name in `ContactCheck::at_search_edge`)
    let parameters = [
        (
            "stiffness, every element sticking",
            quantity(c.stiffness_n_per_m, "N/m"),
            None,
        ),
        (
            "slip lag rate",
            quantity(c.lag_rate_per_s, "1/s"),
            Some(contact::LAG_RATE),
        ),
        (
            "Coulomb level, the elements together",
            quantity(c.coulomb_n, "N"),
            None,
        ),
        (
            "static level, the elements together",
            quantity(c.static_n, "N"),
            Some(contact::STATIC_OVER_COULOMB),
        ),
        (
            "Stribeck velocity",
            quantity(c.stribeck_velocity_m_per_s, "m/s"),
            Some(contact::STRIBECK_VELOCITY),
        ),
        ("moving mass", quantity(c.mass_kg, "kg"), None),
        ("viscous force over the model's", num(c.viscous_scale), None),
        (
            "damping of the sticking elements",
            quantity(c.damping_n_s_per_m, "N\u{a0}s/m"),
            None,
        ),
    ];
    let parameters: Vec<Vec<String>> = parameters
        .into_iter()
        .map(|(name, value, searched)| {
            let status = match searched {
                Some(s) if c.at_search_edge.iter().any(|(n, _)| *n == s) => {
                    "searched: at the edge of its range"
                }
                Some(_) => "searched",
                None => "solved (linear)",
            };
            vec![name.to_string(), value, status.to_string()]
        })
        .collect();
    table(
        &elements,
        &[
            "element",
            "break distance",
            "level (its share of the curve)",
            "stiffness",
        ],
    ) + &table(&parameters, &["parameter", "value", "status"])
}

/// A value and its unit in a table cell, joined so a narrow column does not part them.
fn quantity(value: f64, unit: &str) -> String {
    format!("{}{NBSP}{unit}", num(value))
}

fn residual_vs_velocity(d: &Diagnosis, first: &[f64], last: &[f64]) -> Result<String> {
    let p = &d.prepared;
    let r_first: Vec<f64> = p.force.iter().zip(first).map(|(f, q)| f - q).collect();
    let r_last: Vec<f64> = p.force.iter().zip(last).map(|(f, q)| f - q).collect();
    let idx: Vec<usize> = chart::thin(p.len(), 3000)
        .filter(|&i| p.weight[i] > 0.0)
        .collect();
    let x = chart::range(p.v.iter().map(|v| v * 1e3));
    let y = chart::range(idx.iter().flat_map(|&i| [r_first[i], r_last[i]]));
    let panel = |title, r: &[f64]| Panel {
        frame: Frame {
            title,
            x_desc: "velocity [mm/s]",
            y_desc: "measured - model [N]",
            x,
            y,
        },
        points: idx
            .iter()
            .map(|&i| {
                let color = if p.v[i] >= 0.0 {
                    chart::PLUS
                } else {
                    chart::MINUS
                };
                (p.v[i] * 1e3, r[i], color)
            })
            .collect(),
        radius: 1,
        rings: Vec::new(),
    };
    chart::scatter_panels(
        H,
        &[
            panel("Residual vs velocity: first model", &r_first),
            panel("Residual vs velocity: final model", &r_last),
        ],
    )
}

/// The evidence beyond sliding: breakaway peaks against the rest before them, per direction,
/// measured and as each model predicts them, and the holding force during each rest.
fn breakaway_section(d: &Diagnosis, first: &[f64], last: &[f64]) -> Result<String> {
    let b = &d.breakaway;
    let mut out = String::from("<h2>Breakaway and standstill</h2>");
    out += &format!(
        "<p>{} departures from a rest of at least {:.0} ms. A peak is the largest force in the \
         direction of motion from {:.0} ms before to {:.0} ms after the rest ends; dwell stiction \
         makes it grow with the rest, asymmetry differs per direction, an offset shifts both \
         directions and the holding force alike.</p>",
        b.departures.len(),
        super::breakaway::MIN_REST_S * 1e3,
        super::breakaway::PRE_S * 1e3,
        super::breakaway::POST_S * 1e3
    );
    match (&b.untestable, &b.trend) {
        (Some(why), _) => {
            out += &format!("<p>Dwell stiction cannot be tested: {}.</p>", escape(why))
        }
        (None, Some(t)) => {
            out += &format!(
                "<p>Peak against rest time: grows by {:.3} &plusmn; {:.3} N (95 %, time constant {:.2} s); evidence dBIC {:.1}{}.</p>",
                t.increase_n, t.increase_ci_n, t.time_constant_s, t.delta_bic, t.kinematics_note()
            )
        }
        _ => {}
    }
    if b.departures.is_empty() {
        return Ok(out);
    }
    let (m_first, m_last) = (b.model_peaks(first), b.model_peaks(last));
    let x = |e: &super::breakaway::Departure| e.rest_s.max(1e-3).log10();
    let xr = chart::range(b.departures.iter().map(x));
    let y = chart::range(
        b.departures
            .iter()
            .zip(m_first.iter().zip(&m_last))
            .flat_map(|(e, (f, l))| [e.peak_n * e.direction, f * e.direction, l * e.direction]),
    );
    let panel = |title, dir: f64| Panel {
        frame: Frame {
            title,
            x_desc: "log10 rest before [s]",
            y_desc: "breakaway peak |F| [N]",
            x: xr,
            y,
        },
        points: b
            .departures
            .iter()
            .zip(m_first.iter().zip(&m_last))
            .filter(|(e, _)| e.direction == dir)
            .flat_map(|(e, (f, l))| [(x(e), f * dir, FIRST_MODEL), (x(e), l * dir, FINAL_MODEL)])
            .collect(),
        radius: 3,
        // the measured peaks as rings over the models' dots: a model that meets a peak shows
        // inside its ring (drawn as dots on top, the final model hid under every peak it met)
        rings: (b.departures.iter())
            .filter(|e| e.direction == dir)
            .map(|e| (x(e), e.peak_n * dir, chart::MEASURED))
            .collect(),
    };
    let holding = Panel {
        frame: Frame {
            title: "Holding force during the rest",
            x_desc: "log10 rest [s]",
            y_desc: "mean force [N]",
            x: xr,
            y: chart::range(b.departures.iter().map(|e| e.holding_n)),
        },
        points: b
            .departures
            .iter()
            .map(|e| {
                let c = if e.direction > 0.0 {
                    chart::PLUS
                } else {
                    chart::MINUS
                };
                (x(e), e.holding_n, c)
            })
            .collect(),
        radius: 3,
        rings: Vec::new(),
    };
    out += &chart::scatter_panels(
        H,
        &[
            panel("Breakaway, moving off in +x", 1.0),
            panel("Breakaway, moving off in -x", -1.0),
            holding,
        ],
    )?;
    out += "<p>Peaks: black rings measured, red first model, blue final model (a model dot \
            inside a ring meets that peak). Holding force: \
            coloured by the direction the axis then moved off in (green +x, purple -x).</p>";
    Ok(out)
}

fn regime_bias(first: &Stage, last: &Stage) -> Result<String> {
    let names: Vec<String> = first
        .regimes
        .regimes
        .iter()
        .map(|r| r.name.clone())
        .collect();
    let value = |s: &Stage, name: &str| {
        s.regimes
            .regimes
            .iter()
            .find(|r| r.name == name)
            .map_or(0.0, |r| {
                if name.starts_with("stuck") {
                    r.mean_residual_n
                } else {
                    r.friction_bias_n
                }
            })
    };
    let a: Vec<f64> = names.iter().map(|n| value(first, n)).collect();
    let b: Vec<f64> = names.iter().map(|n| value(last, n)).collect();
    chart::bars(
        H + 60,
        "Friction the model misses, by regime (> 0: under-predicted)",
        "mean residual [N]",
        &names,
        &[
            Bars {
                label: "first model",
                color: FIRST_MODEL,
                values: a,
            },
            Bars {
                label: "final model",
                color: FINAL_MODEL,
                values: b,
            },
        ],
        None,
    )
}

/// Joins a number to its unit in a table cell: a narrow column breaks the line at a space, and
/// "1.30" above "%" reads as two cells.
const NBSP: char = '\u{a0}';

fn table(rows: &[Vec<String>], head: &[&str]) -> String {
    let mut s = String::from("<table><tr>");
    for h in head {
        s += &format!("<th>{}</th>", escape(h));
    }
    s += "</tr>";
    for r in rows {
        s += "<tr>";
        for c in r {
            s += &format!("<td>{}</td>", escape(c));
        }
        s += "</tr>";
    }
    s + "</table>"
}

/// Wheel zoom, drag pan and double-click reset for the SVG charts inside `.zoom` blocks, by
/// moving each SVG's viewBox: self-contained, works offline (no library, no network).
const ZOOM_SCRIPT: &str = "<script>\
document.querySelectorAll('.zoom svg').forEach(function(s){\
var w=s.viewBox.baseVal.width,h=s.viewBox.baseVal.height,v=[0,0,w,h],drag=null;\
function set(){s.setAttribute('viewBox',v.join(' '));}\
function at(e){var r=s.getBoundingClientRect();return[v[0]+(e.clientX-r.left)/r.width*v[2],v[1]+(e.clientY-r.top)/r.height*v[3]];}\
s.addEventListener('wheel',function(e){e.preventDefault();var p=at(e),k=e.deltaY<0?0.8:1.25;\
v=[p[0]-(p[0]-v[0])*k,p[1]-(p[1]-v[1])*k,v[2]*k,v[3]*k];set();});\
s.addEventListener('mousedown',function(e){drag=at(e);});\
window.addEventListener('mouseup',function(){drag=null;});\
s.addEventListener('mousemove',function(e){if(!drag)return;var p=at(e);v[0]-=p[0]-drag[0];v[1]-=p[1]-drag[1];set();});\
s.addEventListener('dblclick',function(){v=[0,0,w,h];set();});\
s.style.cursor='zoom-in';});\
</script>";

/// A number for a table: three significant digits, in exponent form when very large or small.
fn num(v: f64) -> String {
    crate::timing::number(v, 3)
}

/// A candidate's verdict in the table of the next candidates. How it was fitted is said by
/// its label and its note's number in `notes` (the ways of [`super::HOW_FITTED`] that hold of
/// some candidate in the table, in order; [`candidate_notes`]).
fn verdict(c: &Candidate, notes: &[HowFitted]) -> String {
    let mut v = match &c.skipped {
        Some(w) => format!("skipped: {w}"),
        None if c.significant => "SIGNIFICANT".into(),
        None => match (&c.caution, c.held_note()) {
            (Some(why), _) => format!("not significant: {why}"),
            (None, Some(why)) => why,
            (None, None) => "not significant".into(),
        },
    };
    for (k, how) in notes.iter().enumerate() {
        if (how.flag)(c) {
            v += &format!(" ({}, note {}", how.label, k + 1);
            if let Some(detail) = (how.detail)(c) {
                v += &format!("; {detail}");
            }
            v += ")";
        }
    }
    if let Some(what) = c.saturated_note() {
        v += &format!(" ({what})");
    }
    if let Some(n) = c.kept_over_larger.filter(|_| c.significant) {
        // the whole sentence opens a one-stage page; a cell holds its numbers
        v += &format!(" (kept over {}, which contains it", n.larger);
        if let Some(cut) = n.larger_on_top_cut() {
            v += &format!(
                ": on top of it {} cuts the error by {:.0} % only",
                n.larger,
                100.0 * cut
            );
        }
        v += ")";
    }
    v
}

/// The ways of [`super::HOW_FITTED`] that hold of some candidate in `candidates`: the notes
/// under their table, in order.
fn candidate_notes(candidates: &[Candidate]) -> Vec<HowFitted> {
    super::HOW_FITTED
        .into_iter()
        .filter(|how| candidates.iter().any(how.flag))
        .collect()
}

/// A table of candidates ([`candidate_rows`]) and, under it, its numbered notes: each way a
/// candidate in it was fitted, the candidates it holds of and its whole sentence, once.
fn candidate_table(candidates: &[Candidate]) -> String {
    let notes = candidate_notes(candidates);
    let mut out = table(&candidate_rows(candidates, &notes), &CANDIDATE_HEAD);
    if !notes.is_empty() {
        out += "<ol class=\"notes\">";
        for how in &notes {
            let named: Vec<&str> = candidates
                .iter()
                .filter(|c| (how.flag)(c))
                .map(|c| c.kind.name())
                .collect();
            out += &format!(
                "<li><b>{}</b> ({}): {}</li>",
                escape(how.label),
                escape(&named.join(", ")),
                escape(how.sentence)
            );
        }
        out += "</ol>";
    }
    out
}

/// The final model's rows: every parameter-file entry with its interval and status.
fn model_rows(fit: &super::fit::Fit) -> Vec<Vec<String>> {
    let m = &fit.model;
    let file = crate::params_file::ParamFile::new(&m.friction, m.mass_kg);
    // (section, key, value): a number, or a rule by its name (the dwell's age at a stick)
    let mut entries: Vec<(String, String, Entry)> = Vec::new();
    enum Entry {
        Number(f64),
        Rule(String),
    }
    let mut push = |section: &str, value: toml::Value| {
        if let toml::Value::Table(t) = value {
            for (k, v) in t {
                match v {
                    toml::Value::Float(x) => {
                        entries.push((section.to_string(), k, Entry::Number(x)))
                    }
                    toml::Value::Integer(i) => {
                        entries.push((section.to_string(), k, Entry::Number(i as f64)))
                    }
                    toml::Value::Array(a) => {
                        for (j, x) in a.iter().enumerate() {
                            if let Some(x) = x.as_float() {
                                entries.push((
                                    section.to_string(),
                                    format!("{k}[{j}]"),
                                    Entry::Number(x),
                                ));
                            }
                        }
                    }
                    toml::Value::Table(_) => push_nested(&mut entries, section, &k, v),
                    _ => {}
                }
            }
        }
    };
    fn push_nested(
        entries: &mut Vec<(String, String, Entry)>,
        section: &str,
        name: &str,
        v: toml::Value,
    ) {
        if let toml::Value::Table(t) = v {
            for (k, v) in t {
                if let Some(x) = v.as_float().or(v.as_integer().map(|i| i as f64)) {
                    entries.push((format!("{section}.{name}"), k, Entry::Number(x)));
                } else if let toml::Value::String(rule) = v {
                    entries.push((format!("{section}.{name}"), k, Entry::Rule(rule)));
                } else if let toml::Value::Array(a) = v {
                    for (j, x) in a.iter().enumerate() {
                        if let Some(x) = x.as_float() {
                            entries.push((
                                format!("{section}.{name}"),
                                format!("{k}[{j}]"),
                                Entry::Number(x),
                            ));
                        }
                    }
                }
            }
        }
    }
    for (section, value) in [
        ("lugre", toml::Value::try_from(file.lugre)),
        ("axis", toml::Value::try_from(file.axis)),
        ("effects", toml::Value::try_from(&file.effects)),
    ] {
        if let Ok(v) = value {
            push(section, v);
        }
    }
    // the effects' searched parameters at an edge of their range, by section and name
    let effect_edges = super::effect_search_edges(m);
    entries
        .into_iter()
        .map(|(section, key, value)| {
            let estimate = fit.estimates.iter().find(|e| e.param.label() == key);
            let prior = fit.flags.priors.iter().find(|p| p.0 == key);
            let effect = section
                .strip_prefix("effects.")
                .and_then(|n| super::parse_effect(n).ok());
            // searched (no interval from the linearisation): the stage's nonlinear parameters,
            // and an effect's own ones (its grid's name, or its second shape parameter's)
            let searched = match effect {
                Some(k) => {
                    let info = super::effect_info(k);
                    info.nonlinear.is_some_and(|(n, _, _)| n == key)
                        || info.shape.is_some_and(|(n, _)| n == key)
                        || info.stage_searched.is_some_and(|(n, _)| n == key)
                }
                None => section == "lugre" && estimate.is_none(),
            };
            let edge = match effect {
                Some(k) => effect_edges
                    .iter()
                    .find(|e| e.effect == k && e.name == key)
                    .map(|e| format!(" ({} .. {})", num(e.range.0), num(e.range.1))),
                None => fit
                    .flags
                    .at_search_edge
                    .iter()
                    .find(|p| p.0 == key)
                    .map(|_| String::new()),
            };
            let interval = estimate.map_or(String::new(), |e| {
                let (low, high) = e.interval_95();
                format!("{}{NBSP}..{NBSP}{}", num(low), num(high))
            });
            let value = match value {
                Entry::Number(x) => num(x),
                // (the only rules: the dwell's age, clock and growth, which the candidate's
                // search chose, or the stage's where the term was added under the aging law or
                // grown hyperbolically)
                Entry::Rule(rule) => {
                    let how = match key.as_str() {
                        "age_at_stick" => {
                            "chosen by the data (accumulates or restarts; aging where the model \
                             leaves more than the measurement accounts for, or once added)"
                        }
                        "clock" => "chosen by the data (body_speed or contact_slip)",
                        "growth" => {
                            "chosen by the data (exponential; hyperbolic under the aging rule, \
                             or once added)"
                        }
                        _ => "chosen by the data",
                    };
                    return vec![section, key, rule, String::new(), how.into()];
                }
            };
            let status = if let Some(p) = prior {
                format!("prior: {}", p.1)
            } else if let Some(range) = edge {
                format!(
                    "at the edge of its search range{range}: the fit may want a value beyond it"
                )
            } else if fit.at_bound.iter().any(|q| q.label() == key) {
                "at the edge of its physical range: the data pushed it against physics, or the \
                 record does not determine it"
                    .into()
            } else if estimate.is_some() {
                "fitted".into()
            } else if searched {
                "searched (nonlinear): no interval".into()
            } else {
                "fixed by the effect's definition".into()
            };
            vec![section, key, value, interval, status]
        })
        .collect()
}

/// The page of a diagnosis across records: each friction level against each condition that
/// varies, every record with its 95 % interval, the least-squares line and its verdict in
/// words; then every record's levels.
pub fn across_html(a: &super::across::Across) -> String {
    across_page(a).unwrap_or_else(|e| {
        format!(
            "<!doctype html><html><body><p>report failed: {}</p></body></html>",
            escape(&e.to_string())
        )
    })
}

fn across_page(a: &super::across::Across) -> Result<String> {
    let mut out = String::from(
        "<!doctype html><html><head><meta charset=\"utf-8\"><title>lugre-servo: friction across records</title><style>\
         body{font-family:sans-serif;max-width:960px;margin:2em auto;color:#222}\
         table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #ccc;padding:4px 8px;text-align:left}\
         .sig{color:#1b7837;font-weight:bold}</style></head><body>",
    );
    out += &format!(
        "<h1>Friction across {} records of one axis</h1>",
        a.records.len()
    );
    for t in &a.trends {
        let points: Vec<(f64, f64, f64)> = a
            .records
            .iter()
            .filter_map(|r| {
                let x = r.condition(&t.condition)?;
                let (y, h) = r.interval95(&t.level)?;
                Some((x, y, h))
            })
            .collect();
        let x = chart::range(points.iter().map(|p| p.0));
        let y = chart::range(points.iter().flat_map(|p| [p.1 - p.2, p.1 + p.2]));
        let x_mean = crate::stats::mean(&points.iter().map(|p| p.0).collect::<Vec<_>>());
        let title = format!("{} against {}", t.level, t.condition);
        out += &format!(
            "<h2>{}</h2><p class=\"{}\">{}</p>",
            escape(&title),
            if t.significant { "sig" } else { "" },
            escape(&t.sentence())
        );
        out += &chart::intervals(
            H,
            &Frame {
                title: &title,
                x_desc: &t.condition,
                y_desc: &t.level,
                x,
                y,
            },
            &points,
            Some((x_mean, t.mean_level, t.slope)),
        )?;
    }
    if a.trends.is_empty() {
        out += "<p>No condition varies across these records.</p>";
    }
    if let Some(pv) = a.pooled_viscous {
        out += &format!("<p>{}</p>", escape(&super::across::pooled_sentence(pv)));
    }
    out += "<h2>Records</h2><p>Levels with 95 % intervals (block jackknife, Student's t).</p>";
    let rows: Vec<Vec<String>> = a
        .records
        .iter()
        .map(|r| {
            let conds: Vec<String> = r
                .conditions
                .iter()
                .map(|(k, v)| format!("{k} {}", crate::timing::sig3(*v)))
                .collect();
            let levels: Vec<String> = r
                .levels
                .iter()
                .map(|(k, v, se)| {
                    format!(
                        "{k} {} +- {}",
                        crate::timing::sig3(*v),
                        crate::timing::sig3(super::across::half_width95(*se))
                    )
                })
                .collect();
            vec![
                r.name.clone(),
                conds.join(", "),
                levels.join(", "),
                format!("{:.2}{NBSP}%", r.rel_err_pct),
            ]
        })
        .collect();
    out += &table(&rows, &["record", "conditions", "levels", "fit error"]);
    out += "</body></html>";
    Ok(out)
}

/// The whole page.
pub fn html(d: &Diagnosis, name: &str, validation: Option<f64>) -> String {
    match page(d, name, validation) {
        Ok(s) => s,
        Err(e) => format!(
            "<!doctype html><html><body><p>report failed: {}</p></body></html>",
            escape(&e.to_string())
        ),
    }
}

fn page(d: &Diagnosis, name: &str, validation: Option<f64>) -> Result<String> {
    let first = &d.stages[0];
    let last = d.last_stage();
    let pred_first = &first.fit.prediction;
    let pred_last = &last.fit.prediction;
    let mut history_labels: Vec<String> = d.stages.iter().map(|s| s.label.clone()).collect();
    let mut history: Vec<f64> = d.stages.iter().map(|s| s.fit.rel_err_pct).collect();
    if let Some(c) = &d.contact {
        // the last bar: the final model with a Maxwell-slip contact in its bristle's place
        history_labels.push(CONTACT_BAR.into());
        history.push(c.rel_err_pct);
    }
    let mut out = String::from(
        "<!doctype html><html><head><meta charset=\"utf-8\"><title>lugre-servo diagnosis</title><style>\
         body{font-family:sans-serif;max-width:960px;margin:2em auto;color:#222}\
         table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #ccc;padding:4px 8px;text-align:left}\
         .big{font-size:1.4em}ol.notes{font-size:0.9em;color:#444}.sig{color:#1b7837;font-weight:bold}</style></head><body>",
    );
    out += &format!("<h1>Friction diagnosis of {}</h1>", escape(name));
    let end = last.fit.rel_err_pct;
    out += &format!(
        "<p class=\"big\">Relative force error: <b>{:.2} %</b> with the first model, <b>{:.2} %</b> with the final one{}.</p>",
        first.fit.rel_err_pct,
        end,
        d.noise_floor_pct.map_or(String::new(), |n| format!(" (noise floor {n:.2} %)"))
    );
    for n in &d.prepared.notes {
        out += &format!("<p>Note: {}.</p>", escape(n));
    }
    for w in d.stages.windows(2) {
        let effect = w[1].effect.map_or("", |k| k.name());
        let meaning = w[1].effect.map_or("", |k| super::effect_info(k).meaning);
        out += &format!(
            "<p>Added <b>{}</b>: {}. Error {:.2} % &rarr; {:.2} %.</p>",
            escape(effect),
            escape(meaning),
            w[0].fit.rel_err_pct,
            w[1].fit.rel_err_pct
        );
    }
    if let Some(c) = first.first_significant() {
        if d.stages.len() == 1 {
            out += &format!(
                "<p>Most likely missing effect: <b>{}</b> ({}). Add it with <code>--add {}</code>.{}</p>",
                escape(c.kind.name()),
                escape(&c.meaning),
                escape(c.kind.name()),
                c.kept_over_larger
                    .map(|n| format!(" It was {}.", escape(&n.to_string())))
                    .or_else(|| c.beyond_note().map(|n| format!(" It is {}.", escape(&n))))
                    .unwrap_or_default()
            );
        }
    } else if let Some(c) = first
        .candidates
        .iter()
        .find(|c| c.held_by_contact.is_some())
        .filter(|_| d.stages.len() == 1)
    {
        out += &format!(
            "<p>No effect is significant. The <b>{}</b> term is {}.</p>",
            escape(c.kind.name()),
            escape(&c.held_note().unwrap_or_default()),
        );
    } else if let Some((c, why)) = first.near_miss().filter(|_| d.stages.len() == 1) {
        out += &format!(
            "<p>No effect is significant. The leading candidate, <b>{}</b>, is {}.</p>",
            escape(c.kind.name()),
            escape(&why),
        );
    }
    // what the final model leaves, against what the measurement accounts for
    out += &format!(
        "<p>The final model {}.{}</p>",
        escape(&d.unexplained(last).to_string()),
        if d.beyond_the_eight(last) {
            format!(
                " <b>No candidate is significant, and {}.</b>",
                escape(BEYOND_THE_EIGHT)
            )
        } else {
            String::new()
        }
    );
    out += &match &d.contact {
        Some(c) => format!(
            "<p>A Maxwell-slip contact in place of the final model's bristle {}.</p>",
            escape(&c.to_string())
        ),
        None => format!(
            "<p>{}.</p>",
            escape(&capitalised(&d.contact_not_tried().unwrap_or_default()))
        ),
    };
    out += "<p>Error = 100 ||F - F_hat|| / ||F|| on the force filtered at 20 Hz, over the samples where the axis moves \
            (while stuck, friction balances whatever force is applied and cannot be predicted from the motion).</p>";
    out += &format!(
        "<p>Motion reading: {}. Counting every moving sample alike: {:.2} % with the first model, {:.2} % with the \
         final one.</p>",
        escape(&d.motion_note()),
        first.plain_rel_err_pct,
        last.plain_rel_err_pct
    );
    out += &format!(
        "<p>Force reading: white noise {:.3} N rms, {:.3} N rms in the scored band (the scale of the \
         force each candidate explains).</p>",
        d.prepared.force_noise_n, d.prepared.force_noise_in_band_n
    );
    for s in &d.stages {
        for r in &s.restarts {
            out += &format!(
                "<p>{}: {}; the candidates were judged again against it.</p>",
                escape(&s.label),
                escape(&r.to_string())
            );
        }
    }
    if let Some(g) = d.given_rel_err_pct {
        out += &format!("<p>The model from the parameter file, as given: {g:.2} %.</p>");
    }
    if let Some(v) = validation {
        out += &format!("<p>On the validation record (no refit): {v:.2} %.</p>");
    }
    out += "<h2>Where the model fails</h2><ul>";
    if d.stages.len() == 1 {
        // one model: first and final are the same, listed once
        for f in &last.regimes.findings {
            out += &format!("<li>{}</li>", escape(f));
        }
    } else {
        for f in &first.regimes.findings {
            out += &format!("<li>first model: {}</li>", escape(f));
        }
        for f in &last.regimes.findings {
            out += &format!("<li>final model: {}</li>", escape(f));
        }
    }
    out += "</ul>";
    out += &chart::bars(
        H + 60,
        "Error after each added effect",
        "relative force error [%]",
        &history_labels,
        &[Bars {
            label: "error",
            color: FINAL_MODEL,
            values: history,
        }],
        d.noise_floor_pct,
    )?;
    out += "<p>The next two charts zoom: mouse wheel over a point, drag to pan, double-click \
            to reset.</p>";
    out += &format!(
        "<div class=\"zoom\">{}</div>",
        force_over_time(d, pred_first, pred_last)?
    );
    out += &format!(
        "<div class=\"zoom\">{}</div>",
        residual_vs_velocity(d, pred_first, pred_last)?
    );
    out += "<p>Green: moving in +x, purple: moving in -x.</p>";
    out += &regime_bias(first, last)?;
    out += &breakaway_section(d, pred_first, pred_last)?;
    out += "<h2>Which effect is missing (next candidates, best first)</h2>";
    out += &candidate_table(&last.candidates);
    out += &chosen_sections(d);
    out += "<h2>Final model</h2><p>Every parameter of the model the record ends with, in the \
            parameter file's names and units; the 95 % interval where the fit determined it, and \
            what it is where it did not.</p>";
    out += &table(
        &model_rows(&last.fit),
        &["section", "parameter", "value", "95 % interval", "status"],
    );
    if let Some(c) = &d.contact {
        out += &format!(
            "<h2>{CONTACT_HEADING}</h2><p>{}. It errs {:.2} % against the final model's {:.2} % \
             (the last bar above).</p>",
            if c.describes {
                "It describes what the final model leaves"
            } else {
                "It does not describe what the final model leaves"
            },
            c.rel_err_pct,
            c.model_rel_err_pct
        );
        out += &contact_tables(c);
    }
    let edges = super::effect_search_edges(&last.fit.model);
    if !edges.is_empty() {
        let listed: Vec<String> = edges
            .iter()
            .map(|e| {
                format!(
                    "{} {} = {} (searched {} .. {})",
                    e.effect,
                    e.name,
                    num(e.value),
                    num(e.range.0),
                    num(e.range.1)
                )
            })
            .collect();
        out += &format!(
            "<p><b>At the edge of its search range</b> (the fit may want a value beyond it): {}.</p>",
            escape(&listed.join("; "))
        );
    }
    out += ZOOM_SCRIPT;
    out += "</body></html>";
    Ok(out)
}

/// Where effects were added (`--add`, `--auto`), each earlier stage's candidate table: the
/// ranking the added effect was chosen from, with each candidate's verdict and how it was
/// fitted (a candidate handed the nested check's fit says so). The section "Which effect is
/// missing" shows the last stage's only. Empty for a one-stage diagnosis.
fn chosen_sections(d: &Diagnosis) -> String {
    let mut out = String::new();
    for w in d.stages.windows(2) {
        let (Some(added), false) = (w[1].effect, w[0].candidates.is_empty()) else {
            continue;
        };
        if out.is_empty() {
            out += "<h2>How each added effect was chosen</h2>";
        }
        out += &format!(
            "<p><b>{}</b> ({:.2}{NBSP}%): its candidates, best first; <b>{}</b> was added \
             ({:.2}{NBSP}%).</p>",
            escape(&w[0].label),
            w[0].fit.rel_err_pct,
            escape(added.name()),
            w[1].fit.rel_err_pct
        );
        out += &candidate_table(&w[0].candidates);
    }
    out
}

/// The candidate tables' column heads ([`candidate_rows`]).
const CANDIDATE_HEAD: [&str; 7] = [
    "effect",
    "what it means",
    "error with it",
    "dBIC",
    "force it explains (rms)",
    "verdict",
    "parameters (95 % interval)",
];

/// The candidate table's rows: effect, meaning, error with it, dBIC, the force it explains,
/// the verdict (with the numbers of its `notes`), and its parameters with their intervals
/// ([`Candidate::parameter_texts`]: an edge of the search range is said, as the CLI says it).
fn candidate_rows(candidates: &[Candidate], notes: &[HowFitted]) -> Vec<Vec<String>> {
    candidates
        .iter()
        .map(|c| {
            vec![
                c.kind.name().to_string(),
                c.meaning.clone(),
                c.rel_err_pct
                    .map_or("-".into(), |e| format!("{e:.2}{NBSP}%")),
                c.delta_bic.map_or("-".into(), |b| format!("{b:.1}")),
                c.rel_err_pct
                    .map_or("-".into(), |_| format!("{:.3}{NBSP}N", c.explained_rms_n)),
                verdict(c, notes),
                c.parameter_texts().join("; "),
            ]
        })
        .collect()
}

/// `text` with its first letter in capitals.
fn capitalised(text: &str) -> String {
    let mut c = text.chars();
    c.next()
        .map(|f| f.to_uppercase().chain(c).collect())
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnose::fit::{Fit, Flags};
    use crate::diagnose::inverse::AxisModel;
    use lugre_servo::friction::{effects as fx, FrictionModel, LugreParams};

    /// A model with a viscous power law whose exponent sits at the low end of its grid.
    fn fit_with_viscous_exponent(exponent: f64) -> Fit {
        let params = LugreParams::new(1e8, 1e3, 2e3, 300.0, 400.0, 5e-3).unwrap();
        let mut effects = fx::Effects::none();
        effects.viscous_power = Some(fx::ViscousPower {
            exponent,
            reference_velocity: 0.02,
        });
        Fit {
            model: AxisModel {
                mass_kg: 200.0,
                friction: FrictionModel { params, effects },
            },
            prediction: Vec::new(),
            rel_err_pct: 1.0,
            rel_err_all_pct: 1.0,
            rss: 1.0,
            estimates: Vec::new(),
            covariance: nalgebra::DMatrix::zeros(0, 0),
            at_bound: Vec::new(),
            flags: Flags::default(),
        }
    }

    /// The model table's row of `key` in `section`: section, key, value, interval, status.
    fn row<'a>(rows: &'a [Vec<String>], section: &str, key: &str) -> &'a [String] {
        rows.iter()
            .find(|r| r[0] == section && r[1] == key)
            .unwrap_or_else(|| panic!("{section} {key} in {rows:?}"))
    }

    fn status(rows: &[Vec<String>], section: &str, key: &str) -> String {
        row(rows, section, key)[4].clone()
    }

    /// The final model table never lets a searched parameter at the end of its range pass as
    /// found: it says so with the range; a searched parameter inside its range and a value the
    /// effect's definition fixes are told apart.
    #[test]
    fn the_model_table_says_which_parameter_ended_at_its_search_edge() {
        let rows = model_rows(&fit_with_viscous_exponent(0.3));
        let edge = status(&rows, "effects.viscous_power", "exponent");
        assert!(
            edge.starts_with("at the edge of its search range (0.3 .. 2.5)"),
            "{edge}"
        );
        assert_eq!(
            status(&rows, "effects.viscous_power", "reference_velocity_m_per_s"),
            "fixed by the effect's definition"
        );
        assert_eq!(
            status(&rows, "lugre", "bristle_stiffness_n_per_m"),
            "searched (nonlinear): no interval"
        );
        let inside = model_rows(&fit_with_viscous_exponent(1.15));
        assert_eq!(
            status(&inside, "effects.viscous_power", "exponent"),
            "searched (nonlinear): no interval"
        );
    }

    /// A linear parameter that ended on an edge of its physical range (`Fit::at_bound`: a
    /// Coulomb level of zero, session 109) is not shown as fitted, in the model table and in a
    /// candidate's list; one inside its range is.
    #[test]
    fn a_linear_parameter_at_its_physical_edge_is_not_shown_as_fitted() {
        use crate::diagnose::fit::{Estimate, Param};
        use crate::diagnose::{effect_info, ParamReport};
        use lugre_servo::friction::EffectKind;
        let mut fit = fit_with_viscous_exponent(1.15);
        fit.estimates = [Param::Coulomb, Param::Viscous]
            .map(|param| Estimate {
                param,
                value: 0.0,
                std_error: 5.0,
            })
            .to_vec();
        fit.at_bound = vec![Param::Coulomb];
        let rows = model_rows(&fit);
        // an asymmetry ratio the record does not determine: its interval within its range
        let mut asym_fit = fit.clone();
        asym_fit.model.friction.effects.asymmetry = Some(fx::Asymmetry {
            coulomb_ratio: -0.95,
            static_ratio: 0.0,
            viscous_ratio: 0.0,
            stribeck_velocity_ratio: 0.0,
        });
        asym_fit.estimates.push(Estimate {
            param: Param::AsymCoulomb,
            value: -0.95,
            std_error: 1e10,
        });
        asym_fit.at_bound.push(Param::AsymCoulomb);
        let asym_rows = model_rows(&asym_fit);
        let ratio = row(&asym_rows, "effects.asymmetry", "coulomb_ratio");
        assert_eq!(ratio[3], format!("-0.95{NBSP}..{NBSP}0.95"), "{ratio:?}");
        assert!(
            ratio[4].starts_with("at the edge of its physical range"),
            "{ratio:?}"
        );
        // a level that cannot be negative: its interval from zero
        let level = row(&rows, "lugre", "coulomb_force_n");
        assert_eq!(level[3], format!("0{NBSP}..{NBSP}9.8"), "{level:?}");
        let edge = status(&rows, "lugre", "coulomb_force_n");
        assert!(
            edge.starts_with("at the edge of its physical range"),
            "{edge}"
        );
        assert_eq!(
            status(&rows, "lugre", "viscous_coefficient_n_s_per_m"),
            "fitted"
        );
        let mut asym = Candidate::unscored(effect_info(EffectKind::Asymmetry));
        let param = |name: &str, value: f64, at_physical_edge: bool| ParamReport {
            name: name.into(),
            value,
            ci_low: -0.95,
            ci_high: 0.95,
            at_search_edge: false,
            at_physical_edge,
        };
        asym.parameters = vec![
            param("coulomb_ratio", -0.95, true),
            param("static_ratio", 0.02, false),
        ];
        let texts = asym.parameter_texts();
        assert!(
            texts[0].ends_with("(at the edge of its physical range)"),
            "{texts:?}"
        );
        assert!(!texts[1].contains("edge"), "{texts:?}");
    }

    /// A position dependence's net shape is said over the stroke visited, to 0.1 mm, with a
    /// start that rounds to zero written as zero (EMPS read "(-0.0000 .. 0.2464 m)").
    #[test]
    fn the_stroke_visited_starts_at_zero_not_minus_zero() {
        use crate::diagnose::effect_info;
        use lugre_servo::friction::EffectKind;
        let mut fit = fit_with_viscous_exponent(1.0);
        let mut pd = fx::PositionDependence::linear(1.0, 0.1232);
        pd.half_span = 0.1232 + 2e-8;
        fit.model.friction.effects.position_dependence = Some(pd);
        let mut c = Candidate::unscored(effect_info(EffectKind::PositionDependence));
        c.fit = Some(fit);
        let texts = c.parameter_texts();
        assert!(
            texts[0].starts_with("along the stroke visited (0.0000 .. 0.2464 m)"),
            "{texts:?}"
        );
    }

    /// How candidates were fitted is said once per table, in a numbered note under it that
    /// names them; each verdict cell carries the short label and the note's number (a cell
    /// that held the whole sentence read as a paragraph: EMPS's asymmetry and offset, session
    /// 110), and a candidate given the nested check's fit keeps its own search's error in it.
    #[test]
    fn how_candidates_were_fitted_is_said_once_under_their_table() {
        use crate::diagnose::{effect_info, FROM_NESTED_CHECK, FROM_STATIC_TABLE};
        use lugre_servo::friction::EffectKind;
        let mut asymmetry = Candidate::unscored(effect_info(EffectKind::Asymmetry));
        asymmetry.from_static_table = true;
        asymmetry.from_nested_check = Some(1.234);
        let mut offset = Candidate::unscored(effect_info(EffectKind::Offset));
        offset.from_static_table = true;
        let plain = Candidate::unscored(effect_info(EffectKind::ViscousPower));
        let html = candidate_table(&[asymmetry, offset, plain]);
        assert_eq!(
            html.matches(&escape(FROM_STATIC_TABLE)).count(),
            1,
            "{html}"
        );
        assert_eq!(
            html.matches(&escape(FROM_NESTED_CHECK)).count(),
            1,
            "{html}"
        );
        assert!(
            html.contains("fitted from the static table</b> (asymmetry, offset)"),
            "{html}"
        );
        // a table whose candidates were all fitted the ordinary way has no notes
        let ordinary = Candidate::unscored(effect_info(EffectKind::Offset));
        assert!(!candidate_table(&[ordinary]).contains("<ol"));
        let cells: Vec<&str> = html.split("<td>").collect();
        let verdict_of = |effect: &str| {
            let at = cells
                .iter()
                .position(|c| c.starts_with(&format!("{effect}<")))
                .unwrap();
            cells[at + 5]
        };
        assert!(
            verdict_of("asymmetry").contains(
                "(fitted from the static table, note 1) (given the nested check's fit, note 2; \
                 its own search had reached 1.23 %)"
            ),
            "{}",
            verdict_of("asymmetry")
        );
        assert!(verdict_of("offset").contains("(fitted from the static table, note 1)"));
        assert!(!verdict_of("offset").contains("note 2"));
        assert!(!verdict_of("viscous_power").contains("note"));
    }

    /// The report's candidate table says where a candidate's parameter ended at the edge of
    /// its search range, as the CLI's list does (both take `Candidate::parameter_texts`), and
    /// only there; a dwell candidate's age rule and clock are listed with its parameters.
    #[test]
    fn the_candidate_table_says_which_parameter_ended_at_its_search_edge() {
        use crate::diagnose::{effect_info, ParamReport};
        use lugre_servo::friction::{DwellAge, EffectKind};
        let param = |name: &str, value: f64, at_search_edge: bool| ParamReport {
            name: name.into(),
            value,
            ci_low: value,
            ci_high: value,
            at_search_edge,
            at_physical_edge: false,
        };
        let mut load = Candidate::unscored(effect_info(EffectKind::LoadDependence));
        load.parameters = vec![param("terms", 4.0, true), param("static_share", 1.0, false)];
        let mut dwell = Candidate::unscored(effect_info(EffectKind::DwellStiction));
        dwell.parameters = vec![param("time_constant_s", 0.1, true)];
        let mut fit = fit_with_viscous_exponent(1.0);
        fit.model.friction.effects.dwell_stiction = Some(fx::DwellStiction {
            max_increase: 50.0,
            time_constant: 0.1,
            stick_velocity: 2e-4,
            renewal_distance: 1e-3,
            age_at_stick: DwellAge::Restarts,
            clock: lugre_servo::friction::DwellClock::ContactSlip,
            growth: lugre_servo::friction::DwellGrowth::Exponential,
        });
        dwell.fit = Some(fit);
        let rows = candidate_rows(&[load, dwell], &[]);
        let texts: Vec<&str> = rows[0][6].split("; ").collect();
        assert_eq!(texts.len(), 2, "{texts:?}");
        assert!(texts[0].starts_with("terms = 4 [4, 4]"), "{texts:?}");
        assert!(
            texts[0].ends_with("(at the edge of its search range)"),
            "{texts:?}"
        );
        assert!(!texts[1].contains("edge"), "{texts:?}");
        let dwell_texts: Vec<&str> = rows[1][6].split("; ").collect();
        assert!(dwell_texts[0].ends_with("(at the edge of its search range)"));
        assert_eq!(
            dwell_texts[1..],
            [
                "age_at_stick = restarts",
                "clock = contact_slip",
                "growth = exponential"
            ]
        );
    }
}
