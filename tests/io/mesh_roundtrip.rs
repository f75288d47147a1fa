//! Round trips OBJ ↔ PLY ↔ OFF on the real meshes: positions bit-exact, faces, objects and
//! groups exact; and the OBJ reader checked against tobj, an independent parser.

use std::path::Path;

use surfkit::mesh::io::{read_with, write, PlyEncoding, ReadOptions, WriteOptions};
use surfkit::mesh::{FaceLabels, PolygonMesh};

fn lenient() -> ReadOptions {
    ReadOptions {
        keep_degenerate: true,
    }
}

fn labels_by_name(l: &Option<FaceLabels>, faces: usize) -> Vec<Option<String>> {
    (0..faces)
        .map(|f| l.as_ref().and_then(|l| l.name_of(f)).map(str::to_string))
        .collect()
}

fn assert_same_mesh(a: &PolygonMesh, b: &PolygonMesh, what: &str) {
    assert_eq!(a.positions.len(), b.positions.len(), "{what}: vertex count");
    for (i, (p, q)) in a.positions.iter().zip(&b.positions).enumerate() {
        let bits = |p: &[f64; 3]| p.map(f64::to_bits);
        assert_eq!(
            bits(p),
            bits(q),
            "{what}: vertex {i} not bit-exact: {p:?} vs {q:?}"
        );
    }
    assert_eq!(a.face_offsets, b.face_offsets, "{what}: face arities");
    assert_eq!(a.face_indices, b.face_indices, "{what}: face corners");
    let f = a.face_count();
    assert_eq!(
        labels_by_name(&a.objects, f),
        labels_by_name(&b.objects, f),
        "{what}: objects"
    );
    assert_eq!(
        labels_by_name(&a.groups, f),
        labels_by_name(&b.groups, f),
        "{what}: groups"
    );
}

fn through(mesh: &PolygonMesh, dir: &Path, name: &str, encoding: PlyEncoding) -> PolygonMesh {
    let path = dir.join(name);
    write(
        &path,
        mesh,
        &WriteOptions {
            ply_encoding: encoding,
        },
    )
    .unwrap();
    read_with(&path, &lenient()).unwrap()
}

#[test]
fn obj_ply_off_round_trips_are_exact_on_every_fixture() {
    let dir = tempfile::tempdir().unwrap();
    for (path, _) in crate::common::reference_meshes() {
        let original = read_with(&path, &lenient()).unwrap();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let mut current = original.clone();
        for (step, ext, enc) in [
            ("obj", "obj", PlyEncoding::BinaryLittleEndian),
            ("ply binary le", "ply", PlyEncoding::BinaryLittleEndian),
            ("off", "off", PlyEncoding::BinaryLittleEndian),
            ("ply ascii", "ply", PlyEncoding::Ascii),
            ("ply binary be", "ply", PlyEncoding::BinaryBigEndian),
            ("obj again", "obj", PlyEncoding::BinaryLittleEndian),
        ] {
            current = through(&current, dir.path(), &format!("rt.{ext}"), enc);
            assert_same_mesh(&original, &current, &format!("{name} after {step}"));
        }
    }
}

#[test]
fn uvs_quality_and_colours_survive_ply() {
    let path = crate::common::meshes_dir().join("spot.obj");
    let mut mesh = read_with(&path, &lenient()).unwrap();
    let uv = mesh.uvs.clone().expect("spot.obj has texture coordinates");
    mesh.quality = Some((0..mesh.vertex_count()).map(|i| i as f64 / 7.0).collect());
    mesh.colors = Some(
        (0..mesh.vertex_count())
            .map(|i| [(i % 256) as u8, 3, 200, 255])
            .collect(),
    );
    let dir = tempfile::tempdir().unwrap();
    for enc in [
        PlyEncoding::BinaryLittleEndian,
        PlyEncoding::Ascii,
        PlyEncoding::BinaryBigEndian,
    ] {
        let back = through(&mesh, dir.path(), "uv.ply", enc);
        assert_eq!(back.quality, mesh.quality);
        assert_eq!(back.colors, mesh.colors);
        let corner_uv = |m: &PolygonMesh, k: usize| {
            let u = m.uvs.as_ref().unwrap();
            u.coords[u.corner_indices[k] as usize].map(f64::to_bits)
        };
        for k in 0..mesh.face_indices.len() {
            assert_eq!(corner_uv(&mesh, k), corner_uv(&back, k), "corner {k}");
        }
    }
    // OBJ keeps UVs with their own indexing.
    let back = through(&mesh, dir.path(), "uv.obj", PlyEncoding::Ascii);
    assert_eq!(back.uvs.as_ref().unwrap(), &uv);
}

#[test]
fn obj_reader_agrees_with_tobj() {
    for (path, _) in crate::common::reference_meshes() {
        if path.extension().unwrap() != "obj" {
            continue;
        }
        let ours = read_with(&path, &lenient()).unwrap();
        let (models, _) = tobj::load_obj(
            &path,
            &tobj::LoadOptions {
                single_index: false,
                triangulate: false,
                ignore_points: true,
                ignore_lines: true,
            },
        )
        .unwrap();
        // tobj re-indexes each model; compare the corner positions face by face, in order.
        let mut theirs: Vec<Vec<[f64; 3]>> = Vec::new();
        for m in &models {
            let mesh = &m.mesh;
            let arities: Vec<u32> = if mesh.face_arities.is_empty() {
                vec![3; mesh.indices.len() / 3]
            } else {
                mesh.face_arities.clone()
            };
            let mut k = 0;
            for n in arities {
                let face = (0..n as usize)
                    .map(|c| {
                        let i = mesh.indices[k + c] as usize;
                        [0, 1, 2].map(|a| f64::from(mesh.positions[3 * i + a]))
                    })
                    .collect();
                theirs.push(face);
                k += n as usize;
            }
        }
        let ours_faces: Vec<Vec<[f64; 3]>> = ours
            .faces()
            .map(|f| {
                f.iter()
                    .map(|&i| ours.positions[i as usize].map(|c| f64::from(c as f32)))
                    .collect()
            })
            .collect();
        assert_eq!(ours_faces, theirs, "{}", path.display());
    }
}
