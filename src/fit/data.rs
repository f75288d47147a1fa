//! Reading users' scattered data: CSV lines `u,v,x,y,z` (fields split by commas, semicolons
//! or tabs, or else by spaces as in `.xyz` text; a first line without a number is a header;
//! `#` starts a comment), or a mesh — with texture coordinates as (u, v), or else as a
//! height field with (u, v) = (x, y).

use std::path::Path;

use std::collections::HashSet;

use crate::error::{Error, Location, Result};
use crate::mesh::PolygonMesh;

/// Parameters (u, v) and points (x, y, z).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ScatteredData {
    pub params: Vec<[f64; 2]>,
    pub points: Vec<[f64; 3]>,
}

/// The fields of a data line: split by commas, semicolons or tabs where it has one (an
/// empty field stays, and is refused), else by runs of spaces (`0 0 1 2 3`, as `.xyz`).
fn fields(line: &str) -> Vec<&str> {
    if line.contains([',', ';', '\t']) {
        line.split([',', ';', '\t']).map(str::trim).collect()
    } else {
        line.split_whitespace().collect()
    }
}

/// A header: the first line, with no field that is a number (`u,v,x,y,z`). A first line
/// with some numbers is a bad data line, named as such, not skipped.
fn is_header(line_index: usize, fields: &[&str]) -> bool {
    line_index == 0 && fields.iter().all(|f| f.parse::<f64>().is_err())
}

/// Parses CSV text; `path` only names the source in errors.
///
/// Errors: `Parse` naming the line for a line that does not have five finite numbers
/// (except a first line without numbers, taken as a header); `InvalidInput` for no data.
pub fn parse_csv(path: &Path, text: &str) -> Result<ScatteredData> {
    let rows = numeric_rows::<5>(path, text, "five finite numbers u,v,x,y,z")?;
    if rows.is_empty() {
        return Err(Error::InvalidInput(format!(
            "{}: no data lines",
            path.display()
        )));
    }
    Ok(ScatteredData {
        params: rows.iter().map(|(_, v)| [v[0], v[1]]).collect(),
        points: rows.iter().map(|(_, v)| [v[2], v[3], v[4]]).collect(),
    })
}

/// The data lines of CSV text as `N` finite numbers each, with their 1-based line numbers
/// (comments, blank lines and a header skipped); `expected` says what a line must hold.
fn numeric_rows<const N: usize>(
    path: &Path,
    text: &str,
    expected: &str,
) -> Result<Vec<(usize, [f64; N])>> {
    let mut rows = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let fields = fields(line);
        let nums: std::result::Result<Vec<f64>, _> =
            fields.iter().map(|f| f.parse::<f64>()).collect();
        match nums {
            Ok(v) if v.len() == N && v.iter().all(|x| x.is_finite()) => {
                rows.push((i + 1, std::array::from_fn(|k| v[k])))
            }
            Err(_) if is_header(i, &fields) => continue,
            _ => {
                return Err(Error::parse(
                    path,
                    Location::Line(i + 1),
                    format!("expected {expected}, got {line:?}"),
                ))
            }
        }
    }
    Ok(rows)
}

/// Reads a CSV file (the file is never modified).
///
/// Errors: `Io` if it cannot be read; as [`parse_csv`].
pub fn read_csv(path: &Path) -> Result<ScatteredData> {
    parse_csv(path, &read_text(path)?)
}

/// Reads a text file, naming the line and column of its first byte that is not UTF-8 (binary
/// data given as CSV) rather than only "stream did not contain valid UTF-8".
fn read_text(path: &Path) -> Result<String> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    String::from_utf8(bytes).map_err(|e| {
        let bytes = e.as_bytes();
        let at = e.utf8_error().valid_up_to();
        let line_start = bytes[..at]
            .iter()
            .rposition(|&c| c == b'\n')
            .map_or(0, |p| p + 1);
        let line = 1 + bytes[..at].iter().filter(|&&c| c == b'\n').count();
        Error::parse(
            path,
            Location::Line(line),
            format!(
                "not valid UTF-8 text: byte 0x{:02x} at column {} (binary data, not CSV?)",
                bytes[at],
                at - line_start + 1
            ),
        )
    })
}

