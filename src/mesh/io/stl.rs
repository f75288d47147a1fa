//! STL (stereolithography), binary and ASCII: the triangle soups of CAD exports, scanners
//! and 3D printing.
//!
//! A facet lists its corners' coordinates, not vertex indices, so the reader welds corners
//! whose coordinates are equal as the format's 32-bit floats into one vertex, numbered by
//! first appearance (as MeshLab's and OpenMesh's STL readers do): without that no two
//! facets would share an edge and every topological count would describe a soup. An ASCII
//! vertex keeps the digits it was written with (its first appearance's). Nothing else is
//! merged: corners a rounding apart stay apart, and the EAT shows the cracks they leave.
//! Facet normals are not kept (writers often leave them zero or stale; the winding gives
//! the orientation), nor the binary attribute word. ASCII `solid NAME` blocks become
//! objects.
//!
//! Binary or ASCII is decided the way robust readers do: a file whose length is exactly
//! what its facet count says (84 + 50 bytes a facet) is binary even when its 80-byte header
//! starts with `solid` (SolidWorks and others write such headers); otherwise a file that
//! starts with `solid` and holds no NUL byte is ASCII.

use std::io::Write;
use std::path::Path;

use foldhash::{HashMap, HashMapExt};

use super::text::{parse_f64, show, tokens, write_f64, Lines};
use super::ReadOptions;
use crate::error::{Error, Location, Result};
use crate::mesh::{FaceLabels, PolygonMesh, NO_LABEL};

const HEADER_BYTES: usize = 80;
/// Header, then the facet count (u32).
const DATA_START: usize = HEADER_BYTES + 4;
/// Normal and three corners (12 × f32), then the attribute word (u16).
const FACET_BYTES: usize = 50;
/// How many bytes after the header are looked at for a NUL, which no ASCII STL holds.
const ASCII_PROBE_BYTES: usize = 4096;

pub fn parse(path: &Path, bytes: &[u8], options: &ReadOptions) -> Result<PolygonMesh> {
    match binary_facet_count(bytes) {
        Some(count) if DATA_START + FACET_BYTES * count == bytes.len() => {
            parse_binary(path, bytes, count, options)
        }
        claimed if looks_ascii(bytes) => parse_ascii(path, bytes, options).map_err(|e| {
            // A binary file whose header starts with `solid` and whose count is wrong
            // fails as ASCII on its first binary byte: name the count too.
            match claimed {
                Some(n) if bytes.contains(&0) => size_mismatch(path, bytes.len(), n),
                _ => e,
            }
        }),
        Some(count) => Err(size_mismatch(path, bytes.len(), count)),
        None => Err(Error::parse(
            path,
            Location::File,
            format!(
                "not an STL file: it does not start with 'solid' (ASCII STL) and its {} bytes \
                 are fewer than a binary STL's {DATA_START}-byte header",
                bytes.len()
            ),
        )),
    }
}

/// The facet count of a binary STL header, if the file is long enough to hold one.
fn binary_facet_count(bytes: &[u8]) -> Option<usize> {
    let word = bytes.get(HEADER_BYTES..DATA_START)?;
    Some(u32::from_le_bytes(word.try_into().expect("four bytes")) as usize)
}

/// Starts with `solid` (after a UTF-8 byte-order mark and white space) and has no NUL byte
/// near the start.
fn looks_ascii(bytes: &[u8]) -> bool {
    let text = bytes
        .strip_prefix(b"\xEF\xBB\xBF")
        .unwrap_or(bytes)
        .trim_ascii_start();
    let starts_solid = text.len() >= 5 && text[..5].eq_ignore_ascii_case(b"solid");
    starts_solid && !bytes[..bytes.len().min(HEADER_BYTES + ASCII_PROBE_BYTES)].contains(&0)
}

