//! The CSV record reader on any bytes: it refuses or it returns a record that keeps the
//! format's promises (time strictly increasing, known columns finite and as long as `t`), and
//! that survives a write and a read unchanged.
#![no_main]

use host_sim::record::Record;
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(rec) = Record::parse(text, Path::new("fuzz.csv")) else {
        return;
    };
    let n = rec.len();
    assert!(n > 0);
    assert!(rec.t.windows(2).all(|w| w[1] > w[0]), "time not increasing");
    for col in [
        Some(&rec.x),
        Some(&rec.force),
        rec.v.as_ref(),
        rec.x_ref.as_ref(),
    ]
    .into_iter()
    .chain([rec.p_a.as_ref(), rec.p_b.as_ref(), rec.temp.as_ref()])
    .flatten()
    {
        assert_eq!(col.len(), n);
        assert!(col.iter().all(|v| v.is_finite()));
    }
    let mut out = Vec::new();
    rec.write_to(&mut out).expect("writing to memory");
    let again = Record::parse(
        std::str::from_utf8(&out).expect("utf-8"),
        Path::new("fuzz.csv"),
    )
    .expect("a written record reads back");
    assert_eq!(again.t, rec.t);
    assert_eq!(again.x, rec.x);
    assert_eq!(again.force, rec.force);
});
