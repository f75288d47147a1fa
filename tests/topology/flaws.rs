//! Flawed variants of the clean real meshes — one flaw of each kind, injected at a random
//! place (fixed seed) — and the locator must find each with the right kind and ids, and
//! nothing on the clean originals.

use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use surfkit::mesh::PolygonMesh;
use surfkit::topology::{scan, EatOptions, EatReport, Flaw, FlawKind};

fn rebuild(positions: Vec<[f64; 3]>, faces: &[Vec<u32>]) -> PolygonMesh {
    PolygonMesh::from_polygons(positions, faces)
}

fn flaws_of(report: &EatReport, kind: FlawKind) -> Vec<&Flaw> {
    report.flaws.iter().filter(|f| f.kind == kind).collect()
}

fn sorted(v: &[u32]) -> Vec<u32> {
    let mut s = v.to_vec();
    s.sort_unstable();
    s
}

/// A random edge {a, b} of facet f and the other facet g on it.
fn random_shared_edge(faces: &[Vec<u32>], rng: &mut StdRng) -> (usize, usize, u32, u32) {
    let f = rng.random_range(0..faces.len());
    let n = faces[f].len();
    let k = rng.random_range(0..n);
    let (a, b) = (faces[f][k], faces[f][(k + 1) % n]);
    let g = faces
        .iter()
        .enumerate()
        .position(|(i, face)| i != f && face.contains(&a) && face.contains(&b))
        .unwrap();
    (f, g, a, b)
}

#[test]
fn clean_originals_report_nothing() {
    for (name, mesh) in crate::common::sound_meshes(false) {
        let report = scan(&mesh, &EatOptions::default()).unwrap();
        assert!(
            report.flaws.is_empty(),
            "{name}: {:?}",
            report.flaw_counts()
        );
    }
}

