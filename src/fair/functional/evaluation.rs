//! The functional F(p) = S(p) + c Q(p) (paper eq. 4) with S = ∫‖∇_M H‖² dM (eq. 2, computed
//! by eq. 3) and Q = Σ Cᵢ ∫‖P ∇Δp‖²_F (eq. 5), its gradient and its exact Hessian with
//! respect to the free control-vertex coordinates (eq. 6).
//!
//! At each quadrature point the integrand is a function of the 27 coordinates of the nine
//! derivatives; its gradient comes by reverse accumulation and its Hessian as the tangents
//! of that gradient (forward-over-reverse, [`crate::fair::tangent`]), chained through the
//! point's fixed linear map from control vertices (see [`crate::fair::representation`]).
//! The quadrature points of one patch share their control vertices: their contributions
//! are summed in a dense patch matrix before they are scattered into the sparse Hessian,
//! and patches are spread over the cores (rayon) in eight fixed shares, each summing into
//! the blocks its patches touch ([`Share`]), gathered in a fixed order: every run gives
//! the same bits.
//!
//! Both densities are sums of squares of residuals (S: √W L⁻¹∇Hᵀ, Q: P ∇Δp); the
//! Gauss–Newton part 2 Σ JᵀJ of the Hessian, positive semidefinite everywhere, comes from
//! the residuals' tangents, alone or with the exact Hessian in the same pass.

use std::ops::Range;

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par};
use foldhash::{HashMap, HashMapExt};
use num_dual::Dual2_64;
use rayon::prelude::*;

use crate::fair::functional::q_density::{
    q_density, q_density_gradient, q_residual, q_residual_transpose_product,
};
use crate::fair::functional::s_density::{
    mean_curvature, s_density, s_density_gradient, s_density_gradient_residual, s_residual,
    s_residual_transpose_product,
};
use crate::fair::functional::tangent::{cross, dot, Tangent};
use crate::fair::surface::representation::{QuadraturePoint, Representation, DERIVATIVES};

const VARS: usize = 3 * DERIVATIVES;

/// The two terms of F (eq. 4) and their sum.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct Terms {
    /// S (eq. 2–3).
    pub s: f64,
    /// Q (eq. 5), without the factor c.
    pub q: f64,
    /// F = S + c Q.
    pub f: f64,
}

/// Number of variables of Q's density: p_u, p_v, ∂Δp/∂u, ∂Δp/∂v.
const Q_VARS: usize = 12;

/// The derivatives (of the nine) each of Q's four vector variables sums.
const Q_MAP: [&[usize]; 4] = [&[0], &[1], &[5, 7], &[6, 8]];

/// Q's variables `[p_u, p_v, ∂Δp/∂u, ∂Δp/∂v]` from the nine derivatives.
fn q_vars(d: &[[f64; 3]; DERIVATIVES]) -> [[f64; 3]; 4] {
    std::array::from_fn(|i| std::array::from_fn(|a| Q_MAP[i].iter().map(|&k| d[k][a]).sum()))
}

/// Densities of S and Q at a point with derivatives `d`.
fn densities(d: &[[f64; 3]; DERIVATIVES]) -> (f64, f64) {
    (s_density(d), q_density(&q_vars(d)))
}

/// Densities of S and Q at a point and the gradient of `ws · S-density + wq · Q-density`
/// with respect to the 27 derivative coordinates.
fn point_gradient(x: &[f64; VARS], ws: f64, wq: f64) -> (f64, f64, [f64; VARS]) {
    let d = unpack(x);
    let (s, gs) = s_density_gradient(&d);
    let (q, gq) = q_density_gradient(&q_vars(&d));
    let mut g = [0.0; VARS];
    for (i, gi) in g.iter_mut().enumerate() {
        *gi = ws * gs[i / 3][i % 3];
    }
    for (i, di) in Q_MAP.iter().enumerate() {
        for &d in *di {
            for a in 0..3 {
                g[3 * d + a] += wq * gq[i][a];
            }
        }
    }
    (s, q, g)
}

/// The 27 × 27 Hessian of one point's weighted density.
type PointMatrix = [[f64; VARS]; VARS];

/// [`point_hessian`] compiled for the widest SIMD instructions the CPU has (pulp's
/// runtime dispatch; the densities are inlined into it), so the same binary runs
/// everywhere and uses AVX2/AVX-512 where present.
struct PointHessian<'a> {
    x: &'a [f64; VARS],
    ws: f64,
    wq: f64,
    h: &'a mut PointMatrix,
    rows: Option<&'a mut ResidualRows>,
}

impl pulp::WithSimd for PointHessian<'_> {
    type Output = (f64, f64, [f64; VARS]);
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> Self::Output {
        point_hessian(self.x, self.ws, self.wq, self.h, self.rows)
    }
}

/// [`point_gauss_newton`] compiled as [`PointHessian`].
struct PointGaussNewton<'a> {
    x: &'a [f64; VARS],
    ws: f64,
    wq: f64,
    rows: &'a mut ResidualRows,
}

impl pulp::WithSimd for PointGaussNewton<'_> {
    type Output = (f64, f64, [f64; VARS]);
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> Self::Output {
        point_gauss_newton(self.x, self.ws, self.wq, self.rows)
    }
}

/// [`point_residual_curvature`] compiled as [`PointHessian`].
struct PointResidualCurvature<'a> {
    x: &'a [f64; VARS],
    xv: &'a [f64; VARS],
    ws: f64,
    wq: f64,
}

impl pulp::WithSimd for PointResidualCurvature<'_> {
    type Output = [f64; VARS];
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> Self::Output {
        point_residual_curvature(self.x, self.xv, self.ws, self.wq)
    }
}

/// Which second derivatives [`Functional::hessians`] assembles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HessianKind {
    /// F's exact Hessian (eq. 7).
    Exact,
    /// The Gauss–Newton part 2 Σ JᵀJ of the densities written as sums of squares
    /// (`s_density::s_residual`, `q_density::q_residual`): positive semidefinite everywhere.
    GaussNewton,
    /// Both, from the same tangents (6237 vertices, run totals of an earlier session:
    /// ≈ 0.76 s a pass against ≈ 0.65 s for the exact Hessian alone).
    Both,
}

impl HessianKind {
    /// Whether the exact Hessian is assembled.
    fn exact(self) -> bool {
        self != HessianKind::GaussNewton
    }

    /// Whether the Gauss–Newton part is assembled.
    fn gauss_newton(self) -> bool {
        self != HessianKind::Exact
    }
}

/// Rows of the Gauss–Newton factor of one point: its Hessian part is `Σ rowᵀ row`.
const RESIDUALS: usize = 8;
type ResidualRows = [[f64; VARS]; RESIDUALS];

/// Q's 12 variables as sums of the 27 derivative coordinates ([`Q_MAP`] per coordinate).
const Q_COORDINATES: [&[usize]; Q_VARS] = [
    &[0],
    &[1],
    &[2],
    &[3],
    &[4],
    &[5],
    &[15, 21],
    &[16, 22],
    &[17, 23],
    &[18, 24],
    &[19, 25],
    &[20, 26],
];

/// The derivative coordinates 0..27, for [`set_residual_rows`] over all of them.
const IDENTITY: [usize; VARS] = {
    let mut a = [0; VARS];
    let mut i = 0;
    while i < VARS {
        a[i] = i;
        i += 1;
    }
    a
};

