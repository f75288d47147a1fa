//! The domain patches δ_s and the junction functions of every side (see [`super::sides`]).
//!
//! δ_s, the map of the unit square onto sector s of Ω_k, must itself satisfy the side
//! relations with the domain's auxiliary patches ([`super::auxiliary`]) and the domain
//! ring — x and y are functions of the space. Kiciak derives the junction functions corner
//! by corner from the compatibility equations (mixed derivatives up to (2, 2) agreeing
//! where two sides meet), taking them of the lowest degrees that admit a solution; those
//! equations are exactly the conditions for a degree-(9, 9) patch with the four sides'
//! data to exist. So we solve them all at once: unknowns δ_s's Bézier coefficients and the
//! junction functions' Bernstein coefficients, equations the side relations as polynomial
//! identities (at more nodes than their degree, so an inconsistency shows), quadratic in
//! the junction functions — Gauss–Newton with minimum-norm steps, whose Jacobian by central
//! differences is exact for a quadratic residual. δ_s is then the biquintic Coons patch of
//! the solution (the bubbles the equations leave free set by the Coons blending).

use nalgebra::{DMatrix, DVector};

use super::auxiliary::{domain_auxiliary, Auxiliary};
use super::bernstein::COEFFICIENTS;
use super::domain_net::DomainNet;
use super::polynomial::{coons, derivative};
use super::sides::{cross_derivatives, AuxiliaryJet, Side};
use crate::error::{Error, Result};

/// Nodes per polynomial identity (its degree is at most 9).
pub const IDENTITY_NODES: usize = 12;

/// Chebyshev nodes on [0, 1].
pub fn identity_nodes() -> Vec<f64> {
    let n = IDENTITY_NODES;
    (0..n)
        .map(|i| 0.5 - 0.5 * (std::f64::consts::PI * (i as f64 + 0.5) / n as f64).cos())
        .collect()
}

/// One side's junction functions, Bernstein coefficients of B₁, C₁, B₂, C₂.
#[derive(Debug, Clone, PartialEq)]
pub struct Junction(pub [Vec<f64>; 4]);

impl Junction {
    /// The four values at t.
    pub fn at(&self, t: f64) -> [f64; 4] {
        [0, 1, 2, 3].map(|i| derivative(&self.0[i], t, 0))
    }
}

/// A sector's domain patch and the junction functions of its four sides (in
/// [`Side::ALL`] order).
#[derive(Debug, Clone)]
pub struct SectorDomain {
    /// δ_s's Bézier coefficients per coordinate (index 10a + b).
    pub patch: [Vec<f64>; 2],
    pub junctions: [Junction; 4],
}

impl SectorDomain {
    /// This sector's domain patch turned by 2π·`turns`/k about the centre (the origin).
    pub fn rotated(&self, turns: usize, k: usize) -> SectorDomain {
        let angle = 2.0 * std::f64::consts::PI * turns as f64 / k as f64;
        let (sin, cos) = angle.sin_cos();
        let [x, y] = &self.patch;
        SectorDomain {
            patch: [
                x.iter().zip(y).map(|(x, y)| cos * x - sin * y).collect(),
                x.iter().zip(y).map(|(x, y)| sin * x + cos * y).collect(),
            ],
            junctions: self.junctions.clone(),
        }
    }
}

/// The auxiliary jet of side `side` of sector `sector` at t, for the domain coordinate `c`.
fn domain_jet(
    net: &DomainNet,
    curves: &[[Auxiliary; 2]],
    sector: usize,
    side: Side,
    t: f64,
    c: usize,
) -> AuxiliaryJet {
    let k = net.valence;
    match side {
        Side::CurveStart => curves[sector % k][c].jet(t),
        Side::CurveEnd => curves[(sector + 1) % k][c].jet(t),
        _ => {
            let d = |along, cross| -> f64 {
                side.ring_weights(k, sector, along, cross, t)
                    .iter()
                    .map(|&(v, w)| w * net.points[v][c])
                    .sum()
            };
            [d(0, 0), d(1, 0), d(2, 0), d(0, 1), d(1, 1), d(0, 2)]
        }
    }
}

/// Offsets of each side's junction coefficients in the unknown vector (after δ's 200).
fn junction_layout() -> ([[usize; 4]; 4], usize) {
    let mut offsets = [[0; 4]; 4];
    let mut at = 2 * COEFFICIENTS;
    for (s, side) in Side::ALL.iter().enumerate() {
        for (f, d) in side.junction_degrees().iter().enumerate() {
            offsets[s][f] = at;
            at += d + 1;
        }
    }
    (offsets, at)
}

/// Side `side`'s junction functions in the unknowns `z`, at `offsets`.
fn junction_in(z: &[f64], offsets: [usize; 4], side: Side) -> Junction {
    let degrees = side.junction_degrees();
    Junction([0, 1, 2, 3].map(|f| z[offsets[f]..offsets[f] + degrees[f] + 1].to_vec()))
}

