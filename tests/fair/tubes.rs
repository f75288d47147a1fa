//! The junction-of-tubes generator and the author's surface refinement: counts from the
//! construction's own arithmetic and from the paper (Table 1) and issue 6, checked with the
//! EAT statistics; the refined surface compared with the unrefined one by OpenSubdiv's
//! limit evaluation.

use std::collections::{HashMap, HashSet};

use surfkit::fair::{
    condition_violation, fixed_vertices, prepare, refine_surface, tubes, MeshTopology, SurfaceKind,
};
use surfkit::mesh::PolygonMesh;
use surfkit::subdiv::{
    limit_surface, refine_uniform, BoundaryInterpolation, PatchOptions, SubdivOptions, SurfacePoint,
};
use surfkit::tolerance::ROUND_OFF;
use surfkit::topology::{scan, EatOptions, FlawKind};

/// Lengths of the boundary loops, from the directed boundary edges (each loop once).
fn boundary_loops(mesh: &PolygonMesh) -> Vec<usize> {
    let mut directed: HashMap<(u32, u32), u32> = HashMap::new();
    for f in mesh.faces() {
        for c in 0..f.len() {
            *directed.entry((f[c], f[(c + 1) % f.len()])).or_insert(0) += 1;
        }
    }
    // Every directed edge at most once: orientable and consistently oriented.
    assert!(directed.values().all(|&n| n == 1));
    let next: HashMap<u32, u32> = directed
        .keys()
        .filter(|&&(a, b)| !directed.contains_key(&(b, a)))
        .copied()
        .collect();
    let mut seen = HashSet::new();
    let mut starts: Vec<u32> = next.keys().copied().collect();
    starts.sort_unstable();
    let mut loops = Vec::new();
    for a in starts {
        let (mut v, mut len) = (a, 0);
        while seen.insert(v) {
            v = next[&v];
            len += 1;
        }
        if len > 0 {
            loops.push(len);
        }
    }
    loops
}

/// Everything a junction of `n` tubes with `end` boundary vertices per tube end must be:
/// quads; by the EAT one component, genus 0, n boundary loops, χ = 2 − n, no flaw but
/// the n holes; two
/// special vertices of valence 2n, every other internal vertex of valence 4, every
/// boundary vertex of valence 3; the optimizer's conditions met without refinement.
fn check_junction(mesh: &PolygonMesh, n: usize, end: usize) {
    assert!(mesh.faces().all(|f| f.len() == 4));
    let eat = scan(mesh, &EatOptions::default()).unwrap();
    let chi = 2 - n as i64;
    assert_eq!(eat.counts.euler_characteristic, chi);
    assert_eq!(eat.counts.components, 1);
    assert_eq!(eat.counts.genus, Some(0));
    assert_eq!(eat.counts.boundary_loops, n);
    assert_eq!(eat.counts.boundary_edges, n * end);
    // The tube ends are the only "flaws": holes, one per tube (a loop of 4 edges is
    // reported as a missing quad).
    let kind = if end == 4 {
        FlawKind::MissingQuad
    } else {
        FlawKind::Hole
    };
    assert_eq!(eat.flaw_counts(), vec![(kind, n)]);
    assert_eq!(boundary_loops(mesh), vec![end; n]);

    let topo = MeshTopology::new(mesh).unwrap();
    assert_eq!(topo.euler_characteristic(), chi);
    let special = topo.special_vertices();
    assert_eq!(special.len(), 2);
    for v in 0..mesh.vertex_count() {
        let expected = if topo.boundary[v] {
            3
        } else if special.contains(&(v as u32)) {
            2 * n
        } else {
            4
        };
        assert_eq!(topo.valence(v), expected, "vertex {v}");
    }
    assert!(condition_violation(mesh, &topo, SurfaceKind::CatmullClark).is_none());
    let (prepared, levels) = prepare(mesh, 0, SurfaceKind::CatmullClark).unwrap();
    assert_eq!(levels, 0);
    assert_eq!(prepared.positions, mesh.positions);
}

/// Vertices and faces of `tubes(n, m, rings)` by the construction: two discs of 2n m × m
/// sectors glued along n seams of 2m edges, and n tubes of `rings` rings of 4m quads.
fn construction_counts(n: usize, m: usize, rings: usize) -> (usize, usize) {
    let disc = 1 + 2 * n * m + 2 * n * m * m;
    let vertices = 2 * disc - n * (2 * m + 1) + n * 4 * m * rings;
    let faces = 2 * 2 * n * m * m + n * 4 * m * rings;
    (vertices, faces)
}

#[test]
fn fair_tubes_author_mesh_counts() {
    let mesh = tubes(3, 4, 3).unwrap();
    // The author's three-tube mesh (issue 6).
    assert_eq!((mesh.vertex_count(), mesh.face_count()), (359, 336));
    assert_eq!(construction_counts(3, 4, 3), (359, 336));
    check_junction(&mesh, 3, 16);
}

