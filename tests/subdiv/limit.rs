//! The limit surface (OpenSubdiv's adaptive patch table with B-spline end caps): regular
//! faces against the bicubic B-spline of their 1-ring, OpenSubdiv's EvaluateBasis against
//! the exported 16-point patches, derivatives against finite differences, coverage of the
//! faces, the boundary rule `None`, and curvatures against a closed form.

use surfkit::assert_near;
use surfkit::mesh::io::read;
use surfkit::mesh::PolygonMesh;
use surfkit::subdiv::{
    curvature, eval_patch, limit_surface, sample_limit, BoundaryInterpolation, Derivatives,
    PatchOptions, PatchSurface, SampleOptions, SubdivOptions, SurfacePoint,
};
use surfkit::tolerance::{FINITE_DIFFERENCE, ROUND_OFF};

fn surface(mesh: &PolygonMesh) -> PatchSurface {
    limit_surface(mesh, &SubdivOptions::default(), &PatchOptions::default()).unwrap()
}

fn assert_vec_near(a: [f64; 3], b: [f64; 3], tol: f64, what: &str) {
    for k in 0..3 {
        assert_near!(a[k], b[k], tol, "{what}[{k}]");
    }
}

fn all_orders(d: &Derivatives) -> [([f64; 3], &'static str); 10] {
    [
        (d.position, "position"),
        (d.du, "du"),
        (d.dv, "dv"),
        (d.duu, "duu"),
        (d.duv, "duv"),
        (d.dvv, "dvv"),
        (d.duuu, "duuu"),
        (d.duuv, "duuv"),
        (d.duvv, "duvv"),
        (d.dvvv, "dvvv"),
    ]
}

/// A closed n x m quad torus: every vertex has valence 4, every face is regular.
fn torus(n: u32, m: u32) -> PolygonMesh {
    let mut positions = Vec::new();
    for j in 0..m {
        for i in 0..n {
            let (t, p) = (
                std::f64::consts::TAU * i as f64 / n as f64,
                std::f64::consts::TAU * j as f64 / m as f64,
            );
            positions.push([
                (2.0 + 0.7 * p.cos()) * t.cos(),
                (2.0 + 0.7 * p.cos()) * t.sin(),
                0.7 * p.sin(),
            ]);
        }
    }
    let id = |i: u32, j: u32| (j % m) * n + (i % n);
    let faces: Vec<[u32; 4]> = (0..m)
        .flat_map(|j| (0..n).map(move |i| [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]))
        .collect();
    PolygonMesh::from_polygons(positions, &faces)
}

const SAMPLES: [(f64, f64); 5] = [(0.0, 0.0), (0.5, 0.5), (0.25, 0.8), (1.0, 0.3), (0.9, 1.0)];

#[test]
fn regular_faces_equal_the_bicubic_bspline_of_their_one_ring() {
    let (n, m) = (8u32, 6u32);
    let mesh = torus(n, m);
    let s = surface(&mesh);
    let id = |i: i64, j: i64| (j.rem_euclid(m as i64) * n as i64 + i.rem_euclid(n as i64)) as usize;
    for j in 0..m as i64 {
        for i in 0..n as i64 {
            let f = (j * n as i64 + i) as usize;
            assert_eq!(
                s.ptex_faces(f).unwrap(),
                f as u32..f as u32 + 1,
                "a quad is its own ptex face"
            );
            // The 4 x 4 one-ring, rows along v (j), columns along u (i).
            let ring: [[f64; 3]; 16] = std::array::from_fn(|k| {
                mesh.positions[id(i - 1 + (k % 4) as i64, j - 1 + (k / 4) as i64)]
            });
            let points: Vec<SurfacePoint> = SAMPLES
                .iter()
                .map(|&(u, v)| SurfacePoint {
                    ptex_face: f as u32,
                    u,
                    v,
                })
                .collect();
            let got = s.evaluate(&points).unwrap();
            for (&(u, v), d) in SAMPLES.iter().zip(&got) {
                let expect = eval_patch(&ring, u, v);
                for ((a, what), (b, _)) in all_orders(d).into_iter().zip(all_orders(&expect)) {
                    assert_vec_near(a, b, ROUND_OFF, &format!("face {f} ({u}, {v}) {what}"));
                }
            }
        }
    }
    assert!(s.patches().iter().all(|p| p.regular && p.depth == 0));
}

/// Meshes with extraordinary vertices, n-gons, boundaries and corners.
fn irregular_meshes() -> Vec<(&'static str, PolygonMesh)> {
    [
        "catmark_nonquads.obj",
        "rabbit.obj",
        "catmark_torus.obj",
        "comments.off",
        "target.obj",
    ]
    .into_iter()
    .map(|name| (name, read(&crate::cgal::fixture(name)).unwrap()))
    .collect()
}

#[test]
fn exported_patches_reproduce_opensubdiv_evaluate_basis() {
    // evaluate(): orders 0-2 from OpenSubdiv's EvaluateBasis on its own patch points
    // (phantoms folded into the weights); evaluate_in_patch(): our 16-point patch with
    // phantom points reproduced. They must agree on every patch, boundaries included.
    let (mut with_boundary, mut with_corner) = (0, 0);
    for (name, mesh) in irregular_meshes() {
        let s = surface(&mesh);
        for (p, patch) in s.patches().iter().enumerate() {
            with_boundary += (patch.boundary_mask != 0) as usize;
            with_corner += (patch.boundary_mask.count_ones() >= 2) as usize;
            for &(a, b) in &SAMPLES {
                let point = SurfacePoint {
                    ptex_face: patch.ptex_face,
                    u: patch.u0 + a * patch.size,
                    v: patch.v0 + b * patch.size,
                };
                let (q, sa, sb) = s.locate(&point).unwrap();
                let osd = s.evaluate(&[point]).unwrap()[0];
                let ours = s.evaluate_in_patch(q, sa, sb).unwrap();
                for ((x, what), (y, _)) in
                    all_orders(&osd).into_iter().zip(all_orders(&ours)).take(6)
                {
                    assert_vec_near(
                        x,
                        y,
                        ROUND_OFF,
                        &format!("{name} patch {p} ({a}, {b}) {what}"),
                    );
                }
            }
        }
    }
    assert!(with_boundary > 0, "no boundary patch was exercised");
    assert!(
        with_corner > 0,
        "no corner patch (two boundary bits) was exercised"
    );
}

#[test]
fn patch_weights_form_the_patch_control_points() {
    for (name, mesh) in irregular_meshes() {
        let s = surface(&mesh);
        for p in 0..s.patches().len() {
            let pts = s.patch_control_points(p).unwrap();
            let w = s.patch_weights(p).unwrap();
            for k in 0..16 {
                let mut q = [0.0; 3];
                for &(v, wt) in &w[k] {
                    for (qc, pc) in q.iter_mut().zip(mesh.positions[v as usize]) {
                        *qc += wt * pc;
                    }
                }
                assert_vec_near(q, pts[k], ROUND_OFF, &format!("{name} patch {p} point {k}"));
            }
        }
    }
}

#[test]
fn derivatives_match_finite_differences() {
    let h = 1e-5;
    for (name, mesh) in irregular_meshes() {
        let s = surface(&mesh);
        for (p, patch) in s.patches().iter().enumerate().step_by(7) {
            // Inside the patch so that the differences stay on one polynomial piece.
            let (u, v) = (patch.u0 + 0.37 * patch.size, patch.v0 + 0.61 * patch.size);
            let at = |du: f64, dv: f64| SurfacePoint {
                ptex_face: patch.ptex_face,
                u: u + du,
                v: v + dv,
            };
            let e = s
                .evaluate(&[
                    at(0.0, 0.0),
                    at(h, 0.0),
                    at(-h, 0.0),
                    at(0.0, h),
                    at(0.0, -h),
                ])
                .unwrap();
            let fd = |a: [f64; 3], b: [f64; 3]| -> [f64; 3] {
                std::array::from_fn(|k| (a[k] - b[k]) / (2.0 * h))
            };
            let (d, pu, mu, pv, mv) = (e[0], e[1], e[2], e[3], e[4]);
            let checks = [
                (fd(pu.position, mu.position), d.du, "du"),
                (fd(pv.position, mv.position), d.dv, "dv"),
                (fd(pu.du, mu.du), d.duu, "duu"),
                (fd(pv.du, mv.du), d.duv, "duv"),
                (fd(pv.dv, mv.dv), d.dvv, "dvv"),
                (fd(pu.duu, mu.duu), d.duuu, "duuu"),
                (fd(pv.duu, mv.duu), d.duuv, "duuv"),
                (fd(pu.dvv, mu.dvv), d.duvv, "duvv"),
                (fd(pv.dvv, mv.dvv), d.dvvv, "dvvv"),
            ];
            for (a, b, what) in checks {
                // Derivatives of order k grow like size^-k; compare relative to their scale.
                let scale = b.iter().chain(&a).fold(1.0f64, |m, x| m.max(x.abs()));
                for k in 0..3 {
                    assert_near!(
                        a[k] / scale,
                        b[k] / scale,
                        FINITE_DIFFERENCE,
                        "{name} patch {p} {what}[{k}]"
                    );
                }
            }
        }
    }
}

/// Sum of parameter-square areas per ptex face, after checking the squares lie in the unit
/// square and do not overlap.
fn coverage(s: &PatchSurface) -> Vec<f64> {
    (0..s.ptex_face_count() as u32)
        .map(|f| {
            let ps: Vec<_> = s
                .patches_of_ptex_face(f)
                .iter()
                .map(|&p| s.patches()[p as usize])
                .collect();
            for (i, a) in ps.iter().enumerate() {
                assert!(a.u0 >= 0.0 && a.v0 >= 0.0 && a.u0 + a.size <= 1.0 && a.v0 + a.size <= 1.0);
                for b in &ps[i + 1..] {
                    let overlap_u = a.u0 < b.u0 + b.size && b.u0 < a.u0 + a.size;
                    let overlap_v = a.v0 < b.v0 + b.size && b.v0 < a.v0 + a.size;
                    assert!(!(overlap_u && overlap_v), "ptex face {f}: patches overlap");
                }
            }
            ps.iter().map(|p| p.size * p.size).sum()
        })
        .collect()
}

#[test]
fn patch_table_covers_each_face_exactly_once() {
    for (name, mesh) in irregular_meshes() {
        let s = surface(&mesh);
        let expected_ptex: u32 = mesh
            .faces()
            .map(|f| if f.len() == 4 { 1 } else { f.len() as u32 })
            .sum();
        assert_eq!(s.ptex_face_count() as u32, expected_ptex, "{name}");
        for (f, area) in coverage(&s).into_iter().enumerate() {
            assert_near!(area, 1.0, ROUND_OFF, "{name}: ptex face {f} area");
        }
        for f in 0..mesh.face_count() {
            let total: f64 = s.ptex_faces(f).unwrap().map(|p| coverage_of(&s, p)).sum();
            assert_near!(
                total,
                s.ptex_faces(f).unwrap().len() as f64,
                ROUND_OFF,
                "{name}: face {f}"
            );
        }
    }
}

fn coverage_of(s: &PatchSurface, ptex: u32) -> f64 {
    s.patches_of_ptex_face(ptex)
        .iter()
        .map(|&p| s.patches()[p as usize].size.powi(2))
        .sum()
}

#[test]
fn boundary_none_leaves_boundary_faces_without_limit_surface() {
    let mesh = read(&crate::cgal::fixture("catmark_nonquads.obj")).unwrap();
    let options = SubdivOptions {
        boundary: BoundaryInterpolation::None,
        ..Default::default()
    };
    let s = limit_surface(&mesh, &options, &PatchOptions::default()).unwrap();
    // A face is on the boundary when one of its edges belongs to it alone.
    let mut uses = std::collections::HashMap::new();
    for f in mesh.faces() {
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    let mut boundary_faces = 0;
    for (fi, f) in mesh.faces().enumerate() {
        let on_boundary = (0..f.len()).any(|k| {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            uses[&(a.min(b), a.max(b))] == 1
        });
        let area: f64 = s.ptex_faces(fi).unwrap().map(|p| coverage_of(&s, p)).sum();
        if on_boundary {
            boundary_faces += 1;
            assert!(
                area < 1.0,
                "boundary face {fi} has a full limit surface under None"
            );
            let p = s.ptex_faces(fi).unwrap().start;
            assert!(s
                .evaluate(&[SurfacePoint {
                    ptex_face: p,
                    u: 0.0,
                    v: 0.0
                }])
                .is_err());
        } else {
            assert_near!(area, s.ptex_faces(fi).unwrap().len() as f64, ROUND_OFF);
        }
    }
    assert!(boundary_faces > 0);
}

#[test]
fn curvature_of_a_parabolic_cylinder() {
    // Control points (i, j, i²) on a grid: cubic B-splines reproduce quadratics, so away from
    // the boundary the limit surface is z = x² + 1/3 exactly, with K = 0,
    // H = 1 / (1 + 4x²)^{3/2} and k1 = 2 H for the normal (−2x, 0, 1) / √(1 + 4x²).
    let n = 8u32;
    let mesh = parabolic_grid(n);
    let s = surface(&mesh);
    for (i, j, u, v) in [(3u32, 3u32, 0.3, 0.6), (5, 2, 0.9, 0.1), (2, 5, 0.5, 0.5)] {
        let f = j * n + i;
        let d = s.evaluate(&[SurfacePoint { ptex_face: f, u, v }]).unwrap()[0];
        let x = i as f64 - 4.0 + u;
        assert_vec_near(
            d.position,
            [x, j as f64 + v, x * x + 1.0 / 3.0],
            ROUND_OFF,
            "position",
        );
        let c = curvature(&d).unwrap();
        let w = (1.0 + 4.0 * x * x).sqrt();
        assert_vec_near(c.normal, [-2.0 * x / w, 0.0, 1.0 / w], ROUND_OFF, "normal");
        assert_near!(c.gaussian, 0.0, ROUND_OFF);
        assert_near!(c.mean, 1.0 / w.powi(3), ROUND_OFF);
        assert_near!(c.k1, 2.0 / w.powi(3), ROUND_OFF);
        assert_near!(c.k2, 0.0, ROUND_OFF);
    }
}

/// Control points (i − 4, j, (i − 4)²) on an n × n grid of quads.
fn parabolic_grid(n: u32) -> PolygonMesh {
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let x = i as f64 - 4.0;
            positions.push([x, j as f64, x * x]);
        }
    }
    let id = |i: u32, j: u32| j * (n + 1) + i;
    let faces: Vec<[u32; 4]> = (0..n)
        .flat_map(|j| (0..n).map(move |i| [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]))
        .collect();
    PolygonMesh::from_polygons(positions, &faces)
}

