//! Reproduction of Table 1 of Kouibia, Pasadas & Omri 2024 (Mathematics 12, 1736): the
//! generalized offset of f(u, v) = (u, v, 1/(1 + e^{12.73 − 13.5√(0.1 + u² + v²)})) with
//! d₁ = 0.02u, d₂ = 0.02v, d₃ = 0.25(u² + v² − u − v) + 0.175, holes
//! H₁: 3(x − 0.4)² + 12(y − 0.22)² < 0.1 and H₂: 4(x − 0.6)² + 9(y − 0.73)² < 0.2, the
//! Bogner–Fox–Schmit C¹ space on 6 × 9 equal rectangles (6 along u, 9 along v), and σ₁
//! fitted on Ω − H_h to values and first derivatives (k = 1) of s_f with |·|₂ (m = 2).
//! The table's E_r is the relative error of σ₁ on 5000 random points of Ω − H_h.
//!
//! Only the first block (M = 500, 1000, 1500) is reproduced: the paper does not say which
//! partition its second block uses (its parameters repeat the 2022 table's 15-knot block).
//! Derivative data of s_f come from Richardson-extrapolated central differences
//! (error ~1e-11, far below the table's 1e-3…1e-4).

use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use serde::Serialize;

use crate::error::{Error, Result};
use crate::spline::{Partition, Space, TensorSpace};

use super::kp2022::{Spread, SurfaceFn};
use crate::fit::hole::{Hole, HoleShape};
use crate::fit::offset::GeneralizedOffset;
use crate::fit::smoothing::{smoothing_spline, DerivativeData, SmoothingOptions};

/// The paper's Table 1 (M, ε, E_r), first block.
pub const PAPER_TABLE1: [(usize, f64, f64); 9] = [
    (500, 1e-7, 4.8358e-3),
    (500, 1e-9, 2.7416e-3),
    (500, 1e-12, 2.7314e-3),
    (1000, 1e-7, 2.4427e-3),
    (1000, 1e-9, 2.3178e-3),
    (1000, 1e-12, 2.3157e-3),
    (1500, 1e-7, 1.2414e-3),
    (1500, 1e-9, 1.0115e-3),
    (1500, 1e-12, 1.0096e-3),
];

/// Cells along u and along v.
pub const CELLS: (usize, usize) = (6, 9);

/// Random evaluation points for E_r.
pub const EVALUATION_POINTS: usize = 5000;

/// A row of our table next to the paper's.
#[derive(Debug, Clone, Serialize)]
pub struct Kpo2024Row {
    /// M: data points in Ω − H_h.
    pub points: usize,
    /// ε.
    pub epsilon: f64,
    /// Seeds run.
    pub seeds: usize,
    /// Our E_r over the seeds.
    pub error: Spread,
    /// The paper's E_r.
    pub paper_error: f64,
}

/// f and its first derivatives (2024 §6).
pub fn surface(u: f64, v: f64) -> [[f64; 3]; 3] {
    let r = (0.1 + u * u + v * v).sqrt();
    let e = (12.73 - 13.5 * r).exp();
    let phi = 1.0 / (1.0 + e);
    // dφ/dr = 13.5 e / (1 + e)²; dr/du = u / r.
    let dphi = 13.5 * e / ((1.0 + e) * (1.0 + e));
    [
        [u, v, phi],
        [1.0, 0.0, dphi * u / r],
        [0.0, 1.0, dphi * v / r],
    ]
}

/// The generalized offset of the example.
pub fn offset() -> GeneralizedOffset<SurfaceFn> {
    GeneralizedOffset {
        surface: surface as SurfaceFn,
        distances: [
            Box::new(|u, _| 0.02 * u),
            Box::new(|_, v| 0.02 * v),
            Box::new(|u, v| 0.25 * (u * u + v * v - u - v) + 0.175),
        ],
    }
}

/// The example's (open) holes; their closure gives the same H_h.
pub fn hole() -> Hole {
    Hole {
        shapes: vec![
            HoleShape::Ellipse {
                center: [0.4, 0.22],
                coeffs: [3.0, 12.0],
                level: 0.1,
            },
            HoleShape::Ellipse {
                center: [0.6, 0.73],
                coeffs: [4.0, 9.0],
                level: 0.2,
            },
        ],
    }
}

/// ∂/∂u or ∂/∂v of a vector function by Richardson-extrapolated central differences.
pub fn partial(
    f: &dyn Fn(f64, f64) -> Result<[f64; 3]>,
    u: f64,
    v: f64,
    along_v: bool,
) -> Result<[f64; 3]> {
    let d = |h: f64| -> Result<[f64; 3]> {
        let (du, dv) = if along_v { (0.0, h) } else { (h, 0.0) };
        let (p, m) = (f(u + du, v + dv)?, f(u - du, v - dv)?);
        Ok(std::array::from_fn(|k| (p[k] - m[k]) / (2.0 * h)))
    };
    let (a, b) = (d(2e-3)?, d(1e-3)?);
    Ok(std::array::from_fn(|k| (4.0 * b[k] - a[k]) / 3.0))
}

