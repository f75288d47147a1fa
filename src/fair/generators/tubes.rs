//! Junctions of n ≥ 3 tubes like the paper's figures 7, 9 and 10 (§6): genus 0, one
//! boundary loop per tube end, quads only, two special vertices of valence 2n at the
//! saddles of the junction, every other internal vertex of valence 4 and every boundary
//! vertex of valence 3.
//!
//! Construction: a top and a bottom disc of 2n sectors (each an m × m grid) around the two
//! special vertices; their boundaries alternate n seams (glued top to bottom, in the
//! plane z = 0 between neighbouring tubes) and n openings; each opening (a loop of 4m
//! vertices) continues as a tube of `rings` rings, the tubes' axes spread evenly in the
//! plane z = 0. With n = 3, m = 4 and 3 rings this is the author's mesh (359 vertices, 336
//! quads, 16 boundary vertices per tube end); m = 8 and 2 rings gives the 1007-vertex mesh
//! of figure 7 (719 vertices at least 3 edges from the boundary), and n = 5, m = 8, 2 rings
//! the 1677-vertex mesh of Table 1 (figure 10).
//!
//! Why valence 2n and not the "n + 3" (which agrees only for n = 3): for a quad
//! mesh, counting corners gives Σ_internal (4 − d) + Σ_boundary (3 − d) = 4χ = 4 (2 − n).
//! With all boundary vertices of valence 3 and two special vertices of valence k, this is
//! 2 (4 − k) = 8 − 4n, so k = 2n. Valence n + 3 for n = 5 would need 2n − 6 = 4 boundary
//! vertices of valence 4 (or more special vertices). The valence-10 junction is the
//! paper's: m = 8, 2 rings gives exactly Table 1's n_V = 1677, and two refinements of the
//! surface ([`crate::fair::refine_surface`]) exactly its 6237 and 23997.

use std::collections::HashSet;
use std::f64::consts::PI;

use crate::error::{Error, Result};
use crate::mesh::PolygonMesh;

/// Tube radius; the other lengths scale with it.
const RADIUS: f64 = 1.0;
/// Distance of an opening's centre from the junction's centre for three tubes; more tubes
/// move out so that neighbouring openings keep a gap (see [`opening_distance`]).
const OPENING: f64 = 1.6;
/// Most tubes accepted: beyond this the sectors are slivers and the picture is a hedgehog.
pub const MAX_TUBES: u32 = 64;

/// Most vertices [`tubes`] generates (an absurd `--size` or `--rings` is an error, not an
/// allocation failure or minutes of work).
pub const MAX_TUBE_VERTICES: u64 = 4_000_000;

/// Distance of the openings' centres from the junction's centre: at least [`OPENING`], and
/// enough that neighbouring openings (radius [`RADIUS`], angle 2π/n apart) are separated by
/// a quarter of their diameter.
fn opening_distance(n: u32) -> f64 {
    OPENING.max(1.25 * RADIUS / (PI / f64::from(n)).sin())
}

