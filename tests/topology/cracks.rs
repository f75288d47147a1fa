//! Cracks (T-junctions) injected at seeded random places in every clean real mesh: isolated,
//! from a hole's rim, with one, two and three T-vertices on an edge, on the edge's line or
//! 0.1–0.5 % of its length off it. Each must be found as one crack with its edge and
//! T-vertices, the rest of the boundary reported as in the mesh without the crack, and
//! nothing called a crack on the originals, on meshes with ordinary holes, or where a
//! genuine triangle is missing.

use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use surfkit::mesh::PolygonMesh;
use surfkit::topology::{scan, EatOptions, EatReport, FlawKind};

/// The mesh with every facet around `v` removed: a hole whose rim is `v`'s link.
fn punch_hole(faces: &[Vec<u32>], v: u32) -> Vec<Vec<u32>> {
    faces.iter().filter(|f| !f.contains(&v)).cloned().collect()
}

/// The facets using edge {a, b}.
fn facets_on(faces: &[Vec<u32>], a: u32, b: u32) -> Vec<usize> {
    faces
        .iter()
        .enumerate()
        .filter(|(_, f)| {
            let n = f.len();
            (0..n).any(|k| {
                let (p, q) = (f[k], f[(k + 1) % n]);
                (p, q) == (a, b) || (p, q) == (b, a)
            })
        })
        .map(|(i, _)| i)
        .collect()
}

/// Puts `count` new vertices on edge {a, b} of facet `f` only, at jittered even spacing,
/// each `off` × the edge's length off the line towards the facet's centroid. Returns
/// their ids in order from a to b.
fn inject_t_vertices(
    positions: &mut Vec<[f64; 3]>,
    faces: &mut [Vec<u32>],
    f: usize,
    (a, b): (u32, u32),
    count: usize,
    off: f64,
    rng: &mut StdRng,
) -> Vec<u32> {
    let (pa, pb) = (positions[a as usize], positions[b as usize]);
    let d: Vec<f64> = (0..3).map(|k| pb[k] - pa[k]).collect();
    let length = d.iter().map(|x| x * x).sum::<f64>().sqrt();
    let n = faces[f].len() as f64;
    let centre: Vec<f64> = (0..3)
        .map(|k| {
            faces[f]
                .iter()
                .map(|&v| positions[v as usize][k])
                .sum::<f64>()
                / n
        })
        .collect();
    let mut ids = Vec::new();
    for i in 0..count {
        let t = (i as f64 + 1.0 + rng.random_range(-0.2..0.2)) / (count as f64 + 1.0);
        let foot: Vec<f64> = (0..3).map(|k| pa[k] + t * d[k]).collect();
        // Towards the centroid, without the component along the edge.
        let mut w: Vec<f64> = (0..3).map(|k| centre[k] - foot[k]).collect();
        let along = (0..3).map(|k| w[k] * d[k]).sum::<f64>() / (length * length);
        for k in 0..3 {
            w[k] -= along * d[k];
        }
        let wn = w.iter().map(|x| x * x).sum::<f64>().sqrt();
        let p = [0, 1, 2].map(|k| foot[k] + off * length * w[k] / wn);
        ids.push(positions.len() as u32);
        positions.push(p);
    }
    let face = &mut faces[f];
    let m = face.len();
    let k = face.iter().position(|&v| v == a).unwrap();
    if face[(k + 1) % m] == b {
        for (i, &t) in ids.iter().enumerate() {
            face.insert(k + 1 + i, t);
        }
    } else {
        // The facet runs b → a: insert in reverse order before a.
        for &t in ids.iter() {
            face.insert(k, t);
        }
    }
    ids
}

/// Boundary-loop flaws as (kind, sorted vertex set), for comparing the rest of a report.
fn loops_of(report: &EatReport) -> Vec<(FlawKind, Vec<u32>)> {
    let mut loops: Vec<(FlawKind, Vec<u32>)> = report
        .flaws
        .iter()
        .filter(|f| f.kind.is_boundary_loop() && f.kind != FlawKind::Crack)
        .map(|f| {
            let mut v = f.vertices.clone();
            v.sort_unstable();
            (f.kind, v)
        })
        .collect();
    loops.sort();
    loops
}

