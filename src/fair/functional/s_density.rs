//! S's density (paper eq. 3), ∇H G⁻¹ ∇Hᵀ √det G, and its gradient with respect to the nine
//! derivatives by reverse accumulation, written once over [`Num`] so that `f64` gives the
//! gradient and [`crate::fair::functional::tangent::Tangent`] the Hessian (forward-over-reverse).
//!
//! ∂H/∂u and ∂H/∂v come from the product rule on H = (E Ñ − 2 F M̃ + G L̃) / (2 W³) (L̃, M̃,
//! Ñ the second fundamental form times W, W² = EG − F²): along a direction with tangents
//! (p_u′, …), H′ = (num′ − 1.5 num (W²)′ / W²) / (2 W³).

use crate::fair::functional::tangent::{cross, dot, Num, V};

#[inline(always)]
fn add<T: Num>(a: &V<T>, b: &V<T>) -> V<T> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `acc += k v`.
#[inline(always)]
fn axpy<T: Num>(acc: &mut V<T>, k: T, v: &V<T>) {
    for a in 0..3 {
        acc[a] = acc[a] + k * v[a];
    }
}

/// Quantities of the surface point shared by both directions.
struct Point<T> {
    e: T,
    f: T,
    g: T,
    n: V<T>,
    w2: T,
    l: T,
    m: T,
    nn: T,
    num: T,
    w: T,
    w3: T,
}

#[inline(always)]
fn point<T: Num>(pu: &V<T>, pv: &V<T>, puu: &V<T>, puv: &V<T>, pvv: &V<T>) -> Point<T> {
    let (e, f, g) = (dot(pu, pu), dot(pu, pv), dot(pv, pv));
    let n = cross(pu, pv);
    let w2 = e * g - f * f;
    let (l, m, nn) = (dot(puu, &n), dot(puv, &n), dot(pvv, &n));
    let num = e * nn - (f * m).scale(2.0) + g * l;
    let w = w2.sqrt();
    Point {
        e,
        f,
        g,
        n,
        w2,
        l,
        m,
        nn,
        num,
        w,
        w3: w2 * w,
    }
}

/// Mean curvature H = (E N − 2 F M + G L) / (2 (EG − F²)) at a point with derivatives `d`
/// (first and second used; the normal left unnormalized: L, M, N carry a factor W).
#[inline(always)]
pub fn mean_curvature<T: Num>(d: &[V<T>; 9]) -> T {
    let p = point(&d[0], &d[1], &d[2], &d[3], &d[4]);
    p.num / p.w3.scale(2.0)
}

/// The tangents of (p_u, p_v, p_uu, p_uv, p_vv) along u or v.
type Along<'a, T> = [&'a V<T>; 5];

/// Intermediate values of one directional derivative of H.
struct Directional<T> {
    e1: T,
    f1: T,
    g1: T,
    n1: V<T>,
    l1: T,
    m1: T,
    nn1: T,
    w21: T,
    h: T,
}

#[inline(always)]
fn directional<T: Num>(base: &[&V<T>; 5], p: &Point<T>, a: &Along<'_, T>) -> Directional<T> {
    let [pu, pv, puu, puv, pvv] = *base;
    let [a_pu, a_pv, a_puu, a_puv, a_pvv] = *a;
    let e1 = dot(pu, a_pu).scale(2.0);
    let f1 = dot(a_pu, pv) + dot(pu, a_pv);
    let g1 = dot(pv, a_pv).scale(2.0);
    let n1 = add(&cross(a_pu, pv), &cross(pu, a_pv));
    let l1 = dot(a_puu, &p.n) + dot(puu, &n1);
    let m1 = dot(a_puv, &p.n) + dot(puv, &n1);
    let nn1 = dot(a_pvv, &p.n) + dot(pvv, &n1);
    let w21 = e1 * p.g + p.e * g1 - (p.f * f1).scale(2.0);
    let num1 = e1 * p.nn + p.e * nn1 - (f1 * p.m + p.f * m1).scale(2.0) + g1 * p.l + p.g * l1;
    let h = (num1 - (p.num * w21 / p.w2).scale(1.5)) / p.w3.scale(2.0);
    Directional {
        e1,
        f1,
        g1,
        n1,
        l1,
        m1,
        nn1,
        w21,
        h,
    }
}

