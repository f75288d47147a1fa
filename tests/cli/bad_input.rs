//! Bad input: every file in `fixtures/bad/` (see its README) is refused with an error that
//! names the file, the line (text) or element and byte offset (binary), and the problem —
//! never a panic. Degenerate faces are kept when `keep_degenerate` asks for it.

use std::path::{Path, PathBuf};

use surfkit::error::Location;
use surfkit::mesh::io::{read, read_with, ReadOptions};
use surfkit::Error;

fn bad(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures/bad")
        .join(name)
}

/// The binary fixtures' layout (see `fixtures/bad/make_binary.py`): a 213-byte header,
/// 3 float vertices of 12 bytes, then faces of `uchar` count + `int` corners.
const HEADER: usize = 213;
const VERTEX: usize = 12;
const TRIANGLE: usize = 13;
/// Binary STL: an 80-byte header and the facet count, then 50 bytes a facet.
const STL_HEADER: usize = 84;
const STL_FACET: usize = 50;

fn element(kind: &str, index: usize, byte_offset: usize) -> Location {
    Location::Element {
        kind: kind.into(),
        index,
        byte_offset,
    }
}

/// `(file, where, what)`: reading the file fails at `where` with a message containing `what`.
fn cases() -> Vec<(&'static str, Location, &'static str)> {
    use Location::{File, Line};
    vec![
        // OBJ
        (
            "obj_index_out_of_range.obj",
            Line(5),
            "vertex index 4 is out of range: the file has 3 vertices (valid: 1 to 3)",
        ),
        (
            "obj_relative_index_before_first.obj",
            Line(5),
            "relative vertex index -4 reaches before the first vertex (3 read so far)",
        ),
        (
            "obj_index_zero.obj",
            Line(5),
            "vertex index 0: OBJ indices start at 1",
        ),
        (
            "obj_face_two_vertices.obj",
            Line(5),
            "a face needs at least 3 vertices, this one has 2",
        ),
        (
            "obj_repeated_vertex.obj",
            Line(6),
            "vertex index 2 is repeated in the face",
        ),
        (
            "obj_nan.obj",
            Line(3),
            "vertex coordinate NaN is not finite",
        ),
        (
            "obj_inf.obj",
            Line(4),
            "vertex coordinate -inf is not finite",
        ),
        (
            "obj_non_utf8.obj",
            Line(3),
            "not valid UTF-8 text: byte 0xff at column 8",
        ),
        ("obj_empty.obj", File, "the file is empty"),
        (
            "whitespace_only.obj",
            File,
            "the file is empty (it holds only whitespace)",
        ),
        // PLY, ASCII (9 header lines: vertices on lines 10-12, faces from line 13)
        (
            "ply_ascii_index_out_of_range.ply",
            Line(13),
            "face 0: vertex index 3 is out of range: the file has 3 vertices (valid: 0 to 2)",
        ),
        (
            "ply_ascii_negative_index.ply",
            Line(13),
            "face 0: vertex index -1 is negative: the file has 3 vertices (valid: 0 to 2)",
        ),
        (
            "ply_ascii_face_two_vertices.ply",
            Line(13),
            "face 0: a face needs at least 3 vertices, this one has 2",
        ),
        (
            "ply_ascii_nan.ply",
            Line(11),
            "vertex 1: coordinates [1.0, NaN, 0.0] are not finite",
        ),
        (
            "ply_ascii_inf.ply",
            Line(12),
            "vertex 2: coordinates [inf, 1.0, 0.0] are not finite",
        ),
        (
            "ply_ascii_more_faces_than_declared.ply",
            Line(14),
            "data after the last element the header declares (\"3 2 1 0\"): the header's counts are wrong",
        ),
        (
            "ply_ascii_fewer_faces_than_declared.ply",
            Line(13),
            "face 1: the file ends after 1 of the 2 face elements the header declares",
        ),
        ("ply_empty.ply", File, "the file is empty"),
        (
            "ply_no_end_header.ply",
            Line(9),
            "data \"0\" in the header: the end_header line is missing",
        ),
        (
            "ply_unknown_property_type.ply",
            Line(6),
            "unknown property type \"float128\"",
        ),
        // PLY, binary little endian
        (
            "ply_bin_index_out_of_range.ply",
            element("face", 0, HEADER + 3 * VERTEX),
            "vertex index 5 is out of range: the file has 3 vertices (valid: 0 to 2)",
        ),
        (
            "ply_bin_negative_index.ply",
            element("face", 0, HEADER + 3 * VERTEX),
            "vertex index -1 is negative: the file has 3 vertices (valid: 0 to 2)",
        ),
        (
            "ply_bin_face_two_vertices.ply",
            element("face", 1, HEADER + 3 * VERTEX + TRIANGLE),
            "a face needs at least 3 vertices, this one has 2",
        ),
        (
            "ply_bin_nan.ply",
            element("vertex", 1, HEADER + VERTEX),
            "coordinates [1.0, NaN, 0.0] are not finite",
        ),
        (
            "ply_bin_inf.ply",
            element("vertex", 2, HEADER + 2 * VERTEX),
            "coordinates [0.0, 1.0, inf] are not finite",
        ),
        (
            "ply_bin_truncated_in_vertices.ply",
            element("vertex", 2, HEADER + 2 * VERTEX),
            "the file ends inside this element",
        ),
        (
            "ply_bin_truncated_in_faces.ply",
            element("face", 1, HEADER + 3 * VERTEX + TRIANGLE),
            "the file ends inside this element",
        ),
        (
            "ply_bin_trailing_bytes.ply",
            element("end of data", 0, HEADER + 3 * VERTEX + TRIANGLE),
            "5 bytes after the last element the header declares: the header's counts are wrong",
        ),
        // PLY, binary big endian (the header is 3 bytes shorter: "big" for "little")
        (
            "ply_bin_be_index_out_of_range.ply",
            element("face", 0, HEADER - 3 + 3 * VERTEX),
            "vertex index 7 is out of range: the file has 3 vertices (valid: 0 to 2)",
        ),
        // OFF (header on line 1, counts on line 2, vertices from line 3)
        (
            "off_index_out_of_range.off",
            Line(6),
            "face 0: vertex index 3 is out of range: the file has 3 vertices (valid: 0 to 2)",
        ),
        (
            "off_negative_index.off",
            Line(6),
            "face 0: vertex index -1 is negative: the file has 3 vertices (valid: 0 to 2)",
        ),
        (
            "off_face_two_vertices.off",
            Line(6),
            "face 0: a face needs at least 3 vertices, this one has 2",
        ),
        (
            "off_repeated_vertex.off",
            Line(7),
            "face 0: vertex index 1 is repeated in the face",
        ),
        ("off_nan.off", Line(4), "vertex 1: NaN is not a finite number"),
        ("off_inf.off", Line(5), "vertex 2: -inf is not a finite number"),
        (
            "off_fewer_vertices_than_declared.off",
            Line(6),
            "the file ends after 0 of the 1 faces the header declares: line 2 declares 4 \
             vertices and 1 faces, the file has 4 data lines after it",
        ),
        ("off_empty.off", File, "the file is empty"),
        (
            "off_wrong_keyword.off",
            Line(2),
            "not an OFF file: expected OFF, COFF, NOFF or STOFF, found \"MESH\"",
        ),
        // STL
        ("stl_ascii_nan.stl", Line(5), "vertex coordinate NaN is not finite"),
        (
            "stl_ascii_truncated.stl",
            Line(6),
            "the file ends inside a solid (expected 'vertex x y z' or 'endloop'): it is truncated",
        ),
        (
            "stl_ascii_repeated_corner.stl",
            Line(2),
            "facet 0: corners 1 and 3 are the same point (0, 0, 0): a degenerate facet",
        ),
        (
            "stl_ascii_bad_keyword.stl",
            Line(3),
            "expected 'outer loop', found \"outerloop\"",
        ),
        (
            "stl_bin_truncated.stl",
            Location::Header,
            "binary STL: the header gives 2 facets, which take 184 bytes, but the file has \
             154; the file is truncated: it ends inside facet 1 (0-based)",
        ),
        (
            "stl_bin_nan.stl",
            element("facet", 1, STL_HEADER + STL_FACET),
            "corner 2 has a coordinate that is not finite (NaN)",
        ),
        (
            "stl_bin_trailing_bytes.stl",
            Location::Header,
            "the header gives 1 facet, which takes 134 bytes, but the file has 139; 5 bytes \
             follow the last facet",
        ),
    ]
}