/// Checks that `report` has exactly one crack, on {a, b} with T-vertices `ts` (a → b
/// order), and otherwise the loops of `base`.
fn assert_one_crack(
    name: &str,
    report: &EatReport,
    base: &EatReport,
    (a, b): (u32, u32),
    ts: &[u32],
) {
    let cracks: Vec<_> = report
        .flaws
        .iter()
        .filter(|f| f.kind == FlawKind::Crack)
        .collect();
    assert_eq!(cracks.len(), 1, "{name}: {:?}", report.flaw_counts());
    let c = cracks[0];
    let (ca, cb) = (c.vertices[0], c.vertices[1]);
    let mut expected = ts.to_vec();
    if (ca, cb) == (b, a) {
        expected.reverse();
    } else {
        assert_eq!((ca, cb), (a, b), "{name}: crack edge");
    }
    assert_eq!(
        &c.vertices[2..],
        &expected[..],
        "{name}: T-vertices {:#?}",
        report.flaws
    );
    assert_eq!(
        loops_of(report),
        loops_of(base),
        "{name}: the rest of the boundary"
    );
    let others = report
        .flaws
        .iter()
        .filter(|f| !f.kind.is_boundary_loop())
        .count();
    assert_eq!(others, 0, "{name}: {:?}", report.flaw_counts());
}

#[test]
fn isolated_t_junctions_with_one_to_three_vertices_on_and_off_the_line() {
    let mut rng = StdRng::seed_from_u64(0x7_1c);
    for (name, mesh) in crate::common::sound_meshes(false) {
        let faces = crate::common::faces_of(&mesh);
        let base = scan(&mesh, &EatOptions::default()).unwrap();
        for count in 1..=3 {
            for off in [0.0, rng.random_range(0.001..0.005)] {
                let f = rng.random_range(0..faces.len());
                let k = rng.random_range(0..faces[f].len());
                let (a, b) = (faces[f][k], faces[f][(k + 1) % faces[f].len()]);
                let (mut pos, mut cracked) = (mesh.positions.clone(), faces.clone());
                let ts = inject_t_vertices(&mut pos, &mut cracked, f, (a, b), count, off, &mut rng);
                let report = scan(
                    &PolygonMesh::from_polygons(pos, &cracked),
                    &EatOptions::default(),
                )
                .unwrap();
                let label = format!("{name}: {count} T-vertices {off:.4} off");
                assert_one_crack(&label, &report, &base, (a, b), &ts);
            }
        }
    }
}

