//! The block method of Kiciak's §5 against the plain method on the author's three-tube
//! junction (359 vertices; a cheaper quadrature than the default keeps the test short):
//! the same optimum (F to a relative 1e-6, gradient below the tolerance), fixed vertices
//! bit-identical; the Schwarz-preconditioned CG solves a positive definite Hessian system
//! (residual checked with a dense product written here); the blocks cover every free
//! vertex; bad block counts are errors.

use std::sync::OnceLock;

use surfkit::fair::{
    fixed_vertices, optimize, pcg, refine_surface, tubes, voronoi_blocks, BlockOptions, CgStop,
    Factorizer, FairOptions, FairReport, Functional, MeshTopology, PatchRepresentation,
    RepresentationOptions, Schwarz,
};
use surfkit::mesh::PolygonMesh;
use surfkit::tolerance::SOLVE;

fn representation() -> RepresentationOptions {
    RepresentationOptions {
        isolation: 2,
        nodes: 3,
        ..RepresentationOptions::default()
    }
}

fn options(blocks: Option<BlockOptions>) -> FairOptions {
    FairOptions {
        max_refinements: 0,
        representation: representation(),
        blocks,
        ..FairOptions::default()
    }
}

/// The plain method's optimum of the 359-vertex junction (computed once).
fn plain() -> &'static (PolygonMesh, PolygonMesh, FairReport) {
    static PLAIN: OnceLock<(PolygonMesh, PolygonMesh, FairReport)> = OnceLock::new();
    PLAIN.get_or_init(|| {
        let mesh = tubes(3, 4, 3).unwrap();
        let (out, report) = optimize(&mesh, &options(None)).unwrap();
        (mesh, out, report)
    })
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

