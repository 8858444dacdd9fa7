//! The parameter-file reader on any text: it refuses, or the model it returns passes the
//! core's physical check (what a controller may be given) and writes back to the same model.
#![no_main]

use host_sim::params_file::ParamFile;
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok((file, model)) = ParamFile::parse(text, Path::new("fuzz.toml")) else {
        return;
    };
    model
        .params
        .check_physical()
        .expect("an accepted file is physical");
    assert!(file.axis.moving_mass_kg.is_finite() && file.axis.moving_mass_kg > 0.0);
    let written = toml::to_string(&file).expect("serialises");
    let (_, again) =
        ParamFile::parse(&written, Path::new("again.toml")).expect("a written file reads back");
    assert_eq!(again, model);
});