/// `rows[k]` = √(2w) ∇r_k in the 27 derivative coordinates, for residuals `r` over `N`
/// variables, variable i being the sum of the coordinates `coordinates(i)`.
#[inline(always)]
fn set_residual_rows<const N: usize>(
    rows: &mut [[f64; VARS]],
    r: &[Tangent<N>],
    w: f64,
    coordinates: impl Fn(usize) -> &'static [usize],
) {
    let scale = (2.0 * w).sqrt();
    for (row, r) in rows.iter_mut().zip(r) {
        for (i, e) in r.eps.iter().enumerate() {
            for &c in coordinates(i) {
                row[c] = scale * e;
            }
        }
    }
}

/// Rows 0–1 of `rows`: S's residuals ([`s_residual`]) over the 27 coordinates.
#[inline(always)]
fn set_s_rows(rows: &mut ResidualRows, r: &[Tangent<VARS>; 2], ws: f64) {
    set_residual_rows(&mut rows[..2], r, ws, |i| {
        std::slice::from_ref(&IDENTITY[i])
    });
}

/// Rows 2–7 of `rows`: Q's residuals ([`q_residual`]) over its 12 variables, mapped.
#[inline(always)]
fn set_q_rows(rows: &mut ResidualRows, r: &[Tangent<Q_VARS>; 6], wq: f64) {
    set_residual_rows(&mut rows[2..], r, wq, |i| Q_COORDINATES[i]);
}

/// The 27 derivative coordinates as forward-mode variables.
#[inline(always)]
fn s_tangents(x: &[f64; VARS]) -> [[Tangent<VARS>; 3]; DERIVATIVES] {
    std::array::from_fn(|k| std::array::from_fn(|a| Tangent::variable(x[3 * k + a], 3 * k + a)))
}

/// Q's 12 variables ([`q_vars`]) as forward-mode variables.
#[inline(always)]
fn q_tangents(d: &[[f64; 3]; DERIVATIVES]) -> [[Tangent<Q_VARS>; 3]; 4] {
    let qx = q_vars(d);
    std::array::from_fn(|i| std::array::from_fn(|a| Tangent::variable(qx[i][a], 3 * i + a)))
}

/// One point's part of [`Functional::residual_curvature`] over its 27 derivative
/// coordinates `x`, moving along `xv`: 2 w Jᵀ r_vv for S's residuals (weight `ws`) and
/// Q's (`wq`).
#[inline(always)]
fn point_residual_curvature(x: &[f64; VARS], xv: &[f64; VARS], ws: f64, wq: f64) -> [f64; VARS] {
    let mut out = [0.0; VARS];
    let d = unpack(x);
    let dv = unpack(xv);
    if ws != 0.0 {
        let jets: [[Dual2_64; 3]; DERIVATIVES] =
            std::array::from_fn(|k| std::array::from_fn(|a| Dual2_64::new(d[k][a], dv[k][a], 0.0)));
        let [r1, r2] = s_residual(&jets).map(|r| 2.0 * ws * r.v2);
        out = pack(&s_residual_transpose_product(&d, [r1, r2]));
    }
    let (q, qv) = (q_vars(&d), q_vars(&dv));
    let jets: [[Dual2_64; 3]; 4] =
        std::array::from_fn(|i| std::array::from_fn(|a| Dual2_64::new(q[i][a], qv[i][a], 0.0)));
    let r = q_residual(&jets).map(|r| 2.0 * wq * r.v2);
    let product = q_residual_transpose_product(&q, [[r[0], r[1], r[2]], [r[3], r[4], r[5]]]);
    for (i, coordinates) in Q_COORDINATES.iter().enumerate() {
        for &c in *coordinates {
            out[c] += product[i / 3][i % 3];
        }
    }
    out
}

/// Densities and gradient as [`point_hessian`], and in `rows` the Jacobians of the
/// residuals ([`s_residual`], [`q_residual`]) scaled by √(2w), so that `Σ rowᵀ row` is the
/// Gauss–Newton part of the point's Hessian ([`HessianKind::GaussNewton`]).
#[inline(always)]
fn point_gauss_newton(
    x: &[f64; VARS],
    ws: f64,
    wq: f64,
    rows: &mut ResidualRows,
) -> (f64, f64, [f64; VARS]) {
    *rows = [[0.0; VARS]; RESIDUALS];
    if ws != 0.0 {
        set_s_rows(rows, &s_residual(&s_tangents(x)), ws);
    }
    set_q_rows(rows, &q_residual(&q_tangents(&unpack(x))), wq);
    point_gradient(x, ws, wq)
}

/// Densities, gradient and Hessian of `ws · S-density + wq · Q-density` with respect to the
/// 27 derivative coordinates (`h` is overwritten), and when asked the Gauss–Newton rows of
/// [`point_gauss_newton`] from the same tangents. Q is differentiated in its own 12
/// variables and mapped. Forward-over-reverse Hessians are symmetric up to round-off; they
/// are averaged with their transposes.
#[inline(always)]
fn point_hessian(
    x: &[f64; VARS],
    ws: f64,
    wq: f64,
    h: &mut PointMatrix,
    mut rows: Option<&mut ResidualRows>,
) -> (f64, f64, [f64; VARS]) {
    let mut g = [0.0; VARS];
    let d = unpack(x);
    if let Some(rows) = rows.as_deref_mut() {
        *rows = [[0.0; VARS]; RESIDUALS];
    }
    let s = if ws != 0.0 {
        let (s, gs, r) = s_density_gradient_residual(&s_tangents(x));
        if let Some(rows) = rows.as_deref_mut() {
            set_s_rows(rows, &r, ws);
        }
        for i in 0..VARS {
            let gi = &gs[i / 3][i % 3];
            g[i] = ws * gi.re;
            for j in 0..VARS {
                h[i][j] = 0.5 * ws * (gi.eps[j] + gs[j / 3][j % 3].eps[i]);
            }
        }
        s.re
    } else {
        for row in h.iter_mut() {
            *row = [0.0; VARS];
        }
        s_density(&d)
    };
    let qt = q_tangents(&d);
    let (q, gq) = q_density_gradient(&qt);
    if let Some(rows) = rows {
        set_q_rows(rows, &q_residual(&qt), wq);
    }
    for (i, di) in Q_MAP.iter().enumerate() {
        for a in 0..3 {
            let gia = &gq[i][a];
            for &d in *di {
                g[3 * d + a] += wq * gia.re;
            }
            for (j, dj) in Q_MAP.iter().enumerate() {
                for b in 0..3 {
                    let v = 0.5 * wq * (gia.eps[3 * j + b] + gq[j][b].eps[3 * i + a]);
                    for &d in *di {
                        for &e in *dj {
                            h[3 * d + a][3 * e + b] += v;
                        }
                    }
                }
            }
        }
    }
    (s, q.re, g)
}

fn unpack<T: Copy>(x: &[T]) -> [[T; 3]; DERIVATIVES] {
    std::array::from_fn(|d| [x[3 * d], x[3 * d + 1], x[3 * d + 2]])
}

/// The 27 coordinates of nine 3-vectors (the inverse of [`unpack`]).
fn pack(d: &[[f64; 3]; DERIVATIVES]) -> [f64; VARS] {
    std::array::from_fn(|i| d[i / 3][i % 3])
}