#[test]
fn limit_samples_carry_mean_curvature_as_quality() {
    let mesh = parabolic_grid(8);
    let s = surface(&mesh);
    let k = 3;
    let sampled = sample_limit(&s, &SampleOptions { samples: k }).unwrap();
    assert!(sampled.degenerate.is_empty());
    let samples = sampled.mesh;
    assert_eq!(samples.face_count(), mesh.face_count() * (k * k) as usize);
    assert_eq!(
        samples.vertex_count(),
        mesh.face_count() * ((k + 1) * (k + 1)) as usize
    );
    let quality = samples.quality.as_ref().unwrap();
    let mut interior = 0;
    for (p, &h) in samples.positions.iter().zip(quality) {
        // Faces one ring away from the boundary lie on z = x² + 1/3 exactly.
        if (-3.0..=3.0).contains(&p[0]) && (1.0..=7.0).contains(&p[1]) {
            interior += 1;
            assert_near!(p[2], p[0] * p[0] + 1.0 / 3.0, ROUND_OFF);
            assert_near!(h, (1.0 + 4.0 * p[0] * p[0]).powf(-1.5), ROUND_OFF);
        }
    }
    assert!(interior > 0);
    assert!(sample_limit(&s, &SampleOptions { samples: 0 }).is_err());
}

