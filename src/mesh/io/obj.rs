//! Wavefront OBJ: `v` (with MeshLab's optional `r g b`), `vt`, `f` (polygons kept,
//! negative indices relative), `o` and `g` kept as face labels.
//!
//! Comments: a `#` that begins a word starts a comment to the end of the line, on a line of
//! its own or after a record (`v 1 2 3 # corner`, `f 1 2 3 # lid`). OpenMesh's reader reads
//! the same meshes from such lines (it takes a vertex's first three numbers and skips the
//! words of a face that are not indices); MeshLab's (vcglib's `import_obj.h`) takes a
//! vertex's first three numbers too, but reads every word of an `f` line as a corner, the
//! comment's as well (`atoi("#")` is 0, no OBJ index) — a misreading, not copied here. A `#`
//! inside a word (`g part#2`) stays part of it. (tobj refuses the two lines above.)
//!
//! Why not `tobj`, which the design names: tobj re-indexes vertices per model, so vertices
//! shared between two `o`/`g` groups are duplicated and unreferenced vertices are dropped.
//! Both change V, E and χ — the very numbers the Euler test checks — and tobj's errors carry
//! no line number. This reader keeps the file's vertex numbering and names the line of any
//! problem; tobj stays in the test suite as an independent cross-check of what we parse.

use std::io::Write;
use std::path::Path;

use super::face_check::{degeneracy_as_written, out_of_range};
use super::text::{parse_f64, parse_i64, show, strip_word_comment, tokens, write_f64, Lines};
use super::ReadOptions;
use crate::error::{Error, Location, Result};
use crate::mesh::SharpFeatures;
use crate::mesh::{CornerUvs, FaceLabels, PolygonMesh, NO_LABEL};

/// What the reader accumulates while walking the lines.
#[derive(Default)]
struct ObjBuilder {
    mesh: PolygonMesh,
    colors: Vec<[u8; 4]>,
    uv_coords: Vec<[f64; 2]>,
    uv_corners: Vec<u32>,
    faces_with_uv: usize,
    /// `vn` records read so far: normals are not kept, but a face's normal indices must
    /// name one (as its texture indices must name a `vt`).
    normal_count: usize,
    objects: FaceLabels,
    groups: FaceLabels,
    label_ids: [std::collections::HashMap<String, u32>; 2],
    current_object: u32,
    current_group: u32,
    /// Face lines with the line number where they were read: indices are checked against
    /// the final vertex count, since OBJ allows `v` records after the faces that use them.
    face_lines: Vec<usize>,
    raw_indices: Vec<i64>,
    /// Vertex ids named by `t crease` / `t corner` tags, with their line (checked at the end).
    tag_vertices: Vec<(i64, usize)>,
}

