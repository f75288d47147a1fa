//! Q's density (paper eq. 5), ‖P ∇Δp‖²_F with Δp = p_uu + p_vv in the element's parameters
//! and P = I − n nᵀ the projection on the tangent plane, and its gradient by reverse
//! accumulation, written over [`Num`] so that [`crate::fair::functional::tangent::Tangent`] gives the
//! Hessian (forward-over-reverse).
//!
//! All of them start from the tangential parts r = P x themselves, never from
//! ‖x‖² − (n·x)²/‖n‖²: where ∇Δp is almost normal that difference (and the terms of its
//! gradient, of size ‖x‖²) cancels to a round-off of ε ‖x‖², far above ‖r‖² (tested).
//! On the meshes measured so far it made no difference (the 223k junction's gradient at
//! its minimum: the same to 10⁻¹²); its floor is the coordinates'.

use crate::fair::functional::tangent::{cross, dot, Num, V};

/// x − n (n·x)/‖n‖² for x = ∂Δp/∂u and ∂Δp/∂v, with the coefficients (n·x)/‖n‖² along the
/// unnormalized normal n = p_u × p_v.
struct Projection<T> {
    along_normal: [T; 2],
    tangential: [V<T>; 2],
}

#[inline(always)]
fn projection<T: Num>(q: &[V<T>; 4]) -> Projection<T> {
    let [pu, pv, lap_u, lap_v] = q;
    let n = cross(pu, pv);
    let w2 = dot(&n, &n);
    let along_normal = [dot(&n, lap_u) / w2, dot(&n, lap_v) / w2];
    let tangential = [lap_u, lap_v];
    let tangential =
        std::array::from_fn(|k| std::array::from_fn(|i| tangential[k][i] - along_normal[k] * n[i]));
    Projection {
        along_normal,
        tangential,
    }
}

/// Q's density ‖r_u‖² + ‖r_v‖² from `q = [p_u, p_v, ∂Δp/∂u, ∂Δp/∂v]`, r = P ∂Δp/∂u, P ∂Δp/∂v.
#[inline(always)]
pub fn q_density<T: Num>(q: &[V<T>; 4]) -> T {
    let [ru, rv] = projection(q).tangential;
    dot(&ru, &ru) + dot(&rv, &rv)
}

/// Q's density and its gradient with respect to `q` (same layout as `q`).
///
/// With α = (n·x)/‖n‖²: ∂‖r‖²/∂x = 2 P r = 2 r and ∂‖r‖²/∂n = −2 α r, so the adjoint of n
/// is n̄ = −2 (α_u r_u + α_v r_v), of the size of r, and p̄_u = p_v × n̄, p̄_v = n̄ × p_u.
#[inline(always)]
pub fn q_density_gradient<T: Num>(q: &[V<T>; 4]) -> (T, [V<T>; 4]) {
    let [pu, pv, _, _] = q;
    let Projection {
        along_normal: [au, av],
        tangential: [ru, rv],
    } = projection(q);
    let value = dot(&ru, &ru) + dot(&rv, &rv);
    let n_bar: V<T> = std::array::from_fn(|i| -(au * ru[i] + av * rv[i]).scale(2.0));
    let lu_bar = ru.map(|r| r.scale(2.0));
    let lv_bar = rv.map(|r| r.scale(2.0));
    (
        value,
        [cross(pv, &n_bar), cross(&n_bar, pu), lu_bar, lv_bar],
    )
}

/// Jᵀ u for J the Jacobian of [`q_residual`] with respect to `q` (same layout), u = (u_u,
/// u_v) over (r_u, r_v): the gradient of u · r by reverse accumulation.
///
/// With r = x − α n, α = (n·x)/‖n‖²: ∂(u·r)/∂x = P u and ∂(u·r)/∂n = −α u − (u·n)(x −
/// 2 α n)/‖n‖²; p̄_u = p_v × n̄, p̄_v = n̄ × p_u.
#[inline(always)]
pub fn q_residual_transpose_product<T: Num>(q: &[V<T>; 4], u: [V<T>; 2]) -> [V<T>; 4] {
    let [pu, pv, lap_u, lap_v] = q;
    let n = cross(pu, pv);
    let w2 = dot(&n, &n);
    let mut n_bar = [T::constant(0.0); 3];
    let mut x_bar = [[T::constant(0.0); 3]; 2];
    for (k, x) in [lap_u, lap_v].into_iter().enumerate() {
        let alpha = dot(&n, x) / w2;
        let un = dot(&u[k], &n) / w2;
        for i in 0..3 {
            x_bar[k][i] = u[k][i] - un * n[i];
            n_bar[i] = n_bar[i] - alpha * u[k][i] - un * (x[i] - (alpha * n[i]).scale(2.0));
        }
    }
    [cross(pv, &n_bar), cross(&n_bar, pu), x_bar[0], x_bar[1]]
}

