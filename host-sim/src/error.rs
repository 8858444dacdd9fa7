//! The host tools' errors. Each names what it is about the way a user finds it: the file, and
//! where the file gives them the line, the column and the field. `host-sim` prints them as
//! `error: {message}`; the words are fixed by `tests/error_messages.rs`.
//!
//! Two layers: [`RecordError`] and [`ParamFileError`] belong to the two file formats; [`Error`]
//! is what every library function returns, with [`DataProblem`] for a record that was read but
//! cannot be analysed.

use crate::timing::{hz, seconds, MIN_RATE_HZ, MIN_SEGMENT_SAMPLES};
use lugre_servo::friction::EffectKind;
use std::path::PathBuf;

pub use crate::params_file::{InvalidParams, ParamFileError};
pub use crate::record::RecordError;

/// The host library's result.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Everything the host tools refuse.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A record file (CSV) refused: file, line, column.
    #[error(transparent)]
    Record(#[from] RecordError),
    /// A parameter file (TOML) refused: file, line and column or section and field.
    #[error(transparent)]
    ParamFile(#[from] ParamFileError),
    /// A record that was read but cannot be analysed.
    #[error("{record}: {problem}")]
    Data {
        /// The record's name (its file, as the user gave it).
        record: String,
        /// What is wrong with it.
        problem: DataProblem,
    },
    /// An effect name nobody knows.
    #[error("unknown effect '{0}'; known: {known}", known = known_effects())]
    UnknownEffect(String),
    /// An effect asked for twice.
    #[error("effect '{0}' is already in the model")]
    EffectAlreadyInModel(EffectKind),
    /// A parameter file asked of a diagnosis whose record does not determine the mass.
    #[error("the record does not determine the moving mass (its 95 % interval includes 0 kg); a controller needs it: give --mass KG")]
    MassNotDetermined,
    /// A diagnosis's model a controller must not get (invalid or non-physical), with what its
    /// fit says of it.
    #[error("{problem}; {why}")]
    ModelNotPhysical {
        /// Which section and field, and why.
        problem: InvalidParams,
        /// The fitted values and the parameters the fit left at an edge.
        why: String,
    },
    /// Diagnosis across records with fewer than three records.
    #[error("diagnosis across records needs at least 3 records, got {0}")]
    TooFewRecords(usize),
    /// A folder given as data that holds no records.
    #[error("{}: no .csv records in this folder", .0.display())]
    NoRecordsInFolder(PathBuf),
    /// Reading or writing a file (other than the two formats) failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// A chart could not be drawn.
    #[error("chart: {0}")]
    Chart(String),
    /// Results could not be serialised.
    #[error("JSON: {0}")]
    Json(#[from] serde_json::Error),
    /// An output refused before anything was written.
    #[error("{}: not written: {source}", path.display())]
    NotWritten {
        /// The file that was not written.
        path: PathBuf,
        /// Why.
        source: Box<Error>,
    },
    /// An identification whose best individual is not a valid parameter set.
    #[error("the identified set is not a valid parameter set")]
    InvalidIdentifiedSet,
    /// Command-line arguments that cannot be used together.
    #[error("{0}")]
    Usage(&'static str),
    /// The processor-in-the-loop session failed (QEMU, the firmware or the link).
    #[error("processor-in-the-loop: {0}")]
    Pil(String),
    /// A command-line value out of its range.
    #[error("{flag} {problem}")]
    Argument {
        /// The option, as typed (`--mass`).
        flag: &'static str,
        /// What it must be (and what it was).
        problem: String,
    },
}

impl Error {
    /// A problem with the record called `record`.
    pub fn data(record: &str, problem: DataProblem) -> Self {
        Self::Data {
            record: record.to_string(),
            problem,
        }
    }

    /// An I/O failure on `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io {
            path: path.into(),
            source,
        }
    }
}

/// Why a record that was read cannot be analysed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum DataProblem {
    /// Fewer than two samples.
    #[error("a record needs at least 2 samples, has {0}")]
    TooFewSamples(usize),
    /// Time stands still or runs backwards (1-based sample number).
    #[error("time does not increase at sample {sample} ({t_s} after {previous_s})")]
    TimeNotIncreasing {
        /// 1-based sample number.
        sample: usize,
        /// Its time \[s\].
        t_s: f64,
        /// The previous sample's time \[s\].
        previous_s: f64,
    },
    /// Sampled too slowly to see friction dynamics.
    #[error(
        "sampled at {} (median interval {}), too slow for friction dynamics; at least {} Hz is needed",
        hz(1.0 / .median_interval_s), seconds(*.median_interval_s), MIN_RATE_HZ
    )]
    TooSlow {
        /// Median sample interval \[s\].
        median_interval_s: f64,
    },
    /// Logger gaps leave no stretch long enough.
    #[error("every stretch between logger gaps is shorter than {MIN_SEGMENT_SAMPLES} samples")]
    OnlyShortSegments,
    /// Too few samples for the analysis asked.
    #[error("record too short for diagnosis: {samples} samples, need at least {needed}")]
    TooShort {
        /// Samples in the record.
        samples: usize,
        /// Samples needed.
        needed: usize,
    },
    /// The axis hardly moves.
    #[error("no motion to diagnose: the position spans {stroke_m:.3e} m and the axis moves faster than 0.1 mm/s in {moving} of {samples} samples")]
    NoMotion {
        /// Position span \[m\].
        stroke_m: f64,
        /// Samples moving faster than 0.1 mm/s.
        moving: usize,
        /// All samples.
        samples: usize,
    },
    /// The force is zero wherever the axis moves.
    #[error("the force column is zero wherever the axis moves")]
    ZeroForce,
    /// An effect needs a channel the record lacks.
    #[error("cannot add '{effect}': {why}")]
    MissingChannel {
        /// The effect asked for.
        effect: EffectKind,
        /// What the record lacks.
        why: String,
    },
    /// A sweep record without a reference position.
    #[error("the sweep record needs an x_ref column to find its constant-velocity legs")]
    NoReference,
    /// A sweep record with too few steady constant-velocity legs.
    #[error("{}", too_few_legs(*found, *unsteady, *ringing, *settling))]
    TooFewLegs {
        /// Steady legs found.
        found: usize,
        /// Legs long enough but left out as in stick-slip.
        unsteady: usize,
        /// Legs left out because the axis's speed rang through zero while it slid.
        ringing: usize,
        /// Legs left out because their force had not settled.
        settling: usize,
    },
}

