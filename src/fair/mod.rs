//! Shape optimization of Catmull–Clark surfaces (Kiciak, "Shape optimization of smooth
//! surfaces with arbitrary topology"): the free control vertices of a quad mesh are moved
//! to minimize F = S + c Q (eq. 4), S = ∫‖∇_M H‖² dM the unevenness of the mean curvature
//! and Q a regularization of the parameterization, by Newton's method with the exact
//! Hessian and Levenberg–Marquardt safeguards (§5).
//!
//! The folder's rooms: `surface/` (how the surface depends on the control vertices),
//! `functional/` (F and its derivatives), `solvers/` (its minimizers), `preparation/`
//! (what a mesh needs first), `generators/` (test shapes). The public API is re-exported
//! here:
//!
//! - [`tubes`]: the paper's junctions of tubes; [`refine_surface`]: the author's refinement
//!   (Catmull–Clark losing the boundary ring each level), which gives his sizes.
//! - [`prepare`]: refine until the paper's conditions hold (§2); χ checked.
//! - [`Representation`] / [`PatchRepresentation`]: control vertices → derivatives at
//!   quadrature points, from OpenSubdiv's B-spline patches (see [`EndCaps`] for how the
//!   end caps at extraordinary vertices enter S).
//! - [`Functional`]: F, its gradient and Hessian (automatic differentiation).
//! - [`optimize`]: the whole method on a mesh; topology and vertex order are kept.
//! - [`optimize_levels`]: coarse-to-fine, each level started from the refined optimum
//!   of the coarser one (§6).
//! - [`block_newton`]: the block method of §5 for large meshes (Voronoi blocks with
//!   overlaps, block iterations, global Newton by additive-Schwarz preconditioned CG),
//!   chosen by [`FairOptions::blocks`].

mod functional;
mod generators;
mod preparation;
mod solvers;
mod surface;

pub use functional::evaluation::{BlockHessian, Functional, HessianKind, Terms};
pub use functional::statistics::{shape_change, ShapeChange};
pub use generators::disc::sector_disc;
pub use generators::tubes::{tubes, MAX_TUBES};
pub use preparation::prepare::{fixed_vertices, prepare, MAX_FAIR_VALENCE};
pub use preparation::selection::{read_fixed, VCG_SELECTED};
pub use preparation::surface_refine::{drop_boundary_ring, refine_surface};
pub use preparation::topology::{condition_violation, MeshTopology};
pub use solvers::block_method::{block_newton, BlockOptions, BlockPhase, BlockReport};
pub use solvers::blocks::voronoi_blocks;
pub use solvers::cholesky::{Factor, Factorizer};
pub use solvers::coarse_correction::{CoarseCorrection, COARSE_CORRECTION_FREE_VERTICES};
pub use solvers::coordinate_floor::{coordinate_floor, ulp};
pub use solvers::levels::{optimize_levels, optimize_levels_observed, CoarseToFine, LevelReport};
pub use solvers::newton::{
    newton, newton_observed, newton_observed_with_hessians, HessianSources, Iteration, LmMatrix,
    LmSearch, NewtonOptions, NewtonReport, StepKind, FAR_MODEL_DECREASE, FLOOR_MARGIN,
    NEWTON_AFTER_DECREASE, SLOW_NEAR_RATE, SLOW_NEAR_STEPS,
};
pub use solvers::pcg::{multiply, pcg, pcg_operator, CgOutcome, CgStop};
pub use solvers::schwarz::Schwarz;
pub use surface::any_representation::SurfaceRepresentation;
pub use surface::curvature_map::{curvature_samples, surface_samples};
pub use surface::g2::basis::bernstein::{
    bernstein_derivatives, COEFFICIENTS as SPECIAL_PATCH_COEFFICIENTS,
};
pub use surface::g2::basis::disk_cache as g2_basis_cache;
pub use surface::g2::basis::division_curve::{bezier_derivatives, division_curve, Degree7};
pub use surface::g2::basis::domain_derivatives::InverseChainRule;
pub use surface::g2::basis::domain_net::{
    boundary_arcs, cubic_arc, subdominant_eigenvalue, DomainNet,
};
pub use surface::g2::basis::junction::{sector_domain, Junction, SectorDomain};
pub use surface::g2::basis::patch_matrix::{
    map_derivatives, patch_derivatives, PatchMatrix, MAX_SPECIAL_VALENCE,
};
pub use surface::g2::bezier_export::write_bezier_patches;
pub use surface::g2::representation::G2Representation;
pub use surface::g2::sabin_net::SabinNet;
pub use surface::g2::surface::{FacePatch, G2Surface};
pub use surface::quadrature::{gauss_legendre, MAX_NODES};
pub use surface::representation::{
    EndCaps, PatchRepresentation, QDomain, QuadraturePoint, Representation, RepresentationOptions,
    SurfaceKind, DEFAULT_C_SPECIAL, DEFAULT_C_SPECIAL_G2, DERIVATIVES,
};
pub use surface::sub_representation::SubRepresentation;

