//! OFF (Object File Format), ASCII: `OFF`, `COFF`, `NOFF`, `CNOFF`, `STOFF`, … headers,
//! `#` comments anywhere, per-vertex normals/colours/texture coordinates after the
//! position, per-facet colour values after the corners (ignored). As the reference
//! definition of F says, lines after the declared facets are ignored.
//!
//! surfkit writes objects and groups as `# surfkit object|group <name>` comment lines in the
//! facet list; other readers see comments, surfkit reads them back.

use std::io::Write;
use std::path::Path;

use super::face_check::{degeneracy_as_written, out_of_range};
use super::text::{parse_f64, parse_i64, show, strip_comment, tokens, write_f64, Lines};
use super::ReadOptions;
use crate::error::{Error, Location, Result};
use crate::mesh::{FaceLabels, PolygonMesh, NO_LABEL};

/// What the header keyword says each vertex line carries after x y z.
#[derive(Default, Debug)]
struct VertexLayout {
    normal: bool,
    color: bool,
}

fn layout_of(keyword: &str) -> Option<VertexLayout> {
    let rest = keyword.strip_suffix("OFF")?;
    // Texture coordinates (ST) follow the colour; they are not kept.
    let rest = rest.strip_prefix("ST").unwrap_or(rest);
    let (color, rest) = match rest.strip_prefix('C') {
        Some(r) => (true, r),
        None => (false, rest),
    };
    let (normal, rest) = match rest.strip_prefix('N') {
        Some(r) => (true, r),
        None => (false, rest),
    };
    rest.is_empty().then_some(VertexLayout { normal, color })
}

