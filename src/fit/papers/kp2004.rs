//! The examples of Kouibia & Pasadas 2004 (J. Comput. Appl. Math. 164–165) §6: m = 3,
//! ε = 1e-7, τ = 10, B = 2500 points uniformly distributed (a 50 × 50 lattice of cell
//! centres here), BFS C² on 6 × 6 equal squares: a system of order 1323.
//!
//! Readings of the text, whose minus signs were lost in print: example 1 has
//! pₐ = x₀(a) + 4a₁(1 − a₁)a₂(1 − a₂)N(a) + (0, 0, 2); example 2 has
//! x₀ = (u, v, e^{−(u−½)² − (v−½)²}) and
//! pₐ = (−0.1 + 0.5a₁, −0.1 + 0.5a₂, 0.9065 + 0.686(a₁ − a₁² + a₂ − a₂²) +
//! 1.608(a₁a₂ − a₁²a₂ − a₁a₂² + a₁²a₂²)). The unit normal is (D₁x₀ × D₂x₀)/‖D₁x₀ × D₂x₀‖
//! (the printed denominator ⟨D₁x₀, D₂x₀⟩ is a typo).

use serde::Serialize;

use crate::error::Result;
use crate::mesh::PolygonMesh;
use crate::spline::{Hermite1d, Partition, TensorSpace};

use super::kp2022::SurfaceFn;
use crate::fit::offset::unit_normal;
use crate::fit::parallel::{parallel_fit, ParallelFit, ParallelOptions};
use crate::fit::sample::sample_mesh;
use crate::fit::surface::VectorSpline;

/// The paper's parameters.
pub const EPSILON: f64 = 1e-7;
/// The paper's τ.
pub const TAU: f64 = 10.0;
/// The semi-norm order.
pub const M: usize = 3;
/// Samples per side of the figures: a multiple of 6, so the data sites of both examples
/// (steps 2/3 on [−2, 2], ½ on [0, 1]) are sample points.
pub const FIGURE_RESOLUTION: usize = 120;

/// One run of an example at one τ.
#[derive(Debug, Clone, Serialize)]
pub struct Kp2004Row {
    /// Which example (1 or 2).
    pub example: usize,
    /// τ.
    pub tau: f64,
    /// Order of the system (1323 in the paper).
    pub system_dimension: usize,
    /// Π(s, s)/|B|.
    pub pi_per_point: f64,
    /// Σ‖s(a) − pₐ‖².
    pub data_misfit: f64,
}

fn x0_example1(u: f64, v: f64) -> [[f64; 3]; 3] {
    let q = u * u + v * v + 1.0;
    let (qu, qv) = (-2.0 * u / (q * q), -2.0 * v / (q * q)); // ∂(1/q)
    [
        [u + 1.0 / q, v + 1.0 / q, 2.0 * (u + v) / q],
        [1.0 + qu, qu, 2.0 / q + 2.0 * (u + v) * qu],
        [qv, 1.0 + qv, 2.0 / q + 2.0 * (u + v) * qv],
    ]
}

fn x0_example2(u: f64, v: f64) -> [[f64; 3]; 3] {
    let e = (-(u - 0.5).powi(2) - (v - 0.5).powi(2)).exp();
    [
        [u, v, e],
        [1.0, 0.0, -2.0 * (u - 0.5) * e],
        [0.0, 1.0, -2.0 * (v - 0.5) * e],
    ]
}

/// An example's problem: the space, the reference surface x₀ on [lo, hi]², the data A
/// with values pₐ, the points B with x₀'s unit normals N. Kept so the fitted spline can be
/// evaluated and sampled (figures) after [`Kp2004Problem::fit`].
pub struct Kp2004Problem {
    /// Which example (1 or 2).
    pub which: usize,
    /// BFS C² on 6 × 6 equal squares of [lo, hi]².
    pub space: TensorSpace<Hermite1d>,
    /// The parameter interval of both sides.
    pub range: [f64; 2],
    /// x₀ and its first derivatives.
    pub x0: SurfaceFn,
    /// A and pₐ.
    pub a_points: Vec<[f64; 2]>,
    pub values: Vec<[f64; 3]>,
    /// B and N(b).
    pub b_points: Vec<[f64; 2]>,
    pub normals: Vec<[f64; 3]>,
}

