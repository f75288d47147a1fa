//! PLY: ASCII, binary little endian and binary big endian; any element and property layout.
//!
//! Read: `vertex` x, y, z (any numeric type), optional `quality`, `red green blue [alpha]`
//! (uchar, or float in [0, 1]), per-vertex texture coordinates (`u v`, `s t`,
//! `texture_u texture_v`); `face` `vertex_indices` (or `vertex_index`), MeshLab's wedge
//! `texcoord` list, and surfkit's `object_id`/`group_id` with names in `comment surfkit`
//! lines. Every other element and property is skipped, correctly sized.
//!
//! Why not a crate: `ply-rs` (and its fork `ply-rs-bw`) decode every element into a map
//! from property name to a boxed value, tens of times slower than the 1M-triangle target
//! of issue 2, and their errors name neither the element nor its byte offset. This reader
//! decodes straight into surfkit's flat arrays.

use std::io::Write;
use std::path::Path;

use super::face_check::{degeneracy_as_written, out_of_range};
use super::ply_fast;
use super::text::{parse_f64, show, tokens, Lines};
use super::ReadOptions;
use crate::error::{Error, Location, Result};
use crate::mesh::{CornerUvs, FaceLabels, PolygonMesh, NO_LABEL};

/// The encoding of a PLY body.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlyEncoding {
    Ascii,
    BinaryLittleEndian,
    BinaryBigEndian,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn from_name(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    /// Position in `ply_fast`'s decoder table.
    fn index(self) -> usize {
        self as usize
    }

    fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }
}

#[derive(Debug, Clone)]
enum Kind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

#[derive(Debug, Clone)]
struct Property {
    name: String,
    kind: Kind,
}

#[derive(Debug, Clone)]
struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

impl Element {
    fn find(&self, names: &[&str]) -> Option<usize> {
        names
            .iter()
            .find_map(|n| self.properties.iter().position(|p| p.name == *n))
    }
}

struct Header {
    encoding: PlyEncoding,
    elements: Vec<Element>,
    comments: Vec<String>,
    /// Byte offset of the body.
    body: usize,
    /// Line number of the first body line (ASCII).
    body_line: usize,
}

fn parse_header(path: &Path, bytes: &[u8]) -> Result<Header> {
    let err = |line: usize, msg: String| Error::parse(path, Location::Line(line), msg);
    let mut lines = Lines::new(bytes);
    match lines.next() {
        Some((_, l)) if l.trim_ascii_end() == b"ply" => {}
        _ => {
            return Err(Error::parse(
                path,
                Location::Header,
                "not a PLY file: the first line must be \"ply\"",
            ))
        }
    }
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut comments = Vec::new();
    for (number, line) in lines.by_ref() {
        let text = std::str::from_utf8(line)
            .map_err(|_| err(number, "the header is not ASCII text".into()))?;
        let mut words = text.split_ascii_whitespace();
        match words.next() {
            None => {}
            Some("format") => {
                encoding = Some(match (words.next(), words.next()) {
                    (Some("ascii"), Some("1.0")) => PlyEncoding::Ascii,
                    (Some("binary_little_endian"), Some("1.0")) => PlyEncoding::BinaryLittleEndian,
                    (Some("binary_big_endian"), Some("1.0")) => PlyEncoding::BinaryBigEndian,
                    _ => return Err(err(number, format!("unknown PLY format line {text:?}"))),
                })
            }
            Some("comment") | Some("obj_info") => {
                comments.push(text.split_once(' ').map_or("", |x| x.1).to_string())
            }
            Some("element") => {
                let (Some(name), Some(count), None) = (words.next(), words.next(), words.next())
                else {
                    return Err(err(number, format!("malformed element line {text:?}")));
                };
                let count = count
                    .parse()
                    .map_err(|_| err(number, format!("element count {count:?} is not a count")))?;
                elements.push(Element {
                    name: name.to_string(),
                    count,
                    properties: Vec::new(),
                });
            }
            Some("property") => {
                let Some(element) = elements.last_mut() else {
                    return Err(err(number, "property before any element".into()));
                };
                let ws: Vec<&str> = words.collect();
                let ty = |s: &str| {
                    Scalar::from_name(s)
                        .ok_or_else(|| err(number, format!("unknown property type {s:?}")))
                };
                let property = match ws.as_slice() {
                    ["list", c, i, name] => {
                        let count = ty(c)?;
                        if !count.is_integer() {
                            return Err(err(
                                number,
                                format!("list count type {c:?} is not an integer type"),
                            ));
                        }
                        Property {
                            name: name.to_string(),
                            kind: Kind::List {
                                count,
                                item: ty(i)?,
                            },
                        }
                    }
                    [t, name] => Property {
                        name: name.to_string(),
                        kind: Kind::Scalar(ty(t)?),
                    },
                    _ => return Err(err(number, format!("malformed property line {text:?}"))),
                };
                element.properties.push(property);
            }
            Some("end_header") => {
                let encoding = encoding
                    .ok_or_else(|| err(number, "end_header before any format line".into()))?;
                return Ok(Header {
                    encoding,
                    elements,
                    comments,
                    body: bytes.len() - lines.rest().len(),
                    body_line: number + 1,
                });
            }
            Some(other) if parse_f64(other.as_bytes()).is_some() => {
                return Err(err(
                    number,
                    format!("data {other:?} in the header: the end_header line is missing"),
                ))
            }
            Some(other) => return Err(err(number, format!("unknown header keyword {other:?}"))),
        }
    }
    Err(Error::parse(
        path,
        Location::Header,
        "the header has no end_header line",
    ))
}

