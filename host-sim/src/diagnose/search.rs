//! The nonlinear search of a model's parameters: the Stribeck velocity's and the bristle
//! stiffness's ranges on a record, the grid-then-refine search of each, the baseline fits that
//! start from the static table, a stage's or a leader's polish ([`Search`]), the asymmetry's
//! Stribeck velocity ratio, an effect's own parameter searched again, and the parameters a
//! model holds at the edge of their search ranges ([`SearchEdge`]).

use super::fit::Fitting;
use super::*;

/// Search range of the Stribeck velocity on a record [m/s]: from the stuck threshold to a third
/// of the fastest speed the record visits (the 99th percentile). Fc is only determined where
/// the hump has decayed (`exp(-(v/vs)^2) < 1e-4` at `v = 3 vs`): a larger vs would turn the
/// Stribeck curve into a stand-in for whatever bends the friction curve at high speed.
pub fn stribeck_range(p: &Prepared) -> (f64, f64) {
    let top = p.top_speed * STRIBECK_TOP_FRACTION;
    (inverse::STUCK_SPEED, top.max(2.0 * inverse::STUCK_SPEED))
}

/// Upper end of the Stribeck velocity's search range, as a fraction of the record's top speed.
/// When the search ends at this edge the range is extended once to the top speed itself: on an axis in stick-slip the record hardly leaves the
/// Stribeck region, and a vs held at a third of the top speed left a wrong baseline that
/// flexible candidates then "explained" (measured on effect-free independent records).
pub const STRIBECK_TOP_FRACTION: f64 = 1.0 / 3.0;

/// Search range of the bristle stiffness sigma0 [N/m]: from soft seals to stiff metal contacts
/// (the lower end reaches further down on light rigs, see [`bristle_stiffness_range`]).
pub const BRISTLE_STIFFNESS_RANGE: (f64, f64) = (1e5, 1e10);

/// Longest pre-sliding `F / sigma0` a contact is allowed \[m\]: an O-ring on a light test rig
/// deflects a few hundred micrometres before it slides.
pub const MAX_PRESLIDING_M: f64 = 1e-3;

/// The bristle stiffness's search range on this record [N/m]: [`BRISTLE_STIFFNESS_RANGE`],
/// its lower end brought down to `max |F| / MAX_PRESLIDING_M` where that is lower. A light rig's
/// seal (15 N, 150 um of pre-sliding: 1e5 N/m) sits at or below 1e5, and a fit held above it
/// cannot follow the force's lag through a reversal; it read that lag as viscous friction.
pub fn bristle_stiffness_range(p: &Prepared) -> (f64, f64) {
    let (lo, hi) = BRISTLE_STIFFNESS_RANGE;
    ((p.max_abs_force / MAX_PRESLIDING_M).clamp(1.0, lo), hi)
}

/// Prior pre-sliding length `Fs / sigma0` \[m\], used when the record does not determine sigma0.
pub const PRIOR_PRESLIDING_M: f64 = 10e-6;

/// Prior Stribeck velocity as a fraction of the fastest speed visited, used when the record does
/// not determine it.
pub const PRIOR_STRIBECK_FRACTION: f64 = 0.1;

/// A nonlinear parameter of the baseline, searched in log space within bounds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Nonlinear {
    StribeckVelocity,
    BristleStiffness,
}

impl Nonlinear {
    pub(super) fn name(self) -> &'static str {
        match self {
            Nonlinear::StribeckVelocity => "stribeck_velocity_m_per_s",
            Nonlinear::BristleStiffness => "bristle_stiffness_n_per_m",
        }
    }
    fn get(self, m: &AxisModel) -> f64 {
        match self {
            Nonlinear::StribeckVelocity => m.friction.params.stribeck_velocity(),
            Nonlinear::BristleStiffness => m.friction.params.bristle_stiffness(),
        }
    }
    fn set(self, m: &AxisModel, value: f64) -> AxisModel {
        let q = &m.friction.params;
        match self {
            Nonlinear::StribeckVelocity => fit::with_nonlinear(m, value, q.bristle_stiffness()),
            Nonlinear::BristleStiffness => fit::with_nonlinear(m, q.stribeck_velocity(), value),
        }
    }
    fn range(self, p: &Prepared) -> (f64, f64) {
        match self {
            Nonlinear::StribeckVelocity => stribeck_range(p),
            Nonlinear::BristleStiffness => bristle_stiffness_range(p),
        }
    }
    fn prior(self, m: &AxisModel, p: &Prepared) -> f64 {
        let (lo, hi) = self.range(p);
        match self {
            Nonlinear::StribeckVelocity => (PRIOR_STRIBECK_FRACTION * hi).clamp(lo, hi),
            Nonlinear::BristleStiffness => {
                (m.friction.params.static_force() / PRIOR_PRESLIDING_M).clamp(lo, hi)
            }
        }
    }
}