/// The two directions of eq. 3: u and v.
#[inline(always)]
fn directions<T>(d: &[V<T>; 9]) -> [Along<'_, T>; 2] {
    let [_, _, puu, puv, pvv, puuu, puuv, puvv, pvvv] = d;
    [[puu, puv, puuu, puuv, puvv], [puv, pvv, puuv, puvv, pvvv]]
}

/// S's density at a point with derivatives `d = [p_u, p_v, p_uu, p_uv, p_vv, p_uuu, p_uuv,
/// p_uvv, p_vvv]` (eq. 3).
#[inline(always)]
pub fn s_density<T: Num>(d: &[V<T>; 9]) -> T {
    let base = [&d[0], &d[1], &d[2], &d[3], &d[4]];
    let p = point(base[0], base[1], base[2], base[3], base[4]);
    let [du, dv] = directions(d).map(|a| directional(&base, &p, &a).h);
    (du * du * p.g - (du * dv * p.f).scale(2.0) + dv * dv * p.e) / p.w
}

/// S's density as a sum of two squares, r₁² + r₂² (eq. 3 with G⁻¹ = L⁻ᵀL⁻¹, G = LLᵀ):
/// r = √W · L⁻¹ ∇Hᵀ = √W · (H_u / √E, (E H_v − F H_u) / (√E W)). Its Jacobian gives the
/// Gauss–Newton part 2 JᵀJ of the density's Hessian, positive semidefinite everywhere.
#[inline(always)]
pub fn s_residual<T: Num>(d: &[V<T>; 9]) -> [T; 2] {
    let base = [&d[0], &d[1], &d[2], &d[3], &d[4]];
    let p = point(base[0], base[1], base[2], base[3], base[4]);
    let [hu, hv] = directions(d).map(|a| directional(&base, &p, &a).h);
    residual(hu, hv, &p)
}

/// [`s_residual`] from H_u, H_v and the point's metric.
#[inline(always)]
fn residual<T: Num>(hu: T, hv: T, p: &Point<T>) -> [T; 2] {
    let root_e = p.e.sqrt();
    let root_w = p.w.sqrt();
    [
        root_w * hu / root_e,
        (p.e * hv - p.f * hu) / (root_e * root_w),
    ]
}

/// Adjoints of the base quantities, accumulated by both directions.
struct PointBar<T> {
    e: T,
    f: T,
    g: T,
    n: V<T>,
    w2: T,
    l: T,
    m: T,
    nn: T,
    num: T,
    w3: T,
}