pub fn parse(path: &Path, bytes: &[u8], options: &ReadOptions) -> Result<PolygonMesh> {
    let mut b = ObjBuilder {
        current_object: NO_LABEL,
        current_group: NO_LABEL,
        ..Default::default()
    };
    let err = |line: usize, msg: String| Error::parse(path, Location::Line(line), msg);
    let mut joined = Vec::new();
    let mut lines = Lines::new(bytes);
    // Records of a keyword OBJ defines, and the first line that starts with none: a file
    // with content but no OBJ record (binary data named .obj) is refused, not read as an
    // empty mesh.
    let mut known_records = 0usize;
    let mut first_unknown: Option<(usize, String)> = None;
    while let Some((number, mut line)) = lines.next() {
        // A trailing backslash continues the record on the next line.
        if line.last() == Some(&b'\\') {
            joined.clear();
            joined.extend_from_slice(&line[..line.len() - 1]);
            while joined.last().is_some() {
                match lines.next() {
                    Some((_, next)) => {
                        joined.push(b' ');
                        let cont = next.last() == Some(&b'\\');
                        joined.extend_from_slice(if cont { &next[..next.len() - 1] } else { next });
                        if !cont {
                            break;
                        }
                    }
                    None => break,
                }
            }
            line = &joined;
        }
        // A comment runs from a `#` that begins a word to the end of the line, after a
        // record as on a line of its own (`v 1 2 3 # corner`).
        let data = strip_word_comment(line);
        let mut toks = tokens(data);
        let Some(keyword) = toks.next() else {
            // A comment line (no record before its `#`) is part of OBJ too.
            if tokens(line).next().is_some() {
                known_records += 1;
            }
            continue;
        };
        if OBJ_KEYWORDS.contains(&keyword) {
            known_records += 1;
        } else {
            // An unknown record is skipped, but not binary data: OBJ is text.
            if let Some(column) = line.iter().position(|&c| is_binary(c)) {
                return Err(err(
                    number,
                    format!(
                        "binary data (byte 0x{:02x} at column {}): not an OBJ file (OBJ is text)",
                        line[column],
                        column + 1
                    ),
                ));
            }
            if first_unknown.is_none() {
                first_unknown = Some((number, show(keyword)));
            }
        }
        match keyword {
            b"v" => read_vertex(&mut b, toks, number).map_err(|m| err(number, why(data, m)))?,
            b"vt" => {
                let u = toks.next().and_then(parse_f64);
                let v = toks.next().map_or(Some(0.0), parse_f64);
                match (u, v) {
                    (Some(u), Some(v)) if u.is_finite() && v.is_finite() => {
                        b.uv_coords.push([u, v])
                    }
                    _ => {
                        return Err(err(
                            number,
                            why(
                                data,
                                format!(
                                    "texture coordinate is not two finite numbers: {:?}",
                                    show(data)
                                ),
                            ),
                        ))
                    }
                }
            }
            b"vn" => b.normal_count += 1,
            b"f" => read_face(&mut b, toks, number).map_err(|m| err(number, why(data, m)))?,
            b"t" => read_tag(&mut b, toks, number).map_err(|m| err(number, why(data, m)))?,
            b"o" | b"g" => {
                // The name is the rest of the record after the keyword.
                let name = std::str::from_utf8(data.trim_ascii_start()[1..].trim_ascii())
                    .map_err(|e| err(number, non_utf8(data, e)))?;
                let (labels, ids, current) = if keyword == b"o" {
                    (&mut b.objects, &mut b.label_ids[0], &mut b.current_object)
                } else {
                    (&mut b.groups, &mut b.label_ids[1], &mut b.current_group)
                };
                *current = *ids.entry(name.to_string()).or_insert_with(|| {
                    labels.names.push(name.to_string());
                    (labels.names.len() - 1) as u32
                });
            }
            // Normals, materials, smoothing groups, lines, points, free-form geometry,
            // comments: not part of a polygon mesh's topology.
            _ => {}
        }
    }
    if let (0, Some((number, keyword))) = (known_records, first_unknown) {
        return Err(err(
            number,
            format!(
                "no OBJ record in the file (this line starts with {keyword:?}): not an OBJ file?"
            ),
        ));
    }
    finish(b, path, options)
}

/// A byte no text file holds: a C0 control other than tab, vertical tab, form feed and
/// carriage return, or DEL (bytes ≥ 0x80 may be any 8-bit encoding of a name or comment).
fn is_binary(c: u8) -> bool {
    (c < 0x20 && !matches!(c, b'\t' | 0x0b | 0x0c | b'\r')) || c == 0x7f
}

/// The keywords of the OBJ format (Wavefront's specification) and OpenSubdiv's `t` tags:
/// a line starting with one of them is an OBJ record, read or deliberately skipped.
const OBJ_KEYWORDS: [&[u8]; 41] = [
    b"v",
    b"vt",
    b"vn",
    b"vp",
    b"f",
    b"fo",
    b"l",
    b"p",
    b"o",
    b"g",
    b"s",
    b"mg",
    b"usemtl",
    b"mtllib",
    b"maplib",
    b"usemap",
    b"cstype",
    b"deg",
    b"bmat",
    b"step",
    b"curv",
    b"curv2",
    b"surf",
    b"parm",
    b"trim",
    b"hole",
    b"scrv",
    b"sp",
    b"end",
    b"con",
    b"call",
    b"csh",
    b"lod",
    b"shadow_obj",
    b"trace_obj",
    b"ctech",
    b"stech",
    b"bevel",
    b"c_interp",
    b"d_interp",
    b"t",
];