#[test]
fn valence_two_vertices_are_degenerate_points_not_nans() {
    // A cube whose top face is split into two quads through a new vertex 8 joined to 4 and
    // 6 only: an interior vertex of valence 2, where the limit surface has vanishing
    // tangents: no normal, no curvature.
    let p = |x: f64, y: f64, z: f64| [x, y, z];
    let mesh = PolygonMesh::from_polygons(
        vec![
            p(0.0, 0.0, 0.0),
            p(1.0, 0.0, 0.0),
            p(1.0, 1.0, 0.0),
            p(0.0, 1.0, 0.0),
            p(0.0, 0.0, 1.0),
            p(1.0, 0.0, 1.0),
            p(1.0, 1.0, 1.0),
            p(0.0, 1.0, 1.0),
            p(0.5, 0.5, 1.2),
        ],
        &[
            [0u32, 3, 2, 1],
            [0, 1, 5, 4],
            [1, 2, 6, 5],
            [2, 3, 7, 6],
            [3, 0, 4, 7],
            [4, 5, 6, 8],
            [8, 6, 7, 4],
        ],
    );
    let s = surface(&mesh);
    // Vertex 8 is corner 3 of face 5: (u, v) = (0, 1) of its ptex face.
    let at8 = s
        .evaluate(&[SurfacePoint {
            ptex_face: 5,
            u: 0.0,
            v: 1.0,
        }])
        .unwrap()[0];
    assert!(matches!(curvature(&at8), Err(surfkit::Error::Topology(_))));
    let inside = s
        .evaluate(&[SurfacePoint {
            ptex_face: 5,
            u: 0.5,
            v: 0.5,
        }])
        .unwrap()[0];
    assert!(curvature(&inside).is_ok());
    let sampled = sample_limit(&s, &SampleOptions { samples: 2 }).unwrap();
    assert_eq!(
        sampled.degenerate.len(),
        2,
        "vertex 8 once in each of its 2 faces"
    );
    for &g in &sampled.degenerate {
        assert_vec_near(
            sampled.mesh.positions[g as usize],
            at8.position,
            ROUND_OFF,
            "degenerate sample",
        );
    }
    assert!(sampled.mesh.quality.unwrap().iter().all(|q| q.is_finite()));
}

