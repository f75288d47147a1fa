//! Preparation (Kiciak §2, §4): refinement until the paper's conditions hold with χ
//! unchanged, fixed vertices, and the errors for closed meshes with nothing fixed.

use surfkit::error::Error;
use surfkit::fair::{
    condition_violation, fixed_vertices, optimize, prepare, FairOptions, MeshTopology, SurfaceKind,
};
use surfkit::mesh::PolygonMesh;

#[test]
fn fair_prepare_cube_needs_one_level_and_keeps_chi() {
    let mesh = crate::common::unit_cube();
    let topo = MeshTopology::new(&mesh).unwrap();
    assert_eq!(topo.euler_characteristic(), 2);
    assert!(condition_violation(&mesh, &topo, SurfaceKind::CatmullClark).is_some());
    let (refined, levels) = prepare(&mesh, 3, SurfaceKind::CatmullClark).unwrap();
    assert_eq!(levels, 1);
    // V + E + F of the cube.
    assert_eq!(refined.vertex_count(), 8 + 12 + 6);
    let t = MeshTopology::new(&refined).unwrap();
    assert_eq!(t.euler_characteristic(), 2);
    assert!(condition_violation(&refined, &t, SurfaceKind::CatmullClark).is_none());
    // Kiciak's G² surface needs each corner's radius-2 Sabin net on its own: after one
    // refinement the corners are two edges apart and their nets overlap; after two, four.
    let why = condition_violation(&refined, &t, SurfaceKind::G2).unwrap();
    assert!(why.contains("special vertex"), "{why}");
    let (twice, levels) = prepare(&mesh, 3, SurfaceKind::G2).unwrap();
    assert_eq!(levels, 2);
    let t = MeshTopology::new(&twice).unwrap();
    assert!(condition_violation(&twice, &t, SurfaceKind::G2).is_none());
}

#[test]
fn fair_prepare_triangles_become_quads() {
    // A square pyramid without its base: four triangles, one boundary loop, χ = 1.
    let mesh = PolygonMesh::from_polygons(
        vec![
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, -1.0, 0.0],
        ],
        &[[0u32, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1]],
    );
    let (refined, levels) = prepare(&mesh, 3, SurfaceKind::G2).unwrap();
    assert!(levels >= 1);
    assert!(refined.faces().all(|f| f.len() == 4));
    assert_eq!(
        MeshTopology::new(&refined).unwrap().euler_characteristic(),
        1
    );
}

#[test]
fn fair_prepare_too_few_levels_is_a_topology_error() {
    assert!(matches!(
        prepare(&crate::common::unit_cube(), 0, SurfaceKind::G2),
        Err(Error::Topology(_))
    ));
}

#[test]
fn fair_closed_mesh_with_nothing_fixed_is_an_error() {
    let (refined, _) = prepare(&crate::common::unit_cube(), 2, SurfaceKind::G2).unwrap();
    let topo = MeshTopology::new(&refined).unwrap();
    match fixed_vertices(&topo, 3, &[]) {
        Err(Error::InvalidInput(m)) => assert!(m.contains("closed"), "{m}"),
        other => panic!("expected an InvalidInput error, got {other:?}"),
    }
    assert!(matches!(
        optimize(&crate::common::unit_cube(), &FairOptions::default()),
        Err(Error::InvalidInput(_))
    ));
    // With a vertex given, the closed mesh has something to hold.
    let fixed = fixed_vertices(&topo, 3, &[0]).unwrap();
    assert_eq!(fixed.iter().filter(|&&f| f).count(), 1);
    assert!(matches!(
        fixed_vertices(&topo, 3, &[10_000]),
        Err(Error::InvalidInput(_))
    ));
}
