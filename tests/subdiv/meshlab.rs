//! MeshLab's Catmull–Clark (pymeshlab `meshing_surface_subdivision_catmull_clark`) is not
//! the standard rule: its new vertex point is built from the new *edge points* where
//! Catmull and Clark (and OpenSubdiv, CGAL) use the *edge midpoints*. This test shows that
//! this is the only difference: face and edge points agree with ours, and every vertex
//! point equals the variant rule computed here (the variant lives in this test, not in
//! surfkit).
//!
//! With Q the average of the adjacent face points, S the old vertex and n its valence:
//! standard `(Q + 2 R_mid + (n − 3) S) / n`, R_mid the average of the edge midpoints;
//! MeshLab `(Q + R_edge + (n − 2) S) / n`, R_edge the average of the new edge points.
//! (Substituting R_edge into the standard weights, `(Q + 2 R_edge + (n − 3) S) / n`, does
//! not reproduce MeshLab; the weights above were found by least squares on valences 3, 4
//! and 5 and are confirmed here to MeshLab's f32 precision.)
//!
//! Needs pymeshlab, which `scripts/setup.sh` installs into `.venv` (found through
//! `SURFKIT_PYTHON`).

use std::collections::{BTreeSet, HashMap};
use std::process::Command;

use surfkit::mesh::io::{read, write, WriteOptions};
use surfkit::mesh::PolygonMesh;
use surfkit::subdiv::{refine_uniform, SubdivOptions};

/// MeshLab keeps coordinates in `f32`; inputs are rounded to `f32` before both sides run,
/// and MeshLab's few `f32` operations per point stay within this many of its ulps.
const MESHLAB_F32_ROUNDING: f64 = 16.0 * f32::EPSILON as f64;

fn meshlab_catmull_clark(mesh: &PolygonMesh) -> Vec<[f64; 3]> {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.obj");
    write(&input, mesh, &WriteOptions::default()).unwrap();
    let script = "import sys, pymeshlab\n\
                  ms = pymeshlab.MeshSet()\n\
                  ms.load_new_mesh(sys.argv[1])\n\
                  ms.meshing_surface_subdivision_catmull_clark(iterations=1)\n\
                  for p in ms.current_mesh().vertex_matrix():\n    print(repr(float(p[0])), repr(float(p[1])), repr(float(p[2])))\n";
    let out = Command::new(crate::common::peer_python())
        .arg("-c")
        .arg(script)
        .arg(&input)
        .output()
        .expect("the peer Python (scripts/setup.sh)");
    assert!(
        out.status.success(),
        "pymeshlab failed (pip install pymeshlab): {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with("Mesh has"))
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect()
}

fn avg(points: &[[f64; 3]]) -> [f64; 3] {
    let n = points.len() as f64;
    std::array::from_fn(|k| points.iter().map(|p| p[k]).sum::<f64>() / n)
}

/// New vertex points of one Catmull–Clark step on a closed mesh: standard
/// `(Q + 2 R_mid + (n − 3) S) / n` or MeshLab's `(Q + R_edge + (n − 2) S) / n`.
fn vertex_points(mesh: &PolygonMesh, meshlab: bool) -> Vec<[f64; 3]> {
    let p = &mesh.positions;
    let face_point: Vec<[f64; 3]> = mesh
        .faces()
        .map(|f| avg(&f.iter().map(|&v| p[v as usize]).collect::<Vec<_>>()))
        .collect();
    let mut edge_faces: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    let mut vertex_faces = vec![Vec::new(); p.len()];
    let mut vertex_edges = vec![BTreeSet::new(); p.len()];
    for (fi, f) in mesh.faces().enumerate() {
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            let e = (a.min(b), a.max(b));
            edge_faces.entry(e).or_default().push(fi);
            vertex_faces[a as usize].push(fi);
            vertex_edges[a as usize].insert(e);
            vertex_edges[b as usize].insert(e);
        }
    }
    (0..p.len())
        .map(|v| {
            let q = avg(&vertex_faces[v]
                .iter()
                .map(|&f| face_point[f])
                .collect::<Vec<_>>());
            let r = avg(&vertex_edges[v]
                .iter()
                .map(|&(a, b)| {
                    let mid = avg(&[p[a as usize], p[b as usize]]);
                    if meshlab {
                        let fs = &edge_faces[&(a, b)];
                        avg(&[mid, avg(&[face_point[fs[0]], face_point[fs[1]]])])
                    } else {
                        mid
                    }
                })
                .collect::<Vec<_>>());
            let n = vertex_edges[v].len() as f64;
            if meshlab {
                std::array::from_fn(|k| (q[k] + r[k] + (n - 2.0) * p[v][k]) / n)
            } else {
                std::array::from_fn(|k| (q[k] + 2.0 * r[k] + (n - 3.0) * p[v][k]) / n)
            }
        })
        .collect()
}