/// Bounded continuous search of one nonlinear parameter with the linear ones refitted at each
/// point (a profile): a 9-point scan of the whole log range, then a 5-point scan of the best
/// bracket, each closed by a parabola. The scan of the whole range is also the identifiability
/// test: when the profile rises by less than the 95 % likelihood-ratio threshold
/// (`N_eff ln(RSS_max / RSS_min) < 3.84`) anywhere in the range, the record does not determine
/// the parameter and it is held at its prior.
fn search_one(which: Nonlinear, start: &Fit, on: Fitting<'_>, refined: bool) -> Fit {
    let (lo, hi) = which.range(on.p);
    let f = search_in(which, (lo, hi), start, on, refined);
    let at_top = f
        .flags
        .at_search_edge
        .iter()
        .any(|(n, v)| *n == which.name() && *v == hi);
    if which == Nonlinear::StribeckVelocity && at_top {
        // once more, up to the record's top speed (see STRIBECK_TOP_FRACTION)
        let wide = (lo, (hi / STRIBECK_TOP_FRACTION).max(hi));
        let wide = search_in(which, wide, &f, on, refined);
        if wide.rss < f.rss {
            return wide;
        }
    }
    f
}

fn search_in(
    which: Nonlinear,
    (lo, hi): (f64, f64),
    start: &Fit,
    on: Fitting<'_>,
    refined: bool,
) -> Fit {
    let (llo, lhi) = (lo.ln(), hi.ln());
    let eval = |base: &AxisModel, lx: f64| {
        let f = on.refit_quick(&which.set(base, lx.exp()));
        (f.rss, f)
    };
    let base = start.model;
    let coarse: Vec<f64> = (0..9).map(|i| llo + (lhi - llo) * i as f64 / 8.0).collect();
    let (x1, f1, profile) = fit::grid_min(&coarse, |lx| eval(&base, lx));
    let r_min = profile.iter().map(|q| q.1).fold(f64::INFINITY, f64::min);
    let r_max = profile.iter().map(|q| q.1).fold(0.0f64, f64::max);
    let rise = on.n_eff * (r_max / r_min).ln();
    let flat = rise.is_nan() || rise < 3.84;
    let mut best = if f1.rss < start.rss {
        f1
    } else {
        start.clone()
    };
    // flags of the other parameters carry over; this one's are decided here
    let inherited = start.flags.without(which.name());
    if flat {
        let prior = which.prior(&best.model, on.p);
        let mut f = on.refit(&which.set(&best.model, prior));
        f.flags = inherited;
        f.flags.priors.push((
            which.name(),
            format!(
                "the record does not determine it (the fit changes by less than the 95 % threshold over {:.3e}..{:.3e}); held at its prior {:.3e}",
                lo, hi, prior
            ),
        ));
        return f;
    }
    let step = (lhi - llo) / 8.0;
    let fine: Vec<f64> = (0..5)
        .map(|i| (x1 - step + step * i as f64 / 2.0).clamp(llo, lhi))
        .collect();
    let centre = best.model;
    // The refinement steps onto points of the fine scan, and at a bound onto the bound in
    // every round: each point is fitted once (bit for bit what fitting it again gives; 15 of
    // offset 1009's 480 refits were such repeats).
    let fitted: Mutex<Vec<(u64, Fit)>> = Mutex::new(Vec::new());
    let eval_centre = |lx: f64| {
        let known = fitted.lock().ok().and_then(|fits| {
            let hit = fits.iter().find(|(x, _)| *x == lx.to_bits());
            hit.map(|(_, f)| f.clone())
        });
        let f = known.unwrap_or_else(|| {
            let (_, f) = eval(&centre, lx);
            if let Ok(mut fits) = fitted.lock() {
                fits.push((lx.to_bits(), f.clone()));
            }
            f
        });
        (f.rss, f)
    };
    let (_, f2, _) = fit::grid_min(&fine, eval_centre);
    if f2.rss < best.rss {
        best = f2;
    }
    if refined {
        best = refine(
            &best,
            step / 2.0,
            (llo, lhi),
            |lx| eval_centre(lx).1,
            |f| which.get(&f.model).ln(),
        );
    }
    best.flags = inherited;
    let lv = which.get(&best.model).ln();
    if let Some(edge) = [(llo, lo), (lhi, hi)]
        .iter()
        .find(|(l, _)| (lv - l).abs() < 1e-3)
        .map(|e| e.1)
    {
        best.flags.at_search_edge.push((which.name(), edge));
    }
    best
}

