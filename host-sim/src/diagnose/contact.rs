//! A contact that is not LuGre: the final model with its bristle replaced by a generalized
//! Maxwell-slip contact (Al-Bender, Lampaert and Swevers, 2005), the check of what none of the
//! eight effects can describe.
//!
//! LuGre's single bristle gives an exponential presliding curve with no memory of earlier
//! reversals, and a sliding force that follows the Stribeck curve at once. A Maxwell-slip
//! contact is elastic-slip elements in parallel, element `j` with a share `w_j` of the
//! Stribeck curve `s(v)` and a break distance `d_j` (its stiffness `w_j Fs / d_j`):
//!
//! ```text
//! sticking:  dF_j/dt = (w_j Fs / d_j) v               until F_j sign(v) reaches w_j s(v)
//! slipping:  dF_j/dt = C (w_j s(v) sign(v) - F_j)     until v changes sign
//! F = sum F_j + sigma1 v K_stick / K + F_visc(v) + F0
//! ```
//!
//! Each element remembers where it last slipped (nonlocal presliding memory, a hysteresis
//! made of straight pieces) and a slipping element reaches the curve at the lag rate `C`
//! (frictional lag). The damping `sigma1` acts on the sticking elements' share of the
//! stiffness `K` (LuGre's `sigma1 dz/dt`: `v` while all stick, nothing once all slip). The
//! levels' effects, the viscous term and the offset are the model's; the dwell clock is not
//! carried (a dwell term's breakaway growth is lost).
//!
//! **Fit.** The break distances are a fixed ladder, [`ELEMENTS`] of them spread geometrically
//! over [`BREAK_LADDER`] times the model's presliding length `Fs / sigma0`. An element's force
//! is its share times that of a unit element with the same break distance, so for a given
//! curve and lag rate the shares are linear: they are solved with the mass, a scale of the
//! viscous force and the damping by non-negative least squares on the filtered force. (Only a
//! rest couples the elements: there they move by one common displacement until their sum
//! carries the measured force, which needs the shares; the shares of the previous solution are
//! used, and the solution repeated until they settle.) The lag rate, the Stribeck velocity and
//! the static level over the Coulomb one are searched in ln by a Nelder-Mead simplex from the
//! best of a small grid (the model's curve and curves of the contact's own).
//!
//! **When and decision.** The diagnosis tries the contact only where none of the eight effects
//! is significant on the final model and the model leaves more than the measurement accounts
//! for (`Unexplained::beyond_measurement`; together, `Diagnosis::beyond_the_eight`). Where an
//! effect is significant the model lacks it, and a contact in the bristle's place would be
//! fitted to the missing effect (since session 59; until then it was tried there too). Where
//! the model errs within the measurement, a contact that cuts its error further fits the
//! reading, not the friction (tried on every record, it cut 16..55 % on 3 of 100 effect-free
//! LuGre calibration records, each with the model at or under the truth's floor). There it
//! describes what the model leaves ([`judge`]) when it cuts the model's error by at least
//! [`CONTACT_MIN_CUT`] with a `dBIC` above 10, counting as its extra parameters the elements
//! with a share, less the two they replace (the bristle stiffness and a level), and the lag
//! rate ([`ContactCheck::extra_parameters`]).

use super::fit::{box_solve, for_each_combination, unit_scale};
use super::inverse::{AxisModel, Prepared};
use lugre_servo::friction::{EffectKind, Levels, LugreParams};
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;
use serde::Serialize;

/// Elastic-slip elements of the contact: the rungs of the break-distance ladder.
pub const ELEMENTS: usize = 10;

/// The ladder's span: its break distances run from the first to the second factor times the
/// model's presliding length `Fs / sigma0`.
pub const BREAK_LADDER: (f64, f64) = (0.03, 30.0);

/// The slip lag rate's range \[1/s\]: from a lag of a second to one of 10 us (a slipping
/// element on its curve within a sample).
pub const LAG_RATE_RANGE_PER_S: (f64, f64) = (1.0, 1e5);

/// The Stribeck velocity's search range [m/s]: the contact's curve is its own, not the LuGre
/// fit's (whose narrow hump a bristle that must first deflect hides, and a slipping element
/// would follow).
pub const STRIBECK_VELOCITY_RANGE_M_PER_S: (f64, f64) = (1e-5, 1.0);

/// The static level over the Coulomb level: the range searched.
pub const STATIC_OVER_COULOMB_RANGE: (f64, f64) = (1.0, 10.0);

/// The smallest cut of the model's error that calls the contact a description of what the
/// model leaves: the smallest of 0.10, 0.15, 0.20 and 0.30 with at most 4 % of the effect-free
/// and 5 % of the effect-added LuGre calibration records called (none of 100 and none of 80;
/// `docs/diagnosis-log.md`, session 43).
pub const CONTACT_MIN_CUT: f64 = 0.10;

/// Evaluations the simplex may spend after the grid.
const SEARCH_EVALUATIONS: usize = 60;

/// Solutions of the shares at one point, each with the previous one's shares at the rests.
const SHARE_PASSES: usize = 3;

/// One elastic-slip element of a fitted contact.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Element {
    /// Displacement from sticking to slipping \[m\].
    pub break_distance_m: f64,
    /// Its share of the Stribeck curve (of its level at the model's reference conditions)
    /// \[N\].
    pub level_n: f64,
}

impl Element {
    /// Its stiffness while it sticks, its level over its break distance \[N/m\].
    pub fn stiffness_n_per_m(&self) -> f64 {
        self.level_n / self.break_distance_m
    }
}

