//! Nested iteration: the multilevel method's optional start (`--coarse-start`;
//! [`CoarseStart`](crate::fair::CoarseStart) says why it is not the default). The raw fine
//! mesh is un-subdivided once, the coarse control mesh that best reproduces it (least
//! squares through the refinement's stencils) is optimized — the same functional on a
//! quarter of the unknowns, by whichever method its size takes (itself started the same
//! way where its fixed rings allow, [`MIN_COARSE_RINGS`]) — and its optimum, refined, is
//! where the fine Newton iteration starts.
//!
//! Why: from a raw mesh most of the fine Hessians go into the Levenberg–Marquardt phase
//! far from the minimum (the 94 077-vertex five-tube junction: 16 of 28 iterations, most of
//! its 430 s of Hessians); on the coarse mesh that phase costs a quarter as much, and the
//! refined coarse optimum already has the shape (refining a control mesh does not change
//! its Catmull–Clark surface), so the fine level is left the Newton tail — §6's
//! coarse-to-fine cascade, for a mesh given at its finest. Measured on that junction
//! (2026-11-26, single runs): 571 s with 10 fine Hessians and a 120 s coarse stage,
//! against 803 s and 23 Hessians from the raw mesh. The two runs ended in different local
//! minima (F 127.4 from the coarse start, 149.1 from the raw mesh): where a functional has
//! several, a different start may find another — lower there, higher on the 56k
//! three-tube junction.
//!
//! The fine problem is unchanged: its fixed vertices keep the input's coordinates, the
//! tolerance stays relative to the input's gradient, and a start that does not lower F
//! below the input's is not used.

use std::ops::ControlFlow;
use std::time::Instant;

use super::block_csr::Prolongation;
use super::unsubdivision::{coarsen, FaceList};
use crate::error::{Error, Result};
use crate::fair::functional::evaluation::Functional;
use crate::fair::solvers::newton::{Iteration, NewtonOptions};
use crate::fair::solvers::pcg::{pcg_operator, CgStop};
use crate::fair::surface::representation::Representation;
use crate::fair::{optimize_observed, CoarseStart, FairMethod, FairOptions, FairReport};
use crate::linalg::norm;
use crate::mesh::PolygonMesh;

/// The coarse problem is solved to this relative gradient: its optimum is only a start,
/// and the fine level's Newton iterations resolve what is left in a step or two.
pub const COARSE_TOLERANCE: f64 = 1e-6;

/// Conjugate-gradient iterations for the least-squares coarse positions at most (the
/// normal equations of a refinement are well conditioned: ~160 on the junctions).
const LEAST_SQUARES_ITERATIONS: usize = 2000;

/// What the coarse stage did.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CoarseStartReport {
    /// Wall-clock seconds of the stage (un-subdivision and least squares included).
    pub seconds: f64,
    /// The coarse problem's own report (its vertices, Newton iterations, its own coarse
    /// stage if it had one, …).
    pub report: Box<FairReport>,
    /// ‖∇F‖ and F of the fine problem at the refined coarse optimum (the input's are the
    /// fine report's `initial_gradient_norm` and `initial_terms`).
    pub start_gradient_norm: f64,
    pub start_f: f64,
    /// Whether the fine iteration started there (false: F there was not below the input's,
    /// and the fine iteration started from the input).
    pub used: bool,
}

/// The coarse mesh of `mesh` with least-squares positions, and the stencils of every fine
/// vertex over its vertices; `None` when `mesh` is not a Catmull–Clark refinement.
pub fn least_squares_coarse_mesh(mesh: &PolygonMesh) -> Option<(PolygonMesh, Prolongation)> {
    let faces = FaceList {
        vertex_count: mesh.vertex_count(),
        faces: mesh.faces().map(<[u32]>::to_vec).collect(),
    };
    let coarsening = coarsen(&faces)?;
    let coarse_count = coarsening.coarse.vertex_count;
    let mut diagonal = vec![0.0; 3 * coarse_count];
    for &(c, w) in coarsening.stencils.iter().flatten() {
        for a in 0..3 {
            diagonal[3 * c as usize + a] += w * w;
        }
    }
    let refinement = Prolongation::new(coarse_count, &coarsening.stencils);
    let fine: Vec<f64> = mesh.positions.iter().flatten().copied().collect();
    let coarse = least_squares(&refinement, &diagonal, &fine)?;
    let positions = coarse.chunks(3).map(|p| [p[0], p[1], p[2]]).collect();
    Some((
        PolygonMesh::from_polygons(positions, &coarsening.coarse.faces),
        refinement,
    ))
}