fn check(name: &str, expected: &Location, phrase: &str, options: &ReadOptions) {
    let path = bad(name);
    let err = match read_with(&path, options) {
        Ok(m) => panic!(
            "{name}: read succeeded ({} vertices, {} faces)",
            m.vertex_count(),
            m.face_count()
        ),
        Err(e) => e,
    };
    let shown = err.to_string();
    match &err {
        Error::Parse {
            path: p,
            location,
            message,
        } => {
            assert_eq!(p, &path, "{name}: path in {shown}");
            assert_eq!(location, expected, "{name}: location in {shown}");
            assert!(
                message.contains(phrase),
                "{name}: message {message:?} lacks {phrase:?}"
            );
        }
        other => panic!("{name}: expected a parse error, got {other:?}"),
    }
    // (a) the file, (b) the line or element, (c) the problem, in what the user sees.
    let place = match expected {
        Location::Line(n) => format!(": line {n}: "),
        Location::Element {
            kind,
            index,
            byte_offset,
        } => format!(": {kind} {index} (byte {byte_offset}): "),
        Location::File => ": file: ".to_string(),
        Location::Header => ": header: ".to_string(),
    };
    assert!(
        shown.starts_with(&format!("{}{place}", path.display())),
        "{name}: {shown:?} does not start with the path and {place:?}"
    );
    assert!(shown.contains(phrase), "{name}: {shown:?}");
}

