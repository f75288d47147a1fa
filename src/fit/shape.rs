//! Shape-preserving hole filling of the 2024 paper §4 (problems (10)–(11)): σ̄₂ minimizes
//! |v|ₘ,H_h over the Bogner–Fox–Schmit space on H_h, with every degree of freedom of the
//! nodes on ∂H_h interpolating a given spline (σ̄₁ = σ₁ − offset terms), and inequality
//! constraints τ L(v)(x) ≥ 0 — positivity, monotonicity in x and/or y of one component —
//! at the inner knots of H_h and at extra points of its cells (the pseudo-preserving set
//! Γ_h of (11), enlarged). A convex QP solved by clarabel; unconstrained components are
//! plain equality-constrained minimizations.

use std::collections::BTreeMap;

use serde::Serialize;

use faer::Mat;

use crate::error::{Error, Result, SolverFailure};
use crate::linalg::{minimize_with_equalities, solve_qp};
use crate::spline::{seminorm_gram, Basis1d, Cell, Hermite1d, Space, TensorSpace};

use super::surface::VectorSpline;

/// The sign τ = ±1 of a shape condition τ L(v)(x) ≥ 0 of (10): `Plus` asks for L(v) ≥ 0
/// (positive, increasing), `Minus` for L(v) ≤ 0 (negative, decreasing).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Tau {
    Plus,
    Minus,
}

impl Tau {
    /// τ as a number.
    pub fn factor(self) -> f64 {
        match self {
            Tau::Plus => 1.0,
            Tau::Minus => -1.0,
        }
    }
}

/// An extra constraint point (u, v) of Γ_h, with a label that names where it came from
/// (for instance `points.csv line 4`) so an error can point at it.
#[derive(Debug, Clone, PartialEq)]
pub struct ShapePoint {
    pub uv: [f64; 2],
    pub label: String,
}

/// The shape conditions of (10) on one component: each of L(v) = v, ∂v/∂x, ∂v/∂y is
/// either not imposed (`None`) or imposed with its sign τ.
#[derive(Debug, Clone, PartialEq)]
pub struct ShapeConstraints {
    /// The component (0, 1, 2) the conditions apply to.
    pub component: usize,
    /// τ⁰₀: τ v ≥ 0 (positivity for `Plus`).
    pub value: Option<Tau>,
    /// τ¹₀: τ ∂v/∂x ≥ 0 (monotonicity in x).
    pub slope_x: Option<Tau>,
    /// τ¹₁: τ ∂v/∂y ≥ 0 (monotonicity in y).
    pub slope_y: Option<Tau>,
    /// Extra constraint points per cell side (a k × k lattice inside each H_h cell).
    pub extra_per_side: usize,
    /// Extra constraint points given one by one; each must lie in a cell of H_h.
    pub extra_points: Vec<ShapePoint>,
}

/// What the shape-preserving filling did.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ShapeReport {
    /// Free coefficients per component.
    pub unknowns: usize,
    /// Inequality constraints imposed (points × conditions).
    pub inequalities: usize,
    /// The worst violation max(0, −τL(σ̄₂)(x)) over the imposed constraints, evaluated on
    /// the solved spline (not taken from the solver).
    pub max_violation: f64,
    /// Imposed constraints with τL(σ̄₂)(x) < 0, however small.
    pub violated: usize,
    /// The largest violation accepted: clarabel's primal feasibility tolerance scaled as it
    /// scales it (a larger one is an error).
    pub tolerance: f64,
    /// clarabel's status.
    pub status: String,
}

/// σ̄₂ and its report.
#[derive(Debug, Clone)]
pub struct ShapeFill {
    /// σ̄₂: coefficients of the nodes of H_h (others copied from the boundary spline).
    pub spline: VectorSpline,
    /// H_h by cell linear index.
    pub hole_cells: Vec<bool>,
    /// The report.
    pub report: ShapeReport,
}

/// Most extra constraint points of a lattice (each is a row of the QP for every imposed
/// condition): checked before anything is allocated.
pub const MAX_LATTICE_POINTS: usize = 1 << 20;

