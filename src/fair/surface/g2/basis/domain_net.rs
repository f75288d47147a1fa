//! The domain net of a special element of valence k (Kiciak's curvature-continuous
//! construction, paper §3; `../shared/notes/kiciak-g2-construction.md`): the planar
//! radius-3 net around a vertex of valence k that one Catmull–Clark step maps onto itself
//! scaled by the subdominant eigenvalue λ_k — the net of the characteristic map. Its inner
//! part bounds the domain Ω_k over which the k special patches are parameterized; it is
//! scaled so that Ω_k has area k.
//!
//! Net layout: the centre, then per sector i (between spokes i and i+1) the 12 vertices at
//! lattice coordinates (a, b), a ∈ 1..=3, b ∈ 0..=3, a-major: (a, b) lies a steps along
//! spoke i and b steps towards spoke i+1. Sector i's (0, b) is sector i+1's (b, 0), and its
//! (a, −b) is sector i−1's (b, a).

/// Vertices of a radius-3 net per sector.
pub const PER_SECTOR: usize = 12;

/// The planar domain net of one valence, with its eigenvalue.
#[derive(Debug, Clone, PartialEq)]
pub struct DomainNet {
    pub valence: usize,
    /// λ_k, the subdominant eigenvalue of one Catmull–Clark step.
    pub lambda: f64,
    /// 1 + 12k points (layout in the module doc), scaled so that Ω_k has area k.
    pub points: Vec<[f64; 2]>,
}

/// Index of sector `sector`'s lattice point (a, b) in the net, for a ∈ 1..=3, b ∈ 0..=3.
fn slot(k: usize, sector: usize, a: i32, b: i32) -> usize {
    debug_assert!((1..=3).contains(&a) && (0..=3).contains(&b));
    1 + (sector % k) * PER_SECTOR + (a as usize - 1) * 4 + b as usize
}

/// Index of lattice point (a, b) of sector `sector`, for points of the sector or of the
/// sectors round it (the centre for (0, 0)): across spoke i, sector i's (a, −b) is sector
/// i−1's (b, a); across spoke i+1, sector i's (−a, b) is sector i+1's (b, a) — applied
/// until the point is a sector's own, so (−1, 0) is two sectors on.
pub(crate) fn index(k: usize, sector: usize, a: i32, b: i32) -> usize {
    let (mut s, mut a, mut b) = (sector % k, a, b);
    for _ in 0..4 {
        match (a, b) {
            (0, 0) => return 0,
            (_, b0) if b0 < 0 => (s, a, b) = ((s + k - 1) % k, -b0, a),
            (a0, _) if a0 <= 0 => (s, a, b) = ((s + 1) % k, b, -a0),
            _ => return slot(k, s, a, b),
        }
    }
    panic!("lattice point ({a}, {b}) is not round sector {sector}'s corner")
}

/// Catmull–Clark subdominant eigenvalue of valence k (Doo–Sabin / Ball–Storry closed
/// form): (5 + cos 2π/k + cos π/k · √(2 (9 + cos 2π/k))) / 16.
pub fn subdominant_eigenvalue(k: usize) -> f64 {
    let c = (2.0 * std::f64::consts::PI / k as f64).cos();
    let c_half = (std::f64::consts::PI / k as f64).cos();
    (5.0 + c + c_half * (2.0 * (9.0 + c)).sqrt()) / 16.0
}

/// One Catmull–Clark step on a scalar field over the radius-3 net, read back as the
/// radius-3 net around the same vertex in the refined mesh (the operator P_k). Refined
/// lattice point (a', b') is the old point (a'/2, b'/2): a vertex point where both are
/// even, an edge point where one is odd, a face point where both are.
pub fn refine_net(k: usize, values: &[f64]) -> Vec<f64> {
    let at = |s: usize, a: i32, b: i32| values[index(k, s, a, b)];
    // Face [a, a+1] × [b, b+1] of sector s.
    let face = |s: usize, a: i32, b: i32| {
        (at(s, a, b) + at(s, a + 1, b) + at(s, a, b + 1) + at(s, a + 1, b + 1)) / 4.0
    };
    let centre = {
        let n = k as f64;
        let ring: f64 = (0..k).map(|s| at(s, 1, 0)).sum();
        let faces: f64 = (0..k).map(|s| face(s, 0, 0)).sum();
        (n - 2.0) / n * values[0] + (ring + faces) / (n * n)
    };
    // Vertex point of a valence-4 vertex (a, b) of sector s.
    let vertex = |s: usize, a: i32, b: i32| {
        let ring = at(s, a + 1, b) + at(s, a - 1, b) + at(s, a, b + 1) + at(s, a, b - 1);
        let faces = face(s, a, b) + face(s, a - 1, b) + face(s, a, b - 1) + face(s, a - 1, b - 1);
        0.5 * at(s, a, b) + (ring + faces) / 16.0
    };
    let mut out = vec![0.0; values.len()];
    out[0] = centre;
    for s in 0..k {
        for a2 in 1..=3i32 {
            for b2 in 0..=3i32 {
                let (a, b) = (a2 / 2, b2 / 2);
                let value = match (a2 % 2, b2 % 2) {
                    (0, 0) => vertex(s, a, b),
                    // Edge (a, b)–(a+1, b) between faces [a, a+1] × [b−1, b] and × [b, b+1].
                    (1, 0) => {
                        (at(s, a, b) + at(s, a + 1, b) + face(s, a, b - 1) + face(s, a, b)) / 4.0
                    }
                    (0, _) => {
                        (at(s, a, b) + at(s, a, b + 1) + face(s, a - 1, b) + face(s, a, b)) / 4.0
                    }
                    _ => face(s, a, b),
                };
                out[slot(k, s, a2, b2)] = value;
            }
        }
    }
    out
}