use std::ops::ControlFlow;

use crate::error::{Error, Result};
use crate::limits::{human_bytes, MemoryBudget};
use crate::linalg::norm;
use crate::mesh::PolygonMesh;
use solvers::multilevel::coarse_start::nested_start;
pub use solvers::multilevel::coarse_start::{CoarseStartReport, COARSE_TOLERANCE};
use solvers::multilevel::hierarchy::{hierarchy, Hierarchy, COARSEST_VERTICES};
use solvers::multilevel::solver::MultilevelSolver;
use solvers::newton::newton_with_solver;

/// The default C of F = S + C·c·Q, the author's. Measured on his three meshes
/// (kiciak_trojnik3/4/5, 359/1295/4895 vertices, 2026-11-26, README): with the paper's
/// C = 1 the regularization outweighs S — S *rises* from 3.9 to 37.0 and from 5.7 to 68.9
/// on the two finer (already smooth) meshes — while C = 0.01 lowers S on all three
/// (461.6 → 2.7, 3.9 → 2.4, 5.7 → 2.4) in as few Newton steps (≤ 10).
pub const DEFAULT_REGULARIZATION: f64 = 0.01;

/// Options of [`optimize`].
#[derive(Debug, Clone, PartialEq)]
pub struct FairOptions {
    pub representation: RepresentationOptions,
    pub newton: NewtonOptions,
    /// Vertices closer than this many edges to the boundary are fixed (§4: 3).
    pub boundary_rings: u32,
    /// User-given fixed vertices (soft constraints, §4).
    pub fixed: Vec<u32>,
    /// Most uniform refinements [`prepare`] may apply; 0 requires the input to meet the
    /// conditions already (then the output has the input's topology and vertex order).
    pub max_refinements: u32,
    /// Warm start: first minimize F with the end caps isolated at this (lower) level, to
    /// `warm_start_tolerance` relative gradient, then at the full level, hoping a coarse
    /// level does most of the work from a raw mesh with
    /// fewer quadrature points. `None` (default): one stage. Measured on the 1007-vertex
    /// three-tube junction with an earlier version of the optimizer, it did not pay:
    /// level 2 alone converged in 17 Hessians, but the level-4 stage from its result
    /// needed ~200 against 71 from the raw mesh, because the level-2 optimum excites
    /// exactly the components the deeper levels penalize.
    pub warm_start_isolation: Option<u32>,
    pub warm_start_tolerance: f64,
    /// The block method of §5 instead of Newton on all unknowns at once (for large
    /// meshes); `None` (default): the plain method.
    pub blocks: Option<BlockOptions>,
    /// C in F = S + C·c·Q: the paper's text has C = 1 (F = S + cQ, eq. 4); the author's
    /// test program runs with C = 0.01 (its parameter C), the default
    /// ([`DEFAULT_REGULARIZATION`] says why). Must be > 0: S alone does not fix the
    /// parameterization (its Hessian is singular along it).
    pub regularization: f64,
    /// Gauss–Legendre nodes per direction for the Newton Hessians, when fewer than
    /// `representation.nodes`: F and its gradient keep all the nodes (so does the
    /// minimum), each Hessian costs (h / nodes)² as much, and the steps are slightly
    /// inexact. The author's program does the same (Hessians at 6 × 6, F at 8 × 8).
    /// Default [`DEFAULT_HESSIAN_NODES`]; `None`: the Hessians use F's nodes.
    pub hessian_nodes: Option<usize>,
    /// Nodes per direction for the Hessians far from the minimum (from the start and after
    /// damped steps that still gain, [`FAR_MODEL_DECREASE`]), at most those of
    /// `hessian_nodes` ([`HessianSources::far`]). Default [`DEFAULT_FAR_HESSIAN_NODES`];
    /// `None`: those of `hessian_nodes`.
    pub far_hessian_nodes: Option<usize>,
    /// How Newton's steps are solved (plain or multilevel; by size when automatic).
    pub method: FairMethod,
    /// Which solves start from the optimum of the un-subdivided mesh, refined (nested
    /// iteration, `solvers::multilevel::coarse_start`). Never with user-given fixed
    /// vertices (their ids name fine vertices) or a warm start.
    pub coarse_start: CoarseStart,
}