/// The message for a bad record: when the line is not UTF-8, that is the problem to name
/// (a number or index with a stray byte), otherwise `message`.
fn why(line: &[u8], message: String) -> String {
    match std::str::from_utf8(line) {
        Ok(_) => message,
        Err(e) => non_utf8(line, e),
    }
}

fn non_utf8(line: &[u8], e: std::str::Utf8Error) -> String {
    format!(
        "not valid UTF-8 text: byte 0x{:02x} at column {}",
        line[e.valid_up_to()],
        e.valid_up_to() + 1
    )
}

fn read_vertex<'a>(
    b: &mut ObjBuilder,
    toks: impl Iterator<Item = &'a [u8]>,
    _line: usize,
) -> std::result::Result<(), String> {
    let mut vals = [0.0f64; 7];
    let mut n = 0;
    for t in toks {
        if n == 7 {
            return Err("a vertex has at most 7 numbers (x y z [w] or x y z r g b)".into());
        }
        vals[n] = parse_f64(t).ok_or_else(|| format!("{:?} is not a number", show(t)))?;
        n += 1;
    }
    if n < 3 {
        return Err(format!("a vertex needs 3 coordinates, found {n}"));
    }
    if let Some(c) = vals[..n].iter().find(|c| !c.is_finite()) {
        return Err(format!("vertex coordinate {c} is not finite"));
    }
    let index = b.mesh.positions.len();
    b.mesh.positions.push([vals[0], vals[1], vals[2]]);
    if n == 6 {
        // MeshLab's extension: r g b in [0, 1] after the position.
        if b.colors.len() < index {
            b.colors.resize(index, [255, 255, 255, 255]);
        }
        let c = |x: f64| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
        b.colors.push([c(vals[3]), c(vals[4]), c(vals[5]), 255]);
    }
    Ok(())
}

fn read_face<'a>(
    b: &mut ObjBuilder,
    toks: impl Iterator<Item = &'a [u8]>,
    line: usize,
) -> std::result::Result<(), String> {
    let vertex_count = b.mesh.positions.len() as i64;
    let uv_count = b.uv_coords.len() as i64;
    let normal_count = b.normal_count as i64;
    let first_corner = b.raw_indices.len();
    let mut with_uv = 0usize;
    for t in toks {
        let mut parts = t.split(|&c| c == b'/');
        let v = parts.next().unwrap_or_default();
        let vi = parse_i64(v).ok_or_else(|| format!("{:?} is not a vertex index", show(t)))?;
        if vi == 0 {
            return Err("vertex index 0: OBJ indices start at 1".into());
        }
        // Negative indices count back from the last vertex read so far.
        let resolved = if vi < 0 { vertex_count + vi } else { vi - 1 };
        if vi < 0 && resolved < 0 {
            return Err(format!(
                "relative vertex index {vi} reaches before the first vertex ({vertex_count} read so far)"
            ));
        }
        b.raw_indices.push(resolved);
        if let Some(vt) = parts.next().filter(|s| !s.is_empty()) {
            let ti =
                parse_i64(vt).ok_or_else(|| format!("{:?} is not a texture index", show(t)))?;
            let r = if ti < 0 { uv_count + ti } else { ti - 1 };
            if r < 0 || r >= uv_count {
                return Err(format!(
                    "texture index {ti} is out of range: {uv_count} texture coordinates read so far"
                ));
            }
            b.uv_corners.push(r as u32);
            with_uv += 1;
        }
        if let Some(vn) = parts.next().filter(|s| !s.is_empty()) {
            let ni = parse_i64(vn).ok_or_else(|| format!("{:?} is not a normal index", show(t)))?;
            let r = if ni < 0 { normal_count + ni } else { ni - 1 };
            if r < 0 || r >= normal_count {
                return Err(format!(
                    "normal index {ni} is out of range: {normal_count} normals (vn) read so far"
                ));
            }
        }
    }
    let arity = b.raw_indices.len() - first_corner;
    if with_uv != 0 && with_uv != arity {
        return Err("some corners of the face have a texture index and some do not".into());
    }
    if with_uv != 0 {
        b.faces_with_uv += 1;
    } else {
        // Keep uv_corners aligned with the corners of faces read so far.
        b.uv_corners.extend(std::iter::repeat_n(u32::MAX, arity));
    }
    b.face_lines.push(line);
    b.mesh.face_offsets.push(b.raw_indices.len() as u32);
    b.objects.of_face.push(b.current_object);
    b.groups.of_face.push(b.current_group);
    Ok(())
}

