//! The surface representation (paper eq. 1, p = Σ pᵢ φᵢ) as the optimizer sees it: at each
//! quadrature point, the nine partial derivatives of orders 1–3 are fixed linear
//! combinations of the control vertices. The optimizer only needs these rows, so Kiciak's
//! own (9, 9) special elements (§3) can replace the B-spline end caps by implementing
//! [`Representation`] without touching the functional or the optimizer.

use std::sync::Arc;

use crate::error::{Error, Result};
use crate::fair::surface::quadrature::gauss_legendre;
use crate::fair::surface::shared_tables::SharedTables;
use crate::limits::MemoryBudget;
use crate::mesh::PolygonMesh;
use crate::subdiv::{cubic_basis, limit_surface, PatchOptions, PatchSurface, SubdivOptions};

/// Number of derivatives at a quadrature point, in the order
/// `p_u, p_v, p_uu, p_uv, p_vv, p_uuu, p_uuv, p_uvv, p_vvv`.
pub const DERIVATIVES: usize = 9;

/// (order in u, order in v) of each of the [`DERIVATIVES`], in their order.
pub const DERIVATIVE_ORDERS: [(usize, usize); DERIVATIVES] = [
    (1, 0),
    (0, 1),
    (2, 0),
    (1, 1),
    (0, 2),
    (3, 0),
    (2, 1),
    (1, 2),
    (0, 3),
];

/// One quadrature point: weights of the two terms of F (eq. 4) and the sparse rows of the
/// linear map from control vertices to the nine derivatives.
#[derive(Debug, Clone, PartialEq)]
pub struct QuadraturePoint {
    /// Quadrature weight × element area in the parameters, for S (eq. 3); 0 where S is not
    /// integrated.
    pub weight_s: f64,
    /// Quadrature weight × element area × Cᵢ, for Q (eq. 5).
    pub weight_q: f64,
    /// Control vertices with a nonzero coefficient, distinct, in the patch's own order
    /// rather than by id, so that patches of the same kind have the same coefficient
    /// table whatever the mesh's numbering; one list shared by a patch's points.
    pub vertices: Arc<[u32]>,
    /// `coefficients[k][d]`: coefficient of `vertices[k]` in derivative `d` (shared with
    /// the points whose table is the same, [`SharedTables`]).
    pub coefficients: Arc<[[f64; DERIVATIVES]]>,
}

/// Control vertices → per-quadrature-point derivatives as fixed linear maps.
pub trait Representation: Sync {
    /// Number of control vertices.
    fn vertex_count(&self) -> usize;
    /// The quadrature points of all elements.
    fn points(&self) -> &[QuadraturePoint];
    /// Number of elements |E| (for c = |E|² / D⁴, §4).
    fn element_count(&self) -> usize;
}

/// How the last-level end caps around extraordinary vertices enter S.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum EndCaps {
    /// End caps are left out of S (they remain in Q). The Catmull–Clark limit has unbounded
    /// or degenerate curvature at an extraordinary vertex, so ∇H there is no property of
    /// the shape; the B-spline end caps only approximate the limit, and they cover a
    /// neighbourhood whose parameter area is 4^(−isolation) of the faces around the vertex,
    /// which vanishes as the isolation level grows.
    #[default]
    ExcludeFromS,
    /// End caps are integrated in S like any other patch.
    Include,
}

/// In which parameters Q (eq. 5) is integrated over a face split into sub-patches around an
/// extraordinary vertex.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum QDomain {
    /// Every OpenSubdiv patch is an element E_i with its own domain [0, 1]² (eq. 5 sums
    /// over elements, each in its own parameters). Why: in the face's parameters ∇Δp of
    /// the Catmull–Clark limit grows without bound toward an extraordinary vertex and its
    /// square is not integrable there, so Q would grow with the isolation level (×5 per
    /// level by level 5 on the raw 359-vertex junction, `tests/fair/q_domain.rs`) and make the
    /// Hessian ever stiffer; in the sub-patch's own parameters a patch of size h weighs h⁴
    /// as much, and Q converges.
    /// S does not depend on the parameterization and is the same either way.
    #[default]
    Patch,
    /// The face's own (u, v) ∈ [0, 1]² for all its sub-patches.
    Face,
}