/// Where each property of interest sits in its element.
#[derive(Default)]
struct Roles {
    xyz: [usize; 3],
    quality: Option<usize>,
    rgba: Option<[Option<usize>; 4]>,
    vertex_uv: Option<[usize; 2]>,
    corners: usize,
    texcoord: Option<usize>,
    object: Option<usize>,
    group: Option<usize>,
}

/// A source of property values: ASCII tokens of one line, or a binary cursor.
trait Values {
    fn scalar(&mut self, t: Scalar) -> std::result::Result<f64, String>;
}

struct AsciiValues<'a, I: Iterator<Item = &'a [u8]>> {
    tokens: I,
}

impl<'a, I: Iterator<Item = &'a [u8]>> Values for AsciiValues<'a, I> {
    fn scalar(&mut self, t: Scalar) -> std::result::Result<f64, String> {
        let tok = self
            .tokens
            .next()
            .ok_or_else(|| "the line has fewer values than the header declares".to_string())?;
        let v = parse_f64(tok).ok_or_else(|| format!("{:?} is not a number", show(tok)))?;
        if t.is_integer() && v.fract() != 0.0 {
            return Err(format!("{:?} is not an integer", show(tok)));
        }
        Ok(v)
    }
}

struct BinaryValues<'a> {
    data: &'a [u8],
    pos: usize,
    big_endian: bool,
}

impl BinaryValues<'_> {
    #[inline]
    fn take<const N: usize>(&mut self) -> std::result::Result<[u8; N], String> {
        let end = self.pos + N;
        let bytes: [u8; N] = self
            .data
            .get(self.pos..end)
            .ok_or_else(|| "the file ends inside this element".to_string())?
            .try_into()
            .unwrap();
        self.pos = end;
        Ok(bytes)
    }
}

macro_rules! decode {
    ($self:ident, $ty:ty) => {{
        let b = $self.take::<{ std::mem::size_of::<$ty>() }>()?;
        (if $self.big_endian {
            <$ty>::from_be_bytes(b)
        } else {
            <$ty>::from_le_bytes(b)
        }) as f64
    }};
}

impl Values for BinaryValues<'_> {
    #[inline]
    fn scalar(&mut self, t: Scalar) -> std::result::Result<f64, String> {
        Ok(match t {
            Scalar::I8 => decode!(self, i8),
            Scalar::U8 => decode!(self, u8),
            Scalar::I16 => decode!(self, i16),
            Scalar::U16 => decode!(self, u16),
            Scalar::I32 => decode!(self, i32),
            Scalar::U32 => decode!(self, u32),
            Scalar::F32 => decode!(self, f32),
            Scalar::F64 => decode!(self, f64),
        })
    }
}

/// Where an element instance was read, for errors: its line (ASCII) or byte offset.
#[derive(Clone, Copy)]
struct Place {
    line: Option<usize>,
    byte_offset: usize,
}

impl Place {
    /// A parse error of instance `index` of `element`, located at this place.
    fn error(self, path: &Path, element: &Element, index: usize, msg: String) -> Error {
        match self.line {
            Some(l) => Error::parse(
                path,
                Location::Line(l),
                format!("{} {index}: {msg}", element.name),
            ),
            None => Error::parse(
                path,
                Location::Element {
                    kind: element.name.clone(),
                    index,
                    byte_offset: self.byte_offset,
                },
                msg,
            ),
        }
    }
}

/// The body of a PLY file, read one element instance at a time: ASCII one instance per
/// (non-blank) line, binary as a byte cursor.
struct Body<'a> {
    ascii: bool,
    lines: Lines<'a>,
    line_offset: usize,
    /// The last line read (for "the file ends" errors).
    last_line: usize,
    binary: BinaryValues<'a>,
}

impl<'a> Body<'a> {
    fn new(bytes: &'a [u8], header: &Header) -> Self {
        let line_offset = header.body_line - 1;
        Body {
            ascii: header.encoding == PlyEncoding::Ascii,
            lines: Lines::new(&bytes[header.body..]),
            line_offset,
            last_line: line_offset,
            binary: BinaryValues {
                data: bytes,
                pos: header.body,
                big_endian: header.encoding == PlyEncoding::BinaryBigEndian,
            },
        }
    }