pub fn parse(path: &Path, bytes: &[u8], options: &ReadOptions) -> Result<PolygonMesh> {
    let err = |line: usize, msg: String| Error::parse(path, Location::Line(line), msg);
    let mut lines = Lines::new(bytes);
    // Header keyword (possibly followed by the counts on the same line).
    let mut pending: Vec<&[u8]> = Vec::new();
    let mut layout = None;
    let mut header_line = 0;
    for (n, line) in lines.by_ref() {
        let mut toks = tokens(strip_comment(line));
        if let Some(first) = toks.next() {
            let word = std::str::from_utf8(first).unwrap_or("");
            layout = layout_of(word);
            if layout.is_none() {
                return Err(err(
                    n,
                    format!(
                        "not an OFF file: expected OFF, COFF, NOFF or STOFF, found {:?}",
                        show(first)
                    ),
                ));
            }
            if let Some(t) = toks.next() {
                if t == b"BINARY" {
                    return Err(err(
                        n,
                        "binary OFF is not supported; write it as ASCII OFF or PLY".into(),
                    ));
                }
                pending.push(t);
                pending.extend(toks);
            }
            header_line = n;
            break;
        }
    }
    let layout = layout.ok_or_else(|| Error::parse(path, Location::File, "the file is empty"))?;
    // Counts: vertices, faces, edges (edges ignored).
    let mut counts_line = header_line;
    while pending.len() < 2 {
        let (n, line) = lines.next().ok_or_else(|| {
            err(
                header_line,
                "the file ends before the vertex and face counts".into(),
            )
        })?;
        pending.extend(tokens(strip_comment(line)));
        counts_line = n;
    }
    let count = |t: &[u8], what: &str| {
        parse_i64(t)
            .filter(|&c| c >= 0)
            .map(|c| c as usize)
            .ok_or_else(|| {
                err(
                    counts_line,
                    format!("{what} count {:?} is not a count", show(t)),
                )
            })
    };
    let n_vertices = count(pending[0], "vertex")?;
    let n_faces = count(pending[1], "face")?;
    let mut mesh = PolygonMesh::default();
    // The counts are not trusted with memory: each vertex takes at least 6 bytes ("0 0 0\n").
    mesh.positions
        .reserve_exact(n_vertices.min(bytes.len() / 6));
    let mut colors: Vec<[u8; 4]> = Vec::new();
    let mut objects = FaceLabels::default();
    let mut groups = FaceLabels::default();
    let (mut current_object, mut current_group) = (NO_LABEL, NO_LABEL);
    let mut seen = 0;
    let mut data_lines = 0;
    let mut last_line = counts_line;
    while seen < n_vertices + n_faces {
        let Some((n, raw)) = lines.next() else {
            let what = if seen < n_vertices {
                format!("{seen} of the {n_vertices} vertices")
            } else {
                format!("{} of the {n_faces} faces", seen - n_vertices)
            };
            return Err(err(
                last_line,
                format!(
                    "the file ends after {what} the header declares: line {counts_line} \
                     declares {n_vertices} vertices and {n_faces} faces, the file has \
                     {data_lines} data lines after it"
                ),
            ));
        };
        last_line = n;
        if seen >= n_vertices {
            if let Some(label) = surfkit_label(raw) {
                let (labels, current) = match label.0 {
                    "object" => (&mut objects, &mut current_object),
                    _ => (&mut groups, &mut current_group),
                };
                *current = labels.intern(label.1);
                continue;
            }
        }
        let line = strip_comment(raw);
        let mut toks = tokens(line).peekable();
        if toks.peek().is_none() {
            continue;
        }
        data_lines += 1;
        if seen < n_vertices {
            let vals: Vec<f64> = toks
                .map(|t| {
                    parse_f64(t).ok_or_else(|| {
                        err(n, format!("vertex {seen}: {:?} is not a number", show(t)))
                    })
                })
                .collect::<Result<_>>()?;
            let needed = 3 + if layout.normal { 3 } else { 0 };
            if vals.len() < needed {
                return Err(err(
                    n,
                    format!(
                        "vertex {seen}: expected at least {needed} numbers, found {}",
                        vals.len()
                    ),
                ));
            }
            if let Some(c) = vals.iter().find(|c| !c.is_finite()) {
                return Err(err(n, format!("vertex {seen}: {c} is not a finite number")));
            }
            mesh.positions.push([vals[0], vals[1], vals[2]]);
            if layout.color {
                let c = &vals[needed..];
                colors.push(off_color(c).ok_or_else(|| {
                    err(
                        n,
                        format!(
                            "vertex {seen}: COFF needs a colour (3 or 4 values) after the position"
                        ),
                    )
                })?);
            }
        } else {
            let f = seen - n_vertices;
            let first = toks.next().unwrap();
            let arity = parse_i64(first).filter(|&a| a >= 0).ok_or_else(|| {
                err(
                    n,
                    format!("face {f}: corner count {:?} is not a count", show(first)),
                )
            })? as usize;
            let start = mesh.face_indices.len();
            for k in 0..arity {
                let t = toks.next().ok_or_else(|| {
                    err(
                        n,
                        format!("face {f}: declares {arity} corners but lists {k}"),
                    )
                })?;
                let i = parse_i64(t).ok_or_else(|| {
                    err(n, format!("face {f}: {:?} is not a vertex index", show(t)))
                })?;
                if let Some(m) = out_of_range(i, n_vertices, 0) {
                    return Err(err(n, format!("face {f}: {m}")));
                }
                mesh.face_indices.push(i as u32);
            }
            // The rest of the line is the facet's colour: ignored, but it must be numbers.
            if let Some(t) = toks.find(|t| parse_f64(t).is_none()) {
                return Err(err(
                    n,
                    format!("face {f}: unexpected {:?} after the corners", show(t)),
                ));
            }
            if !options.keep_degenerate {
                if let Some(m) = degeneracy_as_written(&mesh.face_indices[start..], 0) {
                    return Err(err(n, format!("face {f}: {m}")));
                }
            }
            mesh.face_offsets.push(mesh.face_indices.len() as u32);
            objects.of_face.push(current_object);
            groups.of_face.push(current_group);
        }
        seen += 1;
    }
    if layout.color {
        mesh.colors = Some(colors);
    }
    if objects.of_face.iter().any(|&i| i != NO_LABEL) {
        mesh.objects = Some(objects);
    }
    if groups.of_face.iter().any(|&i| i != NO_LABEL) {
        mesh.groups = Some(groups);
    }
    Ok(mesh)
}

/// A `# surfkit object|group <name>` line, as `(kind, name)`.
fn surfkit_label(line: &[u8]) -> Option<(&str, &str)> {
    let text = std::str::from_utf8(line).ok()?.trim_start();
    let rest = text.strip_prefix("# surfkit ")?;
    let (kind, name) = rest.split_once(' ').unwrap_or((rest, ""));
    matches!(kind, "object" | "group").then_some((kind, name))
}

