//! Real data: the EMPS benchmark (data/emps, public measurements of an electro-mechanical
//! positioning axis whose ball screw makes friction direction-dependent).

use host_sim::diagnose::{self, Options};
use host_sim::record::Record;
use std::path::Path;

fn emps(name: &str) -> Record {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../data/emps")
        .join(name);
    Record::read(&path).unwrap()
}

#[test]
fn asymmetry_comes_first_and_brings_the_error_below_3p2_percent() {
    let est = emps("emps_estimation.csv");
    let opts = Options {
        add: vec!["asymmetry".into()],
        ..Default::default()
    };
    let d = diagnose::diagnose(&est, "emps_estimation.csv", &opts).unwrap();
    let base = &d.stages[0];
    assert_eq!(base.candidates[0].kind.name(), "asymmetry");
    assert!(base.candidates[0].significant);
    let after = d.stages[1].fit.rel_err_pct;
    let all = d.stages[1].fit.rel_err_all_pct;
    let pulses = emps("emps_validation_pulses.csv");
    let cross = diagnose::validate(
        d.model(),
        &pulses,
        "emps_validation_pulses.csv",
        opts.protocol,
    )
    .unwrap();
    println!(
        "EMPS: symmetric {:.2} %, + asymmetry {after:.2} % (all samples {all:.2} %), cross-test on pulses {cross:.2} %",
        base.fit.rel_err_pct
    );
    // published: 3.11 % (asymmetric), cross-test 5.98 % (symmetric), 5.39 % (asymmetric re-run)
    assert!(after <= 3.2, "estimation error {after} %");
    assert!(all <= 3.2, "estimation error over all samples {all} %");
    assert!(cross < 5.39, "cross-test {cross} %");
    // the identified mass matches the benchmark's IDIM-LS value (95.1 kg) within 1 %
    assert!(
        (d.model().mass_kg - 95.13).abs() < 0.95,
        "M = {}",
        d.model().mass_kg
    );
}