    /// Reads instance `index` of `element` into `slots` and `lists` (see
    /// [`read_instance`]); an ASCII line must hold exactly the declared values.
    fn instance(
        &mut self,
        path: &Path,
        element: &Element,
        index: usize,
        slots: &mut [f64],
        lists: &mut [Vec<f64>],
    ) -> Result<Place> {
        let byte_offset = self.binary.pos;
        if !self.ascii {
            let place = Place {
                line: None,
                byte_offset,
            };
            read_instance(element, &mut self.binary, slots, lists)
                .map_err(|m| place.error(path, element, index, m))?;
            return Ok(place);
        }
        let (n, line) = loop {
            match self.lines.next() {
                Some((n, l)) if l.trim_ascii().is_empty() => self.last_line = n + self.line_offset,
                Some((n, l)) => break (n + self.line_offset, l),
                None => {
                    let place = Place {
                        line: Some(self.last_line),
                        byte_offset,
                    };
                    return Err(place.error(
                        path,
                        element,
                        index,
                        format!(
                            "the file ends after {index} of the {} {} elements the header declares",
                            element.count, element.name
                        ),
                    ));
                }
            }
        };
        self.last_line = n;
        let place = Place {
            line: Some(n),
            byte_offset,
        };
        let mut src = AsciiValues {
            tokens: tokens(line),
        };
        read_instance(element, &mut src, slots, lists)
            .map_err(|m| place.error(path, element, index, m))?;
        if let Some(extra) = src.tokens.next() {
            return Err(place.error(
                path,
                element,
                index,
                format!(
                    "more values than the header declares for {} (extra {:?}){}",
                    element.name,
                    show(extra),
                    // OBJ and OFF have `#` comments; PLY has them only in its header.
                    if extra.starts_with(b"#") {
                        "; PLY has no comments after its header (only `comment` header lines)"
                    } else {
                        ""
                    }
                ),
            ));
        }
        Ok(place)
    }
}

/// Reads one element instance, storing the values of properties of interest in `slots`
/// (by property position) and list items of the property at `list_of_interest` in `items`.
fn read_instance(
    element: &Element,
    src: &mut dyn Values,
    slots: &mut [f64],
    lists: &mut [Vec<f64>],
) -> std::result::Result<(), String> {
    for (k, p) in element.properties.iter().enumerate() {
        match p.kind {
            Kind::Scalar(t) => slots[k] = src.scalar(t)?,
            Kind::List { count, item } => {
                let n = src.scalar(count)?;
                if n < 0.0 {
                    return Err(format!("list {:?} has a negative length {n}", p.name));
                }
                let list = &mut lists[k];
                list.clear();
                for _ in 0..n as usize {
                    list.push(src.scalar(item)?);
                }
            }
        }
    }
    Ok(())
}