/// An OFF colour: 3 or 4 values, integers in 0..=255 or floats in [0, 1].
fn off_color(c: &[f64]) -> Option<[u8; 4]> {
    if c.len() < 3 {
        return None;
    }
    let integral = c.iter().all(|v| v.fract() == 0.0) && c.iter().any(|&v| v > 1.0);
    let conv = |v: f64| {
        if integral {
            v.clamp(0.0, 255.0) as u8
        } else {
            (v.clamp(0.0, 1.0) * 255.0).round() as u8
        }
    };
    Some([
        conv(c[0]),
        conv(c[1]),
        conv(c[2]),
        c.get(3).map_or(255, |&a| conv(a)),
    ])
}

/// Writes OFF (COFF with integer colours when the mesh has vertex colours).
pub fn write(out: &mut dyn Write, mesh: &PolygonMesh) -> std::io::Result<()> {
    let keyword = if mesh.colors.is_some() { "COFF" } else { "OFF" };
    writeln!(
        out,
        "{keyword}\n# written by surfkit {}",
        env!("CARGO_PKG_VERSION")
    )?;
    writeln!(out, "{} {} 0", mesh.vertex_count(), mesh.face_count())?;
    for (v, p) in mesh.positions.iter().enumerate() {
        write_f64(out, p[0])?;
        out.write_all(b" ")?;
        write_f64(out, p[1])?;
        out.write_all(b" ")?;
        write_f64(out, p[2])?;
        if let Some(c) = &mesh.colors {
            let c = c[v];
            write!(out, " {} {} {} {}", c[0], c[1], c[2], c[3])?;
        }
        out.write_all(b"\n")?;
    }
    let (mut last_o, mut last_g) = (NO_LABEL, NO_LABEL);
    for (f, face) in mesh.faces().enumerate() {
        for (kind, labels, last) in [
            ("object", &mesh.objects, &mut last_o),
            ("group", &mesh.groups, &mut last_g),
        ] {
            if let Some(l) = labels {
                let id = l.of_face[f];
                if id != *last && id != NO_LABEL {
                    writeln!(out, "# surfkit {kind} {}", l.names[id as usize])?;
                }
                *last = id;
            }
        }
        write!(out, "{}", face.len())?;
        for i in face {
            write!(out, " {i}")?;
        }
        out.write_all(b"\n")?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(bytes: &[u8]) -> Result<PolygonMesh> {
        parse(Path::new("t.off"), bytes, &ReadOptions::default())
    }

    /// Geomview's OFF: "everything after '#' on a line" is a comment, on any line.
    #[test]
    fn inline_comments_end_every_line() {
        let mesh = read(
            b"OFF # a square\n4 2 0 # counts\n\
              0 0 0 # origin\n1 0 0#x\n1 1 0\t# 7 8 9\n0 1 0 #\n\
              3 0 1 2 # tri\n3 0 2 3#tri\n",
        )
        .unwrap();
        assert_eq!(
            mesh.positions,
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0]
            ]
        );
        assert_eq!(mesh.face_indices, vec![0, 1, 2, 0, 2, 3]);
        assert!(mesh.colors.is_none());
        // A coloured OFF: the comment is no part of the colour.
        let mesh =
            read(b"COFF\n3 1 0\n0 0 0 255 0 0 # red\n1 0 0 0 255 0\n0 1 0 0 0 255\n3 0 1 2\n")
                .unwrap();
        assert_eq!(mesh.colors.unwrap()[0], [255, 0, 0, 255]);
        // Garbage that is no comment is still named.
        let e = read(b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 x # tri\n").unwrap_err();
        assert_eq!(
            e.to_string(),
            "t.off: line 6: face 0: unexpected \"x\" after the corners"
        );
    }

    #[test]
    fn huge_counts_do_not_size_allocations() {
        let e = parse(
            Path::new("t.off"),
            b"OFF\n999999999999999999 1 0\n0 0 0\n",
            &ReadOptions::default(),
        )
        .unwrap_err();
        assert_eq!(
            e.to_string(),
            "t.off: line 3: the file ends after 1 of the 999999999999999999 vertices the header \
             declares: line 2 declares 999999999999999999 vertices and 1 faces, the file has 1 \
             data lines after it"
        );
    }
}
