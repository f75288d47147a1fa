//! Gradient and Hessian of F (Kiciak eq. 4–6) against central finite differences of F on
//! small meshes: a regular grid patch and discs around special vertices of valence 3 and 5.

use surfkit::assert_near;
use surfkit::fair::{
    fixed_vertices, refine_surface, sector_disc, tubes, Functional, HessianKind, MeshTopology,
    PatchRepresentation, Representation, RepresentationOptions, SurfaceKind, SurfaceRepresentation,
};
use surfkit::mesh::PolygonMesh;
use surfkit::tolerance::FINITE_DIFFERENCE;

/// Deterministic pseudo-random offsets in [−0.5, 0.5).
fn jitter(k: usize) -> f64 {
    let x = (k as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    let x = (x ^ (x >> 29)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    ((x >> 11) as f64) / ((1u64 << 53) as f64) - 0.5
}

fn perturbed(mut mesh: PolygonMesh, amount: f64) -> PolygonMesh {
    for (v, p) in mesh.positions.iter_mut().enumerate() {
        for (a, c) in p.iter_mut().enumerate() {
            *c += amount * jitter(3 * v + a);
        }
    }
    mesh
}

fn setup(mesh: &PolygonMesh) -> (PatchRepresentation, Vec<bool>) {
    let topo = MeshTopology::new(mesh).unwrap();
    let fixed = fixed_vertices(&topo, 3, &[]).unwrap();
    let special = topo.special_flags();
    let options = RepresentationOptions {
        isolation: 2,
        ..RepresentationOptions::default()
    };
    let rep = PatchRepresentation::new(mesh, &topo.boundary, &special, &options).unwrap();
    (rep, fixed)
}

/// Positions with free variable `k` (free vertex k / 3, coordinate k % 3) moved by `h`.
fn shifted(mesh: &PolygonMesh, free: &[u32], k: usize, h: f64) -> Vec<[f64; 3]> {
    let mut p = mesh.positions.clone();
    let v = free.iter().position(|&i| i as usize == k / 3).unwrap();
    p[v][k % 3] += h;
    p
}

const STEP: f64 = 1e-5;

fn check_gradient_and_hessian(mesh: &PolygonMesh, hessian_columns: usize) {
    let (rep, fixed) = setup(mesh);
    let functional = Functional::new(&rep, &fixed, 0.7);
    let free = functional.free_index().to_vec();
    assert!(functional.free_count() > 0);
    let (terms, g, h) = functional.hessian(&mesh.positions);
    let (terms2, g2) = functional.gradient(&mesh.positions);
    assert_near!(
        terms.f,
        functional.value(&mesh.positions).f,
        FINITE_DIFFERENCE
    );
    assert_near!(terms.f, terms2.f, FINITE_DIFFERENCE);
    assert!(terms.s > 0.0 && terms.q > 0.0);
    let gscale = g.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    for k in 0..g.len() {
        assert_near!(g[k] / gscale, g2[k] / gscale, FINITE_DIFFERENCE);
        let fp = functional.value(&shifted(mesh, &free, k, STEP)).f;
        let fm = functional.value(&shifted(mesh, &free, k, -STEP)).f;
        let fd = (fp - fm) / (2.0 * STEP);
        assert_near!(
            fd / gscale,
            g[k] / gscale,
            FINITE_DIFFERENCE,
            "gradient entry {k}"
        );
    }
    let n = g.len();
    let dense = dense(&h, n);
    let hscale = dense.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let stride = (n / hessian_columns).max(1);
    for k in (0..n).step_by(stride) {
        let (_, gp) = functional.gradient(&shifted(mesh, &free, k, STEP));
        let (_, gm) = functional.gradient(&shifted(mesh, &free, k, -STEP));
        for r in 0..n {
            let fd = (gp[r] - gm[r]) / (2.0 * STEP);
            assert_near!(
                fd / hscale,
                dense[r * n + k] / hscale,
                FINITE_DIFFERENCE,
                "Hessian entry ({r}, {k})"
            );
        }
    }
}

#[test]
fn fair_derivatives_regular_grid() {
    // Valence 4 everywhere inside: a 4-sector disc is a regular grid.
    let mesh = perturbed(sector_disc(4, 4).unwrap(), 0.1);
    check_gradient_and_hessian(&mesh, 12);
}

#[test]
fn fair_derivatives_valence_5() {
    let mesh = perturbed(sector_disc(5, 4).unwrap(), 0.1);
    check_gradient_and_hessian(&mesh, 12);
}

#[test]
fn fair_derivatives_valence_3() {
    let mesh = perturbed(sector_disc(3, 4).unwrap(), 0.1);
    check_gradient_and_hessian(&mesh, 12);
}

#[test]
fn fair_evaluations_are_bit_identical_on_one_and_two_threads() {
    // The partial sums follow a fixed split of the patches, so the number of cores must
    // not change a single bit of F, its gradient or its Hessian.
    let mesh = perturbed(sector_disc(5, 4).unwrap(), 0.1);
    let (rep, fixed) = setup(&mesh);
    let f = Functional::new(&rep, &fixed, 0.3);
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                let (t, g, h) = f.hessian(&mesh.positions);
                (
                    f.value(&mesh.positions),
                    f.gradient(&mesh.positions),
                    t,
                    g,
                    h.values,
                )
            })
    };
    let (one, two) = (run(1), run(2));
    assert_eq!(one.0, two.0);
    assert_eq!(one.1, two.1);
    assert_eq!(one.2, two.2);
    assert_eq!(one.3, two.3);
    assert_eq!(one.4, two.4);
    // The gradient from `gradient` and from `hessian` are the same sums.
    assert_eq!(one.1 .1, one.3);
}