#[test]
fn every_fixture_gets_a_limit_surface_that_evaluates() {
    // Non-manifold edges and vertices, unreferenced vertices, duplicated faces: OpenSubdiv
    // builds patches where it can; whatever it builds must evaluate to finite values at the
    // centre of every patch, and no face may be covered twice.
    let reference: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(crate::cgal::fixture("REFERENCE.json")).unwrap(),
    )
    .unwrap();
    for entry in reference["meshes"].as_array().unwrap() {
        let name = entry["file"].as_str().unwrap();
        let mesh = read(&crate::cgal::fixture(name)).unwrap();
        let s = limit_surface(&mesh, &SubdivOptions::default(), &PatchOptions::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let points: Vec<SurfacePoint> = s
            .patches()
            .iter()
            .map(|p| SurfacePoint {
                ptex_face: p.ptex_face,
                u: p.u0 + p.size / 2.0,
                v: p.v0 + p.size / 2.0,
            })
            .collect();
        let values = s.evaluate(&points).unwrap();
        assert!(
            values
                .iter()
                .all(|d| d.position.iter().chain(&d.dvvv).all(|c| c.is_finite())),
            "{name}"
        );
        let areas = coverage(&s);
        assert!(
            areas.iter().all(|&a| a <= 1.0 + ROUND_OFF),
            "{name}: a face covered twice"
        );
        let manifold = entry["non_manifold_edges"].as_i64() == Some(0)
            && entry["non_manifold_vertices"].as_i64() == Some(0);
        if manifold {
            assert!(
                areas.iter().all(|&a| (a - 1.0).abs() <= ROUND_OFF),
                "{name}: a face not covered"
            );
        }
        eprintln!(
            "{name}: {} patches over {} ptex faces",
            s.patches().len(),
            s.ptex_face_count()
        );
    }
}

