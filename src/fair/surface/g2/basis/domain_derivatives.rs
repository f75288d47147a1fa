//! Derivatives of a function on Ω_k in domain coordinates (x, y) from its derivatives in a
//! patch's parameters (u, v), through the domain patch δ: (u, v) ↦ (x, y) — the inverse
//! chain rule to third order. The special element's quadrature points carry these, so that
//! Q (eq. 5) is integrated in Ω_k's coordinates and S (parameterization-independent) is the
//! same either way.

use nalgebra::{Matrix2, Matrix3, Matrix4, Vector2, Vector3, Vector4};

/// Derivatives in the order p_u, p_v, p_uu, p_uv, p_vv, p_uuu, p_uuv, p_uvv, p_vvv (or the
/// same with x, y).
pub type Derivatives = [f64; 9];

/// δ's derivatives at a point: `[d][c]` derivative d (order as [`Derivatives`]) of
/// coordinate c.
pub type MapDerivatives = [[f64; 2]; 9];

/// The linear map from parametric to domain derivatives at one point of δ, prepared once.
#[derive(Debug, Clone)]
pub struct InverseChainRule {
    jacobian_inverse_t: Matrix2<f64>,
    second: Matrix3<f64>,
    third: Matrix4<f64>,
    map: MapDerivatives,
    /// |det Dδ|.
    pub jacobian: f64,
}

/// The coefficient vector of f₃(α, β, γ) = Σ f_ijk αᵢβⱼγₖ in (f_xxx, f_xxy, f_xyy, f_yyy).
fn trilinear(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> [f64; 4] {
    [
        a[0] * b[0] * c[0],
        a[0] * b[0] * c[1] + a[0] * b[1] * c[0] + a[1] * b[0] * c[0],
        a[0] * b[1] * c[1] + a[1] * b[0] * c[1] + a[1] * b[1] * c[0],
        a[1] * b[1] * c[1],
    ]
}

/// The coefficient vector of f₂(α, β) in (f_xx, f_xy, f_yy).
fn bilinear(a: [f64; 2], b: [f64; 2]) -> [f64; 3] {
    [a[0] * b[0], a[0] * b[1] + a[1] * b[0], a[1] * b[1]]
}

impl InverseChainRule {
    /// The rule at a point where δ has derivatives `map`; None where Dδ is singular.
    pub fn new(map: MapDerivatives) -> Option<Self> {
        let (du, dv) = (map[0], map[1]);
        let j = Matrix2::new(du[0], dv[0], du[1], dv[1]);
        let det = j.determinant();
        let jacobian_inverse_t = j.transpose().try_inverse()?;
        let rows2 = [bilinear(du, du), bilinear(du, dv), bilinear(dv, dv)];
        let second = Matrix3::from_fn(|r, c| rows2[r][c]).try_inverse()?;
        let rows3 = [
            trilinear(du, du, du),
            trilinear(du, du, dv),
            trilinear(du, dv, dv),
            trilinear(dv, dv, dv),
        ];
        let third = Matrix4::from_fn(|r, c| rows3[r][c]).try_inverse()?;
        Some(InverseChainRule {
            jacobian_inverse_t,
            second,
            third,
            map,
            jacobian: det.abs(),
        })
    }

    /// f's domain derivatives from p = f ∘ δ's parametric ones (linear in `p`).
    pub fn apply(&self, p: &Derivatives) -> Derivatives {
        let m = &self.map;
        let g = self.jacobian_inverse_t * Vector2::new(p[0], p[1]);
        let grad = [g[0], g[1]];
        let dot = |d: [f64; 2]| grad[0] * d[0] + grad[1] * d[1];
        // p_ab = f₂(δ_a, δ_b) + ∇f·δ_ab
        let h = self.second * Vector3::new(p[2] - dot(m[2]), p[3] - dot(m[3]), p[4] - dot(m[4]));
        let f2 = |a: [f64; 2], b: [f64; 2]| {
            let w = bilinear(a, b);
            w[0] * h[0] + w[1] * h[1] + w[2] * h[2]
        };
        let (du, dv) = (m[0], m[1]);
        let (duu, duv, dvv) = (m[2], m[3], m[4]);
        // p_abc = f₃(δ_a, δ_b, δ_c) + f₂(δ_ab, δ_c) + f₂(δ_ac, δ_b) + f₂(δ_bc, δ_a) + ∇f·δ_abc
        let rest = [
            p[5] - 3.0 * f2(duu, du) - dot(m[5]),
            p[6] - (f2(duu, dv) + 2.0 * f2(duv, du)) - dot(m[6]),
            p[7] - (f2(dvv, du) + 2.0 * f2(duv, dv)) - dot(m[7]),
            p[8] - 3.0 * f2(dvv, dv) - dot(m[8]),
        ];
        let t = self.third * Vector4::new(rest[0], rest[1], rest[2], rest[3]);
        [grad[0], grad[1], h[0], h[1], h[2], t[0], t[1], t[2], t[3]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A polynomial map δ and a polynomial f: f ∘ δ's parametric derivatives taken by
    /// hand, and the rule must return f's own.
    #[test]
    fn recovers_the_derivatives_of_a_cubic_through_a_quadratic_map() {
        // δ(u, v) = (u + 0.3v² + 0.1uv, v + 0.2u² − 0.05uv), at (u, v) = (0.4, 0.7)
        let (u, v) = (0.4f64, 0.7f64);
        let x = |u: f64, v: f64| u + 0.3 * v * v + 0.1 * u * v;
        let y = |u: f64, v: f64| v + 0.2 * u * u - 0.05 * u * v;
        let f = |x: f64, y: f64| x * x * x - 2.0 * x * y * y + 0.5 * y * y + x;
        // p = f ∘ δ has degree 6: nested 5-point central differences with h = 10⁻² give its
        // derivatives (and δ's) to ~10⁻⁸
        let p = |u: f64, v: f64| f(x(u, v), y(u, v));
        let h = 1e-2;
        let d = |g: &dyn Fn(f64, f64) -> f64, du: usize, dv: usize| -> f64 {
            // repeated 5-point central differences (exact for degree ≤ 4 per application)
            fn diff(g: &dyn Fn(f64) -> f64, t: f64, order: usize, h: f64) -> f64 {
                if order == 0 {
                    return g(t);
                }
                let inner = |s: f64| diff(g, s, order - 1, h);
                (-inner(t + 2.0 * h) + 8.0 * inner(t + h) - 8.0 * inner(t - h) + inner(t - 2.0 * h))
                    / (12.0 * h)
            }
            diff(&|s: f64| diff(&|t: f64| g(s, t), v, dv, h), u, du, h)
        };
        let orders = crate::fair::surface::representation::DERIVATIVE_ORDERS;
        let pd: Derivatives = orders.map(|(a, b)| d(&p, a, b));
        let map: MapDerivatives = orders.map(|(a, b)| [d(&x, a, b), d(&y, a, b)]);
        let rule = InverseChainRule::new(map).unwrap();
        let fd = rule.apply(&pd);
        let (px, py) = (x(u, v), y(u, v));
        let exact = [
            3.0 * px * px - 2.0 * py * py + 1.0,
            -4.0 * px * py + py,
            6.0 * px,
            -4.0 * py,
            -4.0 * px + 1.0,
            6.0,
            0.0,
            -4.0,
            0.0,
        ];
        for (i, (a, b)) in fd.iter().zip(exact).enumerate() {
            assert!(
                (a - b).abs() < 1e-6 * (1.0 + b.abs()),
                "derivative {i}: {a} vs {b}"
            );
        }
    }
}