fn size_mismatch(path: &Path, len: usize, count: usize) -> Error {
    let expected = DATA_START as u128 + FACET_BYTES as u128 * count as u128;
    let whole = len.saturating_sub(DATA_START) / FACET_BYTES;
    let what = if (len as u128) < expected {
        format!("the file is truncated: it ends inside facet {whole} (0-based)")
    } else {
        format!("{} bytes follow the last facet", len as u128 - expected)
    };
    Error::parse(
        path,
        Location::Header,
        format!(
            "binary STL: the header gives {count} facet{}, which take{} {expected} bytes, but \
             the file has {len}; {what}",
            if count == 1 { "" } else { "s" },
            if count == 1 { "s" } else { "" },
        ),
    )
}

/// Corners welded by their coordinates as `f32` (−0 and +0 alike), numbered by first
/// appearance.
struct Welder {
    index: HashMap<[u32; 3], u32>,
    positions: Vec<[f64; 3]>,
}

impl Welder {
    fn with_corners(corners: usize) -> Self {
        Welder {
            index: HashMap::with_capacity(corners / 4),
            positions: Vec::with_capacity(corners / 4),
        }
    }

    fn vertex(&mut self, p: [f64; 3]) -> std::result::Result<u32, String> {
        // x + 0.0 turns −0.0 into +0.0: the same point.
        let key = p.map(|c| (c as f32 + 0.0).to_bits());
        if let Some(&v) = self.index.get(&key) {
            return Ok(v);
        }
        let v = u32::try_from(self.positions.len())
            .ok()
            .filter(|&v| v < NO_LABEL)
            .ok_or("more distinct corners than a mesh can index (2³² − 1)")?;
        self.index.insert(key, v);
        self.positions.push(p);
        Ok(v)
    }
}

/// The problem with a facet's corners as welded, if any (`keep_degenerate` off).
fn degenerate(corners: &[u32], points: &[[f64; 3]]) -> Option<String> {
    if corners.len() < 3 {
        return Some(format!(
            "a facet needs at least 3 corners, this one has {}",
            corners.len()
        ));
    }
    let repeated = super::face_check::repeated_vertex(corners)?;
    let at: Vec<usize> = (0..corners.len())
        .filter(|&k| corners[k] == repeated)
        .map(|k| k + 1)
        .collect();
    let p = points[repeated as usize];
    Some(format!(
        "corners {} and {} are the same point ({}, {}, {}): a degenerate facet",
        at[0], at[1], p[0], p[1], p[2]
    ))
}

fn parse_binary(
    path: &Path,
    bytes: &[u8],
    count: usize,
    options: &ReadOptions,
) -> Result<PolygonMesh> {
    let mut welder = Welder::with_corners(3 * count);
    let mut mesh = PolygonMesh::default();
    mesh.face_offsets.reserve(count);
    mesh.face_indices.reserve(3 * count);
    let f32_at = |at: usize| {
        f64::from(f32::from_le_bytes(
            bytes[at..at + 4].try_into().expect("four bytes"),
        ))
    };
    for facet in 0..count {
        let start = DATA_START + FACET_BYTES * facet;
        let fail = |message: String| {
            Error::parse(
                path,
                Location::Element {
                    kind: "facet".into(),
                    index: facet,
                    byte_offset: start,
                },
                message,
            )
        };
        let mut corners = [0u32; 3];
        for (k, corner) in corners.iter_mut().enumerate() {
            // The normal's three floats come first.
            let at = start + 12 * (k + 1);
            let p = [f32_at(at), f32_at(at + 4), f32_at(at + 8)];
            if let Some(c) = p.iter().find(|c| !c.is_finite()) {
                return Err(fail(format!(
                    "corner {} has a coordinate that is not finite ({c})",
                    k + 1
                )));
            }
            *corner = welder.vertex(p).map_err(&fail)?;
        }
        if !options.keep_degenerate {
            if let Some(m) = degenerate(&corners, &welder.positions) {
                return Err(fail(m));
            }
        }
        mesh.push_face(&corners);
    }
    mesh.positions = welder.positions;
    Ok(mesh)
}