/// The vertices on edges of one facet.
fn rim_of(faces: &[Vec<u32>]) -> Vec<u32> {
    let mut count: std::collections::HashMap<(u32, u32), usize> = Default::default();
    for f in faces {
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    let mut rim: Vec<u32> = count
        .into_iter()
        .filter(|&(_, n)| n == 1)
        .flat_map(|((a, b), _)| [a, b])
        .collect();
    rim.sort_unstable();
    rim.dedup();
    rim
}

#[test]
fn t_junctions_from_a_hole_rim_or_the_outer_border_leave_that_loop_as_it_is() {
    let mut rng = StdRng::seed_from_u64(0x4013);
    let meshes = crate::common::sound_meshes(false)
        .into_iter()
        .map(|m| (m, true))
        .chain(
            crate::common::sound_meshes(true)
                .into_iter()
                .map(|m| (m, false)),
        );
    for ((name, mesh), punch) in meshes {
        let faces = crate::common::faces_of(&mesh);
        for round in 0..3 {
            // A hole around a random vertex (closed meshes), then an edge leaving a rim.
            let holed = if punch {
                punch_hole(&faces, rng.random_range(0..mesh.vertex_count() as u32))
            } else {
                faces.clone()
            };
            let rim = rim_of(&holed);
            let mut choices = Vec::new();
            for (f, face) in holed.iter().enumerate() {
                let n = face.len();
                for k in 0..n {
                    let (a, b) = (face[k], face[(k + 1) % n]);
                    if rim.contains(&a) && !rim.contains(&b) && facets_on(&holed, a, b).len() == 2 {
                        choices.push((f, a, b));
                    }
                }
            }
            if choices.is_empty() {
                continue;
            }
            let (f, a, b) = choices[rng.random_range(0..choices.len())];
            let base = scan(
                &PolygonMesh::from_polygons(mesh.positions.clone(), &holed),
                &EatOptions::default(),
            )
            .unwrap();
            assert!(
                base.flaws.iter().all(|f| f.kind != FlawKind::Crack),
                "{name}: an ordinary hole is no crack"
            );
            let count = 1 + round % 3;
            let off = [0.0, 0.002, 0.005][round % 3];
            let (mut pos, mut cracked) = (mesh.positions.clone(), holed.clone());
            let ts = inject_t_vertices(&mut pos, &mut cracked, f, (a, b), count, off, &mut rng);
            let report = scan(
                &PolygonMesh::from_polygons(pos, &cracked),
                &EatOptions::default(),
            )
            .unwrap();
            let label = format!("{name}: from the rim at {a}, {count} T-vertices {off} off");
            // The unreferenced vertex of a punched mesh is in both reports.
            let strip = |r: &EatReport| {
                let mut r = r.clone();
                r.flaws.retain(|f| f.kind != FlawKind::UnreferencedVertex);
                r
            };
            assert_one_crack(&label, &strip(&report), &strip(&base), (a, b), &ts);
        }
    }
}

#[test]
fn a_missing_triangle_far_from_any_edge_line_is_no_crack() {
    let mut rng = StdRng::seed_from_u64(0x3a);
    for (name, mesh) in crate::common::sound_meshes(false)
        .into_iter()
        .chain(crate::common::sound_meshes(true))
    {
        let faces = crate::common::faces_of(&mesh);
        let base = scan(&mesh, &EatOptions::default()).unwrap();
        let triangles: Vec<usize> = (0..faces.len()).filter(|&f| faces[f].len() == 3).collect();
        if triangles.is_empty() {
            continue;
        }
        let f = triangles[rng.random_range(0..triangles.len())];
        let mut kept = faces.clone();
        kept.remove(f);
        let report = scan(
            &PolygonMesh::from_polygons(mesh.positions.clone(), &kept),
            &EatOptions::default(),
        )
        .unwrap();
        let mut expected = base.flaw_counts();
        match expected
            .iter_mut()
            .find(|(k, _)| *k == FlawKind::MissingTriangle)
        {
            Some((_, n)) => *n += 1,
            None => expected.insert(0, (FlawKind::MissingTriangle, 1)),
        }
        assert_eq!(report.flaw_counts(), expected, "{name}");
    }
}

#[test]
fn an_isolated_facet_is_not_told_to_add_its_own_reverse() {
    let positions = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let report = scan(
        &PolygonMesh::from_polygons(positions, &[vec![0, 1, 2]]),
        &EatOptions::default(),
    )
    .unwrap();
    assert_eq!(report.flaws.len(), 1);
    assert_eq!(report.flaws[0].kind, FlawKind::Hole);
    assert_eq!(report.flaws[0].faces, vec![0]);
    assert!(!report.flaws[0].suggested_fix.contains("add the facet"));
}

/// A Möbius strip of `n` quads: one boundary loop walked once, one component with one
/// cross-cap, and the whole-mesh genus reported as non-orientable.
#[test]
fn a_moebius_strip_has_one_boundary_loop_and_non_orientable_genus_one() {
    for n in [5usize, 12] {
        let mut positions = Vec::new();
        for i in 0..n {
            let t = std::f64::consts::TAU * i as f64 / n as f64;
            let (c, s) = (t.cos(), t.sin());
            let h = (t / 2.0).cos() * 0.3;
            let r = (t / 2.0).sin() * 0.3;
            positions.push([(1.0 + r) * c, (1.0 + r) * s, h]);
            positions.push([(1.0 - r) * c, (1.0 - r) * s, -h]);
        }
        let m = |i: usize| (i % n) as u32;
        let faces: Vec<Vec<u32>> = (0..n)
            .map(|i| {
                let (a, b) = (2 * m(i), 2 * m(i) + 1);
                let (c, d) = if i + 1 == n {
                    (1, 0) // the half twist: the last quad meets the first upside down
                } else {
                    (2 * m(i + 1), 2 * m(i + 1) + 1)
                };
                vec![a, b, d, c]
            })
            .collect();
        let report = scan(
            &PolygonMesh::from_polygons(positions, &faces),
            &EatOptions::default(),
        )
        .unwrap();
        assert_eq!(report.counts.boundary_loops, 1);
        assert_eq!(
            report.counts.boundary_loops_walk, None,
            "inconsistent orientation"
        );
        let loops = boundary_loops(&report);
        assert_eq!(loops.len(), 1, "n = {n}: {:?}", report.flaw_counts());
        assert_eq!(loops[0].vertices.len(), 2 * n);
        assert_eq!(report.components[0].orientable, Some(false));
        assert_eq!(report.components[0].genus, Some(1));
        assert_eq!(report.counts.genus, None);
        assert_eq!(report.counts.non_orientable_genus, Some(1));
    }
}

/// A flat sliver triangle: its middle corner lies on its long edge, but the facet on that
/// edge uses it — no T-junction.
#[test]
fn a_sliver_facet_is_no_crack() {
    let positions = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.001], [2.0, 0.0, 0.0]];
    let report = scan(
        &PolygonMesh::from_polygons(positions, &[vec![0, 1, 2]]),
        &EatOptions::default(),
    )
    .unwrap();
    assert_eq!(report.flaw_counts(), vec![(FlawKind::Hole, 1)]);
}