/// Spacing in ln at which the continuous refinement of a stage's sigma0 and vs stops (2 %). A grid's parabola left sigma0 23 % from
/// the truth on an independent record whose error that cost 20 % (0.77 % against the true
/// model's 0.64 %, the other parameters within 2 %).
pub const REFINE_TOLERANCE_LN: f64 = 0.02;

/// Continuous refinement of a searched parameter in ln around the best fit so far: the
/// points at `h` either side, the parabola through the three, its vertex; the spacing shrinks
/// threefold each round until [`REFINE_TOLERANCE_LN`]. Each round costs three refits (two of
/// them in parallel); the result is never worse than `start`.
fn refine(
    start: &Fit,
    mut h: f64,
    (llo, lhi): (f64, f64),
    eval: impl Fn(f64) -> Fit + Sync,
    ln_of: impl Fn(&Fit) -> f64,
) -> Fit {
    let mut best = start.clone();
    while h > REFINE_TOLERANCE_LN {
        let xb = ln_of(&best);
        let sides: Vec<(f64, Fit)> = [(xb - h).max(llo), (xb + h).min(lhi)]
            .par_iter()
            .map(|&x| (x, eval(x)))
            .collect();
        let (x0, x2) = (sides[0].0, sides[1].0);
        let (y0, y1, y2) = (sides[0].1.rss, best.rss, sides[1].1.rss);
        let vertex = fit::parabola_vertex((x0, y0), (xb, y1), (x2, y2));
        for (_, f) in sides {
            if f.rss < best.rss {
                best = f;
            }
        }
        if let Some(xv) = vertex.filter(|v| (v - ln_of(&best)).abs() > 1e-6) {
            let f = eval(xv.clamp(llo, lhi));
            if f.rss < best.rss {
                best = f;
            }
        }
        h /= 3.0;
    }
    best
}

/// The practitioners' static table as a LuGre model (`Fs = Fc`, stiff contact, vs at its
/// prior): where every baseline search starts, so that none can end worse than the table.
pub fn static_seed(p: &Prepared, table: &static_table::StaticFit) -> AxisModel {
    let floor = 1e-3 * p.max_abs_force.max(1e-9);
    let fc = table
        .coulomb_forward_n
        .clamp(floor, 3.0 * p.max_abs_force.max(floor));
    let (vs_lo, vs_hi) = stribeck_range(p);
    AxisModel {
        mass_kg: table.mass_kg.max(0.0),
        friction: FrictionModel::plain(
            LugreParams::new(
                (fc / 1e-6).clamp(bristle_stiffness_range(p).0, bristle_stiffness_range(p).1),
                0.0,
                table.viscous_forward_n_s_per_m.max(0.0),
                fc,
                fc,
                (PRIOR_STRIBECK_FRACTION * vs_hi).clamp(vs_lo, vs_hi),
            )
            .unwrap_or_default(),
        ),
    }
}

/// Fits the baseline (symmetric LuGre, all six parameters and the mass) to the record.
///
/// It starts from the practitioners' static table (closed-form Coulomb + viscous least squares,
/// [`static_table`]) as a LuGre model with `Fs = Fc`, so the fit cannot end worse than the
/// table: every later step is accepted only when the real model scores better. The linear
/// parameters (M, Fc, Fs - Fc, sigma2, sigma1) are solved within their physical box
/// ([`fit::Bounds`]); the Stribeck velocity and sigma0 by bounded continuous search
/// ([`stribeck_range`], [`BRISTLE_STIFFNESS_RANGE`]), twice in turn. A parameter the record does
/// not determine is held at a documented prior and listed in [`fit::Flags::priors`].
pub fn baseline(p: &Prepared, opts: &Options, n_eff: f64) -> Fit {
    baseline_searched(p, opts, n_eff, Search::STAGE, None)
}

/// [`baseline`] with the nonlinear search `search`, seeded from the record's symmetric static
/// table `table` (fitted here when `None`).
pub(super) fn baseline_searched(
    p: &Prepared,
    opts: &Options,
    n_eff: f64,
    search: Search,
    table: Option<&static_table::StaticFit>,
) -> Fit {
    let decays = DecayCache::new(p);
    let on = Fitting {
        p,
        fixed_mass: opts.fixed_mass(),
        n_eff,
        decays: &decays,
    };
    if let Some(g) = &opts.given {
        let plain = AxisModel {
            mass_kg: g.mass_kg,
            friction: FrictionModel::plain(g.friction.params),
        };
        return on.refit(&plain);
    }
    let seed = match table {
        Some(t) => static_seed(p, t),
        None => static_seed(p, &static_table::fit(p, on.fixed_mass).symmetric),
    };
    polish(&on.refit(&seed), None, on, search)
}

