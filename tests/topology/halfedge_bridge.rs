//! The OpenMesh bridge on real meshes: counts against REFERENCE.json (measured on the raw
//! polygons, cross-checked with MeshLab and trimesh there), refused faces listed, and every
//! query checked against the pure-Rust reference implementation of the same trait.

use std::collections::BTreeSet;

use surfkit::halfedge::{self, FaceStatus, HalfEdgeTopology, ReferenceTopology};
use surfkit::mesh::io::{read_with, ReadOptions};

fn lenient() -> ReadOptions {
    ReadOptions {
        keep_degenerate: true,
    }
}

/// A loop as a canonical cyclic sequence (rotated to start at its smallest vertex).
fn canonical_loops(loops: &halfedge::Loops) -> BTreeSet<Vec<u32>> {
    loops
        .iter()
        .map(|l| {
            let k = (0..l.len()).min_by_key(|&i| l[i]).unwrap();
            l[k..].iter().chain(&l[..k]).copied().collect()
        })
        .collect()
}

fn edge_set(t: &dyn HalfEdgeTopology) -> BTreeSet<([u32; 2], [u32; 2])> {
    let e = t.edges();
    e.vertices
        .iter()
        .zip(&e.faces)
        .map(|(v, f)| {
            if v[0] < v[1] {
                (*v, *f)
            } else {
                ([v[1], v[0]], [f[1], f[0]])
            }
        })
        .collect()
}

/// Component labels renamed by first appearance in face-id order, so partitions compare.
fn partition(c: &halfedge::Components) -> Vec<(u32, u32)> {
    let mut pairs: Vec<(u32, u32)> = c
        .faces
        .iter()
        .copied()
        .zip(c.of_face.iter().copied())
        .collect();
    pairs.sort_unstable();
    let mut rename = std::collections::HashMap::new();
    pairs
        .into_iter()
        .map(|(f, l)| {
            let n = rename.len() as u32;
            (f, *rename.entry(l).or_insert(n))
        })
        .collect()
}

#[test]
fn counts_match_reference_where_openmesh_takes_every_face() {
    for (path, reference) in crate::common::reference_meshes() {
        let mesh = read_with(&path, &lenient()).unwrap();
        let built = halfedge::build(&mesh).unwrap();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let refused: Vec<_> = built.refused().collect();
        assert_eq!(
            built.mesh.vertex_count(),
            crate::common::count(&reference, "V"),
            "{name}: V"
        );
        if refused.is_empty() {
            assert_eq!(
                built.mesh.edge_count(),
                crate::common::count(&reference, "E"),
                "{name}: E"
            );
            assert_eq!(
                built.mesh.face_count(),
                crate::common::count(&reference, "F"),
                "{name}: F"
            );
            let loops = built.mesh.boundary_loops().unwrap();
            assert_eq!(
                loops.len(),
                crate::common::count(&reference, "boundary_loops_walk"),
                "{name}: walk loops"
            );
            assert_eq!(
                built.mesh.connected_components().count as usize,
                crate::common::count(&reference, "components"),
                "{name}: components"
            );
            assert!(
                built.messages.is_empty(),
                "{name}: OpenMesh said {}",
                built.messages
            );
        } else {
            // Every refused face is named with a reason, and OpenMesh's words were captured.
            assert_eq!(
                built.mesh.face_count() + refused.len(),
                crate::common::count(&reference, "F"),
                "{name}: accepted + refused = F"
            );
            assert!(refused.iter().all(|(_, s)| *s != FaceStatus::Added));
            assert!(
                !built.messages.is_empty(),
                "{name}: refused faces without a message"
            );
        }
    }
}

#[test]
fn meshes_with_non_manifold_edges_have_refused_faces() {
    for (path, reference) in crate::common::reference_meshes() {
        let nm_edges = crate::common::count(&reference, "non_manifold_edges");
        let dup = crate::common::count(&reference, "duplicated_facets");
        let mesh = read_with(&path, &lenient()).unwrap();
        let built = halfedge::build(&mesh).unwrap();
        if nm_edges > 0 || dup > 0 {
            assert!(
                built.refused().count() > 0,
                "{}: OpenMesh took a non-manifold mesh whole",
                path.display()
            );
        }
    }
}