/// Dense symmetric matrix of the upper-triangle blocks of `h` (n × n, row-major).
fn dense(h: &surfkit::fair::BlockHessian, n: usize) -> Vec<f64> {
    let mut out = vec![0.0; n * n];
    for (&(i, j), b) in h.blocks.iter().zip(&h.values) {
        for (a, row) in b.iter().enumerate() {
            for (c, &x) in row.iter().enumerate() {
                let (r, s) = (3 * i as usize + a, 3 * j as usize + c);
                out[r * n + s] = x;
                out[s * n + r] = x;
            }
        }
    }
    out
}

#[test]
fn gauss_newton_part_equals_the_hessian_of_a_flat_surface() {
    // H = 2 Σ JᵀJ + 2 Σ r ∇²r: on a plane ∇H = 0, S's residuals vanish, and with c = 0 the
    // assembled Gauss–Newton matrix must be the exact Hessian (checked against finite
    // differences above). Jitter within the plane keeps it a plane.
    let mut flat = sector_disc(5, 4).unwrap();
    for (v, p) in flat.positions.iter_mut().enumerate() {
        p[0] += 0.1 * jitter(3 * v);
        p[1] += 0.1 * jitter(3 * v + 1);
        p[2] = 0.0;
    }
    let (rep, fixed) = setup(&flat);
    let functional = Functional::new(&rep, &fixed, 0.0);
    let n = 3 * functional.free_count();
    let (terms, g, exact) = functional.hessian(&flat.positions);
    let alone = functional.hessians(&flat.positions, HessianKind::GaussNewton);
    assert_eq!((terms, &g), (alone.terms, &alone.gradient));
    assert!(alone.exact.is_none());
    let (exact, gauss_newton) = (dense(&exact, n), dense(&alone.gauss_newton.unwrap(), n));
    let scale = exact.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(scale > 0.0);
    for (a, b) in gauss_newton.iter().zip(&exact) {
        assert_near!(a / scale, b / scale, 1e-12);
    }
    // On a curved surface they differ, and the Gauss–Newton matrix stays positive
    // semidefinite: vᵀ H v ≥ 0 for every v tried.
    let curved = perturbed(sector_disc(5, 4).unwrap(), 0.1);
    let functional = Functional::new(&rep, &fixed, 0.7);
    let (terms, g, exact) = functional.hessian(&curved.positions);
    let alone = functional.hessians(&curved.positions, HessianKind::GaussNewton);
    // One pass for both gives the same matrices as two.
    let both = functional.hessians(&curved.positions, HessianKind::Both);
    assert_eq!((terms, &g), (both.terms, &both.gradient));
    assert_eq!(exact.values, both.exact.unwrap().values);
    let (exact, gauss_newton) = (dense(&exact, n), dense(&alone.gauss_newton.unwrap(), n));
    let gn_scale = gauss_newton.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    for (a, b) in dense(&both.gauss_newton.unwrap(), n)
        .iter()
        .zip(&gauss_newton)
    {
        assert_near!(a / gn_scale, b / gn_scale, 1e-14);
    }
    let quadratic = |m: &[f64], v: &[f64]| -> f64 {
        (0..n)
            .map(|r| v[r] * (0..n).map(|s| m[r * n + s] * v[s]).sum::<f64>())
            .sum()
    };
    for trial in 0..200 {
        let v: Vec<f64> = (0..n).map(|k| jitter(1000 + trial * n + k)).collect();
        assert!(quadratic(&gauss_newton, &v) >= 0.0);
    }
    let differ = exact
        .iter()
        .zip(&gauss_newton)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(differ > 1e-3 * exact.iter().fold(0.0f64, |m, x| m.max(x.abs())));
}

