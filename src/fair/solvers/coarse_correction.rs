//! The coarse-subspace correction of a Levenberg–Marquardt step (beyond the paper): after
//! the damped step of the fine matrix, a step of the same matrix restricted to the first
//! coarse level's subspace, x + t P δ_c with Pᵀ(H + ν′I)P δ_c = −Pᵀ g at the damped
//! step's point, the best of t = 1, ½, ¼ if it lowers F.
//!
//! Why: on the 223 487-vertex Catmull–Clark junction the damped phase is slow (18 steps
//! where the 14 399-vertex one takes 8) and its motion smooth and global; the coarse
//! level's subspace step from a damped step's start lowered F by 0.8 to 4.8 times as much
//! as the fine damped step itself (2026-12-07, docs/fairing-at-scale-log.md). Taken after
//! each damped step with that step's matrix, the run took 15 damped steps instead of 18
//! and 515.3 s instead of 582.0 s, to the same minimum, and the 94 077-vertex five-tube
//! junction 19 instead of 25 and 312.0 s instead of 350.9 s; at 14k and 56k (three tubes),
//! 9 and 11 damped steps instead of 8 and 11 and 1.29 and 1.20 times as long (back to
//! back). Hence on by default from [`COARSE_CORRECTION_FREE_VERTICES`] only.

use crate::fair::SurfaceKind;

/// Whether Levenberg–Marquardt steps get the coarse-subspace correction (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum CoarseCorrection {
    /// From [`COARSE_CORRECTION_FREE_VERTICES`] free vertices.
    #[default]
    Auto,
    Always,
    Never,
}

/// The free vertices from which [`CoarseCorrection::Auto`] corrects: between the sizes
/// where it was slower (54 143 free vertices, 1.20 times) and faster (72 190, 90 237 and
/// 218 879, 1.12 to 1.13 times), single runs of 2026-12-07.
pub const COARSE_CORRECTION_FREE_VERTICES: usize = 70_000;

/// The shift ν′ of the correction's solve as a fraction of the damped step's ν: nearly
/// the coarse Newton step (the coarse Gauss–Newton matrix is positive definite), the line
/// search doing the damping (in the runs measured the best t was ½ or ¼ in most steps).
pub const COARSE_SHIFT_FRACTION: f64 = 1.0 / 4096.0;

/// The relative residual of the correction's coarse solve.
pub const COARSE_FORCING: f64 = 0.05;

/// The step lengths the correction tries, the best of them taken.
pub const COARSE_STEP_LENGTHS: [f64; 3] = [1.0, 0.5, 0.25];

impl CoarseCorrection {
    /// The setting for `surface`: [`CoarseCorrection::Auto`] stays automatic on the
    /// Catmull–Clark surface, where its threshold was measured, and is off on the G² one,
    /// where it made the 223k junction slower (476.3 s against 448.2 s, README); an explicit
    /// setting stays.
    pub fn for_surface(self, surface: SurfaceKind) -> Self {
        match (self, surface) {
            (CoarseCorrection::Auto, SurfaceKind::G2) => CoarseCorrection::Never,
            (setting, _) => setting,
        }
    }

    /// Whether a problem of `free` free vertices is corrected.
    pub fn applies(self, free: usize) -> bool {
        match self {
            CoarseCorrection::Auto => free >= COARSE_CORRECTION_FREE_VERTICES,
            CoarseCorrection::Always => true,
            CoarseCorrection::Never => false,
        }
    }
}

/// The index of the lowest finite value of `values` below `f`, if any.
pub fn lowest_below(values: &[f64], f: f64) -> Option<usize> {
    values
        .iter()
        .enumerate()
        .filter(|(_, v)| v.is_finite() && **v < f)
        .min_by(|a, b| a.1.total_cmp(b.1))
        .map(|(i, _)| i)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_corrects_from_the_threshold() {
        let n = COARSE_CORRECTION_FREE_VERTICES;
        assert!(!CoarseCorrection::Auto.applies(n - 1));
        assert!(CoarseCorrection::Auto.applies(n));
        assert!(CoarseCorrection::Always.applies(1));
        assert!(!CoarseCorrection::Never.applies(10 * n));
    }

    #[test]
    fn auto_is_off_on_the_g2_surface_and_explicit_settings_stay() {
        use CoarseCorrection::*;
        assert_eq!(Auto.for_surface(SurfaceKind::CatmullClark), Auto);
        assert_eq!(Auto.for_surface(SurfaceKind::G2), Never);
        assert_eq!(Always.for_surface(SurfaceKind::G2), Always);
        assert_eq!(Never.for_surface(SurfaceKind::CatmullClark), Never);
    }

    #[test]
    fn lowest_below_skips_rises_and_nan() {
        assert_eq!(lowest_below(&[3.0, f64::NAN, 1.5, 2.0], 2.5), Some(2));
        assert_eq!(lowest_below(&[3.0, f64::NAN], 2.5), None);
        assert_eq!(lowest_below(&[], 2.5), None);
    }
}