/// argmin ‖P x − fine‖ by conjugate gradients on PᵀP x = Pᵀ fine, preconditioned by
/// PᵀP's `diagonal`; `None` if PᵀP is singular (a coarse vertex no stencil uses) or CG
/// does not converge.
fn least_squares(p: &Prolongation, diagonal: &[f64], fine: &[f64]) -> Option<Vec<f64>> {
    if diagonal.iter().any(|&d| d <= 0.0) {
        return None;
    }
    let normal = |x: &[f64]| {
        let mut px = vec![0.0; fine.len()];
        p.add_prolonged(x, &mut px);
        p.restrict(&px)
    };
    let rhs = p.restrict(fine);
    let cg = pcg_operator(
        &normal,
        &rhs,
        &|r: &[f64]| r.iter().zip(diagonal).map(|(r, d)| r / d).collect(),
        1e-12,
        LEAST_SQUARES_ITERATIONS,
    );
    (cg.stop == CgStop::Converged).then_some(cg.x)
}

/// The fixed rings of the coarse problem for `fine_rings` fixed rings of the fine one: the
/// fewest whose refinement holds the fine fixed rings (fine ring 2k + 1 is coarse ring k's
/// vertex points, and the edge and face points between coarse rings k and k + 1 lie on
/// fine ring 2k + 2), so that no free fine vertex is held by the coarse problem. Holding
/// the coarse problem's default three rings instead leaves fine rings 3–6 at the input's
/// shape, a kink that costs the fine level more Hessians than the coarse stage saves (the
/// 14 399-vertex junction, 2026-11-26: 10 fine Hessians against 6 with two coarse rings).
pub fn coarse_boundary_rings(fine_rings: u32) -> u32 {
    fine_rings.div_ceil(2)
}

/// No coarse stage holds fewer rings: with one ring the coarse surface's tangent plane at
/// the boundary is free, its optimum bends there away from the fine problem's fixed rings,
/// and the refined start is worse than the input (the 14 399-vertex junction: F 7.6e4
/// against the input's 1.2e4) or, a level further down, leads into another local minimum
/// (F 31.2 instead of 18.0). So the default three fine rings allow one coarse stage.
pub const MIN_COARSE_RINGS: u32 = 2;

/// The coarse stage's outcome: the fine start and the coarse problem's report.
pub struct CoarseStage {
    /// All vertex positions of the fine mesh: the fixed ones the input's, the free ones
    /// the refined coarse optimum's.
    pub start: Vec<[f64; 3]>,
    pub seconds: f64,
    pub report: Box<FairReport>,
}

/// The fine start by nested iteration (see the module documentation); `None` when `mesh`
/// does not un-subdivide or the coarse mesh is not a problem `optimize` takes as it is
/// (then the fine iteration starts from the input).
///
/// # Errors
/// Errors of the coarse optimization other than its mesh being refused (a cancelled
/// coarse stage is not an error: its report says `cancelled`).
pub fn coarse_start(
    mesh: &PolygonMesh,
    fixed: &[bool],
    options: &FairOptions,
    observe: &mut dyn FnMut(&Iteration, f64) -> ControlFlow<()>,
) -> Result<Option<CoarseStage>> {
    let clock = Instant::now();
    let rings = coarse_boundary_rings(options.boundary_rings);
    if rings < MIN_COARSE_RINGS {
        return Ok(None);
    }
    let Some((coarse, refinement)) = least_squares_coarse_mesh(mesh) else {
        return Ok(None);
    };
    let mut coarse_options = options.clone();
    coarse_options.max_refinements = 0;
    coarse_options.boundary_rings = rings;
    coarse_options.coarse_start = CoarseStart::Always;
    coarse_options.method = FairMethod::Automatic;
    coarse_options.newton.relative_gradient = COARSE_TOLERANCE;
    let (optimum, report) = match optimize_observed(&coarse, &coarse_options, observe) {
        Ok(done) => done,
        Err(Error::InvalidInput(_) | Error::Topology(_)) => return Ok(None),
        Err(other) => return Err(other),
    };
    let coarse_flat: Vec<f64> = optimum.positions.iter().flatten().copied().collect();
    let mut refined = vec![0.0; 3 * mesh.vertex_count()];
    refinement.add_prolonged(&coarse_flat, &mut refined);
    let start = mesh
        .positions
        .iter()
        .zip(refined.chunks(3))
        .zip(fixed)
        .map(|((&raw, p), &held)| if held { raw } else { [p[0], p[1], p[2]] })
        .collect();
    Ok(Some(CoarseStage {
        start,
        seconds: clock.elapsed().as_secs_f64(),
        report: Box::new(report),
    }))
}

