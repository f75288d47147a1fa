//! Plane polygon geometry shared by the hole shapes of the spline fits and the hole
//! filling of `repair`: orientation, signed area, containment, segment meeting, simplicity
//! and distance to a polygon's border. Polygons are closed (the last corner joins the
//! first).

/// Twice the signed area of triangle (a, b, c): positive when it runs counter-clockwise.
pub fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// The signed area (shoelace formula): positive when the polygon runs counter-clockwise.
pub fn signed_area(polygon: &[[f64; 2]]) -> f64 {
    (0..polygon.len())
        .map(|k| {
            let (a, b) = (polygon[k], polygon[(k + 1) % polygon.len()]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum::<f64>()
        / 2.0
}

pub fn distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// Whether `p` is inside the polygon (crossing number; a point on the border may fall
/// either way).
pub fn point_in_polygon(p: [f64; 2], polygon: &[[f64; 2]]) -> bool {
    let mut inside = false;
    let n = polygon.len();
    for i in 0..n {
        let (a, b) = (polygon[i], polygon[(i + 1) % n]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
            if p[0] < x {
                inside = !inside;
            }
        }
    }
    inside
}

/// Whether the closed segments pq and rs have a point in common (touching counts; two
/// segments on one line meet only where they overlap).
pub fn segments_meet(p: [f64; 2], q: [f64; 2], r: [f64; 2], s: [f64; 2]) -> bool {
    let (d1, d2) = (orient(r, s, p), orient(r, s, q));
    let (d3, d4) = (orient(p, q, r), orient(p, q, s));
    if d1 == 0.0 && d2 == 0.0 {
        let overlap =
            |k: usize| p[k].min(q[k]) <= r[k].max(s[k]) && r[k].min(s[k]) <= p[k].max(q[k]);
        return overlap(0) && overlap(1);
    }
    d1 * d2 <= 0.0 && d3 * d4 <= 0.0
}

/// No two edges meet except neighbours at their shared corner, and no edge is a point.
pub fn is_simple(polygon: &[[f64; 2]]) -> bool {
    let n = polygon.len();
    for i in 0..n {
        let (a, b) = (polygon[i], polygon[(i + 1) % n]);
        if distance(a, b) == 0.0 {
            return false;
        }
        for j in i + 2..n {
            if i == 0 && j == n - 1 {
                continue; // the last edge and the first share corner 0
            }
            if segments_meet(a, b, polygon[j], polygon[(j + 1) % n]) {
                return false;
            }
        }
    }
    true
}

/// Distance from `p` to the polygon's border.
pub fn distance_to_border(p: [f64; 2], polygon: &[[f64; 2]]) -> f64 {
    (0..polygon.len())
        .map(|k| {
            let (a, b) = (polygon[k], polygon[(k + 1) % polygon.len()]);
            let ab = [b[0] - a[0], b[1] - a[1]];
            let t = (((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1])
                / (ab[0] * ab[0] + ab[1] * ab[1]))
                .clamp(0.0, 1.0);
            distance(p, [a[0] + t * ab[0], a[1] + t * ab[1]])
        })
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SQUARE: [[f64; 2]; 4] = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];

    #[test]
    fn a_bow_tie_is_not_simple_and_a_split_side_is() {
        assert!(!is_simple(&[
            [0.0, 0.0],
            [1.0, 1.0],
            [1.0, 0.0],
            [0.0, 1.0]
        ]));
        assert!(is_simple(&SQUARE));
        // Collinear edges that do not overlap (a square's side in two pieces).
        assert!(is_simple(&[
            [0.0, 0.0],
            [0.5, 0.0],
            [1.0, 0.0],
            [1.0, 1.0],
            [0.0, 1.0]
        ]));
        assert!(!is_simple(&[
            [0.0, 0.0],
            [2.0, 0.0],
            [1.0, 0.0],
            [1.0, 1.0]
        ]));
    }

    #[test]
    fn area_containment_and_distance_of_the_unit_square() {
        assert_eq!(signed_area(&SQUARE), 1.0);
        let mut clockwise = SQUARE;
        clockwise.reverse();
        assert_eq!(signed_area(&clockwise), -1.0);
        assert!(point_in_polygon([0.25, 0.5], &SQUARE));
        assert!(!point_in_polygon([1.25, 0.5], &SQUARE));
        assert_eq!(distance_to_border([0.25, 0.5], &SQUARE), 0.25);
        assert!(!segments_meet(
            [0.0, 0.0],
            [1.0, 0.0],
            [2.0, 0.0],
            [3.0, 0.0]
        ));
        assert!(segments_meet(
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 0.0],
            [1.0, 1.0]
        ));
    }
}
