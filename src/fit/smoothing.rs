//! The discrete smoothing variational spline: minimize
//! Σₐ ‖v(a) − pₐ‖² (+ Σₐ Σ_β ‖∂^β v(a) − p^β_a‖² with derivative data) + ε|v|²ₘ,ω
//! over the functions of the space that do not vanish on ω (2022 §3 (6)–(8) with ω = R;
//! 2024 §3 with ω = Ω − H_h and derivative data). One sparse Cholesky factorization of
//! 𝒜𝒜ᵀ + ε𝓡 serves the three components.

use crate::error::{Error, Result};
use crate::linalg::solve_spd;
use crate::spline::{seminorm_gram, Cell, Space, SparseSym};

use super::surface::VectorSpline;

/// Data on one partial derivative ∂ₓᵃ∂ᵧᵇ at every data point (2024 §3: L_j^r, r ≤ k).
#[derive(Debug, Clone)]
pub struct DerivativeData {
    /// Order in x.
    pub a: usize,
    /// Order in y.
    pub b: usize,
    /// ∂ₓᵃ∂ᵧᵇ p at each data point, aligned with the points.
    pub values: Vec<[f64; 3]>,
}

/// Options of [`smoothing_spline`].
#[derive(Debug, Clone)]
pub struct SmoothingOptions {
    /// ε > 0, the weight of the semi-norm.
    pub epsilon: f64,
    /// Order m of the semi-norm |·|ₘ (2 for the C¹ spaces of 2022/2024, 3 for 2004).
    pub m: usize,
    /// The cells of ω; `None` is the whole rectangle R (2022). Data points must lie in ω.
    pub domain: Option<Vec<Cell>>,
}

/// A solved smoothing spline and its report.
#[derive(Debug, Clone)]
pub struct SmoothingFit {
    /// The spline (coefficients of functions vanishing on ω are 0).
    pub spline: VectorSpline,
    /// The basis functions not vanishing on ω (the unknowns).
    pub active: Vec<usize>,
    /// Cells of ω holding no data point (determined by the semi-norm only).
    pub empty_cells: usize,
    /// √(Σ‖σ(a) − pₐ‖² / k): the root-mean-square misfit at the data points.
    pub rms_misfit: f64,
}

