//! The domain nets of Kiciak's special elements (issue 20, first part): for every valence
//! 3–16 the net is an eigenvector of one Catmull–Clark step — checked with OpenSubdiv's
//! own refinement, not surfkit's — for the closed-form subdominant eigenvalue, k-fold
//! rotation and mirror symmetric, and Ω_k (bounded by the ring's cubic arcs) has area k.

use surfkit::fair::{boundary_arcs, cubic_arc, subdominant_eigenvalue, DomainNet};
use surfkit::mesh::PolygonMesh;
use surfkit::subdiv::{refine_uniform, SubdivOptions};

fn rotate(p: [f64; 2], angle: f64) -> [f64; 2] {
    let (s, c) = angle.sin_cos();
    [c * p[0] - s * p[1], s * p[0] + c * p[1]]
}

fn distance(p: [f64; 2], q: [f64; 2]) -> f64 {
    (p[0] - q[0]).hypot(p[1] - q[1])
}

#[test]
fn one_opensubdiv_step_maps_the_net_onto_itself_scaled_by_lambda() {
    for k in 3..=16 {
        let net = DomainNet::new(k);
        let lambda = subdominant_eigenvalue(k);
        assert!(
            (net.lambda - lambda).abs() < 1e-12,
            "k {k}: λ {} vs {lambda}",
            net.lambda
        );
        // The radius-3 net as a quad mesh, refined once by OpenSubdiv: the refined
        // radius-3 net round the centre is λ times the net, so every λ·p is a vertex of
        // the refined mesh (its outer vertices feel OpenSubdiv's boundary rule, not these).
        let positions: Vec<[f64; 3]> = net.points.iter().map(|p| [p[0], p[1], 0.0]).collect();
        let faces: Vec<Vec<u32>> = net.quads().iter().map(|q| q.to_vec()).collect();
        let mesh = PolygonMesh::from_polygons(positions, &faces);
        let refined = refine_uniform(&mesh, 1, &SubdivOptions::default()).unwrap();
        for (i, p) in net.points.iter().enumerate() {
            let target = [lambda * p[0], lambda * p[1]];
            let nearest = refined
                .positions
                .iter()
                .map(|q| distance([q[0], q[1]], target))
                .fold(f64::INFINITY, f64::min);
            assert!(nearest < 1e-10, "k {k}: net point {i} off by {nearest}");
        }
    }
}

#[test]
fn nets_are_rotation_and_mirror_symmetric_with_area_k() {
    for k in 3..=16 {
        let net = DomainNet::new(k);
        let turn = 2.0 * std::f64::consts::PI / k as f64;
        let scale = net
            .points
            .iter()
            .map(|p| p[0].hypot(p[1]))
            .fold(0.0, f64::max);
        for s in 0..k {
            for a in 1..=3 {
                for b in 0..=3 {
                    let p = net.point(s, a, b);
                    let next = net.point(s + 1, a, b);
                    assert!(
                        distance(rotate(p, turn), next) < 1e-12 * scale,
                        "k {k} rotation"
                    );
                    // Mirror in spoke 0: sector s's (a, b) is sector k−1−s's (b, a).
                    let m = net.point(k - 1 - s, b, a);
                    assert!(distance([p[0], -p[1]], m) < 1e-12 * scale, "k {k} mirror");
                }
            }
        }
        // Ω_k's area is k: the enclosed area of its border (the ring's cubic arcs),
        // measured here by the shoelace formula on a fine sampling of the arcs.
        let samples = 2000;
        let border: Vec<[f64; 2]> = boundary_arcs(k, &net.points)
            .into_iter()
            .flat_map(|arc| (0..samples).map(move |i| cubic_arc(arc, i as f64 / samples as f64).0))
            .collect();
        // The arcs join: each ends where the next starts.
        let arcs = boundary_arcs(k, &net.points);
        for (i, &arc) in arcs.iter().enumerate() {
            let next = arcs[(i + 1) % arcs.len()];
            let gap = distance(cubic_arc(arc, 1.0).0, cubic_arc(next, 0.0).0);
            assert!(
                gap < 1e-12 * scale,
                "k {k}: arcs {i} and {} are {gap} apart",
                i + 1
            );
        }
        let area: f64 = (0..border.len())
            .map(|i| {
                let (p, q) = (border[i], border[(i + 1) % border.len()]);
                0.5 * (p[0] * q[1] - q[0] * p[1])
            })
            .sum();
        assert!(
            (area - k as f64).abs() < 1e-5 * k as f64,
            "k {k}: area {area}"
        );
    }
}

#[test]
fn division_curves_meet_their_hermite_data() {
    use surfkit::fair::{bezier_derivatives, division_curve};
    use surfkit::subdiv::eval_patch;
    for k in 3..=16 {
        let net = DomainNet::new(k);
        let scale = net
            .points
            .iter()
            .map(|p| p[0].hypot(p[1]))
            .fold(0.0, f64::max);
        let close = |a: [f64; 2], b: [f64; 2]| distance(a, b) <= 1e-12 * scale;
        for spoke in 0..k {
            let curve = division_curve(&net, spoke);
            // At the far end: the ring's bicubic patch on face [1, 2] × [0, 1] of the
            // sector, evaluated whole from its 16 control points, at its corner on the spoke.
            let mut control = [[0.0; 3]; 16];
            for (i, row) in control.chunks_mut(4).enumerate() {
                for (j, p) in row.iter_mut().enumerate() {
                    let q = net.point(spoke, j as i32, i as i32 - 1);
                    *p = [q[0], q[1], 0.0];
                }
            }
            let ring = eval_patch(&control, 0.0, 0.0);
            let flat = |v: [f64; 3]| [v[0], v[1]];
            let end = bezier_derivatives(&curve, 1.0, 2);
            assert!(close(end[0], flat(ring.position)), "k {k}: end point");
            assert!(close(end[1], flat(ring.du)), "k {k}: end tangent");
            assert!(close(end[2], flat(ring.duu)), "k {k}: end curvature vector");
            // At the centre: the chord to the end as tangent, derivatives 2–4 zero.
            let start = bezier_derivatives(&curve, 0.0, 5);
            let c = net.point(0, 0, 0);
            assert!(close(start[0], c), "k {k}: centre");
            let chord = [end[0][0] - c[0], end[0][1] - c[1]];
            assert!(close(start[1], chord), "k {k}: start tangent");
            for (order, d) in start.iter().enumerate().take(5).skip(2) {
                assert!(close(*d, [0.0, 0.0]), "k {k}: derivative {order}");
            }
            // The k curves are one curve turned by 2π/k.
            let turned = division_curve(&net, (spoke + 1) % k);
            let turn = 2.0 * std::f64::consts::PI / k as f64;
            for (p, q) in curve.iter().zip(&turned) {
                assert!(close(rotate(*p, turn), *q), "k {k}: rotation");
            }
        }
    }
    // Valence 4: the spoke is a straight lattice line; the curve is its segment, at
    // uniform speed (control points equally spaced).
    let net = DomainNet::new(4);
    let curve = division_curve(&net, 0);
    let (c, m) = (curve[0], curve[7]);
    for (i, p) in curve.iter().enumerate() {
        let expected = [0, 1].map(|x| c[x] + i as f64 / 7.0 * (m[x] - c[x]));
        assert!(
            distance(*p, expected) < 1e-13,
            "control point {i}: {p:?} vs {expected:?}"
        );
    }
}