/// Q's density as a sum of squares: the six coordinates of P ∂Δp/∂u and P ∂Δp/∂v, with
/// P x = x − n (n·x) / ‖n‖² (see [`q_density`]); its Jacobian gives the Gauss–Newton part.
#[inline(always)]
pub fn q_residual<T: Num>(q: &[V<T>; 4]) -> [T; 6] {
    let [ru, rv] = projection(q).tangential;
    std::array::from_fn(|i| if i < 3 { ru[i] } else { rv[i - 3] })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    /// The rotation of the unit quaternion (1, 2, 3, 4)/√30, so that no coordinate is exact.
    fn rotate(x: [f64; 3]) -> [f64; 3] {
        let (w, a, b, c) = (1.0, 2.0, 3.0, 4.0);
        let s = 2.0 / 30.0;
        let m = [
            [
                1.0 - s * (b * b + c * c),
                s * (a * b - w * c),
                s * (a * c + w * b),
            ],
            [
                s * (a * b + w * c),
                1.0 - s * (a * a + c * c),
                s * (b * c - w * a),
            ],
            [
                s * (a * c - w * b),
                s * (b * c + w * a),
                1.0 - s * (a * a + b * b),
            ],
        ];
        std::array::from_fn(|i| dot(&m[i], &x))
    }

    /// Tangential parts of ∂Δp/∂u, ∂Δp/∂v in the frame before rotation.
    const TANGENTIAL: [[f64; 3]; 2] = [[0.01, -0.02, 0.0], [0.03, 0.005, 0.0]];

    /// A point whose ∂Δp/∂u, ∂Δp/∂v are the tangential parts plus `l` and −`l`/2 times the
    /// normal (p_u = (1, 0, 0), p_v = (1/4, 1, 0) before rotation: n = (0, 0, 1)).
    fn nearly_normal(l: f64) -> [V<f64>; 4] {
        let [tu, tv] = TANGENTIAL;
        [
            rotate([1.0, 0.0, 0.0]),
            rotate([0.25, 1.0, 0.0]),
            rotate([tu[0], tu[1], l]),
            rotate([tv[0], tv[1], -0.5 * l]),
        ]
    }

    /// Third derivatives 10⁵ times their tangential parts, as near a minimum with a large c:
    /// Q is ‖r_u‖² + ‖r_v‖² of the tangential parts, and its gradient is linear in the
    /// normal parts (∂/∂(p_u, p_v) through n̄ = −2 Σ α r, α ∝ l) and constant in them
    /// (∂/∂∇Δp = 2 r), so it is the gradient at l = 1 (no cancellation there) scaled. The
    /// inputs' own rounding, ε·10⁵ against tangential parts of 10⁻², allows 10⁻⁹; the
    /// difference form ‖x‖² − (n·x)²/‖n‖² was off by 10⁻³ of Q.
    #[test]
    fn nearly_normal_third_derivatives_keep_q_and_its_gradient_accurate() {
        const INPUT_ROUNDING: f64 = 1e-9;
        let large = 1e5;
        let exact: f64 = TANGENTIAL.iter().flatten().map(|t| t * t).sum();
        let (value, gradient) = q_density_gradient(&nearly_normal(large));
        assert_near!(value / exact, 1.0, INPUT_ROUNDING);
        assert_near!(
            q_density(&nearly_normal(large)) / exact,
            1.0,
            INPUT_ROUNDING
        );
        let (_, unit) = q_density_gradient(&nearly_normal(1.0));
        let scale = gradient
            .iter()
            .flatten()
            .fold(0.0f64, |m, g| m.max(g.abs()));
        for k in 0..4 {
            let factor = if k < 2 { large } else { 1.0 };
            for a in 0..3 {
                assert_near!(
                    gradient[k][a] / scale,
                    factor * unit[k][a] / scale,
                    INPUT_ROUNDING,
                    "∂Q/∂q[{k}][{a}]"
                );
            }
        }
    }
}