/// The derivatives at quadrature point `k` of `rep` for vertex `positions`.
///
/// Summed over the control vertices relative to the point's first one, then that vertex
/// times the coefficients' sums added back: the same derivatives, but the products are of
/// the element's size rather than of the coordinates'. Summed over absolute coordinates,
/// a fine element's derivatives lose the digits its size lacks against the mesh's, and
/// the gradient is noise at the minimum: at the 223 487-vertex three-tube junction's
/// (‖g‖ 6.2·10⁻², 3.7·10⁶ at the start) the two sums' gradients differed by 3.4·10⁻², two
/// relative sums (to the first and to the last vertex) by 2.8·10⁻⁵. (That junction then
/// still stopped near 1.1·10⁻⁸ ‖g₀‖, the floor of its `f64` coordinates rounded to nearest,
/// [`crate::fair::solvers::coordinate_floor`]; with the rounding chosen,
/// [`crate::fair::solvers::lattice_rounding`], it reaches 1.4·10⁻⁹, 2026-11-30.)
/// A derivative's coefficients sum to 0 only up to the rounding of their construction
/// (10⁻¹⁰ of their magnitudes at the G² surface's special elements), hence the sums added
/// back; they are summed here rather than stored (72 bytes a point, 255 MB at that size)
/// because the 9 additions a vertex did not show in the Hessian passes' time.
fn point_derivatives<R: Representation>(rep: &R, k: usize, positions: &[[f64; 3]]) -> [f64; VARS] {
    let p = &rep.points()[k];
    let mut x = [0.0; VARS];
    let Some(&first) = p.vertices.first() else {
        return x;
    };
    let origin = positions[first as usize];
    let mut sums = [0.0; DERIVATIVES];
    for (&v, c) in p.vertices.iter().zip(p.coefficients.iter()) {
        let pos = positions[v as usize];
        let relative = [pos[0] - origin[0], pos[1] - origin[1], pos[2] - origin[2]];
        for d in 0..DERIVATIVES {
            sums[d] += c[d];
            for a in 0..3 {
                x[3 * d + a] += c[d] * relative[a];
            }
        }
    }
    for d in 0..DERIVATIVES {
        for a in 0..3 {
            x[3 * d + a] += sums[d] * origin[a];
        }
    }
    x
}

/// A symmetric matrix over the free vertices stored as 3 × 3 blocks of the upper triangle
/// (block row ≤ block column), the Hessian of F̃ (eq. 6–7).
#[derive(Debug, Clone)]
pub struct BlockHessian {
    /// `(row, column)` free-vertex indices of each block, row ≤ column.
    pub blocks: Vec<(u32, u32)>,
    pub values: Vec<[[f64; 3]; 3]>,
}

/// A 3 × 3 block of a Hessian.
type Block3 = [[f64; 3]; 3];

/// A run of consecutive quadrature points with the same control vertices (a patch).
struct Group {
    points: Range<usize>,
    /// Block slot of each (k, l) pair of the vertices (row-major, k ≤ l) in its
    /// [`Share`]'s blocks, with [`TRANSPOSED`] set where the block's row is vertex l's;
    /// `u32::MAX` where a vertex is fixed or the pair lies below the diagonal.
    slots: Vec<u32>,
}

/// One of the [`TASKS`] runs of groups whose Hessian blocks one task sums.
///
/// Why its own blocks: a task's patches touch about an eighth of the matrix, and partial
/// sums of the whole matrix per task were eight arrays of the Hessian's size to zero and
/// add at every pass (at 223 487 vertices the kernel's zeroing of their fresh pages was
/// 5 % of a run's profile samples, 2026-11-30).
struct Share {
    groups: Range<usize>,
    /// The blocks its groups touch, ascending: the global slot of each of its own.
    slots: Vec<u32>,
}

/// Flag of a [`Group`] slot whose block is the transpose of the patch pair's.
const TRANSPOSED: u32 = 1 << 31;

/// Sums of a share of the quadrature points, and the scratch space to compute them.
struct Partial {
    terms: Terms,
    g: Vec<f64>,
    /// Blocks of the exact Hessian, and of the Gauss–Newton part (empty if not asked for).
    values: Vec<Block3>,
    gauss_newton_values: Vec<Block3>,
    /// The point Hessian.
    h: Box<PointMatrix>,
    /// The point Hessian with rows and columns ordered by coordinate, then derivative.
    by_coordinate: Box<PointMatrix>,
    /// The patch's points' coefficient matrices C_p (9 derivatives × m vertices), stacked:
    /// J_p = C_p ⊗ I₃ is never formed, its zeros would triple the products' work.
    maps: Mat<f64>,
    /// H_p J_p stacked by coordinate: rows (a, p, d) — coordinate a of derivative d at
    /// point p —, columns (b, l) — coordinate b of vertex l.
    weighted: Mat<f64>,
    /// The patch's points' Gauss–Newton rows R_p J_p, stacked: 8 rows per point, columns
    /// (b, l).
    rows: Mat<f64>,
    /// The patch matrix Σ_p J_pᵀ H_p J_p over the patch's vertex coordinates, rows and
    /// columns (a, l).
    local: Mat<f64>,
}

impl Partial {
    fn new(free_count: usize, blocks: usize, gauss_newton_blocks: usize) -> Self {
        Partial {
            terms: Terms::default(),
            g: vec![0.0; 3 * free_count],
            values: vec![[[0.0; 3]; 3]; blocks],
            gauss_newton_values: vec![[[0.0; 3]; 3]; gauss_newton_blocks],
            h: Box::new([[0.0; VARS]; VARS]),
            by_coordinate: Box::new([[0.0; VARS]; VARS]),
            maps: Mat::new(),
            weighted: Mat::new(),
            rows: Mat::new(),
            local: Mat::new(),
        }
    }

    /// The terms and gradient of `parts` summed in their order (the same sums, bit for bit,
    /// as merging them one after another), the gradient's entries in parallel. Their
    /// Hessian blocks, each part's its share's, are summed by [`gather_blocks`].
    fn merge_all(parts: Vec<Partial>) -> Option<Partial> {
        let mut parts = parts.into_iter();
        let mut total = parts.next()?;
        let rest: Vec<Partial> = parts.collect();
        for p in &rest {
            total.terms.s += p.terms.s;
            total.terms.q += p.terms.q;
        }
        add_in_order(&mut total.g, rest.iter().map(|p| p.g.as_slice()));
        Some(total)
    }
}

/// Entries per parallel task of [`add_in_order`].
const MERGE_CHUNK: usize = 1 << 14;

/// `total` += each of `parts` in turn, entry by entry (every part as long as `total`).
fn add_in_order<'p>(total: &mut [f64], parts: impl Iterator<Item = &'p [f64]>) {
    let parts: Vec<&[f64]> = parts.collect();
    total
        .par_chunks_mut(MERGE_CHUNK)
        .enumerate()
        .for_each(|(chunk, out)| {
            let range = chunk * MERGE_CHUNK..chunk * MERGE_CHUNK + out.len();
            for part in &parts {
                for (x, y) in out.iter_mut().zip(&part[range.clone()]) {
                    *x += y;
                }
            }
        });
}

/// F of a representation with some vertices fixed: the objective F̃ of eq. 6 and its
/// derivatives, assembled over the free vertices.
pub struct Functional<'a, R: Representation> {
    rep: &'a R,
    /// c of eq. 4.
    pub c: f64,
    /// Free index of each vertex, `u32::MAX` for a fixed vertex.
    free_index: Vec<u32>,
    free_count: usize,
    blocks: Vec<(u32, u32)>,
    groups: Vec<Group>,
    shares: Vec<Share>,
    arch: pulp::Arch,
}

/// Partial sums per evaluation: a fixed split of the patches, whatever the number of
/// cores, so that the sums are added in the same order and every run gives bit-identical
/// results (rayon's adaptive splitting would not).
const TASKS: usize = 8;

/// Length of the [`TASKS`] chunks of `n` items.
fn chunk_len(n: usize) -> usize {
    n.div_ceil(TASKS).max(1)
}

