#![no_main]
//! A structure-aware fuzzer for meshes: the bytes choose a few vertices on a small integer
//! lattice and faces of 1 to 8 corners over them, so that fans, bow-ties, Möbius strips,
//! repeated faces and non-manifold edges of any multiplicity come up at once instead of
//! behind a parser. Each mesh goes through the EAT (with OpenMesh's half-edge structure),
//! the repair of every flaw kind and the check of every suggested fix, one level of
//! Catmull–Clark refinement and the limit surface; none may panic, and what they return must
//! hold together (χ = V − E + F, a repaired mesh that keeps the mesh invariants and is left
//! unchanged when nothing was flawed, finite limit points).

use libfuzzer_sys::fuzz_target;
use surfkit::mesh::PolygonMesh;
use surfkit::subdiv::{limit_surface, refine_uniform, PatchOptions, SubdivOptions, SurfacePoint};
use surfkit::repair::{check_fixes, repair, RepairOptions};
use surfkit::topology::{scan, EatOptions, FlawKind};

fn mesh_from(bytes: &[u8]) -> Option<PolygonMesh> {
    let (&head, rest) = bytes.split_first()?;
    let nv = 3 + usize::from(head % 24);
    let (coords, mut faces) = rest.split_at(rest.len().min(nv));
    let positions: Vec<[f64; 3]> = (0..nv)
        .map(|i| {
            let c = coords.get(i).copied().unwrap_or(i as u8);
            [f64::from(c & 7), f64::from((c >> 3) & 7), f64::from(c >> 6)]
        })
        .collect();
    let mut list: Vec<Vec<u32>> = Vec::new();
    while let Some((&arity, tail)) = faces.split_first() {
        let n = 1 + usize::from(arity % 8);
        if tail.len() < n {
            break;
        }
        list.push(tail[..n].iter().map(|&b| u32::from(b) % nv as u32).collect());
        faces = &tail[n..];
    }
    if list.is_empty() {
        return None;
    }
    Some(PolygonMesh::from_polygons(positions, &list))
}

fuzz_target!(|bytes: &[u8]| {
    let Some(mesh) = mesh_from(bytes) else { return };
    let options = EatOptions {
        halfedge: true,
        ..EatOptions::default()
    };
    if let Ok(report) = scan(&mesh, &options) {
        let c = &report.counts;
        assert_eq!(
            c.euler_characteristic,
            c.vertices_referenced as i64 - c.edges as i64 + c.facets as i64
        );
        let all = RepairOptions {
            kinds: FlawKind::ALL.to_vec(),
            max_hole_edges: 8,
            ..RepairOptions::default()
        };
        let repaired = repair(&mesh, &all).expect("a mesh the EAT scanned can be repaired");
        repaired.mesh.validate().expect("the repaired mesh keeps the invariants");
        if report.flaws.is_empty() {
            assert!(repaired.changes.is_empty(), "{:?}", repaired.changes);
        }
        let mut flaws = report.flaws.clone();
        check_fixes(&mesh, &mut flaws, options.locator).expect("fixes can be checked");
    }
    let subdiv = SubdivOptions::default();
    let _ = refine_uniform(&mesh, 1, &subdiv);
    let patch = PatchOptions {
        max_isolation: 2,
        ..PatchOptions::default()
    };
    if let Ok(surface) = limit_surface(&mesh, &subdiv, &patch) {
        let points: Vec<SurfacePoint> = (0..surface.ptex_face_count() as u32)
            .map(|p| SurfacePoint {
                ptex_face: p,
                u: 0.25,
                v: 0.75,
            })
            .collect();
        if let Ok(values) = surface.evaluate(&points) {
            for d in values {
                assert!(d.position.iter().all(|x| x.is_finite()), "{:?}", d.position);
            }
        }
    }
});
