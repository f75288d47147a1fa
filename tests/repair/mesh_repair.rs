//! `surfkit::repair` on every flaw injected at a seeded random place in every clean real
//! mesh: the EAT of the result has the clean original's χ, boundary loops, components and
//! genus (V, E, F may differ where a crack's edge was split or a hole fanned) and no flaw
//! of the repaired kinds; a facet that hung on a non-manifold edge or touched the surface at
//! one vertex comes apart as a triangle of its own (one component, χ 1, one loop more). A
//! clean mesh comes back unchanged; the paper's stamp loses its three flaws and its stage
//! test points verify.

use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use surfkit::mesh::PolygonMesh;
use surfkit::repair::{check_fixes, repair, RepairOptions};
use surfkit::shapes::{stamp, StampFlaw};
use surfkit::topology::{scan, EatOptions, EatReport, FlawKind};

fn eat(mesh: &PolygonMesh) -> EatReport {
    scan(mesh, &EatOptions::default()).unwrap()
}

/// (χ, boundary loops, components, genus per component) of a report.
fn topology(r: &EatReport) -> (i64, usize, usize, Vec<Option<i64>>) {
    let mut genera: Vec<Option<i64>> = r.components.iter().map(|c| c.genus).collect();
    genera.sort();
    (
        r.counts.euler_characteristic,
        r.counts.boundary_loops,
        r.counts.components,
        genera,
    )
}

/// Repairs `broken` and checks the result against the expected topology.
fn check(
    label: &str,
    broken: &PolygonMesh,
    options: &RepairOptions,
    expected: (i64, usize, usize, Vec<Option<i64>>),
) {
    let before = eat(broken);
    assert!(
        !before.flaws.is_empty(),
        "{label}: the injection made a flaw"
    );
    // Each suggested fix, checked by applying it, is found to work (a judgment call, the
    // border of an isolated facet, stays unchecked).
    let mut checked = before.flaws.clone();
    check_fixes(broken, &mut checked, options.locator).unwrap();
    assert!(
        checked.iter().all(|f| f.fix_verified != Some(false)),
        "{label}: {checked:#?}"
    );
    assert!(
        checked.iter().any(|f| f.fix_verified == Some(true)),
        "{label}"
    );
    let repaired = repair(broken, options).unwrap();
    assert!(
        !repaired.changes.is_empty(),
        "{label}: something was changed"
    );
    let after = eat(&repaired.mesh);
    let left = repaired.remaining(&after, options);
    // Coincidences the repair left are only split vertices and their copies.
    for f in after
        .flaws
        .iter()
        .filter(|f| f.kind == FlawKind::CoincidentVertices)
    {
        let split = repaired.changes.iter().any(|c| {
            c.vertices_after.contains(&Some(f.vertices[0]))
                && c.vertices_after.contains(&Some(f.vertices[1]))
        });
        assert!(split, "{label}: {f:?}");
    }
    assert!(
        left.is_empty(),
        "{label}: left {left:#?}\nchanges {:#?}",
        repaired.changes
    );
    assert_eq!(
        topology(&after),
        expected,
        "{label}: {:?}",
        after.flaw_counts()
    );
}

/// The original's topology with one isolated triangle more.
fn plus_triangle(
    t: &(i64, usize, usize, Vec<Option<i64>>),
) -> (i64, usize, usize, Vec<Option<i64>>) {
    let mut genera = t.3.clone();
    genera.push(Some(0));
    genera.sort();
    (t.0 + 1, t.1 + 1, t.2 + 1, genera)
}

#[test]
fn a_clean_mesh_comes_back_unchanged() {
    for (name, mesh) in crate::common::sound_meshes(false) {
        let r = repair(&mesh, &RepairOptions::default()).unwrap();
        assert!(r.changes.is_empty(), "{name}: {:?}", r.changes);
        assert_eq!(r.mesh, mesh, "{name}");
    }
}