/// The first baseline of a weighted diagnosis: it only sets the motion weights
/// ([`prediction_spread`], [`motion_weights`]) and, where the position count is coarse, the
/// position cutoff ([`prepare`]). [`baseline`] with one round of the nonlinear search, not
/// refined: a weight follows how strongly the prediction moves with the motion reading, which
/// the last steps of the search hardly change (stick-slip record 1504: vs 0.95 against
/// 1.33 mm/s, 1.24 against 1.17 % of error, weights within 0.015 rms), and the weighted
/// baseline searches again from the static table ([`baseline`]). It takes a 60 s record's
/// diagnosis to 0.81 of its time (session 36, `diagnose_timing 1000 1001`).
pub fn first_baseline(p: &Prepared, opts: &Options, n_eff: f64) -> Fit {
    baseline_searched(p, opts, n_eff, Search::FIRST_BASELINE, None)
}

/// Mass and sigma1 whose 95 % interval reaches zero are not determined by the record. The mass
/// is then held at its prior, zero (no inertial force worth modelling: give `--mass` for a
/// controller), and refitted without it; sigma1 stays where the bounded fit put it (its prior,
/// zero, lies inside its interval) and is listed as not identifiable.
pub(super) fn mark_unidentified_linear(f: &mut Fit, on: Fitting<'_>) {
    // an undefined interval (NaN standard error) also counts as reaching zero
    let ci_reaches_zero = |f: &Fit, q: Param| {
        f.estimate(q)
            .filter(|e| {
                let low = e.value - 1.96 * e.std_error;
                low.is_nan() || low <= 0.0
            })
            .map(|e| (e.value, 1.96 * e.std_error))
    };
    // a verdict is redone only where the fit estimated the parameter: a fit that already holds
    // the mass at its prior (no mass estimate) keeps that flag
    for q in [Param::Mass, Param::BristleDamping] {
        if f.estimate(q).is_some() {
            f.flags = f.flags.without(q.label());
        }
    }
    if on.fixed_mass.is_none() {
        if let Some((v, h)) = ci_reaches_zero(f, Param::Mass) {
            let held = Fitting {
                fixed_mass: Some(0.0),
                ..on
            };
            let mut g = held.refit(&f.model);
            g.flags = f.flags.clone();
            g.flags.priors.push((
                Param::Mass.label(),
                format!("the inertial force is below what the record resolves ({v:.3e} +- {h:.1e} kg, 95 %, includes 0); held at its prior 0: give --mass for a controller"),
            ));
            *f = g;
        }
    }
    if let Some((v, h)) = ci_reaches_zero(f, Param::BristleDamping) {
        f.flags.priors.push((
            Param::BristleDamping.label(),
            format!("the record does not resolve the bristle dynamics ({v:.3e} +- {h:.1e} N s/m, 95 %, includes its prior 0)"),
        ));
    }
}

/// How far a search of the nonlinear parameters goes ([`polish`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Search {
    /// Rounds of the alternating search.
    pub rounds: usize,
    /// Whether sigma0 is searched as well as vs.
    pub stiffness: bool,
    /// Whether the last round ends with the continuous refinement of vs and sigma0 (to
    /// [`REFINE_TOLERANCE_LN`]).
    pub refine: bool,
    /// Whether a model with `asymmetry` has its Stribeck velocity ratio searched too
    /// (`search_stribeck_ratio`): a stage's model, not a candidate's ranking.
    pub stribeck_ratio: bool,
}

impl Search {
    /// A stage's model (and the weighted baseline): vs and sigma0, two rounds, refined.
    pub const STAGE: Self = Self {
        rounds: 2,
        stiffness: true,
        refine: true,
        stribeck_ratio: true,
    };
    /// A leading candidate re-judged in a ranking: vs once, not refined.
    pub const LEADER: Self = Self {
        rounds: 1,
        stiffness: false,
        refine: false,
        stribeck_ratio: false,
    };
    /// The rivals of a close call searched again (`ranking::settle_close_call`): a stage's
    /// search (vs, sigma0 and the effect's own parameter, an asymmetry's Stribeck velocity
    /// ratio too, two rounds) without its refinement. A candidate's fit stops short of its
    /// stage where the missing effect bent the Stribeck curve and the stiffness. The
    /// refinement took a quarter of a settlement's time and moved no answer on the five used
    /// records that studied it (session 93: temperature 1131 2.83 -> 2.11 s). The stiffness
    /// stays: searched without it (half the time), a dwell term took up the breakaway peaks the
    /// stiffness shapes on Stribeck record 1504 and was named.
    pub const CLOSE_CALL: Self = Self {
        refine: false,
        ..Self::STAGE
    };
    /// The first baseline, which only sets the motion weights ([`first_baseline`]): vs and
    /// sigma0 once, not refined.
    pub const FIRST_BASELINE: Self = Self {
        rounds: 1,
        stiffness: true,
        refine: false,
        stribeck_ratio: false,
    };
}

