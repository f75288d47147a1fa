//! Tensor products of two univariate spaces: S(Tₙ) ⊗ S(Tₘ). Basis function
//! φᵢ(x)ψⱼ(y) has global index i·dim_y + j (the 2022 paper's B_{(m+2)(i−1)+j}).
//!
//! For Hermite factors this is the Bogner–Fox–Schmit element: the function of x-node p,
//! x-derivative kx, y-node q, y-derivative ky carries ∂ₓ^{kx}∂ᵧ^{ky} v at node (p, q).

use super::basis1d::Basis1d;
use super::bspline::BSpline1d;
use super::grid::{Cell, Grid, Partition};
use super::hermite::Hermite1d;
use super::quadrature::GaussLegendre;
use super::space::{LocalBasis, Space};
use crate::error::Result;

/// The tensor product of an x-basis and a y-basis of the same kind.
#[derive(Debug, Clone)]
pub struct TensorSpace<B: Basis1d> {
    grid: Grid,
    bx: B,
    by: B,
}

impl TensorSpace<BSpline1d> {
    /// Tensor-product B-splines of degree p on Tₙ × Tₘ (p = 2: S₂(Tₙ, Tₘ), C¹, dim (n+2)(m+2)
    /// for n × m cells; p = 3: bicubic C²).
    ///
    /// Errors: `InvalidInput` if `degree == 0`.
    pub fn bspline(x: Partition, y: Partition, degree: usize) -> Result<Self> {
        let bx = BSpline1d::new(x.clone(), degree)?;
        let by = BSpline1d::new(y.clone(), degree)?;
        Ok(Self {
            grid: Grid::new(x, y),
            bx,
            by,
        })
    }
}

impl TensorSpace<Hermite1d> {
    /// Bogner–Fox–Schmit C¹ (bicubic Hermite, 4 dofs per node: v, ∂ₓv, ∂ᵧv, ∂ₓᵧv).
    ///
    /// Errors: none in practice (kept fallible for symmetry with the other constructors).
    pub fn bfs_c1(x: Partition, y: Partition) -> Result<Self> {
        Self::bfs(x, y, 1)
    }

    /// Bogner–Fox–Schmit C² (biquintic Hermite, 9 dofs per node: ∂ₓᵃ∂ᵧᵇv, a, b ≤ 2).
    ///
    /// Errors: none in practice.
    pub fn bfs_c2(x: Partition, y: Partition) -> Result<Self> {
        Self::bfs(x, y, 2)
    }

    fn bfs(x: Partition, y: Partition, r: usize) -> Result<Self> {
        let bx = Hermite1d::new(x.clone(), r)?;
        let by = Hermite1d::new(y.clone(), r)?;
        Ok(Self {
            grid: Grid::new(x, y),
            bx,
            by,
        })
    }

    /// The index of the dof ∂ₓ^{kx}∂ᵧ^{ky} at node (p, q) (p along x, q along y).
    pub fn node_dof(&self, p: usize, q: usize, kx: usize, ky: usize) -> usize {
        let d = self.bx.dofs_per_node();
        (p * d + kx) * self.by.dim() + q * d + ky
    }

    /// Degrees of freedom per node: 4 (C¹) or 9 (C²).
    pub fn dofs_per_node(&self) -> usize {
        self.bx.dofs_per_node() * self.by.dofs_per_node()
    }
}

impl<B: Basis1d> TensorSpace<B> {
    /// The x factor.
    pub fn x_basis(&self) -> &B {
        &self.bx
    }
    /// The y factor.
    pub fn y_basis(&self) -> &B {
        &self.by
    }
}

