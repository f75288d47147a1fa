//! The auxiliary patches along the division curves. Each curve carries one, shared by the
//! two sectors it separates: r(t, σ) given by its curve r(t, 0) (degree 7), its first
//! cross derivative r_σ(t, 0) (degree 6) and its second r_σσ(t, 0) (degree 5), each fixed
//! by Hermite data at the centre (t = 0) and at the ring (t = 1).
//!
//! For the domain (Kiciak's default, `../shared/notes/kiciak-g2-construction.md`): the
//! curve is the [`division_curve`]; at the ring, r_σ and r_σσ with their first and second
//! t-derivatives are the domain ring's ∂_b, ∂_b² (b = the lattice coordinate across the
//! spoke, towards the next spoke) and their a-derivatives at the spoke's lattice point
//! (1, 0); at the centre r_σ is the same vector as at the ring with derivatives 1–3 zero,
//! and r_σσ and its first two derivatives are zero.

use super::division_curve::division_curve;
use super::domain_net::DomainNet;
use super::polynomial::{basis, hermite};
use super::sides::{AuxiliaryJet, Side};

/// Bernstein coefficients of the curve (degree 7), first (6) and second (5) cross
/// derivative, summed: the unknowns of one auxiliary patch per scalar function.
pub const AUXILIARY_UNKNOWNS: usize = 8 + 7 + 6;

/// One scalar auxiliary patch: Bernstein coefficients of r, r_σ, r_σσ.
#[derive(Debug, Clone, PartialEq)]
pub struct Auxiliary {
    pub curve: Vec<f64>,
    pub first: Vec<f64>,
    pub second: Vec<f64>,
}

impl Auxiliary {
    /// The jet (r, r_t, r_tt, r_σ, r_tσ, r_σσ) at t.
    pub fn jet(&self, t: f64) -> AuxiliaryJet {
        let dot = |c: &[f64], r: usize| -> f64 {
            let b = basis(c.len() - 1, t, r);
            b[r].iter().zip(c).map(|(w, x)| w * x).sum()
        };
        [
            dot(&self.curve, 0),
            dot(&self.curve, 1),
            dot(&self.curve, 2),
            dot(&self.first, 0),
            dot(&self.first, 1),
            dot(&self.second, 0),
        ]
    }

    /// The weights of the unknowns (curve, first, second coefficients, concatenated) in
    /// each entry of the jet at t.
    pub fn jet_rows(t: f64) -> [[f64; AUXILIARY_UNKNOWNS]; 6] {
        let mut rows = [[0.0; AUXILIARY_UNKNOWNS]; 6];
        let (b7, b6, b5) = (basis(7, t, 2), basis(6, t, 1), basis(5, t, 0));
        for i in 0..8 {
            rows[0][i] = b7[0][i];
            rows[1][i] = b7[1][i];
            rows[2][i] = b7[2][i];
        }
        for i in 0..7 {
            rows[3][8 + i] = b6[0][i];
            rows[4][8 + i] = b6[1][i];
        }
        for i in 0..6 {
            rows[5][15 + i] = b5[0][i];
        }
        rows
    }
}

/// The domain ring's derivative ∂_a^`a` ∂_b^`b` at spoke `spoke`'s lattice point (1, 0),
/// coordinate `coordinate` (the ring face [1, 2] × [0, 1] at its corner).
fn ring_jet(net: &DomainNet, spoke: usize, a: usize, b: usize, coordinate: usize) -> f64 {
    Side::RingStart
        .ring_weights(net.valence, spoke, b, a, 0.0)
        .iter()
        .map(|&(v, w)| w * net.points[v][coordinate])
        .sum()
}

/// The domain's auxiliary patch along spoke `spoke`'s division curve, per coordinate.
pub fn domain_auxiliary(net: &DomainNet, spoke: usize) -> [Auxiliary; 2] {
    let curve = division_curve(net, spoke);
    [0, 1].map(|c| {
        let jet = |a: usize, b: usize| ring_jet(net, spoke, a, b, c);
        let first_at_ring = [jet(0, 1), jet(1, 1), jet(2, 1)];
        let second_at_ring = [jet(0, 2), jet(1, 2), jet(2, 2)];
        Auxiliary {
            curve: curve.iter().map(|p| p[c]).collect(),
            first: hermite(6, &[first_at_ring[0], 0.0, 0.0, 0.0], &first_at_ring),
            second: hermite(5, &[0.0; 3], &second_at_ring),
        }
    })
}
