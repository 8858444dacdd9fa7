//! The one measurement format every tool reads and writes.
//!
//! ```text
//! # key=value            optional comment lines (metadata), anywhere before the header
//! t,x,force,v,x_ref,p_a,p_b,temp
//! 0.000,0.100000,512.3,...
//! ```
//! SI units: `t` \[s\], `x` \[m\], `force` \[N\] (actuator force) are required; `v` [m/s], `x_ref` \[m\],
//! `p_a`, `p_b` \[Pa\], `temp` \[degC\] are optional; columns in any order; other columns are kept
//! as extras when numeric and otherwise ignored. Refused with file, line and column: an empty
//! file, a missing or duplicated column, a row of the wrong length, a non-numeric, NaN or
//! infinite cell, time that does not strictly increase, and a file without data rows.

use std::fmt;
use std::io::Write;
use std::path::{Path, PathBuf};

/// A measured (or simulated) record.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Record {
    /// `# key=value` metadata, in file order.
    pub meta: Vec<(String, String)>,
    /// Time \[s\], strictly increasing.
    pub t: Vec<f64>,
    /// Position \[m\].
    pub x: Vec<f64>,
    /// Actuator force \[N\].
    pub force: Vec<f64>,
    /// Velocity [m/s].
    pub v: Option<Vec<f64>>,
    /// Reference position \[m\].
    pub x_ref: Option<Vec<f64>>,
    /// Chamber A pressure \[Pa\].
    pub p_a: Option<Vec<f64>>,
    /// Chamber B pressure \[Pa\].
    pub p_b: Option<Vec<f64>>,
    /// Oil temperature \[degC\].
    pub temp: Option<Vec<f64>>,
    /// Other numeric columns, by name (e.g. simulator truth signals).
    pub extra: Vec<(String, Vec<f64>)>,
}

/// A refused file: where, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordError {
    /// The file.
    pub path: PathBuf,
    /// 1-based line, when the problem has one.
    pub line: Option<u64>,
    /// 1-based column and its header name, when the problem has one.
    pub column: Option<(usize, String)>,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for RecordError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.path.display())?;
        if let Some(l) = self.line {
            write!(f, ":{l}")?;
            if let Some((c, _)) = &self.column {
                write!(f, ":{c}")?;
            }
        }
        write!(f, ": ")?;
        if let Some((_, name)) = &self.column {
            write!(f, "column '{name}': ")?;
        }
        f.write_str(&self.message)
    }
}

impl std::error::Error for RecordError {}

const KNOWN: [&str; 8] = ["t", "x", "force", "v", "x_ref", "p_a", "p_b", "temp"];

impl Record {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// True when there are no samples.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Median sample period \[s\] (0 for fewer than 2 samples).
    pub fn sample_period(&self) -> f64 {
        let mut d: Vec<f64> = self.t.windows(2).map(|w| w[1] - w[0]).collect();
        if d.is_empty() {
            return 0.0;
        }
        d.sort_by(f64::total_cmp);
        d[d.len() / 2]
    }

    /// A metadata value.
    pub fn meta_value(&self, key: &str) -> Option<&str> {
        self.meta
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// An extra column by name.
    pub fn extra(&self, name: &str) -> Option<&[f64]> {
        self.extra
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_slice())
    }

    /// Reads and validates a record file.
    pub fn read(path: &Path) -> Result<Self, RecordError> {
        let text = std::fs::read_to_string(path).map_err(|e| RecordError {
            path: path.to_path_buf(),
            line: None,
            column: None,
            message: format!("cannot read: {e}"),
        })?;
        Self::parse(&text, path)
    }

