//! A stamp model in the spirit of Liu et al. (2020) §4: a plate whose top face carries
//! two recessed letter pockets, a side ring, a back face and a handle with a triangle tip;
//! quads with triangles at the corners, pentagons along a row of midpoints, hexagons where
//! two cells merge, a sliver triangle pair and a narrow belt of quads. Its faces are drawn
//! in four stages (OBJ groups) whose χ are −1, 0, 1, 2 as in the paper's §4.4:
//!
//! 1. `fringe_and_middle_row`: the top face's border ring and a middle row: a disk with two
//!    openings, χ = −1;
//! 2. `half_top_face`: the lower opening filled (with pocket A and the sliver triangles):
//!    χ = 0;
//! 3. `top_side_back`: the upper opening (pocket B), the side ring (with the narrow belt)
//!    and the back face with an opening for the handle: χ = 1;
//! 4. `handle`: a square tube with a triangle fan at its tip: a closed surface, χ = 2.
//!
//! [`StampFlaw`] injects the paper's three flaws: the tiny unfilled triangle (§4.1), the
//! narrow unfilled quad (§4.2) and the pentagon written as a quad (§4.3, a crack).

use std::collections::HashMap;

use crate::mesh::{FaceLabels, PolygonMesh};

/// One of the paper's flaws, injected into the stamp.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StampFlaw {
    /// §4.1: one of the two sliver triangles (one edge 0.001 of the others) left out, in stage 2.
    TinyTriangle,
    /// §4.2: one quad of the narrow belt between the top face and the side ring left out,
    /// in stage 3.
    NarrowQuad,
    /// §4.3: a pentagon of stage 2 written as the quad that skips its collinear vertex.
    Crack,
}

/// The stage names, in drawing order, with the χ each stage ends at.
pub const STAMP_STAGES: [(&str, i64); 4] = [
    ("fringe_and_middle_row", -1),
    ("half_top_face", 0),
    ("top_side_back", 1),
    ("handle", 2),
];

/// Lattice unit: one cell is 1000 units, so the sliver and the belt (1 unit) are 0.001 cell.
const C: i64 = 1000;
const NX: i64 = 12;
const NY: i64 = 8;
const THICK: i64 = 3 * C;
const POCKET_DEPTH: i64 = C / 2;

struct Builder {
    index: HashMap<[i64; 3], u32>,
    positions: Vec<[f64; 3]>,
    faces: Vec<Vec<u32>>,
    stage_of_face: Vec<u32>,
    stage: u32,
}

impl Builder {
    fn vertex(&mut self, p: [i64; 3]) -> u32 {
        let next = self.positions.len() as u32;
        *self.index.entry(p).or_insert_with(|| {
            self.positions.push(p.map(|c| c as f64 / C as f64));
            next
        })
    }

    fn face(&mut self, points: &[[i64; 3]]) {
        let f = points.iter().map(|&p| self.vertex(p)).collect();
        self.faces.push(f);
        self.stage_of_face.push(self.stage);
    }

    /// A top-face cell, counter-clockwise seen from +z (outward).
    fn top_cell(&mut self, x: i64, y: i64) {
        let p = |x: i64, y: i64| top_point(x * C, y * C);
        self.face(&[p(x, y), p(x + 1, y), p(x + 1, y + 1), p(x, y + 1)]);
    }

    /// Walls under the directed boundary edges `p → q` of the surface above, from `hi`
    /// down to `lo`: `[q_hi, p_hi, p_lo, q_lo]` runs the shared edge the other way.
    fn wall(&mut self, p: [i64; 2], q: [i64; 2], hi: i64, lo: i64) {
        self.face(&[
            [q[0], q[1], hi],
            [p[0], p[1], hi],
            [p[0], p[1], lo],
            [q[0], q[1], lo],
        ]);
    }
}

/// A point of the top face.
fn top_point(x: i64, y: i64) -> [i64; 3] {
    [x, y, THICK]
}

fn in_pocket_a(x: i64, y: i64) -> bool {
    (2..5).contains(&x) && (1..3).contains(&y)
}

fn in_pocket_b(x: i64, y: i64) -> bool {
    (7..10).contains(&x) && (5..7).contains(&y)
}

fn in_handle_opening(x: i64, y: i64) -> bool {
    (5..7).contains(&x) && (3..5).contains(&y)
}

/// The rim of a rectangular pocket of cells `[x0, x1) × [y0, y1)`, as the top face runs it
/// (clockwise seen from above), in lattice units.
fn rim(x0: i64, x1: i64, y0: i64, y1: i64) -> Vec<([i64; 2], [i64; 2])> {
    let mut corners = Vec::new();
    for x in x0..x1 {
        corners.push([x * C, y0 * C]);
    }
    for y in y0..y1 {
        corners.push([x1 * C, y * C]);
    }
    for x in (x0 + 1..=x1).rev() {
        corners.push([x * C, y1 * C]);
    }
    for y in (y0 + 1..=y1).rev() {
        corners.push([x0 * C, y * C]);
    }
    // Counter-clockwise list; the top face runs an inner rim clockwise.
    let n = corners.len();
    (0..n).map(|k| (corners[(k + 1) % n], corners[k])).collect()
}

fn pocket(b: &mut Builder, x0: i64, x1: i64, y0: i64, y1: i64) {
    let floor = THICK - POCKET_DEPTH;
    for (p, q) in rim(x0, x1, y0, y1) {
        b.wall(p, q, THICK, floor);
    }
    for x in x0..x1 {
        for y in y0..y1 {
            let p = |x: i64, y: i64| [x * C, y * C, floor];
            b.face(&[p(x, y), p(x + 1, y), p(x + 1, y + 1), p(x, y + 1)]);
        }
    }
}