/// The BFS C¹ space of the example.
///
/// Errors: none in practice.
pub fn space() -> Result<TensorSpace<crate::spline::Hermite1d>> {
    TensorSpace::bfs_c1(
        Partition::uniform(0.0, 1.0, CELLS.0)?,
        Partition::uniform(0.0, 1.0, CELLS.1)?,
    )
}

/// σ₁ of one run and the sample sets it was made from.
struct Fitted {
    space: TensorSpace<crate::spline::Hermite1d>,
    mask: Vec<bool>,
    sigma1: crate::fit::surface::VectorSpline,
    /// 5000 random points of Ω − H_h.
    xi_outside: Vec<[f64; 2]>,
    /// 5000 random points of Ω.
    xi_all: Vec<[f64; 2]>,
}

fn fit(points: usize, epsilon: f64, seed: u64, derivative_data: bool) -> Result<Fitted> {
    if points == 0 {
        return Err(Error::InvalidInput(
            "kpo2024: need at least one point".into(),
        ));
    }
    let space = space()?;
    let grid = space.grid().clone();
    let mask = hole().cells(&grid)?;
    let off = offset();
    let in_hh = |x: f64, y: f64| grid.locate(x, y).is_some_and(|c| mask[grid.cell_index(c)]);
    let mut rng = StdRng::seed_from_u64(seed);
    let mut sample = |n: usize, keep: &dyn Fn(f64, f64) -> bool| -> Vec<[f64; 2]> {
        let mut v = Vec::with_capacity(n);
        while v.len() < n {
            let (x, y): (f64, f64) = (rng.random(), rng.random());
            if keep(x, y) {
                v.push([x, y]);
            }
        }
        v
    };
    let data = sample(points, &|x, y| !in_hh(x, y));
    let xi_outside = sample(EVALUATION_POINTS, &|x, y| !in_hh(x, y));
    let xi_all = sample(EVALUATION_POINTS, &|_, _| true);
    let sf = |u: f64, v: f64| off.point(u, v);
    let values = data
        .iter()
        .map(|p| sf(p[0], p[1]))
        .collect::<Result<Vec<_>>>()?;
    let derivatives = if derivative_data {
        let du = data
            .iter()
            .map(|p| partial(&sf, p[0], p[1], false))
            .collect::<Result<Vec<_>>>()?;
        let dv = data
            .iter()
            .map(|p| partial(&sf, p[0], p[1], true))
            .collect::<Result<Vec<_>>>()?;
        vec![
            DerivativeData {
                a: 1,
                b: 0,
                values: du,
            },
            DerivativeData {
                a: 0,
                b: 1,
                values: dv,
            },
        ]
    } else {
        vec![]
    };
    let domain = grid
        .cells()
        .filter(|&c| !mask[grid.cell_index(c)])
        .collect();
    let fit = smoothing_spline(
        &space,
        &data,
        &values,
        &derivatives,
        &SmoothingOptions {
            epsilon,
            m: 2,
            domain: Some(domain),
        },
    )?;
    Ok(Fitted {
        space,
        mask,
        sigma1: fit.spline,
        xi_outside,
        xi_all,
    })
}

/// √(Σ‖σ(ξ) − s_f(ξ)‖² / Σ‖s_f(ξ)‖²), the papers' relative error.
fn relative_error(pts: &[[f64; 2]], sigma: &dyn Fn(f64, f64) -> Result<[f64; 3]>) -> Result<f64> {
    let off = offset();
    let (mut num, mut den) = (0.0, 0.0);
    for p in pts {
        let s = off.point(p[0], p[1])?;
        let a = sigma(p[0], p[1])?;
        num += (0..3).map(|k| (a[k] - s[k]).powi(2)).sum::<f64>();
        den += (0..3).map(|k| s[k] * s[k]).sum::<f64>();
    }
    Ok((num / den).sqrt())
}

/// One run: σ₁ from `points` random points of Ω − H_h with values (and, with
/// `derivative_data`, first derivatives — the paper's k = 1) of s_f, and its E_r.
///
/// Errors: `InvalidInput` for no points or ε ≤ 0; solver errors of [`smoothing_spline`].
pub fn run(points: usize, epsilon: f64, seed: u64, derivative_data: bool) -> Result<f64> {
    let f = fit(points, epsilon, seed, derivative_data)?;
    relative_error(&f.xi_outside, &|x, y| f.sigma1.eval(&f.space, x, y, 0, 0))
}

