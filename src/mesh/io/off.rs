//! OFF (Object File Format), ASCII: `OFF`, `COFF`, `NOFF`, `CNOFF`, `STOFF`, … headers,
//! `#` comments anywhere, per-vertex normals/colours/texture coordinates after the
//! position, per-facet colour values after the corners (ignored).
//!
//! The header's counts are checked against the records, as the ASCII PLY reader does: a
//! vertex line must hold exactly the fields its keyword declares, a facet line at least
//! the corners its count field declares and then only a colour (1, 3 or 4 numbers, as in
//! Geomview's OFF), and nothing but blank or comment lines may follow the declared facets.
//! A header that declares too few vertices would otherwise turn vertex lines into facets
//! and drop the real facets unseen.
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
    texture: bool,
}

impl VertexLayout {
    /// Where the colour starts on a vertex line (after x y z and the normal).
    fn color_start(&self) -> usize {
        3 + if self.normal { 3 } else { 0 }
    }

    /// The colour's length on a vertex line of `len` numbers, `None` when `len` does not
    /// fit the layout.
    fn color_len(&self, len: usize) -> Option<usize> {
        let fixed = self.color_start() + if self.texture { 2 } else { 0 };
        let color = len.checked_sub(fixed)?;
        let allowed: &[usize] = if self.color { &[3, 4] } else { &[0] };
        allowed.contains(&color).then_some(color)
    }

    /// The fields of a vertex line, for error messages.
    fn fields(&self) -> String {
        let mut count = self.color_start() + if self.texture { 2 } else { 0 };
        let mut names = String::from("x y z");
        if self.normal {
            names.push_str(" nx ny nz");
        }
        let mut or_more = "";
        if self.color {
            names.push_str(" r g b [a]");
            count += 3;
            or_more = " or one more";
        }
        if self.texture {
            names.push_str(" s t");
        }
        format!("{count}{or_more} ({names})")
    }
}