/// The [`TASKS`] shares of `groups` (consecutive chunks of [`chunk_len`]): the split of
/// every pass over the patches (the Hessians', the gradient's, the accelerations'), each
/// group's slots turned from global block slots into its share's.
fn shares(groups: &mut [Group]) -> Vec<Share> {
    let len = chunk_len(groups.len());
    let mut shares = Vec::with_capacity(TASKS);
    for (t, chunk) in groups.chunks_mut(len).enumerate() {
        let mut slots: Vec<u32> = chunk
            .iter()
            .flat_map(|g| &g.slots)
            .filter(|&&s| s != u32::MAX)
            .map(|&s| s & !TRANSPOSED)
            .collect();
        slots.sort_unstable();
        slots.dedup();
        for group in chunk.iter_mut() {
            for s in group.slots.iter_mut().filter(|s| **s != u32::MAX) {
                let own = slots
                    .binary_search(&(*s & !TRANSPOSED))
                    .expect("the share holds its groups' slots") as u32;
                *s = own | (*s & TRANSPOSED);
            }
        }
        shares.push(Share {
            groups: t * len..t * len + chunk.len(),
            slots,
        });
    }
    shares
}

/// Blocks per parallel task of [`gather_blocks`].
const GATHER_CHUNK: usize = 1 << 12;

/// The `count` blocks summed from each share's own (`parts`, in the shares' order): every
/// block's parts added in that order, bit for bit the sums of whole arrays added in turn.
fn gather_blocks(count: usize, shares: &[Share], parts: &[&[Block3]]) -> Vec<Block3> {
    let mut total = vec![[[0.0; 3]; 3]; count];
    total
        .par_chunks_mut(GATHER_CHUNK)
        .enumerate()
        .for_each(|(chunk, out)| {
            let first = chunk * GATHER_CHUNK;
            let end = first + out.len();
            for (share, part) in shares.iter().zip(parts) {
                let from = share.slots.partition_point(|&s| (s as usize) < first);
                let to = share.slots.partition_point(|&s| (s as usize) < end);
                for (slot, block) in share.slots[from..to].iter().zip(&part[from..to]) {
                    let out = &mut out[*slot as usize - first];
                    for (x, y) in out.as_flattened_mut().iter_mut().zip(block.as_flattened()) {
                        *x += y;
                    }
                }
            }
        });
    total
}

/// Quadrature points per partial sum of [`Functional::value`].
const VALUE_CHUNK: usize = 1024;

impl<'a, R: Representation> Functional<'a, R> {
    /// F for `rep` with the vertices flagged in `fixed` held, and constant `c` (eq. 4).
    pub fn new(rep: &'a R, fixed: &[bool], c: f64) -> Self {
        let mut free_index = vec![u32::MAX; rep.vertex_count()];
        let mut free_count = 0;
        for (v, &f) in fixed.iter().enumerate().take(rep.vertex_count()) {
            if !f {
                free_index[v] = free_count as u32;
                free_count += 1;
            }
        }
        let points = rep.points();
        let mut slot_of: HashMap<(u32, u32), u32> = HashMap::new();
        let mut blocks = Vec::new();
        let mut groups = Vec::new();
        let mut start = 0;
        while start < points.len() {
            let vertices = &points[start].vertices;
            let end = start
                + points[start..]
                    .iter()
                    .take_while(|p| &p.vertices == vertices)
                    .count();
            let m = vertices.len();
            let mut slots = vec![u32::MAX; m * m];
            for k in 0..m {
                let i = free_index[vertices[k] as usize];
                if i == u32::MAX {
                    continue;
                }
                for l in k..m {
                    let j = free_index[vertices[l] as usize];
                    if j == u32::MAX {
                        continue;
                    }
                    // The patch's order is not the free indices': the pair's block may
                    // be (j, i), which holds this pair's transpose.
                    let next = blocks.len() as u32;
                    let slot = *slot_of.entry((i.min(j), i.max(j))).or_insert_with(|| {
                        blocks.push((i.min(j), i.max(j)));
                        next
                    });
                    slots[k * m + l] = if i > j { slot | TRANSPOSED } else { slot };
                }
            }
            groups.push(Group {
                points: start..end,
                slots,
            });
            start = end;
        }
        let shares = shares(&mut groups);
        Functional {
            rep,
            c,
            free_index,
            free_count,
            blocks,
            groups,
            shares,
            arch: pulp::Arch::new(),
        }
    }

    /// Number of free vertices (the unknowns are their 3 coordinates each).
    pub fn free_count(&self) -> usize {
        self.free_count
    }

    /// Free index of each vertex, `u32::MAX` for a fixed vertex.
    pub fn free_index(&self) -> &[u32] {
        &self.free_index
    }

    /// Whether `other` has the same unknowns and the same Hessian blocks (the same mesh
    /// and fixed vertices, whatever the quadrature nodes), so that its Hessians can serve
    /// Newton steps on this F.
    pub fn same_unknowns<S: Representation>(&self, other: &Functional<'_, S>) -> bool {
        self.free_index == other.free_index && self.blocks == other.blocks
    }

    /// S, Q and F at `positions` (eq. 2–5).
    pub fn value(&self, positions: &[[f64; 3]]) -> Terms {
        let [s, q] = self.point_sums(|k, p| {
            let (s, q) = densities(&unpack(&point_derivatives(self.rep, k, positions)));
            [p.weight_s * s, p.weight_q * q]
        });
        Terms {
            s,
            q,
            f: s + self.c * q,
        }
    }

    /// Σ over the quadrature points of `term(k, point k)`, in fixed chunks on all cores
    /// (added in the same order whatever the number of cores).
    fn point_sums<const N: usize>(
        &self,
        term: impl Fn(usize, &QuadraturePoint) -> [f64; N] + Sync,
    ) -> [f64; N] {
        let partial: Vec<[f64; N]> = self
            .rep
            .points()
            .par_chunks(VALUE_CHUNK)
            .enumerate()
            .map(|(c, chunk)| {
                let mut sums = [0.0; N];
                for (i, p) in chunk.iter().enumerate() {
                    let t = term(c * VALUE_CHUNK + i, p);
                    for (sum, x) in sums.iter_mut().zip(t) {
                        *sum += x;
                    }
                }
                sums
            })
            .collect();
        partial.iter().fold([0.0; N], |mut total, sums| {
            for (t, x) in total.iter_mut().zip(sums) {
                *t += x;
            }
            total
        })
    }

    /// Area-weighted mean and standard deviation of the mean curvature H over the
    /// quadrature points where S is integrated (the surface measure √det G dE of eq. 3).
    pub fn mean_curvature_statistics(&self, positions: &[[f64; 3]]) -> (f64, f64) {
        let [area, sum, sum2] = self.point_sums(|k, p| {
            if p.weight_s == 0.0 {
                return [0.0; 3];
            }
            let d = unpack(&point_derivatives(self.rep, k, positions));
            let h = mean_curvature(&d);
            let w = p.weight_s * {
                let n = cross(&d[0], &d[1]);
                dot(&n, &n).sqrt()
            };
            [w, w * h, w * h * h]
        });
        if area == 0.0 {
            return (0.0, 0.0);
        }
        let mean = sum / area;
        (mean, (sum2 / area - mean * mean).max(0.0).sqrt())
    }

