//! The generalized offset s_f = f + d₁e₁ + d₂e₂ + d₃n (2022 (2)–(3), 2024 (2)–(3)): the
//! frame (e₁, e₂, n) comes from the first derivatives of f.

use crate::error::{Error, Result};
use crate::mesh::vector::{cross, norm};

/// A parametric surface with its first partial derivatives.
pub trait ParametricSurface {
    /// (f, ∂f/∂u, ∂f/∂v) at (u, v).
    fn eval(&self, u: f64, v: f64) -> [[f64; 3]; 3];
}

impl<F: Fn(f64, f64) -> [[f64; 3]; 3]> ParametricSurface for F {
    fn eval(&self, u: f64, v: f64) -> [[f64; 3]; 3] {
        self(u, v)
    }
}

/// The unit normal (f_u × f_v)/‖f_u × f_v‖ of a parametric surface (2004 §2, 2022 (2)).
///
/// Errors: `InvalidInput` where the surface is not regular.
pub fn unit_normal<S: ParametricSurface>(s: &S, u: f64, v: f64) -> Result<[f64; 3]> {
    let [_, fu, fv] = s.eval(u, v);
    let n = cross(fu, fv);
    let c = norm(n);
    if !(c > 0.0 && c.is_finite()) {
        return Err(Error::InvalidInput(format!(
            "the surface is not regular at ({u}, {v})"
        )));
    }
    Ok(n.map(|x| x / c))
}

type Distance = Box<dyn Fn(f64, f64) -> f64 + Send + Sync>;

/// A surface and three offset distances d₁, d₂, d₃ along e₁, e₂ and n.
pub struct GeneralizedOffset<S: ParametricSurface> {
    /// The progenitor surface f.
    pub surface: S,
    /// d₁, d₂, d₃ as functions of (u, v).
    pub distances: [Distance; 3],
}

impl<S: ParametricSurface> GeneralizedOffset<S> {
    /// The unit frame (e₁, e₂, n) of (2): e₁ = f_u/‖f_u‖, e₂ = f_v/‖f_v‖,
    /// n = f_u × f_v / ‖f_u × f_v‖.
    ///
    /// Errors: `InvalidInput` where f is not regular (a vanishing derivative or normal) or
    /// not finite.
    pub fn frame(&self, u: f64, v: f64) -> Result<[[f64; 3]; 3]> {
        let [_, fu, fv] = self.surface.eval(u, v);
        let n = cross(fu, fv);
        let (a, b, c) = (norm(fu), norm(fv), norm(n));
        if !(a > 0.0 && b > 0.0 && c > 0.0 && a.is_finite() && b.is_finite() && c.is_finite()) {
            return Err(Error::InvalidInput(format!(
                "the surface is not regular at ({u}, {v}): ‖f_u‖ = {a}, ‖f_v‖ = {b}, ‖f_u × f_v‖ = {c}"
            )));
        }
        Ok([fu.map(|x| x / a), fv.map(|x| x / b), n.map(|x| x / c)])
    }

    /// s_f(u, v) of (3).
    ///
    /// Errors: as [`GeneralizedOffset::frame`], or a non-finite distance.
    pub fn point(&self, u: f64, v: f64) -> Result<[f64; 3]> {
        let f = self.surface.eval(u, v)[0];
        let [e1, e2, n] = self.frame(u, v)?;
        let d = [
            (self.distances[0])(u, v),
            (self.distances[1])(u, v),
            (self.distances[2])(u, v),
        ];
        if d.iter().any(|x| !x.is_finite()) {
            return Err(Error::InvalidInput(format!(
                "offset distance not finite at ({u}, {v})"
            )));
        }
        Ok(std::array::from_fn(|k| {
            f[k] + d[0] * e1[k] + d[1] * e2[k] + d[2] * n[k]
        }))
    }

    /// d₁e₁ + d₂e₂ + d₃n at (u, v): the offset terms the 2024 method subtracts and adds back.
    ///
    /// Errors: as [`GeneralizedOffset::point`].
    pub fn displacement(&self, u: f64, v: f64) -> Result<[f64; 3]> {
        let s = self.point(u, v)?;
        let f = self.surface.eval(u, v)[0];
        Ok(std::array::from_fn(|k| s[k] - f[k]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::tolerance::ROUND_OFF;

    #[test]
    fn normal_offset_of_a_sphere_patch_is_a_larger_sphere() {
        // f(u, v) = (cos u cos v, sin u cos v, sin v) on the unit sphere; f_u × f_v =
        // cos v · f points outward, so |s_f| = 1 + d₃ with d₁ = d₂ = 0.
        let f = |u: f64, v: f64| {
            [
                [u.cos() * v.cos(), u.sin() * v.cos(), v.sin()],
                [-u.sin() * v.cos(), u.cos() * v.cos(), 0.0],
                [-u.cos() * v.sin(), -u.sin() * v.sin(), v.cos()],
            ]
        };
        let off = GeneralizedOffset {
            surface: f,
            distances: [
                Box::new(|_, _| 0.0),
                Box::new(|_, _| 0.0),
                Box::new(|_, _| 0.25),
            ],
        };
        let p = off.point(0.3, 0.4).unwrap();
        assert_near!(norm(p), 1.25, ROUND_OFF);
        let [e1, e2, n] = off.frame(0.3, 0.4).unwrap();
        assert_near!(norm(e1), 1.0, ROUND_OFF);
        assert_near!(e1[0] * n[0] + e1[1] * n[1] + e1[2] * n[2], 0.0, ROUND_OFF);
        assert_near!(e2[0] * n[0] + e2[1] * n[1] + e2[2] * n[2], 0.0, ROUND_OFF);
    }

    #[test]
    fn singular_point_is_an_error() {
        let f = |_: f64, _: f64| [[0.0; 3], [1.0, 0.0, 0.0], [0.0; 3]];
        let off = GeneralizedOffset {
            surface: f,
            distances: [
                Box::new(|_, _| 0.0),
                Box::new(|_, _| 0.0),
                Box::new(|_, _| 1.0),
            ],
        };
        assert!(off.point(0.0, 0.0).is_err());
    }
}
