//! Uniform Catmull–Clark refinement against CGAL's (`Subdivision_method_3`), the Euler
//! characteristic under refinement, the boundary rules and refined UVs.

use surfkit::assert_near;
use surfkit::mesh::io::read;
use surfkit::mesh::{CornerUvs, PolygonMesh};
use surfkit::subdiv::{
    refine_uniform, BoundaryInterpolation, FaceVaryingInterpolation, SubdivOptions,
};
use surfkit::tolerance::ROUND_OFF;

/// Refines with OpenSubdiv and CGAL and checks: same vertex count, every CGAL vertex has an
/// OpenSubdiv vertex within ROUND_OFF · bbox diagonal, and the same faces. Returns the
/// largest deviation relative to the diagonal.
fn assert_matches_cgal(
    name: &str,
    mesh: &PolygonMesh,
    levels: u32,
    options: &SubdivOptions,
) -> f64 {
    let ours = refine_uniform(mesh, levels, options).unwrap();
    let theirs = crate::cgal::catmull_clark(mesh, levels);
    let diag = crate::cgal::diagonal(mesh);
    assert_eq!(
        ours.vertex_count(),
        theirs.vertex_count(),
        "{name} level {levels}: vertex count"
    );
    assert_eq!(
        ours.face_count(),
        theirs.face_count(),
        "{name} level {levels}: face count"
    );
    let m = crate::cgal::match_vertices(&ours, &theirs, ROUND_OFF * diag);
    assert!(
        m.unmatched_theirs.is_empty() && m.unmatched_ours.is_empty(),
        "{name} level {levels}: {} CGAL vertices have no OpenSubdiv vertex within {:e}",
        m.unmatched_theirs.len(),
        ROUND_OFF * diag
    );
    let our_faces = crate::cgal::face_cycles(
        ours.faces()
            .map(|f| f.iter().map(|&v| v as usize).collect()),
    );
    assert_eq!(
        Some(our_faces),
        crate::cgal::faces_in_our_ids(&theirs, &m),
        "{name} level {levels}: faces differ"
    );
    let rel = m.max_distance / diag;
    eprintln!("{name} level {levels}: max deviation from CGAL {rel:e} of the bbox diagonal");
    rel
}

#[test]
fn closed_quads_match_cgal_at_levels_1_to_3() {
    for name in ["catmark_torus.obj", "quadknot.obj", "comments.off"] {
        let mesh = read(&crate::cgal::fixture(name)).unwrap();
        for levels in 1..=3 {
            assert_matches_cgal(name, &mesh, levels, &SubdivOptions::default());
        }
    }
}

#[test]
fn closed_mixed_polygons_match_cgal_at_levels_1_to_3() {
    // rabbit: triangles, quads and n-gons up to 16 corners; spot and fixed_top: triangles.
    for (name, max_level) in [("rabbit.obj", 3), ("spot.obj", 2), ("fixed_top.ply", 2)] {
        let mesh = read(&crate::cgal::fixture(name)).unwrap();
        for levels in 1..=max_level {
            assert_matches_cgal(name, &mesh, levels, &SubdivOptions::default());
        }
    }
}

const OPEN: [&str; 2] = ["catmark_nonquads.obj", "target.obj"];

fn with_boundary(boundary: BoundaryInterpolation) -> SubdivOptions {
    SubdivOptions {
        boundary,
        ..Default::default()
    }
}

/// Vertices on exactly one face and on the boundary: "corners" in OpenSubdiv's sense.
fn corner_vertices(mesh: &PolygonMesh) -> Vec<(u32, u32, u32)> {
    // (corner, previous, next) along its only face.
    let mut count = vec![0usize; mesh.vertex_count()];
    for f in mesh.faces() {
        for &v in f {
            count[v as usize] += 1;
        }
    }
    let mut out = Vec::new();
    for f in mesh.faces() {
        for k in 0..f.len() {
            if count[f[k] as usize] == 1 {
                out.push((f[k], f[(k + f.len() - 1) % f.len()], f[(k + 1) % f.len()]));
            }
        }
    }
    out
}