/// When [`optimize`] starts from the refined optimum of the mesh its input un-subdivides to
/// (nested iteration, `solvers::multilevel::coarse_start`).
///
/// Not the default: it is faster where it was measured, but it may end in another local
/// minimum than the start from the input — lower on the five-tube junctions, higher on
/// the 56k three-tube one (`benches/fair_ceiling.py`, 2026-11-26: F 39.69 against the plain
/// method's 28.81, in 360 s against 463 s; 24k five-tube: 114.77 against 130.69 in 80.5 s
/// against 185.6 s; 14k three-tube: the same minimum in 53.1 s against 89.2 s).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CoarseStart {
    /// From the input, as the paper (the default).
    #[default]
    Never,
    /// The multilevel method starts from the coarse optimum; the plain method from the
    /// input.
    Multilevel,
    /// Both methods do: the coarse stages of a multilevel run, which are solved by the
    /// plain method when small.
    Always,
}

/// How [`optimize`] solves Newton's steps.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FairMethod {
    /// Multilevel when there are at least [`MULTILEVEL_FREE_VERTICES`] free vertices and
    /// the mesh is the refinement of a coarser one; plain otherwise.
    #[default]
    Automatic,
    /// A sparse Cholesky factor of every Hessian + νI (paper §5).
    Plain,
    /// Inexact Newton: conjugate gradients preconditioned by a multigrid V-cycle over the
    /// coarser control meshes (issue 18); needs a mesh that un-subdivides.
    Multilevel,
}

/// The size from which [`FairMethod::Automatic`] takes the multilevel method: the smallest
/// refined junction measured, where it was already faster. `benches/fair_ceiling.py`
/// (2026-11-27, raw junctions, both surfaces) has it ahead at 13 247, 22 077 and 54 143
/// free vertices, at the same minima (G²: 24.5 s against 31.0 s, 83.1 against 139.1,
/// 116.6 against 318.2); single runs of `surfkit fair` on the three-tube junction refined
/// once (3167 free, the same session): 5.4 s against 8.5 s (G²), 5.2 against 8.3
/// (Catmull–Clark), F the same to 10⁻¹². Below 2000 free vertices there is no coarser
/// level; between 2000 and 3000 nothing was measured.
pub const MULTILEVEL_FREE_VERTICES: usize = 3000;

/// Peak resident memory of a method: `base` + `per_free_vertex` · free vertices, the
/// representation included. Checked against the memory budget before the solver's
/// matrices are allocated, so that a problem too large gets an error, not the OOM killer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SolverMemory {
    pub base: u64,
    pub per_free_vertex: u64,
}

impl SolverMemory {
    /// The peak for `free` free vertices.
    pub fn bytes(self, free: usize) -> u64 {
        self.base
            .saturating_add((free as u64).saturating_mul(self.per_free_vertex))
    }
}

/// The plain method's peak: the line through its peaks at 13 247 and 54 143 free vertices
/// (1.06 and 3.57 GB, G² surface, `benches/fair_ceiling.py`, 2026-11-26: 61 KB per
/// vertex), rounded up (its Cholesky factor's fill grows a little faster than the mesh).
pub const PLAIN_MEMORY: SolverMemory = SolverMemory {
    base: 256 << 20,
    per_free_vertex: 64 << 10,
};

/// The multilevel method's peak (no fine factor: the Hessian, its Gauss–Newton part and
/// the level matrices): through 0.79 and 2.18 GB at the same sizes, 34 KB per vertex,
/// rounded up. The Newton steps' patch factors (computed: about 1 KB per free vertex) are
/// inside it: 3.76 GiB with them against 3.77 GiB without at the 223k Catmull–Clark
/// junction (2026-11-29).
pub const MULTILEVEL_MEMORY: SolverMemory = SolverMemory {
    base: 384 << 20,
    per_free_vertex: 40 << 10,
};

/// The multilevel method's peak when it falls back to a Cholesky factor of the fine matrix
/// where its V-cycle stagnates (see `solvers::multilevel::solver`): the factor on top of
/// the levels. Through the peaks of the five-tube junctions that needed it (1.63 GB at
/// 22 077 and 6.97 GB at 90 237 free vertices, G² surface, `surfkit fair --method
/// multilevel`, 2026-11-26: 78 KB per vertex), rounded up. The fallback is used only when
/// this fits the memory budget.
pub const MULTILEVEL_WITH_FACTOR_MEMORY: SolverMemory = SolverMemory {
    base: 256 << 20,
    per_free_vertex: 80 << 10,
};