/// Default Cᵢ of the elements at special vertices (ordinary elements: 1).
///
/// The paper (§4) takes Cᵢ smaller there to lessen the regularization's effect on the
/// shape, and warns that too small a Cᵢ can hurt convergence. With this representation
/// Cᵢ = 1 was the value that hurt it: Q of the faces at a special vertex, in their
/// sub-patches' own parameters, is positive even where the sectors around the vertex are
/// planar affine grids, and its descent pulls their vertices toward the special vertex
/// (`tests/fair/special_elements.rs`). On the 23997-vertex five-tube junction (saddles of
/// valence 10) the optimizer followed that pull until patches two rings out nearly
/// folded (|p_u| 2.6·10⁻⁴ against edges of 10⁻², sin∠(p_u, p_v) 0.09, Hessian diagonal
/// 10²⁰ against 10¹¹ elsewhere) and stalled. From the raw mesh with Cᵢ = 0.25 it stopped
/// at the gradient's round-off floor (5·10⁻⁸ of its start) after 30 Hessians; with 0.1 /
/// 0.03 / 0.01 / 0.001 it converged in 21 / 16 / 15 / 14 Hessians to S = 581 / 568 /
/// 563 / 560. The faces at the special vertex stay held by the regular patches around
/// them, whose control nets contain the special vertex and its first ring.
pub const DEFAULT_C_SPECIAL: f64 = 0.01;

/// Which surface the control mesh stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SurfaceKind {
    /// Kiciak's curvature-continuous surface (paper §3): bicubic B-spline patches and, at
    /// each special vertex, k degree-(9, 9) patches ([`crate::fair::G2Representation`]).
    /// The default: it is the surface the paper optimizes (curvature continuous where the
    /// Catmull–Clark limit's curvature is unbounded at special vertices), and surfkit's S
    /// and F on it are the author's program's (`tests/fair/g2_surface.rs`).
    #[default]
    G2,
    /// The Catmull–Clark limit surface as OpenSubdiv's feature-adaptive patches with
    /// B-spline end caps ([`PatchRepresentation`]).
    #[serde(rename = "catmull-clark")]
    CatmullClark,
}

impl SurfaceKind {
    /// The name reports use.
    pub fn name(self) -> &'static str {
        match self {
            SurfaceKind::G2 => "g2",
            SurfaceKind::CatmullClark => "catmull-clark",
        }
    }
}

/// Default Cᵢ of special elements on the G² surface: the paper's Cᵢ = C (§4: "taking Cᵢ =
/// C = const works also for meshes with special elements"), as the author's program does.
pub const DEFAULT_C_SPECIAL_G2: f64 = 1.0;

/// Options of [`PatchRepresentation::new`] and [`crate::fair::G2Representation::new`].
#[derive(Debug, Clone, PartialEq)]
pub struct RepresentationOptions {
    /// The surface.
    pub surface: SurfaceKind,
    /// Gauss–Legendre nodes per direction per patch.
    pub nodes: usize,
    /// OpenSubdiv's feature-adaptive isolation level (Catmull–Clark surface).
    pub isolation: u32,
    /// Cᵢ of ordinary elements (eq. 5).
    pub c_ordinary: f64,
    /// Cᵢ of elements with a special vertex (§4: smaller values lessen the
    /// regularization's effect near special vertices). Default 0.01 for the Catmull–Clark
    /// surface ([`DEFAULT_C_SPECIAL`]); [`DEFAULT_C_SPECIAL_G2`] suits the G² surface.
    pub c_special: f64,
    pub end_caps: EndCaps,
    pub q_domain: QDomain,
    /// What the patch table may take; a representation that would need more at
    /// `isolation` is refused with [`Error::ResourceLimit`] (never silently coarsened: the
    /// functional depends on the level).
    pub memory: MemoryBudget,
}