#[test]
fn open_meshes_with_edges_only_boundaries_match_cgal() {
    // CGAL's border rule is the cubic B-spline curve rule (edge midpoint; vertex
    // (prev + 6 v + next) / 8) at every border vertex: OpenSubdiv's EdgesOnly.
    for name in OPEN {
        let mesh = read(&crate::cgal::fixture(name)).unwrap();
        for levels in 1..=3 {
            assert_matches_cgal(
                name,
                &mesh,
                levels,
                &with_boundary(BoundaryInterpolation::EdgesOnly),
            );
        }
    }
}

#[test]
fn edges_and_corners_differs_from_cgal_exactly_at_corners() {
    // surfkit's default keeps corners (boundary vertices of a single face) in place; CGAL
    // smooths them with (prev + 6 v + next) / 8. At level 1 that is the only difference.
    // (target.obj has no corner; a 3 x 2 grid has 4.)
    for (name, mesh) in [
        (
            "catmark_nonquads.obj",
            read(&crate::cgal::fixture("catmark_nonquads.obj")).unwrap(),
        ),
        ("grid 3 x 2", grid(3, 2)),
    ] {
        let corners = corner_vertices(&mesh);
        assert!(
            !corners.is_empty(),
            "{name} should have corners for this test"
        );
        let ours = refine_uniform(&mesh, 1, &SubdivOptions::default()).unwrap();
        let theirs = crate::cgal::catmull_clark(&mesh, 1);
        let diag = crate::cgal::diagonal(&mesh);
        let tol = ROUND_OFF * diag;
        let m = crate::cgal::match_vertices(&ours, &theirs, tol);
        assert_eq!(m.unmatched_ours.len(), corners.len(), "{name}");
        assert_eq!(m.unmatched_theirs.len(), corners.len(), "{name}");
        let p = |v: u32| mesh.positions[v as usize];
        for &(c, prev, next) in &corners {
            let kept = p(c);
            let smoothed: [f64; 3] =
                std::array::from_fn(|k| (p(prev)[k] + 6.0 * p(c)[k] + p(next)[k]) / 8.0);
            let near = |a: [f64; 3], b: [f64; 3]| (0..3).all(|k| (a[k] - b[k]).abs() <= tol);
            assert!(
                m.unmatched_ours
                    .iter()
                    .any(|&i| near(ours.positions[i], kept)),
                "{name}: corner {c} not kept"
            );
            assert!(
                m.unmatched_theirs
                    .iter()
                    .any(|&j| near(theirs.positions[j], smoothed)),
                "{name}: CGAL did not smooth corner {c} by (1, 6, 1) / 8"
            );
        }
    }
}

#[test]
fn boundary_none_refines_like_edges_only() {
    // OpenSubdiv sharpens boundary edges for refinement whatever the rule; `None` only
    // withholds the limit surface of boundary faces (see the patch tests). So the refined
    // positions are bit-for-bit those of EdgesOnly, and thus CGAL's.
    for name in OPEN {
        let mesh = read(&crate::cgal::fixture(name)).unwrap();
        for levels in 1..=2 {
            let none =
                refine_uniform(&mesh, levels, &with_boundary(BoundaryInterpolation::None)).unwrap();
            let edges = refine_uniform(
                &mesh,
                levels,
                &with_boundary(BoundaryInterpolation::EdgesOnly),
            )
            .unwrap();
            assert_eq!(none.positions, edges.positions, "{name} level {levels}");
            assert_eq!(
                none.face_indices, edges.face_indices,
                "{name} level {levels}"
            );
        }
    }
}

/// An open nx x ny grid of unit quads on a curved height field (quadratic in x and y, so
/// that neither corner smoothing nor a crease rule can agree with the smooth rule by accident).
fn grid(nx: u32, ny: u32) -> PolygonMesh {
    let mut positions = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            let (x, y) = (i as f64, j as f64);
            positions.push([x, y, x * y / 4.0 + x * x / 8.0 + y * y / 5.0]);
        }
    }
    let id = |i: u32, j: u32| j * (nx + 1) + i;
    let faces: Vec<[u32; 4]> = (0..ny)
        .flat_map(|j| {
            (0..nx).map(move |i| [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)])
        })
        .collect();
    PolygonMesh::from_polygons(positions, &faces)
}