impl Default for FairOptions {
    fn default() -> Self {
        FairOptions {
            representation: RepresentationOptions::default(),
            newton: NewtonOptions::default(),
            boundary_rings: 3,
            fixed: Vec::new(),
            max_refinements: 2,
            warm_start_isolation: None,
            warm_start_tolerance: 1e-4,
            blocks: None,
            regularization: DEFAULT_REGULARIZATION,
            hessian_nodes: Some(DEFAULT_HESSIAN_NODES),
            far_hessian_nodes: Some(DEFAULT_FAR_HESSIAN_NODES),
            method: FairMethod::Automatic,
            coarse_start: CoarseStart::Never,
        }
    }
}

impl FairOptions {
    /// The nodes per direction of the Hessians near and far from the minimum: the asked
    /// ones, at most F's, far at most near ([`Self::hessian_nodes`],
    /// [`Self::far_hessian_nodes`]).
    pub fn hessian_node_counts(&self) -> (usize, usize) {
        let nodes = self.representation.nodes;
        let near = self.hessian_nodes.unwrap_or(nodes).min(nodes);
        let far = self.far_hessian_nodes.unwrap_or(nodes).min(near);
        (near, far)
    }

    /// The representations of `mesh` the Hessians come from where they take fewer nodes
    /// ([`Self::hessian_node_counts`]) than `rep`, F's own: near and far, each `None`
    /// where the next finer one serves (F's for near, near's for far). Built by
    /// [`SurfaceRepresentation::with_options`], so the G² surface is not built again.
    ///
    /// # Errors
    /// As [`SurfaceRepresentation::with_options`].
    pub fn hessian_representations(
        &self,
        rep: &SurfaceRepresentation,
        mesh: &PolygonMesh,
        boundary: &[bool],
        special: &[bool],
    ) -> Result<(Option<SurfaceRepresentation>, Option<SurfaceRepresentation>)> {
        let nodes = self.representation.nodes;
        let (near_nodes, far_nodes) = self.hessian_node_counts();
        let at = |n: usize, coarser_than: usize| -> Result<Option<SurfaceRepresentation>> {
            (n < coarser_than)
                .then(|| {
                    let options = RepresentationOptions {
                        nodes: n,
                        ..self.representation.clone()
                    };
                    rep.with_options(mesh, boundary, special, &options)
                })
                .transpose()
        };
        Ok((at(near_nodes, nodes)?, at(far_nodes, near_nodes)?))
    }
}

/// Most Gauss–Legendre nodes per direction for the Newton Hessians (F keeps its own): on
/// the author's three meshes at F's 8 × 8 (G² surface, C = 0.01, 2026-11-26) Hessians at
/// 4 × 4 took the same Newton iterations as at 8 × 8 (10 and 10, 7 and 6, 10 and 12) to
/// the same minimum, each at a quarter of the cost. At F's default 4 × 4, 3 × 3 (9/16 of a
/// pass) took the same steps to the same F on the three-tube Catmull–Clark junctions
/// (2026-12-07, single runs of `surfkit fair --method multilevel`): 14 399 vertices 9.98 and
/// 10.15 s against 11.11 and 11.05 s, 223 487 vertices 443.2 s against 505.7 s (the day's
/// previous session); the 94 077-vertex five-tube one 243.6 s against 286.7 s (the same
/// previous session); G² 14 399 vertices 11.33 and
/// 12.12 s against 12.56 and 13.57 s, but 223 487 level (429.9 s against 434.6 s, one more
/// Newton step); the author's meshes in as many iterations or fewer, both surfaces. Where
/// the fewer nodes slow the Newton tail (the 53-vertex junction), [`SLOW_NEAR_STEPS`]
/// raises them to F's.
pub const DEFAULT_HESSIAN_NODES: usize = 3;

