//! The CSV format: lossless round trip and every malformed case refused with file, line and
//! column.

use host_sim::record::Record;
use std::path::Path;

fn parse(text: &str) -> Result<Record, String> {
    Record::parse(text, Path::new("m.csv")).map_err(|e| e.to_string())
}

#[test]
fn round_trip_is_lossless() {
    let rec = Record {
        meta: vec![("rig".into(), "bench 3".into())],
        t: vec![0.0, 0.001, 0.002],
        x: vec![0.1, 0.1000001, 1.0 / 3.0],
        force: vec![512.25, -3.0e-7, 6.02e23],
        v: Some(vec![0.0, 1e-4, -2.5]),
        p_a: Some(vec![1e5, 2e5, 3e5]),
        temp: Some(vec![40.0, 40.5, 41.0]),
        extra: vec![("true_friction".into(), vec![1.0, 2.0, 3.0])],
        ..Default::default()
    };
    let mut buf = Vec::new();
    rec.write_to(&mut buf).unwrap();
    let back = parse(std::str::from_utf8(&buf).unwrap()).unwrap();
    assert_eq!(back, rec);
}

#[test]
fn columns_in_any_order_and_extras_ignored_when_not_numeric() {
    let r = parse("# a=1\nforce,note,x,t\n1,hello,0.5,0\n2,world,0.6,0.001\n").unwrap();
    assert_eq!(r.t, vec![0.0, 0.001]);
    assert_eq!(r.x, vec![0.5, 0.6]);
    assert_eq!(r.force, vec![1.0, 2.0]);
    assert!(r.extra.is_empty());
    assert_eq!(r.meta_value("a"), Some("1"));
}

#[test]
fn malformed_inputs_name_file_line_and_column() {
    let cases = [
        ("", "m.csv:1: empty file"),
        ("# only=comment\n", "m.csv:1: empty file"),
        ("t,x\n0,1\n", "missing required column 'force'"),
        (
            "t,x,force,x\n0,1,2,3\n",
            "m.csv:1:4: column 'x': duplicated",
        ),
        (
            "t,x,force\n0,1,2\n0.001,abc,3\n",
            "m.csv:3:2: column 'x': 'abc' is not a number",
        ),
        (
            "t,x,force\n0,1,NaN\n",
            "m.csv:2:3: column 'force': value 'NaN' is not finite",
        ),
        (
            "t,x,force\n0,1,inf\n",
            "m.csv:2:3: column 'force': value 'inf' is not finite",
        ),
        (
            "t,x,force\n0,1,2\n0,1,2\n",
            "m.csv:3:1: column 't': time does not increase",
        ),
        (
            "t,x,force\n0.1,1,2\n0.05,1,2\n",
            "m.csv:3:1: column 't': time does not increase",
        ),
        (
            "t,x,force\n0,1,2\n0.001,1\n",
            "m.csv:3: row has 2 fields, the header has 3",
        ),
        ("t,x,force\n", "no data rows"),
        (
            "# c=1\n# d=2\nt,x,force\n0,1,2\n1,2,x\n",
            "m.csv:5:3: column 'force'",
        ),
    ];
    for (text, want) in cases {
        match parse(text) {
            Ok(_) => panic!("accepted {text:?}"),
            Err(e) => assert!(e.contains(want), "for {text:?}: got '{e}', want '{want}'"),
        }
    }
}

#[test]
fn unreadable_file_names_the_path() {
    let e = Record::read(Path::new("/nonexistent/dir/m.csv"))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("/nonexistent/dir/m.csv: cannot read"), "{e}");
}