impl Kp2004Problem {
    /// Example 1 or 2 of §6.
    ///
    /// Errors: `InvalidInput` for an example other than 1 or 2, or where x₀ is not regular.
    pub fn new(which: usize) -> Result<Self> {
        let (lo, hi, x0): (f64, f64, SurfaceFn) = match which {
            1 => (-2.0, 2.0, x0_example1),
            2 => (0.0, 1.0, x0_example2),
            _ => {
                return Err(crate::Error::InvalidInput(format!(
                    "kp2004 has examples 1 and 2, not {which}"
                )))
            }
        };
        let part = Partition::uniform(lo, hi, 6)?;
        let space = TensorSpace::bfs_c2(part.clone(), part)?;
        let (a, values): (Vec<[f64; 2]>, Vec<[f64; 3]>) = if which == 1 {
            let pts: Vec<[f64; 2]> = (0..49)
                .map(|k| {
                    [
                        -2.0 + 2.0 * (k / 7) as f64 / 3.0,
                        -2.0 + 2.0 * (k % 7) as f64 / 3.0,
                    ]
                })
                .collect();
            let vals = pts
                .iter()
                .map(|p| {
                    let x = x0(p[0], p[1])[0];
                    let nrm = unit_normal(&x0, p[0], p[1])?;
                    let w = 4.0 * p[0] * (1.0 - p[0]) * p[1] * (1.0 - p[1]);
                    Ok([
                        x[0] + w * nrm[0],
                        x[1] + w * nrm[1],
                        x[2] + w * nrm[2] + 2.0,
                    ])
                })
                .collect::<Result<Vec<_>>>()?;
            (pts, vals)
        } else {
            let pts: Vec<[f64; 2]> = (0..9)
                .map(|k| [(k / 3) as f64 / 2.0, (k % 3) as f64 / 2.0])
                .collect();
            let vals = pts
                .iter()
                .map(|&[a1, a2]| {
                    [
                        -0.1 + 0.5 * a1,
                        -0.1 + 0.5 * a2,
                        0.9065
                            + 0.686 * (a1 - a1 * a1 + a2 - a2 * a2)
                            + 1.608 * (a1 * a2 - a1 * a1 * a2 - a1 * a2 * a2 + a1 * a1 * a2 * a2),
                    ]
                })
                .collect();
            (pts, vals)
        };
        let k = 50;
        let b: Vec<[f64; 2]> = (0..k * k)
            .map(|i| {
                let (s, t) = ((i / k) as f64 + 0.5, (i % k) as f64 + 0.5);
                [lo + (hi - lo) * s / k as f64, lo + (hi - lo) * t / k as f64]
            })
            .collect();
        let normals = b
            .iter()
            .map(|p| unit_normal(&x0, p[0], p[1]))
            .collect::<Result<Vec<_>>>()?;
        Ok(Kp2004Problem {
            which,
            space,
            range: [lo, hi],
            x0,
            a_points: a,
            values,
            b_points: b,
            normals,
        })
    }

    /// Solves (4.6) at τ.
    ///
    /// Errors: `InvalidInput` for a negative or non-finite τ; solver errors.
    pub fn fit(&self, tau: f64) -> Result<ParallelFit> {
        parallel_fit(
            &self.space,
            &self.a_points,
            &self.values,
            &self.b_points,
            &self.normals,
            &ParallelOptions {
                epsilon: EPSILON,
                tau,
                m: M,
            },
        )
    }