pub fn parse(path: &Path, bytes: &[u8], options: &ReadOptions) -> Result<PolygonMesh> {
    let header = parse_header(path, bytes)?;
    let hdr_err = |msg: String| Error::parse(path, Location::Header, msg);
    let vertex = header
        .elements
        .iter()
        .position(|e| e.name == "vertex")
        .ok_or_else(|| hdr_err("no \"vertex\" element".into()))?;
    let face = header.elements.iter().position(|e| e.name == "face");
    let mut roles = Roles::default();
    {
        let v = &header.elements[vertex];
        for (axis, name) in ["x", "y", "z"].iter().enumerate() {
            roles.xyz[axis] = v
                .find(&[name])
                .filter(|&k| matches!(v.properties[k].kind, Kind::Scalar(_)))
                .ok_or_else(|| {
                    hdr_err(format!("element vertex has no scalar property {name:?}"))
                })?;
        }
        roles.quality = v.find(&["quality"]);
        let red = v.find(&["red", "diffuse_red"]);
        if red.is_some() {
            roles.rgba = Some([
                red,
                v.find(&["green", "diffuse_green"]),
                v.find(&["blue", "diffuse_blue"]),
                v.find(&["alpha"]),
            ]);
        }
        roles.vertex_uv = [["u", "v"], ["s", "t"], ["texture_u", "texture_v"]]
            .iter()
            .find_map(|[a, b]| Some([v.find(&[a])?, v.find(&[b])?]));
    }
    if let Some(f) = face {
        let f = &header.elements[f];
        roles.corners = f
            .find(&["vertex_indices", "vertex_index"])
            .filter(|&k| matches!(f.properties[k].kind, Kind::List { .. }))
            .ok_or_else(|| hdr_err("element face has no list property vertex_indices".into()))?;
        roles.texcoord = f
            .find(&["texcoord"])
            .filter(|&k| matches!(f.properties[k].kind, Kind::List { .. }));
        roles.object = f.find(&["object_id"]);
        roles.group = f.find(&["group_id"]);
    }

    let mut mesh = PolygonMesh::default();
    let mut vertices = VertexArrays::default();
    let mut wedge_uv = CornerUvs::default();
    let mut objects = FaceLabels::default();
    let mut groups = FaceLabels::default();
    // Faces are checked against the declared count, so that a face element declared before
    // the vertex element is read right; the vertex element must then hold that many.
    let vertex_count = header.elements[vertex].count;
    // Counts are not trusted with memory: every instance takes at least one byte.
    let room = bytes.len() - header.body;

    let mut body = Body::new(bytes, &header);

    for (ei, element) in header.elements.iter().enumerate() {
        let mut slots = vec![0.0; element.properties.len()];
        let mut lists = vec![Vec::new(); element.properties.len()];
        let is_vertex = ei == vertex;
        let is_face = Some(ei) == face;
        if element.properties.is_empty() {
            // Nothing to read (and a huge count must not spin).
            continue;
        }
        if is_vertex {
            vertices.positions.reserve_exact(element.count.min(room));
        }
        // Binary fast paths for the common layouts (see ply_fast).
        let big_endian = header.encoding == PlyEncoding::BinaryBigEndian;
        if header.encoding != PlyEncoding::Ascii && is_vertex && all_scalar(element) {
            let (offsets, decode, stride) = fixed_layout(element, big_endian);
            let start = body.binary.pos;
            body.binary.pos = ply_fast::read_fixed_records(
                bytes,
                start,
                element.count,
                stride,
                &offsets,
                &decode,
                |_, slots| vertices.push(&roles, element, slots),
            )
            .map_err(|(index, m)| {
                Error::parse(
                    path,
                    Location::Element {
                        kind: element.name.clone(),
                        index,
                        byte_offset: start + index * stride,
                    },
                    m,
                )
            })?;
            continue;
        }
        if header.encoding != PlyEncoding::Ascii && is_face && fast_face(element, roles.corners) {
            let Kind::List { count, item } = element.properties[roles.corners].kind else {
                unreachable!("fast_face checked the corner list")
            };
            mesh.face_offsets.reserve_exact(element.count.min(room));
            mesh.face_indices
                .reserve(element.count.min(room).saturating_mul(3));
            let keep = options.keep_degenerate;
            body.binary.pos = ply_fast::read_list_faces(
                bytes,
                body.binary.pos,
                element.count,
                (ply_fast::decoder(count.index(), big_endian), count.size()),
                (ply_fast::decoder(item.index(), big_endian), item.size()),
                vertex_count,
                &mut mesh.face_indices,
                &mut mesh.face_offsets,
                |corners| {
                    if keep {
                        None
                    } else {
                        degeneracy_as_written(corners, 0)
                    }
                },
            )
            .map_err(|(index, byte_offset, m)| {
                Error::parse(
                    path,
                    Location::Element {
                        kind: element.name.clone(),
                        index,
                        byte_offset,
                    },
                    m,
                )
            })?;
            continue;
        }
        if is_face {
            mesh.face_offsets.reserve_exact(element.count);
            mesh.face_indices.reserve(element.count * 3);
        }
        for index in 0..element.count {
            let place = body.instance(path, element, index, &mut slots, &mut lists)?;
            let fail = |m: String| place.error(path, element, index, m);
            if is_vertex {
                vertices.push(&roles, element, &slots).map_err(fail)?;
            } else if is_face {
                let start = mesh.face_indices.len();
                for &i in &lists[roles.corners] {
                    let i = corner_index(i).map_err(fail)?;
                    if let Some(m) = out_of_range(i, vertex_count, 0) {
                        return Err(fail(m));
                    }
                    mesh.face_indices.push(i as u32);
                }
                if !options.keep_degenerate {
                    if let Some(m) = degeneracy_as_written(&mesh.face_indices[start..], 0) {
                        return Err(fail(m));
                    }
                }
                mesh.face_offsets.push(mesh.face_indices.len() as u32);
                if let Some(t) = roles.texcoord {
                    let tc = &lists[t];
                    let arity = mesh.face_indices.len() - start;
                    if tc.len() != 2 * arity {
                        return Err(fail(format!(
                            "texcoord has {} values for a face of {arity} corners (expected {})",
                            tc.len(),
                            2 * arity
                        )));
                    }
                    if let Some(c) = tc.iter().find(|c| !c.is_finite()) {
                        return Err(fail(format!("texcoord value {c} is not finite")));
                    }
                    for uv in tc.chunks_exact(2) {
                        wedge_uv.corner_indices.push(wedge_uv.coords.len() as u32);
                        wedge_uv.coords.push([uv[0], uv[1]]);
                    }
                }
                for (role, labels) in [(roles.object, &mut objects), (roles.group, &mut groups)] {
                    if let Some(k) = role {
                        let id = slots[k];
                        if id.fract() != 0.0 {
                            return Err(fail(format!(
                                "{} {id} is not an integer",
                                element.properties[k].name
                            )));
                        }
                        // Ids past the names in the header are refused below.
                        labels.of_face.push(if id < 0.0 {
                            NO_LABEL
                        } else {
                            id.min(f64::from(NO_LABEL - 1)) as u32
                        });
                    }
                }
            }
        }
    }
    if header.encoding == PlyEncoding::Ascii {
        if let Some((n, l)) = body.lines.find(|(_, l)| !l.trim_ascii().is_empty()) {
            return Err(Error::parse(
                path,
                Location::Line(n + body.line_offset),
                format!(
                    "data after the last element the header declares ({:?}): the header's counts are wrong",
                    show(l)
                ),
            ));
        }
    } else if body.binary.pos != bytes.len() {
        return Err(Error::parse(
            path,
            Location::Element {
                kind: "end of data".into(),
                index: 0,
                byte_offset: body.binary.pos,
            },
            format!(
                "{} bytes after the last element the header declares: the header's counts are wrong",
                bytes.len() - body.binary.pos
            ),
        ));
    }
    mesh.positions = vertices.positions;
    if roles.quality.is_some() {
        mesh.quality = Some(vertices.quality);
    }
    if roles.rgba.is_some() {
        mesh.colors = Some(vertices.colors);
    }
    if roles.texcoord.is_some() && face.is_some() {
        mesh.uvs = Some(wedge_uv);
    } else if roles.vertex_uv.is_some() {
        mesh.uvs = Some(CornerUvs {
            coords: vertices.uv,
            corner_indices: mesh.face_indices.clone(),
            untextured: None,
        });
    }
    for (kind, role, mut labels, slot) in [
        ("object", roles.object, objects, &mut mesh.objects),
        ("group", roles.group, groups, &mut mesh.groups),
    ] {
        if role.is_none() {
            continue;
        }
        labels.names = label_names(&header.comments, kind);
        if let Some(f) = labels
            .of_face
            .iter()
            .position(|&i| i != NO_LABEL && i as usize >= labels.names.len())
        {
            return Err(hdr_err(format!(
                "face {f} has {kind}_id {} but the header names only {} {kind}s",
                labels.of_face[f],
                labels.names.len()
            )));
        }
        *slot = Some(labels);
    }
    Ok(mesh)
}

