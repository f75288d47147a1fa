//! The four sides of a special patch and what each is joined to. Sector s's patch p(u, v)
//! (u along spoke s, v towards spoke s+1; (0, 0) at the centre) has
//!
//! - side v = 0 on the division curve of spoke s, side u = 0 on that of spoke s+1: there
//!   the patch is joined to the curve's **auxiliary patch** r(t, σ) (t along the curve
//!   from the centre, σ across it towards the sector on its left), shared with the
//!   neighbouring sector;
//! - side u = 1 on the ring's face [1, 2] × [0, 1] of the sector's lattice and side v = 1
//!   on its face [0, 1] × [1, 2]: there the auxiliary patch is the bicubic ring patch
//!   itself (t along the side, σ = outward lattice coordinate − 1).
//!
//! Along every side, with the side's **junction functions** B₁, C₁, B₂, C₂ (polynomials in
//! t), the patch's cross derivatives (∂ᵤ on u-sides, ∂ᵥ on v-sides) are
//!
//!   p = r,  p′ = B₁ r_t + C₁ r_σ,  p″ = B₂ r_t + C₂ r_σ + B₁² r_tt + 2B₁C₁ r_tσ + C₁² r_σσ,
//!
//! which is what f ∘ δ must satisfy when f is C² across the side (Kiciak's construction,
//! `../shared/notes/kiciak-g2-construction.md`; the chain rule with r = f ∘ ρ).

use super::bernstein::{bernstein_derivatives, COEFFICIENTS, ORDER};
use super::domain_net::index;

/// A side of a sector's patch.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// v = 0: spoke s's division curve, t = u.
    CurveStart,
    /// u = 0: spoke s+1's division curve, t = v.
    CurveEnd,
    /// v = 1: the ring face [0, 1] × [1, 2], t = u.
    RingEnd,
    /// u = 1: the ring face [1, 2] × [0, 1], t = v.
    RingStart,
}

impl Side {
    pub const ALL: [Side; 4] = [
        Side::CurveStart,
        Side::CurveEnd,
        Side::RingEnd,
        Side::RingStart,
    ];

    /// Whether the side lies on a division curve (else on the ring).
    pub fn on_curve(self) -> bool {
        matches!(self, Side::CurveStart | Side::CurveEnd)
    }

    /// Degrees of the junction functions (B₁, C₁, B₂, C₂): curve sides (2, 1, 3, 2), ring
    /// sides (4, 3, 5, 4) — the lowest for which every term of p′ and p″ has degree ≤ 9
    /// and the corner compatibility equations can be met.
    pub fn junction_degrees(self) -> [usize; 4] {
        if self.on_curve() {
            [2, 1, 3, 2]
        } else {
            [4, 3, 5, 4]
        }
    }

    /// The weights of the patch's Bézier coefficients in its `cross`-th cross derivative
    /// and `along`-th derivative along the side at parameter t.
    pub fn patch_row(self, cross: usize, along: usize, t: f64) -> [f64; COEFFICIENTS] {
        let bt = bernstein_derivatives(t);
        let (fixed, across_u) = match self {
            Side::CurveStart => (0.0, false),
            Side::CurveEnd => (0.0, true),
            Side::RingEnd => (1.0, false),
            Side::RingStart => (1.0, true),
        };
        let bs = bernstein_derivatives(fixed);
        let mut row = [0.0; COEFFICIENTS];
        for a in 0..ORDER {
            for b in 0..ORDER {
                row[ORDER * a + b] = if across_u {
                    bs[cross][a] * bt[along][b]
                } else {
                    bt[along][a] * bs[cross][b]
                };
            }
        }
        row
    }

    /// For a ring side of sector `sector`: the net vertices and weights of the ring patch's
    /// derivative of order `along` along the side and `cross` across it at (t, σ = 0).
    pub fn ring_weights(
        self,
        k: usize,
        sector: usize,
        along: usize,
        cross: usize,
        t: f64,
    ) -> Vec<(usize, f64)> {
        let (nt, n0) = (
            crate::subdiv::cubic_basis(t),
            crate::subdiv::cubic_basis(0.0),
        );
        let mut out = Vec::with_capacity(16);
        for i in 0..4 {
            for l in 0..4 {
                let (w, a, b) = match self {
                    // face [1, 2] × [0, 1]: σ = a − 1 over lattice a = 0..3, t = b over −1..2
                    Side::RingStart => (n0[cross][i] * nt[along][l], i as i32, l as i32 - 1),
                    // face [0, 1] × [1, 2]: t = a over −1..2, σ = b − 1 over 0..3
                    Side::RingEnd => (nt[along][i] * n0[cross][l], i as i32 - 1, l as i32),
                    _ => unreachable!("ring weights of a curve side"),
                };
                if w != 0.0 {
                    out.push((index(k, sector, a, b), w));
                }
            }
        }
        out
    }
}

/// The auxiliary patch's data along a side at one t: r, r_t, r_tt, r_σ, r_tσ, r_σσ.
pub type AuxiliaryJet = [f64; 6];

/// p′ and p″ from the auxiliary jet and the junction functions' values (B₁, C₁, B₂, C₂).
pub fn cross_derivatives(r: &AuxiliaryJet, j: [f64; 4]) -> [f64; 2] {
    let [b1, c1, b2, c2] = j;
    let [_, rt, rtt, rs, rts, rss] = *r;
    [
        b1 * rt + c1 * rs,
        b2 * rt + c2 * rs + b1 * b1 * rtt + 2.0 * b1 * c1 * rts + c1 * c1 * rss,
    ]
}