    /// The local parallelism defect of `s` at (u, v): (Σᵢ⟨Dᵢs, N⟩²)^½, the square root
    /// of Π's integrand (4.2) at one point.
    ///
    /// Errors: outside the rectangle, or where x₀ is not regular.
    pub fn defect(&self, s: &VectorSpline, u: f64, v: f64) -> Result<f64> {
        let n = unit_normal(&self.x0, u, v)?;
        let mut sq = 0.0;
        for (a, b) in [(1, 0), (0, 1)] {
            let d = s.eval(&self.space, u, v, a, b)?;
            sq += (0..3).map(|k| d[k] * n[k]).sum::<f64>().powi(2);
        }
        Ok(sq.sqrt())
    }

    /// The paper's figures: the reference surface x₀, the fit without parallelism (τ = 0)
    /// and with it (τ = `tau`), each a `res` × `res` sample of [lo, hi]²; the fits carry
    /// their local parallelism defect as quality (MeshLab colours it). Named
    /// `kp2004_example{1,2}_{reference,tau0,tau<τ>}`.
    ///
    /// Errors: `InvalidInput` for res = 0 or τ < 0; those of [`Self::fit`].
    pub fn figures(&self, tau: f64, res: usize) -> Result<Vec<(String, PolygonMesh)>> {
        let r = self.range;
        let x0 = self.x0;
        let mut out = vec![(
            format!("kp2004_example{}_reference", self.which),
            sample_mesh(r, r, res, &|u, v| Ok(x0(u, v)[0]), None)?,
        )];
        for (name, t) in [("tau0".to_string(), 0.0), (format!("tau{tau}"), tau)] {
            let f = self.fit(t)?;
            let mesh = sample_mesh(
                r,
                r,
                res,
                &|u, v| f.spline.eval(&self.space, u, v, 0, 0),
                Some(&|u, v| self.defect(&f.spline, u, v)),
            )?;
            out.push((format!("kp2004_example{}_{name}", self.which), mesh));
        }
        Ok(out)
    }
}

/// The fit of example 1 or 2 at a given τ.
///
/// Errors: `InvalidInput` for an example other than 1 or 2 or a negative τ; solver errors.
pub fn example(which: usize, tau: f64) -> Result<ParallelFit> {
    Kp2004Problem::new(which)?.fit(tau)
}

/// Both examples over a sweep of τ.
///
/// Errors: those of [`example`].
pub fn sweep(which: usize, taus: &[f64]) -> Result<Vec<Kp2004Row>> {
    let problem = Kp2004Problem::new(which)?;
    taus.iter()
        .map(|&tau| {
            let f = problem.fit(tau)?;
            Ok(Kp2004Row {
                example: which,
                tau,
                system_dimension: f.system_dimension,
                pi_per_point: f.pi_per_point,
                data_misfit: f.data_misfit,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn system_dimension_is_1323_and_pi_falls_as_tau_grows() {
        let taus = [0.0, 0.1, 1.0, TAU, 100.0];
        for which in [1, 2] {
            let rows = sweep(which, &taus).unwrap();
            for r in &rows {
                eprintln!(
                    "example {} τ = {:>5}: dim {} Π/|B| = {:.4e} misfit = {:.4e}",
                    r.example, r.tau, r.system_dimension, r.pi_per_point, r.data_misfit
                );
                assert_eq!(r.system_dimension, 1323);
            }
            for w in rows.windows(2) {
                assert!(
                    w[1].pi_per_point < w[0].pi_per_point,
                    "example {which}: τ {} → {}",
                    w[0].tau,
                    w[1].tau
                );
                // The price: the data are fitted less closely.
                assert!(w[1].data_misfit >= w[0].data_misfit, "example {which}");
            }
        }
    }

    #[test]
    fn unknown_example_is_an_error() {
        assert!(example(3, 1.0).is_err());
        assert!(example(1, -1.0).is_err());
    }
}