/// The outcome of the whole 2024 method on one point set.
#[derive(Debug, Clone, Serialize)]
pub struct Kpo2024Fill {
    /// E_r of σ₁ on Ω − H_h (the table's number).
    pub error1: f64,
    /// The relative error of σ = σ₁ ∪ (σ̄₂ + offset terms) on Ω.
    pub error: f64,
    /// Inequality constraints imposed on σ̄₂'s third component.
    pub inequalities: usize,
    /// The worst violation of an imposed constraint (≤ the QP solver's tolerance).
    pub max_violation: f64,
    /// Points of a 40 × 40 lattice of H where σ̄₂'s third component is negative or
    /// decreasing in u or v (not imposed there: a check of how well shape carries over).
    pub lattice_violations: usize,
    /// Lattice points checked.
    pub lattice_points: usize,
    /// The paper's figures when asked for: the offset with its hole, σ₁ on Ω − H and the
    /// filled σ, sampled with the distance to the exact offset as quality.
    #[serde(skip)]
    pub figures: Vec<(String, crate::mesh::PolygonMesh)>,
}

/// The whole method of the 2024 paper (§3–5) on one point set: σ₁, σ̄₁ = σ₁ − offset
/// terms at the nodes of ∂H_h, σ̄₂ with positivity and monotonicity in u and v of the third
/// component (f's height, a sigmoid increasing in u and v), σ₂ = σ̄₂ + offset terms.
///
/// Errors: as [`run`], and [`crate::fit::shape::shape_preserving_fill`]'s.
pub fn fill_run(
    points: usize,
    epsilon: f64,
    seed: u64,
    extra_per_side: usize,
    figures: bool,
) -> Result<Kpo2024Fill> {
    use crate::fit::shape::{shape_preserving_fill, ShapeConstraints, Tau};
    let f = fit(points, epsilon, seed, true)?;
    let off = offset();
    let disp = |u: f64, v: f64| off.displacement(u, v);
    // σ̄₁'s nodal dofs: σ₁'s coefficients minus (D, ∂ᵤD, ∂ᵥD, ∂ᵤᵥD) of the displacement D.
    let mut boundary = f.sigma1.clone();
    let (xs, ys) = (
        f.space.grid().x.breaks().to_vec(),
        f.space.grid().y.breaks().to_vec(),
    );
    for (p, &x) in xs.iter().enumerate() {
        for (q, &y) in ys.iter().enumerate() {
            let d0 = disp(x, y)?;
            let dx = partial(&disp, x, y, false)?;
            let dy = partial(&disp, x, y, true)?;
            let dxy = partial(&|u, v| partial(&disp, u, v, false), x, y, true)?;
            for (k, (kx, ky)) in [(0, 0), (1, 0), (0, 1), (1, 1)].into_iter().enumerate() {
                let dd = [d0, dx, dy, dxy][k];
                let idx = f.space.node_dof(p, q, kx, ky);
                for (c, dc) in boundary.coeffs.iter_mut().zip(dd) {
                    c[idx] -= dc;
                }
            }
        }
    }
    let shape = ShapeConstraints {
        component: 2,
        value: Some(Tau::Plus),
        slope_x: Some(Tau::Plus),
        slope_y: Some(Tau::Plus),
        extra_per_side,
        extra_points: vec![],
    };
    let filled = shape_preserving_fill(&f.space, &boundary, &f.mask, 2, &shape)?;
    let grid = f.space.grid();
    let sigma = |x: f64, y: f64| -> Result<[f64; 3]> {
        let c = grid
            .locate(x, y)
            .ok_or_else(|| Error::InvalidInput(format!("({x}, {y}) outside Ω")))?;
        if f.mask[grid.cell_index(c)] {
            let a = filled.spline.eval_on_cell(&f.space, c, x, y, 0, 0)?;
            let d = disp(x, y)?;
            Ok(std::array::from_fn(|k| a[k] + d[k]))
        } else {
            f.sigma1.eval_on_cell(&f.space, c, x, y, 0, 0)
        }
    };
    let error1 = relative_error(&f.xi_outside, &|x, y| f.sigma1.eval(&f.space, x, y, 0, 0))?;
    let error = relative_error(&f.xi_all, &sigma)?;
    let hole = hole();
    let (mut checked, mut bad) = (0, 0);
    for i in 0..40 {
        for j in 0..40 {
            let (x, y) = ((i as f64 + 0.5) / 40.0, (j as f64 + 0.5) / 40.0);
            if !hole.contains(grid, x, y) {
                continue;
            }
            checked += 1;
            let v = filled.spline.eval(&f.space, x, y, 0, 0)?[2];
            let vx = filled.spline.eval(&f.space, x, y, 1, 0)?[2];
            let vy = filled.spline.eval(&f.space, x, y, 0, 1)?[2];
            if v < 0.0 || vx < 0.0 || vy < 0.0 {
                bad += 1;
            }
        }
    }
    let figures = if figures {
        crate::fit::sample::hole_figures(
            [
                "kpo2024_offset_with_hole",
                "kpo2024_sigma1_approximation",
                "kpo2024_shape_preserving_fill",
            ],
            &|u, v| off.point(u, v),
            &|u, v| f.sigma1.eval(&f.space, u, v, 0, 0),
            &sigma,
            &|u, v| !hole.contains(grid, u, v),
        )?
    } else {
        Vec::new()
    };
    Ok(Kpo2024Fill {
        error1,
        error,
        inequalities: filled.report.inequalities,
        max_violation: filled.report.max_violation,
        lattice_violations: bad,
        lattice_points: checked,
        figures,
    })
}

