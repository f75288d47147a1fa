//! Where Q (eq. 5) is integrated around extraordinary vertices ([`QDomain`]): S does not
//! depend on the parameterization, so it is the same in both domains; on a mesh without
//! extraordinary vertices every patch is a whole face and the two are the same functional;
//! and in the face's parameters Q grows without bound with the isolation level (∇Δp of
//! Catmull–Clark is not square-integrable at an extraordinary vertex), while in each
//! patch's own parameters it converges.

use surfkit::fair::{
    fixed_vertices, sector_disc, tubes, Functional, MeshTopology, PatchRepresentation, QDomain,
    RepresentationOptions, Terms,
};
use surfkit::mesh::PolygonMesh;

fn terms(mesh: &PolygonMesh, isolation: u32, q_domain: QDomain) -> Terms {
    let topo = MeshTopology::new(mesh).unwrap();
    let fixed = fixed_vertices(&topo, 3, &[]).unwrap();
    let special = topo.special_flags();
    let options = RepresentationOptions {
        isolation,
        q_domain,
        ..RepresentationOptions::default()
    };
    let rep = PatchRepresentation::new(mesh, &topo.boundary, &special, &options).unwrap();
    Functional::new(&rep, &fixed, 1.0).value(&mesh.positions)
}

#[test]
fn fair_q_domain_s_is_parameterization_independent() {
    for mesh in [tubes(3, 4, 3).unwrap(), sector_disc(5, 6).unwrap()] {
        for isolation in [2, 4] {
            let patch = terms(&mesh, isolation, QDomain::Patch);
            let face = terms(&mesh, isolation, QDomain::Face);
            assert!(
                (patch.s - face.s).abs() <= 1e-12 * face.s,
                "S {} vs {}",
                patch.s,
                face.s
            );
            assert!(patch.q < face.q, "Q {} vs {}", patch.q, face.q);
        }
    }
}

#[test]
fn fair_q_domain_same_functional_without_extraordinary_vertices() {
    let grid = sector_disc(4, 6).unwrap();
    let patch = terms(&grid, 4, QDomain::Patch);
    let face = terms(&grid, 4, QDomain::Face);
    assert_eq!(patch.f.to_bits(), face.f.to_bits());
    assert_eq!(patch.q.to_bits(), face.q.to_bits());
}

#[test]
fn fair_q_domain_q_converges_with_isolation_only_in_patch_parameters() {
    let mesh = tubes(3, 4, 3).unwrap();
    let q = |domain| -> Vec<f64> { (2..=5).map(|l| terms(&mesh, l, domain).q).collect() };
    let (patch, face) = (q(QDomain::Patch), q(QDomain::Face));
    eprintln!("Q by isolation 2..5: patch {patch:?}, face {face:?}");
    for l in 1..3 {
        // Face parameters: each level adds more than the previous one (divergent).
        assert!(face[l + 1] - face[l] > face[l] - face[l - 1], "{face:?}");
        // Own parameters: the increments shrink geometrically.
        let (d0, d1) = (patch[l] - patch[l - 1], patch[l + 1] - patch[l]);
        assert!(d1.abs() < 0.5 * d0.abs(), "{patch:?}");
    }
}