/// The figure-8 immersion of a Klein bottle, an n × m quad grid whose u-seam meets itself
/// with v reversed (m odd, so no two grid vertices share a point): χ 0, no boundary, one
/// non-orientable component with two cross-caps — never "genus 1".
#[test]
fn a_klein_bottle_has_non_orientable_genus_two_and_no_orientable_genus() {
    for (n, m) in [(12usize, 7usize), (20, 9)] {
        let point = |u: f64, v: f64| {
            let a = (u / 2.0).cos() * v.sin() - (u / 2.0).sin() * (2.0 * v).sin();
            let z = (u / 2.0).sin() * v.sin() + (u / 2.0).cos() * (2.0 * v).sin();
            [(2.0 + a) * u.cos(), (2.0 + a) * u.sin(), z]
        };
        let mut positions = Vec::new();
        for i in 0..n {
            for j in 0..m {
                let u = std::f64::consts::TAU * i as f64 / n as f64;
                let v = std::f64::consts::TAU * j as f64 / m as f64;
                positions.push(point(u, v));
            }
        }
        // Grid vertex (i, j), with the seam i = n glued to i = 0 upside down.
        let id = |i: usize, j: usize| -> u32 {
            let j = j % m;
            if i == n {
                ((m - j) % m) as u32
            } else {
                (i * m + j) as u32
            }
        };
        let faces: Vec<Vec<u32>> = (0..n)
            .flat_map(|i| (0..m).map(move |j| (i, j)))
            .map(|(i, j)| vec![id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)])
            .collect();
        let report = scan(
            &PolygonMesh::from_polygons(positions, &faces),
            &EatOptions::default(),
        )
        .unwrap();
        let c = &report.counts;
        assert_eq!(
            (c.vertices_referenced, c.edges, c.facets),
            (n * m, 2 * n * m, n * m)
        );
        assert_eq!(c.euler_characteristic, 0);
        assert_eq!(c.boundary_loops, 0);
        assert_eq!(c.components, 1);
        assert_eq!(report.components[0].orientable, Some(false));
        assert_eq!(report.components[0].genus, Some(2), "2 − χ cross-caps");
        assert_eq!(c.genus, None, "no orientable genus for the whole mesh");
        assert_eq!(c.non_orientable_genus, Some(2));
        assert!(
            report.flaws.iter().all(|f| !f.kind.is_boundary_loop()),
            "{:?}",
            report.flaw_counts()
        );
    }
}

/// A fin (a triangle, or a flap of two) hanging on an edge of a closed tetrahedron: its
/// free border is one chain whose ends meet across the non-manifold edge, walked whole as
/// one loop — not as loops of one edge and perimeter 0.
#[test]
fn a_fin_on_an_edge_has_one_boundary_loop_closed_across_that_edge() {
    let positions = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [2.0, 1.0, 1.0],
    ];
    let tetrahedron = vec![vec![0, 2, 1], vec![0, 1, 3], vec![1, 2, 3], vec![0, 3, 2]];
    // The report and its one boundary loop (sorted vertices, faces) of the tetrahedron
    // with `extra` facets on its edge {0, 1}, over the first `vertices` positions.
    let one_loop = |extra: &[Vec<u32>], vertices: usize| {
        let mut faces = tetrahedron.clone();
        faces.extend_from_slice(extra);
        let mesh = PolygonMesh::from_polygons(positions[..vertices].to_vec(), &faces);
        let report = scan(&mesh, &EatOptions::default()).unwrap();
        let loops = boundary_loops(&report);
        assert_eq!(loops.len(), 1, "{:?}", report.flaw_counts());
        let mut border = loops[0].vertices.clone();
        border.sort_unstable();
        let faces = loops[0].faces.clone();
        (report, border, faces)
    };
    let (report, border, faces) = one_loop(&[vec![0, 1, 4]], 5);
    assert_eq!(report.counts.boundary_loops, 1);
    assert_eq!(border, vec![0, 1, 4]);
    assert_eq!(faces, vec![4], "the fin's own border");
    assert_eq!(
        report.flaw_counts().len(),
        2,
        "and the non-manifold edge: {:#?}",
        report.flaws
    );
    let (_, border, _) = one_loop(&[vec![0, 1, 4], vec![4, 1, 5]], 6);
    assert_eq!(border, vec![0, 1, 4, 5]);
}

