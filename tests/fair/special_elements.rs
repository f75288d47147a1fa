//! Why the elements at special vertices get a small Cᵢ by default
//! (`fair::DEFAULT_C_SPECIAL`): on a planar disc around a vertex of valence 10 whose sectors
//! are affine grids, Q of the faces at the special vertex is positive, and its descent
//! direction pulls their other vertices straight toward the special vertex — the drift
//! that made the 23997-vertex five-tube junction stall with Cᵢ = 1 there.

use surfkit::fair::{
    fixed_vertices, sector_disc, Functional, MeshTopology, PatchRepresentation,
    RepresentationOptions,
};
use surfkit::mesh::PolygonMesh;

/// Free-vertex index, F's gradient and Q on `mesh` with Cᵢ = `c_special` at the faces of
/// special vertices (1 elsewhere).
fn gradient(mesh: &PolygonMesh, c_special: f64) -> (Vec<u32>, Vec<f64>, f64) {
    let topo = MeshTopology::new(mesh).unwrap();
    let fixed = fixed_vertices(&topo, 3, &[]).unwrap();
    let special = topo.special_flags();
    let options = RepresentationOptions {
        c_special,
        ..RepresentationOptions::default()
    };
    let rep = PatchRepresentation::new(mesh, &topo.boundary, &special, &options).unwrap();
    let functional = Functional::new(&rep, &fixed, 1.0);
    let (terms, g) = functional.gradient(&mesh.positions);
    (functional.free_index().to_vec(), g, terms.q)
}

#[test]
fn fair_special_elements_q_pulls_their_vertices_toward_the_special_vertex() {
    let mut disc = sector_disc(10, 6).unwrap();
    for p in &mut disc.positions {
        p[2] = 0.0;
    }
    // Q and the gradient are linear in the Cᵢ: the special faces' share is the difference
    // (S and its gradient vanish on a plane).
    let (index, with, q_with) = gradient(&disc, 1.0);
    let (_, without, q_without) = gradient(&disc, 1e-9);
    assert!(
        q_with - q_without > 1e-3 * q_with,
        "Q {q_with} vs {q_without}"
    );
    let mut around: Vec<usize> = disc
        .faces()
        .filter(|f| f.contains(&0))
        .flatten()
        .map(|&v| v as usize)
        .filter(|&v| v != 0)
        .collect();
    around.sort_unstable();
    around.dedup();
    assert_eq!(around.len(), 2 * 10, "spokes and diagonals");
    for v in around {
        let i = index[v] as usize;
        let descent: Vec<f64> = (0..3)
            .map(|a| without[3 * i + a] - with[3 * i + a])
            .collect();
        let p = disc.positions[v];
        let toward_centre = -(descent[0] * p[0] + descent[1] * p[1]) / p[0].hypot(p[1]);
        let size = descent[0].hypot(descent[1]);
        assert_eq!(descent[2], 0.0, "vertex {v}");
        assert!(
            size > 0.0 && toward_centre >= (1.0 - 1e-9) * size,
            "vertex {v} at {p:?}: descent {descent:?}"
        );
    }
}
