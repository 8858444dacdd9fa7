//! The diagnosis on axes it was never tuned on: records from the independent axis generator
//! (`generators/axis.rs`: its own LuGre code, actuators, sensors and effect shapes). A few
//! records each; the whole benchmark is `cargo run --release -p host-sim --example axis_suite`.
//!
//! The test command checks each claim on one record. The records kept for a mechanism of the
//! ranking (a restart, a close call, a fit from the static table, the motion weights, ...) and
//! the second record of a claim are the expensive suite, `#[ignore]`d here and run by
//! `cargo test --workspace -- --ignored` (CI runs it).

mod generators;

use generators::axis::{
    random_record, random_record_of, random_record_with, record_on_axes, truth_error_pct, Actuator,
    Axes, Axis, ContactKind, DwellLaw, Family, Sensors,
};
use host_sim::diagnose::inverse::{Prepared, Protocol};
use host_sim::diagnose::{self, Diagnosis, Options};
use host_sim::params_file::ParamFile;
use host_sim::record::Record;
use lugre_servo::friction::{DwellAge, DwellClock, DwellGrowth, EffectKind};
use std::path::Path;

fn diagnose(effect: Option<&'static str>, seed: u64, add: &[&str]) -> (Diagnosis, Axis) {
    let opts = Options {
        add: add.iter().map(|s| s.to_string()).collect(),
        ..Default::default()
    };
    diagnose_with(effect, seed, opts)
}

/// [`diagnose`] with options of its own (the final ranking skipped whatever they say).
fn diagnose_with(effect: Option<&'static str>, seed: u64, opts: Options) -> (Diagnosis, Axis) {
    let (text, axis) = random_record(effect, seed);
    let rec = Record::parse(&text, Path::new("axis.csv")).unwrap();
    let opts = Options {
        skip_final_ranking: true,
        ..opts
    };
    (diagnose::diagnose(&rec, "axis.csv", &opts).unwrap(), axis)
}

/// A generated record's numbers, row by row (its comment and header lines left out).
fn rows(text: &str) -> Vec<Vec<f64>> {
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with('t'))
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect()
}

/// The first significant candidate's name, if any.
fn first_significant(c: &[diagnose::Candidate]) -> Option<&'static str> {
    c.iter().find(|c| c.significant).map(|c| c.kind.name())
}

/// The `dwell_stiction` candidate of a ranked stage.
fn dwell_candidate(stage: &diagnose::Stage) -> &diagnose::Candidate {
    stage
        .candidates
        .iter()
        .find(|c| c.kind == EffectKind::DwellStiction)
        .expect("every ranked stage scores the dwell term")
}

fn report(d: &Diagnosis) -> String {
    d.stages[0]
        .candidates
        .iter()
        .take(3)
        .map(|c| {
            format!(
                "{} {:.2} % dBIC {:.1} {}",
                c.kind,
                c.rel_err_pct.unwrap_or(f64::NAN),
                c.delta_bic.unwrap_or(f64::NAN),
                if c.significant { "significant" } else { "-" }
            )
        })
        .collect::<Vec<_>>()
        .join("; ")
}

/// The generator's force-actuated records log beside each position the force held over the
/// period before it: read half a sample later (`Protocol::force_skew_samples`), its true model
/// along the measured motion errs far less (effect-free record 3183 of the issue's axes, where
/// the diagnosis names viscous power on the force as logged). Its hydraulic records compute the
/// force from chamber pressures sampled with the position: there the same skew costs.
#[test]
fn a_force_logged_half_a_sample_late_is_lined_up_by_reading_it_later() {
    let truth_at = |effect: Option<&'static str>, seed: u64, actuator: Actuator| {
        let (text, axis) = record_on_axes(effect, seed, Axes::Issue);
        assert_eq!(axis.actuator, actuator);
        let rec = Record::parse(&text, Path::new("r.csv")).unwrap();
        let p = Prepared::new(&rec, "r.csv", Protocol::default()).unwrap();
        [0.0, 0.5].map(|s| truth_error_pct(&axis, &p.with_force_read_later(s)))
    };
    let [logged, later] = truth_at(None, 3183, Actuator::Force);
    assert!(later < 0.5 * logged, "{later:.2} % against {logged:.2} %");
    let [logged, later] = truth_at(Some("load_dependence"), 3120, Actuator::Hydraulic);
    assert!(later > 1.5 * logged, "{later:.2} % against {logged:.2} %");
}

/// Effect-free records (a hydraulic and a force-actuated axis from the calibration seeds): the
/// plain model is structurally right, so no candidate may be called significant.
#[test]
fn no_effect_is_claimed_on_effect_free_axes() {
    for seed in [103, 124] {
        let (d, axis) = diagnose(None, seed, &[]);
        println!("seed {seed} ({:?}): {}", axis.actuator, report(&d));
        assert!(
            d.stages[0].candidates.iter().all(|c| !c.significant),
            "seed {seed}: {}",
            report(&d)
        );
    }
}

/// The stage's model is the best of its family its candidates reveal
/// (`diagnose::BETTER_START_CUT`): on the effect-free hydraulic calibration record 185 the
/// baseline's search of the Stribeck velocity stopped at 0.73 % where the generator's truth
/// scores 0.29 %, every leading candidate's own search went on to 0.31 %, and one was called
/// significant. Refitted from there, the baseline is within 1.2x the truth and nothing is
/// called.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn a_baseline_goes_where_its_candidates_show_it_can() {
    let (d, axis) = diagnose(None, 185, &[]);
    let floor = truth_error_pct(&axis, &d.prepared);
    let base = d.stages[0].fit.rel_err_pct;
    println!("baseline {base:.3} %, truth {floor:.3} %: {}", report(&d));
    assert!(
        base <= 1.2 * floor,
        "baseline {base:.3} %, truth {floor:.3} %"
    );
    assert!(
        d.stages[0].candidates.iter().all(|c| !c.significant),
        "{}",
        report(&d)
    );
}

/// The stage says where its model was replaced by a better start (`diagnose::Restart`): on
/// the independent temperature record 1001 the baseline's search from the static table stops
/// at 3.56 %, and the temperature candidate's fit, its effect switched off again, is a plain
/// model at 3.17 %. The stage keeps that model, judges the candidates again against it without
/// a second search (a second whole ranking took this record to 6.5 s against the 5 s target,
/// session 27; 4.1 s since session 28), and names the effect that is there.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn a_restart_from_a_better_start_is_reported() {
    let (d, _) = diagnose(Some("temperature_dependence"), 1001, &[]);
    let s = &d.stages[0];
    println!("{:?}: {}", s.restarts, report(&d));
    let first = s
        .restarts
        .first()
        .expect("the premise: this baseline restarts");
    assert!(
        first.to_rel_err_pct <= (1.0 - diagnose::BETTER_START_CUT) * first.from_rel_err_pct,
        "{first:?}"
    );
    let last = s.restarts.last().unwrap();
    assert_eq!(s.fit.rel_err_pct, last.to_rel_err_pct, "{:?}", s.restarts);
    let answer = s.candidates.iter().find(|c| c.significant);
    assert_eq!(
        answer.map(|c| c.kind.name()),
        Some("temperature_dependence"),
        "{}",
        report(&d)
    );
    // after the restart nothing is searched again: the candidates not significant before keep
    // their fits, say so, and are judged against the new model (their cut is of its error,
    // the dwell term's too since session 80: its twin weighs only its growth with the rest)
    let kept: Vec<_> = s
        .candidates
        .iter()
        .filter(|c| c.fitted_before_restart)
        .collect();
    assert!(!kept.is_empty(), "{}", report(&d));
    assert!(!answer.unwrap().fitted_before_restart);
    for c in kept {
        let err = c.rel_err_pct.expect("a tested candidate");
        let cut = 1.0 - err / s.fit.rel_err_pct;
        assert!(
            (c.error_cut - cut).abs() < 1e-12,
            "{}: cut {} against the new model's {cut}",
            c.kind,
            c.error_cut
        );
    }
    // every tested dwell term, kept or not: the decision's cut is of the current model's
    // error, and its twin's cut (the growth's share) never exceeds it
    for c in s
        .candidates
        .iter()
        .filter(|c| c.kind == EffectKind::DwellStiction)
    {
        if let (Some(dw), Some(err)) = (c.dwell, c.rel_err_pct) {
            let cut = 1.0 - err / s.fit.rel_err_pct;
            assert!((c.error_cut - cut).abs() < 1e-12, "{}: {cut}", c.error_cut);
            assert!(dw.twin_cut <= c.error_cut + 1e-12, "{dw:?}");
        }
    }
}

/// A strong direction dependence on an axis whose baseline has no viscous friction: the
/// asymmetry's viscous-ratio regressor is all zero there, which once turned the normal
/// equations into NaN and froze every asymmetry fit at its start. (Seed 1007: since the
/// generator's schedule bounds its bursts, seed 1000 draws an asymmetry whose static and
/// Coulomb shifts are nearly equal in newtons, which an offset mimics within 0.1 % of error;
/// 1007 keeps this test's premise, a baseline with sigma2 = 0.)
#[test]
fn asymmetry_is_found_where_the_baseline_has_no_viscous_term() {
    let (d, _) = diagnose(Some("asymmetry"), 1007, &[]);
    assert_eq!(
        d.stages[0].fit.model.friction.params.viscous_coefficient(),
        0.0,
        "the premise: a baseline without viscous friction"
    );
    let first = &d.stages[0].candidates[0];
    println!("{}", report(&d));
    assert_eq!(first.kind.name(), "asymmetry", "{}", report(&d));
    assert!(first.significant);
    assert!(
        first.rel_err_pct.unwrap() < 0.3 * d.stages[0].fit.rel_err_pct,
        "{}",
        report(&d)
    );
    // the contact is the check of what none of the eight effects describes: with asymmetry
    // significant it is not tried, and the diagnosis says to add it first
    assert!(d.contact.is_none());
    let why = d.contact_not_tried().expect("not tried");
    assert!(
        why.contains("asymmetry is significant") && why.contains("--add asymmetry"),
        "{why}"
    );
    // fitted anyway in this baseline's place (its viscous column zero on every sample), the
    // contact gets its elements and errs near the model (before session 59 the scaling made
    // its normal equations 0/0: no element, 100 %)
    let (fit, c) = (&d.stages[0].fit, contact_in_the_baselines_place(&d));
    assert!(
        !c.elements.is_empty() && c.rel_err_pct < 1.5 * fit.rel_err_pct,
        "{c}"
    );
}

/// The Maxwell-slip contact fitted in the place of `d`'s baseline, whether or not the diagnosis
/// tried it there.
fn contact_in_the_baselines_place(d: &Diagnosis) -> diagnose::contact::ContactCheck {
    let fit = &d.stages[0].fit;
    diagnose::contact::check(
        &fit.model,
        &fit.prediction,
        &d.prepared,
        d.effective_samples,
    )
    .expect("a contact fitted")
}

/// Parsimony between nested effects (`diagnose::NESTED`): on an independent offset record
/// (calibration seed 1108) the asymmetry candidate leads the offset
/// (its two extra ratios absorb more of the biased baseline's misfit), but with the offset
/// added it cuts the error by a few percent only: the offset is the first significant
/// candidate, and the asymmetry says why it is not. Without the rule the answer was asymmetry.
#[test]
fn an_offset_is_not_read_as_the_asymmetry_that_contains_it() {
    nested_answer(("offset", 1108), "asymmetry", "contains offset");
}