#[test]
fn each_bad_file_names_file_place_and_problem() {
    for (name, location, phrase) in cases() {
        check(name, &location, phrase, &ReadOptions::default());
    }
}

/// Files refused only because a face is degenerate.
const DEGENERATE: [(&str, &[&[u32]]); 7] = [
    ("obj_face_two_vertices.obj", &[&[0, 1]]),
    ("obj_repeated_vertex.obj", &[&[0, 1, 1, 3]]),
    ("ply_ascii_face_two_vertices.ply", &[&[0, 1]]),
    ("ply_bin_face_two_vertices.ply", &[&[0, 1, 2], &[0, 1]]),
    ("off_face_two_vertices.off", &[&[0, 1]]),
    ("off_repeated_vertex.off", &[&[0, 1, 1, 3]]),
    ("stl_ascii_repeated_corner.stl", &[&[0, 1, 0]]),
];

#[test]
fn keep_degenerate_keeps_the_degenerate_faces() {
    let keep = ReadOptions {
        keep_degenerate: true,
    };
    for (name, faces) in DEGENERATE {
        let mesh = read_with(&bad(name), &keep).unwrap_or_else(|e| panic!("{name}: {e}"));
        let got: Vec<&[u32]> = mesh.faces().collect();
        assert_eq!(got, faces, "{name}");
        mesh.validate().unwrap();
    }
}

#[test]
fn every_other_case_fails_the_same_way_with_keep_degenerate() {
    let keep = ReadOptions {
        keep_degenerate: true,
    };
    for (name, location, phrase) in cases() {
        if !DEGENERATE.iter().any(|(d, _)| *d == name) {
            check(name, &location, phrase, &keep);
        }
    }
}

#[test]
fn unknown_extension_names_file_and_extension() {
    let path = bad("mesh.3mf");
    let err = read(&path).unwrap_err();
    match &err {
        Error::UnknownFormat { path: p, extension } => {
            assert_eq!(p, &path);
            assert_eq!(extension, "3mf");
        }
        other => panic!("expected UnknownFormat, got {other:?}"),
    }
    assert_eq!(
        err.to_string(),
        format!(
            "{}: unknown mesh format (extension \"3mf\"); surfkit reads and writes .obj, .ply, .off \
             and .stl",
            path.display()
        )
    );
}

/// Every file in the folder has a case above, so a new fixture cannot go unchecked.
#[test]
fn every_fixture_is_checked() {
    let known: Vec<&str> = cases().iter().map(|c| c.0).collect();
    for entry in std::fs::read_dir(bad("")).unwrap() {
        let name = entry.unwrap().file_name().into_string().unwrap();
        if name == "README.md" || name == "make_binary.py" || name == "mesh.3mf" {
            continue;
        }
        assert!(known.contains(&name.as_str()), "{name} has no case");
    }
}