/// The vertex columns surfkit keeps, filled record by record.
#[derive(Default)]
struct VertexArrays {
    positions: Vec<[f64; 3]>,
    quality: Vec<f64>,
    colors: Vec<[u8; 4]>,
    uv: Vec<[f64; 2]>,
}

impl VertexArrays {
    /// Stores one vertex record whose property values are `slots`.
    fn push(
        &mut self,
        roles: &Roles,
        element: &Element,
        slots: &[f64],
    ) -> std::result::Result<(), String> {
        let p = [
            slots[roles.xyz[0]],
            slots[roles.xyz[1]],
            slots[roles.xyz[2]],
        ];
        if !p.iter().all(|c| c.is_finite()) {
            return Err(format!("coordinates {p:?} are not finite"));
        }
        self.positions.push(p);
        if let Some(q) = roles.quality {
            let q = slots[q];
            if !q.is_finite() {
                return Err(format!("quality {q} is not finite"));
            }
            self.quality.push(q);
        }
        if let Some(rgba) = roles.rgba {
            if let Some(c) = rgba
                .iter()
                .flatten()
                .map(|&k| slots[k])
                .find(|c| !c.is_finite())
            {
                return Err(format!("colour value {c} is not finite"));
            }
            self.colors.push(rgba_of(element, slots, rgba));
        }
        if let Some([u, v]) = roles.vertex_uv {
            let uv = [slots[u], slots[v]];
            if !uv.iter().all(|c| c.is_finite()) {
                return Err(format!("texture coordinates {uv:?} are not finite"));
            }
            self.uv.push(uv);
        }
        Ok(())
    }
}

fn all_scalar(element: &Element) -> bool {
    element
        .properties
        .iter()
        .all(|p| matches!(p.kind, Kind::Scalar(_)))
}

/// Offsets, decoders and record size of an element of scalar properties only.
fn fixed_layout(element: &Element, big_endian: bool) -> (Vec<usize>, Vec<ply_fast::Decode>, usize) {
    let mut offsets = Vec::new();
    let mut decode = Vec::new();
    let mut stride = 0;
    for p in &element.properties {
        if let Kind::Scalar(t) = p.kind {
            offsets.push(stride);
            decode.push(ply_fast::decoder(t.index(), big_endian));
            stride += t.size();
        }
    }
    (offsets, decode, stride)
}

/// A corner's vertex index as read (any numeric type): an error unless it is an integer.
fn corner_index(i: f64) -> std::result::Result<i64, String> {
    if i.fract() == 0.0 {
        Ok(i as i64)
    } else {
        Err(format!("vertex index {i} is not an integer"))
    }
}