/// The parsimony check between nested effects on an independent record (`hidden`, `seed`):
/// as candidates `set_aside` leads the hidden effect (the premise), it is neither detected
/// nor significant, its caution says why (`why` in it), and the hidden effect is the first
/// significant candidate.
fn nested_answer((hidden, seed): (&'static str, u64), set_aside: &str, why: &str) {
    // the hidden effect added too: the kept one's check states the error its stage reaches
    let (d, _) = diagnose(Some(hidden), seed, &[hidden]);
    let c = &d.stages[0].candidates;
    println!("{}", report(&d));
    let named = |n: &str| c.iter().find(|c| c.kind.name() == n).unwrap();
    let (aside, answer) = (named(set_aside), named(hidden));
    assert!(
        aside.delta_bic > answer.delta_bic,
        "the premise: as candidates {set_aside} leads ({})",
        report(&d)
    );
    assert!(!aside.significant && !aside.detected, "{}", report(&d));
    let caution = aside.caution.as_deref().unwrap_or_default();
    assert!(caution.contains(why), "{caution}");
    assert_eq!(first_significant(c), Some(hidden), "{}", report(&d));
    if hidden == "offset" {
        kept_says_why(answer, set_aside, &d);
    } else {
        assert!(answer.kept_over_larger.is_none());
    }
}

/// The same parsimony the other way round: on an independent asymmetry record (calibration
/// seed 1020, a force actuator) the offset candidate leads the asymmetry (whose fit, which
/// contains the offset's, stopped short of it), but with the offset fitted as a stage the
/// asymmetry still cuts the error by the decision's cut: the asymmetry is the first significant
/// candidate, and the offset says why it is not. Without the check the answer was offset.
#[test]
fn an_asymmetry_is_not_read_as_the_offset_it_contains() {
    nested_answer(("asymmetry", 1020), "offset", "contains it");
}

/// Where the larger effect of a nested pair is significant on top of the simpler one's stage
/// and not significant as a candidate, its candidate is given that fit
/// (`diagnose::FROM_NESTED_CHECK`): on asymmetry record 33069
/// (hydraulic, one departure from rest; session 68) the baseline sat in a poor valley, 11.30 %,
/// the asymmetry's own candidate stopped at 8.00 % (dBIC 3.7, not significant) and the offset
/// (7.35 %) was named, where the asymmetry on top of the offset's stage reaches 0.60 %. The
/// check now runs wherever the asymmetry gains anything, hands its fit over, and the asymmetry
/// is named, its candidate within 1.2x the noise floor; the offset says why it is not.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn an_asymmetry_its_candidate_stopped_short_of_is_handed_the_nested_checks_fit() {
    // the asymmetry added too: the report shows the ranking it was chosen from
    let (d, axis) = diagnose(Some("asymmetry"), 33069, &["asymmetry"]);
    let c = &d.stages[0].candidates;
    let named = |n: &str| c.iter().find(|c| c.kind.name() == n).unwrap();
    let (asymmetry, offset) = (named("asymmetry"), named("offset"));
    assert_eq!(first_significant(c), Some("asymmetry"), "{}", report(&d));
    let own = asymmetry.from_nested_check;
    assert!(
        own.is_some_and(|own| own > 2.0 * asymmetry.rel_err_pct.unwrap()),
        "the premise: its own search stopped short ({own:?}): {}",
        report(&d)
    );
    assert!(!offset.significant && !offset.detected, "{}", report(&d));
    let caution = offset.caution.as_deref().unwrap_or_default();
    assert!(caution.contains("contains it"), "{caution}");
    let floor = truth_error_pct(&axis, &d.prepared);
    let err = asymmetry.rel_err_pct.unwrap();
    assert!(
        err <= 1.2 * floor,
        "asymmetry {err:.3} % against the floor {floor:.3} %"
    );
    // the report's ranking the asymmetry was chosen from says how its fit was found
    let html = diagnose::report::html(&d, "axis.csv", None);
    let chosen = html
        .split("How each added effect was chosen")
        .nth(1)
        .expect("the section of the ranking the added effect was chosen from");
    // in the asymmetry's verdict cell the label and its own search's error, the sentence once
    // in the table's notes
    let said = format!(
        "given the nested check's fit, note 1; its own search had reached {:.2}",
        own.unwrap()
    );
    assert!(chosen.contains(&said), "{said}");
    assert_eq!(chosen.matches(diagnose::FROM_NESTED_CHECK).count(), 1);
}

/// The nested check fits the simpler effect as a stage does, from both starts: on never-run
/// offset record 20137 (hydraulic) the offset fitted from the static table alone ended at
/// 0.52 %, where the stage ends at 0.31 % (the truth 0.36 %); asymmetry on top of it cut that
/// difference, a third of the error, and the record was read as asymmetry. On the stage's fit
/// the asymmetry explains nothing more and the offset is the answer, which says so with the
/// two errors the check weighed.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn the_nested_check_judges_on_the_stage_fit() {
    let (d, _) = diagnose(Some("offset"), 20137, &["offset"]);
    let c = &d.stages[0].candidates;
    println!("{}", report(&d));
    let first = c.iter().find(|c| c.significant);
    assert_eq!(
        first.map(|c| c.kind.name()),
        Some("offset"),
        "{}",
        report(&d)
    );
    assert!(first.is_some_and(|c| c.caution.is_none()));
    kept_says_why(first.unwrap(), "asymmetry", &d);
}

/// An offset candidate is fitted from the static table as well where its fit from the model
/// errs more than that table, a closed-form static fit (`diagnose::TABLE_SPANNED`): on offset record
/// 31127 (force actuator) the baseline bent into a basin around the missing offset (8.00 %,
/// its bristle stiffness at the search's lower end, 537 kg for 340), where the offset's own refit
/// reached 7.08 % only and viscous power was named (6.57 %). The asymmetric static table scores
/// 2.20 %; from it the offset candidate reaches the floor, and the offset is the answer.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn an_offset_the_baseline_bent_around_is_fitted_from_the_static_table() {
    let d = named_from_the_static_table("offset", 31127);
    // the premise: the static table beats the model the candidates start from
    assert!(d.tables.asymmetric.rel_err_pct < d.stages[0].fit.rel_err_pct);
}

/// Where the offset's candidate is its fit from the static table (the table start won), the
/// nested check fits the offset as a stage from that candidate and from its fit from the model,
/// and not from the table a second time (session 62, registration B3): on offset timing record
/// 1047 (force actuator; the offset from the table 0.39 %, the asymmetry on top of its stage
/// cutting 2 % more) the offset is kept, its stage is the one added, and it errs within 1.2x the
/// noise floor.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn a_table_fitted_offset_is_staged_from_the_candidate_and_the_model() {
    let (d, axis) = diagnose(Some("offset"), 1047, &["offset"]);
    let c = &d.stages[0].candidates;
    let offset = c.iter().find(|c| c.kind.name() == "offset").unwrap();
    assert!(offset.from_static_table, "the premise: {}", report(&d));
    assert_eq!(first_significant(c), Some("offset"), "{}", report(&d));
    kept_says_why(offset, "asymmetry", &d);
    let floor = truth_error_pct(&axis, &d.prepared);
    let staged = d.stages[1].fit.rel_err_pct;
    assert!(
        staged <= 1.2 * floor,
        "the offset's stage {staged:.3} % against the floor {floor:.3} %"
    );
}

/// `effect`'s record `seed` names `effect` first, on its fit from the static table (the
/// table's start won over the model's), within 1.2x the noise floor.
fn named_from_the_static_table(effect: &'static str, seed: u64) -> Diagnosis {
    let (d, axis) = diagnose(Some(effect), seed, &[]);
    let c = &d.stages[0].candidates;
    assert_eq!(first_significant(c), Some(effect), "{}", report(&d));
    let named = c.iter().find(|c| c.kind.name() == effect).unwrap();
    assert!(named.from_static_table, "{}", report(&d));
    let floor = truth_error_pct(&axis, &d.prepared);
    let err = named.rel_err_pct.unwrap();
    assert!(
        err <= 1.2 * floor,
        "{effect} {err:.2} % against the floor {floor:.2} %"
    );
    d
}

/// A record nothing explains, led by a candidate the static table spans, is fitted from the
/// table too whatever the table's own error (`table_start_where_unexplained`, session 98). On
/// asymmetry record 34280 (issue's axes; never-run in session 98's issue table, where it named
/// nothing) the asymmetry is large (static ratio 0.86) and the baseline bent to 19.93 %; the
/// offset and asymmetry candidates stopped at 16.15 and 16.23 %, cuts of 19 %, below the
/// asymmetric table's 16.69 %, so the table start that compares with the table did not fire.
/// From the table the asymmetry is named, and the offset is held by the nested check.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn an_asymmetry_nothing_else_explains_is_fitted_from_the_static_table() {
    let d = diagnose_on_issue_axes("asymmetry", 34280);
    let base = &d.stages[0];
    let c = &base.candidates;
    assert_eq!(first_significant(c), Some("asymmetry"), "{}", report(&d));
    let named = c.iter().find(|c| c.kind.name() == "asymmetry").unwrap();
    assert!(named.from_static_table, "{}", report(&d));
    // the premise: the table itself is far from explaining the record (the comparison with
    // it cannot fire where the bent candidates err less), and the baseline is farther
    let table = d.tables.asymmetric.rel_err_pct;
    assert!(
        table > 10.0 && base.fit.rel_err_pct > table,
        "{}",
        report(&d)
    );
    // from the table the asymmetry explains most of what the baseline left
    let err = named.rel_err_pct.unwrap();
    assert!(err < 0.5 * base.fit.rel_err_pct, "{err:.2} %");
    // the offset, which the asymmetry contains, steps aside and says why
    let offset = c.iter().find(|c| c.kind.name() == "offset").unwrap();
    let why = offset.caution.as_deref().unwrap_or_default();
    assert!(
        !offset.significant && why.contains("asymmetry, which contains it"),
        "{why}"
    );
}

/// A model that fails the core's physical check is refused for a controller, and the refusal
/// says what its fit left at an edge (`diagnose::parameter_file`, session 108). On Stribeck
/// record 34959 (issue's axes; never-run in session 107's table M) the motion stays under
/// 15 mm/s, 1.8 times the Stribeck velocity, and the baseline's Coulomb level bends to zero
/// (Fs > 20 Fc): until then the refusal named the field alone.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn a_model_refused_for_a_controller_says_what_its_fit_left_at_an_edge() {
    let d = stribeck_34959();
    let coulomb = d.model().friction.params.coulomb_force();
    assert!(coulomb < 1.0, "Fc {coulomb} N\n{}", report(d));
    let why = diagnose::parameter_file(d, None).unwrap_err().to_string();
    assert!(
        why.starts_with("[lugre] static_force (Fs) [N] is outside the physical range")
            && why.contains("the fitted model has M ")
            && why.contains(", Fc 0.000 N,")
            && why.contains("coulomb_force_n")
            && why.contains("the record does not determine"),
        "{why}"
    );
}

/// A linear parameter that ends on an edge of its physical range is said to, in a candidate's
/// list as in the model table, and its interval stays within that range (session 109). On
/// Stribeck record 34959 the baseline's Coulomb level is zero, so the asymmetry candidate's
/// Coulomb ratio scales nothing: it ended at -0.95 with an interval of +-2.5e10, shown as
/// fitted.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn a_ratio_the_record_does_not_determine_is_shown_at_its_physical_edge() {
    let d = stribeck_34959();
    let asym = (d.stages[0].candidates.iter())
        .find(|c| c.kind.name() == "asymmetry")
        .unwrap();
    let q = (asym.parameters.iter())
        .find(|q| q.name == "coulomb_ratio")
        .unwrap();
    // the premise: the ratio of a zero Coulomb level, at its bound
    assert!(q.value.abs() > 0.949, "{q:?}\n{}", report(d));
    assert!(q.at_physical_edge, "{q:?}");
    assert!(q.ci_low >= -0.95 && q.ci_high <= 0.95, "{q:?}");
    let texts = asym.parameter_texts();
    assert!(
        texts.iter().any(|t| t.starts_with("coulomb_ratio")
            && t.ends_with("(at the edge of its physical range)")),
        "{texts:?}"
    );
}

/// A record nothing explains has its leading candidate fitted from the static table whatever
/// its effect (`table_start_where_unexplained`, session 108). On Stribeck record 34959
/// (issue's axes; never-run in session 107's table M, where it named nothing) the motion stays
/// under 15 mm/s and the baseline bends to a Coulomb level of zero; the Stribeck candidate
/// fitted from that model stopped at 1.96 % (a cut of 35 % with dBIC 6.9, short of 10), where
/// the stage reaches 0.81 % from the table. From the table the ranking names it.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn a_leader_nothing_else_explains_is_fitted_from_the_static_table_whatever_its_effect() {
    let d = stribeck_34959();
    let base = &d.stages[0];
    let c = &base.candidates;
    assert_eq!(
        first_significant(c),
        Some("stribeck_shape"),
        "{}",
        report(d)
    );
    let named = c
        .iter()
        .find(|c| c.kind.name() == "stribeck_shape")
        .unwrap();
    assert!(named.from_static_table, "{}", report(d));
    // the premise: the baseline's Coulomb level bent to the bottom of its range
    let coulomb = base.fit.model.friction.params.coulomb_force();
    assert!(coulomb < 1.0, "Fc {coulomb} N\n{}", report(d));
    // from the table the candidate explains most of what the baseline left, as its stage does
    let err = named.rel_err_pct.unwrap();
    assert!(err < 0.4 * base.fit.rel_err_pct, "{err:.2} %");
}

/// A Stribeck curve with two lubrication scales is named a Stribeck shape, not viscous power:
/// the candidate fits a share of the hump on a second, slower scale (session 99). On family-B
/// record 36500 (issue's axes; a boundary hump at vs and 38 % of the hump decaying over 4 vs;
/// never-run in session 99's family-B table, where viscous power was named at 0.84 % against
/// the one-scale Stribeck candidate's 1.11 %, floor 0.39 %) the tail takes a real share and the
/// Stribeck candidate explains what viscous power could not.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn a_stribeck_curve_with_a_slower_second_scale_is_not_read_as_viscous_power() {
    let (text, axis) = random_record_of(
        Some("stribeck_shape"),
        36500,
        Sensors::default(),
        ContactKind::LuGre,
        Family::B,
        Axes::Issue,
        DwellLaw::RestartAtStick,
    );
    assert!(
        format!("{:?}", axis.shape).starts_with("StribeckB"),
        "{:?}",
        axis.shape
    );
    let rec = Record::parse(&text, Path::new("axis.csv")).unwrap();
    let opts = Options {
        skip_final_ranking: true,
        ..Default::default()
    };
    let d = diagnose::diagnose(&rec, "axis.csv", &opts).unwrap();
    let c = &d.stages[0].candidates;
    assert_eq!(
        first_significant(c),
        Some("stribeck_shape"),
        "{}",
        report(&d)
    );
    let of = |name: &str| c.iter().find(|c| c.kind.name() == name).unwrap();
    let (stribeck, viscous) = (of("stribeck_shape"), of("viscous_power"));
    let share = stribeck
        .parameters
        .iter()
        .find(|q| q.name == "tail_share")
        .map(|q| q.value);
    assert!(share.is_some_and(|w| w > 0.2 && w < 0.8), "{share:?}");
    let (s, v) = (stribeck.rel_err_pct.unwrap(), viscous.rel_err_pct.unwrap());
    assert!(
        s < 0.6 * v,
        "Stribeck {s:.2} % against viscous power {v:.2} %"
    );
}