impl RepresentationOptions {
    /// The defaults for the Catmull–Clark surface (Cᵢ of special elements
    /// [`DEFAULT_C_SPECIAL`]).
    pub fn catmull_clark() -> Self {
        RepresentationOptions {
            surface: SurfaceKind::CatmullClark,
            c_special: DEFAULT_C_SPECIAL,
            ..RepresentationOptions::default()
        }
    }
}

impl Default for RepresentationOptions {
    fn default() -> Self {
        RepresentationOptions {
            surface: SurfaceKind::default(),
            nodes: 4,
            isolation: 4,
            c_ordinary: 1.0,
            c_special: DEFAULT_C_SPECIAL_G2,
            end_caps: EndCaps::ExcludeFromS,
            q_domain: QDomain::Patch,
            memory: MemoryBudget::default(),
        }
    }
}

/// The Catmull–Clark limit surface as OpenSubdiv's bicubic B-spline patches (B-spline end
/// caps). Elements are the internal quads (all corners off the boundary): as in the paper,
/// only they carry the surface; boundary faces depend only on fixed vertices.
pub struct PatchRepresentation {
    vertex_count: usize,
    element_count: usize,
    points: Vec<QuadraturePoint>,
}

impl PatchRepresentation {
    /// Builds the quadrature rows of `mesh`'s limit surface.
    ///
    /// Derivatives are taken with respect to each patch's own (u, v) ∈ [0, 1]² (an
    /// ordinary face is the paper's unit-square element), or with [`QDomain::Face`] to the
    /// face's: a sub-patch of size h then contributes area h² and derivatives scaled by
    /// h^(−order).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for a bad option (nodes, isolation, Cᵢ ≤ 0) or a face
    /// that is not a quad; errors of [`limit_surface`].
    pub fn new(
        mesh: &PolygonMesh,
        boundary: &[bool],
        special: &[bool],
        options: &RepresentationOptions,
    ) -> Result<Self> {
        check_weights(options)?;
        check_quad_mesh(mesh, boundary, special)?;
        let rule = gauss_legendre(options.nodes)?;
        let surface: PatchSurface = limit_surface(
            mesh,
            &SubdivOptions::default(),
            &PatchOptions {
                max_isolation: options.isolation,
                memory: options.memory,
                ..PatchOptions::default()
            },
        )?;
        if surface.isolation() < options.isolation {
            return Err(Error::ResourceLimit {
                what: format!(
                    "the limit surface of {} vertices at isolation level {}",
                    mesh.vertex_count(),
                    options.isolation
                ),
                limit: options.memory.get(),
                advice: format!("--isolation {} fits", surface.isolation()),
            });
        }
        let internal: Vec<bool> = mesh
            .faces()
            .map(|f| f.iter().all(|&v| !boundary[v as usize]))
            .collect();
        let with_special: Vec<bool> = mesh
            .faces()
            .map(|f| f.iter().any(|&v| special[v as usize]))
            .collect();
        let element_count = internal.iter().filter(|&&b| b).count();
        let mut points = Vec::new();
        let tables = SharedTables::default();
        for (p, patch) in surface.patches().iter().enumerate() {
            let f = patch.base_face as usize;
            if !internal[f] {
                continue;
            }
            let rows = surface.patch_weights(p)?;
            let h = match options.q_domain {
                QDomain::Patch => 1.0,
                QDomain::Face => patch.size,
            };
            let c = if with_special[f] {
                options.c_special
            } else {
                options.c_ordinary
            };
            let in_s = patch.regular || options.end_caps == EndCaps::Include;
            push_bicubic_points(&mut points, &tables, &rows, &rule, h, in_s, c);
        }
        Ok(PatchRepresentation {
            vertex_count: mesh.vertex_count(),
            element_count,
            points,
        })
    }
}

