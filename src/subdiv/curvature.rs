//! Normals and curvatures of a parametric surface from its first and second derivatives
//! (the first and second fundamental forms).

use crate::error::{Error, Result};
use crate::mesh::vector::{cross, dot};
use crate::subdiv::Derivatives;
use crate::tolerance::ROUND_OFF;

/// Unit normal, mean, Gaussian and principal curvatures at a surface point.
///
/// Signs follow the normal `n = S_u × S_v / |S_u × S_v|` (outward for a counter-clockwise
/// control mesh): curvature is positive where the surface bends towards `n`, so a sphere
/// with outward normals has `H = −1/r`. `k1 ≥ k2`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Curvature {
    pub normal: [f64; 3],
    pub mean: f64,
    pub gaussian: f64,
    pub k1: f64,
    pub k2: f64,
}

/// The unit normal `S_u × S_v / |S_u × S_v|`.
///
/// A point is degenerate when the tangents are parallel or vanish relative to the
/// surface's bending: `EG − F² ≤ ROUND_OFF · (|S_uu|² + 2 |S_uv|² + |S_vv|²)²` (both sides
/// scale as length⁴ under any reparametrisation u → c u). This catches the limit points
/// of valence-2 vertices, where both tangents vanish.
///
/// # Errors
/// [`Error::Topology`] at a degenerate point, since no normal exists there.
pub fn normal(d: &Derivatives) -> Result<[f64; 3]> {
    let n = cross(d.du, d.dv);
    let det = dot(n, n);
    let bend = dot(d.duu, d.duu) + 2.0 * dot(d.duv, d.duv) + dot(d.dvv, d.dvv);
    if !det.is_finite() || det <= ROUND_OFF * bend * bend || det == 0.0 {
        return Err(Error::Topology(
            "the limit surface is degenerate here (parallel or vanishing tangents): no normal"
                .into(),
        ));
    }
    let len = det.sqrt();
    Ok(n.map(|c| c / len))
}

/// Curvatures from the fundamental forms: `H = (E N − 2 F M + G L) / (2 (E G − F²))`,
/// `K = (L N − M²) / (E G − F²)`, `k = H ± √(H² − K)` (the radicand clamped at 0 against
/// round-off at umbilics).
///
/// # Errors
/// Those of [`normal`].
pub fn curvature(d: &Derivatives) -> Result<Curvature> {
    let n = normal(d)?;
    let (e, f, g) = (dot(d.du, d.du), dot(d.du, d.dv), dot(d.dv, d.dv));
    let (l, m, nn) = (dot(d.duu, n), dot(d.duv, n), dot(d.dvv, n));
    let det = e * g - f * f;
    let mean = (e * nn - 2.0 * f * m + g * l) / (2.0 * det);
    let gaussian = (l * nn - m * m) / det;
    let root = (mean * mean - gaussian).max(0.0).sqrt();
    Ok(Curvature {
        normal: n,
        mean,
        gaussian,
        k1: mean + root,
        k2: mean - root,
    })
}