/// Solves (8) of the 2022 paper: (𝒜𝒜ᵀ + ε𝓡)α = b, one factorization, three right-hand
/// sides (and the 2024 variant with derivative data).
///
/// Preconditions (checked, each an `InvalidInput` error otherwise): ε > 0 and finite;
/// points and values finite, as many values as points, each derivative-data vector aligned
/// with the points and of order ≤ the space's smoothness; every point inside a cell of ω;
/// the points unisolvent for ℙ_{m−1} (2022 (5), 2024 §3: no non-zero polynomial of degree
/// < m vanishes at all of them), which with ε > 0 makes the problem well posed.
/// Errors: also `Solver { NotPositiveDefinite }` if the factorization breaks down.
pub fn smoothing_spline(
    space: &dyn Space,
    points: &[[f64; 2]],
    values: &[[f64; 3]],
    derivatives: &[DerivativeData],
    opts: &SmoothingOptions,
) -> Result<SmoothingFit> {
    if !(opts.epsilon > 0.0 && opts.epsilon.is_finite()) {
        return Err(Error::InvalidInput(format!(
            "the smoothing parameter ε must be positive and finite, got {}",
            opts.epsilon
        )));
    }
    if opts.m == 0 || opts.m > space.degree() {
        return Err(Error::InvalidInput(format!(
            "semi-norm order m = {} must be in 1..={}",
            opts.m,
            space.degree()
        )));
    }
    if points.len() != values.len() {
        return Err(Error::InvalidInput(format!(
            "{} points but {} values",
            points.len(),
            values.len()
        )));
    }
    for d in derivatives {
        if d.values.len() != points.len() || d.a + d.b == 0 || d.a.max(d.b) > space.smoothness() {
            return Err(Error::InvalidInput(format!(
                "derivative data ∂({}, {}): {} values for {} points, order must be 1..={} per variable",
                d.a,
                d.b,
                d.values.len(),
                points.len(),
                space.smoothness()
            )));
        }
    }
    for (i, (p, v)) in points.iter().zip(values).enumerate() {
        if p.iter().chain(v).any(|x| !x.is_finite())
            || derivatives
                .iter()
                .any(|d| d.values[i].iter().any(|x| !x.is_finite()))
        {
            return Err(Error::InvalidInput(format!("data point {i} is not finite")));
        }
    }
    let grid = space.grid();
    let domain: Vec<Cell> = match &opts.domain {
        Some(c) => c.clone(),
        None => grid.cells().collect(),
    };
    if domain.is_empty() {
        return Err(Error::InvalidInput("the fitting domain has no cell".into()));
    }
    let mut in_domain = vec![false; grid.cell_count()];
    for &c in &domain {
        if c.i >= grid.shape().0 || c.j >= grid.shape().1 {
            return Err(Error::InvalidInput(format!(
                "domain cell ({}, {}) is outside the grid",
                c.i, c.j
            )));
        }
        in_domain[grid.cell_index(c)] = true;
    }
    let mut cells_of_points = Vec::with_capacity(points.len());
    let mut count = vec![0usize; grid.cell_count()];
    for (i, p) in points.iter().enumerate() {
        let c = grid
            .locate(p[0], p[1])
            .filter(|&c| in_domain[grid.cell_index(c)])
            .ok_or_else(|| {
                Error::InvalidInput(format!(
                    "data point {i} ({}, {}) is outside the fitting domain",
                    p[0], p[1]
                ))
            })?;
        count[grid.cell_index(c)] += 1;
        cells_of_points.push(c);
    }
    check_unisolvent(points, opts.m)?;

    // Unknowns: the functions not vanishing on ω; `local[k]` is function k's unknown
    // (usize::MAX for none) — an array, not a map, since it is read for every entry.
    let mut local = vec![usize::MAX; space.dim()];
    let mut active = vec![];
    for &c in &domain {
        for k in space.cell_functions(c) {
            if local[k] == usize::MAX {
                local[k] = active.len();
                active.push(k);
            }
        }
    }
    let n = active.len();
    let mut sys = SparseSym::new(n);
    let mut rhs = vec![vec![0.0; n]; 3];
    let order = derivatives.iter().map(|d| d.a.max(d.b)).max().unwrap_or(0);
    // 𝒜𝒜ᵀ accumulated per cell in a dense block (the local functions of a cell are fixed),
    // scattered into the sparse matrix once per cell.
    let mut blocks: Vec<Option<(Vec<usize>, Vec<f64>)>> = vec![None; grid.cell_count()];
    let mut vals = vec![];
    // Each point's basis values, kept for the misfit after the solve (no re-evaluation).
    let mut point_values: Vec<f64> = Vec::new();
    for (i, (&c, p)) in cells_of_points.iter().zip(points).enumerate() {
        let lb = space.eval_on_cell(c, p[0], p[1], order);
        let nl = lb.indices.len();
        point_values.extend((0..nl).map(|l| lb.d(l, 0, 0)));
        let (loc, block) = blocks[grid.cell_index(c)].get_or_insert_with(|| {
            (
                lb.indices.iter().map(|&k| local[k]).collect(),
                vec![0.0; nl * nl],
            )
        });
        let mut add = |a: usize, b: usize, target: &[f64; 3]| {
            vals.clear();
            vals.extend((0..nl).map(|l| lb.d(l, a, b)));
            for (l, &gl) in loc.iter().enumerate() {
                let dl = vals[l];
                if dl == 0.0 {
                    continue;
                }
                for (comp, r) in rhs.iter_mut().enumerate() {
                    r[gl] += dl * target[comp];
                }
                let row = &mut block[l * nl..(l + 1) * nl];
                for (x, &dq) in row.iter_mut().zip(vals.iter()) {
                    *x += dl * dq;
                }
            }
        };
        add(0, 0, &values[i]);
        for d in derivatives {
            add(d.a, d.b, &d.values[i]);
        }
    }
    let gram = seminorm_gram(space, opts.m, &domain)?;
    sys.reserve(
        blocks
            .iter()
            .flatten()
            .map(|(l, _)| l.len().pow(2))
            .sum::<usize>()
            + gram.entries().len(),
    );
    for (loc, block) in blocks.iter().flatten() {
        let nl = loc.len();
        for (l, &gl) in loc.iter().enumerate() {
            for (q, &gq) in loc.iter().enumerate() {
                sys.add(gl, gq, block[l * nl + q]);
            }
        }
    }
    // Duplicates are summed by `solve_spd`: no sort of the entries here.
    for &(i, j, v) in gram.entries() {
        sys.add(local[i], local[j], opts.epsilon * v);
    }
    let sol = solve_spd(n, sys.entries(), &rhs)?;
    let mut spline = VectorSpline::zeros(space.dim());
    for (comp, s) in sol.iter().enumerate() {
        for (l, &k) in active.iter().enumerate() {
            spline.coeffs[comp][k] = s[l];
        }
    }
    let mut sq = 0.0;
    let mut at = 0;
    for (&c, v) in cells_of_points.iter().zip(values) {
        // Every data point's cell has its block (made in the loop above).
        let Some((loc, _)) = &blocks[grid.cell_index(c)] else {
            continue;
        };
        let phi = &point_values[at..at + loc.len()];
        at += loc.len();
        for (k, vk) in v.iter().enumerate() {
            let s: f64 = loc.iter().zip(phi).map(|(&l, &f)| sol[k][l] * f).sum();
            sq += (s - vk).powi(2);
        }
    }
    let empty_cells = domain
        .iter()
        .filter(|&&c| count[grid.cell_index(c)] == 0)
        .count();
    Ok(SmoothingFit {
        spline,
        active,
        empty_cells,
        rms_misfit: (sq / points.len().max(1) as f64).sqrt(),
    })
}

