//! The self-contained HTML report: SVG plots (plotters) and the story in words.
//!
//! 1. measured vs model force over time (first and final model);
//! 2. residual vs velocity, coloured by direction (first and final model);
//! 3. the friction bias per regime (first and final model);
//! 4. the error after each added effect, against the noise floor.

use super::{Diagnosis, Stage};
use plotters::prelude::*;

const W: u32 = 900;
const H: u32 = 300;
const MEASURED: RGBColor = RGBColor(40, 40, 40);
const FIRST: RGBColor = RGBColor(214, 96, 77);
const FINAL: RGBColor = RGBColor(33, 102, 172);
const PLUS: RGBColor = RGBColor(27, 120, 55);
const MINUS: RGBColor = RGBColor(153, 112, 171);

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

fn range(v: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = v.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    });
    if !lo.is_finite() || !hi.is_finite() {
        return (-1.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05).max(1e-9);
    (lo - pad, hi + pad)
}

/// Every `step`-th index so a plot holds at most `max` points.
fn thin(n: usize, max: usize) -> impl Iterator<Item = usize> {
    let step = n.div_ceil(max).max(1);
    (0..n).step_by(step)
}

fn force_over_time(d: &Diagnosis, first: &[f64], last: &[f64]) -> Result<String, String> {
    let p = &d.prepared;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (W, H)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let (y0, y1) = range(p.force.iter().copied().chain(last.iter().copied()));
        let t0 = p.t[0];
        let t1 = p.t[p.len() - 1];
        let mut c = ChartBuilder::on(&root)
            .caption("Measured vs model force", ("sans-serif", 18))
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(65)
            .build_cartesian_2d(t0..t1, y0..y1)
            .map_err(|e| e.to_string())?;
        c.configure_mesh()
            .x_desc("time [s]")
            .y_desc("force [N]")
            .draw()
            .map_err(|e| e.to_string())?;
        let idx: Vec<usize> = thin(p.len(), 4000).collect();
        for (data, color, label) in [
            (&p.force, MEASURED, "measured"),
            (&first.to_vec(), FIRST, "first model"),
            (&last.to_vec(), FINAL, "final model"),
        ] {
            c.draw_series(LineSeries::new(
                idx.iter().map(|&i| (p.t[i], data[i])),
                color.stroke_width(1),
            ))
            .map_err(|e| e.to_string())?
            .label(label)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
        }
        c.configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

fn residual_vs_velocity(d: &Diagnosis, first: &[f64], last: &[f64]) -> Result<String, String> {
    let p = &d.prepared;
    let r_first: Vec<f64> = p.force.iter().zip(first).map(|(f, q)| f - q).collect();
    let r_last: Vec<f64> = p.force.iter().zip(last).map(|(f, q)| f - q).collect();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (W, H)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let halves = root.split_evenly((1, 2));
        let (v0, v1) = range(p.v.iter().map(|v| v * 1e3));
        let idx: Vec<usize> = thin(p.len(), 3000).filter(|&i| p.weight[i] > 0.0).collect();
        let (y0, y1) = range(
            idx.iter()
                .map(|&i| r_first[i])
                .chain(idx.iter().map(|&i| r_last[i])),
        );
        for (area, r, title) in [
            (&halves[0], &r_first, "Residual vs velocity: first model"),
            (&halves[1], &r_last, "Residual vs velocity: final model"),
        ] {
            let mut c = ChartBuilder::on(area)
                .caption(title, ("sans-serif", 15))
                .margin(8)
                .x_label_area_size(35)
                .y_label_area_size(55)
                .build_cartesian_2d(v0..v1, y0..y1)
                .map_err(|e| e.to_string())?;
            c.configure_mesh()
                .x_desc("velocity [mm/s]")
                .y_desc("measured - model [N]")
                .draw()
                .map_err(|e| e.to_string())?;
            c.draw_series(idx.iter().map(|&i| {
                let color = if p.v[i] >= 0.0 { PLUS } else { MINUS };
                Circle::new((p.v[i] * 1e3, r[i]), 1, color.filled())
            }))
            .map_err(|e| e.to_string())?;
        }
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

fn bars(
    title: &str,
    y_desc: &str,
    labels: &[String],
    series: &[(&str, RGBColor, Vec<f64>)],
    floor: Option<f64>,
) -> Result<String, String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (W, H + 60)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let (mut y0, y1) = range(
            series
                .iter()
                .flat_map(|(_, _, v)| v.iter().copied())
                .chain([0.0])
                .chain(floor),
        );
        if y0 > 0.0 {
            y0 = 0.0;
        }
        let n = labels.len() as f64;
        let mut c = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 18))
            .margin(10)
            .x_label_area_size(90)
            .y_label_area_size(65)
            .build_cartesian_2d(-0.5..(n - 0.5), y0..y1)
            .map_err(|e| e.to_string())?;
        let labels_owned = labels.to_vec();
        c.configure_mesh()
            .disable_x_mesh()
            .x_labels(labels.len().max(1))
            .x_label_formatter(&|x| {
                let i = x.round();
                if (x - i).abs() < 1e-6 && i >= 0.0 && (i as usize) < labels_owned.len() {
                    labels_owned[i as usize].clone()
                } else {
                    String::new()
                }
            })
            .x_label_style(
                ("sans-serif", 11)
                    .into_font()
                    .transform(FontTransform::Rotate90),
            )
            .y_desc(y_desc)
            .draw()
            .map_err(|e| e.to_string())?;
        let k = series.len() as f64;
        let w = 0.8 / k;
        for (j, (name, color, vals)) in series.iter().enumerate() {
            let color = *color;
            c.draw_series(vals.iter().enumerate().map(|(i, v)| {
                let x0 = i as f64 - 0.4 + j as f64 * w;
                Rectangle::new([(x0, 0.0), (x0 + w * 0.9, *v)], color.filled())
            }))
            .map_err(|e| e.to_string())?
            .label(*name)
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 12, y + 5)], color.filled()));
        }
        if let Some(f) = floor {
            c.draw_series(LineSeries::new(
                [(-0.5, f), (n - 0.5, f)],
                BLACK.stroke_width(2),
            ))
            .map_err(|e| e.to_string())?
            .label("noise floor")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK));
        }
        c.configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