/// The report's flaws that are boundary loops (holes, missing facets, cracks).
fn boundary_loops(report: &surfkit::topology::EatReport) -> Vec<&surfkit::topology::Flaw> {
    report
        .flaws
        .iter()
        .filter(|f| f.kind.is_boundary_loop())
        .collect()
}

/// A pile of `n` coincident degenerate triangles on one line — each with its own three
/// vertices at x = 0, 1, 2 — and, when `crack`, a crack on that line beside it: triangle
/// (0,0) (2,0) (1,1) over triangles (2,0) (1,0) (1,−1) and (1,0) (0,0) (1,−1), whose vertex
/// at (1,0) lies on the first one's edge. Every vertex of the crack lies where n vertices
/// of the pile do, and its edge where n edges of the pile do.
fn pile(n: usize, crack: bool) -> PolygonMesh {
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    for i in 0..n as u32 {
        positions.extend([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]);
        faces.push(vec![3 * i, 3 * i + 1, 3 * i + 2]);
    }
    if crack {
        let b = positions.len() as u32;
        positions.extend([
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, -1.0, 0.0],
        ]);
        faces.extend([
            vec![b, b + 1, b + 2],
            vec![b + 1, b + 3, b + 4],
            vec![b + 3, b, b + 4],
        ]);
    }
    PolygonMesh::from_polygons(positions, &faces)
}

/// Thousands of coincident degenerate facets (the crack search once listed every vertex of
/// the pile on every edge of it: quadratic) are no crack: each is an isolated facet, its
/// own hole, and its vertices coincide with the pile's. A crack beside the pile is found,
/// with nothing else of the pile taken for a T-vertex of it.
#[test]
fn a_pile_of_coincident_collinear_triangles_is_no_crack_and_one_beside_it_is_found() {
    let n = 3000;
    let report = scan(&pile(n, false), &EatOptions::default()).unwrap();
    let s = &report.statistics;
    assert_eq!(
        (s.vertices, s.edges, s.facets, s.euler_characteristic),
        (3 * n, 3 * n, n, n as i64)
    );
    assert_eq!(
        report.flaw_counts(),
        vec![
            (FlawKind::Hole, n),
            (FlawKind::CoincidentVertices, 3 * n - 3)
        ]
    );

    let report = scan(&pile(n, true), &EatOptions::default()).unwrap();
    let cracks: Vec<_> = report
        .flaws
        .iter()
        .filter(|f| f.kind == FlawKind::Crack)
        .collect();
    assert_eq!(cracks.len(), 1, "{:?}", report.flaw_counts());
    let b = 3 * n as u32;
    let mut edge = cracks[0].vertices[..2].to_vec();
    edge.sort_unstable();
    assert_eq!(
        edge,
        vec![b, b + 1],
        "the crack's edge: the top triangle's base"
    );
    assert_eq!(
        cracks[0].vertices[2..],
        [b + 3],
        "its T-vertex: the split at (1, 0)"
    );
    // Once stitched, the border of the three triangles is one loop of four edges; the pile
    // keeps its n holes, and the crack's five vertices add three coincidences (at x = 0,
    // 1, 2).
    let loops = loops_of(&report);
    let border: Vec<_> = loops.iter().filter(|(_, v)| v.contains(&(b + 2))).collect();
    assert_eq!(border.len(), 1);
    assert_eq!(border[0].1, vec![b, b + 1, b + 2, b + 4]);
    assert_eq!(loops.len(), n + 1);
    assert_eq!(
        report
            .flaw_counts()
            .iter()
            .find(|k| k.0 == FlawKind::CoincidentVertices),
        Some(&(FlawKind::CoincidentVertices, 3 * n))
    );
}