/// Where the trigger fires, the leader is fitted from the static table as well as the offset
/// and the asymmetry: on load record 20280 (hydraulic) the baseline bent to 28.56 % (the
/// asymmetric table 21.58 %), the load led from it at 19.82 %, and an asymmetry fitted from the
/// table alone (14.59 %) outranked it (session 50, registration A). From the table the load
/// reaches the floor and is named.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn the_leader_is_fitted_from_the_static_table_with_the_offset_and_the_asymmetry() {
    named_from_the_static_table("load_dependence", 20280);
}

/// The simpler effect of a nested pair, kept as the answer, carries the check that kept it:
/// `larger` judged on top of it, with a cut under the decision's, the error of the stage that
/// adding the kept effect gives (`d`'s second stage), and a sentence saying what would
/// separate the two.
fn kept_says_why(kept: &diagnose::Candidate, larger: &str, d: &Diagnosis) {
    let n = kept.kept_over_larger.expect("the check that kept it");
    assert_eq!((n.larger.name(), n.kept), (larger, kept.kind));
    assert!(n.larger_on_top_rel_err_pct.is_some(), "tested: {n}");
    assert!(
        n.larger_on_top_cut().unwrap() < diagnose::MIN_ERROR_CUT,
        "{n}"
    );
    assert_eq!(d.stages[1].effect, Some(kept.kind));
    assert_eq!(
        n.kept_rel_err_pct, d.stages[1].fit.rel_err_pct,
        "the check's stage is the one added"
    );
    let said = n.to_string();
    assert!(
        said.contains("does not separate") && said.contains("each direction"),
        "{said}"
    );
}

/// A close call is settled on fits searched again (`diagnose::CLOSE_CALL`,
/// `Search::CLOSE_CALL`): on never-run viscous-power record 20642 (hydraulic) the Stribeck
/// shape scored 1.02 % as a candidate and the viscous power 1.08 %, and the Stribeck shape was
/// named; searched again, viscous power reaches about half that error (the truth 0.58 %) and
/// is the answer, and both say how they were judged.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn a_close_call_is_settled_on_converged_fits() {
    let (d, _) = diagnose(Some("viscous_power"), 20642, &[]);
    println!("{}", report(&d));
    viscous_power_settles_over_stribeck(&d, 0.6);
}

/// The viscous power and the Stribeck shape of `d`'s baseline stage, both settled as a close
/// call ([`diagnose::Candidate::settled_close_call`]), the viscous power under `max_err_pct`
/// and named first; returns their errors \[%\] (viscous, Stribeck).
fn viscous_power_settles_over_stribeck(d: &Diagnosis, max_err_pct: f64) -> (f64, f64) {
    let c = &d.stages[0].candidates;
    let named = |n: &str| c.iter().find(|c| c.kind.name() == n).unwrap();
    let (viscous, stribeck) = (named("viscous_power"), named("stribeck_shape"));
    assert!(
        viscous.settled_close_call && stribeck.settled_close_call,
        "{}",
        report(d)
    );
    assert!(viscous.rel_err_pct.unwrap() < max_err_pct, "{}", report(d));
    assert_eq!(first_significant(c), Some("viscous_power"), "{}", report(d));
    (viscous.rel_err_pct.unwrap(), stribeck.rel_err_pct.unwrap())
}

/// A rival whose candidate error is up to twice the leader's is a close call (session 93):
/// on viscous-power record 34770 (issue's axes; never-run in session 92, used since) the
/// Stribeck shape scored 1.23 % and the viscous power 1.79 % (1.46x), and with the window at
/// 1.25 the Stribeck shape was named; searched again, the viscous power reaches under 1 % (the
/// truth's floor 0.28 %) and is the answer, the Stribeck shape stays where it was.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn a_rival_at_twice_the_leaders_error_is_a_close_call() {
    let d = diagnose_on_issue_axes("viscous_power", 34770);
    let (viscous, stribeck) = viscous_power_settles_over_stribeck(&d, 1.0);
    assert!(stribeck > 1.1 * viscous, "{}", report(&d));
}

/// A close call's leader is searched again only where a rival, searched again, reaches its
/// evidence (session 96): on temperature record 1144 (issue's axes; a timing seed first run in
/// session 95) the position dependence (16 cosine terms) scored 1.01 % against the
/// temperature's 0.71 %, a close call; searched again it stays below the temperature's
/// evidence as it stood, so the temperature keeps its candidate fit, says so (its own flag),
/// and is named.
/// (On 20642 and 34770 above the rival does reach it, and both are searched again.)
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn a_close_calls_leader_that_no_rival_reaches_is_not_searched_again() {
    let d = diagnose_on_issue_axes("temperature_dependence", 1144);
    let c = &d.stages[0].candidates;
    let named = |n: &str| c.iter().find(|c| c.kind.name() == n).unwrap();
    let (lead, rival) = (
        named("temperature_dependence"),
        named("position_dependence"),
    );
    assert!(
        lead.unchallenged_close_call && !lead.settled_close_call,
        "{}",
        report(&d)
    );
    assert!(
        rival.settled_close_call && !rival.unchallenged_close_call,
        "{}",
        report(&d)
    );
    assert!(rival.delta_bic.unwrap() < lead.delta_bic.unwrap());
    assert_eq!(first_significant(c), Some("temperature_dependence"));
}

/// The dwell term's renewal distance is searched between its grid's decades
/// (`diagnose::shape_vertex_ln`): on fresh dwell record 20737 (hydraulic; the truth forgets the
/// dwell over 0.6 mm) the grid's best, 1 mm, left the dwell candidate at 2.63 % and a cut of
/// 14.7 %, below the decision's 15 %, and nothing was named; between the decades it errs less
/// and is named.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn the_dwell_renewal_distance_is_searched_between_its_grid_points() {
    let (d, _) = diagnose(Some("dwell_stiction"), 20737, &[]);
    let c = &d.stages[0].candidates;
    let dwell = c
        .iter()
        .find(|c| c.kind.name() == "dwell_stiction")
        .unwrap();
    let renewal = dwell
        .parameters
        .iter()
        .find(|q| q.name == "renewal_distance_m")
        .map(|q| q.value)
        .unwrap();
    let on_grid = diagnose::fit::DWELL_RENEWAL_GRID_M
        .iter()
        .any(|g| (renewal / g - 1.0).abs() < 1e-9);
    assert!(!on_grid, "{renewal:e}");
    assert!(dwell.rel_err_pct.unwrap() < 2.6, "{}", report(&d));
    assert_eq!(
        first_significant(c),
        Some("dwell_stiction"),
        "{}",
        report(&d)
    );
}

/// The aging law (`DwellLaw::Aging`) renews a dwell contact's age only over its renewal
/// distance of slip: from one sample to the next the age falls by no more than the travel
/// allows, with two counts and a slip of twice the travel as slack. The age that any slip
/// renews (`DwellLaw::RestartAtStick`) falls where no count moves: on this record at
/// 9.30 s an age of 1.3 s renewed in a 4 um creep, the reading still at rest (session 97).
#[test]
fn the_aging_law_renews_a_dwell_age_only_over_its_renewal_distance() {
    let renewed_beyond_travel = |law| {
        let (text, axis) = generators::axis::dwell_record(35270, Axes::Issue, law);
        let rec = Record::parse(&text, Path::new("dwell.csv")).unwrap();
        let generators::axis::Shape::Dwell { renewal_m, .. } = axis.shape else {
            panic!("a dwell record: {:?}", axis.shape)
        };
        let age = axis.dwell_trace.expect("the record's clock").0;
        (1..age.len())
            .filter(|&i| {
                let travel = (rec.x[i] - rec.x[i - 1]).abs() + 2e-6;
                age[i] < age[i - 1] * (-2.0 * travel / renewal_m).exp() - 1e-12
            })
            .count()
    };
    assert_eq!(renewed_beyond_travel(DwellLaw::Aging), 0);
    let restarts = renewed_beyond_travel(DwellLaw::RestartAtStick);
    assert!(restarts > 10, "{restarts}");
}

/// Main's dwell rule gated by the contact check (session 86): where the dwell term is the
/// first significant candidate by its 10 % cut, the model leaves more than the measurement
/// accounts for, and a Maxwell-slip contact in the bristle's place describes what the model
/// leaves, cutting more than every significant candidate, they are all held. Effect-free
/// record 4552 (issue's axes, a Maxwell-slip contact under them, session 85's M11): main named
/// dwell there at a 19 % cut, with asymmetry significant too (21 %); the contact cuts 89 %.
/// The stage then ends beyond the eight and the diagnosis reports the contact that held them. Its twin, a true dwell record the contact does not describe, is
/// `a_dwell_term_beyond_the_measurement_that_no_contact_describes_is_named`.
#[test]
fn a_dwell_term_that_a_contact_describes_better_is_held() {
    let d = diagnose_issue_record(None, 4552, ContactKind::Maxwell);
    let base = &d.stages[0];
    let dwell = dwell_candidate(base);
    // the record exercises the rule: detected and over main's cut, beyond the measurement
    assert!(
        dwell.detected && dwell.error_cut >= diagnose::DWELL_MIN_ERROR_CUT,
        "{}",
        report(&d)
    );
    assert!(d.unexplained(base).beyond_measurement(), "{}", report(&d));
    let contact_cut = dwell.held_by_contact.expect("held by the contact");
    assert!(contact_cut > dwell.error_cut && contact_cut >= diagnose::contact::CONTACT_MIN_CUT);
    assert!(!dwell.significant && dwell.held_note().is_some() && dwell.near_cut().is_none());
    // every candidate it held cut less than the contact, and none is left significant
    let held: Vec<_> = base
        .candidates
        .iter()
        .filter(|c| c.held_by_contact.is_some())
        .collect();
    assert!(held.len() >= 2, "{}", report(&d));
    assert!(held
        .iter()
        .all(|c| c.held_by_contact == Some(contact_cut) && c.error_cut < contact_cut));
    assert_eq!(first_significant(&base.candidates), None, "{}", report(&d));
    // the contact that held it is the one reported: it describes what the model leaves
    let tried = d.contact.as_ref().expect("the contact tried is kept");
    assert!(tried.describes && tried.error_cut == contact_cut);
    let html = diagnose::report::html(&d, "axis.csv", None);
    assert!(
        html.contains("describes what it leaves better"),
        "the report names the rule"
    );
}

/// Stribeck record 34959 on the issue's axes (its motion under 15 mm/s, the baseline's Coulomb
/// level at zero), diagnosed once for the three tests that read it: the table start, the
/// refusal of its baseline, the ratio at its physical edge.
fn stribeck_34959() -> &'static Diagnosis {
    static D: std::sync::LazyLock<Diagnosis> =
        std::sync::LazyLock::new(|| diagnose_on_issue_axes("stribeck_shape", 34959));
    &D
}

/// [`diagnose`] of a record on the axes issue 9 describes (`Axes::Issue`).
fn diagnose_on_issue_axes(effect: &'static str, seed: u64) -> Diagnosis {
    diagnose_issue_record(Some(effect), seed, ContactKind::LuGre)
}

/// [`diagnose`] of a record on the axes issue 9 describes, with `contact` under them.
fn diagnose_issue_record(
    effect: Option<&'static str>,
    seed: u64,
    contact: ContactKind,
) -> Diagnosis {
    diagnose_issue_axes(effect, seed, contact, DwellLaw::RestartAtStick, &[]).0
}