    /// Parses and validates record text (`path` is only used in errors).
    pub fn parse(text: &str, path: &Path) -> Result<Self, RecordError> {
        let err =
            |line: Option<u64>, column: Option<(usize, String)>, message: String| RecordError {
                path: path.to_path_buf(),
                line,
                column,
                message,
            };
        let mut meta = Vec::new();
        for l in text.lines() {
            let l = l.trim();
            if let Some(c) = l.strip_prefix('#') {
                if let Some((k, v)) = c.split_once('=') {
                    meta.push((k.trim().to_string(), v.trim().to_string()));
                }
            } else if !l.is_empty() {
                break;
            }
        }
        let mut rdr = csv::ReaderBuilder::new()
            .comment(Some(b'#'))
            .trim(csv::Trim::All)
            .from_reader(text.as_bytes());
        let headers = rdr
            .headers()
            .map_err(|e| err(csv_line(&e), None, format!("unreadable header: {e}")))?
            .clone();
        let header_line = headers.position().map_or(1, |p| p.line()).max(1);
        if headers.is_empty() || (headers.len() == 1 && headers[0].is_empty()) {
            return Err(err(Some(1), None, "empty file: no header row".into()));
        }
        let names: Vec<String> = headers.iter().map(str::to_string).collect();
        for (i, n) in names.iter().enumerate() {
            if names[..i].contains(n) {
                return Err(err(
                    Some(header_line),
                    Some((i + 1, n.clone())),
                    "duplicated column".into(),
                ));
            }
        }
        for req in ["t", "x", "force"] {
            if !names.iter().any(|n| n == req) {
                return Err(err(
                    Some(header_line),
                    None,
                    format!(
                        "missing required column '{req}' (header has: {}); required: t [s], x [m], force [N]",
                        names.join(",")
                    ),
                ));
            }
        }
        let mut cols: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
        let mut extra_ok: Vec<bool> = names.iter().map(|n| !KNOWN.contains(&n.as_str())).collect();
        let t_idx = names.iter().position(|n| n == "t").unwrap_or(0);
        for row in rdr.records() {
            let row = row.map_err(|e| err(csv_line(&e), None, csv_message(&e)))?;
            let line = row.position().map_or(0, |p| p.line());
            for (i, cell) in row.iter().enumerate() {
                let known = KNOWN.contains(&names[i].as_str());
                match cell.parse::<f64>() {
                    Ok(v) if v.is_finite() => cols[i].push(v),
                    Ok(v) if known => {
                        return Err(err(
                            Some(line),
                            Some((i + 1, names[i].clone())),
                            format!("value '{cell}' is not finite ({v})"),
                        ))
                    }
                    Err(_) if known => {
                        return Err(err(
                            Some(line),
                            Some((i + 1, names[i].clone())),
                            format!("'{cell}' is not a number"),
                        ))
                    }
                    _ => {
                        extra_ok[i] = false;
                        cols[i].push(f64::NAN);
                    }
                }
            }
            let t = &cols[t_idx];
            if t.len() >= 2 && t[t.len() - 1] <= t[t.len() - 2] {
                return Err(err(
                    Some(line),
                    Some((t_idx + 1, "t".into())),
                    format!(
                        "time does not increase ({} after {})",
                        t[t.len() - 1],
                        t[t.len() - 2]
                    ),
                ));
            }
        }
        if cols[t_idx].is_empty() {
            return Err(err(
                Some(header_line),
                None,
                "no data rows after the header".into(),
            ));
        }
        let take = |name: &str, cols: &mut Vec<Vec<f64>>| -> Option<Vec<f64>> {
            names
                .iter()
                .position(|n| n == name)
                .map(|i| std::mem::take(&mut cols[i]))
        };
        let mut rec = Record {
            meta,
            t: take("t", &mut cols).unwrap_or_default(),
            x: take("x", &mut cols).unwrap_or_default(),
            force: take("force", &mut cols).unwrap_or_default(),
            v: take("v", &mut cols),
            x_ref: take("x_ref", &mut cols),
            p_a: take("p_a", &mut cols),
            p_b: take("p_b", &mut cols),
            temp: take("temp", &mut cols),
            extra: Vec::new(),
        };
        for (i, n) in names.iter().enumerate() {
            if extra_ok[i] {
                rec.extra.push((n.clone(), std::mem::take(&mut cols[i])));
            }
        }
        Ok(rec)
    }

    /// The columns present, as (name, values), in canonical order, extras last.
    fn columns(&self) -> Vec<(&str, &[f64])> {
        let mut c: Vec<(&str, &[f64])> =
            vec![("t", &self.t), ("x", &self.x), ("force", &self.force)];
        for (name, col) in [
            ("v", &self.v),
            ("x_ref", &self.x_ref),
            ("p_a", &self.p_a),
            ("p_b", &self.p_b),
            ("temp", &self.temp),
        ] {
            if let Some(col) = col {
                c.push((name, col));
            }
        }
        for (name, col) in &self.extra {
            c.push((name, col));
        }
        c
    }

    /// Writes the record (metadata as `# key=value`, then header and rows; floats are written
    /// in their shortest exact form so a round trip is lossless).
    pub fn write_to<W: Write>(&self, mut w: W) -> std::io::Result<()> {
        for (k, v) in &self.meta {
            writeln!(w, "# {k}={v}")?;
        }
        let cols = self.columns();
        let mut out = csv::Writer::from_writer(&mut w);
        out.write_record(cols.iter().map(|(n, _)| *n))?;
        let mut row = Vec::with_capacity(cols.len());
        for i in 0..self.len() {
            row.clear();
            row.extend(
                cols.iter()
                    .map(|(_, c)| c.get(i).copied().unwrap_or(f64::NAN).to_string()),
            );
            out.write_record(&row)?;
        }
        out.flush()
    }

    /// Writes the record to a file.
    pub fn write(&self, path: &Path) -> std::io::Result<()> {
        let f = std::fs::File::create(path)?;
        self.write_to(std::io::BufWriter::new(f))
    }
}

fn csv_line(e: &csv::Error) -> Option<u64> {
    e.position().map(|p| p.line())
}

fn csv_message(e: &csv::Error) -> String {
    match e.kind() {
        csv::ErrorKind::UnequalLengths {
            expected_len, len, ..
        } => {
            format!("row has {len} fields, the header has {expected_len}")
        }
        _ => e.to_string(),
    }
}