#[test]
fn fair_tubes_any_number_of_tubes() {
    for (n, m, rings) in [
        (3, 1, 1),
        (4, 2, 2),
        (5, 3, 1),
        (5, 8, 2),
        (6, 2, 3),
        (8, 1, 2),
    ] {
        let mesh = tubes(n as u32, m as u32, rings as u32).unwrap();
        let counts = (mesh.vertex_count(), mesh.face_count());
        assert_eq!(counts, construction_counts(n, m, rings), "n = {n}, m = {m}");
        check_junction(&mesh, n, 4 * m);
    }
}

#[test]
fn fair_tubes_tubes_do_not_overlap() {
    // Tube ends are disjoint circles: every boundary vertex is closer to its own tube
    // end's centre than to any other's (the loops found above are the tube ends).
    for n in [3u32, 5, 7] {
        let mesh = tubes(n, 2, 2).unwrap();
        let topo = MeshTopology::new(&mesh).unwrap();
        let b = topo.boundary_vertices();
        let ends = b.len() / n as usize;
        // The generator numbers each tube's last ring consecutively.
        let centres: Vec<[f64; 3]> = b
            .chunks(ends)
            .map(|c| {
                let mut s = [0.0; 3];
                for &v in c {
                    for (acc, x) in s.iter_mut().zip(mesh.positions[v as usize]) {
                        *acc += x / c.len() as f64;
                    }
                }
                s
            })
            .collect();
        let d = |p: [f64; 3], q: [f64; 3]| (0..3).map(|x| (p[x] - q[x]).powi(2)).sum::<f64>();
        for (t, c) in b.chunks(ends).enumerate() {
            for &v in c {
                let p = mesh.positions[v as usize];
                for (u, &q) in centres.iter().enumerate() {
                    if u != t {
                        assert!(d(p, q) > d(p, centres[t]), "n = {n}, vertex {v}");
                    }
                }
            }
        }
    }
}

#[test]
fn fair_tubes_figure_7_mesh() {
    let mesh = tubes(3, 8, 2).unwrap();
    assert_eq!(mesh.vertex_count(), 1007);
    let topo = MeshTopology::new(&mesh).unwrap();
    assert_eq!(topo.euler_characteristic(), -1);
    let fixed = fixed_vertices(&topo, 3, &[]).unwrap();
    // Paper §6, figure 7: 719 of the 1007 vertices are computed by the optimization.
    assert_eq!(fixed.iter().filter(|&&f| !f).count(), 719);
}

#[test]
fn fair_tubes_rejects_bad_arguments() {
    assert!(tubes(2, 4, 3).is_err());
    assert!(tubes(3, 0, 3).is_err());
    assert!(tubes(3, 4, 0).is_err());
    assert!(tubes(65, 1, 1).is_err());
}

/// Counts after one refinement of the surface: Catmull–Clark gives V + E + F vertices and
/// 4F quads; the dropped ring is the 2B refined boundary vertices and the 2B quads on the
/// refined boundary edges (every boundary vertex has valence 3).
fn refined_counts(mesh: &PolygonMesh) -> (usize, usize, usize) {
    let topo = MeshTopology::new(mesh).unwrap();
    let (v, e, f) = (mesh.vertex_count(), topo.edges.len(), mesh.face_count());
    let b = topo.boundary_vertices().len();
    (v + e + f - 2 * b, 4 * f - 2 * b, 2 * b)
}

#[test]
fn fair_tubes_author_refinements() {
    // Issue 6: one and two refinements of the author's mesh give 1295 and 4895 vertices.
    let mut mesh = tubes(3, 4, 3).unwrap();
    for (level, vertices, end) in [(1, 1295, 32), (2, 4895, 64)] {
        let expected = refined_counts(&mesh);
        mesh = refine_surface(&mesh, 1).unwrap();
        assert_eq!(mesh.vertex_count(), vertices, "level {level}");
        assert_eq!(
            (mesh.vertex_count(), mesh.face_count(), 3 * end),
            expected,
            "level {level}"
        );
        check_junction(&mesh, 3, end);
        // Free vertices under the 3-ring rule: three rings of `end` vertices per tube end
        // (level 1: 1007, the "1295 vertices (1007 free)" of BSTools' run).
        let topo = MeshTopology::new(&mesh).unwrap();
        let fixed = fixed_vertices(&topo, 3, &[]).unwrap();
        let free = fixed.iter().filter(|&&f| !f).count();
        assert_eq!(free, vertices - 3 * 3 * end, "level {level}");
    }
    assert_eq!(refine_surface(&tubes(3, 4, 3).unwrap(), 2).unwrap(), mesh);
}