/// Where the model leaves more than the measurement accounts for and a Maxwell-slip contact in
/// the bristle's place does not describe what it leaves, a detected dwell term is significant
/// from a cut of `diagnose::DWELL_BEYOND_MIN_ERROR_CUT` (session 85). Dwell record 35440
/// (issue's axes, the restart law `DwellLaw::RestartAtStick`; session 102's set B): the baseline leaves 7.9x
/// what the measurement accounts for, the term cuts 6.9 % of it, from the static table too,
/// under the 10 % cut elsewhere, and the contact cuts -1.6 %. Until session 109 the record was
/// 34996 (session 84's D10, a cut of 9.8 %); since the table start for any leader of a record
/// nothing explains (adopted in session 109) its dwell term, fitted from the table, cuts
/// 10.3 % and is named by the ordinary cut. Its twin, the Maxwell-slip contact that is not
/// named dwell, is `a_contact_that_is_not_lugre_is_not_called_explained` (its dwell term also
/// cuts over 4 %).
#[test]
fn a_dwell_term_beyond_the_measurement_that_no_contact_describes_is_named() {
    let d = diagnose_on_issue_axes("dwell_stiction", 35440);
    let base = &d.stages[0];
    let dwell = dwell_candidate(base);
    // the record exercises the rule: between the two cuts, beyond the measurement
    assert!(
        dwell.error_cut >= diagnose::DWELL_BEYOND_MIN_ERROR_CUT
            && dwell.error_cut < diagnose::DWELL_MIN_ERROR_CUT,
        "{}",
        report(&d)
    );
    assert!(d.unexplained(base).beyond_measurement(), "{}", report(&d));
    let contact_cut = dwell
        .beyond_the_measurement
        .expect("made significant beyond");
    assert!(
        contact_cut < diagnose::contact::CONTACT_MIN_CUT,
        "{contact_cut}"
    );
    assert!(dwell.significant && dwell.beyond_note().is_some());
    // the contact that decided it is the one the diagnosis reports
    let tried = d.contact.as_ref().expect("the contact tried is kept");
    assert!(!tried.describes && tried.error_cut == contact_cut);
    // the report says why it is significant at that cut
    let html = diagnose::report::html(&d, "axis.csv", None);
    assert!(
        html.contains("does not describe it"),
        "the report names the rule"
    );
    assert_eq!(
        first_significant(&base.candidates),
        Some("dwell_stiction"),
        "{}",
        report(&d)
    );
    // no other candidate was made significant by it
    assert!(base
        .candidates
        .iter()
        .all(|c| c.beyond_the_measurement.is_none() || c.kind == EffectKind::DwellStiction));
}

/// The dwell term is detected on positive evidence against the current model
/// (`diagnose::DWELL_MIN_DBIC`), where every other effect needs very strong evidence
/// (`diagnose::MIN_DBIC`): its own nulls (growth with the rest time against its twin, the 10 %
/// cut) still hold it. Dwell record 34907 (issue's axes, session 81): the term cuts the error by
/// 16 % and shows growth (9.7), but with few independent samples its dBIC is 3.4; until session
/// 81 it was not named.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn a_dwell_term_with_positive_evidence_and_nulls_of_its_own_is_named() {
    let d = diagnose_on_issue_axes("dwell_stiction", 34907);
    let c = &d.stages[0].candidates;
    let dwell = c
        .iter()
        .find(|c| c.kind == EffectKind::DwellStiction)
        .unwrap();
    let dbic = dwell.delta_bic.unwrap();
    // the record exercises the gate: between the dwell's bar and everyone else's
    assert!(
        dbic > diagnose::DWELL_MIN_DBIC && dbic <= diagnose::MIN_DBIC,
        "{}",
        report(&d)
    );
    let growth = dwell.dwell.as_ref().unwrap().growth_dbic;
    assert!(
        growth >= diagnose::breakaway::DWELL_MIN_GROWTH_DBIC,
        "{growth}"
    );
    assert!(
        dwell.error_cut >= diagnose::DWELL_MIN_ERROR_CUT,
        "{}",
        report(&d)
    );
    assert_eq!(
        first_significant(c),
        Some("dwell_stiction"),
        "{}",
        report(&d)
    );
    // every other effect is still held to the very strong bar
    assert!(c
        .iter()
        .filter(|c| c.kind != EffectKind::DwellStiction && c.detected)
        .all(|c| c.delta_bic.unwrap() > diagnose::MIN_DBIC));
}

/// A record with exactly `breakaway::MIN_DEPARTURES` departures from rest tests the dwell
/// term: dwell record 34862 (issue's axes) has 5, and its term (dBIC 240, cut 0.20) was
/// untested until session 81, when 6 were needed.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn five_departures_test_dwell_stiction() {
    let d = diagnose_on_issue_axes("dwell_stiction", 34862);
    assert_eq!(
        d.breakaway.departures.len(),
        diagnose::breakaway::MIN_DEPARTURES
    );
    assert_eq!(d.breakaway.untestable, None);
    let c = &d.stages[0].candidates;
    assert_eq!(
        first_significant(c),
        Some("dwell_stiction"),
        "{}",
        report(&d)
    );
}

/// The first baseline only sets the motion weights (`diagnose::first_baseline`): one round of
/// the vs and sigma0 search, not refined, instead of the weighted baseline's two rounds and
/// refinement. On the stick-slip Stribeck record 1504 (a force actuator), where the weights
/// discount the most, it errs more than the full search (session 36: 1.24 against 1.17 %, vs
/// 0.95 against 1.33 mm/s), yet the weights it gives must agree with the full search's within
/// 0.02 rms (weights lie in 0..1; measured 0.015).
#[test]
fn the_first_baseline_sets_the_weights_the_full_search_would() {
    let (text, _) = random_record(Some("stribeck_shape"), 1504);
    let rec = Record::parse(&text, Path::new("axis.csv")).unwrap();
    let protocol = Protocol::default();
    let p = Prepared::new(&rec, "axis.csv", protocol).unwrap();
    let n_eff = diagnose::fit::effective_samples(&p, protocol.parallel_cutoff_hz);
    let opts = Options::default();
    let (first, full) = (
        diagnose::first_baseline(&p, &opts, n_eff),
        diagnose::baseline(&p, &opts, n_eff),
    );
    let weights = |f: &diagnose::fit::Fit| {
        let (own, spread) = diagnose::prediction_spread(&rec, "axis.csv", protocol, &p, &f.model);
        diagnose::motion_weights(&p, &own, &spread, diagnose::MOTION_WEIGHT_FLOOR)
    };
    let (w_first, w_full) = (weights(&first), weights(&full));
    let moving: Vec<usize> = p.scored_samples().collect();
    let rms = (moving
        .iter()
        .map(|&i| (w_first[i] - w_full[i]).powi(2))
        .sum::<f64>()
        / moving.len() as f64)
        .sqrt();
    let mean = |w: &[f64]| moving.iter().map(|&i| w[i]).sum::<f64>() / moving.len() as f64;
    println!(
        "first {:.3} % (vs {:.2e}, sigma0 {:.2e}), full {:.3} % (vs {:.2e}, sigma0 {:.2e}); \
         weights: mean {:.3} against {:.3}, rms difference {rms:.4}",
        first.rel_err_pct,
        first.model.friction.params.stribeck_velocity(),
        first.model.friction.params.bristle_stiffness(),
        full.rel_err_pct,
        full.model.friction.params.stribeck_velocity(),
        full.model.friction.params.bristle_stiffness(),
        mean(&w_first),
        mean(&w_full)
    );
    assert!(rms <= 0.02, "rms difference of the weights {rms}");
}

/// The motion weights are on in every diagnosis (`diagnose::motion_weights`): on a stick-slip
/// Stribeck record of the calibration seeds (1504, a force actuator) the weighted baseline errs
/// less than over every moving sample alike, since the weights discount the abrupt stops
/// where it errs most, and the Stribeck shape is the first significant candidate. Without the
/// weights the two errors are one. (Until session 24 the unweighted fit missed the Stribeck
/// shape here; with the bristle carrying the measured force at rest it finds it too.) The
/// weighted ranking is a close call led by the dwell term, which searched again loses its
/// significance: a close call's leading dwell term is always searched again (session 96).
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn the_motion_weights_discount_the_abrupt_stops_of_a_stick_slip_record() {
    let (text, _) = random_record(Some("stribeck_shape"), 1504);
    let rec = Record::parse(&text, Path::new("axis.csv")).unwrap();
    let run = |unweighted: bool| {
        let opts = Options {
            skip_final_ranking: true,
            unweighted,
            ..Default::default()
        };
        diagnose::diagnose(&rec, "axis.csv", &opts).unwrap()
    };
    let first = |d: &Diagnosis| {
        d.stages[0]
            .candidates
            .iter()
            .find(|c| c.significant)
            .map(|c| c.kind.name())
    };
    let (weighted, plain) = (run(false), run(true));
    let (w, p) = (&weighted.stages[0], &plain.stages[0]);
    println!(
        "weighted: baseline {:.3} % ({:.3} % alike), {}\nunweighted: baseline {:.3} % ({:.3} % alike), {}",
        w.fit.rel_err_pct,
        w.plain_rel_err_pct,
        report(&weighted),
        p.fit.rel_err_pct,
        p.plain_rel_err_pct,
        report(&plain)
    );
    assert!((p.fit.rel_err_pct - p.plain_rel_err_pct).abs() < 1e-9 * p.plain_rel_err_pct);
    assert!(w.fit.rel_err_pct < 0.8 * w.plain_rel_err_pct);
    assert_eq!(
        first(&weighted),
        Some("stribeck_shape"),
        "{}",
        report(&weighted)
    );
    assert_eq!(first(&plain), Some("stribeck_shape"), "{}", report(&plain));
}

/// Friction that ripples along the stroke (not a linear gradient): the cosine terms of the
/// position dependence follow it, their number chosen by the data, and the written parameter
/// file carries them back unchanged.
#[test]
fn a_periodic_position_dependence_is_found_and_its_shape_kept() {
    let (d, _) = diagnose(Some("position_dependence"), 1301, &["position_dependence"]);
    println!("{}", report(&d));
    let first = &d.stages[0].candidates[0];
    assert_eq!(first.kind.name(), "position_dependence", "{}", report(&d));
    assert!(first.significant);
    let base = d.stages[0].fit.rel_err_pct;
    let added = d.stages[1].fit.rel_err_pct;
    assert!(added < 0.25 * base, "{base:.2} % -> {added:.2} %");
    let pd = d.model().friction.effects.position_dependence.unwrap();
    assert!(pd.terms >= 1, "a linear gradient cannot follow a ripple");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("p.toml");
    let file = diagnose::parameter_file(&d, Some(200.0)).unwrap();
    file.write_checked(&path).unwrap();
    let (_, back) = ParamFile::read(&path).unwrap();
    let q = back.effects.position_dependence.unwrap();
    assert_eq!(q.terms, pd.terms);
    for x in [-0.1, 0.0, 0.03, 0.1] {
        assert!((q.shift(x) - pd.shift(x)).abs() < 1e-6 * (1.0 + pd.shift(x).abs()));
    }
}

/// A local wear spot narrower than four half-waves of the stroke can draw (calibration seed
/// 1300: a 5 cm bump on a 30 cm visited stroke): the data pick more cosine terms, and with
/// the position dependence added the error comes within 1.2x the noise floor (the generator's
/// true model driven by the same measured motion). With at most four terms it stayed at 2.13 %
/// against the floor's 1.23 %.
#[test]
fn a_narrow_wear_spot_is_followed_to_the_noise_floor() {
    spot_followed_past(1300, 4);
}

/// A wear spot narrower than eight half-waves of the stroke can draw (never-run seed 20305,
/// studied in session 47: a Gaussian bump 3.7 cm wide on a 42 cm stroke): the data pick more
/// than eight cosine terms, and the error comes within 1.2x the noise floor. With at most
/// eight terms it stayed at 0.70 % against the floor's 0.44 % (1.6x), its order at the edge.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn a_wear_spot_narrower_than_eight_half_waves_gets_more_terms() {
    spot_followed_past(20305, 8);
}

/// The position record of `seed` with its dependence added: more than `terms` cosine terms,
/// and the error within 1.2x the noise floor.
fn spot_followed_past(seed: u64, terms: usize) {
    let (d, axis) = diagnose(Some("position_dependence"), seed, &["position_dependence"]);
    position_followed_past(&d, &axis, terms);
}

/// A diagnosis `d` of `axis`'s record with the position dependence added: more than `terms`
/// cosine terms, and the error within 1.2x the noise floor.
fn position_followed_past(d: &Diagnosis, axis: &Axis, terms: usize) {
    let floor = truth_error_pct(axis, &d.prepared);
    let added = d.stages[1].fit.rel_err_pct;
    let pd = d.model().friction.effects.position_dependence.unwrap();
    println!(
        "{}; added {added:.2} %, floor {floor:.2} %, {} terms",
        report(d),
        pd.terms
    );
    assert!(pd.terms > terms, "{} terms", pd.terms);
    assert!(
        added <= 1.2 * floor,
        "{added:.2} % against the floor's {floor:.2} %"
    );
}

/// A position dependence whose shape every other cosine term carries is searched past a term
/// that does not pay (session 106, `fit::grid_min_extending`): on the issue's axes, position
/// record 34617 (never run before table L: a periodic dependence of 214 N, wavelength 12.5 cm,
/// over 24 cm of stroke) stopped at 3 terms because the fourth did not pay for itself, and
/// with the dependence added erred 2.63 % against its floor's 0.40 % (`axis_suite 0 0 --axes
/// issue --seeds position_dependence:34617..34617`); searched on, it takes 11 terms and errs
/// 0.27 %. Fails if one term that does not pay ends the order search.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn a_position_shape_carried_by_every_other_term_is_searched_past_one_that_does_not_pay() {
    let (d, axis) = diagnose_issue_axes(
        Some("position_dependence"),
        34617,
        ContactKind::LuGre,
        DwellLaw::Aging,
        &["position_dependence"],
    );
    position_followed_past(&d, &axis, 4);
}