/// The junction of `n` tubes with `m` quads along each sector side and `rings` rings per
/// tube (the tube ends have `4 m` boundary vertices).
///
/// # Errors
/// [`Error::InvalidInput`] unless `3 ≤ n ≤ MAX_TUBES`, `m ≥ 1` and `rings ≥ 1`.
pub fn tubes(n: u32, m: u32, rings: u32) -> Result<PolygonMesh> {
    if !(3..=MAX_TUBES).contains(&n) {
        return Err(Error::InvalidInput(format!(
            "a junction of {n} tubes: the number of tubes must be between 3 and {MAX_TUBES}"
        )));
    }
    if m == 0 || rings == 0 {
        return Err(Error::InvalidInput(format!(
            "a tube junction needs m ≥ 1 and rings ≥ 1 (got {m}, {rings})"
        )));
    }
    let k = 2 * n;
    // Vertices the request implies, counted in u64 before anything is allocated.
    let (k64, m64) = (u64::from(k), u64::from(m));
    let implied = 2 * (1 + k64 * m64 + k64 * m64 * m64) + u64::from(n) * 4 * m64 * u64::from(rings);
    if implied > MAX_TUBE_VERTICES {
        return Err(Error::InvalidInput(format!(
            "a junction of {n} tubes with {m} quads per sector side (--size) and {rings} rings \
             (--rings) has about {implied} vertices; at most {MAX_TUBE_VERTICES} are generated \
             (refine a smaller junction with --refine for larger meshes)"
        )));
    }
    let opening = opening_distance(n);
    let spread = 360.0 / f64::from(n);
    let per_disc = (1 + k * m + k * m * m) as usize;
    // Disc-local ids as in `sector_disc`.
    let local = |s: u32, i: u32, j: u32| -> u32 {
        let spoke = |s: u32, i: u32| 1 + (s % k) * m + (i - 1);
        match (i, j) {
            (0, 0) => 0,
            (_, 0) => spoke(s, i),
            (0, _) => spoke(s + 1, j),
            _ => 1 + k * m + (s % k) * m * m + (i - 1) * m + (j - 1),
        }
    };
    // Boundary of a disc, counter-clockwise from S0: sector s contributes (m, j) for
    // j = 0..m, then (i, m) for i = m..1 (2m vertices).
    let boundary: Vec<u32> = (0..k)
        .flat_map(|s| {
            (0..m)
                .map(move |j| (s, m, j))
                .chain((1..=m).rev().map(move |i| (s, i, m)))
        })
        .map(|(s, i, j)| local(s, i, j))
        .collect();
    let b = boundary.len(); // 12 m
                            // Boundary position of corner C_s is 2 m s + m, of spoke end S_s is 2 m s.
    let is_seam = |pos: usize| -> bool {
        // Seams C0–S1–C1, C2–S3–C3, … cover [2m s + m, 2m (s + 2) + m] for even s,
        // i.e. positions whose offset from C_s (s even) is ≤ 2m.
        let mu = m as usize;
        let off = (pos + b - mu) % b; // offset from C0
        (off % (4 * mu)) <= 2 * mu
    };
    // Global ids: top disc 0..per_disc; bottom disc ids for non-seam vertices follow.
    let mut bottom = vec![u32::MAX; per_disc];
    let mut next = per_disc as u32;
    let mut on_seam = vec![false; per_disc];
    for (pos, &v) in boundary.iter().enumerate() {
        if is_seam(pos) {
            on_seam[v as usize] = true;
        }
    }
    for v in 0..per_disc {
        if on_seam[v] {
            bottom[v] = v as u32;
        } else {
            bottom[v] = next;
            next += 1;
        }
    }
    let disc_vertices = next as usize;
    let mut faces: Vec<[u32; 4]> = Vec::new();
    for s in 0..k {
        for i in 0..m {
            for j in 0..m {
                let q = [
                    local(s, i, j),
                    local(s, i + 1, j),
                    local(s, i + 1, j + 1),
                    local(s, i, j + 1),
                ];
                faces.push(q);
                let r = q.map(|v| bottom[v as usize]);
                faces.push([r[3], r[2], r[1], r[0]]);
            }
        }
    }
    let directed: HashSet<(u32, u32)> = faces
        .iter()
        .flat_map(|f| (0..4).map(move |c| (f[c], f[(c + 1) % 4])))
        .collect();
    let around = (4 * m) as usize;
    let mut positions = vec![[0.0; 3]; disc_vertices + n as usize * around * rings as usize];
    let mut fixed = vec![false; disc_vertices];
    let dir = |deg: f64| [deg.to_radians().cos(), deg.to_radians().sin()];
    let step = 2.0 * PI * RADIUS / around as f64;
    for t in 0..n {
        // Opening around spoke end S_{2t}, from C_{2t−1} over the top to C_{2t}, back
        // under the bottom.
        let sp = (2 * t) as usize * 2 * m as usize;
        let top_arc: Vec<u32> = (0..=2 * m as usize)
            .map(|o| boundary[(sp + b - m as usize + o) % b])
            .collect();
        let mut loop_ids = top_arc.clone();
        loop_ids.extend(
            top_arc[1..2 * m as usize]
                .iter()
                .rev()
                .map(|&v| bottom[v as usize]),
        );
        let a = dir(spread * f64::from(t));
        let cw = [a[1], -a[0]];
        let circle = |dist: f64, idx: usize| -> [f64; 3] {
            let th = 2.0 * PI * idx as f64 / around as f64;
            [
                dist * a[0] + RADIUS * th.cos() * cw[0],
                dist * a[1] + RADIUS * th.cos() * cw[1],
                RADIUS * th.sin(),
            ]
        };
        for (idx, &v) in loop_ids.iter().enumerate() {
            positions[v as usize] = circle(opening, idx);
            fixed[v as usize] = true;
        }
        let reversed = directed.contains(&(loop_ids[0], loop_ids[1]));
        let mut prev = loop_ids.clone();
        for r in 1..=rings {
            let base = disc_vertices + (t * rings + r - 1) as usize * around;
            let ring: Vec<u32> = (0..around).map(|i| (base + i) as u32).collect();
            for (idx, &v) in ring.iter().enumerate() {
                positions[v as usize] = circle(opening + f64::from(r) * step, idx);
            }
            for i in 0..around {
                let (p0, p1) = (prev[i], prev[(i + 1) % around]);
                let (r0, r1) = (ring[i], ring[(i + 1) % around]);
                faces.push(if reversed {
                    [p1, p0, r0, r1]
                } else {
                    [p0, p1, r1, r0]
                });
            }
            prev = ring;
        }
        // Seam from C_{2t} (this opening's counter-clockwise side) to C_{2t+1} (the next
        // opening's clockwise side) in the plane z = 0, bent towards the centre.
        let c_start = boundary[(sp + m as usize) % b];
        let start = circle(opening, 2 * m as usize);
        let next_a = dir(spread * f64::from(t + 1));
        let end = [
            opening * next_a[0] + RADIUS * next_a[1],
            opening * next_a[1] - RADIUS * next_a[0],
            0.0,
        ];
        let mid = dir(spread * (f64::from(t) + 0.5));
        // The seam bends towards the centre: its control point lies 0.6 radii inside the
        // openings' circle (for three tubes at distance 1 = RADIUS).
        let inner = opening - 0.6 * RADIUS;
        let ctrl = [inner * mid[0], inner * mid[1], 0.0];
        let first = (sp + m as usize) % b;
        debug_assert_eq!(boundary[first], c_start);
        for o in 0..=2 * m as usize {
            let u = o as f64 / (2 * m) as f64;
            let v = boundary[(first + o) % b] as usize;
            positions[v] = std::array::from_fn(|x| {
                (1.0 - u) * (1.0 - u) * start[x] + 2.0 * u * (1.0 - u) * ctrl[x] + u * u * end[x]
            });
            fixed[v] = true;
        }
    }
    // Disc interiors: discrete harmonic (uniform weights) with the seams and openings held,
    // started from the disc's planar layout lifted above (below) the plane.
    let mut neighbours = vec![Vec::new(); disc_vertices];
    for f in &faces {
        for c in 0..4 {
            let (p, q) = (f[c] as usize, f[(c + 1) % 4] as usize);
            if p < disc_vertices && q < disc_vertices {
                neighbours[p].push(q);
                neighbours[q].push(p);
            }
        }
    }
    for v in 0..per_disc {
        if !fixed[v] {
            positions[v] = [0.0, 0.0, RADIUS];
            positions[bottom[v] as usize] = [0.0, 0.0, -RADIUS];
        }
    }
    for _ in 0..20 * (m as usize + 1) * (m as usize + 1) {
        for v in 0..disc_vertices {
            if fixed[v] {
                continue;
            }
            let nb = &neighbours[v];
            let mut p = [0.0; 3];
            for &w in nb {
                for x in 0..3 {
                    p[x] += positions[w][x] / nb.len() as f64;
                }
            }
            positions[v] = p;
        }
    }
    Ok(PolygonMesh::from_polygons(positions, &faces))
}