/// The message of [`DataProblem::TooFewLegs`]: what was found, and for each kind of leg left
/// out, how many and what to change.
fn too_few_legs(found: usize, stick_slip: usize, ringing: usize, settling: usize) -> String {
    let mut why = Vec::new();
    if stick_slip > 0 {
        why.push(format!(
            "{stick_slip} in stick-slip (the axis stuck for part of the leg; slower legs are \
             where it sets in, so raise the slowest speed or the loop's stiffness)"
        ));
    }
    if ringing > 0 {
        why.push(format!(
            "{ringing} ringing (the axis's speed dipped through zero in dips of 15 ms or less \
             while it slid, as a servo loop that oscillates does: not steady sliding, and the \
             mean force is not the steady friction; damp the loop, with a lower gain or \
             pressure feedback, and record again)"
        ));
    }
    if settling > 0 {
        why.push(format!(
            "{settling} still settling (the force drifted over the leg by more than 1 % of it \
             as the bristles settled into sliding; lengthen those legs to many times the \
             contact's pre-sliding travel)"
        ));
    }
    let mut m = format!(
        "found {found} steady constant-velocity legs of at least 0.4 s, need 6 or more for the \
         static stage"
    );
    if !why.is_empty() {
        m += &format!("; left out: {}", why.join("; "));
    }
    m
}

fn known_effects() -> String {
    EffectKind::ALL.map(EffectKind::name).join(", ")
}

/// Turns a chart backend's error into [`Error::Chart`].
pub(crate) fn chart<E: std::fmt::Display>(e: E) -> Error {
    Error::Chart(e.to_string())
}