/// A tag record (OpenSubdiv's shapes: `t name nints/nfloats/nstrings ints floats
/// strings`). `crease` (pairs of vertices: one sharpness, or one per pair), `corner` (one
/// sharpness, or one per vertex) and `creasemethod` (`chaikin` or `normal`) are kept; other
/// tags (`interpolateboundary`, `hole`, …) are not part of surfkit's mesh and are skipped.
fn read_tag<'a>(
    b: &mut ObjBuilder,
    mut toks: impl Iterator<Item = &'a [u8]>,
    line: usize,
) -> std::result::Result<(), String> {
    let name = toks.next().ok_or("a tag needs a name")?;
    if !matches!(name, b"crease" | b"corner" | b"creasemethod") {
        return Ok(());
    }
    let tag = show(name);
    let counts = toks
        .next()
        .ok_or_else(|| format!("tag {tag:?} needs its counts (ints/floats/strings)"))?;
    let counts: Vec<usize> = counts
        .split(|&c| c == b'/')
        .map(|c| std::str::from_utf8(c).ok().and_then(|c| c.parse().ok()))
        .collect::<Option<Vec<usize>>>()
        .filter(|c| c.len() == 3)
        .ok_or_else(|| {
            format!(
                "tag {tag:?}: {:?} is not ints/floats/strings counts",
                show(counts)
            )
        })?;
    let (nints, nfloats, nstrings) = (counts[0], counts[1], counts[2]);
    let mut ints = Vec::new();
    let mut floats = Vec::new();
    let mut strings = Vec::new();
    for (i, t) in toks.by_ref().enumerate() {
        if i < nints {
            ints.push(
                parse_i64(t)
                    .ok_or_else(|| format!("tag {tag:?}: {:?} is not an integer", show(t)))?,
            );
        } else if i < nints + nfloats {
            let x = parse_f64(t)
                .ok_or_else(|| format!("tag {tag:?}: {:?} is not a number", show(t)))?;
            if !(x.is_finite() && x >= 0.0) {
                return Err(format!(
                    "tag {tag:?}: sharpness {x} must be a finite number ≥ 0"
                ));
            }
            floats.push(x as f32);
        } else if i < nints + nfloats + nstrings {
            strings.push(show(t));
        } else {
            return Err(format!(
                "tag {tag:?} has more values than its counts {nints}/{nfloats}/{nstrings}"
            ));
        }
    }
    if ints.len() != nints || floats.len() != nfloats || strings.len() != nstrings {
        return Err(format!(
            "tag {tag:?} has fewer values than its counts {nints}/{nfloats}/{nstrings}"
        ));
    }
    let features = b.mesh.sharp_features.get_or_insert_with(Default::default);
    match name {
        b"crease" => {
            let pairs = nints / 2;
            if nints < 2 || nints % 2 != 0 || !(nfloats == 1 || nfloats == pairs) {
                return Err(format!(
                    "tag \"crease\" takes pairs of vertices and one sharpness or one per pair, not {nints}/{nfloats}/{nstrings}"
                ));
            }
            for (p, pair) in ints.chunks(2).enumerate() {
                b.tag_vertices.extend(pair.iter().map(|&v| (v, line)));
                let s = floats[if nfloats == 1 { 0 } else { p }];
                features.creases.push(([pair[0] as u32, pair[1] as u32], s));
            }
        }
        b"corner" => {
            if nints == 0 || !(nfloats == 1 || nfloats == nints) {
                return Err(format!(
                    "tag \"corner\" takes vertices and one sharpness or one per vertex, not {nints}/{nfloats}/{nstrings}"
                ));
            }
            for (i, &v) in ints.iter().enumerate() {
                b.tag_vertices.push((v, line));
                features
                    .corners
                    .push((v as u32, floats[if nfloats == 1 { 0 } else { i }]));
            }
        }
        _ => match strings.as_slice() {
            [m] if m == "chaikin" => features.chaikin = true,
            [m] if m == "normal" || m == "uniform" => features.chaikin = false,
            _ => {
                return Err(format!(
                    "tag \"creasemethod\" takes one string, chaikin or normal, not {strings:?}"
                ))
            }
        },
    }
    Ok(())
}