/// The side relations' residuals at unknowns `z`, given the auxiliary jets and the patch's
/// derivative rows at the identity nodes (per side, node, coordinate / order).
fn residual(
    z: &[f64],
    jets: &[Vec<[AuxiliaryJet; 2]>; 4],
    rows: &[Vec<[[f64; COEFFICIENTS]; 3]>; 4],
) -> Vec<f64> {
    let (offsets, _) = junction_layout();
    let nodes = identity_nodes();
    let mut out = Vec::with_capacity(4 * 3 * IDENTITY_NODES * 2);
    for (s, side) in Side::ALL.iter().enumerate() {
        let junction = junction_in(z, offsets[s], *side);
        for (q, &t) in nodes.iter().enumerate() {
            let j = junction.at(t);
            for c in 0..2 {
                let patch = &z[c * COEFFICIENTS..(c + 1) * COEFFICIENTS];
                let r = &jets[s][q][c];
                let cross = cross_derivatives(r, j);
                let target = [r[0], cross[0], cross[1]];
                for (order, want) in target.iter().enumerate() {
                    let have: f64 = rows[s][q][order]
                        .iter()
                        .zip(patch)
                        .map(|(w, x)| w * x)
                        .sum();
                    out.push(have - want);
                }
            }
        }
    }
    out
}

/// Solves sector `sector`'s domain patch and junction functions.
///
/// # Errors
/// [`Error::InvalidInput`] if Gauss–Newton does not bring the side relations to round-off
/// (it does for 3 ≤ k ≤ 16: tested).
pub fn sector_domain(net: &DomainNet, sector: usize) -> Result<SectorDomain> {
    let k = net.valence;
    let curves: Vec<[Auxiliary; 2]> = (0..k).map(|s| domain_auxiliary(net, s)).collect();
    let nodes = identity_nodes();
    let jets: [Vec<[AuxiliaryJet; 2]>; 4] = Side::ALL.map(|side| {
        nodes
            .iter()
            .map(|&t| [0, 1].map(|c| domain_jet(net, &curves, sector, side, t, c)))
            .collect()
    });
    let rows: [Vec<[[f64; COEFFICIENTS]; 3]>; 4] = Side::ALL.map(|side| {
        nodes
            .iter()
            .map(|&t| [0, 1, 2].map(|o| side.patch_row(o, 0, t)))
            .collect()
    });
    let (offsets, n) = junction_layout();
    // Start: the regular junction (B₁ = B₂ = C₂ = 0, C₁ = ±1 by the side's orientation).
    let mut z = vec![0.0; n];
    for (s, side) in Side::ALL.iter().enumerate() {
        let sign = if *side == Side::CurveEnd { -1.0 } else { 1.0 };
        let d = side.junction_degrees()[1];
        for i in 0..=d {
            z[offsets[s][1] + i] = sign;
        }
    }
    let scale = net
        .points
        .iter()
        .flatten()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let eval = |z: &[f64]| residual(z, &jets, &rows);
    let mut r = eval(&z);
    let norm = |r: &[f64]| r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for _ in 0..50 {
        if norm(&r) <= 1e-12 * scale {
            break;
        }
        let h = 1e-3;
        let mut jac = DMatrix::<f64>::zeros(r.len(), n);
        for col in 0..n {
            let (mut zp, mut zm) = (z.clone(), z.clone());
            zp[col] += h;
            zm[col] -= h;
            let (rp, rm) = (eval(&zp), eval(&zm));
            for i in 0..r.len() {
                jac[(i, col)] = (rp[i] - rm[i]) / (2.0 * h);
            }
        }
        let step = jac
            .svd(true, true)
            .solve(&DVector::from_vec(r.iter().map(|v| -v).collect()), 1e-11)
            .map_err(|e| Error::InvalidInput(format!("valence {k}: domain solve: {e}")))?;
        for (x, d) in z.iter_mut().zip(step.iter()) {
            *x += d;
        }
        r = eval(&z);
    }
    if norm(&r) > 1e-10 * scale {
        return Err(Error::InvalidInput(format!(
            "valence {k}: the domain patch of sector {sector} does not meet its side \
             relations (residual {:.1e})",
            norm(&r)
        )));
    }
    let junctions: [Junction; 4] =
        std::array::from_fn(|s| junction_in(&z, offsets[s], Side::ALL[s]));
    let patch = [0, 1].map(|c| coons(&z[c * COEFFICIENTS..(c + 1) * COEFFICIENTS]));
    Ok(SectorDomain { patch, junctions })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_domain_meets_its_side_relations_and_the_regular_case_is_regular() {
        for k in [3usize, 4, 5, 8] {
            let net = DomainNet::new(k);
            let d = sector_domain(&net, 0).unwrap();
            let j = &d.junctions;
            println!("k {k}");
            for (s, side) in Side::ALL.iter().enumerate() {
                println!("  {side:?}: {:?}", j[s].0);
            }
            // the net is k-fold symmetric: sector 1 solved on its own is sector 0 turned
            let turned = d.rotated(1, k);
            let second = sector_domain(&net, 1).unwrap();
            for c in 0..2 {
                for (a, b) in turned.patch[c].iter().zip(&second.patch[c]) {
                    assert!((a - b).abs() < 1e-9, "k {k}: {a} vs {b}");
                }
            }
            if k == 4 {
                // The square lattice needs no reparameterization across any side.
                for (s, side) in Side::ALL.iter().enumerate() {
                    let sign = if *side == Side::CurveEnd { -1.0 } else { 1.0 };
                    for &t in &[0.0, 0.4, 1.0] {
                        let v = j[s].at(t);
                        assert!(v[0].abs() < 1e-9 && (v[1] - sign).abs() < 1e-9);
                        assert!(v[2].abs() < 1e-9 && v[3].abs() < 1e-9, "{side:?} {v:?}");
                    }
                }
            }
        }
    }
}