/// Where the ASCII reader is in the grammar
/// `solid NAME (facet … outer loop (vertex x y z)+ endloop endfacet)* endsolid NAME`.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Expect {
    Solid,
    FacetOrEndsolid,
    OuterLoop,
    VertexOrEndloop,
    Endfacet,
}

fn parse_ascii(path: &Path, bytes: &[u8], options: &ReadOptions) -> Result<PolygonMesh> {
    let mut welder = Welder::with_corners(bytes.len() / 40);
    let mut mesh = PolygonMesh::default();
    let mut objects = FaceLabels::default();
    let mut object = NO_LABEL;
    let mut expect = Expect::Solid;
    let mut corners: Vec<u32> = Vec::new();
    let mut facet_line = 0;
    let mut last_line = 0;
    for (n, line) in Lines::new(bytes) {
        let err = |message: String| Error::parse(path, Location::Line(n), message);
        let text = line.trim_ascii();
        let Some(keyword) = tokens(text).next() else {
            continue;
        };
        // A truncation is shown at the last line that holds something.
        last_line = n;
        let rest = text[keyword.len()..].trim_ascii();
        let is = |word: &str| keyword.eq_ignore_ascii_case(word.as_bytes());
        match expect {
            Expect::Solid if is("solid") => {
                let name = String::from_utf8_lossy(rest);
                object = if name.is_empty() {
                    NO_LABEL
                } else {
                    objects.intern(&name)
                };
                expect = Expect::FacetOrEndsolid;
            }
            Expect::FacetOrEndsolid if is("facet") => {
                facet_line = n;
                expect = Expect::OuterLoop;
            }
            Expect::FacetOrEndsolid if is("endsolid") => expect = Expect::Solid,
            Expect::OuterLoop if is("outer") && rest.eq_ignore_ascii_case(b"loop") => {
                expect = Expect::VertexOrEndloop;
            }
            Expect::VertexOrEndloop if is("vertex") => {
                let p = vertex_coordinates(rest).map_err(&err)?;
                corners.push(welder.vertex(p).map_err(&err)?);
            }
            Expect::VertexOrEndloop if is("endloop") => expect = Expect::Endfacet,
            Expect::Endfacet if is("endfacet") => {
                let facet = mesh.face_count();
                if !options.keep_degenerate {
                    if let Some(m) = degenerate(&corners, &welder.positions) {
                        return Err(Error::parse(
                            path,
                            Location::Line(facet_line),
                            format!("facet {facet}: {m}"),
                        ));
                    }
                }
                mesh.push_face(&corners);
                corners.clear();
                objects.of_face.push(object);
                expect = Expect::FacetOrEndsolid;
            }
            _ => {
                return Err(err(format!(
                    "expected {}, found {:?}",
                    expected(expect),
                    show(text)
                )))
            }
        }
    }
    if expect != Expect::Solid {
        return Err(Error::parse(
            path,
            Location::Line(last_line),
            format!(
                "the file ends inside a solid (expected {}): it is truncated",
                expected(expect)
            ),
        ));
    }
    mesh.positions = welder.positions;
    if !objects.names.is_empty() {
        mesh.objects = Some(objects);
    }
    Ok(mesh)
}

fn expected(state: Expect) -> &'static str {
    match state {
        Expect::Solid => "'solid' (or the end of the file)",
        Expect::FacetOrEndsolid => "'facet normal …' or 'endsolid'",
        Expect::OuterLoop => "'outer loop'",
        Expect::VertexOrEndloop => "'vertex x y z' or 'endloop'",
        Expect::Endfacet => "'endfacet'",
    }
}