fn layout_of(keyword: &str) -> Option<VertexLayout> {
    let rest = keyword.strip_suffix("OFF")?;
    // Texture coordinates (ST) follow the colour; they are not kept.
    let (texture, rest) = match rest.strip_prefix("ST") {
        Some(r) => (true, r),
        None => (false, rest),
    };
    let (color, rest) = match rest.strip_prefix('C') {
        Some(r) => (true, r),
        None => (false, rest),
    };
    let (normal, rest) = match rest.strip_prefix('N') {
        Some(r) => (true, r),
        None => (false, rest),
    };
    rest.is_empty().then_some(VertexLayout {
        normal,
        color,
        texture,
    })
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
            if let Some(c) = vals.iter().find(|c| !c.is_finite()) {
                return Err(err(n, format!("vertex {seen}: {c} is not a finite number")));
            }
            let color_len = layout.color_len(vals.len()).ok_or_else(|| {
                err(
                    n,
                    format!(
                        "vertex {seen}: the line holds {} numbers where a vertex has {}: \
                         the header's counts are wrong or the line is malformed",
                        vals.len(),
                        layout.fields()
                    ),
                )
            })?;
            mesh.positions.push([vals[0], vals[1], vals[2]]);
            if layout.color {
                let start = layout.color_start();
                // color_len accepts only 3 or 4 values here, which off_color takes.
                colors.push(off_color(&vals[start..start + color_len]).unwrap_or([255; 4]));
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
            // The rest of the line is the facet's colour: ignored, but it must be numbers,
            // and as many as a colour has (a colour-map index, RGB or RGBA).
            let mut color_len = 0;
            for t in toks {
                if parse_f64(t).is_none() {
                    return Err(err(
                        n,
                        format!("face {f}: unexpected {:?} after the corners", show(t)),
                    ));
                }
                color_len += 1;
            }
            if ![0, 1, 3, 4].contains(&color_len) {
                return Err(err(
                    n,
                    format!(
                        "face {f}: the line declares {arity} corners and holds {color_len} more \
                         numbers, which are not a colour (1, 3 or 4 numbers): the header's \
                         counts are wrong or the line is malformed"
                    ),
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
    // Records after the declared facets mean the header's counts are wrong.
    if let Some((n, l)) = lines.find(|(_, l)| tokens(strip_comment(l)).next().is_some()) {
        return Err(err(
            n,
            format!(
                "data after the {n_faces} faces the header declares ({:?}): the header's \
                 counts are wrong",
                show(strip_comment(l).trim_ascii())
            ),
        ));
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

    fn read(text: &str) -> Result<PolygonMesh> {
        parse(Path::new("t.off"), text.as_bytes(), &ReadOptions::default())
    }

    fn refused(text: &str) -> String {
        read(text).unwrap_err().to_string()
    }

    #[test]
    fn vertex_lines_hold_the_fields_the_keyword_declares() {
        let tri = "3 0 1 2\n";
        for (keyword, vertex) in [
            ("OFF", "0 0 0"),
            ("NOFF", "0 0 0 0 0 1"),
            ("COFF", "0 0 0 255 0 0"),
            ("COFF", "0 0 0 1 0 0 0.5"),
            ("CNOFF", "0 0 0 0 0 1 255 0 0 255"),
            ("STOFF", "0 0 0 0.5 0.5"),
            ("STCOFF", "0 0 0 1 0 0 0.5 0.5"),
        ] {
            let text = format!("{keyword}\n3 1 0\n{vertex}\n{vertex}\n{vertex}\n{tri}");
            let keep = ReadOptions {
                keep_degenerate: true,
            };
            let mesh = parse(Path::new("t.off"), text.as_bytes(), &keep)
                .unwrap_or_else(|e| panic!("{keyword} {vertex}: {e}"));
            assert_eq!(mesh.positions.len(), 3, "{keyword}");
            assert_eq!(mesh.colors.is_some(), keyword.contains('C'), "{keyword}");
        }
        for (keyword, vertex, fields) in [
            ("OFF", "0 0", "2 numbers where a vertex has 3 (x y z)"),
            ("OFF", "0 0 0 1", "4 numbers where a vertex has 3 (x y z)"),
            (
                "NOFF",
                "0 0 0",
                "3 numbers where a vertex has 6 (x y z nx ny nz)",
            ),
            (
                "COFF",
                "0 0 0",
                "3 numbers where a vertex has 6 or one more (x y z r g b [a])",
            ),
            (
                "COFF",
                "0 0 0 1 0 0 1 1",
                "8 numbers where a vertex has 6 or one more (x y z r g b [a])",
            ),
            (
                "STOFF",
                "0 0 0",
                "3 numbers where a vertex has 5 (x y z s t)",
            ),
        ] {
            assert_eq!(
                refused(&format!("{keyword}\n1 0 0\n{vertex}\n")),
                format!(
                    "t.off: line 3: vertex 0: the line holds {fields}: the header's counts \
                     are wrong or the line is malformed"
                ),
                "{keyword}"
            );
        }
    }

    #[test]
    fn a_header_with_too_few_vertices_is_refused_not_read_as_faces() {
        // The defect the hostile-input sweep found: the third vertex line was read as a
        // 0-corner face "0 1 0" and the real face ignored.
        let text = "OFF\n2 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
        let keep = ReadOptions {
            keep_degenerate: true,
        };
        let e = parse(Path::new("t.off"), text.as_bytes(), &keep).unwrap_err();
        assert_eq!(
            e.to_string(),
            "t.off: line 5: face 0: the line declares 0 corners and holds 2 more numbers, which \
             are not a colour (1, 3 or 4 numbers): the header's counts are wrong or the line is \
             malformed"
        );
    }

    #[test]
    fn facet_colours_are_one_three_or_four_numbers() {
        let head = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n";
        for color in ["", " 7", " 1 0 0", " 255 0 0 128"] {
            let mesh = read(&format!("{head}3 0 1 2{color}\n")).unwrap();
            assert_eq!(mesh.faces().next(), Some(&[0, 1, 2][..]), "{color:?}");
        }
        for color in [" 1 0", " 1 0 0 0 0"] {
            let shown = refused(&format!("{head}3 0 1 2{color}\n"));
            assert!(
                shown.starts_with("t.off: line 6: face 0: the line declares 3 corners and holds"),
                "{shown}"
            );
        }
        assert_eq!(
            refused(&format!("{head}4 0 1 2\n")),
            "t.off: line 6: face 0: declares 4 corners but lists 3"
        );
    }

    #[test]
    fn records_after_the_declared_facets_are_refused_comments_are_not() {
        let body = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
        let mesh = read(&format!("{body}\n# the end\n   \n# surfkit group g\n")).unwrap();
        assert_eq!(mesh.face_count(), 1);
        assert_eq!(
            refused(&format!("{body}\n3 2 1 0 # again\n")),
            "t.off: line 8: data after the 1 faces the header declares (\"3 2 1 0\"): the \
             header's counts are wrong"
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
