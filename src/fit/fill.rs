//! Hole filling of the 2022 paper §4: σ₂ on H_h minimizes
//! J₂(v) = Σ_{b ∈ B_h} ‖v(b) − σ₁(b)‖² + ε|v|²₂,H_h over the restrictions to H_h of V_h,
//! with v = σ₁ at the knots C_h on ∂H_h and ∂v/∂n = ∂σ₁/∂n at the non-corner knots D_h,
//! through the saddle-point system (14). The `ExactC1` variant keeps σ ∈ V_h exactly:
//! only the functions supported inside H_h are free, the others keep σ₁'s coefficients.

use std::collections::BTreeMap;

use faer::Mat;

use crate::error::{Error, Result};
use crate::linalg::minimize_with_equalities;
use crate::spline::{seminorm_gram, Cell, Space};

use super::surface::VectorSpline;

/// Which filling problem to solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum FillVariant {
    /// The paper's σ₂ with the constraints of (14): C⁰ at the boundary knots, C¹ in the
    /// normal direction at the non-corner knots; between knots σ may jump.
    Paper,
    /// σ ∈ V_h: the coefficients of the functions reaching outside H_h are σ₁'s.
    ExactC1,
}

/// Options of [`fill_hole`].
#[derive(Debug, Clone)]
pub struct FillOptions {
    /// ε > 0 of J₂.
    pub epsilon: f64,
    /// Order m of the semi-norm (2 in the 2022 paper).
    pub m: usize,
    /// The problem to solve.
    pub variant: FillVariant,
}

/// What the filling did, and how continuous the result is across ∂H_h.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct FillReport {
    /// M₂ + M₃: the equality constraints of (14) (0 for `ExactC1`).
    pub constraints: usize,
    /// Rank of the constraint matrix (< `constraints` when they are dependent).
    pub constraint_rank: usize,
    /// max ‖Cβ − d‖∞ over the components.
    pub constraint_residual: f64,
    /// Unknown coefficients per component.
    pub unknowns: usize,
    /// M₁: data points in H_h.
    pub data_in_hole: usize,
    /// max ‖σ₂ − σ₁‖ on ∂H_h (sampled on every interface edge).
    pub c0_jump: f64,
    /// max ‖∂ₙσ₂ − ∂ₙσ₁‖ on ∂H_h.
    pub c1_jump: f64,
    /// ‖λ‖∞ of the minimum-norm multipliers (λ is not unique when constraints are dependent).
    pub lambda_norm: f64,
}

/// The filled spline σ = σ₁ on R − H_h, σ₂ on H_h (2022 Definition 1).
#[derive(Debug, Clone)]
pub struct HoleFill {
    /// σ₁, the smoothing spline outside the hole.
    pub sigma1: VectorSpline,
    /// σ₂ (its coefficients on the functions vanishing on H_h are unused).
    pub sigma2: VectorSpline,
    /// H_h by cell linear index.
    pub hole_cells: Vec<bool>,
    /// The report.
    pub report: FillReport,
}

impl HoleFill {
    /// σ(x, y) and its derivatives: σ₂'s pieces on H_h cells, σ₁'s elsewhere.
    ///
    /// Errors: `InvalidInput` outside the rectangle or for NaN.
    pub fn eval(&self, space: &dyn Space, x: f64, y: f64, a: usize, b: usize) -> Result<[f64; 3]> {
        let g = space.grid();
        let c = g.locate(x, y).ok_or_else(|| {
            Error::InvalidInput(format!(
                "point ({x}, {y}) is outside the spline's rectangle"
            ))
        })?;
        if self.hole_cells[g.cell_index(c)] {
            self.sigma2.eval_on_cell(space, c, x, y, a, b)
        } else {
            self.sigma1.eval_on_cell(space, c, x, y, a, b)
        }
    }
}

/// An edge of ∂H_h between an H_h cell and a cell outside: from node `from` to node `to`
/// (grid node indices (p, q)), with the cells on both sides.
#[derive(Debug, Clone, Copy)]
struct Interface {
    from: (usize, usize),
    to: (usize, usize),
    inside: Cell,
    outside: Cell,
    /// Normal direction: 0 = x (a vertical edge), 1 = y (a horizontal edge).
    normal: usize,
}

