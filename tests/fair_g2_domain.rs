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
