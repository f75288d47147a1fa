//! The EAT scan on every real mesh agrees with REFERENCE.json (raw polygon counts measured
//! there and cross-checked with MeshLab and trimesh), and its boundary walk agrees with
//! OpenMesh's where OpenMesh takes every facet.

use std::collections::BTreeSet;

use surfkit::halfedge::{self, HalfEdgeTopology};
use surfkit::mesh::io::{read_with, ReadOptions};
use surfkit::topology::{boundary_walks, scan, EatOptions, ModelCompanion, Structure};

fn lenient() -> ReadOptions {
    ReadOptions {
        keep_degenerate: true,
    }
}

fn opt(record: &serde_json::Value, field: &str) -> Option<usize> {
    record[field].as_u64().map(|v| v as usize)
}

#[test]
fn every_count_agrees_with_reference() {
    for (path, r) in crate::common::reference_meshes() {
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let mesh = read_with(&path, &lenient()).unwrap();
        let report = scan(&mesh, &EatOptions::default()).unwrap();
        let c = &report.counts;
        let n = |f: &str| crate::common::count(&r, f);
        assert_eq!(c.vertices_in_file, n("V"), "{name}: V");
        assert_eq!(
            c.vertices_referenced,
            n("V_referenced"),
            "{name}: V_referenced"
        );
        assert_eq!(c.edges, n("E"), "{name}: E");
        assert_eq!(c.facets, n("F"), "{name}: F");
        assert_eq!(
            c.euler_characteristic,
            r["chi"].as_i64().unwrap(),
            "{name}: chi"
        );
        assert_eq!(
            c.boundary_edges,
            n("boundary_edges"),
            "{name}: boundary edges"
        );
        assert_eq!(
            c.boundary_loops,
            n("boundary_loops"),
            "{name}: boundary loops (edge graph)"
        );
        assert_eq!(
            c.boundary_loops_walk,
            opt(&r, "boundary_loops_walk"),
            "{name}: boundary loops (walk)"
        );
        assert_eq!(
            c.non_manifold_edges,
            n("non_manifold_edges"),
            "{name}: nm edges"
        );
        assert_eq!(
            c.non_manifold_vertices,
            n("non_manifold_vertices"),
            "{name}: nm vertices"
        );
        assert_eq!(c.components, n("components"), "{name}: components");
        assert_eq!(c.genus, r["genus"].as_i64(), "{name}: genus");
        assert_eq!(
            c.unreferenced_vertices,
            n("unreferenced_vertices"),
            "{name}: unreferenced"
        );
        assert_eq!(
            c.duplicated_facets,
            n("duplicated_facets"),
            "{name}: duplicated"
        );
        assert_eq!(
            c.degenerate_facets,
            n("degenerate_facets"),
            "{name}: degenerate"
        );
        assert_eq!(
            c.inconsistent_orientation_edges,
            n("inconsistent_orientation_edges"),
            "{name}: inconsistent orientation"
        );
        assert_eq!(
            c.coincident_vertices,
            n("coincident_vertex_extra"),
            "{name}: coincident"
        );
        // The paper's EAT-SA agrees with the counts.
        assert_eq!(
            report.statistics.euler_characteristic,
            c.euler_characteristic
        );
        // Components add up.
        assert_eq!(
            report.components.iter().map(|k| k.facets).sum::<usize>(),
            c.facets,
            "{name}"
        );
        assert_eq!(
            report.components.iter().map(|k| k.edges).sum::<usize>(),
            c.edges,
            "{name}"
        );
        if let Some(walk) = c.boundary_loops_walk {
            let loops_in_components: usize =
                report.components.iter().map(|k| k.boundary_loops).sum();
            assert_eq!(loops_in_components, walk, "{name}: walks per component");
        }
    }
}

#[test]
fn closed_clean_meshes_report_no_flaw() {
    for (path, r) in crate::common::reference_meshes() {
        let clean = r["tags"].as_array().unwrap().iter().any(|t| t == "closed")
            && crate::common::count(&r, "non_manifold_edges") == 0
            && crate::common::count(&r, "non_manifold_vertices") == 0
            && crate::common::count(&r, "unreferenced_vertices") == 0
            && crate::common::count(&r, "duplicated_facets") == 0
            && crate::common::count(&r, "coincident_vertex_extra") == 0
            && crate::common::count(&r, "boundary_edges") == 0;
        if !clean {
            continue;
        }
        let mesh = read_with(&path, &lenient()).unwrap();
        let report = scan(&mesh, &EatOptions::default()).unwrap();
        assert!(
            report.flaws.is_empty(),
            "{}: {:?}",
            path.display(),
            report.flaw_counts()
        );
        for comp in &report.components {
            assert_eq!(comp.orientable, Some(true), "{}", path.display());
        }
    }
}

#[test]
fn holes_are_the_loops_openmesh_walks_where_it_takes_every_facet() {
    for (path, _) in crate::common::reference_meshes() {
        let mesh = read_with(&path, &lenient()).unwrap();
        let built = halfedge::build(&mesh).unwrap();
        if built.refused().count() > 0 {
            continue;
        }
        let canonical = |l: &[u32]| {
            let k = (0..l.len()).min_by_key(|&i| l[i]).unwrap();
            l[k..].iter().chain(&l[..k]).copied().collect::<Vec<u32>>()
        };
        let om: BTreeSet<Vec<u32>> = built
            .mesh
            .boundary_loops()
            .unwrap()
            .iter()
            .map(canonical)
            .collect();
        let mut companion = ModelCompanion::with_capacity(
            mesh.vertex_count(),
            mesh.face_count(),
            mesh.face_indices.len(),
        );
        for (f, corners) in mesh.faces().enumerate() {
            companion.register(corners, f as u32).unwrap();
        }
        let structure = Structure::of(companion.registry());
        let ours: BTreeSet<Vec<u32>> = boundary_walks(companion.registry(), &structure)
            .iter()
            .map(|w| canonical(w))
            .collect();
        // The flaw list reports each walk once (no T-junction in these meshes).
        let report = scan(&mesh, &EatOptions::default()).unwrap();
        let listed = report
            .flaws
            .iter()
            .filter(|f| f.kind.is_boundary_loop())
            .count();
        assert_eq!(listed, ours.len(), "{}", path.display());
        assert_eq!(ours, om, "{}", path.display());
    }
}

#[test]
fn target_obj_has_six_holes_in_one_genus_zero_component() {
    let mesh = read_with(&crate::common::meshes_dir().join("target.obj"), &lenient()).unwrap();
    let report = scan(&mesh, &EatOptions::default()).unwrap();
    assert_eq!(report.components.len(), 1);
    assert_eq!(report.components[0].boundary_loops, 6);
    assert_eq!(report.components[0].genus, Some(0));
    let mut sizes: Vec<usize> = report
        .flaws
        .iter()
        .filter_map(|f| f.shape.as_ref().map(|s| s.edges))
        .collect();
    sizes.sort_unstable_by(|a, b| b.cmp(a));
    assert_eq!(sizes, vec![34, 28, 18, 18, 11, 11]); // REFERENCE.json boundary_loop_sizes
}