/// The contact fitted in the model's place, and what it did to the error.
#[derive(Clone, Debug, Serialize)]
pub struct ContactCheck {
    /// The elements with a share, shortest break distance first.
    pub elements: Vec<Element>,
    /// Initial (presliding) stiffness of the elements together \[N/m\].
    pub stiffness_n_per_m: f64,
    /// Rate at which a slipping element's force reaches its share of the curve \[1/s\].
    pub lag_rate_per_s: f64,
    /// The elements' Coulomb level together \[N\] (at the model's reference conditions).
    pub coulomb_n: f64,
    /// Their static level together \[N\].
    pub static_n: f64,
    /// The curve's Stribeck velocity \[m/s\].
    pub stribeck_velocity_m_per_s: f64,
    /// The mass fitted with it \[kg\].
    pub mass_kg: f64,
    /// Its viscous force over the model's.
    pub viscous_scale: f64,
    /// Damping of the sticking elements' deflection \[N s/m\] (LuGre's sigma1).
    pub damping_n_s_per_m: f64,
    /// The model's error [%].
    pub model_rel_err_pct: f64,
    /// The error with the contact in the bristle's place [%].
    pub rel_err_pct: f64,
    /// `1 - rel_err / model_rel_err`.
    pub error_cut: f64,
    /// `N_eff ln(RSS_model / RSS_contact) - k ln(N_eff)`, `k` [`Self::extra_parameters`].
    pub delta_bic: f64,
    /// Searched parameters whose best value is the edge of their range (name, edge).
    pub at_search_edge: Vec<(&'static str, f64)>,
    /// The contact describes what the model leaves ([`judge`]).
    pub describes: bool,
    /// The contact's predicted force along the record, filtered like the measured one \[N\].
    #[serde(skip)]
    pub prediction: Vec<f64>,
}

impl ContactCheck {
    /// Parameters the contact has beyond the model's: its elements with a share and its lag
    /// rate, less the bristle stiffness and the Coulomb level they replace (the curve's
    /// shape, the damping, the viscous term and the mass each have their counterpart); at
    /// least 2.
    pub fn extra_parameters(&self) -> usize {
        (self.elements.len() + 1).saturating_sub(2).max(2)
    }
}

/// Said after its subject: "a Maxwell-slip contact in the bristle's place ...".
impl core::fmt::Display for ContactCheck {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        if self.elements.is_empty() {
            // no range of break distances and no stiffness to state
            write!(f, "(no element with a share of the curve")?;
        } else {
            let (near, far) = self
                .elements
                .iter()
                .fold((f64::INFINITY, 0.0f64), |(a, b), e| {
                    (a.min(e.break_distance_m), b.max(e.break_distance_m))
                });
            write!(
                f,
                "({} elements breaking at {:.1e}..{:.1e} m, stiffness {:.3e} N/m",
                self.elements.len(),
                near,
                far,
                self.stiffness_n_per_m
            )?;
        }
        write!(
            f,
            ", lag rate {:.0} 1/s; curve Fc {:.1} N, Fs {:.1} N, vs {:.2e} m/s) errs {:.2} % \
             against the model's {:.2} % (cut {:.0} %, dBIC {:.1})",
            self.lag_rate_per_s,
            self.coulomb_n,
            self.static_n,
            self.stribeck_velocity_m_per_s,
            self.rel_err_pct,
            self.model_rel_err_pct,
            100.0 * self.error_cut,
            self.delta_bic
        )?;
        if self.describes {
            write!(f, ": {DESCRIBES}")
        } else {
            write!(
                f,
                ": it does not describe what the model leaves (that takes a cut of {:.0} % and \
                 dBIC above 10)",
                100.0 * CONTACT_MIN_CUT
            )
        }
    }
}

/// What the diagnosis says where it did not try the contact because the final model leaves
/// no more than the measurement accounts for.
pub const NOT_TRIED: &str = "a Maxwell-slip contact in the bristle's place was not tried: the \
     model leaves no more than the measurement accounts for";

/// What the diagnosis says where the final model has no friction a contact could replace (a
/// Coulomb level or bristle stiffness that is not positive).
pub const NO_FRICTION: &str = "a Maxwell-slip contact in the bristle's place was not tried: the \
     model has no friction to replace (its Coulomb level or bristle stiffness is not positive)";

/// What the diagnosis says where it did not try the contact because `effect` is significant
/// on the final model: the contact is the check of what none of the eight effects describes,
/// so the effect is added first.
pub fn not_tried_for(effect: EffectKind) -> String {
    format!(
        "a Maxwell-slip contact in the bristle's place was not tried: {name} is significant, and \
         the contact is the check of what none of the eight effects describes (add {name} first: \
         `--add {name}` or `--auto`)",
        name = effect.name()
    )
}

/// What a contact that describes what the model leaves says.
pub const DESCRIBES: &str = "it describes what the model leaves: the contact has presliding \
     memory or frictional lag, which LuGre does not; identify a Maxwell-slip contact (or \
     another model with them) rather than add an effect";

/// Whether a fitted contact describes what a model that leaves more than the measurement
/// accounts for leaves: it cuts the model's error by at least [`CONTACT_MIN_CUT`] with a
/// `dBIC` above 10.
pub fn judge(error_cut: f64, delta_bic: f64) -> bool {
    error_cut >= CONTACT_MIN_CUT && delta_bic > 10.0
}

/// The ladder's break distances \[m\] for a presliding length `length` \[m\].
fn ladder(length: f64) -> [f64; ELEMENTS] {
    let ratio = (BREAK_LADDER.1 / BREAK_LADDER.0).powf(1.0 / (ELEMENTS - 1) as f64);
    core::array::from_fn(|j| length * BREAK_LADDER.0 * ratio.powi(j as i32))
}