/// Whether a face element holds only the corner list (the layout of most binary PLY files).
fn fast_face(element: &Element, corners: usize) -> bool {
    element.properties.len() == 1 && corners == 0
}

fn rgba_of(element: &Element, slots: &[f64], rgba: [Option<usize>; 4]) -> [u8; 4] {
    let mut c = [255u8; 4];
    for (k, slot) in rgba.iter().enumerate() {
        if let Some(i) = *slot {
            let v = slots[i];
            let floating = matches!(
                element.properties[i].kind,
                Kind::Scalar(Scalar::F32 | Scalar::F64)
            );
            c[k] = if floating {
                (v.clamp(0.0, 1.0) * 255.0).round() as u8
            } else {
                v.clamp(0.0, 255.0) as u8
            };
        }
    }
    c
}

/// Label names from `comment surfkit object|group <id> <name>` header lines.
fn label_names(comments: &[String], kind: &str) -> Vec<String> {
    let mut names: Vec<(usize, String)> = comments
        .iter()
        .filter_map(|c| {
            let rest = c
                .strip_prefix("surfkit ")?
                .strip_prefix(kind)?
                .strip_prefix(' ')?;
            let (id, name) = rest.split_once(' ').unwrap_or((rest, ""));
            Some((id.parse().ok()?, name.to_string()))
        })
        .collect();
    names.sort_by_key(|(i, _)| *i);
    names.into_iter().map(|(_, n)| n).collect()
}

/// The values of one scalar property of the `vertex` element: the first of `names` the
/// header declares, with its name, or `None` when it declares none of them. For per-vertex
/// data `parse` does not keep, such as MeshLab's selection in `flags`. Decodes the
/// elements up to the vertex element, one instance at a time (no fast path: selections are
/// small files).
///
/// # Errors
/// [`Error::Parse`] naming the line (ASCII) or element and byte offset (binary) of a
/// malformed or truncated instance, or the header.
pub fn read_vertex_property(
    path: &Path,
    bytes: &[u8],
    names: &[&str],
) -> Result<Option<(String, Vec<f64>)>> {
    let header = parse_header(path, bytes)?;
    let vertex = header
        .elements
        .iter()
        .position(|e| e.name == "vertex")
        .ok_or_else(|| Error::parse(path, Location::Header, "no \"vertex\" element"))?;
    let element = &header.elements[vertex];
    let Some(k) = element
        .find(names)
        .filter(|&k| matches!(element.properties[k].kind, Kind::Scalar(_)))
    else {
        return Ok(None);
    };
    let mut body = Body::new(bytes, &header);
    let mut values = Vec::new();
    for (ei, element) in header.elements.iter().enumerate().take(vertex + 1) {
        if element.properties.is_empty() {
            continue;
        }
        let mut slots = vec![0.0; element.properties.len()];
        let mut lists = vec![Vec::new(); element.properties.len()];
        for index in 0..element.count {
            body.instance(path, element, index, &mut slots, &mut lists)?;
            if ei == vertex {
                values.push(slots[k]);
            }
        }
    }
    Ok(Some((element.properties[k].name.clone(), values)))
}

