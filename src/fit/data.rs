//! Reading users' scattered data: CSV lines `u,v,x,y,z` (a header line is skipped,
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

/// Parses CSV text; `path` only names the source in errors.
///
/// Errors: `Parse` naming the line for a line that does not have five finite numbers
/// (except a non-numeric first line, taken as a header); `InvalidInput` for no data.
pub fn parse_csv(path: &Path, text: &str) -> Result<ScatteredData> {
    let mut d = ScatteredData::default();
    for (i, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.split([',', ';', '\t']).map(str::trim).collect();
        let nums: std::result::Result<Vec<f64>, _> =
            fields.iter().map(|f| f.parse::<f64>()).collect();
        match nums {
            Ok(v) if v.len() == 5 && v.iter().all(|x| x.is_finite()) => {
                d.params.push([v[0], v[1]]);
                d.points.push([v[2], v[3], v[4]]);
            }
            Err(_) if d.params.is_empty() && i == 0 => continue,
            _ => {
                return Err(Error::parse(
                    path,
                    Location::Line(i + 1),
                    format!("expected five finite numbers u,v,x,y,z, got {line:?}"),
                ))
            }
        }
    }
    if d.params.is_empty() {
        return Err(Error::InvalidInput(format!(
            "{}: no data lines",
            path.display()
        )));
    }
    Ok(d)
}

/// Reads a CSV file (the file is never modified).
///
/// Errors: `Io` if it cannot be read; as [`parse_csv`].
pub fn read_csv(path: &Path) -> Result<ScatteredData> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    parse_csv(path, &text)
}

/// Parses extra shape-constraint points (2024 (11)'s Γ_h): CSV lines `u,v` (a header line is
/// skipped, `#` starts a comment); each point is labelled with its file and line so a
/// point outside the hole can be named.
///
/// Errors: `Parse` naming the line for a line that is not two finite numbers (except a
/// non-numeric first line); `InvalidInput` for no points.
pub fn parse_uv_points(path: &Path, text: &str) -> Result<Vec<super::shape::ShapePoint>> {
    let mut out = vec![];
    for (i, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let nums: std::result::Result<Vec<f64>, _> = line
            .split([',', ';', '\t'])
            .map(|f| f.trim().parse::<f64>())
            .collect();
        match nums {
            Ok(v) if v.len() == 2 && v.iter().all(|x| x.is_finite()) => {
                out.push(super::shape::ShapePoint {
                    uv: [v[0], v[1]],
                    label: format!("{} line {}", path.display(), i + 1),
                })
            }
            Err(_) if out.is_empty() && i == 0 => continue,
            _ => {
                return Err(Error::parse(
                    path,
                    Location::Line(i + 1),
                    format!("expected two finite numbers u,v, got {line:?}"),
                ))
            }
        }
    }
    if out.is_empty() {
        return Err(Error::InvalidInput(format!(
            "{}: no constraint points",
            path.display()
        )));
    }
    Ok(out)
}

/// Reads a CSV of `u,v` constraint points (the file is never modified).
///
/// Errors: `Io` if it cannot be read; as [`parse_uv_points`].
pub fn read_uv_points(path: &Path) -> Result<Vec<super::shape::ShapePoint>> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    parse_uv_points(path, &text)
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
        });
        let d = from_mesh(&m2).unwrap();
        assert_eq!(d.params, vec![[0.5, 0.5], [0.7, 0.1], [0.7, 0.1]]);
        assert_eq!(d.points[2], [0.0, 1.0, 3.0]);
        m2.uvs.as_mut().unwrap().corner_indices = vec![0, 1, 5];
        assert!(from_mesh(&m2).is_err());
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
}