fn finish(mut b: ObjBuilder, path: &Path, options: &ReadOptions) -> Result<PolygonMesh> {
    let n = b.mesh.positions.len();
    // Tags name vertices 0-based (OpenSubdiv's convention), unlike faces.
    if let Some(&(v, line)) = b
        .tag_vertices
        .iter()
        .find(|&&(v, _)| v < 0 || v >= n as i64)
    {
        return Err(Error::parse(
            path,
            Location::Line(line),
            format!(
                "tag vertex {v} is out of range: tags count vertices from 0, and there are {n}"
            ),
        ));
    }
    if b.mesh
        .sharp_features
        .as_ref()
        .is_some_and(SharpFeatures::is_empty)
    {
        b.mesh.sharp_features = None;
    }
    let mut indices = Vec::with_capacity(b.raw_indices.len());
    for (f, w) in b.mesh.face_offsets.windows(2).enumerate() {
        let corners = &b.raw_indices[w[0] as usize..w[1] as usize];
        let line = b.face_lines[f];
        for &i in corners {
            if let Some(m) = out_of_range(i, n, 1) {
                return Err(Error::parse(path, Location::Line(line), m));
            }
        }
        let start = indices.len();
        indices.extend(corners.iter().map(|&i| i as u32));
        if !options.keep_degenerate {
            if let Some(m) = degeneracy_as_written(&indices[start..], 1) {
                return Err(Error::parse(path, Location::Line(line), m));
            }
        }
    }
    b.mesh.face_indices = indices;
    let faces = b.mesh.face_count();
    if !b.colors.is_empty() {
        b.colors.resize(n, [255, 255, 255, 255]);
        b.mesh.colors = Some(b.colors);
    }
    if b.faces_with_uv == faces && faces > 0 {
        b.mesh.uvs = Some(CornerUvs {
            coords: b.uv_coords,
            corner_indices: b.uv_corners,
            untextured: None,
        });
    } else if b.faces_with_uv > 0 {
        // Some faces without texture indices: their corners point to one stand-in
        // coordinate, so the other faces keep theirs.
        let stand_in = b.uv_coords.len() as u32;
        b.uv_coords.push(CornerUvs::UNTEXTURED_VALUE);
        for k in &mut b.uv_corners {
            if *k == u32::MAX {
                *k = stand_in;
            }
        }
        b.mesh.uvs = Some(CornerUvs {
            coords: b.uv_coords,
            corner_indices: b.uv_corners,
            untextured: Some(stand_in),
        });
    }
    let labelled = |l: &FaceLabels| l.of_face.iter().any(|&i| i != NO_LABEL);
    if labelled(&b.objects) {
        b.mesh.objects = Some(b.objects);
    }
    if labelled(&b.groups) {
        b.mesh.groups = Some(b.groups);
    }
    Ok(b.mesh)
}