/// The unit elements along the record, unfiltered: each element's force with a unit share of
/// the curve \[N\], the sticking share of the stiffness times `v` [m/s] (what the damping
/// multiplies) and the viscous force \[N\] (the offset is the model's, constant).
struct Basis {
    elements: Vec<Vec<f64>>,
    deflection_rate: Vec<f64>,
    viscous: Vec<f64>,
}

/// One element's state: force per unit share \[N\] and the direction it slips in (0:
/// sticking).
#[derive(Clone, Copy, Default)]
struct State {
    force: f64,
    slipping: i8,
}

/// One point of the search: the unit elements of break distances `d` with `model`'s levels,
/// effects and viscous term, slipping towards the curve at `lag_rate` \[1/s\], along the
/// measured motion of `p`, whose scored samples (weight above zero) are `scored`.
struct Trial<'a> {
    model: AxisModel,
    d: &'a [f64; ELEMENTS],
    lag_rate: f64,
    p: &'a Prepared,
    scored: &'a [usize],
}

/// The unit elements of a trial along the record. Inside a rest of the reading the elements
/// carry the measured force less `M a` and the offset (as the LuGre model's bristle does,
/// `AxisModel::simulate`): each moves by one common displacement from its own state, so that
/// their sum weighted by `shares` is that force, up to the static level in each direction
/// ([`hold`]).
fn basis(t: &Trial<'_>, shares: &[f64; ELEMENTS]) -> Basis {
    let (model, d, lag_rate, p) = (&t.model, t.d, t.lag_rate, t.p);
    let n = p.len();
    let fm = &model.friction;
    let reference = fm.effects.reference_conditions();
    let fs = fm.params.static_force();
    // a unit element's stiffness, and the shares' stiffness together (the damping's weights)
    let k: [f64; ELEMENTS] = core::array::from_fn(|j| fs / d[j]);
    let total: f64 = shares.iter().zip(&k).map(|(w, k)| w * k).sum();
    let lag = (-lag_rate * p.dt).exp();
    let offset = fm.offset_force();
    let mut out = Basis {
        elements: vec![vec![0.0; n]; ELEMENTS],
        deflection_rate: vec![0.0; n],
        viscous: vec![0.0; n],
    };
    // levels that no condition moves are evaluated once, not at every sample
    // (with them the Stribeck curve does not move either: no temperature dependence)
    let constant = fm
        .constant_levels()
        .map(|_| fm.levels_by_direction(&reference, 0.0));
    for r in &p.segments {
        let mut el = [State::default(); ELEMENTS];
        for i in r.clone() {
            let v = p.v_step[i];
            let ((fw, bw), decay): ((Levels<f64>, Levels<f64>), f64) = match constant {
                Some(l) => (l, fm.stribeck_decay(v)),
                None => {
                    let f = fm.under(&p.conditions(i, &reference));
                    (
                        fm.levels_by_direction_under(&f, 0.0),
                        fm.stribeck_decay_under(v, &f),
                    )
                }
            };
            let l = if v >= 0.0 { fw } else { bw };
            let cap = (l.coulomb + (l.static_ - l.coulomb) * decay).max(0.0);
            let dir: i8 = if v > 0.0 {
                1
            } else if v < 0.0 {
                -1
            } else {
                0
            };
            let dx = v * p.dt;
            for (e, &kj) in el.iter_mut().zip(&k) {
                if e.slipping != 0 && e.slipping == dir {
                    let target = f64::from(dir) * cap;
                    e.force = target + (e.force - target) * lag;
                } else {
                    e.slipping = 0;
                    e.force += kj * dx;
                    if e.force * f64::from(dir) > cap {
                        // loaded past its share in the direction of motion: it slips
                        e.force = f64::from(dir) * cap;
                        e.slipping = dir;
                    } else if e.force.abs() > cap {
                        // above a level that fell, against the motion: held at it
                        e.force = cap.copysign(e.force);
                    }
                }
            }
            let sticking: f64 = el
                .iter()
                .zip(shares.iter().zip(&k))
                .filter(|(e, _)| e.slipping == 0)
                .map(|(_, (w, k))| w * k)
                .sum();
            out.deflection_rate[i] = if total > 0.0 { v * sticking / total } else { v };
            if p.inside_rest[i] {
                let held = p.force_motion_band[i] - model.mass_kg * p.a[i] - offset;
                hold(
                    &mut el,
                    &k,
                    shares,
                    held,
                    fw.static_.max(0.0),
                    bw.static_.max(0.0),
                );
            }
            for (column, e) in out.elements.iter_mut().zip(&el) {
                column[i] = e.force;
            }
            out.viscous[i] = fm.viscous_force(p.v[i], &l);
        }
    }
    out
}