#[test]
fn every_injected_flaw_is_repaired_to_the_original_topology() {
    let mut rng = StdRng::seed_from_u64(0x4e_9a14);
    let options = RepairOptions::default();
    for (name, mesh) in crate::common::sound_meshes(false) {
        let faces = crate::common::faces_of(&mesh);
        let pos = mesh.positions.clone();
        let original = topology(&eat(&mesh));
        let pick = |rng: &mut StdRng| rng.random_range(0..faces.len());

        // A facet left out.
        let mut fewer = faces.clone();
        let removed = fewer.remove(pick(&mut rng));
        if removed.len() <= 4 {
            check(
                &format!("{name}: missing facet"),
                &PolygonMesh::from_polygons(pos.clone(), &fewer),
                &options,
                original.clone(),
            );
        }

        // A crack: a vertex at the middle of an edge, in one of its two facets only.
        let f = pick(&mut rng);
        let (a, b) = (faces[f][0], faces[f][1]);
        let mut p = pos.clone();
        let m = p.len() as u32;
        p.push([0, 1, 2].map(|k| 0.5 * (pos[a as usize][k] + pos[b as usize][k])));
        let mut cracked = faces.clone();
        cracked[f].insert(1, m);
        check(
            &format!("{name}: crack"),
            &PolygonMesh::from_polygons(p, &cracked),
            &options,
            original.clone(),
        );

        // A duplicated facet, another starting corner.
        let f = pick(&mut rng);
        let mut doubled = faces.clone();
        let mut copy = faces[f].clone();
        copy.rotate_left(1);
        doubled.push(copy);
        check(
            &format!("{name}: duplicate"),
            &PolygonMesh::from_polygons(pos.clone(), &doubled),
            &options,
            original.clone(),
        );

        // A degenerate facet: a corner repeated.
        let f = pick(&mut rng);
        let mut degenerate = faces.clone();
        let first = degenerate[f][0];
        degenerate[f].insert(0, first);
        check(
            &format!("{name}: degenerate"),
            &PolygonMesh::from_polygons(pos.clone(), &degenerate),
            &options,
            original.clone(),
        );

        // Coincident vertices: a copy of v used by one of v's facets.
        let f = pick(&mut rng);
        let v = faces[f][0];
        let mut p = pos.clone();
        p.push(pos[v as usize]);
        let mut split = faces.clone();
        split[f][0] = (p.len() - 1) as u32;
        check(
            &format!("{name}: coincident"),
            &PolygonMesh::from_polygons(p, &split),
            &options,
            original.clone(),
        );

        // An unreferenced vertex.
        let mut p = pos.clone();
        p.push([9.0, 9.0, 9.0]);
        check(
            &format!("{name}: unreferenced"),
            &PolygonMesh::from_polygons(p, &faces),
            &options,
            original.clone(),
        );

        // One facet reversed.
        let f = pick(&mut rng);
        let mut flipped = faces.clone();
        flipped[f].reverse();
        check(
            &format!("{name}: reversed facet"),
            &PolygonMesh::from_polygons(pos.clone(), &flipped),
            &options,
            original.clone(),
        );

        // A fin on an edge (non-manifold edge): it comes apart as a triangle of its own.
        let f = pick(&mut rng);
        let (a, b) = (faces[f][0], faces[f][1]);
        let mut p = pos.clone();
        p.push([
            pos[a as usize][0] + 1.0,
            pos[a as usize][1] + 2.0,
            pos[a as usize][2] + 3.0,
        ]);
        let mut finned = faces.clone();
        finned.push(vec![a, b, (p.len() - 1) as u32]);
        check(
            &format!("{name}: fin"),
            &PolygonMesh::from_polygons(p, &finned),
            &options,
            plus_triangle(&original),
        );

        // A triangle touching the surface at one vertex (non-manifold vertex).
        let v = rng.random_range(0..pos.len() as u32);
        let mut p = pos.clone();
        p.push([5.0, 5.0, 5.0]);
        p.push([6.0, 5.0, 5.0]);
        let mut pinched = faces.clone();
        pinched.push(vec![v, (p.len() - 2) as u32, (p.len() - 1) as u32]);
        check(
            &format!("{name}: pinched"),
            &PolygonMesh::from_polygons(p, &pinched),
            &options,
            plus_triangle(&original),
        );

        // A hole (a vertex's facets left out, the vertex left unreferenced), closed on
        // request by a fan.
        let v = faces[pick(&mut rng)][0];
        let holed: Vec<Vec<u32>> = faces.iter().filter(|f| !f.contains(&v)).cloned().collect();
        let fill = RepairOptions {
            kinds: FlawKind::ALL.to_vec(),
            max_hole_edges: 64,
            ..RepairOptions::default()
        };
        check(
            &format!("{name}: hole"),
            &PolygonMesh::from_polygons(pos.clone(), &holed),
            &fill,
            original.clone(),
        );
    }
}