/// The generator's own check: its true model driven by the measured motion through the
/// diagnosis pipeline (the noise floor) scores far better than the fitted baseline when a
/// strong effect is hidden, and the visibility rule keeps the drawn effect visible.
#[test]
fn the_generator_truth_explains_its_record() {
    let (d, axis) = diagnose(Some("offset"), 1102, &[]);
    let floor = truth_error_pct(&axis, &d.prepared);
    let base = d.stages[0].fit.rel_err_pct;
    println!("floor {floor:.2} %, baseline {base:.2} %");
    assert!(floor < 3.0, "{floor}");
    assert!(base > 3.0 * floor, "{base} vs {floor}");
}

/// The dwell term's age at a new stick is the data's choice (session 67). On the issue's axes,
/// dwell record 33711's contact restarts its age at each stick (the generator's law): with an
/// accumulating age our term left 0.73 % where the record's floor is 0.22 % (session 66); the
/// restarting age is chosen and reaches the floor. On 33712 the accumulating age fits better
/// (with a restarting one the dwell was lost, 5.55 %) and is kept (there our dwell term stays at
/// 3.65 % against the floor's 0.53 %, its time constant and renewal distance at the ends of
/// their searches: a bound of 7.5x the floor). The pair fails if the search tries one rule
/// only, or if the rule does not reach the model.
#[test]
fn a_restarting_dwell_rule_is_chosen_where_the_record_shows_it() {
    dwell_rule_is_chosen(33711, DwellAge::Restarts, DwellClock::BodySpeed, 1.2);
}

/// The other half of [`a_restarting_dwell_rule_is_chosen_where_the_record_shows_it`]: on 33712
/// the body's restarting age lost the dwell (5.55 %) and the accumulating age was kept (3.65 %
/// against the floor's 0.53 %, sessions 66..89). Since session 90 the age restarting at each
/// stick of the contact is searched too, and is chosen there: 1.43 % (2.7x the floor;
/// `axis_suite 0 0 --axes issue --seeds dwell_stiction:33712`). Fails if the search tries the
/// body's rules only, or if the rule does not reach the model (expensive suite).
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn a_dwell_age_the_body_misses_is_kept_where_the_contact_shows_it() {
    dwell_rule_is_chosen(33712, DwellAge::Restarts, DwellClock::ContactSlip, 3.0);
}

/// The third dwell rule (session 89, searched whole only where a coarse first pass chooses it,
/// session 90): on the issue's axes, dwell record 35110's contact sticks at the reversals of
/// sinusoids while the body moves through them in pre-sliding, so a clock on the body's speed
/// misses those sticks. The age restarting at each stick of the contact, its clock on the
/// bristle's slip, is chosen and errs 1.82 % against the floor's 0.39 % (4.6x); the best point
/// of the body's clocks errs 2.59 % (6.6x, `dwell_clock_probe fit 35110 --axes issue`). Fails
/// if the first pass chooses another rule or the clock does not reach the model.
#[test]
fn a_dwell_clock_on_the_contacts_slip_is_chosen_where_the_record_shows_it() {
    dwell_rule_is_chosen(35110, DwellAge::Restarts, DwellClock::ContactSlip, 5.0);
}

/// The aging rule where a dwell term is added as a stage (session 101, `STAGE_DWELL_RULE`): a
/// contact whose junctions age by rate-and-state friction's aging law (the generator's
/// `DwellLaw::Aging`) keeps an age `D / v` through a slow slide, which the first three rules
/// cannot follow. The ranking searches the aging rules only where the model leaves more than
/// the measurement accounts for (session 104; as a rule searched everywhere it named dwell on
/// effect-free record 138, session 100); the stage searches them whatever the model leaves. On
/// the issue's axes, used aging dwell record 35462's baseline leaves 0.7x what the measurement
/// accounts for; the ranking names dwell stiction under an accumulating age at 0.84 %, and the
/// stage reaches 0.55 % under the aging law, within 1.2x the record's floor of 0.74 % (`host-sim diagnose --data
/// dwell_stiction.csv --add dwell_stiction` on `axis_suite --write DIR --seed 35462 --axes
/// issue`). (Until session 104 this test ran on 35290, whose baseline leaves 5.1x: the ranking
/// takes the aging rule there now.) Fails if the ranking tries the aging rule where the model
/// leaves no more than the measurement accounts for, if the stage does not, or if the rule does
/// not reach the model.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn a_dwell_stage_takes_the_aging_rule_where_the_contact_ages_by_it() {
    let seed = 35462;
    let (d, floor) = aging_dwell_stage(seed);
    let left = d.unexplained(&d.stages[0]);
    assert!(!left.exceeds_measurement(), "ratio {:.2}", left.ratio());
    let ranked = dwell_candidate(&d.stages[0]);
    let ranked_age = ranked.dwell.as_ref().and_then(|e| e.age_at_stick);
    assert!(
        ranked_age.is_some_and(|a| a != DwellAge::Aging),
        "{ranked_age:?}"
    );
    let ranked_err = ranked.rel_err_pct.unwrap();
    let added = aged_on_the_contacts_slip(&d);
    assert!(
        added <= 0.8 * ranked_err && added <= 1.2 * floor,
        "{added:.2} % against the ranked {ranked_err:.2} % and the floor {floor:.2} %"
    );
}

/// The aging law ages on the contact's slip (session 107, `STAGE_DWELL_RULE`): the junctions
/// are renewed where the contact slides, and a bristle that only deflects (pre-sliding, the
/// creep of a held axis, a reversal) renews none of them. On the issue's axes, used aging dwell
/// record 35631's stage erred 0.62 % under the aging law on the body's speed (1.9x its floor of
/// 0.33 %), and errs 0.29 % on the contact's slip (`host-sim diagnose --data dwell_stiction.csv
/// --add dwell_stiction` on `axis_suite --write DIR --seed 35631 --axes issue`). Fails if the
/// stage's aging rule runs on the body's speed, or if the stage errs more than 1.2x the floor.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn a_dwell_stage_ages_its_junctions_on_the_contacts_slip() {
    let seed = 35631;
    let (d, floor) = aging_dwell_stage(seed);
    let added = aged_on_the_contacts_slip(&d);
    assert!(
        added <= 1.2 * floor,
        "{added:.3} % against the floor {floor:.3} %"
    );
}

/// The last stage's dwell term ages by the aging law on the contact's slip
/// (`STAGE_DWELL_RULE`); the stage's error \[%\].
fn aged_on_the_contacts_slip(d: &diagnose::Diagnosis) -> f64 {
    let stage = d.last_stage();
    let term = stage.fit.model.friction.effects.dwell_stiction.unwrap();
    assert_eq!(
        (term.age_at_stick, term.clock),
        (DwellAge::Aging, DwellClock::ContactSlip),
        "{term:?}"
    );
    stage.fit.rel_err_pct
}

/// A stage refines its effect's second shape parameter too (session 107,
/// `search::refine_shape`), after the first and before the first once more: the dwell's
/// renewal distance and time constant trade against each other. On the issue's axes, used aging
/// dwell record 35683's stage ended at 0.32 % (time constant 0.58 s, renewal 0.76 mm at the
/// parabola's vertex between grid points), 1.27x its floor of 0.25 %; refined jointly it errs
/// 0.23 % (0.45 s, 0.62 mm) (`host-sim diagnose --data dwell_stiction.csv --add
/// dwell_stiction` on `axis_suite --write DIR --seed 35683 --axes issue`). Fails if the stage
/// does not refine the renewal distance with the time constant, or errs more than 1.2x the
/// floor.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn a_dwell_stage_refines_its_renewal_distance_with_its_time_constant() {
    let seed = 35683;
    let (d, floor) = aging_dwell_stage(seed);
    let added = d.last_stage().fit.rel_err_pct;
    assert!(
        added <= 1.2 * floor,
        "{added:.3} % against the floor {floor:.3} %"
    );
}

/// The growth's form where a dwell term is added as a stage (session 103,
/// `ranking::growth_start`): the generator's contacts grow their junctions by a Hill law, whose
/// tail is slower than the exponential's. On the issue's axes, used aging dwell record 35427
/// (Hill exponent 1.12) is named by the ranking, which fits the exponential alone; the stage
/// takes the hyperbolic form and errs within 1.2x the record's floor (0.51 % against 0.53 %,
/// where the exponential's best stage erred 0.58 %: `host-sim diagnose --data dwell_stiction.csv
/// --add dwell_stiction` on `axis_suite --write DIR --seed 35427 --axes issue`). Fails if the
/// ranking fits another form, if the stage does not choose the hyperbolic, or if it errs more
/// than the exponential's stage did.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn a_dwell_stage_takes_the_hyperbolic_growth_where_it_fits_better() {
    let seed = 35427;
    let (d, floor) = aging_dwell_stage(seed);
    let ranked = dwell_candidate(&d.stages[0]);
    let ranked_growth = ranked.dwell.as_ref().and_then(|e| e.growth);
    assert_eq!(ranked_growth, Some(DwellGrowth::Exponential));
    let stage = d.last_stage();
    let term = stage.fit.model.friction.effects.dwell_stiction.unwrap();
    assert_eq!(term.growth, DwellGrowth::Hyperbolic, "{term:?}");
    let added = stage.fit.rel_err_pct;
    assert!(
        added <= 1.2 * floor && added < 0.55,
        "{added:.3} % against the floor {floor:.3} %"
    );
}

/// A stage refines the added effect's own parameter continuously (session 103,
/// `search::refine_effect`), as it refines vs and sigma0: on the issue's axes, used aging dwell
/// record 35458's stage kept the time-constant grid's 0.5 s and erred 0.28 %, above the
/// record's floor of 0.25 %; refined, its time constant is 0.37 s and it errs 0.24 %
/// (`host-sim diagnose --data dwell_stiction.csv --add dwell_stiction` on `axis_suite --write
/// DIR --seed 35458 --axes issue`). Fails if the time constant stays on a grid point or the
/// stage errs more than the floor.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn a_dwell_stage_refines_its_time_constant_between_grid_points() {
    let seed = 35458;
    let (d, floor) = aging_dwell_stage(seed);
    let stage = d.last_stage();
    let tau = (stage.fit.model.friction.effects.dwell_stiction)
        .unwrap()
        .time_constant;
    let info = diagnose::effect_info(EffectKind::DwellStiction);
    let (_, grid, _) = info.nonlinear.unwrap();
    assert!(
        grid.iter().all(|g| (tau / g - 1.0).abs() > 1e-3),
        "time constant {tau} s on the grid {grid:?}"
    );
    let added = stage.fit.rel_err_pct;
    assert!(
        added <= floor,
        "{added:.3} % against the floor {floor:.3} %"
    );
}

/// The ranking searches the aging rules where the model leaves more than the measurement
/// accounts for (session 104, `fit::rules`): on the issue's axes, used aging dwell record
/// 35474's baseline leaves 1.45x what the measurement accounts for, above 1 and under the
/// margin of `UNEXPLAINED_RATIO` (1.5). Under the first three rules the dwell candidate erred
/// 0.24 % (dBIC 1293) and asymmetry was named first (0.22 %, dBIC 1450); under the aging rule
/// the dwell candidate errs 0.16 % and is named first (`axis_suite 0 0 --axes issue --seeds
/// dwell_stiction:35474..35474`). Fails if the ranking leaves the aging rules out there (or
/// keeps them only beyond the margin), or if dwell stiction is not named first.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn the_ranking_searches_the_aging_rule_where_the_model_leaves_more_than_the_reading() {
    let seed = 35474;
    let d = ranked_where_aging_rules_are_searched(Some("dwell_stiction"), seed, ContactKind::LuGre);
    let stage = &d.stages[0];
    let left = d.unexplained(stage);
    assert!(
        !left.beyond_measurement(),
        "{seed}: ratio {:.2}",
        left.ratio()
    );
    assert_eq!(
        first_significant(&stage.candidates),
        Some("dwell_stiction"),
        "{seed}: {}",
        report(&d)
    );
    let ranked = dwell_candidate(stage);
    let age = ranked.dwell.as_ref().and_then(|e| e.age_at_stick);
    assert_eq!(age, Some(DwellAge::Aging), "{seed}");
    let err = ranked.rel_err_pct.unwrap();
    assert!(err < 0.2, "{seed}: {err:.3} %");
}

/// Where the ranking chose an aging dwell rule, a dwell stage also runs from the candidate the
/// first three rules gave (session 104, `ranking::stage_fit`, `Candidate::rule_start`) and
/// keeps the lower residual: on the issue's axes, used aging dwell record 35523 (its baseline
/// leaves 9x what the measurement accounts for) is named under the aging rule; the stage from
/// that candidate alone erred 0.27 %, the stage from the first three rules' candidate 0.25 %
/// (`host-sim diagnose --data dwell_stiction.csv --add dwell_stiction` on `axis_suite --write
/// DIR --seed 35523 --axes issue`, builds c4a6725 and 4079f0a). Fails if the stage loses the
/// other rules' start, or if the ranking does not choose the aging rule there.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn a_dwell_stage_keeps_what_the_other_rules_candidate_reaches() {
    let seed = 35523;
    let (d, floor) = aging_dwell_stage(seed);
    let ranked = dwell_candidate(&d.stages[0]);
    let age = ranked.dwell.as_ref().and_then(|e| e.age_at_stick);
    assert_eq!(age, Some(DwellAge::Aging), "{seed}");
    let added = d.last_stage().fit.rel_err_pct;
    assert!(
        added < 0.26 && added <= 1.2 * floor,
        "{seed}: {added:.3} % against the floor {floor:.3} %"
    );
}