/// Most nodes per direction for the Hessians far from the minimum
/// ([`HessianSources::far`]): at F's default 4 × 4, Hessians at 3 × 3 throughout took as
/// many Hessians to the same F on raw tube junctions (2026-11-27: 14 399 vertices, plain,
/// 9 and 9, 41.4 s against 56.2 s; 94 077 vertices, multilevel, 21 against the 23 of an
/// earlier session's run with 4-node Hessians), each at
/// 9/16 of the cost — but slowed Newton's last steps on a small Catmull–Clark junction
/// (now the near Hessians' concern, [`SLOW_NEAR_STEPS`]). Far from the minimum 2 × 2 (4/9
/// of a 3 × 3 pass) serves as well
/// while the damped steps gain, and [`FAR_MODEL_DECREASE`] hands the Newton trials the
/// near model once they do not (single runs of `surfkit fair`, 2026-11-29, against 3 × 3
/// the same evening, the same F every time): the 223 487-vertex Catmull–Clark junction,
/// multilevel, 381.8 s against 498.7 s (Hessian passes 128.1 s against 188.4 s); its
/// 14 399-vertex one in three vertex numberings 9.7, 6.9 and 12.3 s against 11.0, 11.2 and
/// 17.7 s, plain 17.4 s against 18.6 s; on the G² surface 43.0 s against 51.3 s at 56 447
/// vertices (plain at 14 399: 16.9 s against 18.1 s). Not faster everywhere: the 14 399-vertex
/// G² junction took 10.47 s against 10.26 s (15 steps against 12), the 94 077-vertex
/// five-tube Catmull–Clark one 227.1 s against 215.8 s (32 steps against 25, runs an hour
/// and a half apart), the same F.
pub const DEFAULT_FAR_HESSIAN_NODES: usize = 2;

/// What [`optimize`] did.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct FairReport {
    /// The surface that was optimized.
    pub surface: SurfaceKind,
    /// Uniform refinements applied by [`prepare`] (0: same topology as the input).
    pub refinements: u32,
    pub vertices: usize,
    pub free_vertices: usize,
    pub elements: usize,
    /// c of eq. 4 (|E|²/D⁴).
    pub c: f64,
    /// C: Q's weight in F is C·c ([`FairOptions::regularization`]).
    pub regularization: f64,
    /// F, S, Q and ‖∇F̃‖ at the input (full isolation level).
    pub initial_terms: Terms,
    pub initial_gradient_norm: f64,
    /// The warm-start stage, if any.
    pub warm_start: Option<NewtonReport>,
    /// The global steps (the block method: its final-phase steps).
    pub newton: NewtonReport,
    /// What the block method did, when it was chosen.
    pub blocks: Option<BlockReport>,
    /// The method that solved Newton's steps: `plain` or `multilevel` (`plain` also for
    /// the block method's global phase).
    pub method: FairMethod,
    /// The multilevel method's unknown vertices per level, finest first (empty for plain).
    pub multilevel_sizes: Vec<usize>,
    /// The multilevel method's coarse stage (nested iteration), when it ran.
    pub coarse_start: Option<CoarseStartReport>,
    pub final_terms: Terms,
    pub final_gradient_norm: f64,
    /// S and the spread of H at the prepared input and at the optimum, on the optimizer's
    /// own quadrature ([`shape_change`] computes the same for any pair of meshes).
    pub change: ShapeChange,
}

/// c = |E|² / D⁴ (§4), D the diameter of the surface boundary, taken as that of the
/// boundary control vertices (`held`), or of the fixed vertices for a closed mesh.
fn scale_constant(mesh: &PolygonMesh, held: &[bool], elements: usize) -> Result<f64> {
    let pts: Vec<[f64; 3]> = (0..mesh.vertex_count())
        .filter(|&v| held[v])
        .map(|v| mesh.positions[v])
        .collect();
    let mut d2: f64 = 0.0;
    for (i, a) in pts.iter().enumerate() {
        for b in &pts[i + 1..] {
            d2 = d2.max((0..3).map(|k| (a[k] - b[k]).powi(2)).sum());
        }
    }
    if d2.is_nan() || d2 <= 0.0 || elements == 0 {
        return Err(Error::InvalidInput(format!(
            "c = |E|²/D⁴ is undefined: {elements} elements, boundary diameter {}",
            d2.sqrt()
        )));
    }
    Ok((elements as f64).powi(2) / (d2 * d2))
}

/// [`prepare`] under `options`, refusing user-given fixed ids when it had to refine (they
/// name input vertices, which refinement renumbers).
fn prepare_with_fixed(mesh: &PolygonMesh, options: &FairOptions) -> Result<(PolygonMesh, u32)> {
    let (prepared, refinements) = prepare(
        mesh,
        options.max_refinements,
        options.representation.surface,
    )?;
    if refinements > 0 && !options.fixed.is_empty() {
        return Err(Error::InvalidInput(
            "user-given fixed vertices refer to the input's ids, but the mesh needs \
             refinement first; refine it (fair::prepare) and give ids of the refined mesh"
                .into(),
        ));
    }
    Ok((prepared, refinements))
}