/// The three finite numbers of a `vertex` record.
fn vertex_coordinates(rest: &[u8]) -> std::result::Result<[f64; 3], String> {
    // Counted first, then read: no allocation per vertex line.
    let count = tokens(rest).count();
    if count != 3 {
        return Err(format!(
            "a vertex needs 3 coordinates, this one has {count}"
        ));
    }
    let mut p = [0.0; 3];
    for (c, t) in p.iter_mut().zip(tokens(rest)) {
        *c = parse_f64(t)
            .ok_or_else(|| format!("vertex coordinate {:?} is not a number", show(t)))?;
        if !c.is_finite() {
            return Err(format!("vertex coordinate {c} is not finite"));
        }
        if (*c as f32).is_infinite() {
            return Err(format!(
                "vertex coordinate {c} is beyond the range of STL's 32-bit floats"
            ));
        }
    }
    Ok(p)
}

/// Why `mesh` cannot be written as STL, if it cannot: a face of fewer than 3 corners, a
/// coordinate beyond 32-bit floats' range, more triangles than the count word holds.
pub fn check(mesh: &PolygonMesh) -> Result<()> {
    let mut triangles: u64 = 0;
    for (f, face) in mesh.faces().enumerate() {
        if face.len() < 3 {
            return Err(Error::InvalidInput(format!(
                "face {f} has {} corners: STL holds triangles",
                face.len()
            )));
        }
        triangles += face.len() as u64 - 2;
    }
    if triangles > u64::from(u32::MAX) {
        return Err(Error::InvalidInput(format!(
            "{triangles} triangles: more than binary STL's count holds (2³² − 1)"
        )));
    }
    for (v, p) in mesh.positions.iter().enumerate() {
        if let Some(c) = p.iter().find(|c| (**c as f32).is_infinite()) {
            return Err(Error::InvalidInput(format!(
                "vertex {v}: coordinate {c} is beyond the range of STL's 32-bit floats"
            )));
        }
    }
    Ok(())
}

/// The triangles of `mesh` in face order, each polygon as a fan from its first corner.
fn triangles(mesh: &PolygonMesh) -> impl Iterator<Item = (usize, [u32; 3])> + '_ {
    mesh.faces().enumerate().flat_map(|(f, face)| {
        (1..face.len().saturating_sub(1)).map(move |k| (f, [face[0], face[k], face[k + 1]]))
    })
}

/// The unit normal of a triangle by its winding, zero when it has no area.
fn unit_normal(mesh: &PolygonMesh, t: [u32; 3]) -> [f64; 3] {
    let [a, b, c] = t.map(|v| mesh.positions[v as usize]);
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let w = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let n = [
        u[1] * w[2] - u[2] * w[1],
        u[2] * w[0] - u[0] * w[2],
        u[0] * w[1] - u[1] * w[0],
    ];
    let length = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if length > 0.0 && length.is_finite() {
        n.map(|x| x / length)
    } else {
        [0.0; 3]
    }
}

/// Binary STL: a header that does not start with `solid`, the count, the triangles with
/// their normals, coordinates rounded to `f32`. [`check`] first.
pub fn write_binary(out: &mut dyn Write, mesh: &PolygonMesh) -> std::io::Result<()> {
    let mut header = [b' '; HEADER_BYTES];
    let title = format!(
        "binary STL written by surfkit {}",
        env!("CARGO_PKG_VERSION")
    );
    header[..title.len()].copy_from_slice(title.as_bytes());
    out.write_all(&header)?;
    let count = triangles(mesh).count() as u32;
    out.write_all(&count.to_le_bytes())?;
    let mut record = [0u8; FACET_BYTES];
    for (_, t) in triangles(mesh) {
        let floats = unit_normal(mesh, t)
            .into_iter()
            .chain(t.iter().flat_map(|&v| mesh.positions[v as usize]));
        for (k, x) in floats.enumerate() {
            record[4 * k..4 * k + 4].copy_from_slice(&(x as f32).to_le_bytes());
        }
        out.write_all(&record)?;
    }
    Ok(())
}