/// An aging dwell term counts only where its growth with the rest time is shown (session 105,
/// `ranking::score` and `ranking::judge`): while sliding its age holds `D / |v|`, so a level
/// whose growth is not shown is a velocity-weakening curve. On the issue's axes, Stribeck record
/// 34843 (never run before session 104) leaves 1.85x what the measurement accounts for; with
/// the aging rules in the ranking as session 104 searched them, the dwell candidate took the
/// aging rule, its growth with the rest not shown (evidence 0), and was named first (dBIC 1433
/// against the Stribeck shape's 1376; `axis_suite 0 0 --axes issue --seeds
/// stribeck_shape:34843..34843`). Fails if the aging term is judged as a saturated level, or
/// if the candidate keeps an aging term whose growth is not shown and is named first.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn an_aging_dwell_level_whose_growth_is_not_shown_is_not_named() {
    let seed = 34843;
    let d = ranked_where_aging_rules_are_searched(Some("stribeck_shape"), seed, ContactKind::LuGre);
    let stage = &d.stages[0];
    assert_eq!(
        first_significant(&stage.candidates),
        Some("stribeck_shape"),
        "{seed}: {}",
        report(&d)
    );
    let dwell = dwell_candidate(stage);
    let evidence = dwell
        .dwell
        .as_ref()
        .expect("the record tests the dwell term");
    assert!(
        evidence.growth_shown
            || evidence.age_at_stick != Some(DwellAge::Aging)
            || !dwell.significant,
        "{seed}: an aging term whose growth is not shown judged significant"
    );
}

/// An aging dwell term's growth with the rest time must show at the breakaway peaks alone as
/// well (session 105, `ranking::judge`): while sliding what it adds is a speed curve, which the
/// whole record's evidence against its rest-independent twin counts too. Maxwell-contact
/// effect-free record 5882 of the issue's axes (never run before session 105) leaves 1.05x what
/// the measurement accounts for; with the aging rules counted on the whole record's evidence
/// alone, its dwell candidate took the aging rule with evidence 168 against its twin while its
/// breakaway peaks fitted 1 % worse than the twin's, and was named (error cut 0.104;
/// `axis_suite 0 0 --axes issue --contact maxwell --seeds none:5882..5882`). Fails if an aging
/// term is judged significant without its peaks showing its growth, or if the record is given
/// an effect.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn an_aging_dwell_term_must_show_its_growth_at_the_breakaway_peaks() {
    let seed = 5882;
    let d = ranked_where_aging_rules_are_searched(None, seed, ContactKind::Maxwell);
    let stage = &d.stages[0];
    assert_eq!(
        first_significant(&stage.candidates),
        None,
        "{seed}: {}",
        report(&d)
    );
    for c in &stage.candidates {
        let aging = c.dwell.as_ref().and_then(|e| e.age_at_stick) == Some(DwellAge::Aging);
        assert!(!(aging && c.significant && c.dwell.as_ref().is_some_and(|e| e.peak_cut <= 0.0)));
    }
}

/// The issue's axes' family-A record of `effect` (`None`: effect-free) with seed `seed` on the
/// `contact`, a dwell contact aged by the generator's aging law, diagnosed with the final
/// ranking skipped; the model the first stage ranks against must leave more than the
/// measurement accounts for (`Unexplained::exceeds_measurement`), where the ranking searches
/// the aging dwell rules (`fit::rules`).
fn ranked_where_aging_rules_are_searched(
    effect: Option<&'static str>,
    seed: u64,
    contact: ContactKind,
) -> Diagnosis {
    let (d, _) = diagnose_issue_axes(effect, seed, contact, DwellLaw::Aging, &[]);
    let left = d.unexplained(&d.stages[0]);
    assert!(
        left.exceeds_measurement(),
        "{seed}: ratio {:.2}",
        left.ratio()
    );
    d
}

/// The issue's axes' family-A record of `effect` (`None`: effect-free) with seed `seed` on the
/// `contact`, a dwell contact aged by the generator's `law` (`DwellLaw::Aging` is what
/// `axis_suite --axes issue` draws), diagnosed with the effects `add` added and the final
/// ranking skipped.
fn diagnose_issue_axes(
    effect: Option<&'static str>,
    seed: u64,
    contact: ContactKind,
    law: DwellLaw,
    add: &[&str],
) -> (Diagnosis, Axis) {
    let (text, axis) = random_record_of(
        effect,
        seed,
        Sensors::default(),
        contact,
        Family::A,
        Axes::Issue,
        law,
    );
    let rec = Record::parse(&text, Path::new("axis.csv")).unwrap();
    let opts = Options {
        add: add.iter().map(|s| s.to_string()).collect(),
        skip_final_ranking: true,
        ..Default::default()
    };
    (diagnose::diagnose(&rec, "axis.csv", &opts).unwrap(), axis)
}

/// The issue's axes' aging dwell record `seed` diagnosed with `dwell_stiction` added as a
/// stage (the final ranking skipped), and the record's floor \[%\]; the ranking must have
/// named dwell stiction first.
fn aging_dwell_stage(seed: u64) -> (diagnose::Diagnosis, f64) {
    dwell_named_first(seed, DwellLaw::Aging, vec!["dwell_stiction".into()])
}

/// The issue's axes' dwell record `seed` under the generator's `law`, diagnosed with the
/// effects `add` added as stages (the final ranking skipped), and the record's floor \[%\];
/// the ranking must have named dwell stiction first.
fn dwell_named_first(seed: u64, law: DwellLaw, add: Vec<String>) -> (diagnose::Diagnosis, f64) {
    let (text, axis) = generators::axis::dwell_record(seed, Axes::Issue, law);
    let rec = Record::parse(&text, Path::new("axis.csv")).unwrap();
    let opts = Options {
        add,
        skip_final_ranking: true,
        ..Default::default()
    };
    let d = diagnose::diagnose(&rec, "axis.csv", &opts).unwrap();
    assert_eq!(
        first_significant(&d.stages[0].candidates),
        Some("dwell_stiction"),
        "{seed}: {}",
        report(&d)
    );
    let p = Prepared::new(&rec, "axis.csv", Protocol::default()).unwrap();
    (d, truth_error_pct(&axis, &p))
}

/// Diagnoses the issue's axes' dwell record `seed`: the dwell term is named first, with the
/// age rule `rule` on the clock `clock`, and errs at most `floor_factor` times the record's
/// floor.
fn dwell_rule_is_chosen(seed: u64, rule: DwellAge, clock: DwellClock, floor_factor: f64) {
    let (d, floor) = dwell_named_first(seed, DwellLaw::RestartAtStick, Vec::new());
    let first = &d.stages[0].candidates[0];
    let evidence = first.dwell.expect("the dwell candidate weighs its growth");
    assert_eq!(evidence.age_at_stick, Some(rule), "{seed}");
    assert_eq!(evidence.clock, Some(clock), "{seed}");
    let model = first.fit.as_ref().unwrap().model;
    assert_eq!(
        model
            .friction
            .effects
            .dwell_stiction
            .map(|t| (t.age_at_stick, t.clock)),
        Some((rule, clock))
    );
    let added = first.rel_err_pct.unwrap();
    assert!(
        added <= floor_factor * floor,
        "{seed}: {added:.2} % against the floor {floor:.2} %"
    );
}

/// The axes issue 9 describes its own check on (`--axes issue`, `generators::axis::Axes`):
/// every draw inside the issue's ranges (a force actuator unless the effect needs chamber
/// pressures, 100..400 kg, sigma0 5e6..5e7 N/m, sigma1 0.2..1.0 of `sqrt(sigma0 M)`), the rest of
/// the seed's axis as drawn; and the wide axes of every earlier suite left exactly as drawn.
#[test]
fn the_issues_axes_lie_in_its_ranges_and_the_wide_ones_are_untouched() {
    use generators::axis::{Actuator, Axes, EFFECTS};
    let mut forces = 0;
    for seed in 0..200u64 {
        for effect in std::iter::once(None).chain(EFFECTS.map(Some)) {
            let wide = Axis::random(effect, seed);
            let same = Axes::Wide.narrow(wide.clone(), seed);
            assert_eq!(
                format!("{same:?}"),
                format!("{wide:?}"),
                "wide axis moved: {seed}"
            );
            let a = Axes::Issue.narrow(wide.clone(), seed);
            let damping = a.sigma1 / (a.sigma0 * a.mass_kg).sqrt();
            assert!(
                (100.0..=400.0).contains(&a.mass_kg),
                "{seed}: {} kg",
                a.mass_kg
            );
            assert!(
                (5e6..=5e7).contains(&a.sigma0),
                "{seed}: sigma0 {}",
                a.sigma0
            );
            assert!(
                (0.2..=1.0).contains(&damping),
                "{seed}: sigma1 {damping} critical"
            );
            let needs_pressures = effect == Some("load_dependence");
            assert_eq!(
                a.actuator == Actuator::Hydraulic,
                needs_pressures,
                "{seed} {effect:?}"
            );
            forces += usize::from(a.actuator == Actuator::Force);
            // the levels, the curve and the effect are the seed's
            assert_eq!(
                (a.coulomb_n, a.static_n, a.stribeck_m_per_s, a.sigma2),
                (
                    wide.coulomb_n,
                    wide.static_n,
                    wide.stribeck_m_per_s,
                    wide.sigma2
                )
            );
            assert_eq!(format!("{:?}", a.shape), format!("{:?}", wide.shape));
        }
    }
    assert_eq!(forces, 200 * 8);
}

/// The wrong-model contact behaves as a generalized Maxwell-slip model must (what makes it a
/// model our LuGre baseline does not contain): from rest it is as stiff as its elements
/// together; a presliding loop closes where it began (each element remembers its last slip);
/// and after a change of sliding speed its force reaches the new level with the time constant
/// `1/C`, not over a bristle's presliding distance.
#[test]
fn the_maxwell_contact_has_memory_and_lag() {
    use generators::axis::{Contact, Maxwell};
    let mut axis = Axis::random(None, 7);
    let m = Maxwell::random(&axis, 7);
    axis.contact = Contact::Maxwell(m.clone());
    let dt = 1e-3;
    let run = |v: &[f64]| {
        let x: Vec<f64> = v
            .iter()
            .scan(0.0, |x, v| {
                *x += v * dt;
                Some(*x)
            })
            .collect();
        let t: Vec<f64> = (0..v.len()).map(|i| i as f64 * dt).collect();
        let whole = 0..v.len();
        axis.friction_along(
            &t,
            &x,
            v,
            None,
            None,
            std::slice::from_ref(&whole),
            dt,
            None,
        )
    };
    // virgin loading, far inside every element's break: F = (sum k_i) x + sigma1 v
    let stiffness: f64 = m.elements.iter().map(|e| e.0).sum();
    let first_break_m = m
        .elements
        .iter()
        .map(|(k, a)| a * axis.static_n / k)
        .fold(f64::INFINITY, f64::min);
    let creep = 0.01 * first_break_m / 0.1; // [m/s]: a hundredth of the first break in 0.1 s
    let f = run(&vec![creep; 100]);
    let elastic = f[99] - axis.sigma1 * creep - axis.sigma2 * creep;
    let x = creep * 100.0 * dt;
    assert!(
        (elastic / (stiffness * x) - 1.0).abs() < 1e-6,
        "{elastic} against {}",
        stiffness * x
    );
    // a loop past every element's break, twice round: it closes
    let last_break_m = m
        .elements
        .iter()
        .map(|(k, a)| a * axis.static_n / k)
        .fold(0.0, f64::max);
    let amplitude = 1.5 * last_break_m;
    let speed = amplitude / 0.2;
    let mut v = vec![speed; 200];
    for _ in 0..2 {
        v.extend(vec![-speed; 400]);
        v.extend(vec![speed; 400]);
    }
    let f = run(&v);
    let (top1, top2) = (f[999], f[1799]);
    let span = f.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
        - f.iter().cloned().fold(f64::INFINITY, f64::min);
    assert!(span > 0.2 * axis.static_n, "no loop: span {span}");
    assert!((top1 - top2).abs() < 1e-6 * span, "{top1} vs {top2}");
    // and it is a loop: up and down through the middle differ
    assert!(
        (f[399] - f[799]).abs() > 0.05 * span,
        "{} {}",
        f[399],
        f[799]
    );
    // frictional lag: sliding at 50 mm/s, then at 1 mm/s; after 1/C the force has covered
    // 1 - 1/e of its way
    let steps_lag = (1.0 / m.lag_rate_per_s / dt).round() as usize;
    let mut v = vec![0.05; 1000];
    v.extend(vec![1e-3; 1000]);
    let f = run(&v);
    // the elements' part (all of them slip: no bristle damping)
    let elastic = |i: usize| f[i] - axis.sigma2 * v[i];
    let (before, after) = (elastic(999), elastic(1999));
    let done = (elastic(999 + steps_lag) - before) / (after - before);
    let expected = 1.0 - (-(steps_lag as f64) * dt * m.lag_rate_per_s).exp();
    println!(
        "C {:.0} 1/s, {} elements: {done:.3} of the way after {steps_lag} ms (expected {expected:.3})",
        m.lag_rate_per_s,
        m.elements.len()
    );
    assert!((done - expected).abs() < 0.03, "{done} vs {expected}");
}

