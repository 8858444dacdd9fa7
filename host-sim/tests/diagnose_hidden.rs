//! Hidden effects: a simulated record with one effect switched on (realistic sensors), the
//! diagnosis not told which. It must name that effect first and significant (the first
//! significant candidate; one ranked above it only where the parsimony between nested effects
//! sets the larger effect aside, as for an offset inside an asymmetry), adding it must
//! cut the error at least in half for the strong cases and bring it within 1.2x of the noise
//! floor (the true model driven by the measured motion through the same pipeline). A record
//! without an extra effect must yield no significant candidate.
//!
//! The test command diagnoses one record per effect (seed 1 at full strength) and one without;
//! the rest of the grid (a second seed, 0.4 of the strength, two more effect-free records) is
//! the expensive suite, `cargo test --workspace -- --ignored`, which CI runs.

use host_sim::diagnose::{self, inverse::AxisModel, Options};
use host_sim::plant::{PlantConfig, SensorConfig};
use host_sim::scenarios;

const DURATION_S: f64 = 60.0;

struct Outcome {
    /// The first significant candidate, or the first ranked where none is.
    first: String,
    significant: bool,
    /// Every candidate ranked above `first` was set aside as containing it (the parsimony
    /// between nested effects, `diagnose::prefer_nested`).
    set_aside_above: bool,
    base: f64,
    added: f64,
    floor: f64,
    /// An effect other than the hidden one was called significant.
    other_significant: bool,
}

fn run(effect: Option<&str>, strength: f64, seed: u64) -> Outcome {
    let mut cfg = PlantConfig::default();
    if let Some(e) = effect {
        scenarios::with_effect(&mut cfg, e, strength).unwrap();
    }
    let rec = scenarios::diagnosis_run(&cfg, SensorConfig::realistic(seed), DURATION_S);
    let truth = AxisModel {
        mass_kg: cfg.cylinder.moving_mass_kg,
        friction: cfg.friction,
    };
    let opts = Options {
        truth: Some(truth),
        add: effect.map(|e| vec![e.to_string()]).unwrap_or_default(),
        // only the error with the effect added is checked, not what would come next
        skip_final_ranking: true,
        ..Default::default()
    };
    let d = diagnose::diagnose(&rec, "hidden.csv", &opts).unwrap();
    let cands = &d.stages[0].candidates;
    // the diagnosis's answer: the first significant candidate (the first ranked if none is)
    let first = cands.iter().find(|c| c.significant).unwrap_or(&cands[0]);
    // candidates ranked above it are set aside only by the parsimony between nested effects
    let set_aside_for = |name: &str| {
        cands.iter().take_while(|c| c.kind != first.kind).all(|c| {
            c.caution
                .as_deref()
                .is_some_and(|w| w.contains(&format!("contains {name}")))
        })
    };
    let o = Outcome {
        first: first.kind.name().to_string(),
        significant: first.significant,
        set_aside_above: set_aside_for(first.kind.name()),
        base: d.stages[0].fit.rel_err_pct,
        added: d.stages[d.stages.len() - 1].fit.rel_err_pct,
        floor: d.noise_floor_pct.unwrap(),
        other_significant: d.stages[0]
            .candidates
            .iter()
            .any(|c| c.significant && Some(c.kind.name()) != effect),
    };
    println!(
        "{:<23} strength {strength} seed {seed}: first {} ({}), {:.2} % -> {:.2} %, floor {:.2} %",
        effect.unwrap_or("none"),
        o.first,
        if o.significant {
            "significant"
        } else {
            "not significant"
        },
        o.base,
        o.added,
        o.floor
    );
    o
}

/// The record the test command diagnoses for each effect: seed 1 at full strength.
const FIRST: [(u64, f64); 1] = [(1, 1.0)];
/// The rest of the grid, for the expensive suite (`cargo test --workspace -- --ignored`): the
/// second seed, and both seeds at 0.4 of the strength.
const REST: [(u64, f64); 3] = [(1, 0.4), (2, 1.0), (2, 0.4)];

