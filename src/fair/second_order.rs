//! A second-order forward-mode dual number over 27 variables (value, gradient, packed upper
//! triangle of the Hessian) with inlined arithmetic, for the per-quadrature-point Hessian
//! of S's density (paper eq. 3). `num-dual`'s `Dual2Vec` computes the same numbers (the
//! tests compare both, and the assembled Hessian with finite differences), but it moves
//! its 5.8 kB values through out-of-line calls: profiling showed ~60 % of the time in
//! `memmove`. This type keeps the work in place.

use std::ops::{Add, Div, Mul, Sub};

/// Number of variables.
pub const N: usize = 27;
/// Entries of the packed upper triangle.
pub const PACKED: usize = N * (N + 1) / 2;

/// Scalars the densities are written over: `f64` and [`Second`].
pub trait Num:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self>
{
    fn scale(self, k: f64) -> Self;
    fn sqrt(self) -> Self;
}

impl Num for f64 {
    #[inline(always)]
    fn scale(self, k: f64) -> Self {
        self * k
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
}

/// Value, gradient and Hessian (upper triangle, row-major packed) of a function of N
/// variables.
#[derive(Clone, Copy, Debug)]
pub struct Second {
    pub re: f64,
    pub g: [f64; N],
    pub h: [f64; PACKED],
}

impl Second {
    /// Variable `i` with value `x`.
    pub fn variable(x: f64, i: usize) -> Self {
        let mut g = [0.0; N];
        g[i] = 1.0;
        Second {
            re: x,
            g,
            h: [0.0; PACKED],
        }
    }

    /// f(self) from f, f′, f″ at `self.re` (the chain rule to second order).
    #[inline(always)]
    fn chain(self, f: f64, d1: f64, d2: f64) -> Self {
        let mut out = Second {
            re: f,
            g: [0.0; N],
            h: [0.0; PACKED],
        };
        for i in 0..N {
            out.g[i] = d1 * self.g[i];
        }
        let mut k = 0;
        for i in 0..N {
            let gi = d2 * self.g[i];
            for j in i..N {
                out.h[k] = d1 * self.h[k] + gi * self.g[j];
                k += 1;
            }
        }
        out
    }

    /// The full Hessian, row-major.
    pub fn hessian(&self) -> Vec<f64> {
        let mut out = vec![0.0; N * N];
        let mut k = 0;
        for i in 0..N {
            for j in i..N {
                out[i * N + j] = self.h[k];
                out[j * N + i] = self.h[k];
                k += 1;
            }
        }
        out
    }
}

impl Add for Second {
    type Output = Second;
    #[inline(always)]
    fn add(mut self, b: Second) -> Second {
        self.re += b.re;
        for i in 0..N {
            self.g[i] += b.g[i];
        }
        for k in 0..PACKED {
            self.h[k] += b.h[k];
        }
        self
    }
}

impl Sub for Second {
    type Output = Second;
    #[inline(always)]
    fn sub(mut self, b: Second) -> Second {
        self.re -= b.re;
        for i in 0..N {
            self.g[i] -= b.g[i];
        }
        for k in 0..PACKED {
            self.h[k] -= b.h[k];
        }
        self
    }
}

impl Mul for Second {
    type Output = Second;
    #[inline(always)]
    fn mul(self, b: Second) -> Second {
        let mut out = Second {
            re: self.re * b.re,
            g: [0.0; N],
            h: [0.0; PACKED],
        };
        for i in 0..N {
            out.g[i] = self.re * b.g[i] + b.re * self.g[i];
        }
        let mut k = 0;
        for i in 0..N {
            let (ai, bi) = (self.g[i], b.g[i]);
            for j in i..N {
                out.h[k] = self.re * b.h[k] + b.re * self.h[k] + ai * b.g[j] + bi * self.g[j];
                k += 1;
            }
        }
        out
    }
}

impl Div for Second {
    type Output = Second;
    #[inline(always)]
    fn div(self, b: Second) -> Second {
        let r = 1.0 / b.re;
        self * b.chain(r, -r * r, 2.0 * r * r * r)
    }
}

impl Num for Second {
    #[inline(always)]
    fn scale(mut self, k: f64) -> Self {
        self.re *= k;
        for i in 0..N {
            self.g[i] *= k;
        }
        for x in self.h.iter_mut() {
            *x *= k;
        }
        self
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        let s = self.re.sqrt();
        self.chain(s, 0.5 / s, -0.25 / (s * self.re))
    }
}

#[inline(always)]
fn dot<T: Num>(a: &[T; 3], b: &[T; 3]) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline(always)]
fn cross<T: Num>(a: &[T; 3], b: &[T; 3]) -> [T; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Density of S (eq. 3), ∇H G⁻¹ ∇Hᵀ √det G, with ∂H/∂u and ∂H/∂v by the product rule
/// on H = (E Ñ − 2 F M̃ + G L̃) / (2 W³) (L̃, M̃, Ñ the second fundamental form times W,
/// W² = EG − F²): for a direction with tangents (p_u′, …), H′ = (num′ − 1.5 num (W²)′ /
/// W²) / (2 W³).
pub fn s_density<T: Num>(d: &[[T; 3]; 9]) -> T {
    let [pu, pv, puu, puv, pvv, puuu, puuv, puvv, pvvv] = d;
    let (e, f, g) = (dot(pu, pu), dot(pu, pv), dot(pv, pv));
    let n = cross(pu, pv);
    let w2 = e * g - f * f;
    let (l, m, nn) = (dot(puu, &n), dot(puv, &n), dot(pvv, &n));
    let num = e * nn - (f * m).scale(2.0) + g * l;
    let w3 = w2 * w2.sqrt();
    let along = |a_pu: &[T; 3], a_pv: &[T; 3], a_puu: &[T; 3], a_puv: &[T; 3], a_pvv: &[T; 3]| {
        let e1 = dot(pu, a_pu).scale(2.0);
        let f1 = dot(a_pu, pv) + dot(pu, a_pv);
        let g1 = dot(pv, a_pv).scale(2.0);
        let c1 = cross(a_pu, pv);
        let c2 = cross(pu, a_pv);
        let n1 = [c1[0] + c2[0], c1[1] + c2[1], c1[2] + c2[2]];
        let l1 = dot(a_puu, &n) + dot(puu, &n1);
        let m1 = dot(a_puv, &n) + dot(puv, &n1);
        let nn1 = dot(a_pvv, &n) + dot(pvv, &n1);
        let w21 = e1 * g + e * g1 - (f * f1).scale(2.0);
        let num1 = e1 * nn + e * nn1 - (f1 * m + f * m1).scale(2.0) + g1 * l + g * l1;
        (num1 - (num * w21 / w2).scale(1.5)) / w3.scale(2.0)
    };
    let hu = along(puu, puv, puuu, puuv, puvv);
    let hv = along(puv, pvv, puuv, puvv, pvvv);
    (hu * hu * g - (hu * hv * f).scale(2.0) + hv * hv * e) / w2.sqrt()
}