/// Moves every unit element by one displacement `delta` (each bounded by the static level in
/// that direction, `up` forward and `down` backward \[N\]) so that their sum weighted by
/// `shares` is `held` \[N\], or as near as the bounds allow; every element sticks afterwards.
///
/// The sum `S(delta) = sum w_j clamp(F_j + k_j delta, -down, up)` is piecewise linear and
/// nondecreasing, with a knee where each element meets a bound: solved exactly between the two
/// knees that bracket `held`.
fn hold(
    el: &mut [State; ELEMENTS],
    k: &[f64; ELEMENTS],
    shares: &[f64; ELEMENTS],
    held: f64,
    up: f64,
    down: f64,
) {
    let sum_at = |delta: f64| -> f64 {
        el.iter()
            .zip(k.iter().zip(shares))
            .map(|(e, (kj, w))| w * (e.force + kj * delta).clamp(-down, up))
            .sum()
    };
    let mut knees = [0.0; 2 * ELEMENTS];
    for (j, (e, kj)) in el.iter().zip(k).enumerate() {
        let kj = kj.max(f64::MIN_POSITIVE);
        knees[2 * j] = (-down - e.force) / kj;
        knees[2 * j + 1] = (up - e.force) / kj;
    }
    knees.sort_by(f64::total_cmp);
    // below the first knee every element is at `-down`, above the last at `up`
    let delta = match knees.iter().position(|&d| sum_at(d) >= held) {
        None => knees[2 * ELEMENTS - 1],
        Some(0) => knees[0],
        Some(j) => {
            let (d0, d1) = (knees[j - 1], knees[j]);
            let (s0, s1) = (sum_at(d0), sum_at(d1));
            if s1 > s0 {
                d0 + (held - s0) / (s1 - s0) * (d1 - d0)
            } else {
                d1
            }
        }
    };
    for (e, kj) in el.iter_mut().zip(k) {
        e.force = (e.force + kj * delta).clamp(-down, up);
        e.slipping = 0;
    }
}

/// The columns the shares, the mass, the viscous scale and the damping multiply.
const COLUMNS: usize = ELEMENTS + 3;

/// Rows `0..FIRST_GROUP_ROWS` of the normal equations hold 50 of its 104 products (row `r`
/// has `COLUMNS - r` and its right-hand side): the first of the two groups [`solve`] sums side
/// by side.
const FIRST_GROUP_ROWS: usize = 4;

/// Rows `rows` of the normal equations of the columns `x` against the measured force less
/// `offset` (`force`, weighted by `weight`), over the `scored` samples: each row's upper
/// triangle (from its diagonal; the entries before it stay 0) and its right-hand side. One
/// pass over the samples reads each column once for all the rows, where a pass per row read
/// them all once per row; every sum still runs in sample order from 0.0 (the same numbers bit
/// for bit).
fn normal_rows(
    x: &[&[f64]],
    rows: std::ops::Range<usize>,
    scored: &[usize],
    (weight, force): (&[f64], &[f64]),
    offset: f64,
) -> Vec<([f64; COLUMNS], f64)> {
    let mut out = vec![([0.0; COLUMNS], 0.0); rows.len()];
    let mut sample = [0.0; COLUMNS];
    for &i in scored {
        for (s, col) in sample.iter_mut().zip(x) {
            *s = col[i];
        }
        let y = force[i] - offset;
        for (r, (row, rhs)) in rows.clone().zip(out.iter_mut()) {
            let wr = weight[i] * sample[r];
            *rhs += wr * y;
            for (c, s) in row.iter_mut().zip(&sample).skip(r) {
                *c += wr * s;
            }
        }
    }
    out
}

/// A fit at one point of the search.
#[derive(Clone)]
struct Point {
    /// The shares of the unit elements.
    shares: [f64; ELEMENTS],
    mass_kg: f64,
    viscous_scale: f64,
    damping_n_s_per_m: f64,
    /// Residual sum of squares \[N^2\].
    rss: f64,
    prediction: Vec<f64>,
}

/// The shares, the mass, the viscous scale and the damping that fit the filtered force best
/// (least squares, each at least zero), with the unit elements held at the rests by `shares`.
fn solve(t: &Trial<'_>, shares: &[f64; ELEMENTS]) -> Point {
    let (model, p, scored) = (&t.model, t.p, t.scored);
    let b = basis(t, shares);
    let mut raw: Vec<&[f64]> = b.elements.iter().map(|c| c.as_slice()).collect();
    raw.push(&b.viscous);
    raw.push(&b.deflection_rate);
    // the columns filtered in two halves side by side (each column's numbers are its own)
    let (first, second) = raw.split_at(raw.len() / 2);
    let (mut filtered, rest) = rayon::join(|| p.filter_many(first), || p.filter_many(second));
    filtered.extend(rest);
    let mut x: Vec<&[f64]> = vec![&p.acceleration_filtered];
    x.extend(filtered.iter().map(|c| c.as_slice()));
    let offset = model.friction.offset_force();
    // the rows in two groups of about equal work side by side
    let group = |rows| normal_rows(&x, rows, scored, (&p.weight, &p.force), offset);
    let (first, second) = rayon::join(
        || group(0..FIRST_GROUP_ROWS),
        || group(FIRST_GROUP_ROWS..COLUMNS),
    );
    let rows: Vec<([f64; COLUMNS], f64)> = first.into_iter().chain(second).collect();
    let mut a = DMatrix::<f64>::zeros(COLUMNS, COLUMNS);
    let mut rhs = DVector::<f64>::zeros(COLUMNS);
    for (r, (row, b)) in rows.iter().enumerate() {
        rhs[r] = *b;
        for c in r..COLUMNS {
            a[(r, c)] = row[c];
            a[(c, r)] = row[c];
        }
    }
    // columns of forces, accelerations and deflection rates differ by 1e6 and more: solved
    // on unit columns (the bounds at zero and infinity are the same there)
    let norm: [f64; COLUMNS] = core::array::from_fn(|j| unit_scale(a[(j, j)].sqrt()));
    let a = DMatrix::from_fn(COLUMNS, COLUMNS, |r, c| a[(r, c)] / (norm[r] * norm[c]));
    let rhs = DVector::from_fn(COLUMNS, |r, _| rhs[r] / norm[r]);
    let unit = box_solve(&a, &rhs, &[0.0; COLUMNS], &[f64::INFINITY; COLUMNS]);
    let c: [f64; COLUMNS] = core::array::from_fn(|j| unit[j] / norm[j]);
    let mut prediction = vec![0.0; p.len()];
    for_each_combination(&x, &c, p.len(), |i, sum| prediction[i] = sum + offset);
    Point {
        shares: core::array::from_fn(|j| c[1 + j]),
        mass_kg: c[0],
        viscous_scale: c[ELEMENTS + 1],
        damping_n_s_per_m: c[ELEMENTS + 2],
        rss: p.weighted_rss_filtered(&prediction),
        prediction,
    }
}