/// Re-searches the nonlinear parameters of an extended model within their bounds: the
/// Stribeck velocity (and, with [`Search::stiffness`], sigma0), then the added effect's own
/// nonlinear parameter, alternating [`Search::rounds`] times. The symmetric baseline's values
/// are biased when an effect was missing (it bends its Stribeck curve to mimic the effect), so
/// an effect is only judged fairly once they have moved. A step is not run again from a fit
/// that has not moved since it last ran (`StepMemo`): the answer would be the same.
pub fn polish(current: &Fit, effect: Option<EffectKind>, on: Fitting<'_>, search: Search) -> Fit {
    let Search {
        rounds,
        stiffness,
        refine,
        stribeck_ratio,
    } = search;
    let mut best = current.clone();
    let searched: &[Nonlinear] = if stiffness {
        &[Nonlinear::StribeckVelocity, Nonlinear::BristleStiffness]
    } else {
        &[Nonlinear::StribeckVelocity]
    };
    let mut steps = StepMemo::<Fit>::default();
    for round in 0..rounds {
        // an answer is worth keeping (`!last`) only for a round still to come
        let last = round + 1 == rounds;
        // the last round of a full polish (a stage's model, not a candidate's quick
        // re-judging) ends with a continuous refinement
        let refined = refine && last;
        for (k, which) in searched.iter().enumerate() {
            let searched_one = steps.run(k, refined, !last, || {
                Some(search_one(*which, &best, on, refined))
            });
            if let Some(f) = searched_one {
                // on the last round a parameter the record does not determine goes to its
                // prior (the profile is flat: the fit changes by less than the 95 % threshold)
                let held = last && f.flags.is_prior(which.name());
                if f.rss < best.rss || held {
                    best = f;
                    steps.moved();
                }
            }
        }
        let k = searched.len();
        if stribeck_ratio {
            if let Some(f) = steps.run(k, false, !last, || search_stribeck_ratio(&best, on)) {
                best = f;
                steps.moved();
            }
        }
        let regridded = steps.run(k + 1, false, !last, || {
            effect.and_then(|e| regrid_effect(&best, e, on))
        });
        if let Some(f) = regridded {
            best = f;
            steps.moved();
        }
        // the last round of a stage's polish refines the effect's own parameter continuously
        // too, as it refines vs and sigma0
        if let Some(f) = effect
            .filter(|_| refined)
            .and_then(|e| refine_effect(&best, e, on))
        {
            best = f;
            steps.moved();
        }
    }
    mark_unidentified_linear(&mut best, on);
    best
}

/// The effects whose own nonlinear parameter a stage refines continuously
/// ([`refine_effect`]): the positive, continuous ones (the dwell's time constant, the Stribeck
/// and viscous exponents). A position or load dependence's order is a count; a temperature
/// dependence's viscosity coefficient crosses zero, so it has no ln to refine in.
const CONTINUOUSLY_REFINED: [EffectKind; 3] = [
    EffectKind::DwellStiction,
    EffectKind::StribeckShape,
    EffectKind::ViscousPower,
];

/// The fit with effect `e`'s own nonlinear parameter refined continuously in ln between its
/// grid's ends ([`refine`], from half the grid's widest step down to
/// [`REFINE_TOLERANCE_LN`]; the linear parameters refitted at each point), the best point
/// refitted fully: `Some` only where that lowers the residual (and `e` is one of
/// [`CONTINUOUSLY_REFINED`]). The grid and its parabola leave the parameter on or near a grid
/// point (a dwell stage of used record 35427 kept its time constant at the grid's 0.2 s);
/// issue 9 asks for bounded continuous optimisation of time constants and exponents. It keeps
/// `current`'s flags.
fn refine_effect(current: &Fit, e: EffectKind, on: Fitting<'_>) -> Option<Fit> {
    if !CONTINUOUSLY_REFINED.contains(&e) {
        return None;
    }
    let (_, grid, _) = effect_info(e).nonlinear?;
    let value = nonlinear_value(&current.model, e).filter(|v| *v > 0.0)?;
    let (ends, step) = ln_span(grid)?;
    // the first parameter refined from `from`, whose value is `value` (the others held)
    let refine_first = |from: &Fit, value: f64| {
        let base = from.model;
        let ln_of = |f: &Fit| nonlinear_value(&f.model, e).map_or(value.ln(), f64::ln);
        let eval = |lx: f64| on.refit_quick(&fit::add_effect(&base, e, on.p, lx.exp()));
        refine(from, step, ends, eval, ln_of)
    };
    let mut refined = refine_first(current, value);
    // the second shape parameter (the dwell's renewal distance, the Stribeck tail's scale)
    // refined the same way from there, then the first once more: the two trade against each
    // other, and each was left on or near a grid point of its own
    if let Some(shaped) = refine_shape(&refined, e, on) {
        let value = nonlinear_value(&shaped.model, e).unwrap_or(value);
        refined = refine_first(&shaped, value);
    }
    if refined.rss >= current.rss {
        return None;
    }
    let mut f = on.refit(&refined.model);
    (f.rss < current.rss).then(|| {
        f.flags = current.flags.clone();
        f
    })
}