/// Optimizes the shape of `mesh`'s Catmull–Clark surface (the whole method of the paper).
///
/// The mesh is first refined by [`prepare`] if needed (at most
/// `options.max_refinements` levels); fixed vertices (§4) keep their coordinates bit for
/// bit; the returned mesh has the (prepared) mesh's faces and vertex order.
///
/// # Errors
/// [`Error::InvalidInput`] for an invalid mesh or options, or a closed mesh with nothing
/// fixed; [`Error::Topology`] for a non-manifold mesh or one refinement cannot prepare;
/// [`Error::Solver`] when F is not finite at the start; errors of OpenSubdiv. A run that
/// stops early says why in [`NewtonReport`] (`stalled`, `stuck`).
pub fn optimize(mesh: &PolygonMesh, options: &FairOptions) -> Result<(PolygonMesh, FairReport)> {
    optimize_observed(mesh, options, &mut |_, _| ControlFlow::Continue(()))
}

/// [`optimize`], calling `observe` after each Newton iteration (warm-start stage
/// included) with the iteration and the initial gradient norm of its stage, for progress
/// display. When `observe` returns `ControlFlow::Break`, the run stops there and returns
/// the positions reached, with `newton.cancelled` set (a cancelled warm start skips the
/// main stage).
///
/// # Errors
/// As [`optimize`].
pub fn optimize_observed(
    mesh: &PolygonMesh,
    options: &FairOptions,
    observe: &mut dyn FnMut(&Iteration, f64) -> ControlFlow<()>,
) -> Result<(PolygonMesh, FairReport)> {
    if !(options.regularization > 0.0 && options.regularization.is_finite()) {
        return Err(Error::InvalidInput(format!(
            "regularization C = {} must be a finite number > 0 (F = S + C·c·Q)",
            options.regularization
        )));
    }
    let after_decrease = options.newton.newton_after_decrease;
    if !(0.0..=1.0).contains(&after_decrease) {
        return Err(Error::InvalidInput(format!(
            "newton_after_decrease {after_decrease} must lie in [0, 1] (a fraction of F)"
        )));
    }
    let (prepared, refinements) = prepare_with_fixed(mesh, options)?;
    let topo = MeshTopology::new(&prepared)?;
    let fixed = fixed_vertices(&topo, options.boundary_rings, &options.fixed)?;
    let special = topo.special_flags();
    let rep =
        SurfaceRepresentation::new(&prepared, &topo.boundary, &special, &options.representation)?;
    let held = if topo.boundary.iter().any(|&b| b) {
        &topo.boundary
    } else {
        &fixed
    };
    let c = scale_constant(&prepared, held, rep.element_count())?;
    let weight = options.regularization * c;
    let functional = Functional::new(&rep, &fixed, weight);
    let mut positions = prepared.positions.clone();
    let (initial_terms, initial_gradient) = functional.gradient(&positions);
    let warm_start = match options.warm_start_isolation {
        Some(level)
            if level < options.representation.isolation
                && options.representation.surface == SurfaceKind::CatmullClark =>
        {
            let coarse = PatchRepresentation::new(
                &prepared,
                &topo.boundary,
                &special,
                &RepresentationOptions {
                    isolation: level,
                    ..options.representation.clone()
                },
            )?;
            let newton_options = NewtonOptions {
                relative_gradient: options.warm_start_tolerance,
                ..options.newton.clone()
            };
            let coarse_functional = Functional::new(&coarse, &fixed, weight);
            let g0 = norm(&coarse_functional.gradient(&positions).1);
            Some(newton_observed(
                &coarse_functional,
                &mut positions,
                &newton_options,
                &mut |it| observe(it, g0),
            )?)
        }
        _ => None,
    };
    // The warm start moved the mesh; without one the start is the input.
    let (start_terms, g0) = match &warm_start {
        Some(_) => {
            let (terms, gradient) = functional.gradient(&positions);
            (terms, norm(&gradient))
        }
        None => (initial_terms, norm(&initial_gradient)),
    };
    let mut multilevel_sizes = Vec::new();
    let mut coarse_stage = None;
    let (report, blocks) = match &options.blocks {
        _ if warm_start.as_ref().is_some_and(|w| w.cancelled) => (
            NewtonReport {
                converged: false,
                cancelled: true,
                ..NewtonReport::new(start_terms, g0)
            },
            None,
        ),
        None => {
            // The representations of fewer nodes the Hessians come from (HessianSources).
            let (near_rep, far_rep) =
                options.hessian_representations(&rep, &prepared, &topo.boundary, &special)?;
            let near = near_rep
                .as_ref()
                .map(|r| Functional::new(r, &fixed, weight));
            let far = far_rep.as_ref().map(|r| Functional::new(r, &fixed, weight));
            let near = near.as_ref().unwrap_or(&functional);
            let sources = HessianSources {
                near,
                far: far.as_ref().unwrap_or(near),
            };
            let levels = multilevel_hierarchy(&prepared, &functional, options.method)?;
            check_solver_memory(
                functional.free_count(),
                levels.is_some(),
                options.representation.memory,
            )?;
            let nested = match options.coarse_start {
                CoarseStart::Never => false,
                CoarseStart::Multilevel => levels.is_some(),
                CoarseStart::Always => true,
            } && options.fixed.is_empty()
                && warm_start.is_none()
                && functional.free_count() > COARSEST_VERTICES;
            let mut newton_options = options.newton.clone();
            newton_options.coarse_correction = newton_options
                .coarse_correction
                .for_surface(options.representation.surface);
            if nested {
                coarse_stage = nested_start(
                    &prepared,
                    &functional,
                    options,
                    &mut positions,
                    (start_terms.f, g0),
                    &mut newton_options,
                    &mut *observe,
                )?;
            }
            if let Some(levels) = &levels {
                multilevel_sizes = levels.sizes();
            }
            let report = match levels {
                _ if coarse_stage
                    .as_ref()
                    .is_some_and(|s| s.report.newton.cancelled) =>
                {
                    NewtonReport {
                        converged: false,
                        cancelled: true,
                        ..NewtonReport::new(start_terms, g0)
                    }
                }
                Some(levels) => newton_with_solver(
                    &functional,
                    sources,
                    &mut positions,
                    &newton_options,
                    MultilevelSolver::new(
                        levels,
                        MULTILEVEL_WITH_FACTOR_MEMORY.bytes(functional.free_count())
                            <= options.representation.memory.get(),
                    ),
                    &mut |it| observe(it, g0),
                )?,
                None => newton_observed_with_hessians(
                    &functional,
                    sources,
                    &mut positions,
                    &newton_options,
                    &mut |it| observe(it, g0),
                )?,
            };
            (report, None)
        }
        Some(block_options) => {
            let (report, blocks) = block_newton(
                &rep,
                &topo,
                &fixed,
                weight,
                &mut positions,
                &options.newton,
                block_options,
                &mut |it| observe(it, g0),
            )?;
            (report, Some(blocks))
        }
    };
    let (final_terms, g) = functional.gradient(&positions);
    let change = ShapeChange::with_s(
        &functional,
        &prepared.positions,
        &positions,
        [initial_terms.s, final_terms.s],
    );
    let mut out = prepared.clone();
    out.positions = positions;
    Ok((
        out,
        FairReport {
            surface: options.representation.surface,
            refinements,
            vertices: prepared.vertex_count(),
            free_vertices: functional.free_count(),
            elements: rep.element_count(),
            c,
            regularization: options.regularization,
            initial_terms,
            initial_gradient_norm: norm(&initial_gradient),
            warm_start,
            newton: report,
            blocks,
            method: if multilevel_sizes.is_empty() {
                FairMethod::Plain
            } else {
                FairMethod::Multilevel
            },
            multilevel_sizes,
            coarse_start: coarse_stage,
            final_terms,
            final_gradient_norm: norm(&g),
            change,
        },
    ))
}