#[test]
fn linear_uvs_refine_bilinearly() {
    // FaceVaryingInterpolation::All (the default): the UVs of each child quad of a face are
    // its corner's UV, the two adjacent edge midpoints and the face's centroid. OpenSubdiv
    // numbers child faces consecutively per parent face, one per parent corner.
    let mesh = read(&crate::cgal::fixture("catmark_torus.obj")).unwrap();
    let uvs = mesh.uvs.as_ref().expect("catmark_torus.obj has vt");
    let refined = refine_uniform(&mesh, 1, &SubdivOptions::default()).unwrap();
    let ruv = refined.uvs.as_ref().expect("refined UVs");
    assert_eq!(ruv.corner_indices.len(), refined.face_indices.len());
    let mut child = 0;
    for (f, face) in mesh.faces().enumerate() {
        let start = mesh.face_offsets[f] as usize;
        let n = face.len();
        let uv = |k: usize| uvs.coords[uvs.corner_indices[start + k % n] as usize];
        let mid = |a: [f64; 2], b: [f64; 2]| [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
        let centroid = (0..n).fold([0.0, 0.0], |c, k| {
            [c[0] + uv(k)[0] / n as f64, c[1] + uv(k)[1] / n as f64]
        });
        let expected: Vec<[[f64; 2]; 4]> = (0..n)
            .map(|k| {
                [
                    uv(k),
                    mid(uv(k), uv(k + 1)),
                    centroid,
                    mid(uv(k + n - 1), uv(k)),
                ]
            })
            .collect();
        for _ in 0..n {
            let got: Vec<[f64; 2]> = (0..4)
                .map(|c| ruv.coords[ruv.corner_indices[4 * child + c] as usize])
                .collect();
            let same = |e: &[[f64; 2]; 4]| {
                (0..4).any(|r| {
                    (0..4)
                        .all(|c| (0..2).all(|d| (got[(c + r) % 4][d] - e[c][d]).abs() <= ROUND_OFF))
                })
            };
            assert!(
                expected.iter().any(same),
                "face {f}: child {child} UVs {got:?} not bilinear"
            );
            child += 1;
        }
    }
    assert_eq!(child, refined.face_count());
}

#[test]
fn invalid_input_is_an_error_not_a_panic() {
    let mesh = grid(2, 2);
    assert!(matches!(
        refine_uniform(&mesh, 11, &SubdivOptions::default()),
        Err(surfkit::Error::InvalidInput(_))
    ));
    let bad_crease = SubdivOptions {
        creases: vec![surfkit::subdiv::Crease {
            vertices: [0, 8],
            sharpness: 1.0,
        }],
        ..Default::default()
    };
    let e = refine_uniform(&mesh, 1, &bad_crease)
        .unwrap_err()
        .to_string();
    assert!(e.contains("crease 0"), "{e}");
    let nan = SubdivOptions {
        corners: vec![surfkit::subdiv::Corner {
            vertex: 0,
            sharpness: f32::NAN,
        }],
        ..Default::default()
    };
    assert!(matches!(
        refine_uniform(&mesh, 1, &nan),
        Err(surfkit::Error::InvalidInput(_))
    ));
    let mut two = mesh.clone();
    two.push_face(&[0, 1]);
    assert!(matches!(
        refine_uniform(&two, 1, &SubdivOptions::default()),
        Err(surfkit::Error::InvalidInput(_))
    ));
    assert!(matches!(
        refine_uniform(&PolygonMesh::default(), 1, &SubdivOptions::default()),
        Err(surfkit::Error::InvalidInput(_))
    ));
}

#[test]
fn infinitely_sharp_crease_refines_as_a_curve() {
    // An infinitely sharp crease (interior edge chain) follows the cubic B-spline curve
    // rules: a crease vertex with crease neighbours a, b goes to (a + 6 v + b) / 8.
    let mesh = grid(4, 2);
    let id = |i: u32, j: u32| j * 5 + i;
    let creases = (0..4)
        .map(|i| surfkit::subdiv::Crease {
            vertices: [id(i, 1), id(i + 1, 1)],
            sharpness: 10.0,
        })
        .collect();
    let options = SubdivOptions {
        creases,
        ..Default::default()
    };
    let refined = refine_uniform(&mesh, 1, &options).unwrap();
    let p = |v: u32| mesh.positions[v as usize];
    for i in 1..4 {
        let expect: [f64; 3] = std::array::from_fn(|k| {
            (p(id(i - 1, 1))[k] + 6.0 * p(id(i, 1))[k] + p(id(i + 1, 1))[k]) / 8.0
        });
        let found = refined
            .positions
            .iter()
            .any(|q| (0..3).all(|k| (q[k] - expect[k]).abs() <= ROUND_OFF));
        assert!(
            found,
            "crease vertex ({i}, 1) not at the curve rule's {expect:?}"
        );
        let mid: [f64; 3] = std::array::from_fn(|k| (p(id(i, 1))[k] + p(id(i + 1, 1))[k]) / 2.0);
        assert!(
            refined
                .positions
                .iter()
                .any(|q| (0..3).all(|k| (q[k] - mid[k]).abs() <= ROUND_OFF)),
            "crease edge point is not the midpoint"
        );
    }
}

#[test]
fn smooth_uvs_without_seams_refine_like_positions() {
    // With UVs equal to (x, y) of each vertex and no seam, a smooth face-varying rule must
    // produce the refined positions' (x, y): the same Catmull–Clark masks on the same data.
    // Closed surface, so no boundary rule is involved.
    let mesh = read(&crate::cgal::fixture("quadknot.obj")).unwrap();
    let mut with_uv = mesh.clone();
    with_uv.uvs = Some(CornerUvs {
        coords: mesh.positions.iter().map(|p| [p[0], p[1]]).collect(),
        corner_indices: mesh.face_indices.clone(),
        untextured: None,
    });
    let scale = crate::cgal::diagonal(&mesh);
    for rule in [
        FaceVaryingInterpolation::None,
        FaceVaryingInterpolation::CornersOnly,
        FaceVaryingInterpolation::Boundaries,
    ] {
        let options = SubdivOptions {
            face_varying: rule,
            ..Default::default()
        };
        let r = refine_uniform(&with_uv, 2, &options).unwrap();
        let uv = r.uvs.as_ref().unwrap();
        for (c, &v) in r.face_indices.iter().enumerate() {
            let t = uv.coords[uv.corner_indices[c] as usize];
            let p = r.positions[v as usize];
            assert_near!(t[0] / scale, p[0] / scale, ROUND_OFF, "{rule:?}");
            assert_near!(t[1] / scale, p[1] / scale, ROUND_OFF, "{rule:?}");
        }
    }
}

#[test]
fn semi_sharp_crease_blends_smooth_and_sharp_edge_points() {
    // Sdc: an edge of sharpness s in (0, 1) gets s · midpoint + (1 − s) · smooth edge point
    // (the average of its ends and the two face centroids); s ≥ 1 is sharp at this level.
    let mesh = grid(4, 2);
    let id = |i: u32, j: u32| j * 5 + i;
    let (a, b) = (id(1, 1), id(2, 1));
    let p = |v: u32| mesh.positions[v as usize];
    let centroid = |f: [u32; 4]| -> [f64; 3] {
        std::array::from_fn(|k| f.iter().map(|&v| p(v)[k]).sum::<f64>() / 4.0)
    };
    let below = centroid([id(1, 0), id(2, 0), id(2, 1), id(1, 1)]);
    let above = centroid([id(1, 1), id(2, 1), id(2, 2), id(1, 2)]);
    for sharpness in [0.0f32, 0.25, 0.5, 1.0, 3.0] {
        let options = SubdivOptions {
            creases: vec![surfkit::subdiv::Crease {
                vertices: [a, b],
                sharpness,
            }],
            ..Default::default()
        };
        let refined = refine_uniform(&mesh, 1, &options).unwrap();
        let s = f64::from(sharpness).min(1.0);
        let expect: [f64; 3] = std::array::from_fn(|k| {
            let mid = (p(a)[k] + p(b)[k]) / 2.0;
            let smooth = (p(a)[k] + p(b)[k] + below[k] + above[k]) / 4.0;
            s * mid + (1.0 - s) * smooth
        });
        assert!(
            refined
                .positions
                .iter()
                .any(|q| (0..3).all(|k| (q[k] - expect[k]).abs() <= ROUND_OFF)),
            "sharpness {sharpness}: no edge point at {expect:?}"
        );
    }
}

#[test]
fn opensubdiv_links_and_is_debians_3_5() {
    // build.rs links Debian's libosd-dev 3.5; the shim's self-test refines a cube once and
    // checks OpenSubdiv's counts (26 vertices, 24 quads).
    let (major, minor, _) = surfkit::subdiv::opensubdiv_version();
    assert_eq!((major, minor), (3, 5));
    surfkit::subdiv::self_test().unwrap();
}

#[test]
fn degenerate_faces_refine_without_failing_or_are_refused_by_name() {
    // A duplicated face and opposite orientations: OpenSubdiv accepts them and refinement
    // still yields one quad per corner. A repeated corner is refused before OpenSubdiv sees
    // it (its end-cap construction overflows the stack on one), naming the face and vertex.
    let positions = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    let cases: [&[&[u32]]; 2] = [&[&[0, 1, 2, 3], &[0, 1, 2, 3]], &[&[0, 1, 2], &[0, 2, 1]]];
    for faces in cases {
        let mesh = PolygonMesh::from_polygons(positions.clone(), faces);
        let refined = refine_uniform(&mesh, 2, &SubdivOptions::default()).unwrap();
        assert_eq!(
            refined.face_count(),
            4 * mesh.face_indices.len(),
            "{faces:?}"
        );
        assert!(refined.positions.iter().flatten().all(|c| c.is_finite()));
        refined.validate().unwrap();
    }
    let repeated = PolygonMesh::from_polygons(positions, &[&[0u32, 1, 1, 2][..]]);
    let err = refine_uniform(&repeated, 2, &SubdivOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("face 0") && err.contains("vertex index 1"),
        "{err}"
    );
}

#[test]
fn faces_without_uvs_leave_the_others_refined_as_if_all_had_them() {
    // The torus's UVs kept on every other face, the rest given none: the textured faces'
    // children carry exactly the UVs of the fully textured refinement (linear face-varying
    // interpolation depends on the face's own corners only), the others the stand-in.
    let full = read(&crate::cgal::fixture("catmark_torus.obj")).unwrap();
    let uvs = full.uvs.clone().expect("catmark_torus.obj has vt");
    let mut partial = full.clone();
    let stand_in = uvs.coords.len() as u32;
    let mut corner_indices = uvs.corner_indices.clone();
    for (f, w) in full.face_offsets.windows(2).enumerate() {
        if f % 2 == 1 {
            corner_indices[w[0] as usize..w[1] as usize].fill(stand_in);
        }
    }
    let mut coords = uvs.coords.clone();
    coords.push(CornerUvs::UNTEXTURED_VALUE);
    partial.uvs = Some(CornerUvs {
        coords,
        corner_indices,
        untextured: Some(stand_in),
    });
    for levels in [1, 2] {
        let a = refine_uniform(&full, levels, &SubdivOptions::default()).unwrap();
        let b = refine_uniform(&partial, levels, &SubdivOptions::default()).unwrap();
        assert_eq!(a.positions, b.positions);
        let (ua, ub) = (a.uvs.as_ref().unwrap(), b.uvs.as_ref().unwrap());
        let mut textured = 0;
        let mut first_child = 0;
        for (f, w) in full.face_offsets.windows(2).enumerate() {
            let children = (w[1] - w[0]) as usize * 4usize.pow(levels - 1);
            for child in first_child..first_child + children {
                for k in 4 * child..4 * child + 4 {
                    if f % 2 == 0 {
                        let (pa, pb) = (ua.corner_indices[k], ub.corner_indices[k]);
                        assert_eq!(ua.coords[pa as usize], ub.coords[pb as usize], "face {f}");
                        assert!(ub.is_textured(k));
                    } else {
                        assert_eq!(Some(ub.corner_indices[k]), ub.untextured, "face {f}");
                    }
                }
                textured += usize::from(f % 2 == 0);
            }
            first_child += children;
        }
        assert_eq!(first_child, b.face_count());
        assert_eq!(ub.textured_faces(&b.face_offsets), textured);
        // No coordinate is left that no corner uses (the stand-ins' refined values dropped).
        let mut used = vec![false; ub.coords.len()];
        ub.corner_indices
            .iter()
            .for_each(|&t| used[t as usize] = true);
        assert!(used.iter().all(|&u| u), "level {levels}");
    }
}