/// Runs the coarse stage for the fine problem `functional` of `mesh` and, if its refined
/// optimum lowers F below the input's (`positions` on entry, where F is `input_f` and
/// ‖∇F‖ `input_gradient`, already evaluated by the caller), moves `positions` there and
/// sets `newton.relative_gradient` so that the fine iteration still stops at the
/// tolerance relative to the input's gradient. `None` when there is no coarse stage.
///
/// # Errors
/// As [`coarse_start`].
pub fn nested_start<R: Representation>(
    mesh: &PolygonMesh,
    functional: &Functional<R>,
    options: &FairOptions,
    positions: &mut Vec<[f64; 3]>,
    (input_f, input_gradient): (f64, f64),
    newton: &mut NewtonOptions,
    observe: &mut dyn FnMut(&Iteration, f64) -> ControlFlow<()>,
) -> Result<Option<CoarseStartReport>> {
    let fixed: Vec<bool> = functional
        .free_index()
        .iter()
        .map(|&u| u == u32::MAX)
        .collect();
    let Some(stage) = coarse_start(mesh, &fixed, options, observe)? else {
        return Ok(None);
    };
    let (start_terms, start_gradient) = functional.gradient(&stage.start);
    let start_gradient = norm(&start_gradient);
    let used = !stage.report.newton.cancelled
        && start_terms.f.is_finite()
        && start_terms.f < input_f
        && start_gradient.is_finite();
    if used {
        *positions = stage.start;
        newton.relative_gradient *= input_gradient / start_gradient;
    }
    Ok(Some(CoarseStartReport {
        seconds: stage.seconds,
        report: stage.report,
        start_gradient_norm: start_gradient,
        start_f: start_terms.f,
        used,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fair::{refine_surface, tubes};

    #[test]
    fn least_squares_recovers_the_coarse_mesh_a_refinement_was_made_from() {
        // Fine positions made from known coarse positions by the refinement's own stencils
        // (CC's rules inside, averages along the dropped boundary ring): the
        // least-squares coarse mesh is the coarse mesh, positions and faces.
        let mesh = refine_surface(&tubes(3, 8, 2).unwrap(), 1).unwrap();
        let faces = FaceList {
            vertex_count: mesh.vertex_count(),
            faces: mesh.faces().map(<[u32]>::to_vec).collect(),
        };
        let coarsening = coarsen(&faces).unwrap();
        let n = coarsening.coarse.vertex_count;
        let coarse: Vec<f64> = (0..3 * n)
            .map(|i| ((i * 7919) % 1009) as f64 / 1009.0)
            .collect();
        let mut fine = vec![0.0; 3 * mesh.vertex_count()];
        Prolongation::new(n, &coarsening.stencils).add_prolonged(&coarse, &mut fine);
        let mut made = mesh.clone();
        made.positions = fine.chunks(3).map(|p| [p[0], p[1], p[2]]).collect();
        let (found, refinement) = least_squares_coarse_mesh(&made).unwrap();
        assert_eq!(found.vertex_count(), n);
        assert_eq!(refinement.fine_count(), mesh.vertex_count());
        let found_faces: Vec<Vec<u32>> = found.faces().map(<[u32]>::to_vec).collect();
        assert_eq!(found_faces, coarsening.coarse.faces);
        let error = found
            .positions
            .iter()
            .flatten()
            .zip(&coarse)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(error <= 1e-9, "largest error {error:e}");
    }
}