/// The multilevel method's levels if `method` asks for it (or, automatically, when the
/// problem is large enough), `None` for the plain method.
///
/// # Errors
/// [`Error::InvalidInput`] when the multilevel method is asked for and the mesh is not the
/// Catmull–Clark refinement of a coarser mesh, or too small to have a coarser level.
fn multilevel_hierarchy<R: Representation>(
    mesh: &PolygonMesh,
    functional: &Functional<'_, R>,
    method: FairMethod,
) -> Result<Option<Hierarchy>> {
    let free = functional.free_count();
    if method == FairMethod::Plain
        || (method == FairMethod::Automatic && free < MULTILEVEL_FREE_VERTICES)
    {
        return Ok(None);
    }
    let levels = hierarchy(mesh, functional.free_index(), free);
    match (levels.prolongations.is_empty(), method) {
        (false, _) => Ok(Some(levels)),
        (true, FairMethod::Multilevel) => Err(Error::InvalidInput(format!(
            "the multilevel method needs a coarser level: the mesh ({} vertices, {free} free) \
             is not the Catmull–Clark refinement of a coarser mesh, or has at most {} free \
             vertices; use the plain method",
            mesh.vertex_count(),
            COARSEST_VERTICES
        ))),
        (true, _) => Ok(None),
    }
}