    /// The quadrature points of `share`'s groups.
    fn points_of(&self, share: &Share) -> impl Iterator<Item = usize> + '_ {
        self.groups[share.groups.clone()]
            .iter()
            .flat_map(|group| group.points.clone())
    }

    /// The terms and the gradient of F̃ (3 entries per free vertex).
    pub fn gradient(&self, positions: &[[f64; 3]]) -> (Terms, Vec<f64>) {
        let total = self
            .shares
            .par_iter()
            .map(|share| {
                let mut acc = Partial::new(self.free_count, 0, 0);
                for k in self.points_of(share) {
                    let (x, ws, wq) = self.point_input(k, positions);
                    self.add_point(k, point_gradient(&x, ws, wq), &mut acc);
                }
                acc
            })
            .collect::<Vec<_>>();
        let total =
            Partial::merge_all(total).unwrap_or_else(|| Partial::new(self.free_count, 0, 0));
        let mut t = total.terms;
        t.f = t.s + self.c * t.q;
        (t, total.g)
    }

    /// 2 Σ_p w_p J_pᵀ r_vv,p over the free coordinates: the residuals' (S's and Q's, as in
    /// the Gauss–Newton part) second directional derivatives along `direction` (3 entries
    /// per free vertex), exact through second-order duals, mapped back by their Jacobians. With the
    /// Gauss–Newton matrix B, −(B + νI)⁻¹ of it is the geodesic acceleration of the
    /// Levenberg–Marquardt step `direction` (Transtrum and Sethna 2012, eq. 14). `None`
    /// where a residual is not finite (a folded point).
    pub fn residual_curvature(
        &self,
        positions: &[[f64; 3]],
        direction: &[f64],
    ) -> Option<Vec<f64>> {
        // The direction as a displacement of every vertex, so that its derivatives at a
        // point come by the same linear map as the positions' (fixed vertices: 0).
        let displacement: Vec<[f64; 3]> = self
            .free_index
            .iter()
            .map(|&i| match i {
                u32::MAX => [0.0; 3],
                i => std::array::from_fn(|a| direction[3 * i as usize + a]),
            })
            .collect();
        let total = self
            .shares
            .par_iter()
            .map(|share| {
                let mut out = vec![0.0; 3 * self.free_count];
                for k in self.points_of(share) {
                    let (x, ws, wq) = self.point_input(k, positions);
                    let xv = point_derivatives(self.rep, k, &displacement);
                    let grad = self.arch.dispatch(PointResidualCurvature {
                        x: &x,
                        xv: &xv,
                        ws,
                        wq,
                    });
                    self.scatter_gradient(k, &grad, &mut out);
                }
                out
            })
            .reduce_with(|mut a, b| {
                a.iter_mut().zip(&b).for_each(|(a, b)| *a += b);
                a
            })
            .unwrap_or_else(|| vec![0.0; 3 * self.free_count]);
        total.iter().all(|x| x.is_finite()).then_some(total)
    }

    /// Point `k`'s derivatives and the weights of its S and Q densities in F.
    fn point_input(&self, k: usize, positions: &[[f64; 3]]) -> ([f64; VARS], f64, f64) {
        let p = &self.rep.points()[k];
        (
            point_derivatives(self.rep, k, positions),
            p.weight_s,
            self.c * p.weight_q,
        )
    }

    /// Adds point `k`'s weighted densities and its gradient `(s, q, grad)` (the latter
    /// over the 27 derivative coordinates) to `acc`.
    fn add_point(&self, k: usize, (s, q, grad): (f64, f64, [f64; VARS]), acc: &mut Partial) {
        let p = &self.rep.points()[k];
        acc.terms.s += p.weight_s * s;
        acc.terms.q += p.weight_q * q;
        self.scatter_gradient(k, &grad, &mut acc.g);
    }

    fn scatter_gradient(&self, k: usize, grad: &[f64], g: &mut [f64]) {
        let p = &self.rep.points()[k];
        for (&v, c) in p.vertices.iter().zip(p.coefficients.iter()) {
            let i = self.free_index[v as usize];
            if i == u32::MAX {
                continue;
            }
            for a in 0..3 {
                let mut sum = 0.0;
                for d in 0..DERIVATIVES {
                    sum += c[d] * grad[3 * d + a];
                }
                g[3 * i as usize + a] += sum;
            }
        }
    }

    /// Adds one patch's terms, gradient and Hessian blocks of `kind` to `acc`: patch
    /// matrices over the patch's vertex coordinates ([`Self::patch_points`]), each
    /// scattered once into its sparse blocks.
    fn add_patch_hessian(
        &self,
        group: &Group,
        positions: &[[f64; 3]],
        kind: HessianKind,
        acc: &mut Partial,
    ) {
        self.patch_points(group, positions, kind, acc);
        if kind.exact() {
            // Σ_p J_pᵀ (H_p J_p) = Σ_p (C_p ⊗ I₃)ᵀ (H_p J_p): per coordinate a, one dense
            // product of the stacked C_p with the rows of coordinate a.
            let n = 3 * acc.maps.ncols();
            let stacked = acc.maps.nrows();
            acc.local.resize_with(n, n, |_, _| 0.0);
            for a in 0..3 {
                matmul(
                    acc.local.as_mut().subrows_mut(a * (n / 3), n / 3),
                    Accum::Replace,
                    acc.maps.transpose(),
                    acc.weighted.as_ref().subrows(a * stacked, stacked),
                    1.0,
                    Par::Seq,
                );
            }
            scatter_blocks(group, &acc.local, &mut acc.values);
        }
        if kind.gauss_newton() {
            // Σ_p (R_p J_p)ᵀ (R_p J_p): one dense product over the stacked rows.
            let rows = acc.rows.as_ref();
            let n = rows.ncols();
            acc.local.resize_with(n, n, |_, _| 0.0);
            matmul(
                acc.local.as_mut(),
                Accum::Replace,
                rows.transpose(),
                rows,
                1.0,
                Par::Seq,
            );
            scatter_blocks(group, &acc.local, &mut acc.gauss_newton_values);
        }
    }

    /// Adds the patch's points' terms and gradients to `acc` and stacks, per `kind`, the
    /// coefficient matrices C_p (`acc.maps`) with H_p J_p (`acc.weighted`) for the exact
    /// Hessian, and the Gauss–Newton rows mapped to vertex coordinates,
    /// R_p J_p (`acc.rows`, 8 rows per point instead of the exact Hessian's 27).
    fn patch_points(
        &self,
        group: &Group,
        positions: &[[f64; 3]],
        kind: HessianKind,
        acc: &mut Partial,
    ) {
        let points = self.rep.points();
        let m = points[group.points.start].vertices.len();
        let (exact, rows) = (kind.exact(), kind.gauss_newton());
        let stacked = DERIVATIVES * group.points.len();
        if exact {
            acc.maps.resize_with(stacked, m, |_, _| 0.0);
            acc.weighted.resize_with(3 * stacked, 3 * m, |_, _| 0.0);
        }
        if rows {
            acc.rows
                .resize_with(RESIDUALS * group.points.len(), 3 * m, |_, _| 0.0);
        }
        let mut point_rows = [[0.0; VARS]; RESIDUALS];
        for (i, k) in group.points.clone().enumerate() {
            let p = &points[k];
            let (x, ws, wq) = self.point_input(k, positions);
            let point = if exact {
                self.arch.dispatch(PointHessian {
                    x: &x,
                    ws,
                    wq,
                    h: &mut acc.h,
                    rows: rows.then_some(&mut point_rows),
                })
            } else {
                self.arch.dispatch(PointGaussNewton {
                    x: &x,
                    ws,
                    wq,
                    rows: &mut point_rows,
                })
            };
            self.add_point(k, point, acc);
            if rows {
                map_rows(p, &point_rows, RESIDUALS * i, &mut acc.rows);
            }
            if exact {
                let top = DERIVATIVES * i;
                for (l, c) in p.coefficients.iter().enumerate() {
                    for (d, &cd) in c.iter().enumerate() {
                        acc.maps[(top + d, l)] = cd;
                    }
                }
                // H_p (C_p ⊗ I₃): block (a, b) of H_p (derivatives × derivatives) times C_p,
                // column by column (9 × 9 blocks are too small for a gemm call to pay).
                // `by_coordinate[9b + e][9a + d]` = H_p[(d, a), (e, b)] (H_p is symmetric).
                for (i, row) in acc.h.iter().enumerate() {
                    for (j, &x) in row.iter().enumerate() {
                        acc.by_coordinate[DERIVATIVES * (j % 3) + j / 3]
                            [DERIVATIVES * (i % 3) + i / 3] = x;
                    }
                }
                for (l, c) in p.coefficients.iter().enumerate() {
                    for b in 0..3 {
                        let column = acc
                            .weighted
                            .as_mut()
                            .col_mut(b * m + l)
                            .try_as_col_major_mut()
                            .expect("a Mat's columns are contiguous")
                            .as_slice_mut();
                        for a in 0..3 {
                            let mut w = [0.0; DERIVATIVES];
                            for (e, &ce) in c.iter().enumerate() {
                                let h = &acc.by_coordinate[DERIVATIVES * b + e]
                                    [DERIVATIVES * a..DERIVATIVES * (a + 1)];
                                for d in 0..DERIVATIVES {
                                    w[d] += h[d] * ce;
                                }
                            }
                            column[a * stacked + top..a * stacked + top + DERIVATIVES]
                                .copy_from_slice(&w);
                        }
                    }
                }
            }
        }
    }

    /// The terms, gradient and Hessian of F̃ (eq. 7's g and H).
    pub fn hessian(&self, positions: &[[f64; 3]]) -> (Terms, Vec<f64>, BlockHessian) {
        let out = self.hessians(positions, HessianKind::Exact);
        (
            out.terms,
            out.gradient,
            out.exact.expect("the exact Hessian was asked for"),
        )
    }

    /// The terms, gradient and the Hessians of `kind` of F̃, from one pass over the
    /// quadrature points.
    pub fn hessians(&self, positions: &[[f64; 3]], kind: HessianKind) -> Hessians {
        let blocks = |wanted: bool, share: &Share| if wanted { share.slots.len() } else { 0 };
        let parts = self
            .shares
            .par_iter()
            .map(|share| {
                let mut acc = Partial::new(
                    self.free_count,
                    blocks(kind.exact(), share),
                    blocks(kind.gauss_newton(), share),
                );
                for group in &self.groups[share.groups.clone()] {
                    self.add_patch_hessian(group, positions, kind, &mut acc);
                }
                acc
            })
            .collect::<Vec<_>>();
        let gather = |values: &dyn Fn(&Partial) -> &[Block3]| BlockHessian {
            blocks: self.blocks.clone(),
            values: gather_blocks(
                self.blocks.len(),
                &self.shares,
                &parts.iter().map(values).collect::<Vec<_>>(),
            ),
        };
        let exact = kind.exact().then(|| gather(&|p| &p.values));
        let gauss_newton = kind
            .gauss_newton()
            .then(|| gather(&|p| &p.gauss_newton_values));
        let total =
            Partial::merge_all(parts).unwrap_or_else(|| Partial::new(self.free_count, 0, 0));
        let mut terms = total.terms;
        terms.f = terms.s + self.c * terms.q;
        Hessians {
            terms,
            exact,
            gauss_newton,
            gradient: total.g,
        }
    }
}

