//! Q's density (paper eq. 5), ‖P ∇Δp‖²_F with Δp = p_uu + p_vv in the element's parameters
//! and P = I − n nᵀ the projection on the tangent plane, and its gradient by reverse
//! accumulation, written over [`Num`] so that [`crate::fair::functional::tangent::Tangent`] gives the
//! Hessian (forward-over-reverse).

use crate::fair::functional::tangent::{cross, dot, Num, V};

/// Q's density from `q = [p_u, p_v, ∂Δp/∂u, ∂Δp/∂v]`: with the normal n = p_u × p_v left
/// unnormalized, ‖P x‖² = ‖x‖² − (n·x)² / ‖n‖² and ‖n‖² = EG − F².
#[inline(always)]
pub fn q_density<T: Num>(q: &[V<T>; 4]) -> T {
    let [pu, pv, lap_u, lap_v] = q;
    let (e, f, g) = (dot(pu, pu), dot(pu, pv), dot(pv, pv));
    let w2 = e * g - f * f;
    let n = cross(pu, pv);
    let (a, b) = (dot(&n, lap_u), dot(&n, lap_v));
    dot(lap_u, lap_u) + dot(lap_v, lap_v) - (a * a + b * b) / w2
}

/// Q's density and its gradient with respect to `q` (same layout as `q`).
#[inline(always)]
pub fn q_density_gradient<T: Num>(q: &[V<T>; 4]) -> (T, [V<T>; 4]) {
    let [pu, pv, lap_u, lap_v] = q;
    let (e, f, g) = (dot(pu, pu), dot(pu, pv), dot(pv, pv));
    let w2 = e * g - f * f;
    let n = cross(pu, pv);
    let (a, b) = (dot(&n, lap_u), dot(&n, lap_v));
    let k = a * a + b * b;
    let value = dot(lap_u, lap_u) + dot(lap_v, lap_v) - k / w2;
    // Adjoints: k̄ = −1/w2, w̄2 = k/w2², ā = 2a k̄, b̄ = 2b k̄.
    let a_bar = -(a / w2).scale(2.0);
    let b_bar = -(b / w2).scale(2.0);
    let w2_bar = k / (w2 * w2);
    let lu_bar: V<T> = std::array::from_fn(|i| lap_u[i].scale(2.0) + a_bar * n[i]);
    let lv_bar: V<T> = std::array::from_fn(|i| lap_v[i].scale(2.0) + b_bar * n[i]);
    let n_bar: V<T> = std::array::from_fn(|i| a_bar * lap_u[i] + b_bar * lap_v[i]);
    // w2 = e g − f², e = pu·pu, f = pu·pv, g = pv·pv; n = pu × pv.
    let (e_bar, g_bar, f_bar) = (w2_bar * g, w2_bar * e, -(w2_bar * f).scale(2.0));
    let (cu, cv) = (cross(pv, &n_bar), cross(&n_bar, pu));
    let pu_bar: V<T> = std::array::from_fn(|i| (e_bar * pu[i]).scale(2.0) + f_bar * pv[i] + cu[i]);
    let pv_bar: V<T> = std::array::from_fn(|i| (g_bar * pv[i]).scale(2.0) + f_bar * pu[i] + cv[i]);
    (value, [pu_bar, pv_bar, lu_bar, lv_bar])
}

/// Q's density as a sum of squares: the six coordinates of P ∂Δp/∂u and P ∂Δp/∂v, with
/// P x = x − n (n·x) / ‖n‖² (see [`q_density`]); its Jacobian gives the Gauss–Newton part.
#[inline(always)]
pub fn q_residual<T: Num>(q: &[V<T>; 4]) -> [T; 6] {
    let [pu, pv, lap_u, lap_v] = q;
    let n = cross(pu, pv);
    let w2 = dot(&n, &n);
    let (a, b) = (dot(&n, lap_u) / w2, dot(&n, lap_v) / w2);
    std::array::from_fn(|i| {
        if i < 3 {
            lap_u[i] - a * n[i]
        } else {
            lap_v[i - 3] - b * n[i - 3]
        }
    })
}
