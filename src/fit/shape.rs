//! Shape-preserving hole filling of the 2024 paper §4 (problems (10)–(11)): σ̄₂ minimizes
//! |v|ₘ,H_h over the Bogner–Fox–Schmit space on H_h, with every degree of freedom of the
//! nodes on ∂H_h interpolating a given spline (σ̄₁ = σ₁ − offset terms), and inequality
//! constraints τ L(v)(x) ≥ 0 — positivity, monotonicity in x and/or y of one component —
//! at the inner knots of H_h and at extra points of its cells (the pseudo-preserving set
//! Γ_h of (11), enlarged). A convex QP solved by clarabel; unconstrained components are
//! plain equality-constrained minimizations.

use std::collections::BTreeMap;

use faer::Mat;

use crate::error::{Error, Result};
use crate::linalg::{minimize_with_equalities, solve_qp};
use crate::spline::{seminorm_gram, Basis1d, Cell, Hermite1d, Space, TensorSpace};

use super::surface::VectorSpline;

/// The shape conditions τ of (10): which L(v) ≥ 0 to impose on one component.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ShapeConstraints {
    /// The component (0, 1, 2) the conditions apply to.
    pub component: usize,
    /// τ⁰₀: v ≥ 0.
    pub positive: bool,
    /// τ¹₀: ∂v/∂x ≥ 0.
    pub increasing_x: bool,
    /// τ¹₁: ∂v/∂y ≥ 0.
    pub increasing_y: bool,
    /// Extra constraint points per cell side (a k × k lattice inside each H_h cell).
    pub extra_per_side: usize,
}

/// What the shape-preserving filling did.
#[derive(Debug, Clone, Default)]
pub struct ShapeReport {
    /// Free coefficients per component.
    pub unknowns: usize,
    /// Inequality constraints imposed.
    pub inequalities: usize,
    /// The worst violation max(0, −τL(σ̄₂)(x)) over the imposed constraints.
    pub max_violation: f64,
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
    let mut spline = boundary.clone();
    let mut report = ShapeReport {
        unknowns: free.len(),
        status: "no free coefficient".into(),
        ..Default::default()
    };
    if free.is_empty() {
        return Ok(ShapeFill {
            spline,
            hole_cells: hole_cells.to_vec(),
            report,
        });
    }
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

    // Constraint points: the free nodes and a lattice inside every H_h cell.
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
    let ops: Vec<(usize, usize)> = [
        (shape.positive, (0, 0)),
        (shape.increasing_x, (1, 0)),
        (shape.increasing_y, (0, 1)),
    ]
    .iter()
    .filter(|(on, _)| *on)
    .map(|&(_, o)| o)
    .collect();
    if ops.is_empty() {
        report.status = "no shape condition".into();
        return Ok(ShapeFill {
            spline,
            hole_cells: hole_cells.to_vec(),
            report,
        });
    }
    let comp = shape.component;
    let mut a_entries = vec![];
    let mut b = vec![];
    for &(c, x, y) in &pts {
        let lb = space.eval_on_cell(c, x, y, 1);
        for &(da, db) in &ops {
            // −Σ_free φₗ β ≤ Σ_fixed φₗ c
            let row = b.len();
            let mut rhs = 0.0;
            for (l, &k) in lb.indices.iter().enumerate() {
                let v = lb.d(l, da, db);
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
    let qp = solve_qp(nf, &p_entries, &qs[comp], b.len(), &a_entries, &b)?;
    for (i, &l) in free.iter().enumerate() {
        spline.coeffs[comp][active[l]] = qp.x[i];
    }
    report.inequalities = b.len();
    report.max_violation = qp.max_violation;
    report.status = qp.status;
    Ok(ShapeFill {
        spline,
        hole_cells: hole_cells.to_vec(),
        report,
    })
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
        positive: true,
        increasing_x: true,
        increasing_y: true,
        extra_per_side: 3,
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
            positive: false,
            increasing_x: false,
            increasing_y: false,
            ..ALL
        };
        let free = shape_preserving_fill(&s, &b, &mask, 2, &none).unwrap();
        assert_near!(
            free.spline.eval(&s, 0.5, 0.5, 0, 0).unwrap()[2],
            -0.02,
            SOLVE
        );
        let pos = ShapeConstraints {
            increasing_x: false,
            increasing_y: false,
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
            positive: false,
            increasing_y: false,
            ..ALL
        };
        assert!(matches!(
            shape_preserving_fill(&s, &b, &mask, 2, &inc),
            Err(Error::Solver { .. })
        ));
    }
}