/// ASCII STL, one `solid` per run of faces of one object, coordinates in the shortest form
/// that reads back to the same double. [`check`] first.
pub fn write_ascii(out: &mut dyn Write, mesh: &PolygonMesh) -> std::io::Result<()> {
    let object_of = |f: usize| mesh.objects.as_ref().and_then(|o| o.name_of(f));
    let mut open: Option<Option<&str>> = None;
    for (f, t) in triangles(mesh) {
        let name = object_of(f);
        if open != Some(name) {
            if let Some(previous) = open {
                writeln!(out, "endsolid {}", previous.unwrap_or(""))?;
            }
            writeln!(out, "solid {}", name.unwrap_or(""))?;
            open = Some(name);
        }
        let n = unit_normal(mesh, t);
        out.write_all(b"  facet normal")?;
        write_numbers(out, n)?;
        out.write_all(b"\n    outer loop\n")?;
        for v in t {
            out.write_all(b"      vertex")?;
            write_numbers(out, mesh.positions[v as usize])?;
            out.write_all(b"\n")?;
        }
        out.write_all(b"    endloop\n  endfacet\n")?;
    }
    match open {
        Some(name) => writeln!(out, "endsolid {}", name.unwrap_or("")),
        None => writeln!(out, "solid\nendsolid"),
    }
}