/// Writes PLY: double positions, `double quality`, `uchar` RGBA, corner lists, MeshLab's
/// wedge `texcoord`, and surfkit's `object_id`/`group_id` with names in comments. A face
/// without texture coordinates is written with its stand-in (0, 0) at each corner: a
/// `texcoord` list holds two numbers per corner (surfkit's reader refuses other lengths).
pub fn write(
    out: &mut dyn Write,
    mesh: &PolygonMesh,
    encoding: PlyEncoding,
) -> std::io::Result<()> {
    let format = match encoding {
        PlyEncoding::Ascii => "ascii",
        PlyEncoding::BinaryLittleEndian => "binary_little_endian",
        PlyEncoding::BinaryBigEndian => "binary_big_endian",
    };
    let max_arity = mesh
        .face_offsets
        .windows(2)
        .map(|w| w[1] - w[0])
        .max()
        .unwrap_or(0);
    let count_type = if max_arity <= 255 { "uchar" } else { "int" };
    writeln!(
        out,
        "ply\nformat {format} 1.0\ncomment written by surfkit {}",
        env!("CARGO_PKG_VERSION")
    )?;
    for (kind, labels) in [("object", &mesh.objects), ("group", &mesh.groups)] {
        if let Some(l) = labels {
            for (i, n) in l.names.iter().enumerate() {
                writeln!(
                    out,
                    "comment surfkit {kind} {i} {}",
                    n.replace(['\n', '\r'], " ")
                )?;
            }
        }
    }
    writeln!(out, "element vertex {}", mesh.vertex_count())?;
    writeln!(
        out,
        "property double x\nproperty double y\nproperty double z"
    )?;
    if mesh.quality.is_some() {
        writeln!(out, "property double quality")?;
    }
    if mesh.colors.is_some() {
        writeln!(
            out,
            "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha"
        )?;
    }
    writeln!(out, "element face {}", mesh.face_count())?;
    writeln!(out, "property list {count_type} int vertex_indices")?;
    if mesh.uvs.is_some() {
        writeln!(out, "property list {count_type} double texcoord")?;
    }
    if mesh.objects.is_some() {
        writeln!(out, "property int object_id")?;
    }
    if mesh.groups.is_some() {
        writeln!(out, "property int group_id")?;
    }
    writeln!(out, "end_header")?;
    let mut enc = Encoder { out, encoding };
    for (v, p) in mesh.positions.iter().enumerate() {
        enc.f64(p[0])?;
        enc.f64(p[1])?;
        enc.f64(p[2])?;
        if let Some(q) = &mesh.quality {
            enc.f64(q[v])?;
        }
        if let Some(c) = &mesh.colors {
            for &b in &c[v] {
                enc.int(i64::from(b), 1)?;
            }
        }
        enc.end_line()?;
    }
    let count_size = if count_type == "uchar" { 1 } else { 4 };
    for (f, w) in mesh.face_offsets.windows(2).enumerate() {
        let range = w[0] as usize..w[1] as usize;
        enc.int(range.len() as i64, count_size)?;
        for &i in &mesh.face_indices[range.clone()] {
            enc.int(i64::from(i), 4)?;
        }
        if let Some(uv) = &mesh.uvs {
            enc.int(2 * range.len() as i64, count_size)?;
            for &k in &uv.corner_indices[range] {
                let t = uv.coords[k as usize];
                enc.f64(t[0])?;
                enc.f64(t[1])?;
            }
        }
        for labels in [&mesh.objects, &mesh.groups].into_iter().flatten() {
            let id = labels.of_face[f];
            enc.int(if id == NO_LABEL { -1 } else { i64::from(id) }, 4)?;
        }
        enc.end_line()?;
    }
    Ok(())
}

/// Writes values in one of the three encodings.
struct Encoder<'a> {
    out: &'a mut dyn Write,
    encoding: PlyEncoding,
}