impl<B: Basis1d> Space for TensorSpace<B> {
    fn grid(&self) -> &Grid {
        &self.grid
    }
    fn dim(&self) -> usize {
        self.bx.dim() * self.by.dim()
    }
    fn degree(&self) -> usize {
        self.bx.degree().max(self.by.degree())
    }
    fn smoothness(&self) -> usize {
        self.bx.smoothness().min(self.by.smoothness())
    }
    fn cell_functions(&self, cell: Cell) -> Vec<usize> {
        let (fx, fy) = (self.bx.first_on(cell.i), self.by.first_on(cell.j));
        let ny = self.by.dim();
        let mut v = Vec::with_capacity(self.bx.local_count() * self.by.local_count());
        for a in 0..self.bx.local_count() {
            for b in 0..self.by.local_count() {
                v.push((fx + a) * ny + fy + b);
            }
        }
        v
    }
    fn eval_on_cell(&self, cell: Cell, x: f64, y: f64, order: usize) -> LocalBasis {
        let (lx, ly) = (self.bx.local_count(), self.by.local_count());
        let o = order + 1;
        let mut vx = vec![0.0; lx * o];
        let mut vy = vec![0.0; ly * o];
        self.bx.eval(cell.i, x, order, &mut vx);
        self.by.eval(cell.j, y, order, &mut vy);
        let mut data = vec![0.0; lx * ly * o * o];
        for a in 0..lx {
            for b in 0..ly {
                let l = a * ly + b;
                for da in 0..o {
                    for db in 0..o {
                        data[l * o * o + da * o + db] = vx[a * o + da] * vy[b * o + db];
                    }
                }
            }
        }
        LocalBasis::new(cell, self.cell_functions(cell), order, data)
    }
    /// (φ_aψ_b, φ_cψ_d)ₘ = Σₖ Xₖ[a, c] · Y_{m−k}[b, d] with Xₖ[a, c] = ∫ φ_a⁽ᵏ⁾φ_c⁽ᵏ⁾ over the
    /// cell's x-interval and Y likewise (Fubini: the integrand of a tensor-product function
    /// factorizes); each 1D integral with `rule`, as the product rule of the default does.
    fn cell_seminorm_gram(&self, cell: Cell, m: usize, rule: &GaussLegendre) -> Vec<f64> {
        let ([x0, x1], [y0, y1]) = self.grid.cell_bounds(cell);
        let o = m + 1;
        // moments[k][a * n + c] = ∫ f_a⁽ᵏ⁾ f_c⁽ᵏ⁾ for one factor.
        let moments = |basis: &B, interval: usize, lo: f64, hi: f64| -> Vec<Vec<f64>> {
            let n = basis.local_count();
            let mut out = vec![vec![0.0; n * n]; o];
            let mut v = vec![0.0; n * o];
            for (t, w) in rule.on_interval(lo, hi) {
                basis.eval(interval, t, m, &mut v);
                for (k, mk) in out.iter_mut().enumerate() {
                    for a in 0..n {
                        let wa = w * v[a * o + k];
                        for c in 0..n {
                            mk[a * n + c] += wa * v[c * o + k];
                        }
                    }
                }
            }
            out
        };
        let (lx, ly) = (self.bx.local_count(), self.by.local_count());
        let xm = moments(&self.bx, cell.i, x0, x1);
        let ym = moments(&self.by, cell.j, y0, y1);
        let nl = lx * ly;
        let mut g = vec![0.0; nl * nl];
        for k in 0..=m {
            let (xk, yk) = (&xm[k], &ym[m - k]);
            for a in 0..lx {
                for c in 0..lx {
                    let xac = xk[a * lx + c];
                    if xac == 0.0 {
                        continue;
                    }
                    for b in 0..ly {
                        let row =
                            &mut g[(a * ly + b) * nl + c * ly..(a * ly + b) * nl + (c + 1) * ly];
                        for (gd, &y) in row.iter_mut().zip(&yk[b * ly..(b + 1) * ly]) {
                            *gd += xac * y;
                        }
                    }
                }
            }
        }
        g
    }
    fn support(&self, k: usize) -> (Cell, Cell) {
        let ny = self.by.dim();
        let (ix, iy) = (k / ny, k % ny);
        let (x0, x1) = self.bx.support(ix);
        let (y0, y1) = self.by.support(iy);
        (Cell { i: x0, j: y0 }, Cell { i: x1, j: y1 })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::spline::gram::seminorm_gram;
    use crate::tolerance::{FINITE_DIFFERENCE, ROUND_OFF, SOLVE};

    /// ∂ₓᵃ∂ᵧᵇ of Σ c·xⁱyʲ over `terms` = [(c, i, j)], computed by hand (independent of
    /// the spline code).
    fn poly(terms: &[(f64, i32, i32)], x: f64, y: f64, a: i32, b: i32) -> f64 {
        let fall = |p: i32, k: i32| -> f64 { (0..k).map(|q| (p - q) as f64).product() };
        terms
            .iter()
            .filter(|&&(_, i, j)| i >= a && j >= b)
            .map(|&(c, i, j)| c * fall(i, a) * fall(j, b) * x.powi(i - a) * y.powi(j - b))
            .sum()
    }

    fn nonuniform() -> (Partition, Partition) {
        (
            Partition::new(vec![-1.0, -0.2, 0.1, 0.9, 1.5]).unwrap(),
            Partition::new(vec![0.0, 0.5, 0.6, 2.0]).unwrap(),
        )
    }

    const PTS: [(f64, f64); 6] = [
        (-1.0, 0.0),
        (-0.5, 0.3),
        (0.1, 0.55),
        (0.42, 1.7),
        (1.1, 0.61),
        (1.5, 2.0),
    ];

    /// hₓᵃ·hᵧᵇ of the cell holding (x, y): a derivative of order (a, b) computed from
    /// round-off-exact reference values carries the factor hₓ⁻ᵃhᵧ⁻ᵇ, so the comparison at
    /// round-off is made in the cell's reference coordinates.
    fn cell_scale(s: &dyn Space, x: f64, y: f64, a: usize, b: usize) -> f64 {
        let cell = s.grid().locate(x, y).unwrap();
        let ([x0, x1], [y0, y1]) = s.grid().cell_bounds(cell);
        (x1 - x0).powi(a as i32) * (y1 - y0).powi(b as i32)
    }

    /// max(1, Σ|cₗ ∂ᵃᵇφₗ|)·hₓ⁻ᵃhᵧ⁻ᵇ: the size of the terms a spline value sums, which bounds
    /// its round-off (a cancelling sum of large terms is exact only relative to them).
    fn term_scale(s: &dyn Space, c: &[f64], x: f64, y: f64, a: usize, b: usize) -> f64 {
        let lb = s.eval(x, y, a.max(b)).unwrap();
        let t: f64 = lb
            .indices
            .iter()
            .enumerate()
            .map(|(l, &g)| (c[g] * lb.d(l, a, b)).abs())
            .sum();
        (t * cell_scale(s, x, y, a, b)).max(1.0)
    }

    /// BFS interpolation: coefficients are the nodal derivatives of p.
    fn bfs_interpolant(s: &TensorSpace<Hermite1d>, r: usize, p: &[(f64, i32, i32)]) -> Vec<f64> {
        let mut c = vec![0.0; s.dim()];
        let (xs, ys) = (s.grid().x.breaks().to_vec(), s.grid().y.breaks().to_vec());
        for (pi, &x) in xs.iter().enumerate() {
            for (qi, &y) in ys.iter().enumerate() {
                for kx in 0..=r {
                    for ky in 0..=r {
                        c[s.node_dof(pi, qi, kx, ky)] = poly(p, x, y, kx as i32, ky as i32);
                    }
                }
            }
        }
        c
    }

    #[test]
    fn bfs_reproduces_polynomials_of_its_degree_with_all_derivatives() {
        let (x, y) = nonuniform();
        for r in 1..=2usize {
            let s = TensorSpace::bfs(x.clone(), y.clone(), r).unwrap();
            let deg = 2 * r as i32 + 1;
            let p = [
                (1.0, deg, deg),
                (-2.0, deg, 0),
                (0.5, 1, deg - 1),
                (3.0, 0, 0),
            ];
            let c = bfs_interpolant(&s, r, &p);
            for &(px, py) in &PTS {
                for a in 0..=deg as usize {
                    for b in 0..=deg as usize {
                        let k = cell_scale(&s, px, py, a, b) / term_scale(&s, &c, px, py, a, b);
                        let got = k * s.evaluate(&c, px, py, a, b).unwrap();
                        let want = k * poly(&p, px, py, a as i32, b as i32);
                        assert_near!(got, want, ROUND_OFF, "r {r} ∂({a},{b}) at ({px},{py})");
                    }
                }
            }
        }
    }

    /// Least-squares fit (normal equations, dense) of samples of p on a fine lattice.
    fn lsq_fit(s: &dyn Space, p: &[(f64, i32, i32)]) -> Vec<f64> {
        let n = s.dim();
        let mut ata = faer::Mat::<f64>::zeros(n, n);
        let mut atb = faer::Mat::<f64>::zeros(n, 1);
        let ([x0, x1], [y0, y1]) = s.grid().bounds();
        let k = 40;
        for i in 0..=k {
            for j in 0..=k {
                let (x, y) = (
                    x0 + (x1 - x0) * i as f64 / k as f64,
                    y0 + (y1 - y0) * j as f64 / k as f64,
                );
                let lb = s.eval(x, y, 0).unwrap();
                for (l, &gi) in lb.indices.iter().enumerate() {
                    atb[(gi, 0)] += lb.d(l, 0, 0) * poly(p, x, y, 0, 0);
                    for (m, &gj) in lb.indices.iter().enumerate() {
                        ata[(gi, gj)] += lb.d(l, 0, 0) * lb.d(m, 0, 0);
                    }
                }
            }
        }
        let llt = ata.llt(faer::Side::Lower).unwrap();
        use faer::linalg::solvers::Solve;
        let c = llt.solve(&atb);
        (0..n).map(|i| c[(i, 0)]).collect()
    }

    #[test]
    fn bsplines_reproduce_polynomials_of_their_degree_on_nonuniform_knots() {
        let (x, y) = nonuniform();
        for p in 2..=3usize {
            let s = TensorSpace::bspline(x.clone(), y.clone(), p).unwrap();
            let d = p as i32;
            let poly_terms = [(1.0, d, d), (-0.7, d - 1, d), (2.0, 0, 1), (0.25, 0, 0)];
            let c = lsq_fit(&s, &poly_terms);
            for &(px, py) in &PTS {
                for a in 0..=p {
                    for b in 0..=p {
                        let k = cell_scale(&s, px, py, a, b);
                        let got = k * s.evaluate(&c, px, py, a, b).unwrap();
                        let want = k * poly(&poly_terms, px, py, a as i32, b as i32);
                        assert_near!(got, want, SOLVE, "p {p} ∂({a},{b}) at ({px},{py})");
                    }
                }
            }
        }
    }

    #[test]
    fn mixed_derivatives_match_finite_differences() {
        let (x, y) = nonuniform();
        let spaces: Vec<Box<dyn Space>> = vec![
            Box::new(TensorSpace::bspline(x.clone(), y.clone(), 2).unwrap()),
            Box::new(TensorSpace::bspline(x.clone(), y.clone(), 3).unwrap()),
            Box::new(TensorSpace::bfs_c1(x.clone(), y.clone()).unwrap()),
            Box::new(TensorSpace::bfs_c2(x.clone(), y.clone()).unwrap()),
        ];
        let h = 1e-5;
        for s in &spaces {
            // A generic spline: pseudo-random coefficients.
            let c: Vec<f64> = (0..s.dim())
                .map(|k| ((k * 7919 % 113) as f64 / 113.0) - 0.5)
                .collect();
            let (px, py) = (0.37, 1.13);
            let f = |x: f64, y: f64, a: usize, b: usize| s.evaluate(&c, x, y, a, b).unwrap();
            let dx = (f(px + h, py, 0, 0) - f(px - h, py, 0, 0)) / (2.0 * h);
            let dy = (f(px, py + h, 0, 0) - f(px, py - h, 0, 0)) / (2.0 * h);
            let dxy = (f(px, py + h, 1, 0) - f(px, py - h, 1, 0)) / (2.0 * h);
            let dxx = (f(px + h, py, 1, 0) - f(px - h, py, 1, 0)) / (2.0 * h);
            assert_near!(f(px, py, 1, 0), dx, FINITE_DIFFERENCE);
            assert_near!(f(px, py, 0, 1), dy, FINITE_DIFFERENCE);
            assert_near!(f(px, py, 1, 1), dxy, FINITE_DIFFERENCE);
            assert_near!(f(px, py, 2, 0), dxx, FINITE_DIFFERENCE);
        }
    }

    #[test]
    fn splines_are_continuous_across_cell_borders_to_their_smoothness() {
        let (x, y) = nonuniform();
        let spaces: Vec<Box<dyn Space>> = vec![
            Box::new(TensorSpace::bspline(x.clone(), y.clone(), 2).unwrap()),
            Box::new(TensorSpace::bfs_c1(x.clone(), y.clone()).unwrap()),
            Box::new(TensorSpace::bfs_c2(x.clone(), y.clone()).unwrap()),
        ];
        for s in &spaces {
            let c: Vec<f64> = (0..s.dim()).map(|k| ((k * 31 % 17) as f64) - 8.0).collect();
            // x = 0.1 is the border between cells i = 1 and i = 2.
            let (xb, yb) = (0.1, 1.3);
            let left = s.eval_on_cell(Cell { i: 1, j: 2 }, xb, yb, 2);
            let right = s.eval_on_cell(Cell { i: 2, j: 2 }, xb, yb, 2);
            for a in 0..=s.smoothness() {
                assert_near!(
                    left.combine(&c, a, 0),
                    right.combine(&c, a, 0),
                    ROUND_OFF * 1e2
                );
            }
        }
    }

    #[test]
    fn dimensions_match_the_papers() {
        let u = |n| Partition::uniform(0.0, 1.0, n).unwrap();
        // 2022: S₂(Tₙ, Tₘ) has (n+2)(m+2) functions for n × m cells.
        assert_eq!(TensorSpace::bspline(u(8), u(8), 2).unwrap().dim(), 100);
        // 2004: BFS C² on 6 × 6 cells, three components: 3·7·7·9 = 1323.
        let c2 = TensorSpace::bfs_c2(u(6), u(6)).unwrap();
        assert_eq!(3 * c2.dim(), 1323);
        assert_eq!(c2.dofs_per_node(), 9);
        // 2024: BFS C¹ on 6 × 9 cells: 7·10 nodes × 4 dofs.
        assert_eq!(TensorSpace::bfs_c1(u(6), u(9)).unwrap().dim(), 280);
    }

    #[test]
    fn gram_matches_closed_forms_on_one_cell() {
        let u = |n| Partition::uniform(0.0, 1.0, n).unwrap();
        // (H₀⊗H₀, H₀⊗H₀)₂ on [0,1]² = 2·∫H₀''²·∫H₀² + (∫H₀'²)² = 2·12·13/35 + (6/5)².
        let s = TensorSpace::bfs_c1(u(1), u(1)).unwrap();
        let cells = [Cell { i: 0, j: 0 }];
        let g = seminorm_gram(&s, 2, &cells).unwrap();
        let k = s.node_dof(0, 0, 0, 0);
        assert_near!(
            g.get(k, k),
            2.0 * 12.0 * 13.0 / 35.0 + 36.0 / 25.0,
            ROUND_OFF
        );

        // |x²y|²₂ on [0,2]×[0,1] = ∫∫ (2y)² + (2x)² = 8/3 + 32/3 = 40/3.
        let p = [(1.0, 2, 1)];
        let s = TensorSpace::bfs_c1(Partition::uniform(0.0, 2.0, 1).unwrap(), u(1)).unwrap();
        let c = bfs_interpolant(&s, 1, &p);
        let g = seminorm_gram(&s, 2, &cells).unwrap();
        assert_near!(g.quadratic_form(&c), 40.0 / 3.0, ROUND_OFF);

        // The same with biquadratic B-splines (coefficients by least squares).
        let s = TensorSpace::bspline(Partition::uniform(0.0, 2.0, 1).unwrap(), u(1), 2).unwrap();
        let c = lsq_fit(&s, &p);
        let g = seminorm_gram(&s, 2, &cells).unwrap();
        assert_near!(g.quadratic_form(&c), 40.0 / 3.0, SOLVE);

        // |x³y²|²₃ on [0,1]² with BFS C²: ∫∫ 36y⁴ + 144x²y² + 36x⁴ = 36/5 + 16 + 36/5.
        let p = [(1.0, 3, 2)];
        let s = TensorSpace::bfs_c2(u(1), u(1)).unwrap();
        let c = bfs_interpolant(&s, 2, &p);
        let g = seminorm_gram(&s, 3, &cells).unwrap();
        assert_near!(
            g.quadratic_form(&c),
            36.0 / 5.0 + 16.0 + 36.0 / 5.0,
            ROUND_OFF
        );
    }

    #[test]
    fn gram_over_a_union_of_cells_adds_up() {
        // |x²y|²₂ over two of four cells of [0,2]×[0,1] equals the integral over them.
        let s = TensorSpace::bfs_c1(
            Partition::uniform(0.0, 2.0, 2).unwrap(),
            Partition::uniform(0.0, 1.0, 2).unwrap(),
        )
        .unwrap();
        let c = bfs_interpolant(&s, 1, &[(1.0, 2, 1)]);
        let cells = [Cell { i: 1, j: 0 }, Cell { i: 1, j: 1 }];
        let g = seminorm_gram(&s, 2, &cells).unwrap();
        // ∫_1^2∫_0^1 4y² + 4x² = 4/3 + 4·7/3 = 32/3.
        assert_near!(g.quadratic_form(&c), 32.0 / 3.0, ROUND_OFF);
        assert!(seminorm_gram(&s, 4, &cells).is_err());
        assert!(seminorm_gram(&s, 2, &[Cell { i: 5, j: 0 }]).is_err());
    }

    #[test]
    fn evaluation_outside_or_nan_is_an_error() {
        let (x, y) = nonuniform();
        let s = TensorSpace::bspline(x, y, 2).unwrap();
        let c = vec![0.0; s.dim()];
        assert!(s.evaluate(&c, 5.0, 0.0, 0, 0).is_err());
        assert!(s.evaluate(&c, f64::NAN, 0.0, 0, 0).is_err());
        assert!(s.evaluate(&c[1..], 0.0, 0.0, 0, 0).is_err());
    }

    /// The default `cell_seminorm_gram` (basis evaluated at every product-rule point), for
    /// comparison with the factorized override.
    struct Pointwise<'a>(&'a dyn Space);
    impl Space for Pointwise<'_> {
        fn grid(&self) -> &Grid {
            self.0.grid()
        }
        fn dim(&self) -> usize {
            self.0.dim()
        }
        fn degree(&self) -> usize {
            self.0.degree()
        }
        fn smoothness(&self) -> usize {
            self.0.smoothness()
        }
        fn cell_functions(&self, cell: Cell) -> Vec<usize> {
            self.0.cell_functions(cell)
        }
        fn eval_on_cell(&self, cell: Cell, x: f64, y: f64, order: usize) -> LocalBasis {
            self.0.eval_on_cell(cell, x, y, order)
        }
        fn support(&self, k: usize) -> (Cell, Cell) {
            self.0.support(k)
        }
    }

    #[test]
    fn factorized_cell_gram_equals_the_pointwise_one() {
        let (x, y) = nonuniform();
        let spaces: Vec<Box<dyn Space>> = vec![
            Box::new(TensorSpace::bspline(x.clone(), y.clone(), 2).unwrap()),
            Box::new(TensorSpace::bspline(x.clone(), y.clone(), 3).unwrap()),
            Box::new(TensorSpace::bfs_c1(x.clone(), y.clone()).unwrap()),
            Box::new(TensorSpace::bfs_c2(x, y).unwrap()),
        ];
        for s in &spaces {
            let rule = GaussLegendre::new(s.degree() + 1).unwrap();
            for m in 1..=s.smoothness() + 1 {
                for cell in s.grid().cells() {
                    let fast = s.cell_seminorm_gram(cell, m, &rule);
                    let slow = Pointwise(s.as_ref()).cell_seminorm_gram(cell, m, &rule);
                    let scale = slow.iter().fold(0.0f64, |a, v| a.max(v.abs()));
                    for (f, p) in fast.iter().zip(&slow) {
                        assert_near!(f / scale, p / scale, ROUND_OFF);
                    }
                }
            }
        }
    }
}