/// Parses extra shape-constraint points (2024 (11)'s Γ_h): CSV lines `u,v` (split as
/// [`parse_csv`]'s; a first line without numbers is a header, `#` starts a comment); each point is labelled with its file and line so a
/// point outside the hole can be named.
///
/// Errors: `Parse` naming the line for a line that is not two finite numbers (except a
/// first line without numbers); `InvalidInput` for no points.
pub fn parse_uv_points(path: &Path, text: &str) -> Result<Vec<super::shape::ShapePoint>> {
    let rows = numeric_rows::<2>(path, text, "two finite numbers u,v")?;
    if rows.is_empty() {
        return Err(Error::InvalidInput(format!(
            "{}: no constraint points",
            path.display()
        )));
    }
    Ok(rows
        .into_iter()
        .map(|(line, uv)| super::shape::ShapePoint {
            uv,
            label: format!("{} line {line}", path.display()),
        })
        .collect())
}

/// Reads a CSV of `u,v` constraint points (the file is never modified).
///
/// Errors: `Io` if it cannot be read; as [`parse_uv_points`].
pub fn read_uv_points(path: &Path) -> Result<Vec<super::shape::ShapePoint>> {
    parse_uv_points(path, &read_text(path)?)
}

/// The data of a mesh: one point per distinct (vertex, texture coordinate) pair when the
/// mesh has UVs (a vertex on a UV seam gives one datum per side), else one per vertex with
/// (u, v) = (x, y) (a height field).
///
/// Errors: `InvalidInput` for a mesh without vertices, with non-finite coordinates, or
/// with UV indices out of range.
pub fn from_mesh(mesh: &PolygonMesh) -> Result<ScatteredData> {
    let mut d = ScatteredData::default();
    if mesh.positions.iter().flatten().any(|x| !x.is_finite()) {
        return Err(Error::InvalidInput(
            "mesh has a non-finite vertex coordinate".into(),
        ));
    }
    match &mesh.uvs {
        Some(uv) => {
            if uv.corner_indices.len() != mesh.face_indices.len() {
                return Err(Error::InvalidInput(
                    "mesh UVs do not match its face corners".into(),
                ));
            }
            let mut seen = HashSet::new();
            for (&v, &t) in mesh.face_indices.iter().zip(&uv.corner_indices) {
                let (p, q) = (mesh.positions.get(v as usize), uv.coords.get(t as usize));
                let (Some(p), Some(q)) = (p, q) else {
                    return Err(Error::InvalidInput(format!(
                        "corner (vertex {v}, uv {t}) out of range"
                    )));
                };
                if uv.untextured == Some(t) {
                    return Err(Error::InvalidInput(format!(
                        "vertex {v} is a corner of a face without texture coordinates ({} of {} \
                         faces have them): fitting by UV needs them on every face, or on none \
                         to fit a height field",
                        uv.textured_faces(&mesh.face_offsets),
                        mesh.face_count()
                    )));
                }
                if seen.insert((v, t)) {
                    d.params.push(*q);
                    d.points.push(*p);
                }
            }
        }
        None => {
            for p in &mesh.positions {
                d.params.push([p[0], p[1]]);
                d.points.push(*p);
            }
        }
    }
    if d.params.is_empty() {
        return Err(Error::InvalidInput(
            "the mesh has no vertices to fit".into(),
        ));
    }
    Ok(d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mesh_as_height_field_and_with_uvs() {
        let m = PolygonMesh::from_polygons(
            vec![[0.0, 0.0, 1.0], [1.0, 0.0, 2.0], [0.0, 1.0, 3.0]],
            &[[0u32, 1, 2]],
        );
        let d = from_mesh(&m).unwrap();
        assert_eq!(d.params, vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
        let mut m2 = m.clone();
        m2.uvs = Some(crate::mesh::CornerUvs {
            coords: vec![[0.5, 0.5], [0.7, 0.1]],
            corner_indices: vec![0, 1, 1],
            untextured: None,
        });
        let d = from_mesh(&m2).unwrap();
        assert_eq!(d.params, vec![[0.5, 0.5], [0.7, 0.1], [0.7, 0.1]]);
        assert_eq!(d.points[2], [0.0, 1.0, 3.0]);
        m2.uvs.as_mut().unwrap().corner_indices = vec![0, 1, 5];
        assert!(from_mesh(&m2).is_err());
        // A face without texture coordinates: its stand-in (0, 0) is no parameter.
        let mut m3 = PolygonMesh::from_polygons(
            vec![
                [0.0, 0.0, 1.0],
                [1.0, 0.0, 2.0],
                [0.0, 1.0, 3.0],
                [1.0, 1.0, 4.0],
            ],
            &[[0u32, 1, 2], [1, 3, 2]],
        );
        m3.uvs = Some(crate::mesh::CornerUvs {
            coords: vec![[0.5, 0.5], [0.7, 0.1], [0.2, 0.9], [0.0, 0.0]],
            corner_indices: vec![0, 1, 2, 3, 3, 3],
            untextured: Some(3),
        });
        let e = from_mesh(&m3).unwrap_err().to_string();
        assert!(
            e.contains("vertex 1 is a corner of a face without texture coordinates (1 of 2 faces"),
            "{e}"
        );
    }

    #[test]
    fn header_comments_and_errors() {
        let p = Path::new("t.csv");
        let d = parse_csv(p, "u,v,x,y,z\n0,0,1,2,3 # a\n\n0.5;1;4;5;6\n").unwrap();
        assert_eq!(d.params, vec![[0.0, 0.0], [0.5, 1.0]]);
        assert_eq!(d.points[1], [4.0, 5.0, 6.0]);
        let e = parse_csv(p, "0,0,1,2,3\n0,0,1,2\n").unwrap_err();
        assert!(e.to_string().contains("line 2"), "{e}");
        assert!(parse_csv(p, "0,0,1,2,nan\n").is_err());
        assert!(parse_csv(p, "u,v,x,y,z\n").is_err());
    }

    #[test]
    fn space_separated_lines_are_data_and_a_half_numeric_first_line_is_no_header() {
        let p = Path::new("t.csv");
        // Spaces separate fields where a line has no comma, semicolon or tab (`.xyz`).
        let d = parse_csv(p, "0 0  1 2 3\n0.5 1 4 5 6\n").unwrap();
        assert_eq!(d.params, vec![[0.0, 0.0], [0.5, 1.0]]);
        assert_eq!(d.points[0], [1.0, 2.0, 3.0]);
        // A first line with numbers is a bad data line, not a header.
        let e = parse_csv(p, "0,0,1,2,x\n0,0,1,2,3\n").unwrap_err();
        assert!(e.to_string().contains("line 1"), "{e}");
        // An empty field between commas is still refused, not closed up.
        let e = parse_csv(p, "0,,0,1,2,3\n").unwrap_err();
        assert!(e.to_string().contains("line 1"), "{e}");
        let pts = parse_uv_points(p, "u v\n0.25 0.5\n").unwrap();
        assert_eq!(pts[0].uv, [0.25, 0.5]);
        let e = parse_uv_points(p, "0.25 x\n0.25 0.5\n").unwrap_err();
        assert!(e.to_string().contains("line 1"), "{e}");
    }

    #[test]
    fn binary_data_is_named_by_line_and_column() {
        let dir = std::env::temp_dir().join(format!("surfkit-data-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("scan.csv");
        std::fs::write(&path, b"u,v,x,y,z\n0,0,1,2,3\n0,\xff\x00\x01").unwrap();
        let e = read_csv(&path).unwrap_err().to_string();
        assert!(
            e.ends_with(
                "line 3: not valid UTF-8 text: byte 0xff at column 3 (binary data, not CSV?)"
            ),
            "{e}"
        );
        let e = read_uv_points(&path).unwrap_err().to_string();
        assert!(e.contains("line 3: not valid UTF-8"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
