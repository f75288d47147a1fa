//! The functional F(p) = S(p) + c Q(p) (paper eq. 4) with S = ∫‖∇_M H‖² dM (eq. 2, computed
//! by eq. 3) and Q = Σ Cᵢ ∫‖P ∇Δp‖²_F (eq. 5), its gradient and its exact Hessian with
//! respect to the free control-vertex coordinates (eq. 6).
//!
//! At each quadrature point the integrand is a function of the 27 coordinates of the nine
//! derivatives; its gradient and Hessian come from automatic differentiation (`num-dual`,
//! second-order vector duals; ∂H/∂u and ∂H/∂v by a nested first-order dual whose tangent
//! is the next derivative order) and are chained through the point's fixed linear map
//! from control vertices (see [`crate::fair::representation`]).

use std::collections::HashMap;

use nalgebra::SVector;
use num_dual::{gradient, hessian, Dual, DualNum};

use crate::fair::representation::{Representation, DERIVATIVES};
use crate::fair::second_order::{self, Num, Second};

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

fn dot<U: DualNum + Copy>(a: &[U; 3], b: &[U; 3]) -> U {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross<U: DualNum + Copy>(a: &[U; 3], b: &[U; 3]) -> [U; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Mean curvature H = (E N − 2 F M + G L) / (2 (EG − F²)) from first and second derivatives
/// (the normal left unnormalized: L, M, N carry a factor W = √(EG − F²)).
fn mean_curvature<U: DualNum<Primitive = f64> + Copy>(
    pu: &[U; 3],
    pv: &[U; 3],
    puu: &[U; 3],
    puv: &[U; 3],
    pvv: &[U; 3],
) -> U {
    let (e, f, g) = (dot(pu, pu), dot(pu, pv), dot(pv, pv));
    let n = cross(pu, pv);
    let w2 = e * g - f * f;
    let (l, m, nn) = (dot(puu, &n), dot(puv, &n), dot(pvv, &n));
    (e * nn - f * m * 2.0 + g * l) / (w2 * w2.sqrt() * 2.0)
}

/// Density of S (eq. 3): ∇H G⁻¹ ∇Hᵀ √det G at a point with derivatives `d`.
fn s_density<T: DualNum<Primitive = f64> + Copy>(d: &[[T; 3]; DERIVATIVES]) -> T {
    let [pu, pv, puu, puv, pvv, puuu, puuv, puvv, pvvv] = d;
    let lift =
        |a: &[T; 3], b: &[T; 3]| -> [Dual<T>; 3] { std::array::from_fn(|k| Dual::new(a[k], b[k])) };
    // ∂H/∂u: the tangent of (p_u, p_v, p_uu, p_uv, p_vv) along u.
    let hu = mean_curvature(
        &lift(pu, puu),
        &lift(pv, puv),
        &lift(puu, puuu),
        &lift(puv, puuv),
        &lift(pvv, puvv),
    )
    .eps;
    let hv = mean_curvature(
        &lift(pu, puv),
        &lift(pv, pvv),
        &lift(puu, puuv),
        &lift(puv, puvv),
        &lift(pvv, pvvv),
    )
    .eps;
    let (e, f, g) = (dot(pu, pu), dot(pu, pv), dot(pv, pv));
    let w2 = e * g - f * f;
    (hu * hu * g - hu * hv * f * 2.0 + hv * hv * e) / w2.sqrt()
}

/// Number of variables of Q's density: p_u, p_v, ∂Δp/∂u, ∂Δp/∂v.
const Q_VARS: usize = 12;

/// The derivatives (of the nine) each of Q's four vector variables sums.
const Q_MAP: [&[usize]; 4] = [&[0], &[1], &[5, 7], &[6, 8]];

/// Density of Q (eq. 5): ‖P ∇Δp‖²_F with Δp = p_uu + p_vv in the element's parameters and
/// P = I − n nᵀ, from `q = [p_u, p_v, ∂Δp/∂u, ∂Δp/∂v]`.
fn q_density<T: DualNum<Primitive = f64> + Copy>(q: &[[T; 3]; 4]) -> T {
    let [pu, pv, lap_u, lap_v] = q;
    let (e, f, g) = (dot(pu, pu), dot(pu, pv), dot(pv, pv));
    let w2 = e * g - f * f;
    let n = cross(pu, pv);
    let (nu, nv) = (dot(&n, lap_u), dot(&n, lap_v));
    dot(lap_u, lap_u) + dot(lap_v, lap_v) - (nu * nu + nv * nv) / w2
}

fn q_vars<T: DualNum<Primitive = f64> + Copy>(d: &[[T; 3]; DERIVATIVES]) -> [[T; 3]; 4] {
    std::array::from_fn(|i| std::array::from_fn(|a| Q_MAP[i].iter().map(|&k| d[k][a]).sum()))
}

/// Densities of S and Q at a point with derivatives `d`.
fn densities<T: DualNum<Primitive = f64> + Copy>(d: &[[T; 3]; DERIVATIVES]) -> (T, T) {
    (s_density(d), q_density(&q_vars(d)))
}

/// Gradient and Hessian of `ws · S-density + wq · Q-density` with respect to the 27
/// derivative coordinates; Q's part is differentiated in its own 12 variables and mapped.
fn point_hessian(
    x: &[f64; VARS],
    ws: f64,
    wq: f64,
) -> (SVector<f64, VARS>, nalgebra::SMatrix<f64, VARS, VARS>) {
    let (mut g, mut h) = if ws != 0.0 {
        let d: [[Second; 3]; DERIVATIVES] = std::array::from_fn(|k| {
            std::array::from_fn(|a| Second::variable(x[3 * k + a], 3 * k + a))
        });
        let s = second_order::s_density(&d).scale(ws);
        (
            SVector::<f64, VARS>::from(s.g),
            nalgebra::SMatrix::<f64, VARS, VARS>::from_row_slice(&s.hessian()),
        )
    } else {
        (SVector::zeros(), nalgebra::SMatrix::zeros())
    };
    let q = q_vars(&unpack(x));
    let qx = SVector::<f64, Q_VARS>::from_fn(|i, _| q[i / 3][i % 3]);
    let (_, gq, hq) = hessian(
        |y| {
            q_density(&std::array::from_fn(|i| {
                [y[3 * i], y[3 * i + 1], y[3 * i + 2]]
            })) * wq
        },
        &qx,
    );
    for (i, di) in Q_MAP.iter().enumerate() {
        for a in 0..3 {
            for &d in *di {
                g[3 * d + a] += gq[3 * i + a];
            }
            for (j, dj) in Q_MAP.iter().enumerate() {
                for b in 0..3 {
                    let v = hq[(3 * i + a, 3 * j + b)];
                    for &d in *di {
                        for &e in *dj {
                            h[(3 * d + a, 3 * e + b)] += v;
                        }
                    }
                }
            }
        }
    }
    (g, h)
}

fn norm3(a: &[f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

fn unpack<T: Copy>(x: &[T]) -> [[T; 3]; DERIVATIVES] {
    std::array::from_fn(|d| [x[3 * d], x[3 * d + 1], x[3 * d + 2]])
}

/// The derivatives at quadrature point `k` of `rep` for vertex `positions`.
fn point_derivatives<R: Representation>(rep: &R, k: usize, positions: &[[f64; 3]]) -> [f64; VARS] {
    let p = &rep.points()[k];
    let mut x = [0.0; VARS];
    for (&v, c) in p.vertices.iter().zip(&p.coefficients) {
        let pos = positions[v as usize];
        for d in 0..DERIVATIVES {
            for a in 0..3 {
                x[3 * d + a] += c[d] * pos[a];
            }
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
    /// Per quadrature point, block slot of each (k, l) pair of its vertices (row-major),
    /// `u32::MAX` where a vertex is fixed or the pair lies below the diagonal.
    slots: Vec<Vec<u32>>,
}

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
        let mut slot_of: HashMap<(u32, u32), u32> = HashMap::new();
        let mut blocks = Vec::new();
        let mut slots = Vec::with_capacity(rep.points().len());
        for p in rep.points() {
            let m = p.vertices.len();
            let mut s = vec![u32::MAX; m * m];
            for k in 0..m {
                let i = free_index[p.vertices[k] as usize];
                if i == u32::MAX {
                    continue;
                }
                for l in 0..m {
                    let j = free_index[p.vertices[l] as usize];
                    if j == u32::MAX || i > j {
                        continue;
                    }
                    let next = blocks.len() as u32;
                    let slot = *slot_of.entry((i, j)).or_insert_with(|| {
                        blocks.push((i, j));
                        next
                    });
                    s[k * m + l] = slot;
                }
            }
            slots.push(s);
        }
        Functional {
            rep,
            c,
            free_index,
            free_count,
            blocks,
            slots,
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

    /// S, Q and F at `positions` (eq. 2–5).
    pub fn value(&self, positions: &[[f64; 3]]) -> Terms {
        let mut t = Terms::default();
        for (k, p) in self.rep.points().iter().enumerate() {
            let x = point_derivatives(self.rep, k, positions);
            let (s, q) = densities(&unpack(&x));
            t.s += p.weight_s * s;
            t.q += p.weight_q * q;
        }
        t.f = t.s + self.c * t.q;
        t
    }

    /// Area-weighted mean and standard deviation of the mean curvature H over the
    /// quadrature points where S is integrated (the surface measure √det G dE of eq. 3).
    pub fn mean_curvature_statistics(&self, positions: &[[f64; 3]]) -> (f64, f64) {
        let (mut area, mut sum, mut sum2) = (0.0, 0.0, 0.0);
        for (k, p) in self.rep.points().iter().enumerate() {
            if p.weight_s == 0.0 {
                continue;
            }
            let d = unpack(&point_derivatives(self.rep, k, positions));
            let h = mean_curvature(&d[0], &d[1], &d[2], &d[3], &d[4]);
            let w = p.weight_s * norm3(&cross(&d[0], &d[1]));
            area += w;
            sum += w * h;
            sum2 += w * h * h;
        }
        if area == 0.0 {
            return (0.0, 0.0);
        }
        let mean = sum / area;
        (mean, (sum2 / area - mean * mean).max(0.0).sqrt())
    }

    /// The terms and the gradient of F̃ (3 entries per free vertex).
    pub fn gradient(&self, positions: &[[f64; 3]]) -> (Terms, Vec<f64>) {
        let mut t = Terms::default();
        let mut g = vec![0.0; 3 * self.free_count];
        for (k, p) in self.rep.points().iter().enumerate() {
            let x = SVector::<f64, VARS>::from(point_derivatives(self.rep, k, positions));
            let (ws, wq) = (p.weight_s, self.c * p.weight_q);
            let ((s, q), (_, grad)) = (
                densities(&unpack(x.as_slice())),
                gradient(
                    |y| {
                        let (s, q) = densities(&unpack(y.as_slice()));
                        s * ws + q * wq
                    },
                    &x,
                ),
            );
            t.s += ws * s;
            t.q += p.weight_q * q;
            self.scatter_gradient(k, grad.as_slice(), &mut g);
        }
        t.f = t.s + self.c * t.q;
        (t, g)
    }

    fn scatter_gradient(&self, k: usize, grad: &[f64], g: &mut [f64]) {
        let p = &self.rep.points()[k];
        for (&v, c) in p.vertices.iter().zip(&p.coefficients) {
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

    /// The terms, gradient and Hessian of F̃ (eq. 7's g and H).
    pub fn hessian(&self, positions: &[[f64; 3]]) -> (Terms, Vec<f64>, BlockHessian) {
        let mut t = Terms::default();
        let mut g = vec![0.0; 3 * self.free_count];
        let mut values = vec![[[0.0; 3]; 3]; self.blocks.len()];
        let mut right: Vec<[[f64; 3]; VARS]> = Vec::new();
        for (k, p) in self.rep.points().iter().enumerate() {
            let x = point_derivatives(self.rep, k, positions);
            let (ws, wq) = (p.weight_s, self.c * p.weight_q);
            let (s, q) = densities(&unpack(&x));
            t.s += ws * s;
            t.q += p.weight_q * q;
            let (grad, h) = point_hessian(&x, ws, wq);
            self.scatter_gradient(k, grad.as_slice(), &mut g);
            // right[l][3d + a][b] = Σ_e c_l[e] h[3d + a][3e + b]
            let m = p.vertices.len();
            right.clear();
            for c in &p.coefficients {
                let mut r = [[0.0; 3]; VARS];
                for (row, rrow) in r.iter_mut().enumerate() {
                    for (e, &ce) in c.iter().enumerate() {
                        if ce == 0.0 {
                            continue;
                        }
                        for b in 0..3 {
                            rrow[b] += ce * h[(row, 3 * e + b)];
                        }
                    }
                }
                right.push(r);
            }
            let slots = &self.slots[k];
            for kk in 0..m {
                let ck = &p.coefficients[kk];
                for l in 0..m {
                    let slot = slots[kk * m + l];
                    if slot == u32::MAX {
                        continue;
                    }
                    let r = &right[l];
                    let block = &mut values[slot as usize];
                    for (d, &cd) in ck.iter().enumerate() {
                        if cd == 0.0 {
                            continue;
                        }
                        for a in 0..3 {
                            for b in 0..3 {
                                block[a][b] += cd * r[3 * d + a][b];
                            }
                        }
                    }
                }
            }
        }
        t.f = t.s + self.c * t.q;
        (
            t,
            g,
            BlockHessian {
                blocks: self.blocks.clone(),
                values,
            },
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::tolerance::ROUND_OFF;

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

    #[test]
    fn sphere_has_constant_mean_curvature_and_no_s_density() {
        let r = 2.0;
        let d = point(0.3, -0.4, r);
        let h = mean_curvature(&d[0], &d[1], &d[2], &d[3], &d[4]);
        assert_near!(h.abs(), 1.0 / r, ROUND_OFF);
        let (s, _) = densities(&d);
        assert_near!(s, 0.0, ROUND_OFF);
    }

    #[test]
    fn own_second_order_type_matches_num_dual() {
        // A generic point: derivatives with no special structure.
        let x: [f64; VARS] = std::array::from_fn(|i| {
            let t = i as f64;
            (0.7 * t + 0.3).sin() + if i == 0 || i == 4 { 2.0 } else { 0.0 }
        });
        let d = unpack(&x);
        assert_near!(second_order::s_density(&d), s_density(&d), ROUND_OFF);
        let (value, grad, hess) = hessian(
            |y| s_density(&unpack(y.as_slice())),
            &SVector::<f64, VARS>::from(x),
        );
        let own: [[Second; 3]; DERIVATIVES] = std::array::from_fn(|k| {
            std::array::from_fn(|a| Second::variable(x[3 * k + a], 3 * k + a))
        });
        let own = second_order::s_density(&own);
        let full = own.hessian();
        let scale = hess.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert_near!(own.re, value, ROUND_OFF);
        for i in 0..VARS {
            assert_near!(own.g[i] / scale, grad[i] / scale, ROUND_OFF);
            for j in 0..VARS {
                assert_near!(full[i * VARS + j] / scale, hess[(i, j)] / scale, ROUND_OFF);
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
        assert_near!(second_order::s_density(&d), 1.25, ROUND_OFF);
        assert_near!(q, 0.0, ROUND_OFF);
        // A tangential one is not: ‖(3, 0, 0)‖² for Δp_u.
        d[5] = [3.0, 0.0, 0.0];
        let (_, q) = densities(&d);
        assert_near!(q, 9.0, ROUND_OFF);
    }
}