/// A grid's ends in ln, and half its widest step in ln: where [`refine`] searches a
/// parameter the grid placed, and the spacing it starts from.
fn ln_span(grid: &[f64]) -> Option<((f64, f64), f64)> {
    let ends = (grid.first()?.ln(), grid.last()?.ln());
    let widest = (grid.windows(2))
        .map(|w| (w[1] / w[0]).ln())
        .fold(0.0f64, f64::max);
    Some((ends, widest / 2.0))
}

/// The fit with effect `e`'s second shape parameter ([`super::EffectInfo::shape`]: the dwell's
/// renewal distance, the Stribeck tail's scale) refined continuously in ln between its grid's
/// ends ([`refine`], from half the grid's widest step; the linear parameters refitted at each
/// point): `Some` only where that lowers the residual, and where the model holds the parameter
/// ([`fit::shape_value`]).
fn refine_shape(current: &Fit, e: EffectKind, on: Fitting<'_>) -> Option<Fit> {
    let (_, grid) = effect_info(e).shape?;
    let value = fit::shape_value(&current.model, e).filter(|v| *v > 0.0)?;
    let (ends, step) = ln_span(grid)?;
    let base = current.model;
    let ln_of = |f: &Fit| fit::shape_value(&f.model, e).map_or(value.ln(), f64::ln);
    let eval = |lx: f64| on.refit_quick(&fit::with_shape(&base, e, lx.exp()));
    let refined = refine(current, step, ends, eval, ln_of);
    (refined.rss < current.rss).then_some(refined)
}

/// What each step of a [`polish`] found, and from which start: a step is a function of the
/// fit it starts from (and whether it refines), so where no step has moved the fit since a
/// step last ran, running it again gives the same fit bit for bit and its answer is reused. A
/// round that moved nothing would otherwise be repeated at full cost: on temperature record
/// 34579 the close call's three searches (two rounds, about 2 s each) left every fit where it
/// was, so each second round repeated the first.
struct StepMemo<T> {
    /// How many times the polished fit has moved.
    moves: usize,
    /// Per step: the moves counted when it ran, whether it refined, and what it returned.
    last: Vec<Option<(usize, bool, Option<T>)>>,
}

impl<T> Default for StepMemo<T> {
    fn default() -> Self {
        Self {
            moves: 0,
            last: Vec::new(),
        }
    }
}

impl<T: Clone> StepMemo<T> {
    /// Step `k`'s answer from the fit as it stands: `step` run, or what it returned when it
    /// last ran from this same fit with the same `refined`. The answer is kept for a later
    /// round only with `keep` (a fit is half a megabyte on a 60 s record: copying one for a
    /// round that will not come cost 1 % of a record's time, session 95).
    fn run(
        &mut self,
        k: usize,
        refined: bool,
        keep: bool,
        step: impl FnOnce() -> Option<T>,
    ) -> Option<T> {
        if self.last.len() <= k {
            self.last.resize_with(k + 1, || None);
        }
        if let Some((moves, r, answer)) = self.last[k].take() {
            if moves == self.moves && r == refined {
                if keep {
                    self.last[k] = Some((moves, r, answer.clone()));
                }
                return answer;
            }
        }
        let answer = step();
        if keep {
            self.last[k] = Some((self.moves, refined, answer.clone()));
        }
        answer
    }

    /// The polished fit moved: every answer so far was found from another start.
    fn moved(&mut self) {
        self.moves += 1;
    }
}

/// The name of the asymmetry's Stribeck velocity ratio, as the parameter file names it.
pub const STRIBECK_RATIO_NAME: &str = "stribeck_velocity_ratio";

/// The asymmetry's Stribeck velocity ratios a stage searches (`vs (1 ± rvs)`): the same
/// speed both ways (0) to one direction's hump lifting at four times the other's speed (0.6).
pub const STRIBECK_RATIO_GRID: [f64; 7] = [-0.6, -0.4, -0.2, 0.0, 0.2, 0.4, 0.6];