#[test]
fn each_injected_flaw_is_found_with_its_kind_and_ids() {
    let mut rng = StdRng::seed_from_u64(20_200_228);
    let meshes = crate::common::sound_meshes(false);
    assert!(meshes.len() >= 4, "need several clean meshes");
    for (name, mesh) in &meshes {
        let faces = crate::common::faces_of(mesh);
        let positions = mesh.positions.clone();

        // A facet left out: a missing triangle or quad (or a hole for larger facets).
        let f = rng.random_range(0..faces.len());
        let mut fewer = faces.clone();
        let removed = fewer.remove(f);
        let report = scan(&rebuild(positions.clone(), &fewer), &EatOptions::default()).unwrap();
        let kind = match removed.len() {
            3 => FlawKind::MissingTriangle,
            4 => FlawKind::MissingQuad,
            _ => FlawKind::Hole,
        };
        let found = flaws_of(&report, kind);
        assert_eq!(
            found.len(),
            1,
            "{name}: {kind:?} {:?}",
            report.flaw_counts()
        );
        assert_eq!(
            sorted(&found[0].vertices),
            sorted(&removed),
            "{name}: missing facet"
        );
        assert_eq!(report.flaws.len(), 1, "{name}: only the missing facet");

        // A hole: a facet and all its edge neighbours left out (on meshes large enough
        // that what remains is more than one facet: on the cube it would be a missing quad).
        let f = rng.random_range(0..faces.len());
        if faces.len() >= 20 {
            let ring: Vec<usize> = (0..faces.len())
                .filter(|&g| {
                    let n = faces[f].len();
                    g == f
                        || (0..n).any(|k| {
                            faces[g].contains(&faces[f][k])
                                && faces[g].contains(&faces[f][(k + 1) % n])
                        })
                })
                .collect();
            let kept: Vec<Vec<u32>> = (0..faces.len())
                .filter(|g| !ring.contains(g))
                .map(|g| faces[g].clone())
                .collect();
            let report = scan(&rebuild(positions.clone(), &kept), &EatOptions::default()).unwrap();
            let holes = flaws_of(&report, FlawKind::Hole);
            assert_eq!(holes.len(), 1, "{name}: hole {:?}", report.flaw_counts());
            let rim: std::collections::BTreeSet<u32> = ring
                .iter()
                .flat_map(|&g| faces[g].iter().copied())
                .collect();
            assert!(
                holes[0].vertices.iter().all(|v| rim.contains(v)),
                "{name}: hole rim"
            );
            assert!(
                !holes[0]
                    .vertices
                    .iter()
                    .any(|v| faces[f].contains(v) && !kept.iter().any(|k| k.contains(v))),
                "{name}: rim only"
            );
        }

        // A crack: a vertex inserted at the midpoint of an edge in one of its two facets.
        let (f1, _, a, b) = random_shared_edge(&faces, &mut rng);
        let mut pos = positions.clone();
        let m = pos.len() as u32;
        let (pa, pb) = (pos[a as usize], pos[b as usize]);
        pos.push([
            0.5 * (pa[0] + pb[0]),
            0.5 * (pa[1] + pb[1]),
            0.5 * (pa[2] + pb[2]),
        ]);
        let mut cracked = faces.clone();
        let k = cracked[f1].iter().position(|&v| v == a).unwrap();
        let n = cracked[f1].len();
        if cracked[f1][(k + 1) % n] == b {
            cracked[f1].insert(k + 1, m);
        } else {
            cracked[f1].insert(k, m);
        }
        let report = scan(&rebuild(pos, &cracked), &EatOptions::default()).unwrap();
        let cracks = flaws_of(&report, FlawKind::Crack);
        assert_eq!(cracks.len(), 1, "{name}: crack {:?}", report.flaw_counts());
        assert_eq!(
            sorted(&cracks[0].vertices[..2]),
            sorted(&[a, b]),
            "{name}: crack edge"
        );
        assert_eq!(&cracks[0].vertices[2..], &[m], "{name}: crack chain");
        assert_eq!(report.flaws.len(), 1, "{name}: only the crack");

        // A non-manifold edge: a fin facet on an existing edge.
        let (_, _, a, b) = random_shared_edge(&faces, &mut rng);
        let mut pos = positions.clone();
        let p = pos.len() as u32;
        pos.push([
            pos[a as usize][0] + 1.0,
            pos[a as usize][1] + 2.0,
            pos[a as usize][2] + 3.0,
        ]);
        let mut finned = faces.clone();
        finned.push(vec![a, b, p]);
        let report = scan(&rebuild(pos, &finned), &EatOptions::default()).unwrap();
        let nm = flaws_of(&report, FlawKind::NonManifoldEdge);
        assert_eq!(nm.len(), 1, "{name}: nm edge");
        assert_eq!(sorted(&nm[0].vertices), sorted(&[a, b]));
        assert!(
            nm[0].faces.contains(&(faces.len() as u32)),
            "{name}: the fin is named"
        );

        // A non-manifold vertex: a triangle touching the surface at one vertex.
        let v = rng.random_range(0..positions.len() as u32);
        let mut pos = positions.clone();
        let (p, q) = (pos.len() as u32, pos.len() as u32 + 1);
        pos.push([5.0, 5.0, 5.0]);
        pos.push([6.0, 5.0, 5.0]);
        let mut pinched = faces.clone();
        pinched.push(vec![v, p, q]);
        let report = scan(&rebuild(pos, &pinched), &EatOptions::default()).unwrap();
        let nmv = flaws_of(&report, FlawKind::NonManifoldVertex);
        assert_eq!(nmv.len(), 1, "{name}: nm vertex");
        assert_eq!(nmv[0].vertices, vec![v]);

        // A duplicated facet (same vertices, another starting corner).
        let f = rng.random_range(0..faces.len());
        let mut doubled = faces.clone();
        let mut copy = faces[f].clone();
        copy.rotate_left(1);
        doubled.push(copy);
        let report = scan(
            &rebuild(positions.clone(), &doubled),
            &EatOptions::default(),
        )
        .unwrap();
        let dup = flaws_of(&report, FlawKind::DuplicatedFacet);
        assert_eq!(dup.len(), 1, "{name}: duplicate");
        assert_eq!(dup[0].faces, vec![faces.len() as u32, f as u32]);

        // A degenerate facet: a corner repeated (its edges unchanged).
        let f = rng.random_range(0..faces.len());
        let mut degenerate = faces.clone();
        let first = degenerate[f][0];
        degenerate[f].insert(0, first);
        let report = scan(
            &rebuild(positions.clone(), &degenerate),
            &EatOptions::default(),
        )
        .unwrap();
        let deg = flaws_of(&report, FlawKind::DegenerateFacet);
        assert_eq!(deg.len(), 1, "{name}: degenerate");
        assert_eq!(deg[0].faces, vec![f as u32]);
        assert_eq!(report.flaws.len(), 1, "{name}: only the degenerate facet");

        // Coincident vertices: a copy of v, used by one of v's facets instead of v.
        let f = rng.random_range(0..faces.len());
        let v = faces[f][0];
        let mut pos = positions.clone();
        let w = pos.len() as u32;
        pos.push(pos[v as usize]);
        let mut split = faces.clone();
        split[f][0] = w;
        let report = scan(&rebuild(pos, &split), &EatOptions::default()).unwrap();
        let co = flaws_of(&report, FlawKind::CoincidentVertices);
        assert_eq!(co.len(), 1, "{name}: coincident");
        assert_eq!(co[0].vertices, vec![w, v]);

        // An unreferenced vertex.
        let mut pos = positions.clone();
        pos.push([9.0, 9.0, 9.0]);
        let report = scan(&rebuild(pos, &faces), &EatOptions::default()).unwrap();
        let un = flaws_of(&report, FlawKind::UnreferencedVertex);
        assert_eq!(un.len(), 1, "{name}: unreferenced");
        assert_eq!(un[0].vertices, vec![positions.len() as u32]);
        assert_eq!(
            report.flaws.len(),
            1,
            "{name}: only the unreferenced vertex"
        );

        // Inconsistent orientation: one facet reversed.
        let f = rng.random_range(0..faces.len());
        let mut flipped = faces.clone();
        flipped[f].reverse();
        let report = scan(
            &rebuild(positions.clone(), &flipped),
            &EatOptions::default(),
        )
        .unwrap();
        let inc = flaws_of(&report, FlawKind::InconsistentOrientation);
        assert_eq!(
            inc.len(),
            faces[f].len(),
            "{name}: one per edge of the reversed facet"
        );
        assert!(
            inc.iter().all(|fl| fl.faces.contains(&(f as u32))),
            "{name}: the reversed facet is named"
        );
    }
}

