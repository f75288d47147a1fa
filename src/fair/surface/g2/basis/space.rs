//! The space V of a special element as linear conditions: scalar functions on Ω_k given by
//! k degree-(9, 9) patches and k auxiliary patches (one per division curve), with every
//! patch side joined by its junction functions ([`super::sides`]) to the auxiliary patch
//! of its curve or to the bicubic ring. A function of V is C² on Ω_k (in Ω_k's coordinates,
//! through the domain patches δ_s) and joins the ring C²: the surface it makes is curvature
//! continuous. Its dimension with the ring data zero is Kiciak's extended space (the
//! biquintic Coons patches of the basic space plus the 16 bubbles per patch).
//!
//! Unknowns: patch s's Bézier coefficients at `100·s + 10a + b`, then curve i's auxiliary
//! patch (r, r_σ, r_σσ coefficients) at `100·k + 21·i`. Conditions `c·x = data·net` with
//! `net` one value per domain-net vertex (1 + 12k; the radius-3 ones get zero weight).

use faer::Mat;

use super::auxiliary::{Auxiliary, AUXILIARY_UNKNOWNS};
use super::bernstein::COEFFICIENTS;
use super::domain_net::PER_SECTOR;
use super::junction::{identity_nodes, SectorDomain};
use super::sides::Side;

/// A condition: its unknowns' weights and its data's (net vertex, weight).
type Row = (Vec<(usize, f64)>, Vec<(usize, f64)>);

/// The conditions of V for valence k.
pub struct Conditions {
    pub c: Mat<f64>,
    pub data: Mat<f64>,
}

/// Unknowns of the space for valence k.
pub fn unknowns(k: usize) -> usize {
    k * (COEFFICIENTS + AUXILIARY_UNKNOWNS)
}

/// Offset of curve i's auxiliary unknowns.
fn auxiliary_offset(k: usize, curve: usize) -> usize {
    k * COEFFICIENTS + (curve % k) * AUXILIARY_UNKNOWNS
}

/// The weights of p′ (order 1) or p″ (order 2) in the entries of the auxiliary jet
/// (r, r_t, r_tt, r_σ, r_tσ, r_σσ), from the junction values (B₁, C₁, B₂, C₂).
fn jet_weights(order: usize, j: [f64; 4]) -> [f64; 6] {
    let [b1, c1, b2, c2] = j;
    match order {
        0 => [1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        1 => [0.0, b1, 0.0, c1, 0.0, 0.0],
        _ => [0.0, b2, b1 * b1, c2, 2.0 * b1 * c1, c1 * c1],
    }
}

impl Conditions {
    /// The conditions for valence k with the sectors' junction functions `sectors`.
    pub fn new(k: usize, sectors: &[SectorDomain]) -> Conditions {
        let n = unknowns(k);
        let vertices = 1 + PER_SECTOR * k;
        let nodes = identity_nodes();
        let mut rows: Vec<Row> = Vec::new();
        for (s, domain) in sectors.iter().enumerate() {
            for (side_index, side) in Side::ALL.iter().enumerate() {
                let junction = &domain.junctions[side_index];
                for &t in &nodes {
                    let j = junction.at(t);
                    for order in 0..3 {
                        let weights = jet_weights(order, j);
                        let mut row: Vec<(usize, f64)> = side
                            .patch_row(order, 0, t)
                            .iter()
                            .enumerate()
                            .filter(|(_, w)| **w != 0.0)
                            .map(|(i, &w)| (s * COEFFICIENTS + i, w))
                            .collect();
                        let mut data = Vec::new();
                        if side.on_curve() {
                            let curve = if *side == Side::CurveStart { s } else { s + 1 };
                            let at = auxiliary_offset(k, curve);
                            let jet_rows = Auxiliary::jet_rows(t);
                            for (e, &w) in weights.iter().enumerate() {
                                if w == 0.0 {
                                    continue;
                                }
                                for (i, &x) in jet_rows[e].iter().enumerate() {
                                    if x != 0.0 {
                                        row.push((at + i, -w * x));
                                    }
                                }
                            }
                        } else {
                            // jet entry e ↔ (along, cross) derivative of the ring patch
                            let orders = [(0, 0), (1, 0), (2, 0), (0, 1), (1, 1), (0, 2)];
                            for (e, &w) in weights.iter().enumerate() {
                                if w == 0.0 {
                                    continue;
                                }
                                let (along, cross) = orders[e];
                                for (v, x) in side.ring_weights(k, s, along, cross, t) {
                                    data.push((v, w * x));
                                }
                            }
                        }
                        rows.push((row, data));
                    }
                }
            }
        }
        let mut c = Mat::<f64>::zeros(rows.len(), n);
        let mut data = Mat::<f64>::zeros(rows.len(), vertices);
        for (i, (row, d)) in rows.iter().enumerate() {
            for &(col, value) in row {
                c[(i, col)] += value;
            }
            for &(col, value) in d {
                data[(i, col)] += value;
            }
        }
        Conditions { c, data }
    }
}
