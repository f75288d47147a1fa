#![no_main]
//! Fuzzes the STL reader (binary and ASCII): no input may panic or hang, and a mesh the reader accepts must
//! satisfy `PolygonMesh::validate`, with and without `keep_degenerate`.

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use surfkit::mesh::io::{parse, Format, ReadOptions};

fuzz_target!(|bytes: &[u8]| {
    for keep_degenerate in [false, true] {
        let options = ReadOptions { keep_degenerate };
        if let Ok(mesh) = parse(Path::new("fuzz.stl"), bytes, Format::Stl, &options) {
            if let Err(e) = mesh.validate() {
                panic!("the STL reader returned an invalid mesh: {e}");
            }
        }
    }
});