/// ℙ_{m−1}-unisolvence (2022 (5)): the Vandermonde matrix V of the monomials xⁱyʲ,
/// i + j < m, at the points (centred and scaled) has full column rank.
fn check_unisolvent(points: &[[f64; 2]], m: usize) -> Result<()> {
    let monomials: Vec<(i32, i32)> = (0..m as i32)
        .flat_map(|t| (0..=t).map(move |j| (t - j, j)))
        .collect();
    let q = monomials.len();
    if points.len() < q {
        return Err(Error::InvalidInput(format!(
            "{} data points cannot determine a smoothing spline with |·|_{m}: at least {q} points not on a curve of degree < {m} are needed",
            points.len()
        )));
    }
    let k = points.len() as f64;
    let (cx, cy) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), p| (a + p[0] / k, b + p[1] / k));
    let scale = points
        .iter()
        .fold(0.0f64, |s, p| {
            s.max((p[0] - cx).abs()).max((p[1] - cy).abs())
        })
        .max(f64::MIN_POSITIVE);
    // VᵀV (q × q, q ≤ 10) instead of V itself: its eigenvalues are σᵢ². They carry an
    // absolute error ~ ε_machine·λ_max, so rank deficiency is declared below k·ε·λ_max.
    let mut gram = faer::Mat::<f64>::zeros(q, q);
    let mut row = vec![0.0; q];
    for p in points {
        let (x, y) = ((p[0] - cx) / scale, (p[1] - cy) / scale);
        for (c, &(i, j)) in monomials.iter().enumerate() {
            row[c] = x.powi(i) * y.powi(j);
        }
        for a in 0..q {
            for b in 0..q {
                gram[(a, b)] += row[a] * row[b];
            }
        }
    }
    let s: Vec<f64> = gram
        .self_adjoint_eigenvalues(faer::Side::Lower)
        .map_err(|e| Error::Solver {
            failure: crate::error::SolverFailure::NotConverged,
            detail: format!("eigenvalues of the Vandermonde Gram matrix: {e:?}"),
        })?;
    let smax = s.iter().copied().fold(0.0, f64::max);
    let thresh = points.len().max(q) as f64 * f64::EPSILON * smax;
    if s.iter().any(|&x| x <= thresh) {
        return Err(Error::InvalidInput(format!(
            "the data points are not unisolvent for polynomials of degree < {m} (e.g. all on one line): the smoothing spline is not determined"
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::spline::{Partition, TensorSpace};
    use crate::tolerance::SOLVE;

    fn lattice(k: usize) -> Vec<[f64; 2]> {
        (0..k * k)
            .map(|i| {
                let (a, b) = (i / k, i % k);
                [(a as f64 + 0.5) / k as f64, (b as f64 + 0.3) / k as f64]
            })
            .collect()
    }

    #[test]
    fn affine_data_is_reproduced_for_any_epsilon() {
        // |v|₂ = 0 and zero misfit for an affine v ∈ V_h: the unique minimizer is v.
        let u = |n| Partition::uniform(0.0, 1.0, n).unwrap();
        let s = TensorSpace::bspline(u(4), u(3), 2).unwrap();
        let pts = lattice(12);
        let f = |p: &[f64; 2]| [1.0 + 2.0 * p[0] - p[1], 0.5 * p[1], -3.0 * p[0]];
        let vals: Vec<[f64; 3]> = pts.iter().map(f).collect();
        for eps in [1e-9, 1.0, 1e3] {
            let opts = SmoothingOptions {
                epsilon: eps,
                m: 2,
                domain: None,
            };
            let fit = smoothing_spline(&s, &pts, &vals, &[], &opts).unwrap();
            for p in [[0.1, 0.9], [0.77, 0.2], [1.0, 1.0]] {
                let got = fit.spline.eval(&s, p[0], p[1], 0, 0).unwrap();
                let want = f(&p);
                for c in 0..3 {
                    assert_near!(got[c], want[c], SOLVE);
                }
            }
        }
    }

    #[test]
    fn biquadratic_data_is_reproduced_as_epsilon_vanishes_with_derivative_data() {
        // A polynomial of V_h fitted by BFS C¹ with gradient data: with ε tiny the
        // least-squares part dominates and the fit is the polynomial to O(ε).
        let u = |n| Partition::uniform(0.0, 1.0, n).unwrap();
        let s = TensorSpace::bfs_c1(u(3), u(3)).unwrap();
        let pts = lattice(15);
        let f = |p: &[f64; 2]| [p[0] * p[0] * p[1], p[1].powi(3), p[0] * p[1]];
        let fx = |p: &[f64; 2]| [2.0 * p[0] * p[1], 0.0, p[1]];
        let fy = |p: &[f64; 2]| [p[0] * p[0], 3.0 * p[1] * p[1], p[0]];
        let vals: Vec<[f64; 3]> = pts.iter().map(f).collect();
        let ders = vec![
            DerivativeData {
                a: 1,
                b: 0,
                values: pts.iter().map(fx).collect(),
            },
            DerivativeData {
                a: 0,
                b: 1,
                values: pts.iter().map(fy).collect(),
            },
        ];
        let opts = SmoothingOptions {
            epsilon: 1e-12,
            m: 2,
            domain: None,
        };
        let fit = smoothing_spline(&s, &pts, &vals, &ders, &opts).unwrap();
        let got = fit.spline.eval(&s, 0.4, 0.6, 0, 0).unwrap();
        let want = f(&[0.4, 0.6]);
        for c in 0..3 {
            assert_near!(got[c], want[c], SOLVE);
        }
        assert_eq!(fit.empty_cells, 0);
    }

    #[test]
    fn ill_posed_input_is_an_error() {
        let u = |n| Partition::uniform(0.0, 1.0, n).unwrap();
        let s = TensorSpace::bspline(u(2), u(2), 2).unwrap();
        let pts = lattice(5);
        let vals = vec![[0.0; 3]; pts.len()];
        let ok = SmoothingOptions {
            epsilon: 1e-6,
            m: 2,
            domain: None,
        };
        for eps in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let o = SmoothingOptions {
                epsilon: eps,
                ..ok.clone()
            };
            assert!(
                smoothing_spline(&s, &pts, &vals, &[], &o).is_err(),
                "ε = {eps}"
            );
        }
        // Collinear points: an affine function vanishing on the line is in the kernel.
        let line: Vec<[f64; 2]> = (0..20)
            .map(|i| [i as f64 / 19.0, i as f64 / 19.0])
            .collect();
        assert!(smoothing_spline(&s, &line, &vec![[0.0; 3]; 20], &[], &ok).is_err());
        // NaN data, a point outside, too few points, mismatched lengths.
        let mut bad = vals.clone();
        bad[3][1] = f64::NAN;
        assert!(smoothing_spline(&s, &pts, &bad, &[], &ok).is_err());
        assert!(smoothing_spline(&s, &[[2.0, 0.5]], &[[0.0; 3]], &[], &ok).is_err());
        assert!(smoothing_spline(&s, &pts[..2], &vals[..2], &[], &ok).is_err());
        assert!(smoothing_spline(&s, &pts, &vals[..3], &[], &ok).is_err());
        // A point outside the restricted domain ω.
        let o = SmoothingOptions {
            domain: Some(vec![Cell { i: 0, j: 0 }]),
            ..ok
        };
        assert!(smoothing_spline(&s, &pts, &vals, &[], &o).is_err());
    }
}
