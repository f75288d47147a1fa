//! The half-edge structure of an oriented 2-manifold is built directly (twins paired, the
//! kernel's links set) instead of face by face through OpenMesh's add_face: on every
//! manifold fixture and generated mesh the two give the same structure — accepted faces,
//! vertex valences, the edges with the faces on each side, each face's neighbours across
//! its edges, boundary loops and components — and a non-manifold mesh still goes through
//! add_face with its refusals reported.

use std::collections::BTreeSet;

use surfkit::halfedge::{build, FaceStatus, HalfEdgeTopology, OpenMeshHalfEdge};
use surfkit::mesh::PolygonMesh;
use surfkit::shapes::grid_torus;
use surfkit::topology::{scan, EatOptions};

/// The structure OpenMesh's add_face makes of `mesh`: vertices first, then every face.
fn by_add_face(mesh: &PolygonMesh) -> (OpenMeshHalfEdge, Vec<FaceStatus>) {
    let vertices = PolygonMesh {
        positions: mesh.positions.clone(),
        ..Default::default()
    };
    let mut built = build(&vertices).unwrap().mesh;
    let (status, _) = built
        .add_faces(&mesh.face_offsets, &mesh.face_indices, 0)
        .unwrap();
    (built, status)
}

/// Edges as {a, b} → the set of faces beside them (numbering-free).
fn edge_faces(m: &OpenMeshHalfEdge) -> BTreeSet<([u32; 2], [u32; 2])> {
    let t = m.edges();
    t.vertices
        .iter()
        .zip(&t.faces)
        .map(|(v, f)| {
            let mut v = *v;
            let mut f = *f;
            v.sort();
            f.sort();
            (v, f)
        })
        .collect()
}

/// Each boundary loop as its smallest rotation (numbering-free).
fn loops(m: &OpenMeshHalfEdge) -> BTreeSet<Vec<u32>> {
    m.boundary_loops()
        .unwrap()
        .iter()
        .map(|l| {
            let k = (0..l.len()).min_by_key(|&k| l[k]).unwrap();
            l[k..].iter().chain(&l[..k]).copied().collect()
        })
        .collect()
}

fn same_structure(name: &str, mesh: &PolygonMesh) {
    let direct = build(mesh).unwrap();
    // The direct build takes every mesh whose vertices each have one fan of facets (the
    // EAT's count, independent of OpenMesh); add_face also takes boundary vertices with
    // several fans, which go face by face.
    let options = EatOptions {
        halfedge: false,
        ..EatOptions::default()
    };
    let one_fan_each = scan(mesh, &options).unwrap().counts.non_manifold_vertices == 0;
    assert_eq!(
        direct.built_directly, one_fan_each,
        "{name}: built directly"
    );
    assert_eq!(
        direct.face_status.len(),
        mesh.face_count(),
        "{name}: statuses"
    );
    assert!(direct.refused().next().is_none(), "{name}: refusals");
    let (reference, status) = by_add_face(mesh);
    assert!(
        status.iter().all(|s| *s == FaceStatus::Added),
        "{name}: add_face refused"
    );
    let a = &direct.mesh;
    let b = &reference;
    assert_eq!(a.face_count(), b.face_count(), "{name}: faces");
    assert_eq!(a.edge_count(), b.edge_count(), "{name}: edges");
    assert_eq!(a.vertex_valences(), b.vertex_valences(), "{name}: valences");
    assert_eq!(edge_faces(a), edge_faces(b), "{name}: edge sides");
    let (na, nb) = (a.face_neighbours(), b.face_neighbours());
    assert_eq!(
        na, nb,
        "{name}: neighbours across each edge in corner order"
    );
    assert_eq!(loops(a), loops(b), "{name}: boundary loops");
    assert_eq!(
        a.connected_components(),
        b.connected_components(),
        "{name}: components"
    );
}

#[test]
fn manifold_fixtures_and_generated_meshes_give_add_faces_structure() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/meshes");
    let mut manifold = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let Ok(mesh) = surfkit::mesh::io::read(&path) else {
            continue;
        };
        // Only meshes add_face takes whole are oriented manifolds.
        let (_, status) = by_add_face(&mesh);
        if status.iter().all(|s| *s == FaceStatus::Added) {
            same_structure(&path.display().to_string(), &mesh);
            manifold += 1;
        }
    }
    assert!(manifold >= 6, "{manifold} manifold fixtures");
    for (nu, nv, tri) in [(7, 5, false), (12, 9, true), (3, 3, true)] {
        same_structure(&format!("torus {nu}×{nv}"), &grid_torus(nu, nv, tri));
    }
    // Faces of several sizes (the direct build keeps next/prev arrays for these): every
    // third quad of a quad torus split into two triangles.
    let quads = grid_torus(10, 8, false);
    let mixed: Vec<Vec<u32>> = quads
        .faces()
        .enumerate()
        .flat_map(|(f, c)| {
            if f % 3 == 0 {
                vec![vec![c[0], c[1], c[2]], vec![c[0], c[2], c[3]]]
            } else {
                vec![c.to_vec()]
            }
        })
        .collect();
    same_structure(
        "quads and triangles",
        &PolygonMesh::from_polygons(quads.positions.clone(), &mixed),
    );
    // Open meshes: a torus with a hole, and with facets taken out here and there (holes,
    // boundary vertices of valence 2, isolated facets) where add_face takes them all.
    let torus = grid_torus(16, 12, true);
    let holed: Vec<Vec<u32>> = torus
        .faces()
        .enumerate()
        .filter(|(f, _)| !(40..52).contains(f))
        .map(|(_, c)| c.to_vec())
        .collect();
    same_structure(
        "torus with a hole",
        &PolygonMesh::from_polygons(torus.positions.clone(), &holed),
    );
    for step in [3usize, 5, 7] {
        let faces: Vec<Vec<u32>> = torus
            .faces()
            .enumerate()
            .filter(|(f, _)| f % step != 0)
            .map(|(_, c)| c.to_vec())
            .collect();
        let mesh = PolygonMesh::from_polygons(torus.positions.clone(), &faces);
        if by_add_face(&mesh).1.iter().all(|s| *s == FaceStatus::Added) {
            same_structure(&format!("torus minus every {step}th facet"), &mesh);
        }
    }
}

#[test]
fn a_non_manifold_mesh_still_reports_what_openmesh_refuses() {
    // Three triangles on one edge: the third is refused (complex edge), as add_face says.
    let positions = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let mesh =
        PolygonMesh::from_polygons(positions, &[vec![0, 1, 2], vec![1, 0, 3], vec![0, 1, 4]]);
    assert!(!build(&mesh).unwrap().built_directly);
    let built = build(&mesh).unwrap();
    let refused: Vec<(usize, FaceStatus)> = built.refused().collect();
    assert_eq!(refused.len(), 1, "{refused:?}");
    assert_eq!(refused[0].0, 2);
    let (_, status) = by_add_face(&mesh);
    assert_eq!(status[2], refused[0].1);
}