#[test]
fn fair_gradient_stays_smooth_far_from_the_origin() {
    // The derivatives at a quadrature point are sums of coefficients times control
    // vertices. Summed over absolute coordinates, a mesh far from the origin (or a fine
    // element of a large mesh) loses the digits its element size lacks against its
    // coordinates, and the gradient becomes noise at the scale of the Newton tail's steps.
    // The change of ∇F over a step Δ of 10⁻⁵ must be H Δ (Hessian assembled at the
    // midpoint) here, 10⁸ from the origin, as it is near it (summing absolute coordinates:
    // 5.7·10⁻⁴, measured when this test was written). Δ is the difference of the rounded
    // positions, exact by Sterbenz's lemma.
    const FAR: f64 = 1e8;
    const STEP: f64 = 1e-5;
    let mut mesh = perturbed(sector_disc(5, 4).unwrap(), 0.1);
    for p in &mut mesh.positions {
        for c in p.iter_mut() {
            *c += FAR;
        }
    }
    let (rep, fixed) = setup(&mesh);
    let functional = Functional::new(&rep, &fixed, 0.7);
    let free = functional.free_index().to_vec();
    let n = 3 * functional.free_count();
    let moved = |sign: f64| -> Vec<[f64; 3]> {
        let mut p = mesh.positions.clone();
        for (v, q) in p.iter_mut().enumerate() {
            if free[v] != u32::MAX {
                for (a, c) in q.iter_mut().enumerate() {
                    *c += sign * STEP * jitter(7 * v + a);
                }
            }
        }
        p
    };
    let (plus, minus) = (moved(1.0), moved(-1.0));
    let (_, g_plus) = functional.gradient(&plus);
    let (_, g_minus) = functional.gradient(&minus);
    let (_, _, h) = functional.hessian(&mesh.positions);
    let h = dense(&h, n);
    let mut delta = vec![0.0; n];
    for (v, (a, b)) in plus.iter().zip(&minus).enumerate() {
        if free[v] != u32::MAX {
            for c in 0..3 {
                delta[3 * free[v] as usize + c] = a[c] - b[c];
            }
        }
    }
    let (mut error, mut norm) = (0.0f64, 0.0f64);
    for r in 0..n {
        let h_delta: f64 = (0..n).map(|k| h[r * n + k] * delta[k]).sum();
        error += (g_plus[r] - g_minus[r] - h_delta).powi(2);
        norm += h_delta.powi(2);
    }
    let relative = (error / norm).sqrt();
    assert!(relative < 1e-6, "‖Δg − H Δ‖ / ‖H Δ‖ = {relative:e}");
}