#[test]
fn patch_weights_are_the_derivative_with_respect_to_control_vertices() {
    // The limit position is linear in the control vertices: moving vertex j by δ moves the
    // point at (s, t) of patch p by δ · Σ_k B_k(s, t) w_kj. Checked by moving each vertex
    // that patch p depends on and re-evaluating through OpenSubdiv.
    let mesh = read(&crate::cgal::fixture("catmark_nonquads.obj")).unwrap();
    let mut s = surface(&mesh);
    for p in [0usize, 5, 17, 40] {
        let patch = s.patches()[p];
        let (a, b) = (0.3, 0.7);
        let point = SurfacePoint {
            ptex_face: patch.ptex_face,
            u: patch.u0 + a * patch.size,
            v: patch.v0 + b * patch.size,
        };
        let weights = s.patch_weights(p).unwrap();
        let (bu, bv) = (
            surfkit::subdiv::cubic_basis(a)[0],
            surfkit::subdiv::cubic_basis(b)[0],
        );
        let mut derivative = std::collections::HashMap::new();
        for (k, row) in weights.iter().enumerate() {
            for &(v, w) in row {
                *derivative.entry(v).or_insert(0.0) += bu[k % 4] * bv[k / 4] * w;
            }
        }
        let base = s.evaluate(&[point]).unwrap()[0].position;
        for (&v, &dp) in &derivative {
            let mut moved = mesh.positions.clone();
            moved[v as usize][2] += 1.0;
            s.set_control_points(&moved).unwrap();
            let shifted = s.evaluate(&[point]).unwrap()[0].position;
            assert_near!(shifted[2] - base[2], dp, ROUND_OFF, "patch {p} vertex {v}");
            assert_near!(shifted[0] - base[0], 0.0, ROUND_OFF);
        }
        // Vertices outside the stencils do not move the point.
        for v in (0..mesh.vertex_count() as u32).filter(|v| !derivative.contains_key(v)) {
            let mut moved = mesh.positions.clone();
            moved[v as usize][2] += 1.0;
            s.set_control_points(&moved).unwrap();
            let shifted = s.evaluate(&[point]).unwrap()[0].position;
            assert_near!(
                shifted[2] - base[2],
                0.0,
                ROUND_OFF,
                "patch {p}: vertex {v} is outside its support"
            );
        }
        s.set_control_points(&mesh.positions).unwrap();
    }
}
