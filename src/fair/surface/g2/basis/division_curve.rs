//! The division curves of Ω_k (Kiciak's construction; `../shared/notes/
//! kiciak-g2-construction.md`): the k curves from the centre c to the points m_i where
//! spoke i meets Ω_k's border, which split Ω_k into the k domains of the special patches.
//! Each is a degree-7 polynomial curve fixed by Hermite data: at c, position c, first
//! derivative m_i − c and derivatives 2–4 zero; at m_i, position, first and second
//! derivative of the ring's mesh line through m_i — the spoke's lattice line as the ring of
//! bicubic patches has it, so the curve continues it C², parameter for parameter.

use super::domain_net::{cubic_arc, DomainNet};

/// Bézier control points of a planar curve of degree 7.
pub type Degree7 = [[f64; 2]; 8];

/// The ring's mesh line along spoke `spoke` for lattice a ∈ [1, 2] as a uniform cubic
/// B-spline arc (parameter a − 1): the edge the patches on either side of the spoke share,
/// whose control points are the net's lattice lines b = −1, 0, 1 averaged (1, 4, 1)/6.
fn spoke_arc(net: &DomainNet, spoke: usize) -> [[f64; 2]; 4] {
    let p = |a: i32, b: i32| net.point(spoke, a, b);
    [0, 1, 2, 3].map(|a| {
        let (x, y, z) = (p(a, -1), p(a, 0), p(a, 1));
        [0, 1].map(|c| (x[c] + 4.0 * y[c] + z[c]) / 6.0)
    })
}

/// Position, first and second derivative (in a) of the spoke's mesh line at a = 1: m_i.
fn ring_data(net: &DomainNet, spoke: usize) -> [[f64; 2]; 3] {
    let arc = spoke_arc(net, spoke);
    let (position, first) = cubic_arc(arc, 0.0);
    // A uniform cubic B-spline's second derivative at t = 0: P0 − 2P1 + P2.
    let second = [0, 1].map(|c| arc[0][c] - 2.0 * arc[1][c] + arc[2][c]);
    [position, first, second]
}

/// The division curve from the centre to spoke `spoke`'s border point, in Bézier form. With
/// derivatives 2–4 zero at c, its first five control points are equally spaced on the line
/// from c towards m_i; the last three carry the ring's data (d'(1) = 7 (b₇ − b₆),
/// d''(1) = 42 (b₇ − 2 b₆ + b₅)).
pub fn division_curve(net: &DomainNet, spoke: usize) -> Degree7 {
    let c = net.point(spoke, 0, 0);
    let [m, d1, d2] = ring_data(net, spoke);
    let mut b = [[0.0; 2]; 8];
    for (k, point) in b.iter_mut().enumerate().take(5) {
        *point = [0, 1].map(|x| c[x] + k as f64 * (m[x] - c[x]) / 7.0);
    }
    b[7] = m;
    b[6] = [0, 1].map(|x| m[x] - d1[x] / 7.0);
    b[5] = [0, 1].map(|x| d2[x] / 42.0 + 2.0 * b[6][x] - b[7][x]);
    b
}

/// The curve's derivatives of order 0..=`order` at t, by differencing the control points
/// (the derivative of a degree-n Bézier curve is n times the curve of its differences).
pub fn bezier_derivatives(points: &[[f64; 2]], t: f64, order: usize) -> Vec<[f64; 2]> {
    let mut out = Vec::with_capacity(order + 1);
    let mut current = points.to_vec();
    let mut factor = 1.0;
    for _ in 0..=order {
        // de Casteljau for the value of the current difference curve.
        let mut work = current.clone();
        for level in 1..work.len() {
            for i in 0..work.len() - level {
                work[i] = [0, 1].map(|c| (1.0 - t) * work[i][c] + t * work[i + 1][c]);
            }
        }
        out.push(work.first().map_or([0.0; 2], |p| p.map(|v| factor * v)));
        let n = current.len().saturating_sub(1);
        factor *= n as f64;
        current = current
            .windows(2)
            .map(|w| [0, 1].map(|c| w[1][c] - w[0][c]))
            .collect();
    }
    out
}