#[test]
fn fair_tubes_paper_table_1_sizes() {
    // Table 1: n_V of the junctions of three (figure 9) and five (figure 10) tubes.
    for (n, sizes, end) in [(3, [1007, 3743, 14399], 32), (5, [1677, 6237, 23997], 32)] {
        let base = tubes(n, 8, 2).unwrap();
        for (level, &vertices) in sizes.iter().enumerate() {
            let mesh = refine_surface(&base, level as u32).unwrap();
            assert_eq!(mesh.vertex_count(), vertices, "n = {n}, level {level}");
            check_junction(&mesh, n as usize, end << level);
        }
    }
}

#[test]
fn fair_tubes_closed_mesh_and_thin_mesh() {
    // A closed mesh has no ring to drop: refine_surface is Catmull–Clark.
    let cube = crate::common::unit_cube();
    let refined = refine_surface(&cube, 1).unwrap();
    assert_eq!((refined.vertex_count(), refined.face_count()), (26, 24));
    // A single quad is all boundary: refinement leaves nothing, an error not an empty mesh.
    let quad = PolygonMesh::from_polygons(
        vec![[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
        &[[0u32, 1, 2, 3]],
    );
    assert!(refine_surface(&quad, 1).is_err());
}

/// Limit positions on the grid {0, ½, 1}² (`half` = true) or at the corners only of every
/// face with a limit surface when boundary faces have none (the surface the optimizer
/// sees), leaving out points at special vertices, where OpenSubdiv's end caps only
/// approximate the limit (differently at different depths).
fn limit_points(mesh: &PolygonMesh, half: bool) -> Vec<[f64; 3]> {
    let options = SubdivOptions {
        boundary: BoundaryInterpolation::None,
        ..Default::default()
    };
    let surface = limit_surface(mesh, &options, &PatchOptions::default()).unwrap();
    let topo = MeshTopology::new(mesh).unwrap();
    let special: HashSet<u32> = topo.special_vertices().into_iter().collect();
    let steps: &[f64] = if half { &[0.0, 0.5, 1.0] } else { &[0.0, 1.0] };
    let mut out = Vec::new();
    for (f, corners) in mesh.faces().enumerate() {
        let mut points = Vec::new();
        for &v in steps {
            for &u in steps {
                // Quads are their own ptex faces: corner (0,0) is the face's first
                // vertex, (1,0) its second, (1,1) its third, (0,1) its fourth.
                let corner = match (u, v) {
                    (0.0, 0.0) => Some(corners[0]),
                    (1.0, 0.0) => Some(corners[1]),
                    (1.0, 1.0) => Some(corners[2]),
                    (0.0, 1.0) => Some(corners[3]),
                    _ => None,
                };
                if corner.is_some_and(|c| special.contains(&c)) {
                    continue;
                }
                points.push(SurfacePoint {
                    ptex_face: f as u32,
                    u,
                    v,
                });
            }
        }
        if surface.locate(&points[0]).is_err() {
            continue;
        }
        out.extend(
            surface
                .evaluate(&points)
                .unwrap()
                .iter()
                .map(|d| d.position),
        );
    }
    out
}

/// Whether every point of `a` is within `tol` of a point of `b`.
fn covered(a: &[[f64; 3]], b: &[[f64; 3]], tol: f64) -> bool {
    let mut sorted = b.to_vec();
    sorted.sort_by(|p, q| p[0].total_cmp(&q[0]));
    a.iter().all(|p| {
        let start = sorted.partition_point(|q| q[0] < p[0] - tol);
        sorted[start..]
            .iter()
            .take_while(|q| q[0] <= p[0] + tol)
            .any(|q| (0..3).all(|x| (p[x] - q[x]).abs() <= tol))
    })
}

#[test]
fn fair_tubes_refined_surface_is_the_same_surface() {
    // Knot insertion: the refined mesh's complete patches are the quarters of the
    // original's, so the limit points at the original's half-parameters are the refined
    // mesh's corner points, and no refined point lies elsewhere.
    let mesh = tubes(3, 4, 3).unwrap();
    let refined = refine_surface(&mesh, 1).unwrap();
    let coarse = limit_points(&mesh, true);
    let fine = limit_points(&refined, false);
    let (lo, hi) = mesh.bounding_box().unwrap();
    let diameter = (0..3).map(|x| (hi[x] - lo[x]).powi(2)).sum::<f64>().sqrt();
    let tol = ROUND_OFF * diameter;
    assert!(!coarse.is_empty());
    assert!(covered(&coarse, &fine, tol));
    assert!(covered(&fine, &coarse, tol));
    // The refined mesh is not plain Catmull–Clark: that has the 3 · 32 boundary vertices
    // of the refined tube ends more (issue 6: 1391 = 1295 + 96).
    let plain = refine_uniform(&mesh, 1, &SubdivOptions::default()).unwrap();
    assert_eq!(plain.vertex_count(), 1391);
}
