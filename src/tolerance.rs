//! The one tolerance policy: named tolerances for comparisons in code and tests, and
//! `assert_near!`. A tolerance is chosen by what is compared, never loosened to get green.

/// Values that must agree to the last few bits (round trips, exact arithmetic in f64).
pub const BIT_EXACT: f64 = 0.0;
/// Results of a well-conditioned direct computation compared with a closed form.
pub const ROUND_OFF: f64 = 1e-12;
/// Results of a linear solve compared with the exact solution (condition-number bounded).
pub const SOLVE: f64 = 1e-9;
/// Central finite differences with step h ~ 1e-5 against analytic derivatives.
pub const FINITE_DIFFERENCE: f64 = 1e-6;

/// `|a - b| <= tol * max(1, |a|, |b|)`: absolute near zero, relative elsewhere.
pub fn near(a: f64, b: f64, tol: f64) -> bool {
    let scale = 1f64.max(a.abs()).max(b.abs());
    (a - b).abs() <= tol * scale
}

/// Asserts `near(a, b, tol)` with a message showing both values and the gap.
#[macro_export]
macro_rules! assert_near {
    ($a:expr, $b:expr, $tol:expr $(,)?) => {{
        let (a, b, tol): (f64, f64, f64) = ($a, $b, $tol);
        assert!(
            $crate::tolerance::near(a, b, tol),
            "assert_near!({}, {}): {a} vs {b}, difference {:e} exceeds tolerance {tol:e}",
            stringify!($a),
            stringify!($b),
            (a - b).abs()
        );
    }};
    ($a:expr, $b:expr, $tol:expr, $($msg:tt)+) => {{
        let (a, b, tol): (f64, f64, f64) = ($a, $b, $tol);
        assert!(
            $crate::tolerance::near(a, b, tol),
            "{}: {a} vs {b}, difference {:e} exceeds tolerance {tol:e}",
            format!($($msg)+),
            (a - b).abs()
        );
    }};
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_and_absolute() {
        assert!(near(1e6, 1e6 + 1e-7, ROUND_OFF));
        assert!(!near(1.0, 1.0 + 1e-9, ROUND_OFF));
        assert!(near(0.0, 1e-13, ROUND_OFF));
        assert_near!(2.0, 2.0, BIT_EXACT);
    }
}