fn interfaces(space: &dyn Space, mask: &[bool]) -> Vec<Interface> {
    let g = space.grid();
    let (nx, ny) = g.shape();
    let mut out = vec![];
    for c in g.cells().filter(|&c| mask[g.cell_index(c)]) {
        let nb = |di: isize, dj: isize| -> Option<Cell> {
            let (i, j) = (c.i as isize + di, c.j as isize + dj);
            (i >= 0 && j >= 0 && (i as usize) < nx && (j as usize) < ny).then_some(Cell {
                i: i as usize,
                j: j as usize,
            })
        };
        let sides = [
            (nb(-1, 0), (c.i, c.j), (c.i, c.j + 1), 0),
            (nb(1, 0), (c.i + 1, c.j), (c.i + 1, c.j + 1), 0),
            (nb(0, -1), (c.i, c.j), (c.i + 1, c.j), 1),
            (nb(0, 1), (c.i, c.j + 1), (c.i + 1, c.j + 1), 1),
        ];
        for (o, from, to, normal) in sides {
            if let Some(o) = o.filter(|o| !mask[g.cell_index(*o)]) {
                out.push(Interface {
                    from,
                    to,
                    inside: c,
                    outside: o,
                    normal,
                });
            }
        }
    }
    out
}

/// Fills the hole H_h of `sigma1` (2022 §4, Propositions 2–3, system (14)).
///
/// `points` are all the data sites A_N; those in H_h form B_h and are fitted to σ₁'s values.
/// Preconditions (each an `InvalidInput` otherwise): ε > 0 finite; `hole_cells` a mask over
/// the grid with at least one cell in and one out; `sigma1` matching the space; finite points.
/// Errors: `Solver { NotPositiveDefinite }` if J₂ is not coercive on the constrained set.
/// Dependent constraints (a hole component that is a rectangle of cells) are handled:
/// β is unique, λ is the minimum-norm one.
pub fn fill_hole(
    space: &dyn Space,
    sigma1: &VectorSpline,
    points: &[[f64; 2]],
    hole_cells: &[bool],
    opts: &FillOptions,
) -> Result<HoleFill> {
    let g = space.grid();
    if !(opts.epsilon > 0.0 && opts.epsilon.is_finite()) {
        return Err(Error::InvalidInput(format!(
            "the smoothing parameter ε must be positive and finite, got {}",
            opts.epsilon
        )));
    }
    if hole_cells.len() != g.cell_count() {
        return Err(Error::InvalidInput(format!(
            "hole mask of {} cells for a grid of {}",
            hole_cells.len(),
            g.cell_count()
        )));
    }
    let nh = hole_cells.iter().filter(|&&b| b).count();
    if nh == 0 || nh == hole_cells.len() {
        return Err(Error::InvalidInput(format!(
            "the hole covers {nh} of {} cells: it must cover some but not all",
            hole_cells.len()
        )));
    }
    if sigma1.coeffs.iter().any(|c| c.len() != space.dim()) {
        return Err(Error::InvalidInput("σ₁ does not match the space".into()));
    }
    if points.iter().flatten().any(|x| !x.is_finite()) {
        return Err(Error::InvalidInput("a data point is not finite".into()));
    }
    let hcells: Vec<Cell> = g.cells().filter(|&c| hole_cells[g.cell_index(c)]).collect();

    // V_h*: the functions not vanishing on H_h.
    let mut local: BTreeMap<usize, usize> = BTreeMap::new();
    for &c in &hcells {
        for k in space.cell_functions(c) {
            let n = local.len();
            local.entry(k).or_insert(n);
        }
    }
    let active: Vec<usize> = {
        let mut v = vec![0; local.len()];
        for (&k, &l) in &local {
            v[l] = k;
        }
        v
    };
    let mu = active.len();

    // 𝒜_h𝒜_hᵀ + ε𝓡 and d₁ = (⟨ρ₁(vᵢ), ρ₁(σ₁)⟩).
    let mut kmat = Mat::<f64>::zeros(mu, mu);
    let mut rhs = vec![vec![0.0; mu]; 3];
    let mut m1 = 0;
    for p in points {
        let Some(c) = g.locate(p[0], p[1]) else {
            return Err(Error::InvalidInput(format!(
                "data point ({}, {}) is outside R",
                p[0], p[1]
            )));
        };
        if !hole_cells[g.cell_index(c)] {
            continue;
        }
        m1 += 1;
        let target = sigma1.eval_on_cell(space, c, p[0], p[1], 0, 0)?;
        let lb = space.eval_on_cell(c, p[0], p[1], 0);
        for (l, &kl) in lb.indices.iter().enumerate() {
            let (il, dl) = (local[&kl], lb.d(l, 0, 0));
            for (comp, r) in rhs.iter_mut().enumerate() {
                r[il] += dl * target[comp];
            }
            for (q, &kq) in lb.indices.iter().enumerate() {
                kmat[(il, local[&kq])] += dl * lb.d(q, 0, 0);
            }
        }
    }
    let gram = seminorm_gram(space, opts.m, &hcells)?;
    for (i, j, v) in gram.triplets() {
        kmat[(local[&i], local[&j])] += opts.epsilon * v;
    }

    let edges = interfaces(space, hole_cells);
    let mut report = FillReport {
        unknowns: mu,
        data_in_hole: m1,
        ..Default::default()
    };
    let mut sigma2 = sigma1.clone();
    match opts.variant {
        FillVariant::Paper => {
            // C_h: knots on ∂H_h (interface edges); D_h: those that are not vertices of the
            // boundary polygon (exactly two interface edges, both with the same normal).
            let mut knots: BTreeMap<(usize, usize), (Cell, Vec<usize>)> = BTreeMap::new();
            for e in &edges {
                for node in [e.from, e.to] {
                    knots
                        .entry(node)
                        .or_insert((e.inside, vec![]))
                        .1
                        .push(e.normal);
                }
            }
            let (bx, by) = (g.x.breaks(), g.y.breaks());
            let mut rows: Vec<(Cell, f64, f64, usize, usize)> = vec![];
            for (&(p, q), (cell, normals)) in &knots {
                rows.push((*cell, bx[p], by[q], 0, 0));
                if normals.len() == 2 && normals[0] == normals[1] {
                    let (a, b) = if normals[0] == 0 { (1, 0) } else { (0, 1) };
                    rows.push((*cell, bx[p], by[q], a, b));
                }
            }
            let mut cmat = Mat::<f64>::zeros(rows.len(), mu);
            let mut d = vec![vec![0.0; rows.len()]; 3];
            for (r, &(cell, x, y, a, b)) in rows.iter().enumerate() {
                let lb = space.eval_on_cell(cell, x, y, 1);
                for (l, &k) in lb.indices.iter().enumerate() {
                    cmat[(r, local[&k])] = lb.d(l, a, b);
                }
                let t = sigma1.eval_on_cell(space, cell, x, y, a, b)?;
                for comp in 0..3 {
                    d[comp][r] = t[comp];
                }
            }
            let sol = minimize_with_equalities(&kmat, &cmat, &rhs, &d)?;
            report.constraints = sol.rows;
            report.constraint_rank = sol.rank;
            report.constraint_residual = sol.constraint_residual;
            report.lambda_norm = sol.lambda.iter().flatten().fold(0.0, |m, x| m.max(x.abs()));
            for comp in 0..3 {
                for (l, &k) in active.iter().enumerate() {
                    sigma2.coeffs[comp][k] = sol.beta[comp][l];
                }
            }
        }
        FillVariant::ExactC1 => {
            // Free: functions whose whole support is in H_h.
            let inside = |k: usize| {
                let (lo, hi) = space.support(k);
                (lo.i..=hi.i)
                    .all(|i| (lo.j..=hi.j).all(|j| hole_cells[g.cell_index(Cell { i, j })]))
            };
            let free: Vec<usize> = (0..mu).filter(|&l| inside(active[l])).collect();
            let fixed: Vec<usize> = (0..mu).filter(|&l| !inside(active[l])).collect();
            report.unknowns = free.len();
            if !free.is_empty() {
                let nf = free.len();
                let kff = Mat::<f64>::from_fn(nf, nf, |i, j| kmat[(free[i], free[j])]);
                let mut r = vec![vec![0.0; nf]; 3];
                for comp in 0..3 {
                    for (i, &fi) in free.iter().enumerate() {
                        r[comp][i] = rhs[comp][fi]
                            - fixed
                                .iter()
                                .map(|&xj| kmat[(fi, xj)] * sigma1.coeffs[comp][active[xj]])
                                .sum::<f64>();
                    }
                }
                let empty = Mat::<f64>::zeros(0, nf);
                let sol = minimize_with_equalities(&kff, &empty, &r, &[vec![], vec![], vec![]])?;
                for comp in 0..3 {
                    for (i, &fi) in free.iter().enumerate() {
                        sigma2.coeffs[comp][active[fi]] = sol.beta[comp][i];
                    }
                }
            }
        }
    }

    let (c0, c1) = border_jumps(space, sigma1, &sigma2, hole_cells)?;
    report.c0_jump = c0;
    report.c1_jump = c1;
    Ok(HoleFill {
        sigma1: sigma1.clone(),
        sigma2,
        hole_cells: hole_cells.to_vec(),
        report,
    })
}