/// Solves (11) of the 2024 paper on the BFS space `space`.
///
/// `boundary` is a spline of `space` whose nodal degrees of freedom on ∂H_h are
/// interpolated (the 𝓛ᵢ(σ̄₁) of (10)); only those are read. `m` is the semi-norm order.
/// Preconditions (`InvalidInput` otherwise): mask of the grid's size with some but not all
/// cells; `boundary` matching the space; a component index < 3; 1 ≤ m ≤ degree.
/// Errors: `Solver { Infeasible }` when the boundary data contradict the shape conditions;
/// `Solver { NotConverged | NotPositiveDefinite }` from the solvers.
pub fn shape_preserving_fill(
    space: &TensorSpace<Hermite1d>,
    boundary: &VectorSpline,
    hole_cells: &[bool],
    m: usize,
    shape: &ShapeConstraints,
) -> Result<ShapeFill> {
    let g = space.grid();
    if hole_cells.len() != g.cell_count() {
        return Err(Error::InvalidInput(
            "hole mask does not match the grid".into(),
        ));
    }
    let nh = hole_cells.iter().filter(|&&b| b).count();
    if nh == 0 || nh == hole_cells.len() {
        return Err(Error::InvalidInput(format!(
            "the hole covers {nh} of {} cells: it must cover some but not all",
            hole_cells.len()
        )));
    }
    if boundary.coeffs.iter().any(|c| c.len() != space.dim()) || shape.component > 2 {
        return Err(Error::InvalidInput(
            "boundary spline does not match the space, or component index > 2".into(),
        ));
    }
    let lattice_points = nh
        .saturating_mul(shape.extra_per_side)
        .saturating_mul(shape.extra_per_side);
    if lattice_points > MAX_LATTICE_POINTS {
        return Err(Error::InvalidInput(format!(
            "a {k} × {k} lattice of extra constraint points in each of {nh} hole cells makes \
             {lattice_points} points: at most {MAX_LATTICE_POINTS} are supported",
            k = shape.extra_per_side
        )));
    }
    let (nx, ny) = g.shape();
    let hcells: Vec<Cell> = g.cells().filter(|&c| hole_cells[g.cell_index(c)]).collect();
    // A node is free if every cell around it is in H_h (so it is not on ∂H_h and not on ∂R).
    let node_free = |p: usize, q: usize| -> bool {
        if p == 0 || q == 0 || p == nx || q == ny {
            return false;
        }
        [(p - 1, q - 1), (p, q - 1), (p - 1, q), (p, q)]
            .iter()
            .all(|&(i, j)| hole_cells[g.cell_index(Cell { i, j })])
    };
    let d = space.x_basis().dofs_per_node();
    let ndy = space.y_basis().dim();
    let node_of = |k: usize| ((k / ndy) / d, (k % ndy) / d);
    let mut local: BTreeMap<usize, usize> = BTreeMap::new();
    for &c in &hcells {
        for k in space.cell_functions(c) {
            let n = local.len();
            local.entry(k).or_insert(n);
        }
    }
    let mut active = vec![0; local.len()];
    for (&k, &l) in &local {
        active[l] = k;
    }
    let free: Vec<usize> = (0..active.len())
        .filter(|&l| {
            let (p, q) = node_of(active[l]);
            node_free(p, q)
        })
        .collect();
    // Constraint points Γ_h: the free nodes, a k × k lattice inside every H_h cell, and the
    // extra points (each in an H_h cell that contains it).
    let (bx, by) = (g.x.breaks(), g.y.breaks());
    let mut pts: Vec<(Cell, f64, f64)> = vec![];
    for &c in &hcells {
        let ([x0, x1], [y0, y1]) = g.cell_bounds(c);
        let k = shape.extra_per_side;
        for a in 1..=k {
            for b in 1..=k {
                let (s, t) = (a as f64 / (k + 1) as f64, b as f64 / (k + 1) as f64);
                pts.push((c, x0 + s * (x1 - x0), y0 + t * (y1 - y0)));
            }
        }
        // The cell's lower-left corner if it is a free node (each free node is the
        // lower-left corner of exactly one H_h cell).
        if node_free(c.i, c.j) {
            pts.push((c, bx[c.i], by[c.j]));
        }
    }
    for p in &shape.extra_points {
        let [x, y] = p.uv;
        let inside = hcells.iter().find(|&&c| {
            let ([x0, x1], [y0, y1]) = g.cell_bounds(c);
            (x0..=x1).contains(&x) && (y0..=y1).contains(&y)
        });
        match inside {
            Some(&c) => pts.push((c, x, y)),
            None => {
                return Err(Error::InvalidInput(format!(
                    "{}: constraint point ({x}, {y}) is not in the hole H_h ({nh} cells); \
                     shape conditions apply inside the filled cells only",
                    p.label
                )))
            }
        }
    }
    // (L as derivative orders, τ): v, ∂v/∂x, ∂v/∂y.
    let ops: Vec<Op> = [
        (shape.value, (0, 0)),
        (shape.slope_x, (1, 0)),
        (shape.slope_y, (0, 1)),
    ]
    .iter()
    .filter_map(|&(t, o)| t.map(|t| (o, t.factor())))
    .collect();

    let mut spline = boundary.clone();
    let mut report = ShapeReport {
        unknowns: free.len(),
        inequalities: pts.len() * ops.len(),
        status: "no free coefficient".into(),
        ..Default::default()
    };
    let comp = shape.component;
    if !free.is_empty() {
        let gram = seminorm_gram(space, m, &hcells)?;
        let mut pos_free = vec![usize::MAX; active.len()];
        for (i, &l) in free.iter().enumerate() {
            pos_free[l] = i;
        }
        let nf = free.len();
        let mut kff = Mat::<f64>::zeros(nf, nf);
        let mut qs = vec![vec![0.0; nf]; 3];
        for (i, j, v) in gram.triplets() {
            let (li, lj) = (local[&i], local[&j]);
            let fi = pos_free[li];
            if fi == usize::MAX {
                continue;
            }
            let fj = pos_free[lj];
            if fj != usize::MAX {
                kff[(fi, fj)] += v;
            } else {
                for (comp, q) in qs.iter_mut().enumerate() {
                    q[fi] += v * boundary.coeffs[comp][j];
                }
            }
        }
        // Unconstrained components: Kff β = −q.
        let neg: Vec<Vec<f64>> = qs.iter().map(|q| q.iter().map(|x| -x).collect()).collect();
        let empty = Mat::<f64>::zeros(0, nf);
        let sol = minimize_with_equalities(&kff, &empty, &neg, &[vec![], vec![], vec![]])?;
        for comp in 0..3 {
            for (i, &l) in free.iter().enumerate() {
                spline.coeffs[comp][active[l]] = sol.beta[comp][i];
            }
        }
        report.status = "no shape condition".into();
        if !ops.is_empty() {
            let mut a_entries = vec![];
            let mut b = vec![];
            for &(c, x, y) in &pts {
                let lb = space.eval_on_cell(c, x, y, 1);
                for &((da, db), tau) in &ops {
                    // τL(v) ≥ 0 as −τ Σ_free L(φₗ) β ≤ τ Σ_fixed L(φₗ) c.
                    let row = b.len();
                    let mut rhs = 0.0;
                    for (l, &k) in lb.indices.iter().enumerate() {
                        let v = tau * lb.d(l, da, db);
                        let f = pos_free[local[&k]];
                        if f != usize::MAX {
                            a_entries.push((row, f, -v));
                        } else {
                            rhs += v * boundary.coeffs[comp][k];
                        }
                    }
                    b.push(rhs);
                }
            }
            let mut p_entries = vec![];
            for i in 0..nf {
                for j in i..nf {
                    if kff[(i, j)] != 0.0 {
                        p_entries.push((i, j, kff[(i, j)]));
                    }
                }
            }
            let qp =
                solve_qp(nf, &p_entries, &qs[comp], b.len(), &a_entries, &b).map_err(
                    |e| match e {
                        Error::Solver {
                            failure: SolverFailure::Infeasible,
                            detail,
                        } => Error::Solver {
                            failure: SolverFailure::Infeasible,
                            detail: format!(
                                "{detail}: the border data (σ₁'s nodal values and derivatives on \
                             ∂H_h) contradict the shape conditions ({}) at the {} constraint \
                             points; drop a condition or choose another hole",
                                describe(&ops, comp),
                                pts.len()
                            ),
                        },
                        e => e,
                    },
                )?;
            for (i, &l) in free.iter().enumerate() {
                spline.coeffs[comp][active[l]] = qp.x[i];
            }
            report.tolerance = qp.violation_tolerance;
            report.status = qp.status;
        }
    }
    // The check, on the solved spline itself: τL(σ̄₂)(x) at every constraint point.
    let mut worst: Option<(f64, f64, f64, Op)> = None;
    let mut values = vec![];
    for &(c, x, y) in &pts {
        for &((da, db), tau) in &ops {
            let l = tau * spline.eval_on_cell(space, c, x, y, da, db)?[comp];
            values.push(l);
            if l < 0.0 {
                report.violated += 1;
                if worst.is_none_or(|w| -l > w.0) {
                    worst = Some((-l, x, y, ((da, db), tau)));
                }
            }
        }
    }
    report.max_violation = worst.map_or(0.0, |w| w.0);
    if report.tolerance == 0.0 {
        // No QP was solved (no free coefficient): the values are fixed by the boundary, so
        // only round-off of their evaluation is allowed.
        let scale = values.iter().fold(1.0f64, |m, v| m.max(v.abs()));
        report.tolerance = crate::tolerance::ROUND_OFF * scale;
    }
    if let Some((w, x, y, op)) = worst.filter(|w| w.0 > report.tolerance) {
        let what = describe(&[op], comp);
        let failure = if free.is_empty() {
            SolverFailure::Infeasible
        } else {
            SolverFailure::NotConverged
        };
        return Err(Error::Solver {
            failure,
            detail: format!(
                "shape condition {what} violated by {w:.3e} at ({x}, {y}) \
                 (tolerance {:.3e}; {} of {} constraints violated{})",
                report.tolerance,
                report.violated,
                report.inequalities,
                if free.is_empty() {
                    "; the hole has no free coefficient, so the boundary data decide"
                } else {
                    ""
                }
            ),
        });
    }
    Ok(ShapeFill {
        spline,
        hole_cells: hole_cells.to_vec(),
        report,
    })
}