/// The result of [`Functional::hessians`].
pub struct Hessians {
    pub terms: Terms,
    pub gradient: Vec<f64>,
    /// F̃'s exact Hessian, unless only the Gauss–Newton part was asked for.
    pub exact: Option<BlockHessian>,
    /// The Gauss–Newton part, if asked for.
    pub gauss_newton: Option<BlockHessian>,
}

/// Point rows (27 derivative coordinates each) mapped to the point's vertex coordinates,
/// R_p J_p, into `out` from row `top`.
fn map_rows(p: &QuadraturePoint, rows: &ResidualRows, top: usize, out: &mut Mat<f64>) {
    let m = p.coefficients.len();
    for (r, row) in rows.iter().enumerate() {
        for (l, c) in p.coefficients.iter().enumerate() {
            for a in 0..3 {
                let mut sum = 0.0;
                for (d, &cd) in c.iter().enumerate() {
                    sum += cd * row[3 * d + a];
                }
                out[(top + r, a * m + l)] = sum;
            }
        }
    }
}

/// Adds the patch matrix `local` (rows and columns (a, l): coordinate a of patch vertex
/// l) to the sparse blocks of its free vertex pairs, transposed where the block's row is
/// the pair's second vertex.
fn scatter_blocks(group: &Group, local: &Mat<f64>, values: &mut [[[f64; 3]; 3]]) {
    let m = local.nrows() / 3;
    for k in 0..m {
        for l in k..m {
            let slot = group.slots[k * m + l];
            if slot == u32::MAX {
                continue;
            }
            let block = &mut values[(slot & !TRANSPOSED) as usize];
            let transposed = slot & TRANSPOSED != 0;
            for (a, row) in block.iter_mut().enumerate() {
                for (b, x) in row.iter_mut().enumerate() {
                    *x += if transposed {
                        local[(b * m + k, a * m + l)]
                    } else {
                        local[(a * m + k, b * m + l)]
                    };
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::tolerance::ROUND_OFF;
    use nalgebra::SVector;
    use num_dual::{hessian, Dual, DualNum};

    // Independent formulations over num-dual's scalars (the production code uses `Num`).
    fn ddot<U: DualNum + Copy>(a: &[U; 3], b: &[U; 3]) -> U {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }

    fn dcross<U: DualNum + Copy>(a: &[U; 3], b: &[U; 3]) -> [U; 3] {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }

    /// H = (E N − 2 F M + G L) / (2 (EG − F²)) with the unnormalized normal.
    fn dual_mean_curvature<U: DualNum<Primitive = f64> + Copy>(
        pu: &[U; 3],
        pv: &[U; 3],
        puu: &[U; 3],
        puv: &[U; 3],
        pvv: &[U; 3],
    ) -> U {
        let (e, f, g) = (ddot(pu, pu), ddot(pu, pv), ddot(pv, pv));
        let n = dcross(pu, pv);
        let w2 = e * g - f * f;
        let (l, m, nn) = (ddot(puu, &n), ddot(puv, &n), ddot(pvv, &n));
        (e * nn - f * m * 2.0 + g * l) / (w2 * w2.sqrt() * 2.0)
    }

    fn point(x: f64, y: f64, r: f64) -> [[f64; 3]; DERIVATIVES] {
        // A sphere of radius r, p(u, v) = (u, v, √(r² − u² − v²)), derivatives at (x, y).
        let z = (r * r - x * x - y * y).sqrt();
        let zu = -x / z;
        let zv = -y / z;
        let zuu = -(r * r - y * y) / z.powi(3);
        let zuv = -x * y / z.powi(3);
        let zvv = -(r * r - x * x) / z.powi(3);
        let z5 = z.powi(5);
        let zuuu = -3.0 * x * (r * r - y * y) / z5;
        let zuuv = -y * (r * r - y * y + 2.0 * x * x) / z5 + 0.0;
        let zuvv = -x * (r * r - x * x + 2.0 * y * y) / z5;
        let zvvv = -3.0 * y * (r * r - x * x) / z5;
        [
            [1.0, 0.0, zu],
            [0.0, 1.0, zv],
            [0.0, 0.0, zuu],
            [0.0, 0.0, zuv],
            [0.0, 0.0, zvv],
            [0.0, 0.0, zuuu],
            [0.0, 0.0, zuuv],
            [0.0, 0.0, zuvv],
            [0.0, 0.0, zvvv],
        ]
    }

    /// Density of S (eq. 3): ∇H G⁻¹ ∇Hᵀ √det G at a point with derivatives `d`.
    fn nested_dual_s_density<T: DualNum<Primitive = f64> + Copy>(d: &[[T; 3]; DERIVATIVES]) -> T {
        let [pu, pv, puu, puv, pvv, puuu, puuv, puvv, pvvv] = d;
        let lift = |a: &[T; 3], b: &[T; 3]| -> [Dual<T>; 3] {
            std::array::from_fn(|k| Dual::new(a[k], b[k]))
        };
        // ∂H/∂u: the tangent of (p_u, p_v, p_uu, p_uv, p_vv) along u.
        let hu = dual_mean_curvature(
            &lift(pu, puu),
            &lift(pv, puv),
            &lift(puu, puuu),
            &lift(puv, puuv),
            &lift(pvv, puvv),
        )
        .eps;
        let hv = dual_mean_curvature(
            &lift(pu, puv),
            &lift(pv, pvv),
            &lift(puu, puuv),
            &lift(puv, puvv),
            &lift(pvv, pvvv),
        )
        .eps;
        let (e, f, g) = (ddot(pu, pu), ddot(pu, pv), ddot(pv, pv));
        let w2 = e * g - f * f;
        (hu * hu * g - hu * hv * f * 2.0 + hv * hv * e) / w2.sqrt()
    }

    #[test]
    fn sphere_has_constant_mean_curvature_and_no_s_density() {
        let r = 2.0;
        let d = point(0.3, -0.4, r);
        let h = mean_curvature(&d);
        assert_near!(h.abs(), 1.0 / r, ROUND_OFF);
        let (s, _) = densities(&d);
        assert_near!(s, 0.0, ROUND_OFF);
    }

    /// Derivative coordinates with no special structure, `wave(i)` each, plus a regular
    /// metric (p_u, p_v near (2, 0, 0), (0, 2, 0)).
    fn generic_derivatives(wave: impl Fn(f64) -> f64) -> [f64; VARS] {
        std::array::from_fn(|i| wave(i as f64) + if i == 0 || i == 4 { 2.0 } else { 0.0 })
    }

    #[test]
    fn forward_over_reverse_matches_num_dual() {
        // A generic point: derivatives with no special structure. num-dual's second-order
        // duals through the nested-dual formulation (an independent implementation of
        // eq. 3) against the reverse-accumulated gradient and its tangents.
        let x = generic_derivatives(|t| (0.7 * t + 0.3).sin());
        let d = unpack(&x);
        assert_near!(nested_dual_s_density(&d), s_density(&d), ROUND_OFF);
        let (value, grad, hess) = hessian(
            |y| nested_dual_s_density(&unpack(y.as_slice())),
            &SVector::<f64, VARS>::from(x),
        );
        let (own_value, own_grad) = s_density_gradient(&d);
        let mut h = [[0.0; VARS]; VARS];
        let (s, _, g) = point_hessian(&x, 1.0, 0.0, &mut h, None);
        let scale = hess.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let gscale = grad.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert_near!(own_value, value, ROUND_OFF);
        assert_near!(s, value, ROUND_OFF);
        for i in 0..VARS {
            assert_near!(own_grad[i / 3][i % 3] / gscale, grad[i] / gscale, ROUND_OFF);
            assert_near!(g[i] / gscale, grad[i] / gscale, ROUND_OFF);
            for j in 0..VARS {
                assert_near!(h[i][j] / scale, hess[(i, j)] / scale, ROUND_OFF);
            }
        }
    }

    /// Q's density written directly over num-dual's scalars (eq. 5 with P = I − n nᵀ).
    fn num_dual_q_density<T: DualNum<Primitive = f64> + Copy>(d: &[[T; 3]; DERIVATIVES]) -> T {
        let lap_u: [T; 3] = std::array::from_fn(|a| d[5][a] + d[7][a]);
        let lap_v: [T; 3] = std::array::from_fn(|a| d[6][a] + d[8][a]);
        let n = dcross(&d[0], &d[1]);
        let nn = ddot(&n, &n);
        let project = |x: &[T; 3]| -> [T; 3] {
            let k = ddot(&n, x) / nn;
            std::array::from_fn(|a| x[a] - n[a] * k)
        };
        let (pu, pv) = (project(&lap_u), project(&lap_v));
        ddot(&pu, &pu) + ddot(&pv, &pv)
    }

    #[test]
    fn q_forward_over_reverse_matches_num_dual() {
        let x = generic_derivatives(|t| (1.3 * t + 0.1).cos());
        let (value, grad, hess) = hessian(
            |y| num_dual_q_density(&unpack(y.as_slice())),
            &SVector::<f64, VARS>::from(x),
        );
        let mut h = [[0.0; VARS]; VARS];
        let (_, q, g) = point_hessian(&x, 0.0, 1.0, &mut h, None);
        let (_, q_only, g_only) = point_gradient(&x, 0.0, 1.0);
        let scale = hess.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let gscale = grad.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert_near!(q, value, ROUND_OFF);
        assert_near!(q_only, value, ROUND_OFF);
        for i in 0..VARS {
            assert_near!(g[i] / gscale, grad[i] / gscale, ROUND_OFF);
            assert_near!(g_only[i] / gscale, grad[i] / gscale, ROUND_OFF);
            for j in 0..VARS {
                assert_near!(h[i][j] / scale, hess[(i, j)] / scale, ROUND_OFF);
            }
        }
    }

    #[test]
    fn flat_point_closed_forms() {
        // Third derivatives normal to the tangent plane are projected away by P in Q.
        let mut d = [[0.0; 3]; DERIVATIVES];
        d[0] = [1.0, 0.0, 0.0];
        d[1] = [0.0, 1.0, 0.0];
        d[5] = [0.0, 0.0, 2.0];
        d[8] = [0.0, 0.0, -1.0];
        let (s, q) = densities(&d);
        // At a flat point of the graph z(u, v), H_u = (z_uuu + z_uvv) / 2 = 1 and
        // H_v = (z_uuv + z_vvv) / 2 = −1/2: the density is H_u² + H_v².
        assert_near!(s, 1.25, ROUND_OFF);
        assert_near!(q, 0.0, ROUND_OFF);
        // A tangential one is not: ‖(3, 0, 0)‖² for Δp_u.
        d[5] = [3.0, 0.0, 0.0];
        let (_, q) = densities(&d);
        assert_near!(q, 9.0, ROUND_OFF);
    }

    #[test]
    fn residuals_square_to_the_densities() {
        let x = generic_derivatives(|t| (0.7 * t + 0.3).sin());
        let d = unpack(&x);
        let (s, q) = densities(&d);
        let r = s_residual(&d);
        assert_near!(r[0] * r[0] + r[1] * r[1], s, ROUND_OFF);
        let rq = q_residual(&q_vars(&d));
        assert_near!(rq.iter().map(|v| v * v).sum::<f64>(), q, ROUND_OFF);
    }

    /// Σ rowᵀ row of [`point_gauss_newton`]'s rows, and its gradient.
    fn gauss_newton_matrix(x: &[f64; VARS], ws: f64, wq: f64, h: &mut PointMatrix) -> [f64; VARS] {
        let mut rows = [[0.0; VARS]; RESIDUALS];
        let (_, _, g) = point_gauss_newton(x, ws, wq, &mut rows);
        for i in 0..VARS {
            for j in 0..VARS {
                h[i][j] = rows.iter().map(|r| r[i] * r[j]).sum();
            }
        }
        g
    }

    #[test]
    fn residual_curvature_matches_second_differences_through_the_gauss_newton_rows() {
        // 2 w Jᵀ r_vv at a generic point, against a second implementation: the residuals'
        // central second differences along the direction (f64 evaluations, h = 10⁻³,
        // error O(h²)) through the Gauss–Newton rows √(2w) ∇r.
        let x = generic_derivatives(|t| (0.7 * t + 0.3).sin());
        let xv = generic_derivatives(|t| 0.2 * (1.3 * t - 0.5).cos());
        let (ws, wq) = (0.8, 0.3);
        let residuals = |t: f64| -> [f64; RESIDUALS] {
            let d = unpack(&std::array::from_fn::<f64, VARS, _>(|i| x[i] + t * xv[i]));
            let (s, q) = (s_residual(&d), q_residual(&q_vars(&d)));
            std::array::from_fn(|k| if k < 2 { s[k] } else { q[k - 2] })
        };
        let h = 1e-3;
        let (minus, centre, plus) = (residuals(-h), residuals(0.0), residuals(h));
        let mut rows = [[0.0; VARS]; RESIDUALS];
        point_gauss_newton(&x, ws, wq, &mut rows);
        let mut expected = [0.0; VARS];
        for (k, row) in rows.iter().enumerate() {
            let w = if k < 2 { ws } else { wq };
            let second = (plus[k] - 2.0 * centre[k] + minus[k]) / (h * h);
            for (e, r) in expected.iter_mut().zip(row) {
                *e += (2.0 * w).sqrt() * second * r;
            }
        }
        let got = point_residual_curvature(&x, &xv, ws, wq);
        let scale = expected.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(
            scale > 1e-3,
            "a direction along which the residuals bend: {scale}"
        );
        for (g, e) in got.iter().zip(&expected) {
            assert!((g - e).abs() <= 1e-5 * scale, "{g} vs {e}");
        }
    }

    #[test]
    fn residual_transpose_product_matches_the_forward_jacobian() {
        // Jᵀu by reverse accumulation against the forward-mode Jacobian of S's residuals.
        let x = generic_derivatives(|t| (0.7 * t + 0.3).sin());
        let u = [0.7, -1.3];
        let jacobian = s_residual(&s_tangents(&x));
        let got = pack(&s_residual_transpose_product(&unpack(&x), u));
        let expected: [f64; VARS] =
            std::array::from_fn(|c| u[0] * jacobian[0].eps[c] + u[1] * jacobian[1].eps[c]);
        let scale = expected.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (g, e) in got.iter().zip(&expected) {
            assert_near!(g / scale, e / scale, ROUND_OFF);
        }
    }

    #[test]
    fn q_residual_transpose_product_matches_the_forward_jacobian() {
        // Jᵀu by reverse accumulation against the forward-mode Jacobian of Q's residuals.
        let x = generic_derivatives(|t| (0.7 * t + 0.3).sin());
        let u = [[0.7, -1.3, 0.4], [0.2, 0.9, -0.6]];
        let jacobian = q_residual(&q_tangents(&unpack(&x)));
        let got = q_residual_transpose_product(&q_vars(&unpack(&x)), u);
        let flat = u.as_flattened();
        let scale = (0..Q_VARS).fold(0.0f64, |m, i| m.max(got[i / 3][i % 3].abs()));
        for i in 0..Q_VARS {
            let expected: f64 = (0..6).map(|k| flat[k] * jacobian[k].eps[i]).sum();
            assert_near!(got[i / 3][i % 3] / scale, expected / scale, ROUND_OFF);
        }
    }

    /// The largest |entry| of the difference of two point matrices over that of `b`.
    fn relative_difference(a: &PointMatrix, b: &PointMatrix) -> f64 {
        let scale = b.as_flattened().iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let diff = a
            .as_flattened()
            .iter()
            .zip(b.as_flattened())
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        diff / scale
    }

    #[test]
    fn gauss_newton_part_is_the_hessian_where_the_residuals_vanish() {
        // H = 2 JᵀJ + 2 Σ r_k ∇²r_k: on a sphere ∇H = 0, so S's residuals vanish and the
        // exact Hessian (checked against num-dual above) is its Gauss–Newton part.
        let sphere = point(0.3, -0.4, 2.0);
        let x: [f64; VARS] = std::array::from_fn(|i| sphere[i / 3][i % 3]);
        let (mut exact, mut gauss_newton) = ([[0.0; VARS]; VARS], [[0.0; VARS]; VARS]);
        let (_, _, g) = point_hessian(&x, 1.0, 0.0, &mut exact, None);
        let g_gn = gauss_newton_matrix(&x, 1.0, 0.0, &mut gauss_newton);
        assert_eq!(g, g_gn);
        assert!(relative_difference(&gauss_newton, &exact) < 1e-12);
        // Q: third derivatives along the normal are projected away, P ∇Δp = 0.
        let mut d = [[0.0; 3]; DERIVATIVES];
        d[0] = [1.0, 0.2, 0.0];
        d[1] = [0.1, 1.0, 0.0];
        d[5] = [0.0, 0.0, 2.0];
        d[8] = [0.0, 0.0, -1.0];
        let x: [f64; VARS] = std::array::from_fn(|i| d[i / 3][i % 3]);
        point_hessian(&x, 0.0, 1.0, &mut exact, None);
        gauss_newton_matrix(&x, 0.0, 1.0, &mut gauss_newton);
        assert!(relative_difference(&gauss_newton, &exact) < 1e-12);
        // Away from such points the two differ.
        let x = generic_derivatives(|t| (1.3 * t + 0.1).cos());
        point_hessian(&x, 1.0, 1.0, &mut exact, None);
        gauss_newton_matrix(&x, 1.0, 1.0, &mut gauss_newton);
        assert!(relative_difference(&gauss_newton, &exact) > 1e-3);
    }

    #[test]
    fn shares_blocks_gather_to_the_sums_of_whole_arrays_in_order() {
        // Three shares over 10 000 blocks (more than one gather chunk), overlapping, with
        // values of mixed magnitudes so that the order of the additions shows in the bits.
        let count = 10_000;
        let owned: Vec<Vec<u32>> = vec![
            (0..6000).step_by(2).collect(),
            (3000..9000).step_by(3).collect(),
            (0..count as u32).filter(|s| s % 5 != 1).collect(),
        ];
        let value = |t: usize, k: usize| -> Block3 {
            std::array::from_fn(|a| {
                std::array::from_fn(|b| {
                    let x = (t * 7919 + k * 104_729 + 3 * a + b) as f64;
                    (x * 0.618).sin() * 10f64.powi((k % 9) as i32 - 4)
                })
            })
        };
        let shares: Vec<Share> = owned
            .iter()
            .map(|slots| Share {
                groups: 0..0,
                slots: slots.clone(),
            })
            .collect();
        let parts: Vec<Vec<Block3>> = owned
            .iter()
            .enumerate()
            .map(|(t, slots)| (0..slots.len()).map(|k| value(t, k)).collect())
            .collect();
        let got = gather_blocks(
            count,
            &shares,
            &parts.iter().map(|p| p.as_slice()).collect::<Vec<_>>(),
        );
        // The whole arrays: each share's blocks scattered into a zeroed array of all of
        // them, the arrays added one after another.
        let mut expected = vec![[[0.0; 3]; 3]; count];
        for (slots, part) in owned.iter().zip(&parts) {
            let mut whole = vec![[[0.0; 3]; 3]; count];
            for (&s, v) in slots.iter().zip(part) {
                whole[s as usize] = *v;
            }
            for (e, w) in expected.iter_mut().zip(&whole) {
                for (x, y) in e.as_flattened_mut().iter_mut().zip(w.as_flattened()) {
                    *x += y;
                }
            }
        }
        assert_eq!(got, expected);
    }
}
