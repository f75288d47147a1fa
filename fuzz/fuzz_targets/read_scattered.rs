#![no_main]
//! Fuzzes the readers of `fit`/`fill`'s scattered data: CSV `u,v,x,y,z`, shape points
//! `u,v`, and a mesh read as a height field or through its UVs. No input may panic; accepted
//! data must be finite, with one parameter pair per point.

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use surfkit::fit::data::{from_mesh, parse_csv, parse_uv_points};
use surfkit::mesh::io::{parse, Format, ReadOptions};

fuzz_target!(|bytes: &[u8]| {
    let text = String::from_utf8_lossy(bytes);
    if let Ok(d) = parse_csv(Path::new("fuzz.csv"), &text) {
        assert_eq!(d.params.len(), d.points.len());
        assert!(d.params.iter().flatten().all(|x| x.is_finite()));
        assert!(d.points.iter().flatten().all(|x| x.is_finite()));
    }
    if let Ok(points) = parse_uv_points(Path::new("fuzz.csv"), &text) {
        assert!(!points.is_empty());
    }
    if let Ok(mesh) = parse(Path::new("fuzz.obj"), bytes, Format::Obj, &ReadOptions::default()) {
        if let Ok(d) = from_mesh(&mesh) {
            assert_eq!(d.params.len(), d.points.len());
            assert!(d.params.iter().flatten().all(|x| x.is_finite()));
        }
    }
});