/// Refuses Cᵢ that are not positive and finite (both representations).
pub(crate) fn check_weights(options: &RepresentationOptions) -> Result<()> {
    let c_ok = |c: f64| c.is_finite() && c > 0.0;
    if !c_ok(options.c_ordinary) || !c_ok(options.c_special) {
        return Err(Error::InvalidInput(format!(
            "Cᵢ must be positive and finite (ordinary {}, special {})",
            options.c_ordinary, options.c_special
        )));
    }
    Ok(())
}

/// Refuses flags of the wrong length and a face that is not a quad (both surfaces).
pub(crate) fn check_quad_mesh(
    mesh: &PolygonMesh,
    boundary: &[bool],
    special: &[bool],
) -> Result<()> {
    if boundary.len() != mesh.vertex_count() || special.len() != mesh.vertex_count() {
        return Err(Error::InvalidInput(
            "boundary and special flags must have one entry per vertex".into(),
        ));
    }
    if let Some(f) = mesh.faces().position(|f| f.len() != 4) {
        return Err(Error::InvalidInput(format!(
            "face {f} is not a quad; refine first (fair::prepare)"
        )));
    }
    Ok(())
}

/// Appends the quadrature points of one bicubic B-spline patch (its 16 control points'
/// vertex weights `rows`, row-major with u along a row) under `rule` per direction;
/// derivatives scaled to a domain of size `h` (see [`QDomain`]), S integrated if `in_s`, Q
/// weighted by `c`; coefficient tables shared through `tables`.
pub(crate) fn push_bicubic_points(
    points: &mut Vec<QuadraturePoint>,
    tables: &SharedTables,
    rows: &[Vec<(u32, f64)>; 16],
    rule: &[(f64, f64)],
    h: f64,
    in_s: bool,
    c: f64,
) {
    // Distinct, in the order of first appearance (see `QuadraturePoint::vertices`).
    let mut vertices: Vec<u32> = Vec::with_capacity(16);
    for &(v, _) in rows.iter().flatten() {
        if !vertices.contains(&v) {
            vertices.push(v);
        }
    }
    let vertices: Arc<[u32]> = vertices.into();
    let bases: Vec<[[f64; 4]; 4]> = rule.iter().map(|&(x, _)| cubic_basis(x)).collect();
    for (a, &(_, wu)) in rule.iter().enumerate() {
        for (b, &(_, wv)) in rule.iter().enumerate() {
            let (bu, bv) = (&bases[a], &bases[b]);
            let mut coefficients = vec![[0.0; DERIVATIVES]; vertices.len()];
            for (k, row) in rows.iter().enumerate() {
                let (i, j) = (k / 4, k % 4);
                let mut d = [0.0; DERIVATIVES];
                for (slot, &(ou, ov)) in DERIVATIVE_ORDERS.iter().enumerate() {
                    d[slot] = bu[ou][j] * bv[ov][i] * h.powi(-((ou + ov) as i32));
                }
                for &(v, w) in row {
                    let at = vertices.iter().position(|&u| u == v).unwrap_or(0);
                    for s in 0..DERIVATIVES {
                        coefficients[at][s] += w * d[s];
                    }
                }
            }
            let area = wu * wv * h * h;
            points.push(QuadraturePoint {
                weight_s: if in_s { area } else { 0.0 },
                weight_q: area * c,
                vertices: Arc::clone(&vertices),
                coefficients: tables.share(coefficients),
            });
        }
    }
}

impl Representation for PatchRepresentation {
    fn vertex_count(&self) -> usize {
        self.vertex_count
    }
    fn points(&self) -> &[QuadraturePoint] {
        &self.points
    }
    fn element_count(&self) -> usize {
        self.element_count
    }
}