fn check(effect: &str, cases: &[(u64, f64)]) {
    for &(seed, strength) in cases {
        let o = run(Some(effect), strength, seed);
        // An effect is visible when the plain model cannot come within 1.2x the noise floor
        // (the yardstick). A visible effect must be ranked first and called
        // significant; one that leaves the baseline at the floor (stribeck_shape x0.4 on
        // Table 2: 0.38 % against 0.38 %) is below what the calibrated rule reports, and
        // no other effect may be called in its place. (Its rank among insignificant
        // candidates carries nothing: since the dwell term chooses its renewal distance,
        // dwell_stiction ranks first there, 0.38 % -> 0.34 %, not significant.)
        if o.base > 1.2 * o.floor {
            assert_eq!(
                o.first, effect,
                "seed {seed} strength {strength}: named {} first",
                o.first
            );
            assert!(
                o.set_aside_above,
                "seed {seed} strength {strength}: an effect ranked above {effect} was not \
                 set aside as containing it"
            );
            assert!(
                o.significant,
                "seed {seed} strength {strength}: visible {effect} not significant"
            );
        } else {
            assert!(
                !o.other_significant,
                "seed {seed} strength {strength}: another effect called significant"
            );
        }
        if strength >= 1.0 {
            if o.base >= 2.0 * o.floor {
                assert!(
                    o.added <= 0.5 * o.base,
                    "strong {effect}: {} % -> {} %",
                    o.base,
                    o.added
                );
            } else {
                // the effect lifts the error less than the noise floor itself (stribeck_shape
                // on Table 2: a 126 N hump beside 48 900 N s/m of viscous friction): halving
                // the total is impossible for any model, so the excess must halve
                let (before, after) = (o.base - o.floor, o.added - o.floor);
                assert!(
                    after <= 0.5 * before,
                    "strong {effect}: excess {before} % -> {after} %"
                );
            }
        }
        assert!(
            o.added <= 1.2 * o.floor,
            "{effect} s{seed} x{strength}: {} % vs floor {} %",
            o.added,
            o.floor
        );
    }
}

/// Two tests per effect: the test command's record ([`FIRST`]) and the rest of the grid
/// ([`REST`], ignored unless asked for: `cargo test --workspace -- --ignored`, which CI runs).
macro_rules! finds {
    ($($first:ident, $rest:ident: $effect:literal;)*) => {$(
        #[test]
        fn $first() {
            check($effect, &FIRST);
        }
        #[test]
        #[ignore = "expensive suite: cargo test --workspace -- --ignored"]
        fn $rest() {
            check($effect, &REST);
        }
    )*};
}

finds! {
    finds_asymmetry, finds_asymmetry_on_every_seed_and_strength: "asymmetry";
    finds_offset, finds_offset_on_every_seed_and_strength: "offset";
    finds_load_dependence, finds_load_dependence_on_every_seed_and_strength: "load_dependence";
    finds_position_dependence, finds_position_dependence_on_every_seed_and_strength:
        "position_dependence";
    finds_temperature_dependence, finds_temperature_dependence_on_every_seed_and_strength:
        "temperature_dependence";
    finds_stribeck_shape, finds_stribeck_shape_on_every_seed_and_strength: "stribeck_shape";
    finds_viscous_power, finds_viscous_power_on_every_seed_and_strength: "viscous_power";
    finds_dwell_stiction, finds_dwell_stiction_on_every_seed_and_strength: "dwell_stiction";
}

#[test]
fn invents_nothing_without_an_extra_effect() {
    invents_nothing(&[1]);
}
// Seed 2 was a known false positive (stribeck_shape at dBIC 14.9) until the significance rule was
// calibrated on effect-free independent records (diagnose::MIN_ERROR_CUT).
#[test]
#[ignore = "expensive suite: cargo test --workspace -- --ignored"]
fn invents_nothing_on_more_seeds() {
    invents_nothing(&[2, 3]);
}

fn invents_nothing(seeds: &[u64]) {
    for &seed in seeds {
        let mut cfg = PlantConfig::default();
        cfg.thermal.initial_c = 40.0;
        let rec = scenarios::diagnosis_run(&cfg, SensorConfig::realistic(seed), DURATION_S);
        let d = diagnose::diagnose(&rec, "plain.csv", &Options::default()).unwrap();
        let sig: Vec<&str> = d.stages[0]
            .candidates
            .iter()
            .filter(|c| c.significant)
            .map(|c| c.kind.name())
            .collect();
        assert!(sig.is_empty(), "seed {seed}: invented {sig:?}");
    }
}