#[test]
fn an_edge_shared_by_a_hundred_quads_keeps_one_face_per_direction() {
    let mesh = read_with(
        &crate::common::meshes_dir().join("catmark_nonman_edge100.obj"),
        &lenient(),
    )
    .unwrap();
    // Count, from the file, how many faces run each direction of the most shared edge.
    let mut runs = std::collections::HashMap::<(u32, u32), usize>::new();
    for f in mesh.faces() {
        for k in 0..f.len() {
            *runs.entry((f[k], f[(k + 1) % f.len()])).or_default() += 1;
        }
    }
    let (&(a, b), _) = runs
        .iter()
        .max_by_key(|(e, n)| (**n + runs.get(&(e.1, e.0)).unwrap_or(&0), **e))
        .unwrap();
    let (ab, ba) = (runs[&(a, b)], runs.get(&(b, a)).copied().unwrap_or(0));
    assert_eq!(ab + ba, 100);
    let kept = ab.min(1) + ba.min(1);
    let built = halfedge::build(&mesh).unwrap();
    let refused: Vec<_> = built.refused().collect();
    assert_eq!(refused.len(), 100 - kept);
    assert!(refused.iter().all(|(_, s)| *s == FaceStatus::ComplexEdge));
    assert!(built.messages.contains("complex edge"));
}

#[test]
fn openmesh_and_the_reference_agree_on_every_query() {
    for (path, _) in crate::common::reference_meshes() {
        let name = path.display().to_string();
        let mesh = read_with(&path, &lenient()).unwrap();
        let built = halfedge::build(&mesh).unwrap();
        let accepted: Vec<u32> = built
            .face_status
            .iter()
            .enumerate()
            .filter(|(_, s)| **s == FaceStatus::Added)
            .map(|(f, _)| f as u32)
            .collect();
        let reference = ReferenceTopology::new(&mesh, &accepted).unwrap();
        let om: &dyn HalfEdgeTopology = &built.mesh;
        assert_eq!(om.vertex_count(), reference.vertex_count(), "{name}");
        assert_eq!(om.edge_count(), reference.edge_count(), "{name}");
        assert_eq!(om.face_count(), reference.face_count(), "{name}");
        assert_eq!(
            om.vertex_valences(),
            reference.vertex_valences(),
            "{name}: valences"
        );
        assert_eq!(
            edge_set(om),
            edge_set(&reference),
            "{name}: edges and their faces"
        );
        assert_eq!(
            canonical_loops(&om.boundary_loops().unwrap()),
            canonical_loops(&reference.boundary_loops().unwrap()),
            "{name}: boundary loops"
        );
        let (a, b) = (om.face_neighbours(), reference.face_neighbours());
        assert_eq!(a, b, "{name}: face neighbours");
        assert_eq!(
            partition(&om.connected_components()),
            partition(&reference.connected_components()),
            "{name}: components"
        );
    }
}

#[test]
fn positions_written_back_are_read_back() {
    let mesh = read_with(
        &crate::common::meshes_dir().join("catmark_torus.obj"),
        &lenient(),
    )
    .unwrap();
    let mut built = halfedge::build(&mesh).unwrap();
    let moved: Vec<[f64; 3]> = mesh
        .positions
        .iter()
        .map(|p| [p[0] + 1.0, p[1] * 2.0, -p[2]])
        .collect();
    built.mesh.set_positions(&moved).unwrap();
    assert_eq!(built.mesh.positions(), moved.as_flattened());
    let err = built
        .mesh
        .set_positions(&moved[1..])
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("OpenMesh") && err.contains("coordinates"),
        "{err}"
    );
}

#[test]
fn incremental_faces_report_like_the_batch() {
    let mesh = read_with(
        &crate::common::meshes_dir().join("joined_tetrahedra.obj"),
        &lenient(),
    )
    .unwrap();
    let batch = halfedge::build(&mesh).unwrap();
    let empty = surfkit::mesh::PolygonMesh {
        positions: mesh.positions.clone(),
        ..Default::default()
    };
    let mut inc = halfedge::build(&empty).unwrap().mesh;
    for (f, corners) in mesh.faces().enumerate() {
        let (status, _) = inc.add_face(corners, f as u32).unwrap();
        assert_eq!(status, batch.face_status[f], "face {f}");
    }
    assert!(inc.add_face(&[0, 1, 99], 9).is_err());
}

