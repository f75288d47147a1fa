//! The limit surface around vertices of high valence and under a memory limit: the apex of
//! a cone fan (valence up to 1000, which OpenSubdiv's own stencil factory could not build in
//! minutes) against the Catmull–Clark limit-position formula, and the memory and work budgets
//! lowering the isolation level or refusing the surface; faces OpenSubdiv cannot take are
//! refused.

use surfkit::limits::MemoryBudget;
use surfkit::mesh::PolygonMesh;
use surfkit::subdiv::{
    limit_surface, refine_uniform, PatchOptions, PatchSurface, SubdivOptions, SurfacePoint,
};
use surfkit::Error;

/// A cone of `n` triangles around an apex above a circle (an open fan: the circle is the
/// boundary).
fn cone(n: u32) -> PolygonMesh {
    let mut positions = vec![[0.0, 0.0, 1.0]];
    for i in 0..n {
        let a = std::f64::consts::TAU * f64::from(i) / f64::from(n);
        // An uneven radius, so that the apex's limit is not fixed by symmetry alone.
        let r = 1.0 + 0.3 * (3.0 * a).cos();
        positions.push([r * a.cos(), r * a.sin(), 0.2 * (2.0 * a).sin()]);
    }
    let faces: Vec<[u32; 3]> = (0..n).map(|i| [0, i + 1, (i + 1) % n + 1]).collect();
    PolygonMesh::from_polygons(positions, &faces)
}

/// Limit position of vertex `v` of an all-quad mesh (Halstead et al. 1993):
/// (n² v + 4 Σ eᵢ + Σ fᵢ) / (n (n + 5)), eᵢ its edge neighbours, fᵢ the opposite corners of
/// its quads.
fn limit_position_formula(mesh: &PolygonMesh, v: u32) -> [f64; 3] {
    let mut edge_neighbours = std::collections::BTreeSet::new();
    let mut opposite = Vec::new();
    for f in mesh.faces().filter(|f| f.contains(&v)) {
        assert_eq!(f.len(), 4, "refined faces are quads");
        let k = f.iter().position(|&c| c == v).unwrap();
        edge_neighbours.insert(f[(k + 1) % 4]);
        edge_neighbours.insert(f[(k + 3) % 4]);
        opposite.push(f[(k + 2) % 4]);
    }
    let n = opposite.len() as f64;
    assert_eq!(edge_neighbours.len(), opposite.len(), "an interior vertex");
    let p = |i: u32| mesh.positions[i as usize];
    std::array::from_fn(|k| {
        let e: f64 = edge_neighbours.iter().map(|&i| p(i)[k]).sum();
        let f: f64 = opposite.iter().map(|&i| p(i)[k]).sum();
        (n * n * p(v)[k] + 4.0 * e + f) / (n * (n + 5.0))
    })
}

#[test]
fn apex_of_cones_up_to_valence_1000_is_the_limit_position_formula() {
    for n in [5, 64, 1000] {
        let mesh = cone(n);
        let options = SubdivOptions::default();
        let surface = limit_surface(&mesh, &options, &PatchOptions::default()).unwrap();
        assert_eq!(
            surface.isolation(),
            4,
            "valence {n}: the default isolation fits"
        );
        // Ptex face 0 of triangle 0 has its (0, 0) corner at the triangle's first corner,
        // the apex.
        let ptex = surface.ptex_faces(0).unwrap().start;
        let at = SurfacePoint {
            ptex_face: ptex,
            u: 0.0,
            v: 0.0,
        };
        let got = surface.evaluate(&[at]).unwrap()[0].position;
        // One uniform level makes every face a quad and keeps the limit surface; the apex
        // is the refined vertex of valence n.
        let refined = refine_uniform(&mesh, 1, &options).unwrap();
        let mut valence = vec![0usize; refined.vertex_count()];
        for f in refined.faces() {
            for &c in f {
                valence[c as usize] += 1;
            }
        }
        let apex = valence.iter().position(|&k| k == n as usize).unwrap() as u32;
        let want = limit_position_formula(&refined, apex);
        for k in 0..3 {
            assert!(
                (got[k] - want[k]).abs() < 1e-12,
                "valence {n}, coordinate {k}: patch table {} vs formula {}",
                got[k],
                want[k]
            );
        }
    }
}

