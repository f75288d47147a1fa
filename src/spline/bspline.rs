//! Univariate B-splines of any degree p on a partition with simple interior knots
//! (maximal smoothness C^{p−1}) and (p+1)-fold end knots: dim = n + p for n intervals.
//! Degree 2 gives the space S₂(Tₙ) of the 2022 paper (dim n + 2).

use super::basis1d::Basis1d;
use super::grid::Partition;
use crate::error::{Error, Result};

/// Clamped B-spline basis of degree p on a partition.
#[derive(Debug, Clone)]
pub struct BSpline1d {
    partition: Partition,
    degree: usize,
    knots: Vec<f64>,
}

impl BSpline1d {
    /// The clamped basis of degree `degree` ≥ 1 on `partition`.
    ///
    /// Errors: `InvalidInput` if `degree == 0` (a discontinuous space has no use here).
    pub fn new(partition: Partition, degree: usize) -> Result<Self> {
        if degree == 0 {
            return Err(Error::InvalidInput(
                "B-spline degree must be at least 1".into(),
            ));
        }
        let b = partition.breaks();
        let mut knots = vec![b[0]; degree];
        knots.extend_from_slice(b);
        knots.extend(std::iter::repeat_n(b[b.len() - 1], degree));
        Ok(Self {
            partition,
            degree,
            knots,
        })
    }
}

impl Basis1d for BSpline1d {
    fn partition(&self) -> &Partition {
        &self.partition
    }
    fn dim(&self) -> usize {
        self.partition.intervals() + self.degree
    }
    fn degree(&self) -> usize {
        self.degree
    }
    fn smoothness(&self) -> usize {
        self.degree - 1
    }
    fn local_count(&self) -> usize {
        self.degree + 1
    }
    fn first_on(&self, interval: usize) -> usize {
        interval
    }
    fn support(&self, k: usize) -> (usize, usize) {
        let last = self.partition.intervals() - 1;
        (k.saturating_sub(self.degree), k.min(last))
    }

    /// Cox–de Boor values and derivatives (Piegl & Tiller, The NURBS Book, A2.3).
    fn eval(&self, interval: usize, x: f64, order: usize, out: &mut [f64]) {
        let p = self.degree;
        let span = interval + p;
        let u = &self.knots;
        // ndu: triangular table of basis values (upper) and knot differences (lower).
        let mut ndu = vec![vec![0.0; p + 1]; p + 1];
        let mut left = vec![0.0; p + 1];
        let mut right = vec![0.0; p + 1];
        ndu[0][0] = 1.0;
        for j in 1..=p {
            left[j] = x - u[span + 1 - j];
            right[j] = u[span + j] - x;
            let mut saved = 0.0;
            for r in 0..j {
                ndu[j][r] = right[r + 1] + left[j - r];
                let temp = ndu[r][j - 1] / ndu[j][r];
                ndu[r][j] = saved + right[r + 1] * temp;
                saved = left[j - r] * temp;
            }
            ndu[j][j] = saved;
        }
        let n = order + 1;
        for v in out.iter_mut().take((p + 1) * n) {
            *v = 0.0;
        }
        for j in 0..=p {
            out[j * n] = ndu[j][p];
        }
        let mut a = vec![vec![0.0; p + 1]; 2];
        for r in 0..=p {
            let (mut s1, mut s2) = (0usize, 1usize);
            a[0][0] = 1.0;
            for k in 1..=order.min(p) {
                let mut d = 0.0;
                let rk = r as isize - k as isize;
                let pk = p - k;
                if r >= k {
                    a[s2][0] = a[s1][0] / ndu[pk + 1][rk as usize];
                    d = a[s2][0] * ndu[rk as usize][pk];
                }
                let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
                let j2 = if r as isize - 1 <= pk as isize {
                    k - 1
                } else {
                    p - r
                };
                for j in j1..=j2 {
                    let idx = (rk + j as isize) as usize;
                    a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][idx];
                    d += a[s2][j] * ndu[idx][pk];
                }
                if r <= pk {
                    a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
                    d += a[s2][k] * ndu[r][pk];
                }
                out[r * n + k] = d;
                std::mem::swap(&mut s1, &mut s2);
            }
        }
        let mut factor = p as f64;
        for k in 1..=order.min(p) {
            for j in 0..=p {
                out[j * n + k] *= factor;
            }
            factor *= (p - k) as f64;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::tolerance::{FINITE_DIFFERENCE, ROUND_OFF};

    fn basis(p: usize) -> BSpline1d {
        BSpline1d::new(Partition::new(vec![0.0, 0.3, 0.45, 1.0, 1.2]).unwrap(), p).unwrap()
    }

    #[test]
    fn partition_of_unity_on_non_uniform_knots() {
        for p in 1..=4 {
            let b = basis(p);
            let mut out = vec![0.0; (p + 1) * 2];
            for &x in &[0.0, 0.1, 0.3, 0.44, 0.7, 1.1, 1.2] {
                let i = b.partition().locate(x).unwrap();
                b.eval(i, x, 1, &mut out);
                let s: f64 = (0..=p).map(|l| out[l * 2]).sum();
                let ds: f64 = (0..=p).map(|l| out[l * 2 + 1]).sum();
                assert_near!(s, 1.0, ROUND_OFF);
                assert_near!(ds, 0.0, ROUND_OFF);
            }
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let h = 1e-5;
        for p in 2..=4 {
            let b = basis(p);
            let n = p + 1;
            let (mut o, mut op, mut om) = (vec![0.0; n * n], vec![0.0; n * n], vec![0.0; n * n]);
            for &x in &[0.12, 0.37, 0.8] {
                let i = b.partition().locate(x).unwrap();
                b.eval(i, x, p, &mut o);
                b.eval(i, x + h, p, &mut op);
                b.eval(i, x - h, p, &mut om);
                for l in 0..n {
                    for d in 1..=p {
                        let fd = (op[l * n + d - 1] - om[l * n + d - 1]) / (2.0 * h);
                        assert_near!(o[l * n + d], fd, FINITE_DIFFERENCE, "p {p} l {l} d {d}");
                    }
                }
            }
        }
    }

    #[test]
    fn dimension_is_intervals_plus_degree() {
        assert_eq!(basis(2).dim(), 6);
        assert_eq!(basis(2).support(0), (0, 0));
        assert_eq!(basis(2).support(3), (1, 3));
        assert_eq!(basis(2).support(5), (3, 3));
    }
}