#[test]
fn fair_blocks_reach_the_plain_optimum() {
    let (mesh, plain_out, plain_report) = plain();
    assert!(plain_report.newton.converged);
    let blocks = BlockOptions {
        count: 4,
        ..BlockOptions::default()
    };
    let start = std::time::Instant::now();
    let (out, report) = optimize(mesh, &options(Some(blocks))).unwrap();
    let b = report.blocks.as_ref().unwrap();
    eprintln!(
        "plain: F {:.12e}, {} Hessians; blocks: F {:.12e}, {} sweeps, {} block Hessians \
         (≈ {:.1} whole), {} global Hessians, {} CG iterations, {:.1} s",
        plain_report.final_terms.f,
        plain_report.newton.hessian_evaluations,
        report.final_terms.f,
        b.sweeps,
        b.block_hessian_evaluations,
        b.block_hessians_equivalent,
        b.global_hessian_evaluations,
        b.cg_iterations,
        start.elapsed().as_secs_f64()
    );
    assert!(report.newton.converged);
    assert!(report.final_gradient_norm <= 1e-8 * report.initial_gradient_norm);
    let (f_plain, f_blocks) = (plain_report.final_terms.f, report.final_terms.f);
    assert!(
        (f_plain - f_blocks).abs() <= 1e-6 * f_plain.abs(),
        "F: plain {f_plain}, blocks {f_blocks}"
    );
    // How far apart the two minimizers are (printed for the record, not asserted).
    let gap = out
        .positions
        .iter()
        .zip(&plain_out.positions)
        .map(|(a, b)| (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt())
        .fold(0.0, f64::max);
    eprintln!("largest distance between the two optima's vertices: {gap:e}");
    crate::common::assert_faces_and_boundary_rings_kept(mesh, &out);
}

#[test]
fn fair_blocks_pcg_solves_a_positive_definite_hessian_system() {
    // The Hessian at the plain optimum, where Cholesky shows it positive definite.
    let (mesh, out, report) = plain();
    let topo = MeshTopology::new(mesh).unwrap();
    let fixed = fixed_vertices(&topo, 3, &[]).unwrap();
    let special = topo.special_flags();
    let rep = PatchRepresentation::new(mesh, &topo.boundary, &special, &representation()).unwrap();
    let functional = Functional::new(&rep, &fixed, report.c);
    let (_, _, h) = functional.hessian(&out.positions);
    let n = 3 * functional.free_count();
    assert!(Factorizer::new(functional.free_count())
        .factor(&h, 0.0)
        .is_ok());
    // A right-hand side with every component: the gradient at the raw mesh.
    let b: Vec<f64> = functional.gradient(&mesh.positions).1;
    let blocks: Vec<Vec<u32>> = voronoi_blocks(&topo, &fixed, 5, 2)
        .unwrap()
        .into_iter()
        .map(|blk| {
            blk.iter()
                .map(|&v| functional.free_index()[v as usize])
                .collect()
        })
        .collect();
    let mut schwarz = Schwarz::new(functional.free_count(), blocks).unwrap();
    schwarz.factor(&h, 0.0).unwrap();
    let outcome = pcg(&h, 0.0, &b, &|r| schwarz.apply(r), SOLVE, 10 * n);
    assert_eq!(outcome.stop, CgStop::Converged);
    // The preconditioner must pay: far fewer iterations than unknowns.
    let plain_cg = pcg(&h, 0.0, &b, &|r| r.to_vec(), SOLVE, 10 * n);
    eprintln!(
        "{n} unknowns: Schwarz-preconditioned CG {} iterations, unpreconditioned {} ({:?})",
        outcome.iterations, plain_cg.iterations, plain_cg.stop
    );
    // The residual by a dense product of the full symmetric matrix, built here.
    let mut dense = vec![vec![0.0; n]; n];
    for (&(i, j), v) in h.blocks.iter().zip(&h.values) {
        let (i, j) = (3 * i as usize, 3 * j as usize);
        for a in 0..3 {
            for c in 0..3 {
                if i == j && a > c {
                    continue;
                }
                dense[i + a][j + c] = v[a][c];
                dense[j + c][i + a] = v[a][c];
            }
        }
    }
    let residual: Vec<f64> = (0..n)
        .map(|r| {
            dense[r]
                .iter()
                .zip(&outcome.x)
                .map(|(m, x)| m * x)
                .sum::<f64>()
                - b[r]
        })
        .collect();
    assert!(
        norm(&residual) <= SOLVE * norm(&b),
        "residual {:e} of ‖b‖ {:e}",
        norm(&residual),
        norm(&b)
    );
}

#[test]
fn fair_blocks_cover_every_free_vertex() {
    let base = tubes(3, 4, 3).unwrap();
    for mesh in [base.clone(), refine_surface(&base, 1).unwrap()] {
        let topo = MeshTopology::new(&mesh).unwrap();
        let fixed = fixed_vertices(&topo, 3, &[]).unwrap();
        let free = fixed.iter().filter(|&&f| !f).count();
        for count in [1, 5, 17] {
            for overlap in [0, 1, 3] {
                let blocks = voronoi_blocks(&topo, &fixed, count, overlap).unwrap();
                assert_eq!(blocks.len(), count);
                let mut hits = vec![0usize; mesh.vertex_count()];
                for block in &blocks {
                    assert!(!block.is_empty());
                    for &v in block {
                        assert!(!fixed[v as usize], "fixed vertex {v} in a block");
                        hits[v as usize] += 1;
                    }
                }
                for v in 0..mesh.vertex_count() {
                    assert!(fixed[v] || hits[v] >= 1, "free vertex {v} in no block");
                }
                let total: usize = hits.iter().sum();
                if overlap == 0 {
                    assert_eq!(total, free);
                } else if count > 1 {
                    assert!(total > free);
                }
            }
        }
        for bad in [0, free + 1] {
            let err = voronoi_blocks(&topo, &fixed, bad, 2).unwrap_err();
            assert!(err.to_string().contains("block"), "{err}");
        }
    }
    let bad = FairOptions {
        max_refinements: 0,
        representation: representation(),
        blocks: Some(BlockOptions {
            count: 100_000,
            ..BlockOptions::default()
        }),
        ..FairOptions::default()
    };
    assert!(optimize(&base, &bad).is_err());
}