/// A triangulated grid: after one level every vertex is extraordinary, so each further
/// isolation level refines the whole mesh again.
fn triangle_grid(m: u32) -> PolygonMesh {
    let mut positions = Vec::new();
    for j in 0..=m {
        for i in 0..=m {
            positions.push([f64::from(i), f64::from(j), 0.1 * f64::from((i * j) % 3)]);
        }
    }
    let id = |i: u32, j: u32| j * (m + 1) + i;
    let mut faces = Vec::new();
    for j in 0..m {
        for i in 0..m {
            faces.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            faces.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    PolygonMesh::from_polygons(positions, &faces)
}

/// A surface built at a lowered isolation is still the limit surface wherever its patches
/// are regular (end caps approximate it): compares both at every regular patch's centre of
/// `lowered` and returns how many were compared.
fn regular_patches_agree(full: &PatchSurface, lowered: &PatchSurface) -> usize {
    let centres: Vec<SurfacePoint> = lowered
        .patches()
        .iter()
        .filter(|p| p.regular)
        .map(|p| SurfacePoint {
            ptex_face: p.ptex_face,
            u: p.u0 + 0.5 * p.size,
            v: p.v0 + 0.5 * p.size,
        })
        .collect();
    let a = full.evaluate(&centres).unwrap();
    let b = lowered.evaluate(&centres).unwrap();
    for (a, b) in a.iter().zip(&b) {
        for k in 0..3 {
            let (a, b) = (a.position, b.position);
            assert!((a[k] - b[k]).abs() < 1e-12, "{a:?} vs {b:?}");
        }
    }
    centres.len()
}

#[test]
fn a_memory_limit_lowers_the_isolation_or_refuses_with_the_limit() {
    let mesh = triangle_grid(24);
    let options = SubdivOptions::default();
    let with = |bytes: u64| {
        limit_surface(
            &mesh,
            &options,
            &PatchOptions {
                max_isolation: 4,
                memory: MemoryBudget::bytes(bytes),
                ..PatchOptions::default()
            },
        )
    };
    let full = with(1 << 34).unwrap();
    assert_eq!(full.isolation(), 4);
    // With 96 MiB the stencils of level 4 do not fit (the end caps of level 1 are estimated
    // at a million weights, 24 MB).
    let lowered = with(96 << 20).unwrap();
    assert!(
        (1..4).contains(&lowered.isolation()),
        "{}",
        lowered.isolation()
    );
    assert!(regular_patches_agree(&full, &lowered) > 0);
    match with(1 << 20) {
        Err(e @ Error::ResourceLimit { .. }) => {
            let text = e.to_string();
            assert!(text.contains("memory limit of 1.0 MiB"), "{text}");
            assert!(text.contains("--max-memory"), "{text}");
        }
        Err(e) => panic!("wrong error: {e}"),
        Ok(s) => panic!("1 MiB accepted at isolation {}", s.isolation()),
    }
}

#[test]
fn a_work_limit_lowers_the_isolation_or_refuses_naming_its_option() {
    // Every vertex of a triangle mesh is extraordinary: its end caps carry most weights.
    let mesh = triangle_grid(24);
    let options = SubdivOptions::default();
    let with = |weights: usize| {
        limit_surface(
            &mesh,
            &options,
            &PatchOptions {
                max_isolation: 4,
                max_stencil_weights: weights,
                ..PatchOptions::default()
            },
        )
    };
    let full = with(usize::MAX).unwrap();
    assert_eq!(full.isolation(), 4);
    let lowered = with(2_000_000).unwrap();
    assert!(
        (1..4).contains(&lowered.isolation()),
        "{}",
        lowered.isolation()
    );
    // Lowered by work as by memory: the same limit surface on the regular patches (at level 1
    // a triangle mesh has none).
    let compared = regular_patches_agree(&full, &lowered);
    assert!(lowered.isolation() == 1 || compared > 0);
    match with(10_000) {
        Err(e @ Error::WorkLimit { .. }) => {
            let text = e.to_string();
            assert!(text.contains("10000 stencil weights"), "{text}");
            assert!(text.contains("--max-stencils"), "{text}");
        }
        Err(e) => panic!("wrong error: {e}"),
        Ok(s) => panic!("10 000 weights accepted at isolation {}", s.isolation()),
    }
}

#[test]
fn the_refined_face_count_checked_against_the_memory_limit_is_exact() {
    // Triangles, quads and a pentagon: an n-gon makes n quads, then 4 per level.
    let mut mesh = triangle_grid(3);
    mesh.positions.push([9.0, 9.0, 0.0]);
    mesh.positions.push([10.0, 9.0, 0.0]);
    mesh.push_face(&[0, 1, 5, 4]);
    mesh.push_face(&[12, 13, 14, 15, 16]);
    for levels in 0..=3 {
        let refined = refine_uniform(&mesh, levels, &SubdivOptions::default()).unwrap();
        assert_eq!(
            surfkit::subdiv::refined_face_count(&mesh, levels),
            refined.face_count() as u64,
            "levels {levels}"
        );
    }
}

/// Found by the `mesh_topology` fuzzer: faces that use a vertex twice sent OpenSubdiv's
/// end-cap construction into a stack overflow (an abort no caller can catch). They are
/// refused before OpenSubdiv sees them, naming the face.
#[test]
fn a_face_using_a_vertex_twice_is_refused_before_opensubdiv() {
    let positions = vec![
        [1.0, 0.0, 0.0],
        [0.0, 7.0, 2.0],
        [6.0, 7.0, 1.0],
        [3.0, 0.0, 1.0],
        [0.0, 0.0, 0.0],
        [3.0, 0.0, 0.0],
    ];
    let faces = [vec![2, 0, 3, 2, 2, 1, 4], vec![5, 3, 0, 4, 3, 1, 0, 2]];
    let mesh = PolygonMesh::from_polygons(positions, &faces);
    let patch = PatchOptions {
        max_isolation: 2,
        ..PatchOptions::default()
    };
    let Err(e) = limit_surface(&mesh, &SubdivOptions::default(), &patch) else {
        panic!("a face using a vertex twice was accepted");
    };
    assert!(e.to_string().contains("face 0"), "{e}");
    assert!(refine_uniform(&mesh, 1, &SubdivOptions::default()).is_err());
}