/// Pushes the adjoint `h_bar` of one directional derivative back to the base quantities
/// (`pb`) and to the nine derivatives (`out`); the direction comes with its tangents, its
/// intermediate values and `slots`, the indices of its five tangents in `out`.
#[inline(always)]
fn directional_adjoint<T: Num>(
    base: &[&V<T>; 5],
    p: &Point<T>,
    (a, dir, slots): (&Along<'_, T>, &Directional<T>, [usize; 5]),
    h_bar: T,
    pb: &mut PointBar<T>,
    out: &mut [V<T>; 9],
) {
    let [pu, pv, ..] = *base;
    let [a_pu, a_pv, a_puu, a_puv, a_pvv] = *a;
    let zero = T::constant(0.0);
    // h = A / (2 w3), A = num1 − 1.5 num w21 / w2.
    let a_bar = h_bar / p.w3.scale(2.0);
    pb.w3 = pb.w3 - h_bar * dir.h / p.w3;
    let num1_bar = a_bar;
    pb.num = pb.num - (a_bar * dir.w21 / p.w2).scale(1.5);
    let w21_bar = -(a_bar * p.num / p.w2).scale(1.5);
    pb.w2 = pb.w2 + (a_bar * p.num * dir.w21 / (p.w2 * p.w2)).scale(1.5);
    // num1 = e1 nn + e nn1 − 2 (f1 m + f m1) + g1 l + g l1.
    let mut e1_bar = num1_bar * p.nn;
    pb.nn = pb.nn + num1_bar * dir.e1;
    pb.e = pb.e + num1_bar * dir.nn1;
    let nn1_bar = num1_bar * p.e;
    let mut f1_bar = -(num1_bar * p.m).scale(2.0);
    pb.m = pb.m - (num1_bar * dir.f1).scale(2.0);
    pb.f = pb.f - (num1_bar * dir.m1).scale(2.0);
    let m1_bar = -(num1_bar * p.f).scale(2.0);
    let mut g1_bar = num1_bar * p.l;
    pb.l = pb.l + num1_bar * dir.g1;
    pb.g = pb.g + num1_bar * dir.l1;
    let l1_bar = num1_bar * p.g;
    // w21 = e1 g + e g1 − 2 f f1.
    e1_bar = e1_bar + w21_bar * p.g;
    pb.g = pb.g + w21_bar * dir.e1;
    pb.e = pb.e + w21_bar * dir.g1;
    g1_bar = g1_bar + w21_bar * p.e;
    pb.f = pb.f - (w21_bar * dir.f1).scale(2.0);
    f1_bar = f1_bar - (w21_bar * p.f).scale(2.0);
    // l1, m1, nn1 = (a_puu, a_puv, a_pvv)·n + (puu, puv, pvv)·n1.
    let mut n1_bar = [zero; 3];
    for (bar, a_x, k) in [(l1_bar, a_puu, 2), (m1_bar, a_puv, 3), (nn1_bar, a_pvv, 4)] {
        axpy(&mut out[slots[k]], bar, &p.n);
        axpy(&mut pb.n, bar, a_x);
        axpy(&mut out[k], bar, &dir.n1);
        axpy(&mut n1_bar, bar, base[k]);
    }
    // n1 = a_pu × pv + pu × a_pv; for c = a × b: ā += b × c̄, b̄ += c̄ × a.
    let t = cross(pv, &n1_bar);
    out[slots[0]] = add(&out[slots[0]], &t);
    let t = cross(&n1_bar, a_pu);
    out[1] = add(&out[1], &t);
    let t = cross(a_pv, &n1_bar);
    out[0] = add(&out[0], &t);
    let t = cross(&n1_bar, pu);
    out[slots[1]] = add(&out[slots[1]], &t);
    // e1 = 2 pu·a_pu, f1 = a_pu·pv + pu·a_pv, g1 = 2 pv·a_pv.
    axpy(&mut out[0], e1_bar.scale(2.0), a_pu);
    axpy(&mut out[slots[0]], e1_bar.scale(2.0), pu);
    axpy(&mut out[slots[0]], f1_bar, pv);
    axpy(&mut out[1], f1_bar, a_pu);
    axpy(&mut out[0], f1_bar, a_pv);
    axpy(&mut out[slots[1]], f1_bar, pu);
    axpy(&mut out[1], g1_bar.scale(2.0), a_pv);
    axpy(&mut out[slots[1]], g1_bar.scale(2.0), pv);
}

/// S's density and its gradient with respect to the nine derivatives (same order as `d`),
/// by reverse accumulation through [`s_density`]'s operations.
#[inline(always)]
pub fn s_density_gradient<T: Num>(d: &[V<T>; 9]) -> (T, [V<T>; 9]) {
    let (value, out, _) = s_density_gradient_residual(d);
    (value, out)
}

/// [`s_density_gradient`] and [`s_residual`] from one evaluation of H_u and H_v.
#[inline(always)]
pub fn s_density_gradient_residual<T: Num>(d: &[V<T>; 9]) -> (T, [V<T>; 9], [T; 2]) {
    let forward = Forward::new(d);
    let (hu, hv, p) = (forward.du.h, forward.dv.h, &forward.p);
    // D = P / w, P = hu² g − 2 hu hv f + hv² e.
    let pp = hu * hu * p.g - (hu * hv * p.f).scale(2.0) + hv * hv * p.e;
    let value = pp / p.w;
    let p_bar = T::constant(1.0) / p.w;
    let bars = Bars {
        hu: p_bar * (hu * p.g - hv * p.f).scale(2.0),
        hv: p_bar * (hv * p.e - hu * p.f).scale(2.0),
        e: p_bar * hv * hv,
        f: -(p_bar * hu * hv).scale(2.0),
        g: p_bar * hu * hu,
        w: -value / p.w,
    };
    (value, forward.backward(bars), residual(hu, hv, p))
}

/// Jᵀ u for J the Jacobian of [`s_residual`] with respect to the nine derivatives: the
/// gradient of u · r by reverse accumulation, at the cost of one gradient of the density
/// (forward mode would carry 27 tangents through every operation).
#[inline(always)]
pub fn s_residual_transpose_product<T: Num>(d: &[V<T>; 9], u: [T; 2]) -> [V<T>; 9] {
    let forward = Forward::new(d);
    let (hu, hv, p) = (forward.du.h, forward.dv.h, &forward.p);
    // r₁ = √w hu / √e, r₂ = (e hv − f hu) / (√e √w).
    let [r1, r2] = residual(hu, hv, p);
    let (root_e, root_w) = (p.e.sqrt(), p.w.sqrt());
    let k = root_e * root_w;
    let bars = Bars {
        hu: u[0] * root_w / root_e - u[1] * p.f / k,
        hv: u[1] * root_e / root_w,
        e: u[1] * hv / k - (u[0] * r1 + u[1] * r2).scale(0.5) / p.e,
        f: -(u[1] * hu / k),
        g: T::constant(0.0),
        w: (u[0] * r1 - u[1] * r2).scale(0.5) / p.w,
    };
    forward.backward(bars)
}

/// The forward sweep both reverse accumulations share: the point's quantities and H_u,
/// H_v with their intermediates.
struct Forward<'a, T> {
    d: &'a [V<T>; 9],
    base: [&'a V<T>; 5],
    p: Point<T>,
    along: [Along<'a, T>; 2],
    du: Directional<T>,
    dv: Directional<T>,
}

/// Adjoints of a function of (H_u, H_v, E, F, G, W) at the point, its direct dependences
/// (W = √(EG − F²)).
struct Bars<T> {
    hu: T,
    hv: T,
    e: T,
    f: T,
    g: T,
    w: T,
}

impl<'a, T: Num> Forward<'a, T> {
    #[inline(always)]
    fn new(d: &'a [V<T>; 9]) -> Self {
        let base = [&d[0], &d[1], &d[2], &d[3], &d[4]];
        let p = point(base[0], base[1], base[2], base[3], base[4]);
        let along = directions(d);
        let du = directional(&base, &p, &along[0]);
        let dv = directional(&base, &p, &along[1]);
        Forward {
            d,
            base,
            p,
            along,
            du,
            dv,
        }
    }

    /// The gradient with respect to the nine derivatives of a function with adjoints
    /// `bars`, by reverse accumulation through H_u, H_v and the point's quantities.
    #[inline(always)]
    fn backward(&self, bars: Bars<T>) -> [V<T>; 9] {
        let zero = T::constant(0.0);
        let (d, base, p) = (self.d, &self.base, &self.p);
        let mut pb = PointBar {
            e: bars.e,
            f: bars.f,
            g: bars.g,
            n: [zero; 3],
            w2: zero,
            l: zero,
            m: zero,
            nn: zero,
            num: zero,
            w3: zero,
        };
        let mut out = [[zero; 3]; 9];
        directional_adjoint(
            base,
            p,
            (&self.along[0], &self.du, [2, 3, 5, 6, 7]),
            bars.hu,
            &mut pb,
            &mut out,
        );
        directional_adjoint(
            base,
            p,
            (&self.along[1], &self.dv, [3, 4, 6, 7, 8]),
            bars.hv,
            &mut pb,
            &mut out,
        );
        // w3 = w2 w, w = √w2.
        let mut w2_bar = pb.w2 + pb.w3 * p.w;
        let w_total = bars.w + pb.w3 * p.w2;
        w2_bar = w2_bar + w_total / p.w.scale(2.0);
        // num = e nn − 2 f m + g l.
        pb.e = pb.e + pb.num * p.nn;
        pb.nn = pb.nn + pb.num * p.e;
        pb.f = pb.f - (pb.num * p.m).scale(2.0);
        pb.m = pb.m - (pb.num * p.f).scale(2.0);
        pb.g = pb.g + pb.num * p.l;
        pb.l = pb.l + pb.num * p.g;
        // l, m, nn = (puu, puv, pvv)·n.
        for (bar, slot) in [(pb.l, 2), (pb.m, 3), (pb.nn, 4)] {
            axpy(&mut out[slot], bar, &p.n);
            let x = d[slot];
            axpy(&mut pb.n, bar, &x);
        }
        // w2 = e g − f².
        pb.e = pb.e + w2_bar * p.g;
        pb.g = pb.g + w2_bar * p.e;
        pb.f = pb.f - (w2_bar * p.f).scale(2.0);
        // n = pu × pv.
        let t = cross(&d[1], &pb.n);
        out[0] = add(&out[0], &t);
        let t = cross(&pb.n, &d[0]);
        out[1] = add(&out[1], &t);
        // e = pu·pu, f = pu·pv, g = pv·pv.
        axpy(&mut out[0], pb.e.scale(2.0), &d[0]);
        axpy(&mut out[0], pb.f, &d[1]);
        axpy(&mut out[1], pb.f, &d[0]);
        axpy(&mut out[1], pb.g.scale(2.0), &d[1]);
        out
    }
}