/// Writes OBJ text: positions in shortest round-trip form, faces 1-based, `o`/`g` records
/// where a face's label changes, `vt` and `f v/vt` when the mesh has UVs (`f v` for a face
/// without, whose stand-in coordinate is not written when it is the last one).
pub fn write(out: &mut dyn Write, mesh: &PolygonMesh) -> std::io::Result<()> {
    writeln!(out, "# written by surfkit {}", env!("CARGO_PKG_VERSION"))?;
    writeln!(
        out,
        "# {} vertices, {} faces",
        mesh.vertex_count(),
        mesh.face_count()
    )?;
    for (i, p) in mesh.positions.iter().enumerate() {
        out.write_all(b"v")?;
        for &c in p {
            out.write_all(b" ")?;
            write_f64(out, c)?;
        }
        if let Some(colors) = &mesh.colors {
            for &channel in &colors[i][..3] {
                out.write_all(b" ")?;
                write_f64(out, f64::from(channel) / 255.0)?;
            }
        }
        out.write_all(b"\n")?;
    }
    if let Some(uv) = &mesh.uvs {
        let written = match uv.untextured {
            Some(s) if s as usize + 1 == uv.coords.len() => s as usize,
            _ => uv.coords.len(),
        };
        for t in &uv.coords[..written] {
            out.write_all(b"vt ")?;
            write_f64(out, t[0])?;
            out.write_all(b" ")?;
            write_f64(out, t[1])?;
            out.write_all(b"\n")?;
        }
    }
    let mut itoa = itoa::Buffer::new();
    let (mut last_o, mut last_g) = (NO_LABEL, NO_LABEL);
    for (f, w) in mesh.face_offsets.windows(2).enumerate() {
        if let Some(objects) = &mesh.objects {
            let o = objects.of_face[f];
            if o != last_o && o != NO_LABEL {
                writeln!(out, "o {}", objects.names[o as usize])?;
            }
            last_o = o;
        }
        if let Some(groups) = &mesh.groups {
            let g = groups.of_face[f];
            if g != last_g && g != NO_LABEL {
                writeln!(out, "g {}", groups.names[g as usize])?;
            }
            last_g = g;
        }
        out.write_all(b"f")?;
        let uvs = mesh
            .uvs
            .as_ref()
            .filter(|uv| w[0] == w[1] || uv.is_textured(w[0] as usize));
        for k in w[0] as usize..w[1] as usize {
            out.write_all(b" ")?;
            out.write_all(itoa.format(mesh.face_indices[k] + 1).as_bytes())?;
            if let Some(uv) = uvs {
                out.write_all(b"/")?;
                out.write_all(itoa.format(uv.corner_indices[k] + 1).as_bytes())?;
            }
        }
        out.write_all(b"\n")?;
    }
    if let Some(sharp) = &mesh.sharp_features {
        for ([a, b], s) in &sharp.creases {
            writeln!(out, "t crease 2/1/0 {a} {b} {s}")?;
        }
        for (v, s) in &sharp.corners {
            writeln!(out, "t corner 1/1/0 {v} {s}")?;
        }
        if sharp.chaikin {
            writeln!(out, "t creasemethod 0/0/1 chaikin")?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(bytes: &[u8]) -> Result<PolygonMesh> {
        parse(Path::new("t.obj"), bytes, &ReadOptions::default())
    }

    #[test]
    fn group_name_after_leading_blanks() {
        let mesh = read(b"v 0 0 0\nv 1 0 0\nv 0 1 0\n  g  side  \nf 1 2 3\n").unwrap();
        assert_eq!(mesh.groups.unwrap().names, vec!["side".to_string()]);
    }

    #[test]
    fn inline_comments_end_every_record() {
        let mesh = read(
            b"# a quad and a triangle\n\
              v 0 0 0 # origin\n\
              v 1 0 0\t#x\n\
              v 1 1 0 # 7 8 9 (numbers in a comment are no colour)\n\
              v 0 1 0 #\n\
              vt 0 0 # uv\nvt 1 0\nvt 1 1\nvt 0 1\n\
              g part#2 # the left part\n\
              f 1/1 2/2 3/3 4/4 # the quad\n\
              o lid # top\n\
              f 1/1 3/3 4/4 #tri\n\
              t crease 2/1/0 0 2 1.5 # sharp\n",
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
        assert!(mesh.colors.is_none());
        assert_eq!(mesh.face_offsets, vec![0, 4, 7]);
        assert_eq!(mesh.face_indices, vec![0, 1, 2, 3, 0, 2, 3]);
        assert_eq!(mesh.uvs.unwrap().coords.len(), 4);
        assert_eq!(mesh.groups.unwrap().names, vec!["part#2".to_string()]);
        assert_eq!(mesh.objects.unwrap().names, vec!["lid".to_string()]);
        assert_eq!(mesh.sharp_features.unwrap().creases, vec![([0, 2], 1.5)]);
    }

    #[test]
    fn garbage_after_a_record_is_still_refused() {
        let quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";
        for (line, message) in [
            (
                "f 1 2 3 x # tri",
                "t.obj: line 5: \"x\" is not a vertex index",
            ),
            (
                "f 1 2 3#tri",
                "t.obj: line 5: \"3#tri\" is not a vertex index",
            ),
            ("v 1 2 3#c", "t.obj: line 5: \"3#c\" is not a number"),
            (
                "v 1 2 # 3",
                "t.obj: line 5: a vertex needs 3 coordinates, found 2",
            ),
        ] {
            let e = read(format!("{quad}{line}\n").as_bytes()).unwrap_err();
            assert_eq!(e.to_string(), message, "{line}");
        }
    }

    #[test]
    fn non_utf8_in_a_face_record_is_named() {
        let e = read(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 \xe93\n").unwrap_err();
        assert_eq!(
            e.to_string(),
            "t.obj: line 4: not valid UTF-8 text: byte 0xe9 at column 7"
        );
    }

    #[test]
    fn normal_indices_must_name_a_normal_read_before() {
        let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\n";
        // Absolute and relative indices of the one normal, with and without texture indices.
        for face in ["f 1//1 2//1 3//1", "f 1//-1 2//-1 3//-1"] {
            let mesh = read(format!("{tri}{face}\n").as_bytes()).unwrap();
            assert_eq!(mesh.face_indices, vec![0, 1, 2], "{face}");
        }
        for (face, message) in [
            (
                "f 1//2 2//2 3//2",
                "t.obj: line 5: normal index 2 is out of range: 1 normals (vn) read so far",
            ),
            (
                "f 1//-2 2//1 3//1",
                "t.obj: line 5: normal index -2 is out of range: 1 normals (vn) read so far",
            ),
            (
                "f 1//0 2//1 3//1",
                "t.obj: line 5: normal index 0 is out of range: 1 normals (vn) read so far",
            ),
            (
                "f 1//n 2//1 3//1",
                "t.obj: line 5: \"1//n\" is not a normal index",
            ),
        ] {
            let e = read(format!("{tri}{face}\n").as_bytes()).unwrap_err();
            assert_eq!(e.to_string(), message, "{face}");
        }
        // A normal defined after the face that names it is not one read before.
        let e = read(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\nvn 0 0 1\n").unwrap_err();
        assert!(e.to_string().contains("line 4: normal index 1"), "{e}");
    }

    #[test]
    fn faces_without_texture_indices_keep_the_others_uvs_and_write_back_without() {
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\n\
                    vt 0.25 0.5\nvt 0.75 0.5\nvt 0.5 1\n\
                    f 1/1 2/2 3/3\nf 1 3 4\nf 2 5 3\n";
        let mesh = read(text.as_bytes()).unwrap();
        let uv = mesh.uvs.as_ref().expect("the textured face keeps its UVs");
        assert_eq!(uv.untextured, Some(3));
        assert_eq!(uv.coords[3], CornerUvs::UNTEXTURED_VALUE);
        assert_eq!(uv.corner_indices, vec![0, 1, 2, 3, 3, 3, 3, 3, 3]);
        assert_eq!(uv.textured_faces(&mesh.face_offsets), 1);
        let mut out = Vec::new();
        write(&mut out, &mesh).unwrap();
        let written = String::from_utf8(out).unwrap();
        assert_eq!(written.matches("\nvt ").count(), 3, "{written}");
        assert!(
            written.contains("\nf 1/1 2/2 3/3\nf 1 3 4\nf 2 5 3\n"),
            "{written}"
        );
        assert_eq!(read(written.as_bytes()).unwrap(), mesh);
    }
}