impl Encoder<'_> {
    fn f64(&mut self, x: f64) -> std::io::Result<()> {
        match self.encoding {
            PlyEncoding::Ascii => {
                super::text::write_f64(self.out, x)?;
                self.out.write_all(b" ")
            }
            PlyEncoding::BinaryLittleEndian => self.out.write_all(&x.to_le_bytes()),
            PlyEncoding::BinaryBigEndian => self.out.write_all(&x.to_be_bytes()),
        }
    }

    /// An integer of `size` bytes (1: uchar, 4: int).
    fn int(&mut self, x: i64, size: usize) -> std::io::Result<()> {
        match (self.encoding, size) {
            (PlyEncoding::Ascii, _) => write!(self.out, "{x} "),
            (_, 1) => self.out.write_all(&[x as u8]),
            (PlyEncoding::BinaryLittleEndian, _) => self.out.write_all(&(x as i32).to_le_bytes()),
            (PlyEncoding::BinaryBigEndian, _) => self.out.write_all(&(x as i32).to_be_bytes()),
        }
    }

    fn end_line(&mut self) -> std::io::Result<()> {
        if self.encoding == PlyEncoding::Ascii {
            self.out.write_all(b"\n")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TRIANGLE_ASCII: &str = "0 0 0\n1 0 0\n0 1 0\n";

    fn read(bytes: &[u8]) -> Result<PolygonMesh> {
        parse(Path::new("t.ply"), bytes, &ReadOptions::default())
    }

    fn message(bytes: &[u8]) -> (Location, String) {
        match read(bytes) {
            Err(Error::Parse {
                location, message, ..
            }) => (location, message),
            other => panic!("expected a parse error, got {other:?}"),
        }
    }

    /// A binary little-endian file: the given header lines, then `body`.
    fn binary(header: &str, body: &[u8]) -> Vec<u8> {
        let mut b =
            format!("ply\nformat binary_little_endian 1.0\n{header}end_header\n").into_bytes();
        b.extend_from_slice(body);
        b
    }

    fn triangle_vertices() -> Vec<u8> {
        [0f32, 0., 0., 1., 0., 0., 0., 1., 0.]
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect()
    }

    const XYZ: &str = "property float x\nproperty float y\nproperty float z\n";

    #[test]
    fn face_element_before_vertex_element() {
        let text = format!(
            "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\n\
             element vertex 3\n{XYZ}end_header\n3 0 1 2\n{TRIANGLE_ASCII}"
        );
        let mesh = read(text.as_bytes()).unwrap();
        assert_eq!(mesh.faces().collect::<Vec<_>>(), vec![&[0u32, 1, 2][..]]);
        assert_eq!(mesh.vertex_count(), 3);
    }

    #[test]
    fn element_without_properties_and_a_huge_count_is_skipped() {
        let header = format!("element junk {}\nelement vertex 3\n{XYZ}", usize::MAX);
        let mesh = read(&binary(&header, &triangle_vertices())).unwrap();
        assert_eq!(mesh.vertex_count(), 3);
    }

    #[test]
    fn huge_declared_counts_do_not_size_allocations() {
        let header = format!(
            "element vertex {}\n{XYZ}element face {}\nproperty list uchar int vertex_indices\n",
            usize::MAX,
            usize::MAX
        );
        let (location, m) = message(&binary(&header, &triangle_vertices()));
        assert_eq!(m, "the file ends inside this element");
        let body = binary(&header, b"").len();
        assert_eq!(
            location,
            Location::Element {
                kind: "vertex".into(),
                index: 3,
                byte_offset: body + 36
            }
        );
        let ascii = format!(
            "ply\nformat ascii 1.0\nelement vertex {}\n{XYZ}end_header\n",
            usize::MAX
        );
        let (location, m) = message(ascii.as_bytes());
        assert_eq!(location, Location::Line(7));
        assert!(
            m.contains("the file ends after 0 of the 18446744073709551615 vertex elements"),
            "{m}"
        );
    }

    #[test]
    fn negative_list_length_on_the_binary_fast_path() {
        let header = format!(
            "element vertex 3\n{XYZ}element face 1\nproperty list char int vertex_indices\n"
        );
        let mut body = triangle_vertices();
        body.push(0xff); // -1 as char
        let (location, m) = message(&binary(&header, &body));
        assert_eq!(m, "the face has a negative corner count -1");
        assert!(matches!(location, Location::Element { ref kind, index: 0, .. } if kind == "face"));
    }

    #[test]
    fn corner_indices_must_be_integers() {
        let text = format!(
            "ply\nformat ascii 1.0\nelement vertex 3\n{XYZ}element face 1\n\
             property list uchar float vertex_indices\nend_header\n{TRIANGLE_ASCII}3 0 1.5 2\n"
        );
        assert_eq!(
            message(text.as_bytes()),
            (
                Location::Line(13),
                "face 0: vertex index 1.5 is not an integer".into()
            )
        );
        let header = format!(
            "element vertex 3\n{XYZ}element face 1\nproperty list uchar float vertex_indices\n"
        );
        let mut body = triangle_vertices();
        body.push(3);
        for x in [0f32, f32::NAN, 2.0] {
            body.extend_from_slice(&x.to_le_bytes());
        }
        assert_eq!(
            message(&binary(&header, &body)).1,
            "vertex index NaN is not an integer"
        );
    }

    #[test]
    fn non_finite_quality_and_uv_are_refused() {
        let text = format!(
            "ply\nformat ascii 1.0\nelement vertex 1\n{XYZ}property float quality\nend_header\n0 0 0 nan\n"
        );
        assert_eq!(
            message(text.as_bytes()),
            (
                Location::Line(9),
                "vertex 0: quality NaN is not finite".into()
            )
        );
        let text = format!(
            "ply\nformat ascii 1.0\nelement vertex 1\n{XYZ}property float u\nproperty float v\nend_header\n0 0 0 inf 0\n"
        );
        assert_eq!(
            message(text.as_bytes()),
            (
                Location::Line(10),
                "vertex 0: texture coordinates [inf, 0.0] are not finite".into()
            )
        );
    }

    #[test]
    fn non_finite_colour_is_refused() {
        let text = format!(
            "ply\nformat ascii 1.0\nelement vertex 1\n{XYZ}property float red\nend_header\n0 0 0 nan\n"
        );
        assert_eq!(
            message(text.as_bytes()),
            (
                Location::Line(9),
                "vertex 0: colour value NaN is not finite".into()
            )
        );
    }

    /// PLY's comments are `comment` header lines (Turk's specification): the data have no
    /// comment syntax, so a `#` there is refused, with the reason.
    #[test]
    fn a_comment_in_ascii_data_is_refused_with_the_reason() {
        let text = format!(
            "ply\nformat ascii 1.0\ncomment fine here\nelement vertex 3\n{XYZ}end_header\n\
             0 0 0 # origin\n1 0 0\n0 1 0\n"
        );
        assert_eq!(
            message(text.as_bytes()),
            (
                Location::Line(9),
                "vertex 0: more values than the header declares for vertex (extra \"#\"); PLY \
                 has no comments after its header (only `comment` header lines)"
                    .into()
            )
        );
    }

    #[test]
    fn ascii_end_of_data_points_at_the_last_line() {
        let text = format!(
            "ply\nformat ascii 1.0\nelement vertex 4\n{XYZ}end_header\n{TRIANGLE_ASCII}\n  \n"
        );
        assert_eq!(
            message(text.as_bytes()),
            (
                Location::Line(12),
                "vertex 3: the file ends after 3 of the 4 vertex elements the header declares"
                    .into()
            )
        );
    }
}