/// [`solve`] repeated [`SHARE_PASSES`] times, each holding the rests with the shares found
/// before (from `shares`); the best solution.
fn settle(t: &Trial<'_>, shares: &[f64; ELEMENTS]) -> Point {
    let mut best = solve(t, shares);
    let mut last = best.shares;
    for _ in 1..SHARE_PASSES {
        if last.iter().all(|w| *w == 0.0) {
            break;
        }
        let next = solve(t, &last);
        last = next.shares;
        if next.rss < best.rss {
            best = next;
        }
    }
    best
}

/// The searched coordinates, all in ln: the lag rate, the Stribeck velocity and the static
/// level over the Coulomb one.
const COORDINATES: usize = 3;

/// The lag rate's name in [`ContactCheck::at_search_edge`].
pub const LAG_RATE: &str = "lag_rate_per_s";
/// The Stribeck velocity's name in [`ContactCheck::at_search_edge`].
pub const STRIBECK_VELOCITY: &str = "stribeck_velocity_m_per_s";
/// The static level over the Coulomb one: its name in [`ContactCheck::at_search_edge`].
pub const STATIC_OVER_COULOMB: &str = "static_over_coulomb";

/// The searched coordinates' ranges and names.
const SEARCHED: [(&str, (f64, f64)); COORDINATES] = [
    (LAG_RATE, LAG_RATE_RANGE_PER_S),
    (STRIBECK_VELOCITY, STRIBECK_VELOCITY_RANGE_M_PER_S),
    (STATIC_OVER_COULOMB, STATIC_OVER_COULOMB_RANGE),
];

/// The model with the Stribeck velocity `vs` and the static level `ratio` times its Coulomb
/// level (its bristle, damping, viscous term and effects unchanged).
fn curved(model: &AxisModel, vs: f64, ratio: f64) -> AxisModel {
    let o = &model.friction.params;
    let params = LugreParams::new(
        o.bristle_stiffness(),
        o.bristle_damping(),
        o.viscous_coefficient(),
        o.coulomb_force(),
        o.coulomb_force() * ratio,
        vs,
    )
    .unwrap_or(*o);
    let mut m = *model;
    m.friction.params = params;
    m
}

/// Fits the contact in `model`'s place on `p` and scores it against the model's filtered
/// prediction `model_prediction`, over `n_eff` effective samples. `None` where the model has no
/// friction to replace (a Coulomb level or bristle stiffness that is not positive).
pub fn check(
    model: &AxisModel,
    model_prediction: &[f64],
    p: &Prepared,
    n_eff: f64,
) -> Option<ContactCheck> {
    let o = &model.friction.params;
    let (fc, fs, sigma0) = (o.coulomb_force(), o.static_force(), o.bristle_stiffness());
    if !(fc.is_finite() && fc > 0.0 && fs.is_finite() && sigma0 > 0.0) || p.force_norm <= 0.0 {
        return None;
    }
    let d = ladder(fs / sigma0);
    // the samples every solution is scored on: the record's, found once for the search
    let scored: Vec<usize> = p.scored_samples().collect();
    let ln_ranges: [(f64, f64); COORDINATES] =
        core::array::from_fn(|j| (SEARCHED[j].1 .0.ln(), SEARCHED[j].1 .1.ln()));
    let units = |u: [f64; COORDINATES]| -> [f64; COORDINATES] {
        core::array::from_fn(|j| u[j].clamp(ln_ranges[j].0, ln_ranges[j].1).exp())
    };
    // one solution with the rests held by `shares`, or settled from them
    let at = |u: [f64; COORDINATES], shares: &[f64; ELEMENTS], settled: bool| {
        let x = units(u);
        let t = Trial {
            model: curved(model, x[1], x[2]),
            d: &d,
            lag_rate: x[0],
            p,
            scored: &scored,
        };
        if settled {
            settle(&t, shares)
        } else {
            solve(&t, shares)
        }
    };
    // a grid over the lag rate and the curve, every element with an equal share at the rests:
    // the model's curve, and curves of their own (a LuGre fit's hump can be narrow and tall,
    // hidden by the bristle's deflection, and a slipping element would follow it), with the
    // Stribeck velocity a share of the record's top speed
    let equal = [1.0 / ELEMENTS as f64; ELEMENTS];
    let ratio0 = (fs / fc).clamp(STATIC_OVER_COULOMB_RANGE.0, STATIC_OVER_COULOMB_RANGE.1);
    let mut curves = vec![(o.stribeck_velocity(), ratio0)];
    for share in [0.03, 0.1, 0.3] {
        curves.push((share * p.top_speed, 1.5));
    }
    let mut grid: Vec<[f64; COORDINATES]> = Vec::new();
    for lag in [30.0f64, 300.0, 3000.0] {
        for &(vs, ratio) in &curves {
            grid.push([lag, vs, ratio].map(|x| x.max(f64::MIN_POSITIVE).ln()));
        }
    }
    let starts: Vec<([f64; COORDINATES], Point)> = grid
        .par_iter()
        .map(|&u| (u, at(u, &equal, false)))
        .collect();
    let (u0, p0) = starts
        .into_iter()
        .min_by(|a, b| a.1.rss.total_cmp(&b.1.rss))?;
    let p0 = at(u0, &p0.shares, true);
    // the simplex holds the rests with the grid's best shares
    let held = p0.shares;
    let (u_best, found) = nelder_mead(u0, p0, 0.7, SEARCH_EVALUATIONS, |u| at(u, &held, false));
    // the rests held by the shares found there, until they settle
    let best = at(u_best, &found.shares, true);
    let best = if best.rss <= found.rss { best } else { found };
    let x = units(u_best);
    let mut at_search_edge = Vec::new();
    for (j, (name, (lo, hi))) in SEARCHED.iter().enumerate() {
        // within 1 % of an edge counts as at it
        if x[j] <= lo * 1.01 {
            at_search_edge.push((*name, *lo));
        } else if x[j] >= hi / 1.01 {
            at_search_edge.push((*name, *hi));
        }
    }
    let model_rss = p.weighted_rss_filtered(model_prediction);
    let model_rel_err_pct = 100.0 * model_rss.sqrt() / p.force_norm;
    let rel_err_pct = 100.0 * best.rss.sqrt() / p.force_norm;
    let fs_curve = fc * x[2];
    let elements: Vec<Element> = d
        .iter()
        .zip(&best.shares)
        .filter(|(_, w)| **w > 0.0)
        .map(|(&dj, &w)| Element {
            break_distance_m: dj,
            level_n: w * fs_curve,
        })
        .collect();
    let share: f64 = best.shares.iter().sum();
    let mut check = ContactCheck {
        stiffness_n_per_m: elements.iter().map(Element::stiffness_n_per_m).sum(),
        elements,
        lag_rate_per_s: x[0],
        coulomb_n: share * fc,
        static_n: share * fs_curve,
        stribeck_velocity_m_per_s: x[1],
        mass_kg: best.mass_kg,
        viscous_scale: best.viscous_scale,
        damping_n_s_per_m: best.damping_n_s_per_m,
        model_rel_err_pct,
        rel_err_pct,
        error_cut: 1.0 - rel_err_pct / model_rel_err_pct,
        delta_bic: f64::NAN,
        at_search_edge,
        describes: false,
        prediction: best.prediction,
    };
    let k = check.extra_parameters() as f64;
    check.delta_bic = n_eff * (model_rss / best.rss).ln() - k * n_eff.ln();
    check.describes = judge(check.error_cut, check.delta_bic);
    Some(check)
}