#[test]
fn numbering_changes_neither_f_nor_its_derivatives_nor_the_shared_tables() {
    // Patch vertices are kept in the patch's order, not by id, so that every ordinary
    // patch shares one coefficient table per node; a pair of patch vertices whose free
    // indices run backwards then adds its transpose to the block. Reversing the ids of a
    // 3743-vertex junction turns most pairs around: F, the gradient and both Hessians must
    // be the same (permuted) to round-off, on both surfaces, and so must the number of
    // distinct tables.
    let mesh = perturbed(refine_surface(&tubes(3, 8, 2).unwrap(), 1).unwrap(), 0.05);
    let n = mesh.vertex_count();
    let reversed_id = |v: u32| (n - 1) as u32 - v;
    let faces: Vec<Vec<u32>> = mesh
        .faces()
        .map(|f| f.iter().map(|&v| reversed_id(v)).collect())
        .collect();
    let reversed =
        PolygonMesh::from_polygons(mesh.positions.iter().rev().copied().collect(), &faces);
    for surface in [SurfaceKind::G2, SurfaceKind::CatmullClark] {
        let build = |m: &PolygonMesh| {
            let topo = MeshTopology::new(m).unwrap();
            let options = RepresentationOptions {
                surface,
                isolation: 2,
                ..RepresentationOptions::default()
            };
            let rep =
                SurfaceRepresentation::new(m, &topo.boundary, &topo.special_flags(), &options)
                    .unwrap();
            (rep, fixed_vertices(&topo, 3, &[]).unwrap())
        };
        let ((rep, fixed), (rep_r, fixed_r)) = (build(&mesh), build(&reversed));
        let distinct = |rep: &SurfaceRepresentation| {
            let mut tables: Vec<*const [f64; 9]> = rep
                .points()
                .iter()
                .map(|p| p.coefficients.as_ptr())
                .collect();
            tables.sort_unstable();
            tables.dedup();
            tables.len()
        };
        let points = rep.points().len();
        assert_eq!(distinct(&rep), distinct(&rep_r), "{surface:?}");
        assert!(
            distinct(&rep) * 20 < points,
            "{surface:?}: {} tables for {points} points",
            distinct(&rep)
        );
        let (f, f_r) = (
            Functional::new(&rep, &fixed, 0.7),
            Functional::new(&rep_r, &fixed_r, 0.7),
        );
        let free = f.free_count();
        assert_eq!(free, f_r.free_count());
        // Free index i of `mesh` is free index free − 1 − i of `reversed`.
        let both = f.hessians(&mesh.positions, HessianKind::Both);
        let both_r = f_r.hessians(&reversed.positions, HessianKind::Both);
        assert_near!(both.terms.f, both_r.terms.f, 1e-12 * both.terms.f);
        let g_scale = both.gradient.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for i in 0..free {
            for a in 0..3 {
                let (x, y) = (
                    both.gradient[3 * i + a],
                    both_r.gradient[3 * (free - 1 - i) + a],
                );
                assert_near!(x / g_scale, y / g_scale, 1e-11);
            }
        }
        for (h, h_r) in [
            (both.exact.unwrap(), both_r.exact.unwrap()),
            (both.gauss_newton.unwrap(), both_r.gauss_newton.unwrap()),
        ] {
            let entries = |h: &surfkit::fair::BlockHessian, flip: bool| {
                let mut m = std::collections::HashMap::new();
                for (&(i, j), b) in h.blocks.iter().zip(&h.values) {
                    let (i, j) = if flip {
                        (free as u32 - 1 - i, free as u32 - 1 - j)
                    } else {
                        (i, j)
                    };
                    for (a, row) in b.iter().enumerate() {
                        for (c, &x) in row.iter().enumerate() {
                            // Both triangles, so that a block stored the other way round
                            // meets its counterpart.
                            m.insert((3 * i + a as u32, 3 * j + c as u32), x);
                            m.insert((3 * j + c as u32, 3 * i + a as u32), x);
                        }
                    }
                }
                m
            };
            let (m, m_r) = (entries(&h, false), entries(&h_r, true));
            assert_eq!(m.len(), m_r.len());
            let scale = m.values().fold(0.0f64, |s, x| s.max(x.abs()));
            for (key, x) in &m {
                assert_near!(x / scale, m_r[key] / scale, 1e-11);
            }
        }
    }
}