/// The largest jumps (C⁰, C¹ in the normal direction) between σ₂ on H_h and σ₁ outside,
/// across ∂H_h, sampled at 5 points per interface edge: how continuous the filled σ is.
///
/// Errors: `InvalidInput` if a spline does not match the space.
pub fn border_jumps(
    space: &dyn Space,
    sigma1: &VectorSpline,
    sigma2: &VectorSpline,
    hole_cells: &[bool],
) -> Result<(f64, f64)> {
    let g = space.grid();
    let (mut c0, mut c1) = (0.0f64, 0.0f64);
    let (bx, by) = (g.x.breaks(), g.y.breaks());
    for e in &interfaces(space, hole_cells) {
        for t in [0.0, 0.25, 0.5, 0.75, 1.0] {
            let x = bx[e.from.0] + t * (bx[e.to.0] - bx[e.from.0]);
            let y = by[e.from.1] + t * (by[e.to.1] - by[e.from.1]);
            let (a, b) = if e.normal == 0 { (1, 0) } else { (0, 1) };
            let v2 = sigma2.eval_on_cell(space, e.inside, x, y, 0, 0)?;
            let v1 = sigma1.eval_on_cell(space, e.outside, x, y, 0, 0)?;
            let n2 = sigma2.eval_on_cell(space, e.inside, x, y, a, b)?;
            let n1 = sigma1.eval_on_cell(space, e.outside, x, y, a, b)?;
            let dist = |p: [f64; 3], q: [f64; 3]| {
                ((0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>()).sqrt()
            };
            c0 = c0.max(dist(v2, v1));
            c1 = c1.max(dist(n2, n1));
        }
    }
    Ok((c0, c1))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::fit::smoothing::{smoothing_spline, SmoothingOptions};
    use crate::spline::{Partition, TensorSpace};
    use crate::tolerance::{ROUND_OFF, SOLVE};

    fn space() -> TensorSpace<crate::spline::BSpline1d> {
        let u = |n| Partition::uniform(0.0, 1.0, n).unwrap();
        TensorSpace::bspline(u(6), u(6), 2).unwrap()
    }

    fn lattice(k: usize) -> Vec<[f64; 2]> {
        (0..k * k)
            .map(|i| {
                [
                    ((i / k) as f64 + 0.5) / k as f64,
                    ((i % k) as f64 + 0.5) / k as f64,
                ]
            })
            .collect()
    }

    /// The 2 × 2-cell square hole [1/3, 2/3]² of a 6 × 6 grid.
    fn square_hole(s: &dyn Space) -> Vec<bool> {
        let g = s.grid();
        g.cells()
            .map(|c| (2..4).contains(&c.i) && (2..4).contains(&c.j))
            .collect()
    }

    fn sigma1(s: &dyn Space, f: impl Fn(f64, f64) -> [f64; 3]) -> (VectorSpline, Vec<[f64; 2]>) {
        let pts = lattice(30);
        let vals: Vec<[f64; 3]> = pts.iter().map(|p| f(p[0], p[1])).collect();
        let o = SmoothingOptions {
            epsilon: 1e-9,
            m: 2,
            domain: None,
        };
        (
            smoothing_spline(s, &pts, &vals, &[], &o).unwrap().spline,
            pts,
        )
    }

    #[test]
    fn rectangular_hole_has_dependent_constraints_and_a_unique_beta() {
        // σ₁ affine ⇒ σ₂ = σ₁ is feasible with J₂ = 0, the unique minimum, although the
        // constraints of (14) are linearly dependent on a rectangle of cells.
        let s = space();
        let f = |x: f64, y: f64| [1.0 + x - 2.0 * y, 3.0 * x, 0.5 - y];
        let (s1, pts) = sigma1(&s, f);
        let mask = square_hole(&s);
        let opts = FillOptions {
            epsilon: 1e-9,
            m: 2,
            variant: FillVariant::Paper,
        };
        let fill = fill_hole(&s, &s1, &pts, &mask, &opts).unwrap();
        let r = &fill.report;
        // 8 boundary knots (values) + 4 non-corner knots (normal derivatives).
        assert_eq!(r.constraints, 12);
        assert!(
            r.constraint_rank < r.constraints,
            "rank {} of {}",
            r.constraint_rank,
            r.constraints
        );
        assert_near!(r.constraint_residual, 0.0, SOLVE);
        for p in [[0.4, 0.4], [0.5, 0.6], [0.66, 0.35]] {
            let got = fill.eval(&s, p[0], p[1], 0, 0).unwrap();
            let want = f(p[0], p[1]);
            for c in 0..3 {
                assert_near!(got[c], want[c], SOLVE);
            }
        }
    }

    #[test]
    fn paper_variant_meets_the_boundary_data_at_the_knots() {
        let s = space();
        let f = |x: f64, y: f64| [(3.0 * x).sin() * y, x * x + y * y * y, (x * y).exp()];
        let (s1, pts) = sigma1(&s, f);
        // An L-shaped hole: cells (2,2), (3,2), (2,3).
        let g = s.grid();
        let mask: Vec<bool> = g
            .cells()
            .map(|c| matches!((c.i, c.j), (2, 2) | (3, 2) | (2, 3)))
            .collect();
        let opts = FillOptions {
            epsilon: 1e-9,
            m: 2,
            variant: FillVariant::Paper,
        };
        let fill = fill_hole(&s, &s1, &pts, &mask, &opts).unwrap();
        assert_near!(fill.report.constraint_residual, 0.0, SOLVE);
        // Knot (x, y) = (1/3, 1/2) on the left side of cell (2, 3): a non-corner knot? It is
        // where the left sides of (2,2) and (2,3) meet: value and ∂/∂x are imposed.
        let (x, y) = (2.0 / 6.0, 3.0 / 6.0);
        let inside = fill
            .sigma2
            .eval_on_cell(&s, Cell { i: 2, j: 3 }, x, y, 0, 0)
            .unwrap();
        let outside = s1
            .eval_on_cell(&s, Cell { i: 1, j: 3 }, x, y, 0, 0)
            .unwrap();
        let dxi = fill
            .sigma2
            .eval_on_cell(&s, Cell { i: 2, j: 3 }, x, y, 1, 0)
            .unwrap();
        let dxo = s1
            .eval_on_cell(&s, Cell { i: 1, j: 3 }, x, y, 1, 0)
            .unwrap();
        for c in 0..3 {
            assert_near!(inside[c], outside[c], SOLVE);
            assert_near!(dxi[c], dxo[c], SOLVE);
        }
    }

    #[test]
    fn exact_c1_variant_is_c1_across_the_boundary() {
        let s = space();
        let f = |x: f64, y: f64| [(3.0 * x).sin() * y, x * x + y * y * y, (x * y).exp()];
        let (s1, pts) = sigma1(&s, f);
        // A 4 × 4-cell hole: a biquadratic B-spline spans 3 cells per direction, so
        // 2 × 2 of them are supported inside it.
        let mask: Vec<bool> = s
            .grid()
            .cells()
            .map(|c| (1..5).contains(&c.i) && (1..5).contains(&c.j))
            .collect();
        let opts = FillOptions {
            epsilon: 1e-9,
            m: 2,
            variant: FillVariant::ExactC1,
        };
        let fill = fill_hole(&s, &s1, &pts, &mask, &opts).unwrap();
        assert_eq!(fill.report.unknowns, 4);
        assert_near!(fill.report.c0_jump, 0.0, ROUND_OFF);
        assert_near!(fill.report.c1_jump, 0.0, ROUND_OFF);
    }

    #[test]
    fn ill_posed_fills_are_errors() {
        let s = space();
        let (s1, pts) = sigma1(&s, |x, y| [x, y, 0.0]);
        let all = vec![true; s.grid().cell_count()];
        let none = vec![false; s.grid().cell_count()];
        let o = FillOptions {
            epsilon: 1e-9,
            m: 2,
            variant: FillVariant::Paper,
        };
        assert!(fill_hole(&s, &s1, &pts, &all, &o).is_err());
        assert!(fill_hole(&s, &s1, &pts, &none, &o).is_err());
        let bad = FillOptions { epsilon: 0.0, ..o };
        assert!(fill_hole(&s, &s1, &pts, &square_hole(&s), &bad).is_err());
    }
}
