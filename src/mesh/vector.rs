//! The few 3-vector operations every layer needs (dot, cross, norm, distance), in one place.

/// a · b
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// a × b
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// ‖a‖
pub fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// ‖a − b‖, finite whenever the distance is: for finite points near ±f64::MAX (where
/// a − b or its square overflows) or below 1e-145 (where the squares underflow) it falls
/// back to differences of halves scaled by their largest magnitude. Elsewhere it is the
/// plain √(Σ dᵢ²), bit for bit.
pub fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let squares = dot(d, d);
    if squares.is_nan() || squares.is_finite() && squares > 1e-290 {
        return squares.sqrt();
    }
    // Halves of finite numbers have a finite difference (exact unless subnormal).
    let halves = [
        0.5 * a[0] - 0.5 * b[0],
        0.5 * a[1] - 0.5 * b[1],
        0.5 * a[2] - 0.5 * b[2],
    ];
    let (d, factor) = if d.iter().all(|x| x.is_finite()) {
        (d, 1.0)
    } else {
        (halves, 2.0)
    };
    let largest = d.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if largest == 0.0 || !largest.is_finite() {
        return largest * factor;
    }
    // Past f64::MAX the product is +∞, as the distance is.
    factor * largest * norm(d.map(|x| x / largest))
}

/// The mean of `points`, per coordinate, finite for finite points: the plain sum over the
/// count where the sum is finite (bit for bit what summing gives), else the sum of each
/// point over the count, which cannot overflow.
pub fn mean(points: impl Iterator<Item = [f64; 3]> + Clone) -> [f64; 3] {
    let (mut sum, mut n) = ([0.0; 3], 0usize);
    for p in points.clone() {
        for k in 0..3 {
            sum[k] += p[k];
        }
        n += 1;
    }
    if n == 0 {
        return sum;
    }
    let count = n as f64;
    for k in 0..3 {
        if sum[k].is_infinite() {
            sum[k] = points.clone().map(|p| p[k] / count).sum();
        } else {
            sum[k] /= count;
        }
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn right_handed_unit_vectors() {
        assert_eq!(cross([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]), [0.0, 0.0, 1.0]);
        assert_eq!(dot([1.0, 2.0, 3.0], [4.0, 5.0, 6.0]), 32.0);
        assert_eq!(distance([1.0, 1.0, 1.0], [4.0, 5.0, 1.0]), 5.0);
    }

    #[test]
    fn distance_neither_overflows_nor_underflows() {
        let big = 1e308;
        // a − b overflows, the distance does not.
        assert_eq!(distance([big, 0.0, 0.0], [-0.5e308, 0.0, 0.0]), 1.5e308);
        // The squares overflow, the distance does not.
        let d = distance([3e200, 4e200, 0.0], [0.0; 3]);
        assert!((d / 5e200 - 1.0).abs() < 1e-15, "{d}");
        // Beyond f64::MAX the distance is infinite, not NaN.
        assert_eq!(distance([big, big, 0.0], [-big, 0.0, 0.0]), f64::INFINITY);
        // The squares underflow, the distance does not.
        let d = distance([3e-200, 4e-200, 0.0], [0.0; 3]);
        assert!((d / 5e-200 - 1.0).abs() < 1e-15, "{d}");
        assert_eq!(distance([1e-300; 3], [1e-300; 3]), 0.0);
        assert!(distance([0.0; 3], [f64::NAN, 0.0, 0.0]).is_nan());
    }

    #[test]
    fn mean_of_huge_points_is_finite() {
        let points = [[1e308, 1e308, 1e308], [-1e308, 0.0, 0.0], [0.0, 1e308, 0.0]];
        let m = mean(points.iter().copied());
        assert_eq!(m[0], 0.0);
        assert!((m[1] / (1e308 / 3.0 * 2.0) - 1.0).abs() < 1e-15, "{m:?}");
        assert!((m[2] / (1e308 / 3.0) - 1.0).abs() < 1e-15, "{m:?}");
        assert_eq!(
            mean([[1.0, 2.0, 3.0], [3.0, 4.0, 5.0]].into_iter()),
            [2.0, 3.0, 4.0]
        );
        assert_eq!(mean(std::iter::empty()), [0.0; 3]);
    }
}