/// The same axes and schedules (calibration seeds 128, force-actuated, and 131, hydraulic) with
/// a LuGre contact and with a generalized Maxwell-slip one: no candidate is significant on
/// either, but only on LuGre does the baseline leave no more than the measurement accounts for
/// (`diagnose::Unexplained`). On Maxwell-slip it leaves several times that, and the diagnosis
/// says that none of the eight effects describes it instead of "the model explains what this
/// record shows". A Maxwell-slip contact in the bristle's place (`diagnose::contact`, its own
/// ladder of elements, not the generator's) describes what is left on the Maxwell-slip records,
/// at under half the baseline's error, and errs more than the baseline on the LuGre ones (where
/// the diagnosis does not try it: the model leaves nothing beyond the measurement). The test
/// command runs the hydraulic axis; the force-actuated one is in the expensive suite.
#[test]
fn a_contact_that_is_not_lugre_is_not_called_explained() {
    not_lugre_is_not_called_explained(131);
}
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn a_contact_that_is_not_lugre_is_not_called_explained_on_a_force_actuated_axis() {
    not_lugre_is_not_called_explained(128);
}

fn not_lugre_is_not_called_explained(seed: u64) {
    use generators::axis::random_record_on;
    let mut ratios = Vec::new();
    for contact in [ContactKind::LuGre, ContactKind::Maxwell] {
        let (text, axis) = random_record_on(None, seed, Sensors::default(), contact);
        let rec = Record::parse(&text, Path::new("axis.csv")).unwrap();
        let opts = Options {
            skip_final_ranking: true,
            ..Default::default()
        };
        let d = diagnose::diagnose(&rec, "axis.csv", &opts).unwrap();
        let u = d.unexplained(&d.stages[0]);
        let floor = truth_error_pct(&axis, &d.prepared);
        println!(
            "seed {seed} {contact:?} ({:?}): baseline {:.2} %, floor {floor:.2} %, the model {u}; {}",
            axis.actuator,
            d.stages[0].fit.rel_err_pct,
            report(&d)
        );
        assert!(first_significant(&d.stages[0].candidates).is_none());
        ratios.push(u.ratio());
        // the diagnosis tries the contact where no candidate is significant and the model
        // leaves more than the measurement accounts for; here it is tried on either
        // contact, to compare
        let (fit, c) = (&d.stages[0].fit, contact_in_the_baselines_place(&d));
        println!("  a Maxwell-slip contact in the bristle's place {c}");
        match contact {
            ContactKind::LuGre => {
                assert!(!u.beyond_measurement(), "{u}");
                assert!(d.contact.is_none());
                assert_eq!(
                    d.contact_not_tried().as_deref(),
                    Some(diagnose::contact::NOT_TRIED)
                );
                assert!(!c.describes && c.rel_err_pct > fit.rel_err_pct);
                // the report says it was not tried, and shows no contact
                let html = diagnose::report::html(&d, "axis.csv", None);
                assert!(html.contains("was not tried"));
                assert!(!html.contains(diagnose::report::CONTACT_HEADING));
            }
            ContactKind::Maxwell => {
                assert!(u.beyond_measurement(), "{u}");
                // the truth explains its record far better than the baseline does
                assert!(fit.rel_err_pct > 3.0 * floor);
                assert!(c.describes && c.rel_err_pct < 0.5 * fit.rel_err_pct);
                let tried = d.contact.as_ref().expect("tried");
                assert!(d.contact_not_tried().is_none());
                assert_eq!(tried.rel_err_pct.to_bits(), c.rel_err_pct.to_bits());
                // the report shows it: its bar beside the model's, its force along the
                // record, a row per element and its parameters
                let html = diagnose::report::html(&d, "axis.csv", None);
                assert!(html.contains(diagnose::report::CONTACT_HEADING));
                assert!(html.contains(&format!("errs {:.2} %", tried.rel_err_pct)));
                assert!(
                    html.contains("\nMaxwell-slip contact\n</text>"),
                    "no legend entry"
                );
                assert!(html.contains("\nMaxwell-slip contact in the bristle&apos;s place\n"));
                assert_eq!(html.matches("\u{a0}um</td>").count(), tried.elements.len());
                assert!(html.contains("slip lag rate"));
            }
        }
    }
    assert!(ratios[1] > 3.0 * ratios[0], "{ratios:?}");
}

/// A record measured through other sensors is the same axis run along the same schedule: only
/// what the sensors resolve differs (the suite's `--encoder-um` and `--noise-x`), and a slower
/// logger keeps a subset of the same samples (`--log-hz`).
#[test]
fn other_sensors_measure_the_same_axis_along_the_same_schedule() {
    let coarse = Sensors {
        encoder_m: 5e-6,
        force_noise: 0.01,
        pressure_noise_pa: 25e3,
        log_every: 1,
    };
    let (text, axis) = random_record(None, 101);
    let (text_c, axis_c) = random_record_with(None, 101, coarse);
    assert_eq!(axis_c.sensors, coarse);
    assert_eq!(
        format!(
            "{:?}",
            Axis {
                sensors: coarse,
                ..axis
            }
        ),
        format!("{axis_c:?}")
    );
    let (fine, coarse_rows) = (rows(&text), rows(&text_c));
    assert_eq!(fine.len(), coarse_rows.len());
    // the reference (column 3) is the schedule's, the same; the positions (column 1) are whole
    // counts of each encoder, and the fine one resolves what the coarse one cannot
    let counts = |r: &[Vec<f64>], step: f64| {
        r.iter()
            .all(|c| (c[1] / step - (c[1] / step).round()).abs() < 1e-3)
    };
    assert!(fine.iter().zip(&coarse_rows).all(|(a, b)| a[3] == b[3]));
    assert!(counts(&coarse_rows, 5e-6));
    assert!(counts(&fine, 1e-6) && !counts(&fine, 5e-6));
    // a slower logger (`--log-hz`) keeps every n-th sample of the same run, noise and all
    let (text_4, axis_4) = random_record_with(
        None,
        101,
        Sensors {
            log_every: 4,
            ..Sensors::default()
        },
    );
    let (rows_4, trace) = (rows(&text_4), &axis_4.dwell_trace.as_ref().unwrap().0);
    assert_eq!(rows_4.len(), fine.len().div_ceil(4));
    assert!(rows_4
        .iter()
        .zip(fine.iter().step_by(4))
        .all(|(a, b)| a == b));
    assert_eq!(trace.len(), rows_4.len());
}

/// A record read through a 5 um count is prepared with the position filter its first baseline
/// fits the better: on calibration records, the temperature axis at 50 Hz (its first baseline
/// errs 1.60 % there against 2.99 % at 100 Hz), the Stribeck one at 100 Hz (2.17 % against
/// 6.75 % at 50 Hz: its fast motion needs the bandwidth); each says so. A 1 um record is not
/// asked.
#[test]
fn a_coarse_count_is_read_through_the_filter_its_baseline_fits_better() {
    let coarse = Sensors {
        encoder_m: 5e-6,
        ..Sensors::default()
    };
    let prepared = |effect, seed, sensors| {
        let (text, _) = random_record_with(Some(effect), seed, sensors);
        let rec = Record::parse(&text, Path::new("axis.csv")).unwrap();
        diagnose::prepare(&rec, "axis.csv", &Options::default()).unwrap()
    };
    for (effect, seed, cutoff_hz) in [
        ("temperature_dependence", 1404, 50.0),
        ("stribeck_shape", 1503, 100.0),
    ] {
        let (p, protocol, first) = prepared(effect, seed, coarse);
        assert_eq!(protocol.position_cutoff_hz, cutoff_hz, "{effect} {seed}");
        assert!(first.is_some());
        let said = p.notes.iter().find(|n| n.contains("count is 5.00 um"));
        let said = said.unwrap_or_else(|| panic!("{:?}", p.notes));
        assert!(said.ends_with(&format!("uses {cutoff_hz:.0} Hz")), "{said}");
    }
    let (p, protocol, first) = prepared("temperature_dependence", 1404, Sensors::default());
    assert_eq!(protocol.position_cutoff_hz, 100.0);
    assert!(first.is_none() && !p.notes.iter().any(|n| n.contains("count is")));
}

/// A record logged at 250 Hz is read with the motion bandwidth a 1 kHz record gets: its
/// position filter is at 0.4 of the rate, 100 Hz (0.2 until session 32: 50 Hz). On held-out
/// effect-free record 500, a fast axis with an ideal force actuator, the generator's truth
/// driven by the measured motion (every moving sample alike) errs 1.75 % at 250 Hz against
/// 1.00 % at 1 kHz; through the 50 Hz filter it erred 15.8 %.
#[test]
fn a_slow_logger_keeps_the_motion_bandwidth() {
    let floor = |sensors| {
        let (text, axis) = random_record_with(None, 500, sensors);
        let rec = Record::parse(&text, Path::new("axis.csv")).unwrap();
        let p = Prepared::new(&rec, "axis.csv", Protocol::default()).unwrap();
        assert_eq!(p.position_cutoff_hz, 100.0);
        (truth_error_pct(&axis, &p), p.dt)
    };
    let (fast, dt_fast) = floor(Sensors::default());
    let (slow, dt_slow) = floor(Sensors {
        log_every: 4,
        ..Sensors::default()
    });
    assert!((dt_fast - 1e-3).abs() < 1e-9 && (dt_slow - 4e-3).abs() < 1e-9);
    println!("truth's error: {fast:.2} % at 1 kHz, {slow:.2} % at 250 Hz");
    assert!(fast < 1.5 && slow < 2.5 * fast, "{fast} {slow}");
}

#[test]
fn a_parameter_file_refuses_a_bad_position_shape() {
    let dir = tempfile::tempdir().unwrap();
    let base = "[lugre]\nbristle_stiffness_n_per_m = 3.9e9\nbristle_damping_n_s_per_m = 200.0\nviscous_coefficient_n_s_per_m = 48900.0\ncoulomb_force_n = 506.0\nstatic_force_n = 632.0\nstribeck_velocity_m_per_s = 0.005\n\n[axis]\nmoving_mass_kg = 200.0\n\n[effects.position_dependence]\ngradient_n_per_m = 10.0\ncenter_m = 0.0\n";
    for (extra, why) in [
        ("cosine_n = [1.0, 2.0]\n", "half_span_m"),
        ("half_span_m = 0.0\ncosine_n = [1.0]\n", "half_span_m"),
        (
            "half_span_m = 0.1\ncosine_n = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0, 12.0, 13.0, 14.0, 15.0, 16.0, 17.0]\n",
            "at most 16",
        ),
    ] {
        let path = dir.path().join("bad.toml");
        std::fs::write(&path, format!("{base}{extra}")).unwrap();
        let e = ParamFile::read(&path).unwrap_err().to_string();
        assert!(e.contains(why), "{extra}: {e}");
    }
    let path = dir.path().join("good.toml");
    std::fs::write(
        &path,
        format!("{base}half_span_m = 0.1\ncosine_n = [1.0, -2.0]\n"),
    )
    .unwrap();
    let (_, m) = ParamFile::read(&path).unwrap();
    assert_eq!(m.effects.position_dependence.unwrap().terms, 2);
    // a load dependence's series is written and read back the same (the file a diagnosis
    // writes with it)
    let mut l = lugre_servo::friction::effects::LoadDependence::power(2e-6, 150e5, 1.0);
    (l.half_span, l.terms, l.static_share) = (40e5, 3, 0.4);
    l.cosine[..3].copy_from_slice(&[12.5, -3.0, 0.75]);
    let mut with_load = m;
    with_load.effects.load_dependence = Some(l);
    let path = dir.path().join("load.toml");
    ParamFile::new(&with_load, 200.0).write(&path).unwrap();
    let (_, back) = ParamFile::read(&path).unwrap();
    assert_eq!(back.effects.load_dependence, Some(l));
}

/// The noise floor of a dwell record is the truth with its dwell effect: along the measured
/// motion, the generator's true model reads the record's own dwell clock and explains the
/// breakaway peaks, where the same model without the effect does not. (With the clock run on
/// the measured motion, every 1 um encoder count restarted it: the truth's peaks were the
/// effect-free model's, and the floor of dwell records that of a model without the effect:
/// on calibration seeds 1700..1709 the peaks' rms was 0.3..29 N against the record with the
/// record's clock, 3.6..89 N with the clock on the measured motion, 8.2..111 N without it.)
#[test]
fn the_truth_of_a_dwell_record_keeps_its_dwell_effect() {
    use generators::axis::Shape;
    use host_sim::diagnose::{breakaway::Breakaway, inverse::Prepared};
    for seed in [1701, 1704] {
        let (text, axis) = random_record(Some("dwell_stiction"), seed);
        let rec = Record::parse(&text, Path::new("axis.csv")).unwrap();
        let p = Prepared::new(&rec, "axis.csv", Default::default()).unwrap();
        assert_eq!(axis.dwell_trace.as_ref().map(|d| d.0.len()), Some(p.len()));
        let brk = Breakaway::find(&p);
        let peak_rms = |axis: &Axis| {
            let truth = p.filter(&generators::axis::truth_force(axis, &p));
            (brk.peak_rss(&truth) / brk.departures.len() as f64).sqrt()
        };
        let truth = peak_rms(&axis);
        let own_clock = peak_rms(&Axis {
            dwell_trace: None,
            ..axis.clone()
        });
        let without = peak_rms(&Axis {
            shape: Shape::None,
            ..axis.clone()
        });
        println!(
            "seed {seed}: {} departures, peak rms: truth {truth:.1} N, its clock on the measured motion {own_clock:.1} N, without the effect {without:.1} N",
            brk.departures.len()
        );
        assert!(brk.departures.len() >= 6, "{}", brk.departures.len());
        assert!(truth < 0.6 * without, "{truth} vs {without}");
        assert!(truth < 0.8 * own_clock, "{truth} vs {own_clock}");
    }
}

