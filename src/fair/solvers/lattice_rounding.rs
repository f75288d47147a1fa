//! Choosing the rounding of the control points: the `f64` mesh nearest the stationary
//! condition, below the floor of rounding to nearest.
//!
//! Near the minimum ∇F(x + Δ) = g + H Δ to round-off, and a Newton step x + δ stored as
//! `f64` leaves ∇F = H u for its rounding u ([`super::coordinate_floor`]): white noise of
//! half an ulp, which H, a fourth-order operator, amplifies most along the mesh's
//! oscillating modes. Which way each coordinate is rounded is free, and H's columns are
//! local, so coordinate descent on ‖g + H Δ‖² over whole ulps (Gauss–Seidel on the normal
//! equations, each move to the `f64` nearest its coordinate's exact minimizer) takes that
//! noise out, leaving the smooth part a Newton step had left. Traced on the 14 399-vertex
//! three-tube junction (Catmull–Clark, plain method, 2026-11-30): ‖g‖ 1.40·10⁻⁶ where the
//! run had stalled (its floor estimate 8.2·10⁻⁷), 5.3·10⁻⁷ after 300 sweeps from there, and
//! 9.5·10⁻⁸ after a fresh Newton step and 40 sweeps — the gradient evaluated, not predicted.

use crate::fair::functional::evaluation::BlockHessian;
use crate::fair::solvers::multilevel::block_csr::{Block, UpperLayout};
use crate::linalg::norm;

/// Sweeps at most: on the 14k junction, after a Newton step, ‖g + H Δ‖ fell from 8.2·10⁻⁷
/// to 2.1·10⁻⁷ in the first sweep, 1.0·10⁻⁷ in ten and 9.1·10⁻⁸ in forty.
pub const MAX_SWEEPS: usize = 40;

/// A sweep that lowers ‖g + H Δ‖² by less than this fraction ends the descent.
const LEAST_SWEEP_GAIN: f64 = 1e-3;

/// The outcome of [`lattice_rounding`].
pub struct Rounded {
    /// All vertices' positions, the free ones moved by whole ulps.
    pub positions: Vec<[f64; 3]>,
    /// ‖g + H Δ‖: the gradient the linear model predicts there.
    pub predicted: f64,
    /// The sweeps made.
    pub sweeps: usize,
}