/// A condition: L as the derivative orders (a, b) of ∂ᵃ⁺ᵇv/∂xᵃ∂yᵇ, and τ.
type Op = ((usize, usize), f64);

/// The conditions for messages: `τ∂v/∂x ≥ 0 with τ = −1 on z`.
fn describe(ops: &[Op], comp: usize) -> String {
    ops.iter()
        .map(|&(d, tau)| {
            let l = match d {
                (0, 0) => "v",
                (1, 0) => "∂v/∂x",
                _ => "∂v/∂y",
            };
            format!(
                "τ{l} ≥ 0 with τ = {} on {}",
                if tau < 0.0 { "−1" } else { "+1" },
                ["x", "y", "z"][comp]
            )
        })
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::spline::Partition;
    use crate::tolerance::{FINITE_DIFFERENCE, SOLVE};

    /// BFS C¹ interpolant of three functions given with (v, ∂x, ∂y, ∂xy).
    fn interpolant(
        s: &TensorSpace<Hermite1d>,
        f: &dyn Fn(f64, f64) -> [[f64; 4]; 3],
    ) -> VectorSpline {
        let mut v = VectorSpline::zeros(s.dim());
        let (xs, ys) = (s.grid().x.breaks().to_vec(), s.grid().y.breaks().to_vec());
        for (p, &x) in xs.iter().enumerate() {
            for (q, &y) in ys.iter().enumerate() {
                let d = f(x, y);
                for (c, dc) in v.coeffs.iter_mut().zip(d) {
                    for (k, (kx, ky)) in [(0, 0), (1, 0), (0, 1), (1, 1)].into_iter().enumerate() {
                        c[s.node_dof(p, q, kx, ky)] = dc[k];
                    }
                }
            }
        }
        v
    }

    fn setup() -> (TensorSpace<Hermite1d>, Vec<bool>) {
        let u = Partition::uniform(0.0, 1.0, 6).unwrap();
        let s = TensorSpace::bfs_c1(u.clone(), u).unwrap();
        let mask = s
            .grid()
            .cells()
            .map(|c| (1..5).contains(&c.i) && (1..5).contains(&c.j))
            .collect();
        (s, mask)
    }

    const ALL: ShapeConstraints = ShapeConstraints {
        component: 2,
        value: Some(Tau::Plus),
        slope_x: Some(Tau::Plus),
        slope_y: Some(Tau::Plus),
        extra_per_side: 3,
        extra_points: Vec::new(),
    };

    #[test]
    fn affine_data_is_reproduced() {
        let (s, mask) = setup();
        let f = |x: f64, y: f64| {
            [
                [x, 1.0, 0.0, 0.0],
                [y, 0.0, 1.0, 0.0],
                [1.0 + 2.0 * x + y, 2.0, 1.0, 0.0],
            ]
        };
        let b = interpolant(&s, &f);
        let fill = shape_preserving_fill(&s, &b, &mask, 2, &ALL).unwrap();
        assert_eq!(fill.report.unknowns, 9 * 4);
        for p in [[0.4, 0.5], [0.5, 0.5], [0.7, 0.3]] {
            let got = fill.spline.eval(&s, p[0], p[1], 0, 0).unwrap();
            assert_near!(got[0], p[0], SOLVE);
            assert_near!(got[1], p[1], SOLVE);
            assert_near!(got[2], 1.0 + 2.0 * p[0] + p[1], FINITE_DIFFERENCE);
        }
    }

    #[test]
    fn positivity_is_enforced_where_the_energy_minimizer_dips_below_zero() {
        // z = (x − ½)² + (y − ½)² − 0.02 is positive on ∂H_h = ∂[1/6, 5/6]² but −0.02 at
        // the centre; without conditions the minimizer of |v|₂ is z itself (a quadratic
        // with all boundary dofs fixed), with positivity it must stay ≥ 0.
        let (s, mask) = setup();
        let f = |x: f64, y: f64| {
            let z = (x - 0.5).powi(2) + (y - 0.5).powi(2) - 0.02;
            [
                [x, 1.0, 0.0, 0.0],
                [y, 0.0, 1.0, 0.0],
                [z, 2.0 * (x - 0.5), 2.0 * (y - 0.5), 0.0],
            ]
        };
        let b = interpolant(&s, &f);
        let none = ShapeConstraints {
            value: None,
            slope_x: None,
            slope_y: None,
            ..ALL
        };
        let free = shape_preserving_fill(&s, &b, &mask, 2, &none).unwrap();
        assert_near!(
            free.spline.eval(&s, 0.5, 0.5, 0, 0).unwrap()[2],
            -0.02,
            SOLVE
        );
        let pos = ShapeConstraints {
            slope_x: None,
            slope_y: None,
            ..ALL
        };
        let fill = shape_preserving_fill(&s, &b, &mask, 2, &pos).unwrap();
        assert!(fill.report.inequalities > 0);
        assert!(
            fill.report.max_violation <= FINITE_DIFFERENCE,
            "{}",
            fill.report.max_violation
        );
        // The centre is a free node and a constraint point.
        assert!(fill.spline.eval(&s, 0.5, 0.5, 0, 0).unwrap()[2] >= -FINITE_DIFFERENCE);
    }

    #[test]
    fn contradicting_boundary_data_is_infeasible() {
        // z decreasing in x on the whole boundary, but ∂z/∂x ≥ 0 demanded inside.
        let (s, mask) = setup();
        let f = |x: f64, y: f64| [[x, 1.0, 0.0, 0.0], [y, 0.0, 1.0, 0.0], [-x, -1.0, 0.0, 0.0]];
        let b = interpolant(&s, &f);
        let inc = ShapeConstraints {
            value: None,
            slope_y: None,
            ..ALL
        };
        assert!(matches!(
            shape_preserving_fill(&s, &b, &mask, 2, &inc),
            Err(Error::Solver { .. })
        ));
    }

    #[test]
    fn negative_sign_and_extra_points() {
        // τ = −1 on the bowl of the positivity test turned over: −z ≤ 0 ⇔ z ≥ 0, so the
        // solution is the mirror image of the positive one; an extra point adds one
        // inequality per condition, a point outside H_h is refused with its label.
        let (s, mask) = setup();
        let f = |x: f64, y: f64| {
            let z = 0.02 - (x - 0.5).powi(2) - (y - 0.5).powi(2);
            [
                [x, 1.0, 0.0, 0.0],
                [y, 0.0, 1.0, 0.0],
                [z, -2.0 * (x - 0.5), -2.0 * (y - 0.5), 0.0],
            ]
        };
        let b = interpolant(&s, &f);
        let neg = ShapeConstraints {
            value: Some(Tau::Minus),
            slope_x: None,
            slope_y: None,
            ..ALL
        };
        let base = shape_preserving_fill(&s, &b, &mask, 2, &neg).unwrap();
        assert!(base.spline.eval(&s, 0.5, 0.5, 0, 0).unwrap()[2] <= FINITE_DIFFERENCE);
        let more = ShapeConstraints {
            extra_points: vec![ShapePoint {
                uv: [0.45, 0.55],
                label: "p".into(),
            }],
            ..neg.clone()
        };
        let with = shape_preserving_fill(&s, &b, &mask, 2, &more).unwrap();
        assert_eq!(with.report.inequalities, base.report.inequalities + 1);
        let outside = ShapeConstraints {
            extra_points: vec![ShapePoint {
                uv: [0.05, 0.5],
                label: "the point".into(),
            }],
            ..neg
        };
        let e = shape_preserving_fill(&s, &b, &mask, 2, &outside).unwrap_err();
        assert!(
            e.to_string()
                .contains("the point: constraint point (0.05, 0.5) is not in the hole"),
            "{e}"
        );
    }
}
