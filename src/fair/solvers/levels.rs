//! Coarse-to-fine optimization, as the paper's §6 does for figure 7 ("the mesh was refined
//! and used as the starting point for the optimization"): optimize the input, refine its
//! surface, start the finer problem from the refined optimum, and so on.
//!
//! Why: from a raw mesh most of the Hessians and factorizations go into the
//! Levenberg–Marquardt phase far from the minimum, and that phase grows with the mesh
//! (14399-vertex junction with the paper's steps and Cᵢ = 1, earlier sessions: 29
//! Hessians, 98.7 s from the raw mesh; 9 Hessians at that level, 35.8 s for the whole
//! cascade from 1007 vertices, same minimum. With the defaults, measured in the last
//! bench: raw start 7 Hessians, 24.3 s, cascade 5 Hessians at that level, 20.2 s in all;
//! 23997 five-tube vertices 15 Hessians, 105.3 s raw, 11 at that level, 83.3 s
//! coarse-to-fine). The refined optimum of the coarser level
//! already has the shape; the finer level only adds detail, which Newton's method resolves
//! in a few steps.
//!
//! The finer problem is exactly the one of its raw refined mesh: the fixed vertices (the
//! rings along the boundary) take the raw refinement's coordinates bit for bit; only the
//! free vertices start from the refined optimum.

use std::ops::ControlFlow;
use std::time::Instant;

use crate::error::{Error, Result};
use crate::fair::preparation::prepare::fixed_vertices;
use crate::fair::preparation::surface_refine::refine_surface;
use crate::fair::preparation::topology::MeshTopology;
use crate::fair::solvers::newton::Iteration;
use crate::fair::{optimize_observed, prepare_with_fixed, FairOptions, FairReport};
use crate::mesh::PolygonMesh;

/// One level of [`optimize_levels`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LevelReport {
    /// 0 for the input (after [`prepare`](crate::fair::prepare)), k after k surface refinements.
    pub level: u32,
    /// Wall-clock seconds of this level (refinement included).
    pub seconds: f64,
    pub report: FairReport,
}

/// What [`optimize_levels`] returns.
#[derive(Debug, Clone)]
pub struct CoarseToFine {
    /// The finest level's raw mesh: the input prepared and surface-refined `levels` times
    /// (the problem the last level solved; its fixed vertices are the optimized mesh's).
    pub raw: PolygonMesh,
    /// The finest level's optimized mesh (the topology and vertex order of `raw`).
    pub optimized: PolygonMesh,
    /// One report per level; the last is the finest.
    pub levels: Vec<LevelReport>,
}

/// [`optimize_levels`] with a callback after each Newton iteration: level, iteration and
/// the initial gradient norm of its stage (for progress display). `ControlFlow::Break`
/// stops the run after that iteration: the levels done so far are returned, the last one
/// with `newton.cancelled` set, and `raw`/`optimized` are that level's meshes.
///
/// # Errors
/// As [`optimize_observed`]; [`Error::InvalidInput`] for user-given fixed vertices with
/// `levels > 0` (their ids name input vertices, which refinement renumbers).
pub fn optimize_levels_observed(
    mesh: &PolygonMesh,
    levels: u32,
    options: &FairOptions,
    observe: &mut dyn FnMut(u32, &Iteration, f64) -> ControlFlow<()>,
) -> Result<CoarseToFine> {
    if levels > 0 && !options.fixed.is_empty() {
        return Err(Error::InvalidInput(
            "user-given fixed vertices cannot be carried through surface refinements \
             (their ids name input vertices); optimize the refined mesh directly with ids \
             of that mesh"
                .into(),
        ));
    }
    let clock = Instant::now();
    let (mut raw, refinements) = prepare_with_fixed(mesh, options)?;
    let level_options = FairOptions {
        max_refinements: 0,
        ..options.clone()
    };
    let (mut optimized, mut report) =
        optimize_observed(&raw, &level_options, &mut |it, g0| observe(0, it, g0))?;
    report.refinements = refinements;
    let mut reports = vec![LevelReport {
        level: 0,
        seconds: clock.elapsed().as_secs_f64(),
        report,
    }];
    for level in 1..=levels {
        if reports.last().is_some_and(|r| r.report.newton.cancelled) {
            break;
        }
        let clock = Instant::now();
        raw = refine_surface(&raw, 1)?;
        let start = refined_start(&raw, &refine_surface(&optimized, 1)?, options)?;
        let (out, report) =
            optimize_observed(&start, &level_options, &mut |it, g0| observe(level, it, g0))?;
        optimized = out;
        reports.push(LevelReport {
            level,
            seconds: clock.elapsed().as_secs_f64(),
            report,
        });
    }
    Ok(CoarseToFine {
        raw,
        optimized,
        levels: reports,
    })
}

/// Coarse-to-fine optimization: [`optimize`](crate::fair::optimize) on `mesh`, then
/// `levels` times: [`refine_surface`] and optimize again from the refined optimum. The
/// finest optimized mesh has the topology and vertex order of the finest raw mesh and its
/// fixed vertices bit for bit.
///
/// # Errors
/// As [`optimize_levels_observed`].
pub fn optimize_levels(
    mesh: &PolygonMesh,
    levels: u32,
    options: &FairOptions,
) -> Result<CoarseToFine> {
    optimize_levels_observed(mesh, levels, options, &mut |_, _, _| {
        ControlFlow::Continue(())
    })
}

/// The start of a finer level: the raw refinement's faces and fixed vertices, the free
/// vertices of the refined optimum.
fn refined_start(
    raw: &PolygonMesh,
    refined_optimum: &PolygonMesh,
    options: &FairOptions,
) -> Result<PolygonMesh> {
    debug_assert_eq!(raw.vertex_count(), refined_optimum.vertex_count());
    let topo = MeshTopology::new(raw)?;
    let fixed = fixed_vertices(&topo, options.boundary_rings, &[])?;
    let mut start = raw.clone();
    for (v, position) in start.positions.iter_mut().enumerate() {
        if !fixed[v] {
            *position = refined_optimum.positions[v];
        }
    }
    Ok(start)
}