/// Coordinate descent on ‖g + H Δ‖² over `f64` moves of the free coordinates of
/// `positions` (see the module documentation); `g` is ∇F at `positions` over the free
/// vertices (`free`: each vertex's free index, `u32::MAX` fixed), `h` the Hessian there or
/// near it (the moves are ulps: any nearby Hessian predicts them). The sweeps stop once
/// ‖g + H Δ‖ ≤ `target` (0: as far as they gain): most of the gain is the first sweep's
/// (on the 94 077-vertex five-tube junction, 2026-11-30: 2.0·10⁻² → 4.6·10⁻³ in the first,
/// 1.3·10⁻³ after forty, 0.22 s each), and a run needs only its tolerance.
pub fn lattice_rounding(
    h: &BlockHessian,
    g: &[f64],
    positions: &[[f64; 3]],
    free: &[u32],
    target: f64,
) -> Rounded {
    let count = g.len() / 3;
    // Block row i of the full symmetric matrix: H[3i + a, 3j + c] = block[a][c] for each
    // entry k of `layout.row(i)`, j its column (H[3j + c, 3i + a] the same by symmetry).
    let layout = UpperLayout::new(h, count);
    let mut x = vec![[0.0; 3]; count];
    for (p, &i) in positions.iter().zip(free) {
        if i != u32::MAX {
            x[i as usize] = *p;
        }
    }
    // Block row i's entries as (3j, block), built once per vertex and used by its three
    // coordinates (`UpperLayout::block` assembles a block from its stored triangle).
    let mut row = Vec::new();
    let row_of = |i: usize, row: &mut Vec<(usize, Block)>| {
        row.clear();
        row.extend(
            layout
                .row(i)
                .map(|k| (3 * layout.column(k) as usize, layout.block(h, k))),
        );
    };
    // ‖H e_k‖² of every coordinate k.
    let column_norms: Vec<[f64; 3]> = (0..count)
        .map(|i| {
            row_of(i, &mut row);
            let mut sums = [0.0; 3];
            for (_, block) in &row {
                for (sum, block_row) in sums.iter_mut().zip(block) {
                    *sum += block_row.iter().map(|v| v * v).sum::<f64>();
                }
            }
            sums
        })
        .collect();
    let mut r = g.to_vec();
    let mut squared = r.iter().map(|v| v * v).sum::<f64>();
    let mut sweeps = 0;
    while sweeps < MAX_SWEEPS && squared > target * target {
        sweeps += 1;
        let before = squared;
        for i in 0..count {
            row_of(i, &mut row);
            for a in 0..3 {
                let b = column_norms[i][a];
                if !(b > 0.0 && b.is_finite()) {
                    continue;
                }
                let dot: f64 = row
                    .iter()
                    .map(|(j, block)| (0..3).map(|c| block[a][c] * r[j + c]).sum::<f64>())
                    .sum();
                // The f64 nearest the coordinate's exact minimizer x − dot / b.
                let moved = x[i][a] - dot / b;
                let d = moved - x[i][a];
                let change = d * (2.0 * dot + d * b);
                // (Not `change >= 0`: a NaN change is no gain either.)
                if d == 0.0 || change.partial_cmp(&0.0) != Some(std::cmp::Ordering::Less) {
                    continue;
                }
                for (j, block) in &row {
                    for c in 0..3 {
                        r[j + c] += block[a][c] * d;
                    }
                }
                x[i][a] = moved;
                squared += change;
            }
        }
        if before - squared <= LEAST_SWEEP_GAIN * before {
            break;
        }
    }
    let mut out = positions.to_vec();
    for (p, &i) in out.iter_mut().zip(free) {
        if i != u32::MAX {
            *p = x[i as usize];
        }
    }
    Rounded {
        positions: out,
        predicted: norm(&r),
        sweeps,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::rngs::SmallRng;
    use rand::{Rng, SeedableRng};

    /// Units of 2⁻⁶⁰: coordinates in [1, 2) are multiples of 2⁸ of them (their ulp is 2⁻⁵²).
    const UNIT: f64 = 1.0 / (1u64 << 60) as f64;

    /// A chain of vertices, each coordinate on its own: the fourth-difference stencil
    /// (1, −4, ·, −4, 1) with 11 on the diagonal (diagonally dominant, so positive
    /// definite), all in integers, so that H (x − x*) is exact in i128.
    fn chain(count: usize) -> BlockHessian {
        let scaled =
            |s: f64| std::array::from_fn(|a| std::array::from_fn(|c| if a == c { s } else { 0.0 }));
        let mut h = BlockHessian {
            blocks: Vec::new(),
            values: Vec::new(),
        };
        for i in 0..count {
            for (k, s) in [(0, 6.0), (1, -4.0), (2, 1.0)] {
                if i + k < count {
                    h.blocks.push((i as u32, (i + k) as u32));
                    h.values.push(scaled(s));
                }
            }
        }
        h
    }

    /// H (X − X*) in units of 2⁻⁶⁰ for positions X and the exact minimum X*, both in those
    /// units, exactly.
    fn exact_residual(h: &BlockHessian, x: &[[i128; 3]], star: &[[i128; 3]]) -> Vec<i128> {
        let mut r = vec![0i128; 3 * x.len()];
        for (&(i, j), v) in h.blocks.iter().zip(&h.values) {
            let (i, j) = (i as usize, j as usize);
            for a in 0..3 {
                let w = v[a][a] as i128;
                r[3 * i + a] += w * (x[j][a] - star[j][a]);
                if i != j {
                    r[3 * j + a] += w * (x[i][a] - star[i][a]);
                }
            }
        }
        r
    }

    fn length(r: &[i128]) -> f64 {
        r.iter()
            .map(|&v| (v as f64 * UNIT).powi(2))
            .sum::<f64>()
            .sqrt()
    }

    /// The chain of `count` vertices at its positions rounded to nearest: x* = 1.5 + m 2⁻⁶⁰,
    /// m pseudo-random below 2¹⁶ (8 bits below the doubles' lattice), rounded to the
    /// multiple of 2⁸ units nearest it. Returns H, x*, that rounding (both in units), its
    /// doubles and its exact gradient H (X − X*) as doubles.
    #[allow(clippy::type_complexity)]
    fn rounded_to_nearest(
        count: usize,
        seed: u64,
    ) -> (
        BlockHessian,
        Vec<[i128; 3]>,
        Vec<[i128; 3]>,
        Vec<[f64; 3]>,
        Vec<f64>,
    ) {
        let h = chain(count);
        let mut offsets = SmallRng::seed_from_u64(seed);
        let star: Vec<[i128; 3]> = (0..count)
            .map(|_| std::array::from_fn(|_| (3i128 << 59) + offsets.random_range(0..1 << 16)))
            .collect();
        let nearest: Vec<[i128; 3]> = star
            .iter()
            .map(|p| std::array::from_fn(|a| ((p[a] + 128) >> 8) << 8))
            .collect();
        let positions: Vec<[f64; 3]> = nearest
            .iter()
            .map(|p| std::array::from_fn(|a| p[a] as f64 * UNIT))
            .collect();
        let g = exact_residual(&h, &nearest, &star)
            .iter()
            .map(|&v| v as f64 * UNIT)
            .collect();
        (h, star, nearest, positions, g)
    }

    #[test]
    fn the_chosen_rounding_lowers_the_exact_gradient_below_rounding_to_nearest() {
        let count = 500;
        let (h, star, nearest, positions, g) = rounded_to_nearest(count, 7);
        // Exactly representable: the doubles are the lattice points themselves.
        for (p, q) in positions.iter().zip(&nearest) {
            assert_eq!((p[0] / UNIT) as i128, q[0]);
        }
        let r0 = exact_residual(&h, &nearest, &star);
        let free: Vec<u32> = (0..count as u32).collect();
        let rounded = lattice_rounding(&h, &g, &positions, &free, 0.0);
        let chosen: Vec<[i128; 3]> = rounded
            .positions
            .iter()
            .map(|p| std::array::from_fn(|a| (p[a] / UNIT) as i128))
            .collect();
        let r = exact_residual(&h, &chosen, &star);
        let (before, after) = (length(&r0), length(&r));
        // The prediction is the exact gradient there.
        assert!(
            (rounded.predicted - after).abs() <= 1e-9 * after,
            "predicted {:e}, exact {after:e}",
            rounded.predicted
        );
        // 2.08·10⁻¹⁴ → 1.45·10⁻¹⁴ when this test was written: a chain's coordinates are
        // less coupled than a surface's (the 14k junction: 4 times lower after a Newton step).
        assert!(after < 0.8 * before, "‖g‖ {before:e} → {after:e}");
        // Every coordinate stays within a few ulps of x* (2⁸ units each).
        for (p, q) in chosen.iter().zip(&star) {
            for a in 0..3 {
                assert!((p[a] - q[a]).abs() <= 4 << 8, "{} from {}", p[a], q[a]);
            }
        }
    }

    #[test]
    fn the_descent_stops_once_its_model_meets_the_target() {
        // The same chain from rounding to nearest: with no target the descent runs until
        // it stops gaining; with a target between its start and its end it stops at the
        // first sweep that meets the target, earlier and higher.
        let count = 500;
        let (h, _, _, positions, g) = rounded_to_nearest(count, 11);
        let free: Vec<u32> = (0..count as u32).collect();
        let start = norm(&g);
        let full = lattice_rounding(&h, &g, &positions, &free, 0.0);
        assert!(full.sweeps > 2, "{} sweeps", full.sweeps);
        let target = full.predicted + 0.1 * (start - full.predicted);
        let stopped = lattice_rounding(&h, &g, &positions, &free, target);
        assert!(stopped.predicted <= target);
        assert!(stopped.predicted > full.predicted);
        assert!(stopped.sweeps < full.sweeps);
        // Already met: no sweep, no move.
        let none = lattice_rounding(&h, &g, &positions, &free, start);
        assert_eq!(none.sweeps, 0);
        assert_eq!(none.positions, positions);
    }
}