/// The second pass's step about the coarse grid's best ratio, two steps each way: the search
/// reaches `±(0.6 + 2 x 0.05) = ±0.7`.
const STRIBECK_RATIO_FINE_STEP: f64 = 0.05;

/// The ratios the search can end at: the coarse grid's ends, two fine steps beyond.
pub const STRIBECK_RATIO_REACH: (f64, f64) = (
    STRIBECK_RATIO_GRID[0] - 2.0 * STRIBECK_RATIO_FINE_STEP,
    STRIBECK_RATIO_GRID[STRIBECK_RATIO_GRID.len() - 1] + 2.0 * STRIBECK_RATIO_FINE_STEP,
);

/// The fit with the asymmetry's Stribeck velocity ratio searched on [`STRIBECK_RATIO_GRID`]
/// and again at a quarter of its step about the best point (each time at the parabola's
/// vertex between the best point and its neighbours too), the levels refitted at each:
/// `Some` where the model has asymmetry and the best ratio beats `current` by the
/// likelihood-ratio test's 95 % threshold for one parameter, `n_eff ln(RSS_0 / RSS) > 3.84`
/// (a record that does not determine it keeps its ratio, 0 as added). A ratio at an end of
/// [`STRIBECK_RATIO_REACH`] is reported ([`effect_search_edges`]).
/// The candidates' ranking does not search it ([`Search::stribeck_ratio`]): the probe that
/// asked for it (session 46) found the ranking right and the stage's error short of the floor.
pub(super) fn search_stribeck_ratio(current: &Fit, on: Fitting<'_>) -> Option<Fit> {
    current.model.friction.effects.asymmetry?;
    let with_ratio = |r: f64| {
        let mut m = current.model;
        if let Some(a) = m.friction.effects.asymmetry.as_mut() {
            a.stribeck_velocity_ratio = r;
        }
        m
    };
    // each point fully refitted: the quick refit's few steps from `current`'s levels left
    // the profile's minimum at 0.30 where the truth's 0.33 fits best (0.40 % against 0.45 %
    // quick, 0.20 % against 0.09 % refitted)
    let eval = |r: f64| {
        let f = on.refit(&with_ratio(r));
        (f.rss, f)
    };
    let (coarse, _, _) = fit::grid_min(&STRIBECK_RATIO_GRID, eval);
    // the profile is not a parabola over the grid's steps of 0.2: once more at a quarter of
    // the step about the best point (a ratio of 0.33 was found at 0.29, 0.26 % against the
    // truth's 0.09 %, from the coarse grid's vertex alone)
    let fine: Vec<f64> = (-2..=2)
        .map(|i| coarse + STRIBECK_RATIO_FINE_STEP * f64::from(i))
        .collect();
    let (_, mut f, _) = fit::grid_min(&fine, eval);
    let gain = on.n_eff * (current.rss / f.rss).ln();
    if gain.is_nan() || gain <= 3.84 {
        return None;
    }
    f.flags = current.flags.clone();
    Some(f)
}

/// The fit with effect `e`'s own nonlinear parameter searched again on its grid (the other
/// nonlinear parameters held), the linear ones refitted: `Some` only where that improves the
/// grid's objective (and `e` has a nonlinear parameter). It keeps `current`'s flags.
fn regrid_effect(current: &Fit, e: EffectKind, on: Fitting<'_>) -> Option<Fit> {
    let info = effect_info(e);
    let (_, values, _) = info.nonlinear?;
    let base = current.model;
    let (_, f, _) = effect_grid_min(info, values, |x| {
        let f = on.refit_quick(&fit::add_effect(&base, e, on.p, x));
        (grid_objective(info, x, f.rss, on.n_eff), f)
    });
    let mut f = on.refit(&f.model);
    let objective = |f: &Fit| {
        let order = nonlinear_value(&f.model, e).unwrap_or(0.0);
        grid_objective(info, order, f.rss, on.n_eff)
    };
    (objective(&f) < objective(current)).then(|| {
        f.flags = current.flags.clone();
        f
    })
}

/// An effect's searched parameter that a model holds at the edge of its search range.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SearchEdge {
    /// The effect whose parameter it is (serialised by its name).
    #[serde(serialize_with = "effect_name")]
    pub effect: EffectKind,
    /// The parameter's name, as the candidate list and the parameter file name it.
    pub name: &'static str,
    /// Its value in the model (one of the range's ends).
    pub value: f64,
    /// The range it was searched over, `(low, high)`.
    pub range: (f64, f64),
}