/// `values` with every lattice position's values over the k sectors projected on Fourier
/// mode 1 (cos θ_s, sin θ_s), and the centre (mode 0 only) set to 0.
fn keep_mode_one(k: usize, values: &mut [f64]) {
    let angle = |s: usize| 2.0 * std::f64::consts::PI * s as f64 / k as f64;
    values[0] = 0.0;
    for j in 0..PER_SECTOR {
        let at = |s: usize| 1 + s * PER_SECTOR + j;
        let (mut c, mut d) = (0.0, 0.0);
        for s in 0..k {
            c += values[at(s)] * angle(s).cos();
            d += values[at(s)] * angle(s).sin();
        }
        let (c, d) = (2.0 * c / k as f64, 2.0 * d / k as f64);
        for s in 0..k {
            values[at(s)] = c * angle(s).cos() + d * angle(s).sin();
        }
    }
}

/// The eigen-net of [`refine_net`] for λ_k before scaling: x from the cosine mode, y from
/// the sine mode (a pair that one sector's rotation turns by 2π/k), by power iteration
/// from the regular lattice's mode-1 net. Both coordinates are kept in Fourier mode 1
/// (round-off would otherwise grow the constant mode, eigenvalue 1), where λ_k is the
/// largest eigenvalue, so the iteration converges to it.
fn eigen_net(k: usize) -> (f64, Vec<f64>, Vec<f64>) {
    let n = 1 + PER_SECTOR * k;
    let angle = |s: usize| 2.0 * std::f64::consts::PI * s as f64 / k as f64;
    let mut x = vec![0.0; n];
    let mut y = vec![0.0; n];
    for s in 0..k {
        for a in 1..=3 {
            for b in 0..=3 {
                let i = slot(k, s, a, b);
                let (a, b) = (f64::from(a), f64::from(b));
                x[i] = a * angle(s).cos() + b * angle(s + 1).cos();
                y[i] = a * angle(s).sin() + b * angle(s + 1).sin();
            }
        }
    }
    let norm = |x: &[f64], y: &[f64]| x.iter().chain(y).map(|v| v * v).sum::<f64>().sqrt();
    let mut lambda = 0.0;
    for _ in 0..2000 {
        let (mut rx, mut ry) = (refine_net(k, &x), refine_net(k, &y));
        keep_mode_one(k, &mut rx);
        keep_mode_one(k, &mut ry);
        let grown = norm(&rx, &ry) / norm(&x, &y);
        let settled = (grown - lambda).abs() <= 1e-15;
        lambda = grown;
        let scale = 1.0 / norm(&rx, &ry);
        x = rx.iter().map(|v| v * scale).collect();
        y = ry.iter().map(|v| v * scale).collect();
        if settled {
            break;
        }
    }
    (lambda, x, y)
}

/// The uniform cubic B-spline arc of control points `p` at t ∈ [0, 1], and its derivative.
pub fn cubic_arc(p: [[f64; 2]; 4], t: f64) -> ([f64; 2], [f64; 2]) {
    let [w, dw, ..] = crate::subdiv::cubic_basis(t);
    let combine = |w: [f64; 4]| [0, 1].map(|c| (0..4).map(|j| w[j] * p[j][c]).sum::<f64>());
    (combine(w), combine(dw))
}