/// Nelder-Mead on `N` coordinates from `u0` (already evaluated as `p0`), initial step `step`
/// along each, at most `evaluations` more evaluations of `f`; the best point found and where.
fn nelder_mead<const N: usize>(
    u0: [f64; N],
    p0: Point,
    step: f64,
    evaluations: usize,
    f: impl Fn([f64; N]) -> Point + Sync,
) -> ([f64; N], Point) {
    let mut simplex: Vec<([f64; N], Point)> = vec![(u0, p0)];
    let others: Vec<[f64; N]> = (0..N)
        .map(|j| {
            let mut u = u0;
            u[j] += step;
            u
        })
        .collect();
    simplex.extend(others.par_iter().map(|&u| (u, f(u))).collect::<Vec<_>>());
    let mut used = N;
    while used < evaluations {
        simplex.sort_by(|a, b| a.1.rss.total_cmp(&b.1.rss));
        let worst = simplex[N].0;
        let centroid: [f64; N] =
            core::array::from_fn(|j| simplex[..N].iter().map(|s| s.0[j]).sum::<f64>() / N as f64);
        let along = |t: f64| -> [f64; N] {
            core::array::from_fn(|j| centroid[j] + t * (worst[j] - centroid[j]))
        };
        let reflected = along(-1.0);
        let r = f(reflected);
        used += 1;
        if r.rss < simplex[0].1.rss {
            let expanded = along(-2.0);
            let e = f(expanded);
            used += 1;
            simplex[N] = if e.rss < r.rss {
                (expanded, e)
            } else {
                (reflected, r)
            };
        } else if r.rss < simplex[N - 1].1.rss {
            simplex[N] = (reflected, r);
        } else {
            let contracted = along(0.5);
            let c = f(contracted);
            used += 1;
            if c.rss < simplex[N].1.rss {
                simplex[N] = (contracted, c);
            } else {
                // shrink towards the best
                let best = simplex[0].0;
                let shrunk: Vec<[f64; N]> = simplex[1..]
                    .iter()
                    .map(|(u, _)| core::array::from_fn(|j| best[j] + 0.5 * (u[j] - best[j])))
                    .collect();
                let moved: Vec<([f64; N], Point)> = shrunk.par_iter().map(|&u| (u, f(u))).collect();
                used += N;
                for (slot, m) in simplex[1..].iter_mut().zip(moved) {
                    *slot = m;
                }
            }
        }
        // converged: the simplex spans under 1 % in every coordinate's ln
        let spans = (0..N).all(|j| {
            let (lo, hi) = simplex
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |a, s| {
                    (a.0.min(s.0[j]), a.1.max(s.0[j]))
                });
            hi - lo < 0.01
        });
        if spans {
            break;
        }
    }
    simplex
        .into_iter()
        .min_by(|a, b| a.1.rss.total_cmp(&b.1.rss))
        .expect("N + 1 points")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnose::inverse::Protocol;
    use crate::record::Record;
    use lugre_servo::friction::FrictionModel;

    /// The normal equations summed in one pass over the samples, in the two groups of rows
    /// `solve` sums side by side, are each entry summed alone over the scored samples in their
    /// order, bit for bit (as the pass per row summed them before session 56): the upper
    /// triangle, the zeros below it and the right-hand side.
    #[test]
    fn the_one_pass_normal_equations_are_each_entry_summed_alone() {
        let n = 3000;
        // columns of unlike scales (accelerations, forces, rates), weights with zeros
        let cols: Vec<Vec<f64>> = (0..COLUMNS)
            .map(|j| {
                (0..n)
                    .map(|i| {
                        let t = i as f64 * 1e-3;
                        10f64.powi(j as i32 % 5 - 2) * (t * (1.0 + j as f64)).sin()
                            + 1e-3 * ((i * 7919 + j * 104_729) % 1009) as f64
                    })
                    .collect()
            })
            .collect();
        let x: Vec<&[f64]> = cols.iter().map(|c| c.as_slice()).collect();
        let weight: Vec<f64> = (0..n)
            .map(|i| {
                if i % 7 == 3 {
                    0.0
                } else {
                    0.5 + (i % 11) as f64 / 10.0
                }
            })
            .collect();
        let force: Vec<f64> = (0..n).map(|i| 300.0 * (i as f64 * 0.002).cos()).collect();
        let offset = 12.5;
        let scored: Vec<usize> = (0..n).filter(|&i| weight[i] > 0.0).collect();
        let group = |rows| normal_rows(&x, rows, &scored, (&weight, &force), offset);
        let mut rows = group(0..FIRST_GROUP_ROWS);
        rows.extend(group(FIRST_GROUP_ROWS..COLUMNS));
        assert_eq!(rows.len(), COLUMNS);
        for (r, (row, rhs)) in rows.iter().enumerate() {
            let mut want_rhs = 0.0;
            for &i in &scored {
                want_rhs += weight[i] * x[r][i] * (force[i] - offset);
            }
            assert_eq!(rhs.to_bits(), want_rhs.to_bits(), "rhs {r}");
            for (c, got) in row.iter().enumerate() {
                let mut want = 0.0;
                if c >= r {
                    for &i in &scored {
                        want += weight[i] * x[r][i] * x[c][i];
                    }
                }
                assert_eq!(got.to_bits(), want.to_bits(), "entry ({r}, {c})");
            }
        }
    }

    /// Held inside the bounds, the elements' weighted sum is the held force, each moved by one
    /// common displacement from its own state (their differences, their memory, kept); beyond
    /// the bounds every element sits at the bound.
    #[test]
    fn a_rest_moves_every_element_by_one_displacement_to_the_held_force() {
        let k: [f64; ELEMENTS] = core::array::from_fn(|j| 1e6 * (1.0 + j as f64));
        let shares: [f64; ELEMENTS] = core::array::from_fn(|j| 0.02 + 0.01 * j as f64);
        let start: [State; ELEMENTS] = core::array::from_fn(|j| State {
            force: 300.0 * ((j as f64 * 1.7).sin()),
            slipping: if j % 3 == 0 { 1 } else { 0 },
        });
        let (up, down) = (500.0, 400.0);
        for held in [-20.0, 0.0, 7.5, 30.0] {
            let mut el = start;
            hold(&mut el, &k, &shares, held, up, down);
            let sum: f64 = el.iter().zip(&shares).map(|(e, w)| w * e.force).sum();
            assert!((sum - held).abs() < 1e-9, "{sum} vs {held}");
            // the unclamped elements moved by k_j delta, one delta for all
            let deltas: Vec<f64> = el
                .iter()
                .zip(&start)
                .zip(&k)
                .filter(|((e, _), _)| e.force > -down && e.force < up)
                .map(|((e, s), kj)| (e.force - s.force) / kj)
                .collect();
            assert!(deltas.len() >= 2, "{deltas:?}");
            assert!(
                deltas.iter().all(|d| (d - deltas[0]).abs() < 1e-12),
                "{deltas:?}"
            );
            assert!(el.iter().all(|e| e.slipping == 0));
        }
        let mut el = start;
        hold(&mut el, &k, &shares, 1e9, up, down);
        assert!(el.iter().all(|e| e.force == up));
        let mut el = start;
        hold(&mut el, &k, &shares, -1e9, up, down);
        assert!(el.iter().all(|e| e.force == -down));
    }

    /// 6 s at 1 kHz on a 0.1 um count: 0.5 mm forward at 0.5 mm/s, 0.5 mm back, 0.25 mm
    /// forward again; the force at sample `i` is `force(i)` \[N\] (immaterial to the
    /// elements).
    fn back_and_forth(force: impl Fn(usize) -> f64) -> Record {
        let dt = 1e-3;
        let mut text = String::from("t,x,force\n");
        let mut x = 0.0f64;
        for i in 0..6000 {
            let v = match i {
                0..=999 => 5e-4,
                1000..=1999 => -5e-4,
                2000..=2499 => 5e-4,
                _ => 0.0,
            };
            x += v * dt;
            let t = i as f64 * dt;
            text.push_str(&format!(
                "{t:.3},{:.8},{:.3}\n",
                (x * 1e7).round() * 1e-7,
                force(i)
            ));
        }
        Record::parse(&text, std::path::Path::new("r.csv")).unwrap()
    }

    /// A unit element sticks with stiffness `Fs / d` until its force reaches the curve, slips
    /// there (at a lag rate of 1e5 1/s, on the curve within a sample), and after a reversal
    /// unloads elastically through twice its level over twice its break distance: it remembers
    /// where it last slipped. An element whose break distance exceeds the travel never slips.
    #[test]
    fn a_unit_element_sticks_slips_and_remembers_where_it_slipped() {
        let rec = back_and_forth(|_| 100.0);
        let p = Prepared::new(&rec, "r.csv", Protocol::default()).unwrap();
        // no hump (Fs = Fc): the curve is the Coulomb level at every speed
        let params = LugreParams::new(1e7, 0.0, 0.0, 100.0, 100.0, 0.01).unwrap();
        let model = AxisModel {
            mass_kg: 0.0,
            friction: FrictionModel::plain(params),
        };
        let d = ladder(1e-5);
        let shares = [1.0 / ELEMENTS as f64; ELEMENTS];
        let trial = Trial {
            model,
            d: &d,
            lag_rate: 1e5,
            p: &p,
            // `basis` alone: no solution is scored
            scored: &[],
        };
        let b = basis(&trial, &shares);
        let at = |t_s: f64| (t_s / p.dt).round() as usize;
        // the displacement the elements are driven by (the step's mean velocity, summed), and
        // the reversal, where it turns
        let x: Vec<f64> = p
            .v_step
            .iter()
            .scan(0.0, |x, v| {
                *x += v * p.dt;
                Some(*x)
            })
            .collect();
        let peak = x[at(0.9)..at(1.1)].iter().copied().fold(f64::MIN, f64::max);
        for (j, dj) in d.iter().enumerate() {
            let f = &b.elements[j];
            // 0.1 s into the first move, 50 um from the start: the elements of shorter break
            // distances slip at the level, the others are on their springs
            let i = at(0.1);
            let travelled = x[i];
            let expect = (100.0 / dj * travelled).min(100.0);
            assert!(
                (f[i] - expect).abs() < 1e-6,
                "element {j}: {} vs {expect}",
                f[i]
            );
            // 0.5 mm moved, every element slipped: after the reversal (t = 1 s), 0.1 s back,
            // each has unloaded elastically from its level, through at most twice it
            assert!(
                (f[at(0.99)] - 100.0).abs() < 0.5,
                "element {j}: {}",
                f[at(0.99)]
            );
            let back = peak - x[at(1.1)];
            let i = at(1.1);
            let expect = (100.0 - 100.0 / dj * back).max(-100.0);
            assert!(
                (f[i] - expect).abs() < 1e-6,
                "element {j}: {} vs {expect}",
                f[i]
            );
        }
        // every element of the shortest break distance slips in both directions: +100, -100
        let f0 = &b.elements[0];
        assert!((f0[at(0.9)] - 100.0).abs() < 0.5 && (f0[at(1.9)] + 100.0).abs() < 0.5);
        // the longest (0.3 mm) is still sticking 0.2 mm after the reversal: it keeps the memory
        // of the 0.5 mm slip, its force 100 - 100/0.3 mm * 0.2 mm
        let last = &b.elements[ELEMENTS - 1];
        let i = at(1.4);
        let expect = 100.0 - 100.0 / d[ELEMENTS - 1] * (peak - x[i]);
        assert!(expect > 0.0 && expect < 90.0, "{expect}");
        assert!((last[i] - expect).abs() < 1e-6, "{} vs {expect}", last[i]);
        // the damping's column: v while all stick (the first step back), less once some slip
        let r = (at(0.9)..).find(|&i| p.v_step[i] < 0.0).unwrap();
        assert!((b.deflection_rate[r] / p.v_step[r] - 1.0).abs() < 1e-12);
        assert!(b.deflection_rate[at(1.9)].abs() < 0.5 * p.v_step[at(1.9)].abs());
    }

    /// A model whose viscous coefficient is zero (a fit that held it there) gives the contact
    /// a viscous column that is zero on every sample: the contact is still fitted on the other
    /// columns, its viscous scale left at zero. Until session 59 the columns' scaling made the
    /// normal equations 0/0 there and every coefficient came back zero: no element, no mass, the
    /// contact "erring 100 %".
    #[test]
    fn a_model_without_viscous_friction_still_gets_a_contact() {
        let model = AxisModel {
            mass_kg: 20.0,
            friction: FrictionModel::plain(
                LugreParams::new(1e7, 0.0, 0.0, 100.0, 150.0, 1e-3).unwrap(),
            ),
        };
        // the model's own force along the motion, read as the measured one
        let motion =
            Prepared::new(&back_and_forth(|_| 100.0), "r.csv", Protocol::default()).unwrap();
        let force = model.predict(&motion);
        assert_eq!(force.len(), 6000);
        let p = Prepared::new(&back_and_forth(|i| force[i]), "r.csv", Protocol::default()).unwrap();
        let prediction = p.filter(&model.predict(&p));
        let c = check(&model, &prediction, &p, 1000.0).expect("a model with friction");
        assert_eq!(c.viscous_scale, 0.0);
        assert!(!c.elements.is_empty(), "{c}");
        // ten elements in the bristle's place follow a LuGre contact's force closely
        assert!(c.rel_err_pct < 10.0, "{c}");
        assert!(!format!("{c}").contains("inf"), "{c}");
    }

    /// The decision: a cut of at least `CONTACT_MIN_CUT` and dBIC above 10, both needed.
    #[test]
    fn the_contact_is_called_on_a_cut_and_evidence_together() {
        assert!(judge(CONTACT_MIN_CUT, 10.5));
        assert!(!judge(CONTACT_MIN_CUT - 1e-9, 1e4));
        assert!(!judge(0.9, 10.0));
        assert!(!judge(f64::NAN, 1e4) && !judge(0.9, f64::NAN));
    }
}