#[test]
fn meshlab_differs_from_catmull_clark_exactly_by_its_vertex_rule() {
    let meshes = [
        (
            "catmark_torus.obj",
            read(&crate::cgal::fixture("catmark_torus.obj")).unwrap(),
        ),
        (
            "quadknot.obj",
            read(&crate::cgal::fixture("quadknot.obj")).unwrap(),
        ),
        ("icosahedron split into quads", icosahedron_quads()),
    ];
    for (name, mut mesh) in meshes {
        mesh.uvs = None;
        for p in &mut mesh.positions {
            *p = p.map(|c| c as f32 as f64);
        }
        let scale = mesh
            .positions
            .iter()
            .flatten()
            .fold(0.0f64, |m, c| m.max(c.abs()));
        let tol = MESHLAB_F32_ROUNDING * scale;
        let theirs = PolygonMesh {
            positions: meshlab_catmull_clark(&mesh),
            ..Default::default()
        };
        let ours = refine_uniform(&mesh, 1, &SubdivOptions::default()).unwrap();
        assert_eq!(theirs.vertex_count(), ours.vertex_count(), "{name}");
        let m = crate::cgal::match_vertices(&ours, &theirs, tol);
        // Everything but the V old-vertex points agrees (face points and edge points) ...
        let v = mesh.vertex_count();
        assert_eq!(
            m.unmatched_ours.len(),
            v,
            "{name}: unmatched OpenSubdiv points"
        );
        assert_eq!(
            m.unmatched_theirs.len(),
            v,
            "{name}: unmatched MeshLab points"
        );
        // ... and those are the standard rule on our side, MeshLab's variant on theirs.
        let as_mesh = |pts: Vec<[f64; 3]>| PolygonMesh {
            positions: pts,
            ..Default::default()
        };
        let pick = |from: &PolygonMesh, ids: &[usize]| {
            as_mesh(ids.iter().map(|&i| from.positions[i]).collect())
        };
        let standard = crate::cgal::match_vertices(
            &pick(&ours, &m.unmatched_ours),
            &as_mesh(vertex_points(&mesh, false)),
            tol,
        );
        assert!(
            standard.unmatched_ours.is_empty() && standard.unmatched_theirs.is_empty(),
            "{name}: standard rule"
        );
        let variant = crate::cgal::match_vertices(
            &pick(&theirs, &m.unmatched_theirs),
            &as_mesh(vertex_points(&mesh, true)),
            tol,
        );
        assert!(
            variant.unmatched_ours.is_empty() && variant.unmatched_theirs.is_empty(),
            "{name}: MeshLab's rule"
        );
        eprintln!(
            "{name}: MeshLab = variant within {:e}, ours = standard within {:e} (tolerance {tol:e})",
            variant.max_distance, standard.max_distance
        );
    }
}

/// An icosahedron with each triangle split into 3 quads (centroid + edge midpoints), its
/// points moved off the sphere: vertices of valence 5 (old), 4 (edges) and 3 (centroids).
fn icosahedron_quads() -> PolygonMesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut p: Vec<[f64; 3]> = vec![
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ];
    let tris: [[u32; 3]; 20] = [
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    let mut mids: HashMap<(u32, u32), u32> = HashMap::new();
    let mut faces = Vec::new();
    for [a, b, c] in tris {
        let cen = p.len() as u32;
        p.push(avg(&[p[a as usize], p[b as usize], p[c as usize]]));
        let mut mid = |x: u32, y: u32| {
            *mids.entry((x.min(y), x.max(y))).or_insert_with(|| {
                p.push(avg(&[p[x as usize], p[y as usize]]));
                p.len() as u32 - 1
            })
        };
        let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
        faces.extend([[a, ab, cen, ca], [b, bc, cen, ab], [c, ca, cen, bc]]);
    }
    for (i, q) in p.iter_mut().enumerate() {
        let f = 1.0 + 0.1 * (i as f64 * 1.7).sin();
        *q = q.map(|c| c * f);
    }
    PolygonMesh::from_polygons(p, &faces)
}