/// Refuses a problem whose solver would pass `budget` ([`PLAIN_MEMORY`],
/// [`MULTILEVEL_MEMORY`]), naming what would fit.
fn check_solver_memory(free: usize, multilevel: bool, budget: MemoryBudget) -> Result<()> {
    let (method, memory) = if multilevel {
        ("multilevel", MULTILEVEL_MEMORY)
    } else {
        ("plain", PLAIN_MEMORY)
    };
    let need = memory.bytes(free);
    if need <= budget.get() {
        return Ok(());
    }
    let fits = budget.get().saturating_sub(memory.base) / memory.per_free_vertex;
    let mut advice = format!(
        "the {method} method takes about {} + {} per free vertex: {fits} free vertices fit",
        human_bytes(memory.base),
        human_bytes(memory.per_free_vertex),
    );
    if !multilevel && MULTILEVEL_MEMORY.bytes(free) <= budget.get() {
        advice.push_str("; the multilevel method (--method multilevel, for a refined mesh) fits");
    }
    Err(Error::ResourceLimit {
        what: format!("fairing {free} free vertices (about {})", human_bytes(need)),
        limit: budget.get(),
        advice,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hessians_take_at_most_fs_nodes_and_far_at_most_near() {
        let with = |nodes, near, far| FairOptions {
            representation: RepresentationOptions {
                nodes,
                ..RepresentationOptions::default()
            },
            hessian_nodes: near,
            far_hessian_nodes: far,
            ..FairOptions::default()
        };
        assert_eq!(with(8, Some(4), Some(2)).hessian_node_counts(), (4, 2));
        assert_eq!(with(3, Some(4), Some(2)).hessian_node_counts(), (3, 2));
        assert_eq!(with(8, Some(4), Some(6)).hessian_node_counts(), (4, 4));
        assert_eq!(with(8, None, None).hessian_node_counts(), (8, 8));
        assert_eq!(with(8, Some(5), None).hessian_node_counts(), (5, 5));
    }

    #[test]
    fn the_hessians_representations_are_built_only_below_the_finer_ones_nodes() {
        use crate::fair::surface::representation::Representation;
        let mesh = tubes(3, 1, 3).expect("a junction");
        let topo = MeshTopology::new(&mesh).expect("a topology");
        let special = topo.special_flags();
        let with = |near, far| FairOptions {
            representation: RepresentationOptions::catmull_clark(),
            hessian_nodes: near,
            far_hessian_nodes: far,
            ..FairOptions::default()
        };
        let options = with(None, None);
        let nodes = options.representation.nodes;
        let f =
            SurfaceRepresentation::new(&mesh, &topo.boundary, &special, &options.representation)
                .expect("F's representation");
        // Points per element: nodes² on a regular element, so the ratio of two
        // representations' points is (n₁ / n₀)².
        let points = |r: &SurfaceRepresentation| r.points().len() as f64;
        let build = |o: &FairOptions| {
            o.hessian_representations(&f, &mesh, &topo.boundary, &special)
                .expect("built")
        };
        let (near, far) = build(&with(Some(nodes), Some(nodes)));
        assert!(near.is_none() && far.is_none());
        let (near, far) = build(&with(Some(nodes), Some(2)));
        assert!(near.is_none());
        let far = far.expect("far below near");
        let ratio = (2.0 / nodes as f64).powi(2);
        assert!((points(&far) / points(&f) - ratio).abs() < 1e-12);
        let (near, far) = build(&with(Some(3), Some(3)));
        let near = near.expect("near below F's");
        assert!(far.is_none());
        let ratio = (3.0 / nodes as f64).powi(2);
        assert!((points(&near) / points(&f) - ratio).abs() < 1e-12);
    }

    #[test]
    fn the_solver_memory_check_names_what_fits() {
        let budget = MemoryBudget::bytes(8 << 30);
        // 150 000 free vertices: about 9.4 GiB plain, 6.1 GiB multilevel.
        assert!(check_solver_memory(150_000, true, budget).is_ok());
        let err = check_solver_memory(150_000, false, budget)
            .unwrap_err()
            .to_string();
        assert!(err.contains("fairing 150000 free vertices"), "{err}");
        assert!(err.contains("memory limit of 8.0 GiB"), "{err}");
        // (8 GiB − 256 MiB) / 64 KiB.
        assert!(err.contains("126976 free vertices fit"), "{err}");
        assert!(err.contains("--method multilevel"), "{err}");
        let err = check_solver_memory(250_000, true, budget)
            .unwrap_err()
            .to_string();
        assert!(!err.contains("--method multilevel"), "{err}");
    }
}
