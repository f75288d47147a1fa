//! The smallest ‖∇F‖ that control points stored as `f64` can be expected to reach when
//! rounded to nearest.
//!
//! The minimum x* is not a point of the `f64` lattice: a Newton step returns x* rounded,
//! where ∇F = H (x − x*) with x − x* the rounding, about uniform in ±½ ulp per
//! coordinate. With c ≈ 10⁸ (the 223 487-vertex three-tube junction) that product is
//! ~10⁻⁸ of the raw mesh's gradient: there the gradient tolerance asks for more digits
//! than rounding to nearest keeps, and Newton steps, themselves rounded so, cannot go
//! below it. The estimate tells the optimizer where to choose the rounding instead
//! ([`super::lattice_rounding`], which goes below it) and where to stop after that,
//! instead of spending Hessians to find it.

use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

use crate::fair::functional::evaluation::BlockHessian;
use crate::fair::solvers::pcg::multiply;
use crate::linalg::norm;

/// The gap from |x| to the next larger `f64` (x finite).
pub fn ulp(x: f64) -> f64 {
    let a = x.abs();
    f64::from_bits(a.to_bits() + 1) - a
}

/// ‖H u‖, u the free coordinates' rounding: ulp/√12 (the root mean square of a rounding
/// to nearest) with a random sign per coordinate, from a fixed seed so that runs agree.
/// `free` gives each vertex's free index (`u32::MAX`: fixed), `h` is over the free ones.
pub fn coordinate_floor(h: &BlockHessian, positions: &[[f64; 3]], free: &[u32]) -> f64 {
    let count = free.iter().filter(|&&i| i != u32::MAX).count();
    let mut rounding = vec![0.0; 3 * count];
    let mut signs = SmallRng::seed_from_u64(0x5eed);
    for (p, &i) in positions.iter().zip(free) {
        if i != u32::MAX {
            for (a, &x) in p.iter().enumerate() {
                let sign = if signs.random::<bool>() { 1.0 } else { -1.0 };
                rounding[3 * i as usize + a] = sign * ulp(x) / 12f64.sqrt();
            }
        }
    }
    norm(&multiply(h, &rounding))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ulp_is_the_spacing_of_doubles() {
        assert_eq!(ulp(1.0), f64::EPSILON);
        assert_eq!(ulp(-1.5), f64::EPSILON);
        assert_eq!(ulp(1e8), 2f64.powi(26 - 52));
        assert_eq!(ulp(0.0), f64::from_bits(1));
    }
}