/// Files written by OpenMesh's own exporter read back with surfkit's readers: the same
/// vertices (to the exporter's printed precision) and the same faces up to rotation.
#[test]
fn surfkit_reads_what_openmesh_writes() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["catmark_nonquads.obj", "rabbit.obj", "fixed_top.ply"] {
        let mesh = read_with(&crate::common::meshes_dir().join(name), &lenient()).unwrap();
        let built = halfedge::build(&mesh).unwrap();
        assert_eq!(built.refused().count(), 0);
        for ext in ["obj", "off", "ply"] {
            let path = dir.path().join(format!("om.{ext}"));
            built.mesh.write_with_openmesh(&path).unwrap();
            let back = surfkit::mesh::io::read(&path).unwrap();
            assert_eq!(
                back.vertex_count(),
                mesh.vertex_count(),
                "{name} via OpenMesh {ext}"
            );
            assert_eq!(
                back.face_count(),
                mesh.face_count(),
                "{name} via OpenMesh {ext}"
            );
            for (p, q) in mesh.positions.iter().zip(&back.positions) {
                for k in 0..3 {
                    // OpenMesh prints coordinates as float text (about 7 significant digits).
                    assert!(
                        (p[k] - q[k]).abs() <= 1e-5 * p[k].abs().max(1.0),
                        "{name} {ext}: {p:?} vs {q:?}"
                    );
                }
            }
            let rotated = |f: &[u32]| {
                let k = (0..f.len()).min_by_key(|&i| f[i]).unwrap();
                f[k..].iter().chain(&f[..k]).copied().collect::<Vec<u32>>()
            };
            for (f, g) in mesh.faces().zip(back.faces()) {
                assert_eq!(rotated(f), rotated(g), "{name} {ext}");
            }
        }
    }
}

/// STL holds no vertex indices: surfkit welds the corners by their 32-bit coordinates, as
/// OpenMesh's STL reader does. The STL files surfkit writes (binary and ASCII, polygons as
/// fans) read into the same vertices, in the same order, and the same edges and faces with
/// both readers; and surfkit reads OpenMesh's own STL of a triangle mesh into its vertices
/// and faces.
#[test]
fn surfkit_and_openmesh_read_stl_alike() {
    use surfkit::halfedge::read_with_openmesh;
    use surfkit::mesh::io::{write, PlyEncoding, WriteOptions};
    let dir = tempfile::tempdir().unwrap();
    for name in [
        "catmark_nonquads.obj",
        "spot.obj",
        "fixed_top.ply",
        "rabbit.obj",
    ] {
        let mesh = read_with(&crate::common::meshes_dir().join(name), &lenient()).unwrap();
        for ply_encoding in [PlyEncoding::BinaryLittleEndian, PlyEncoding::Ascii] {
            let path = dir.path().join("surfkit.stl");
            write(&path, &mesh, &WriteOptions { ply_encoding }).unwrap();
            let ours = surfkit::mesh::io::read(&path).unwrap();
            let triangles: usize = mesh.faces().map(|f| f.len() - 2).sum();
            assert_eq!(ours.face_count(), triangles, "{name} {ply_encoding:?}");
            let theirs = read_with_openmesh(&path).unwrap();
            let ours_built = halfedge::build(&ours).unwrap();
            assert_eq!(ours_built.refused().count(), 0);
            let as_f32 = |p: &[f64]| p.iter().map(|&c| c as f32).collect::<Vec<f32>>();
            let ours_flat: Vec<f64> = ours.positions.iter().flatten().copied().collect();
            assert_eq!(as_f32(&ours_flat), as_f32(&theirs.positions()), "{name}");
            assert_eq!(theirs.face_count(), ours.face_count(), "{name}");
            assert_eq!(edge_set(&theirs), edge_set(&ours_built.mesh), "{name}");
        }
    }
    let spot = read_with(&crate::common::meshes_dir().join("spot.obj"), &lenient()).unwrap();
    let built = halfedge::build(&spot).unwrap();
    let path = dir.path().join("openmesh.stl");
    built.mesh.write_with_openmesh(&path).unwrap();
    let back = surfkit::mesh::io::read(&path).unwrap();
    assert_eq!(back.vertex_count(), spot.vertex_count());
    assert_eq!(back.face_count(), spot.face_count());
    // The welded numbering is by first appearance: map it back through the positions.
    let mut of_position = std::collections::HashMap::new();
    for (v, p) in spot.positions.iter().enumerate() {
        of_position.insert(p.map(|c| (c as f32).to_bits()), v as u32);
    }
    // OpenMesh starts each facet at a corner of its own choosing: faces compare up to rotation.
    let rotated = |f: &[u32]| {
        let k = (0..f.len()).min_by_key(|&i| f[i]).unwrap();
        f[k..].iter().chain(&f[..k]).copied().collect::<Vec<u32>>()
    };
    for (f, g) in spot.faces().zip(back.faces()) {
        let g: Vec<u32> = g
            .iter()
            .map(|&v| of_position[&back.positions[v as usize].map(|c| (c as f32).to_bits())])
            .collect();
        assert_eq!(rotated(f), rotated(&g));
    }
}