/// The force reading's noise, measured on the record (`Prepared::force_noise_n`, fourth
/// differences): on hydraulic axes the pressure transducers' noise through the two areas,
/// `sigma_p sqrt(A_a^2 + A_b^2)`, within 6 % (measured 0.99..1.04x on these 30 records; second
/// differences, `signal::force_noise`, read up to 3.09x on 552, the oil column's ringing leaking
/// in); on force-actuated axes no lower than the sensor's 0.2 % of full scale (1.04..2.1x: the
/// controller's force on the 1 um reading adds white force that no model driven by that reading
/// resolves).
#[test]
fn the_force_noise_is_measured_on_the_record() {
    use generators::axis::Actuator;
    let (mut hydraulic, mut force) = (0, 0);
    for seed in 550..580 {
        let (text, axis) = random_record(None, seed);
        let rec = Record::parse(&text, Path::new("axis.csv")).unwrap();
        let p = Prepared::new(&rec, "axis.csv", Protocol::default()).unwrap();
        let s = &axis.sensors;
        let truth = match axis.actuator {
            Actuator::Hydraulic => {
                let (aa, ab) = (axis.area_m2, axis.area_m2 * axis.area_ratio);
                hydraulic += 1;
                s.pressure_noise_pa * aa.hypot(ab)
            }
            Actuator::Force => {
                force += 1;
                s.force_noise * (2.0 * axis.static_n + 3.0 * axis.mass_kg)
            }
        };
        let ratio = p.force_noise_n / truth;
        println!(
            "seed {seed} {:?}: measured {:.3} N, sensor {truth:.3} N, ratio {ratio:.3}; in band {:.3} N",
            axis.actuator, p.force_noise_n, p.force_noise_in_band_n
        );
        match axis.actuator {
            Actuator::Hydraulic => assert!((ratio - 1.0).abs() < 0.06, "seed {seed}: {ratio}"),
            Actuator::Force => assert!(ratio > 0.97, "seed {seed}: {ratio}"),
        }
    }
    assert!(
        hydraulic > 0 && force > 0,
        "both actuators: {hydraulic} {force}"
    );
}

/// Family B ([`generators::axis::Family`]) changes the hidden effect's law and nothing else:
/// each effect gets its family-B shape, the same draw runs the same axis through the same
/// schedule with another force, and the record carries the new law: the
/// truth driven by the measured motion explains it better than the same axis without the
/// effect, and better than with the family-A shape of the same seed. The test command checks
/// the three effects whose family-B law is of another kind (an offset, a position step or pair,
/// a logarithmic dwell) and asymmetry; the other four are in the expensive suite.
#[test]
fn family_b_draws_other_laws_on_the_same_axes() {
    family_b_draws_other_laws(&[0, 1, 3, 7]);
}
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn family_b_draws_other_laws_for_the_other_effects() {
    family_b_draws_other_laws(&[2, 4, 5, 6]);
}

/// [`family_b_draws_other_laws_on_the_same_axes`] for the effects `EFFECTS[k]` (seed 3000 + k).
fn family_b_draws_other_laws(which: &[usize]) {
    use generators::axis::{
        random_record_of, record, Axes, ContactKind, DwellLaw, Family, Shape, EFFECTS,
    };
    use host_sim::diagnose::inverse::Prepared;
    let mut paired = 0;
    for &k in which {
        let (effect, seed) = (&EFFECTS[k], 3000 + k as u64);
        let of = |family| {
            random_record_of(
                Some(effect),
                seed,
                Sensors::default(),
                ContactKind::LuGre,
                family,
                Axes::Wide,
                DwellLaw::RestartAtStick,
            )
        };
        let ((_, axis_a), (text_b, axis_b)) = (of(Family::A), of(Family::B));
        let law = format!("{:?}", axis_b.shape);
        let expected = match *effect {
            "offset" => "Offset",
            "position_dependence" => "Position(",
            "dwell_stiction" => "DwellLog",
            _ => "B {",
        };
        assert!(
            law.contains(expected)
                && (law.starts_with("Position(") == (*effect == "position_dependence")),
            "{effect}: {law}"
        );
        if *effect == "position_dependence" {
            assert!(law.contains("Step") || law.contains("Pair"), "{law}");
        }
        let column = |t: &str, c: usize| -> Vec<f64> { rows(t).iter().map(|r| r[c]).collect() };
        // the same draw: family B replaces the shape, the schedule stays (a record whose
        // visibility is redrawn moves to the next attempt's axis in either family alone)
        let axis = Axis::random(Some(effect), seed);
        let other = Axis {
            shape: Shape::random_b(effect, &axis, seed),
            ..axis.clone()
        };
        let (same_a, same_b) = (record(&axis, seed).0, record(&other, seed).0);
        assert_eq!(
            column(&same_a, 3),
            column(&same_b, 3),
            "{effect}: the schedule"
        );
        assert_ne!(
            column(&same_a, 2),
            column(&same_b, 2),
            "{effect}: the force"
        );
        paired += usize::from(axis_a.mass_kg == axis_b.mass_kg);
        let rec = Record::parse(&text_b, Path::new("axis.csv")).unwrap();
        let p = Prepared::new(&rec, "axis.csv", Default::default()).unwrap();
        let truth = truth_error_pct(&axis_b, &p);
        let without = truth_error_pct(
            &Axis {
                shape: Shape::None,
                ..axis_b.clone()
            },
            &p,
        );
        let as_a = truth_error_pct(
            &Axis {
                shape: axis_a.shape,
                ..axis_b.clone()
            },
            &p,
        );
        println!("{effect} {seed}: {law}\n  truth {truth:.2} %, without the effect {without:.2} %, with family A's law {as_a:.2} %");
        assert!(
            truth.is_finite() && truth < 0.7 * without,
            "{effect}: {truth} vs {without}"
        );
        assert!(truth < as_a, "{effect}: {truth} vs {as_a}");
    }
    println!(
        "{paired} of {} records on the same axis in both families",
        which.len()
    );
}

/// The force read half a sample off the log where the baseline says so
/// (`diagnose::choose_force_reading`). The generator's force-actuated records log beside each
/// position the force of the period before it; on effect-free record 3353 (wide axes) read as
/// logged a viscous power is significant, which read half a sample later is gone, and the
/// diagnosis reads it so unasked and says so. A hydraulic record, whose force comes from
/// pressures sampled with the position (3333: read +0.5, the baseline errs 0.91x), is read as
/// logged. A skew the user gives is read as given.
#[test]
fn a_force_logged_half_a_sample_late_is_read_so_and_a_pressure_force_as_logged() {
    let run = |seed: u64, keep_force_reading: bool| {
        let opts = Options {
            keep_force_reading,
            ..Default::default()
        };
        diagnose_with(None, seed, opts)
    };
    let (chosen, axis) = run(3353, false);
    assert_eq!(axis.actuator, Actuator::Force);
    let (as_logged, _) = run(3353, true);
    read_later_where_the_log_names_viscous_power(&chosen, &as_logged, 0.75);
    let (hydraulic, axis) = run(3333, false);
    assert_eq!(axis.actuator, Actuator::Hydraulic);
    assert_eq!(
        hydraulic.prepared.force_skew_samples,
        0.0,
        "{}",
        report(&hydraulic)
    );
}

/// A skew that bent the baseline's nonlinear parameters is found by searching them at each
/// reading (`diagnose::choose_force_reading`, session 94). Effect-free record 4999 (issue's
/// axes, force-actuated): read as logged the baseline puts vs at 7.5 mm/s (true 2.1) and Fc at
/// 72 N (true 98), its linear refit read +0.5 errs 1.91 % against 1.93 %, and viscous power is
/// named; with vs and sigma0 searched at each reading, +0.5 errs a fifth of the log's and
/// nothing is named.
#[test]
fn a_skew_that_bent_the_baseline_is_found_by_searching_each_reading() {
    let (text, axis) = random_record_of(
        None,
        4999,
        Sensors::default(),
        ContactKind::LuGre,
        Family::A,
        Axes::Issue,
        DwellLaw::RestartAtStick,
    );
    assert_eq!(axis.actuator, Actuator::Force);
    let rec = Record::parse(&text, Path::new("axis.csv")).unwrap();
    let run = |keep_force_reading: bool| {
        let opts = Options {
            keep_force_reading,
            skip_final_ranking: true,
            ..Default::default()
        };
        diagnose::diagnose(&rec, "axis.csv", &opts).unwrap()
    };
    read_later_where_the_log_names_viscous_power(&run(false), &run(true), 0.25);
}

/// An effect-free force-actuated record whose force was logged half a sample late: read as the
/// diagnosis chose (`chosen`) the force is read +0.5 samples, it says so, and nothing is named;
/// read as logged (`as_logged`, `keep_force_reading`) viscous power is named; the chosen
/// reading's baseline errs under `max_ratio` times the logged one's.
fn read_later_where_the_log_names_viscous_power(
    chosen: &Diagnosis,
    as_logged: &Diagnosis,
    max_ratio: f64,
) {
    assert_eq!(
        chosen.prepared.force_skew_samples,
        0.5,
        "{}",
        report(chosen)
    );
    assert!(
        (chosen.prepared.notes.iter()).any(|n| n.contains("off the log")),
        "{:?}",
        chosen.prepared.notes
    );
    assert_eq!(
        first_significant(&chosen.stages[0].candidates),
        None,
        "{}",
        report(chosen)
    );
    assert_eq!(as_logged.prepared.force_skew_samples, 0.0);
    assert_eq!(
        first_significant(&as_logged.stages[0].candidates),
        Some("viscous_power"),
        "{}",
        report(as_logged)
    );
    assert!(chosen.stages[0].fit.rel_err_pct < max_ratio * as_logged.stages[0].fit.rel_err_pct);
}

/// A dwell term whose growth with the rest time the record does not show is dwell stiction
/// that every rest saturates, named where the model leaves more than the measurement accounts
/// for (session 92). Dwell record 35166 (issue's axes): the grid's best term errs 2.70 %, its
/// rest-independent twin 2.55 % against the baseline's 3.01 %; until session 92 a caution held
/// it. The twin is the term's fit, its time constant reported beyond the search range.
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn a_dwell_level_every_rest_saturates_is_named_beyond_the_measurement() {
    let d = diagnose_on_issue_axes("dwell_stiction", 35166);
    let stage = &d.stages[0];
    assert!(d.unexplained(stage).beyond_measurement(), "{}", report(&d));
    let dwell = dwell_candidate(stage);
    let evidence = dwell.dwell.as_ref().unwrap();
    assert!(!evidence.growth_shown, "{}", evidence.growth_dbic);
    assert!(dwell.saturated_note().is_some());
    let tau = &dwell.parameters[0];
    assert_eq!(tau.name, "time_constant_s");
    assert!(
        (tau.value - diagnose::breakaway::REST_INDEPENDENT_TAU_S).abs() < 1e-12
            && tau.at_search_edge,
        "{tau:?}"
    );
    assert!(dwell.caution.is_none(), "{:?}", dwell.caution);
    assert!(
        dwell.error_cut >= diagnose::DWELL_MIN_ERROR_CUT,
        "{}",
        report(&d)
    );
    assert_eq!(
        first_significant(&stage.candidates),
        Some("dwell_stiction"),
        "{}",
        report(&d)
    );
}

/// The same saturated level is held where the model leaves no more than the measurement
/// accounts for: effect-free record 138 (wide axes, force-actuated), whose rest-independent
/// level cuts half the baseline's error (0.50) where the baseline leaves 0.64x what the
/// measurement accounts for, its error below the true model's (1.94 % against 2.75 %).
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn a_saturated_dwell_level_within_the_measurement_is_held() {
    let (d, _) = diagnose(None, 138, &[]);
    let stage = &d.stages[0];
    assert!(!d.unexplained(stage).beyond_measurement(), "{}", report(&d));
    let dwell = dwell_candidate(stage);
    assert!(!dwell.dwell.as_ref().unwrap().growth_shown);
    let why = dwell.caution.as_deref().unwrap_or_default();
    assert!(
        why.contains("no more than the measurement accounts for"),
        "{why}"
    );
    assert!(!dwell.significant && dwell.saturated_note().is_none());
    assert_eq!(first_significant(&stage.candidates), None, "{}", report(&d));
}