fn regime_bias(first: &Stage, last: &Stage) -> Result<String, String> {
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
    bars(
        "Friction the model misses, by regime (> 0: under-predicted)",
        "mean residual [N]",
        &names,
        &[("first model", FIRST, a), ("final model", FINAL, b)],
        None,
    )
}

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

/// The whole page.
pub fn html(d: &Diagnosis, name: &str, validation: Option<f64>) -> String {
    match page(d, name, validation) {
        Ok(s) => s,
        Err(e) => format!(
            "<!doctype html><html><body><p>report failed: {}</p></body></html>",
            escape(&e)
        ),
    }
}

fn page(d: &Diagnosis, name: &str, validation: Option<f64>) -> Result<String, String> {
    let p = &d.prepared;
    let first = &d.stages[0];
    let last = &d.stages[d.stages.len() - 1];
    let pred_first = p.filter(&first.fit.model.predict(p));
    let pred_last = p.filter(&last.fit.model.predict(p));
    let history_labels: Vec<String> = d.stages.iter().map(|s| s.label.clone()).collect();
    let history: Vec<f64> = d.stages.iter().map(|s| s.fit.rel_err_pct).collect();
    let mut out = String::from(
        "<!doctype html><html><head><meta charset=\"utf-8\"><title>lugre-servo diagnosis</title><style>\
         body{font-family:sans-serif;max-width:960px;margin:2em auto;color:#222}\
         table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #ccc;padding:4px 8px;text-align:left}\
         .big{font-size:1.4em}.sig{color:#1b7837;font-weight:bold}</style></head><body>",
    );
    out += &format!("<h1>Friction diagnosis of {}</h1>", escape(name));
    let end = last.fit.rel_err_pct;
    out += &format!(
        "<p class=\"big\">Relative force error: <b>{:.2} %</b> with the first model, <b>{:.2} %</b> with the final one{}.</p>",
        first.fit.rel_err_pct,
        end,
        d.noise_floor_pct.map_or(String::new(), |n| format!(" (noise floor {n:.2} %)"))
    );
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
    if let Some(c) = first.candidates.iter().find(|c| c.significant) {
        if d.stages.len() == 1 {
            out += &format!(
                "<p>Most likely missing effect: <b>{}</b> ({}). Add it with <code>--add {}</code>.</p>",
                escape(c.kind.name()),
                escape(&c.meaning),
                escape(c.kind.name())
            );
        }
    }
    out += "<p>Error = 100 ||F - F_hat|| / ||F|| on the force filtered at 20 Hz, over the samples where the axis moves \
            (while stuck, friction balances whatever force is applied and cannot be predicted from the motion).</p>";
    if let Some(g) = d.given_rel_err_pct {
        out += &format!("<p>The model from the parameter file, as given: {g:.2} %.</p>");
    }
    if let Some(v) = validation {
        out += &format!("<p>On the validation record (no refit): {v:.2} %.</p>");
    }
    out += "<h2>Where the model fails</h2><ul>";
    for f in &first.regimes.findings {
        out += &format!("<li>first model: {}</li>", escape(f));
    }
    for f in &last.regimes.findings {
        out += &format!("<li>final model: {}</li>", escape(f));
    }
    out += "</ul>";
    out += &bars(
        "Error after each added effect",
        "relative force error [%]",
        &history_labels,
        &[("error", FINAL, history)],
        d.noise_floor_pct,
    )?;
    out += &force_over_time(d, &pred_first, &pred_last)?;
    out += &residual_vs_velocity(d, &pred_first, &pred_last)?;
    out += "<p>Green: moving in +x, purple: moving in -x.</p>";
    out += &regime_bias(first, last)?;
    out += "<h2>Which effect is missing (next candidates, best first)</h2>";
    let rows: Vec<Vec<String>> = last
        .candidates
        .iter()
        .map(|c| {
            vec![
                c.kind.name().to_string(),
                c.meaning.clone(),
                c.rel_err_pct.map_or("-".into(), |e| format!("{e:.2} %")),
                c.delta_bic.map_or("-".into(), |b| format!("{b:.1}")),
                match &c.skipped {
                    Some(w) => format!("skipped: {w}"),
                    None if c.significant => "SIGNIFICANT".into(),
                    None => "not significant".into(),
                },
                c.parameters
                    .iter()
                    .map(|q| {
                        format!(
                            "{} = {:.4e} [{:.3e}, {:.3e}]",
                            q.name, q.value, q.ci_low, q.ci_high
                        )
                    })
                    .collect::<Vec<_>>()
                    .join("; "),
            ]
        })
        .collect();
    out += &table(
        &rows,
        &[
            "effect",
            "what it means",
            "error with it",
            "dBIC",
            "verdict",
            "parameters (95 % interval)",
        ],
    );
    let m = &last.fit.model;
    let q = &m.friction.params;
    out += "<h2>Final model</h2>";
    out += &table(
        &[
            vec!["moving mass M".into(), format!("{:.2} kg", m.mass_kg)],
            vec![
                "Coulomb force Fc".into(),
                format!("{:.2} N", q.coulomb_force()),
            ],
            vec![
                "static force Fs".into(),
                format!("{:.2} N", q.static_force()),
            ],
            vec![
                "viscous sigma2".into(),
                format!("{:.1} N s/m", q.viscous_coefficient()),
            ],
            vec![
                "Stribeck velocity vs".into(),
                format!("{:.2} mm/s", q.stribeck_velocity() * 1e3),
            ],
            vec![
                "bristle stiffness sigma0".into(),
                format!("{:.3e} N/m", q.bristle_stiffness()),
            ],
            vec![
                "effects".into(),
                d.stages[1..]
                    .iter()
                    .map(|s| s.label.trim_start_matches("+ ").to_string())
                    .collect::<Vec<_>>()
                    .join(", "),
            ],
        ],
        &["parameter", "value"],
    );
    out += "</body></html>";
    Ok(out)
}
