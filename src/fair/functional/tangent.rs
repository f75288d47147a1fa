//! The scalars the densities of F are written over: `f64`, [`Tangent`], a first-order
//! forward-mode dual number over the derivative coordinates of a quadrature point, and
//! num-dual's `Dual2_64` along one direction.
//!
//! The per-point Hessian is the Jacobian of the reverse-accumulated gradient
//! ([`crate::fair::functional::s_density::s_density_gradient`]) evaluated over [`Tangent`]s
//! (forward-over-reverse): every operation costs O(27) instead of the O(27²) of a
//! second-order dual, and a value is 224 bytes instead of 3.2 kB.

use std::ops::{Add, Div, Mul, Neg, Sub};

use num_dual::{Dual2_64, DualNum};

/// Scalars with the arithmetic S's density needs.
pub trait Num:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    fn constant(x: f64) -> Self;
    fn scale(self, k: f64) -> Self;
    fn sqrt(self) -> Self;
}

impl Num for f64 {
    #[inline(always)]
    fn constant(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn scale(self, k: f64) -> Self {
        self * k
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
}

/// num-dual's second-order dual along one direction: a residual evaluated over it gives its
/// second directional derivative r_vv exactly
/// ([`crate::fair::functional::evaluation::Functional::residual_curvature`]).
impl Num for Dual2_64 {
    #[inline(always)]
    fn constant(x: f64) -> Self {
        Dual2_64::from_re(x)
    }
    #[inline(always)]
    fn scale(self, k: f64) -> Self {
        Dual2_64::new(self.re * k, self.v1 * k, self.v2 * k)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        DualNum::sqrt(&self)
    }
}

/// A value and its derivatives with respect to `N` variables.
#[derive(Clone, Copy, Debug)]
pub struct Tangent<const N: usize> {
    pub re: f64,
    pub eps: [f64; N],
}

impl<const N: usize> Tangent<N> {
    /// Variable `i` with value `x`.
    pub fn variable(x: f64, i: usize) -> Self {
        let mut eps = [0.0; N];
        eps[i] = 1.0;
        Tangent { re: x, eps }
    }

    /// f(self) from f and f′ at `self.re` (the chain rule).
    #[inline(always)]
    fn chain(mut self, f: f64, d1: f64) -> Self {
        self.re = f;
        for e in self.eps.iter_mut() {
            *e *= d1;
        }
        self
    }
}

impl<const N: usize> Add for Tangent<N> {
    type Output = Self;
    #[inline(always)]
    fn add(mut self, b: Self) -> Self {
        self.re += b.re;
        for i in 0..N {
            self.eps[i] += b.eps[i];
        }
        self
    }
}

impl<const N: usize> Sub for Tangent<N> {
    type Output = Self;
    #[inline(always)]
    fn sub(mut self, b: Self) -> Self {
        self.re -= b.re;
        for i in 0..N {
            self.eps[i] -= b.eps[i];
        }
        self
    }
}

impl<const N: usize> Neg for Tangent<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self.scale(-1.0)
    }
}

impl<const N: usize> Mul for Tangent<N> {
    type Output = Self;
    #[inline(always)]
    #[allow(clippy::suspicious_arithmetic_impl)] // the product rule
    fn mul(mut self, b: Self) -> Self {
        for i in 0..N {
            self.eps[i] = self.re * b.eps[i] + b.re * self.eps[i];
        }
        self.re *= b.re;
        self
    }
}

impl<const N: usize> Div for Tangent<N> {
    type Output = Self;
    #[inline(always)]
    #[allow(clippy::suspicious_arithmetic_impl)] // the quotient rule
    fn div(mut self, b: Self) -> Self {
        // The value divides exactly as f64 does, so values and gradients agree bit for
        // bit with the f64 evaluation of the same formula.
        let r = 1.0 / b.re;
        let q = self.re / b.re;
        for i in 0..N {
            self.eps[i] = (self.eps[i] - q * b.eps[i]) * r;
        }
        self.re = q;
        self
    }
}

impl<const N: usize> Num for Tangent<N> {
    #[inline(always)]
    fn constant(x: f64) -> Self {
        Tangent {
            re: x,
            eps: [0.0; N],
        }
    }
    #[inline(always)]
    fn scale(self, k: f64) -> Self {
        self.chain(self.re * k, k)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        let s = self.re.sqrt();
        self.chain(s, 0.5 / s)
    }
}

/// A 3-vector of [`Num`]s.
pub type V<T> = [T; 3];

#[inline(always)]
pub fn dot<T: Num>(a: &V<T>, b: &V<T>) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline(always)]
pub fn cross<T: Num>(a: &V<T>, b: &V<T>) -> V<T> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