/// The boundary of Ω_k, counter-clockwise: per sector, the border of face [0, 1]² along
/// lattice line a = 1 (b from 0 to 1), then along b = 1 (a from 1 to 0) — the edges the
/// ring of bicubic patches round the element shares with it. On such an edge the bicubic
/// B-spline surface is the cubic B-spline whose control points are the net's three lines
/// across the edge averaged (1, 4, 1)/6.
pub fn boundary_arcs(k: usize, points: &[[f64; 2]]) -> Vec<[[f64; 2]; 4]> {
    let p = |s: usize, a: i32, b: i32| points[index(k, s, a, b)];
    let mix =
        |x: [f64; 2], y: [f64; 2], z: [f64; 2]| [0, 1].map(|c| (x[c] + 4.0 * y[c] + z[c]) / 6.0);
    (0..k)
        .flat_map(|s| {
            [
                [-1, 0, 1, 2].map(|b| mix(p(s, 0, b), p(s, 1, b), p(s, 2, b))),
                [2, 1, 0, -1].map(|a| mix(p(s, a, 0), p(s, a, 1), p(s, a, 2))),
            ]
        })
        .collect()
}

/// Area enclosed by closed piecewise-cubic arcs, by Green's theorem: ½∮(x dy − y dx). The
/// integrand is of degree 5 on each arc, so 3 Gauss–Legendre nodes are exact.
pub fn enclosed_area(arcs: &[[[f64; 2]; 4]]) -> f64 {
    let r = (0.6f64).sqrt();
    let nodes = [
        (0.5 - 0.5 * r, 5.0 / 18.0),
        (0.5, 8.0 / 18.0),
        (0.5 + 0.5 * r, 5.0 / 18.0),
    ];
    arcs.iter()
        .map(|&arc| {
            nodes
                .iter()
                .map(|&(t, w)| {
                    let (p, d) = cubic_arc(arc, t);
                    w * 0.5 * (p[0] * d[1] - p[1] * d[0])
                })
                .sum::<f64>()
        })
        .sum()
}

impl DomainNet {
    /// The domain net of valence `k` (3 ≤ k ≤ 16, k ≠ 4 for a special element; 4 gives the
    /// regular lattice, a check).
    ///
    /// # Panics
    /// Never for 3 ≤ k ≤ 64; smaller k has no net.
    pub fn new(k: usize) -> DomainNet {
        assert!(k >= 3, "a domain net needs valence 3 or more, not {k}");
        let (lambda, x, y) = eigen_net(k);
        let raw: Vec<[f64; 2]> = x.iter().zip(&y).map(|(&x, &y)| [x, y]).collect();
        let area = enclosed_area(&boundary_arcs(k, &raw));
        let scale = (k as f64 / area).sqrt();
        DomainNet {
            valence: k,
            lambda,
            points: raw.iter().map(|p| [p[0] * scale, p[1] * scale]).collect(),
        }
    }

    /// Sector `sector`'s lattice point (a, b) (the net's or a neighbouring sector's).
    pub fn point(&self, sector: usize, a: i32, b: i32) -> [f64; 2] {
        self.points[index(self.valence, sector, a, b)]
    }

    /// Index in [`DomainNet::points`] of sector `sector`'s lattice point (a, b) (the net's
    /// or a neighbouring sector's; a, b ≤ 3).
    pub fn vertex(&self, sector: usize, a: i32, b: i32) -> usize {
        index(self.valence, sector, a, b)
    }

    /// The net's 9k quads, counter-clockwise (sector by sector, faces [a, a+1] × [b, b+1]).
    pub fn quads(&self) -> Vec<[u32; 4]> {
        let k = self.valence;
        let mut out = Vec::with_capacity(9 * k);
        for s in 0..k {
            for a in 0..3 {
                for b in 0..3 {
                    out.push(
                        [(a, b), (a + 1, b), (a + 1, b + 1), (a, b + 1)]
                            .map(|(a, b)| index(k, s, a, b) as u32),
                    );
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_regular_lattice_is_the_valence_4_net() {
        // For k = 4, λ = 1/2 and the net is the square lattice (up to rotation and scale):
        // neighbouring points one lattice step apart along both axes.
        let net = DomainNet::new(4);
        assert!((net.lambda - 0.5).abs() < 1e-13);
        let step =
            |p: [f64; 2], q: [f64; 2]| ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt();
        let h = step(net.point(0, 1, 0), net.point(0, 0, 0));
        for s in 0..4 {
            for a in 1..=3 {
                for b in 0..=2 {
                    let d = step(net.point(s, a, b), net.point(s, a, b + 1));
                    assert!(
                        (d - h).abs() < 1e-12 * h,
                        "sector {s} ({a}, {b}): {d} vs {h}"
                    );
                }
            }
        }
        // Area 4 = four unit squares of the lattice: h = 1.
        assert!((h - 1.0).abs() < 1e-12, "{h}");
    }
}