/// Builds the stamp, with `flaws` injected. Faces carry their stage as an OBJ group.
pub fn stamp(flaws: &[StampFlaw]) -> PolygonMesh {
    let mut b = Builder {
        index: HashMap::new(),
        positions: Vec::new(),
        faces: Vec::new(),
        stage_of_face: Vec::new(),
        stage: 0,
    };
    let half = C / 2;
    let t = |x: i64, y: i64| top_point(x, y);

    // Stage 1: border ring (corner cells as two triangles) and the middle row y = 4 of
    // pentagons with a midpoint on their lower edge.
    for x in 0..NX {
        for y in 0..NY {
            let border = x == 0 || y == 0 || x == NX - 1 || y == NY - 1;
            let corner = (x == 0 || x == NX - 1) && (y == 0 || y == NY - 1);
            if corner {
                let (p0, p1, p2, p3) = (
                    t(x * C, y * C),
                    t((x + 1) * C, y * C),
                    t((x + 1) * C, (y + 1) * C),
                    t(x * C, (y + 1) * C),
                );
                b.face(&[p0, p1, p2]);
                b.face(&[p0, p2, p3]);
            } else if border {
                b.top_cell(x, y);
            } else if y == 4 {
                b.face(&[
                    t(x * C, 4 * C),
                    t(x * C + half, 4 * C),
                    t((x + 1) * C, 4 * C),
                    t((x + 1) * C, 5 * C),
                    t(x * C, 5 * C),
                ]);
            }
        }
    }

    // Stage 2: the lower opening (rows 1–3) with pocket A; row 3 are pentagons sharing the
    // middle row's midpoints; the corner (6, 2) is split into u and u' with two slivers.
    b.stage = 1;
    let u = t(6 * C, 2 * C);
    let u_prime = t(6 * C + 1, 2 * C);
    for x in 1..NX - 1 {
        for y in 1..4 {
            if in_pocket_a(x, y) {
                continue;
            }
            // Cells right of x = 6 use u' for the lattice point (6, 2).
            let corner = |cx: i64, cy: i64| {
                if cx == 6 && cy == 2 && x >= 6 {
                    u_prime
                } else {
                    t(cx * C, cy * C)
                }
            };
            if y == 3 {
                let pentagon = [
                    corner(x, 3),
                    corner(x + 1, 3),
                    corner(x + 1, 4),
                    t(x * C + half, 4 * C),
                    corner(x, 4),
                ];
                if flaws.contains(&StampFlaw::Crack) && x == 8 {
                    b.face(&[pentagon[0], pentagon[1], pentagon[2], pentagon[4]]);
                } else {
                    b.face(&pentagon);
                }
            } else {
                b.face(&[
                    corner(x, y),
                    corner(x + 1, y),
                    corner(x + 1, y + 1),
                    corner(x, y + 1),
                ]);
            }
        }
    }
    if !flaws.contains(&StampFlaw::TinyTriangle) {
        b.face(&[u, t(6 * C, C), u_prime]);
    }
    b.face(&[u_prime, t(6 * C, 3 * C), u]);
    pocket(&mut b, 2, 5, 1, 3);

    // Stage 3: the upper opening (rows 5–6) with pocket B and two hexagons, the side ring
    // under a narrow belt, and the back face around the handle opening.
    b.stage = 2;
    for x in 1..NX - 1 {
        for y in 5..7 {
            if in_pocket_b(x, y) || (y == 5 && x == 2) {
                continue;
            }
            if y == 5 && x == 1 {
                // Two cells merged: a hexagon.
                b.face(&[
                    t(C, 5 * C),
                    t(2 * C, 5 * C),
                    t(3 * C, 5 * C),
                    t(3 * C, 6 * C),
                    t(2 * C, 6 * C),
                    t(C, 6 * C),
                ]);
                continue;
            }
            b.top_cell(x, y);
        }
    }
    pocket(&mut b, 7, 10, 5, 7);
    let outline: Vec<[i64; 2]> = (0..NX)
        .map(|x| [x * C, 0])
        .chain((0..NY).map(|y| [NX * C, y * C]))
        .chain((1..=NX).rev().map(|x| [x * C, NY * C]))
        .chain((1..=NY).rev().map(|y| [0, y * C]))
        .collect();
    let n = outline.len();
    for k in 0..n {
        let (p, q) = (outline[k], outline[(k + 1) % n]);
        if !(flaws.contains(&StampFlaw::NarrowQuad) && k == 3) {
            b.wall(p, q, THICK, THICK - 1);
        }
        b.wall(p, q, THICK - 1, 0);
    }
    for x in 0..NX {
        for y in 0..NY {
            if in_handle_opening(x, y) {
                continue;
            }
            let p = |x: i64, y: i64| [x * C, y * C, 0];
            b.face(&[p(x, y), p(x, y + 1), p(x + 1, y + 1), p(x + 1, y)]);
        }
    }

    // Stage 4: the handle, a square tube of two rows under the opening, closed by a fan
    // of triangles.
    b.stage = 3;
    let opening = rim(5, 7, 3, 5);
    let (mid, low) = (-4 * C, -8 * C);
    for &(p, q) in &opening {
        // The back face runs its inner rim opposite to a top face: swap to keep p → q
        // as the back face runs it.
        b.wall(q, p, 0, mid);
        b.wall(q, p, mid, low);
    }
    let apex = [6 * C, 4 * C, low - C];
    for &(p, q) in &opening {
        b.face(&[[p[0], p[1], low], [q[0], q[1], low], apex]);
    }

    let mut mesh = PolygonMesh::from_polygons(b.positions, &b.faces);
    mesh.groups = Some(FaceLabels {
        names: STAMP_STAGES.iter().map(|(n, _)| n.to_string()).collect(),
        of_face: b.stage_of_face,
    });
    mesh
}