#[test]
fn loops_joined_at_a_non_manifold_edge_are_not_holes_to_fill() {
    // OpenSubdiv's test mesh: 100 quads on one edge. Walking their borders joins them in
    // pairs at the edge's ends; filling such a loop would put a 101st facet on the edge.
    let path = crate::common::meshes_dir().join("catmark_nonman_edge100.obj");
    let mesh = surfkit::mesh::io::read(&path).unwrap();
    let mut report = scan(&mesh, &EatOptions::default()).unwrap();
    surfkit::repair::check_fixes(&mesh, &mut report.flaws, Default::default()).unwrap();
    let edges = flaws_of(&report, FlawKind::NonManifoldEdge);
    assert_eq!(edges.len(), 1);
    let (ends, on_edge) = (&edges[0].vertices, &edges[0].faces);
    assert_eq!(on_edge.len(), 100);
    assert_eq!(
        edges[0].fix_verified,
        Some(true),
        "the separation is checked"
    );
    let loops = flaws_of(&report, FlawKind::Hole);
    assert_eq!(loops.len(), 50);
    for l in loops {
        assert!(ends.iter().all(|v| l.vertices.contains(v)), "{l:?}");
        assert_eq!(sorted(&l.faces), sorted(on_edge));
        let edge = format!("{{{}, {}}}", ends[0], ends[1]);
        assert!(l.suggested_fix.contains(&edge), "{}", l.suggested_fix);
        assert!(!l.suggested_fix.contains("fill"), "{}", l.suggested_fix);
    }
}