/// The searched parameters of every effect `m` carries (an effect's nonlinear parameter and
/// its second shape parameter, see [`EffectInfo`]) that sit at an end of their search range:
/// the fit may want a value beyond it, and a reader must be told so, not left to take the
/// value as found. A model order is at the edge only at the top ([`EffectInfo::orders_first`]).
pub fn effect_search_edges(m: &AxisModel) -> Vec<SearchEdge> {
    let ends = |grid: &[f64]| {
        let lo = grid.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = grid.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (lo, hi)
    };
    let mut out = Vec::new();
    for info in &EFFECTS {
        // (name, grid, value, at an edge) of the nonlinear parameter, then of the shape's
        let nonlinear = (info.nonlinear.zip(nonlinear_value(m, info.kind)))
            .map(|((name, grid, _), v)| (name, ends(grid), v, effect_on_edge(info, grid, v)));
        let shape = (info.shape.zip(fit::shape_value(m, info.kind)))
            .map(|((name, grid), v)| (name, ends(grid), v, on_edge(grid, v)));
        let staged = (info.stage_searched.zip(stage_searched_value(m, info.kind)))
            .map(|((name, (lo, hi)), v)| (name, (lo, hi), v, v <= lo || v >= hi));
        out.extend(
            nonlinear
                .into_iter()
                .chain(shape)
                .chain(staged)
                .filter(|q| q.3)
                .map(|(name, range, value, _)| SearchEdge {
                    effect: info.kind,
                    name,
                    value,
                    range,
                }),
        );
    }
    out
}

/// The parameter of an effect in a model that only a stage searches
/// ([`EffectInfo::stage_searched`]).
fn stage_searched_value(m: &AxisModel, effect: EffectKind) -> Option<f64> {
    match effect {
        EffectKind::Asymmetry => m
            .friction
            .effects
            .asymmetry
            .map(|a| a.stribeck_velocity_ratio),
        _ => None,
    }
}

/// The nonlinear parameter of an effect in a model.
pub(super) fn nonlinear_value(m: &AxisModel, effect: EffectKind) -> Option<f64> {
    let e = &m.friction.effects;
    match effect {
        EffectKind::TemperatureDependence => e.temperature_dependence.map(|t| t.viscous_per_kelvin),
        EffectKind::StribeckShape => e.stribeck_shape.map(|s| s.exponent),
        EffectKind::ViscousPower => e.viscous_power.map(|v| v.exponent),
        EffectKind::DwellStiction => e.dwell_stiction.map(|d| d.time_constant),
        EffectKind::PositionDependence => e.position_dependence.map(|x| x.terms as f64),
        EffectKind::LoadDependence => e.load_dependence.map(|l| l.terms as f64),
        EffectKind::Asymmetry | EffectKind::Offset => None,
    }
}

#[cfg(test)]
mod tests {
    use super::StepMemo;
    use std::cell::Cell;

    /// A step runs again only when the fit moved since it last ran, its refinement setting
    /// differs or its answer was not kept; otherwise its last answer comes back, `None`
    /// included.
    #[test]
    fn a_step_is_reused_only_from_the_same_unmoved_fit() {
        let runs = Cell::new(0);
        let step = |answer: Option<u32>| {
            let runs = &runs;
            move || {
                runs.set(runs.get() + 1);
                answer
            }
        };
        let mut memo = StepMemo::<u32>::default();
        assert_eq!(memo.run(0, false, true, step(Some(1))), Some(1));
        assert_eq!(memo.run(1, false, true, step(None)), None);
        assert_eq!(runs.get(), 2);
        // a second round from the same fit: both answers reused, the closures not run
        assert_eq!(memo.run(0, false, true, step(Some(7))), Some(1));
        assert_eq!(memo.run(1, false, true, step(Some(7))), None);
        assert_eq!(runs.get(), 2);
        // the same step refined is another computation
        assert_eq!(memo.run(0, true, true, step(Some(3))), Some(3));
        assert_eq!(runs.get(), 3);
        // once the fit moves, every step runs again
        memo.moved();
        assert_eq!(memo.run(1, false, true, step(Some(4))), Some(4));
        assert_eq!(memo.run(0, true, true, step(Some(5))), Some(5));
        assert_eq!(runs.get(), 5);
        // step 1 ran after the move, so it is reused while nothing moves
        assert_eq!(memo.run(1, false, true, step(Some(9))), Some(4));
        assert_eq!(runs.get(), 5);
        // an answer not kept (no round to come) is not there for a later call
        assert_eq!(memo.run(2, false, false, step(Some(6))), Some(6));
        assert_eq!(memo.run(2, false, true, step(Some(8))), Some(8));
        assert_eq!(runs.get(), 7);
        // nor is one handed out on its last use
        assert_eq!(memo.run(2, false, false, step(Some(10))), Some(8));
        assert_eq!(memo.run(2, false, true, step(Some(11))), Some(11));
        assert_eq!(runs.get(), 8);
    }
}