fn write_numbers(out: &mut dyn Write, p: [f64; 3]) -> std::io::Result<()> {
    for x in p {
        out.write_all(b" ")?;
        write_f64(out, x)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(bytes: &[u8]) -> Result<PolygonMesh> {
        parse(Path::new("t.stl"), bytes, &ReadOptions::default())
    }

    fn binary(header: &[u8], facets: &[[[f32; 3]; 3]]) -> Vec<u8> {
        let mut out = vec![b' '; HEADER_BYTES];
        out[..header.len()].copy_from_slice(header);
        out.extend((facets.len() as u32).to_le_bytes());
        for f in facets {
            out.extend([0u8; 12]);
            for c in f.iter().flatten() {
                out.extend(c.to_le_bytes());
            }
            out.extend([0u8; 2]);
        }
        out
    }

    const TETRAHEDRON: [[[f32; 3]; 3]; 4] = [
        [[0., 0., 0.], [0., 1., 0.], [1., 0., 0.]],
        [[0., 0., 0.], [1., 0., 0.], [0., 0., 1.]],
        [[0., 0., 0.], [0., 0., 1.], [0., 1., 0.]],
        [[1., 0., 0.], [0., 1., 0.], [0., 0., 1.]],
    ];

    #[test]
    fn binary_corners_are_welded_by_exact_coordinates_in_first_appearance_order() {
        let m = read(&binary(b"solid but binary", &TETRAHEDRON)).unwrap();
        assert_eq!(m.vertex_count(), 4);
        assert_eq!(m.face_count(), 4);
        let faces: Vec<Vec<u32>> = m.faces().map(<[u32]>::to_vec).collect();
        assert_eq!(
            faces,
            vec![vec![0, 1, 2], vec![0, 2, 3], vec![0, 3, 1], vec![2, 1, 3]]
        );
        // −0 is the point 0; one f32 ulp away is another point.
        let mut shifted = TETRAHEDRON;
        shifted[1][0] = [-0.0, 0.0, -0.0];
        shifted[3][2] = [0.0, 0.0, f32::from_bits(1.0f32.to_bits() + 1)];
        let m = read(&binary(b"", &shifted)).unwrap();
        assert_eq!(m.vertex_count(), 5);
    }

    #[test]
    fn ascii_solids_become_objects_and_errors_name_the_line() {
        let text = b"solid lid\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   \
            vertex 1 0 0\n   vertex 0 1 0\n  endloop\n endfacet\nendsolid lid\nSOLID base\n \
            FACET NORMAL 0 0 0\n OUTER LOOP\n VERTEX 1.00000001 0 0\n VERTEX 0 0 0\n VERTEX 0 -1 0\n \
            ENDLOOP\n ENDFACET\nENDSOLID\n";
        let with_bom = [&b"\xEF\xBB\xBF"[..], text].concat();
        assert_eq!(read(&with_bom).unwrap().face_count(), 2);
        let m = read(text).unwrap();
        // 1.00000001 is 1 as a 32-bit float: welded, with the first appearance's digits.
        assert_eq!((m.vertex_count(), m.face_count()), (4, 2));
        assert_eq!(m.positions[1], [1.0, 0.0, 0.0]);
        let objects = m.objects.as_ref().unwrap();
        assert_eq!(
            (objects.name_of(0), objects.name_of(1)),
            (Some("lid"), Some("base"))
        );
        let endloop = text.windows(7).rposition(|w| w == b"ENDLOOP").unwrap();
        let e = read(&text[..endloop]).unwrap_err().to_string();
        assert!(e.contains("line 15: the file ends inside a solid"), "{e}");
        assert!(e.contains("truncated"), "{e}");
        let bad = String::from_utf8_lossy(text).replace("vertex 1 0 0", "vertex 1 zero 0");
        let e = read(bad.as_bytes()).unwrap_err().to_string();
        assert!(e.contains("line 5") && e.contains("\"zero\""), "{e}");
        for (record, count) in [("vertex 1 0", 2), ("vertex 1 0 0 0", 4)] {
            let bad = String::from_utf8_lossy(text).replace("vertex 1 0 0", record);
            let e = read(bad.as_bytes()).unwrap_err().to_string();
            let message = format!("line 5: a vertex needs 3 coordinates, this one has {count}");
            assert!(e.contains(&message), "{e}");
        }
    }

    #[test]
    fn a_wrong_binary_count_is_named_with_both_sizes() {
        let mut bytes = binary(b"solid x", &TETRAHEDRON);
        bytes.truncate(bytes.len() - 60);
        let e = read(&bytes).unwrap_err().to_string();
        assert!(
            e.contains("header gives 4 facets, which take 284 bytes, but the file has 224"),
            "{e}"
        );
        assert!(e.contains("ends inside facet 2"), "{e}");
        let e = read(b"\x01\x02junk").unwrap_err().to_string();
        assert!(e.contains("not an STL file"), "{e}");
    }

    #[test]
    fn degenerate_facets_are_refused_or_kept_as_asked() {
        let mut facets = TETRAHEDRON.to_vec();
        facets.push([[0., 0., 0.], [1., 0., 0.], [0., 0., 0.]]);
        let bytes = binary(b"", &facets);
        let e = read(&bytes).unwrap_err().to_string();
        assert!(
            e.contains("facet 4 (byte 284)") && e.contains("corners 1 and 3"),
            "{e}"
        );
        let keep = ReadOptions {
            keep_degenerate: true,
        };
        let m = parse(Path::new("t.stl"), &bytes, &keep).unwrap();
        assert_eq!(m.face_count(), 5);
    }

    #[test]
    fn polygons_are_written_as_fans_and_read_back_welded() {
        let quad = PolygonMesh::from_polygons(
            vec![[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]],
            &[[0u32, 1, 2, 3]],
        );
        for ascii in [false, true] {
            let mut out = Vec::new();
            if ascii {
                write_ascii(&mut out, &quad).unwrap();
            } else {
                write_binary(&mut out, &quad).unwrap();
                assert!(!out.starts_with(b"solid"));
            }
            let m = read(&out).unwrap();
            let faces: Vec<Vec<u32>> = m.faces().map(<[u32]>::to_vec).collect();
            assert_eq!(faces, vec![vec![0, 1, 2], vec![0, 2, 3]]);
            assert_eq!(m.positions, quad.positions);
        }
    }
}