#[test]
fn the_stamp_loses_its_three_flaws_and_its_test_points_verify() {
    let broken = stamp(&[
        StampFlaw::TinyTriangle,
        StampFlaw::NarrowQuad,
        StampFlaw::Crack,
    ]);
    let before = scan(&broken, &crate::common::stamp_stages(&broken)).unwrap();
    assert_eq!(before.flaws.len(), 3);
    assert!(!before.verified());
    let repaired = repair(&broken, &RepairOptions::default()).unwrap();
    assert_eq!(repaired.changes.len(), 3, "{:#?}", repaired.changes);
    let after = scan(&repaired.mesh, &crate::common::stamp_stages(&repaired.mesh)).unwrap();
    assert!(after.flaws.is_empty(), "{:?}", after.flaw_counts());
    assert!(after.verified(), "{:#?}", after.checkpoints);
    let clean = stamp(&[]);
    assert_eq!(
        after.statistics,
        scan(&clean, &EatOptions::default()).unwrap().statistics
    );
}

/// A Möbius strip of 6 quads: no orientation agrees across its twist and its border has
/// no side to fill from, so the suggested fixes are checked and found not to work, and the
/// repair leaves the strip as it is.
#[test]
fn fixes_that_cannot_work_on_a_moebius_strip_are_reported_unverified() {
    let n = 6;
    let mut positions = Vec::new();
    for i in 0..n {
        let t = std::f64::consts::TAU * i as f64 / n as f64;
        let (h, r) = ((t / 2.0).cos() * 0.3, (t / 2.0).sin() * 0.3);
        positions.push([(1.0 + r) * t.cos(), (1.0 + r) * t.sin(), h]);
        positions.push([(1.0 - r) * t.cos(), (1.0 - r) * t.sin(), -h]);
    }
    let faces: Vec<Vec<u32>> = (0..n as u32)
        .map(|i| {
            let (c, d) = if i + 1 == n as u32 {
                (1, 0)
            } else {
                (2 * i + 2, 2 * i + 3)
            };
            vec![2 * i, 2 * i + 1, d, c]
        })
        .collect();
    let strip = PolygonMesh::from_polygons(positions, &faces);
    let mut flaws = eat(&strip).flaws;
    let kinds: Vec<FlawKind> = flaws.iter().map(|f| f.kind).collect();
    assert!(
        kinds.contains(&FlawKind::InconsistentOrientation),
        "{kinds:?}"
    );
    assert!(kinds.contains(&FlawKind::Hole), "{kinds:?}");
    check_fixes(&strip, &mut flaws, Default::default()).unwrap();
    assert!(
        flaws.iter().all(|f| f.fix_verified == Some(false)),
        "{flaws:#?}"
    );
    let all = RepairOptions {
        kinds: FlawKind::ALL.to_vec(),
        max_hole_edges: 2 * n,
        ..RepairOptions::default()
    };
    assert!(repair(&strip, &all).unwrap().changes.is_empty());
}

#[test]
fn two_tetrahedra_glued_on_a_duplicated_facet_come_apart_closed() {
    // MeshLab's joined_tetrahedra: two tetrahedra sharing a face, written once per solid.
    // Deleting the duplicate and taking the three non-manifold edges apart leaves one
    // solid without that face: the repair closes the loop it opened, so the result is two
    // closed tetrahedra (χ 2 each) with nothing of the repaired kinds left.
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/fixtures/meshes/joined_tetrahedra.obj"
    );
    let mesh = surfkit::mesh::io::read(std::path::Path::new(path)).unwrap();
    let options = RepairOptions::default();
    let repaired = repair(&mesh, &options).unwrap();
    let after = eat(&repaired.mesh);
    assert_eq!(
        topology(&after),
        (4, 0, 2, vec![Some(0), Some(0)]),
        "{:?}",
        repaired.changes
    );
    assert!(repaired.remaining(&after, &options).is_empty());
    assert_eq!(
        repaired
            .changes
            .iter()
            .filter(|c| c.kind == FlawKind::MissingTriangle)
            .count(),
        1
    );
}