/// The first block of the paper's Table 1, each row over seeds 0..`seeds`.
///
/// Errors: `InvalidInput` if `seeds == 0`; any error of [`run`].
pub fn table1(seeds: usize) -> Result<Vec<Kpo2024Row>> {
    if seeds == 0 {
        return Err(Error::InvalidInput(
            "kpo2024-table1 needs at least one seed".into(),
        ));
    }
    PAPER_TABLE1
        .iter()
        .map(|&(points, epsilon, paper_error)| {
            let errs = (0..seeds as u64)
                .map(|s| run(points, epsilon, s, true))
                .collect::<Result<Vec<_>>>()?;
            Ok(Kpo2024Row {
                points,
                epsilon,
                seeds,
                error: Spread::of(errs),
                paper_error,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tolerance::FINITE_DIFFERENCE;
    use std::sync::OnceLock;

    const SEEDS: usize = 10;
    /// The acceptance factor for medians against the paper.
    const PAPER_FACTOR: f64 = 1.5;
    /// "Flat in ε": the medians of one block differ by less than 5 %.
    const FLAT_IN_EPSILON: f64 = 1.05;

    fn rows() -> &'static [Kpo2024Row] {
        static ROWS: OnceLock<Vec<Kpo2024Row>> = OnceLock::new();
        ROWS.get_or_init(|| {
            let rows = table1(SEEDS).unwrap();
            for r in &rows {
                eprintln!(
                    "{:>5} {:>7.0e} | E_r {:.3e} [{:.3e}, {:.3e}] paper {:.4e}",
                    r.points, r.epsilon, r.error.median, r.error.min, r.error.max, r.paper_error
                );
            }
            rows
        })
    }

    #[test]
    fn every_median_error_of_the_first_block_is_within_1_5x_of_the_paper() {
        // Ours are 3–9× below the paper's, in line with the paper's own text example
        // (M = 4000, ε = 1e-12: E_r = 2.36e-4), not with its table.
        for r in rows() {
            assert!(
                r.error.median <= PAPER_FACTOR * r.paper_error,
                "M = {}, ε = {:e}: {:e} vs paper {:e}",
                r.points,
                r.epsilon,
                r.error.median,
                r.paper_error
            );
        }
    }

    #[test]
    fn error_falls_with_more_points_and_is_flat_in_epsilon() {
        for e in [1e-7, 1e-9, 1e-12] {
            let b: Vec<&Kpo2024Row> = rows().iter().filter(|r| r.epsilon == e).collect();
            for w in b.windows(2) {
                assert!(w[1].error.median < w[0].error.median, "ε = {e:e}");
            }
        }
        for m in [500, 1000, 1500] {
            let b: Vec<f64> = rows()
                .iter()
                .filter(|r| r.points == m)
                .map(|r| r.error.median)
                .collect();
            let (lo, hi) = (
                b.iter().copied().fold(f64::INFINITY, f64::min),
                b.iter().copied().fold(0.0, f64::max),
            );
            assert!(hi <= FLAT_IN_EPSILON * lo, "M = {m}: {lo:e} .. {hi:e}");
        }
    }

    #[test]
    fn shape_preserving_fill_meets_its_constraints() {
        let r = fill_run(1500, 1e-9, 0, 3, false).unwrap();
        assert!(r.inequalities > 0);
        // Interior-point accuracy: clarabel's default tolerances are ~1e-8.
        assert!(
            r.max_violation <= FINITE_DIFFERENCE,
            "violation {}",
            r.max_violation
        );
        assert!(r.error.is_finite() && r.error1 < r.error);
    }

    #[test]
    fn bad_parameters_are_errors() {
        assert!(run(0, 1e-9, 0, true).is_err());
        assert!(run(500, -1.0, 0, true).is_err());
        assert!(table1(0).is_err());
    }
}
