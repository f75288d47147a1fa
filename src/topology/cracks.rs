//! Cracks (T-junctions): a boundary vertex lying on a boundary edge it does not belong to,
//! within a tolerance relative to that edge's length (the paper's Fig. 22, and its float
//! exports a fraction of a percent off the line). Splitting each such edge at its
//! T-vertices and gluing the boundary edges that then coincide shows what the crack hides:
//! the loops left over are the real holes and borders the T-junction had merged with.

use crate::mesh::vector::distance;
use foldhash::{HashMap as FxHashMap, HashMapExt};

/// One boundary edge with the boundary vertices lying on it, ordered from `a` to `b`.
#[derive(Debug, Clone, PartialEq)]
pub struct TJunction {
    pub a: u32,
    pub b: u32,
    pub t_vertices: Vec<u32>,
    /// Largest distance of a T-vertex from the edge, relative to the edge's length.
    pub offset: f64,
}

/// The boundary once every T-junction is stitched.
#[derive(Debug, Clone, Default)]
pub struct Stitched {
    pub junctions: Vec<TJunction>,
    /// Loops left by stitching the walks that had T-junctions (empty where a crack was
    /// all there was), each with the index of the walk it mostly came from.
    pub remaining: Vec<(Vec<u32>, usize)>,
    /// Whether each walk took part in a T-junction (its loop is replaced by `remaining`).
    pub stitched_walk: Vec<bool>,
}

/// Where vertex `p` falls on segment `a`–`b`: the parameter along it and the distance
/// from the line, when the foot is strictly inside and `p` is off both ends by more
/// than `reach`.
fn foot_on_segment(p: [f64; 3], a: [f64; 3], b: [f64; 3], reach: f64) -> Option<(f64, f64)> {
    let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let w = [p[0] - a[0], p[1] - a[1], p[2] - a[2]];
    let len2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    if len2 == 0.0 {
        return None;
    }
    let t = (w[0] * d[0] + w[1] * d[1] + w[2] * d[2]) / len2;
    if !(t > 0.0 && t < 1.0) || distance(p, a) <= reach || distance(p, b) <= reach {
        return None;
    }
    let foot = [a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]];
    let off = distance(p, foot);
    (off <= reach).then_some((t, off))
}

/// Boundary vertices hashed by cell, to find those near an edge without a pass over all.
struct VertexGrid {
    cell: f64,
    cells: FxHashMap<[i64; 3], Vec<u32>>,
    all: Vec<u32>,
}

impl VertexGrid {
    fn new(vertices: &[u32], positions: &[[f64; 3]], cell: f64) -> Self {
        let mut cells: FxHashMap<[i64; 3], Vec<u32>> = FxHashMap::new();
        for &v in vertices {
            let key = Self::key(positions[v as usize], cell);
            cells.entry(key).or_default().push(v);
        }
        VertexGrid {
            cell,
            cells,
            all: vertices.to_vec(),
        }
    }

    fn key(p: [f64; 3], cell: f64) -> [i64; 3] {
        p.map(|c| (c / cell).floor() as i64)
    }

    /// Every vertex within `reach` of segment a–b (and some more), each once.
    fn near_segment(&self, a: [f64; 3], b: [f64; 3], reach: f64, out: &mut Vec<u32>) {
        out.clear();
        let length = distance(a, b);
        let steps = (length / self.cell).ceil().max(1.0);
        // A vertex within `reach` of the segment is within reach + cell/2 of a sample.
        let radius = ((reach + 0.5 * self.cell) / self.cell).ceil();
        let lookups = (steps + 1.0) * (2.0 * radius + 1.0).powi(3);
        // Past as many lookups as there are occupied cells, a pass over all is cheaper.
        if lookups >= self.cells.len() as f64 {
            out.extend_from_slice(&self.all);
            return;
        }
        // The cells of the segment's box grown by `reach`, when there are fewer of them than
        // the samples would look up (short edges: most of them), each once.
        let lo = Self::key([0, 1, 2].map(|k| a[k].min(b[k]) - reach), self.cell);
        let hi = Self::key([0, 1, 2].map(|k| a[k].max(b[k]) + reach), self.cell);
        let box_cells: f64 = (0..3).map(|k| (hi[k] - lo[k] + 1) as f64).product();
        if box_cells <= lookups {
            for x in lo[0]..=hi[0] {
                for y in lo[1]..=hi[1] {
                    for z in lo[2]..=hi[2] {
                        if let Some(list) = self.cells.get(&[x, y, z]) {
                            out.extend_from_slice(list);
                        }
                    }
                }
            }
            return;
        }
        let (steps, r) = (steps as usize, radius as i64);
        let mut seen: foldhash::HashSet<[i64; 3]> = Default::default();
        for s in 0..=steps {
            let t = s as f64 / steps as f64;
            let p = [0, 1, 2].map(|k| a[k] + t * (b[k] - a[k]));
            let c = Self::key(p, self.cell);
            for dx in -r..=r {
                for dy in -r..=r {
                    for dz in -r..=r {
                        let key = [c[0] + dx, c[1] + dy, c[2] + dz];
                        if seen.insert(key) {
                            if let Some(list) = self.cells.get(&key) {
                                out.extend_from_slice(list);
                            }
                        }
                    }
                }
            }
        }
    }
}

/// Median of the boundary edges' lengths (0 for none).
fn median_length(edges: &[(u32, u32)], positions: &[[f64; 3]]) -> f64 {
    let mut lengths: Vec<f64> = edges
        .iter()
        .map(|&(a, b)| distance(positions[a as usize], positions[b as usize]))
        .collect();
    if lengths.is_empty() {
        return 0.0;
    }
    let mid = lengths.len() / 2;
    *lengths.select_nth_unstable_by(mid, f64::total_cmp).1
}

/// A boundary edge as (walk, position of its first vertex in the walk).
type EdgeKey = (usize, usize);

/// A candidate T-vertex on an edge: (parameter along the edge, vertex, relative offset).
type OnEdge = (f64, u32, f64);

/// Candidate T-junctions: per boundary edge (walk, position in walk), the boundary vertices
/// within `tolerance` × its length of it, with their parameters along it.
fn candidates(
    walks: &[Vec<u32>],
    positions: &[[f64; 3]],
    tolerance: f64,
) -> FxHashMap<EdgeKey, Vec<OnEdge>> {
    let mut found = FxHashMap::new();
    let edges: Vec<(u32, u32)> = walks
        .iter()
        .flat_map(|w| (0..w.len()).map(move |k| (w[k], w[(k + 1) % w.len()])))
        .collect();
    let cell = median_length(&edges, positions);
    if cell.is_nan() || cell <= 0.0 || tolerance <= 0.0 {
        return found;
    }
    let mut vertices: Vec<u32> = walks.iter().flatten().copied().collect();
    vertices.sort_unstable();
    vertices.dedup();
    let grid = VertexGrid::new(&vertices, positions, cell);
    let mut near = Vec::new();
    for (w, walk) in walks.iter().enumerate() {
        for k in 0..walk.len() {
            let (a, b) = (walk[k], walk[(k + 1) % walk.len()]);
            let (pa, pb) = (positions[a as usize], positions[b as usize]);
            let reach = tolerance * distance(pa, pb);
            grid.near_segment(pa, pb, reach, &mut near);
            let mut on: Vec<OnEdge> = near
                .iter()
                .filter(|&&v| v != a && v != b)
                .filter_map(|&v| {
                    foot_on_segment(positions[v as usize], pa, pb, reach)
                        .map(|(t, off)| (t, v, off / distance(pa, pb)))
                })
                .collect();
            if !on.is_empty() {
                on.sort_by(|x, y| x.0.total_cmp(&y.0));
                on.dedup_by_key(|x| x.1);
                found.insert((w, k), on);
            }
        }
    }
    found
}

fn undirected(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

/// The boundary edges of the walks in `group`, each split at its T-vertices, as
/// (walk, a, b); then those that meet an equal edge are glued in pairs and dropped.
fn stitch(
    walks: &[Vec<u32>],
    group: &[usize],
    splits: &FxHashMap<EdgeKey, Vec<u32>>,
) -> Vec<(usize, u32, u32)> {
    let mut pieces = Vec::new();
    for &w in group {
        let walk = &walks[w];
        for k in 0..walk.len() {
            let (a, b) = (walk[k], walk[(k + 1) % walk.len()]);
            let mut from = a;
            for &t in splits.get(&(w, k)).map(Vec::as_slice).unwrap_or(&[]) {
                pieces.push((w, from, t));
                from = t;
            }
            pieces.push((w, from, b));
        }
    }
    let mut count: FxHashMap<(u32, u32), usize> = FxHashMap::new();
    for &(_, a, b) in &pieces {
        *count.entry(undirected(a, b)).or_insert(0) += 1;
    }
    // An edge met an even number of times is glued away; an odd one leaves one piece.
    let mut kept: FxHashMap<(u32, u32), bool> = FxHashMap::new();
    pieces.retain(|&(_, a, b)| {
        let key = undirected(a, b);
        count[&key] % 2 == 1 && !std::mem::replace(kept.entry(key).or_insert(false), true)
    });
    pieces
}

/// Walks the pieces left after stitching into loops; at a vertex with several ways on,
/// keeps to the walk it came along where it can.
fn walk_pieces(pieces: &[(usize, u32, u32)]) -> Vec<(Vec<u32>, usize)> {
    let mut at_vertex: FxHashMap<u32, Vec<u32>> = FxHashMap::new();
    for (i, &(_, a, b)) in pieces.iter().enumerate() {
        at_vertex.entry(a).or_default().push(i as u32);
        at_vertex.entry(b).or_default().push(i as u32);
    }
    let mut used = vec![false; pieces.len()];
    let mut loops = Vec::new();
    for start in 0..pieces.len() {
        if used[start] {
            continue;
        }
        used[start] = true;
        let (walk, origin, mut at) = pieces[start];
        let mut current = walk;
        let mut cycle = vec![origin];
        while at != origin {
            let ways = &at_vertex[&at];
            let free = |i: &&u32| !used[**i as usize];
            let next = ways
                .iter()
                .filter(free)
                .find(|&&i| pieces[i as usize].0 == current)
                .or_else(|| ways.iter().find(free));
            let Some(&i) = next else {
                break;
            };
            used[i as usize] = true;
            cycle.push(at);
            let (w, p, q) = pieces[i as usize];
            current = w;
            at = if p == at { q } else { p };
        }
        loops.push((cycle, walk));
    }
    loops
}

/// Finds every T-junction of the boundary walks and stitches them. A candidate T-vertex
/// counts only where stitching glues one of its two pieces of the edge to another
/// boundary edge (a vertex merely near a border it is not joined to is no crack).
///
/// `facet_uses(a, b, t)`: whether the facet on boundary edge a–b has t as a corner (then t
/// lies on a–b only because that facet is flat there: a sliver, not a T-junction).
pub fn stitch_cracks(
    walks: &[Vec<u32>],
    positions: &[[f64; 3]],
    tolerance: f64,
    facet_uses: impl Fn(u32, u32, u32) -> bool,
) -> Stitched {
    let mut stitched_walk = vec![false; walks.len()];
    let found = candidates(walks, positions, tolerance);
    if found.is_empty() {
        return Stitched {
            stitched_walk,
            ..Default::default()
        };
    }
    let mut walk_of_vertex: FxHashMap<u32, Vec<usize>> = FxHashMap::new();
    for (w, walk) in walks.iter().enumerate() {
        for &v in walk {
            walk_of_vertex.entry(v).or_default().push(w);
        }
    }
    let group_of = |splits: &FxHashMap<EdgeKey, Vec<u32>>| {
        let mut group: Vec<usize> = Vec::new();
        for (&(w, _), ts) in splits {
            group.push(w);
            for t in ts {
                group.extend(&walk_of_vertex[t]);
            }
        }
        group.sort_unstable();
        group.dedup();
        group
    };
    // Each candidate is judged against the boundary as it is: a T-vertex counts on an edge
    // where one of its two pieces of the split edge is already a boundary edge (the other
    // side of the crack). A vertex that counts on several edges (collinear borders) is
    // kept on the one whose split glues most pieces, then the one it is closest to.
    let boundary: foldhash::HashSet<(u32, u32)> = walks
        .iter()
        .flat_map(|w| (0..w.len()).map(move |k| undirected(w[k], w[(k + 1) % w.len()])))
        .collect();
    let mut keys: Vec<EdgeKey> = found.keys().copied().collect();
    keys.sort_unstable();
    // Per vertex: (glued pieces, offset) of the best edge so far, and that edge.
    let mut best: FxHashMap<u32, ((usize, f64), EdgeKey)> = FxHashMap::new();
    for &key in &keys {
        let on = &found[&key];
        let walk = &walks[key.0];
        let (a, b) = (walk[key.1], walk[(key.1 + 1) % walk.len()]);
        let chain: Vec<u32> = std::iter::once(a)
            .chain(on.iter().map(|x| x.1))
            .chain(std::iter::once(b))
            .collect();
        let glued: Vec<bool> = chain
            .windows(2)
            .map(|w| boundary.contains(&undirected(w[0], w[1])))
            .collect();
        let score = glued.iter().filter(|&&g| g).count();
        for (i, &(_, v, off)) in on.iter().enumerate() {
            if !(glued[i] || glued[i + 1]) || facet_uses(a, b, v) {
                continue;
            }
            let better = best
                .get(&v)
                .is_none_or(|&((s, o), _)| score > s || (score == s && off < o));
            if better {
                best.insert(v, ((score, off), key));
            }
        }
    }
    let mut splits: FxHashMap<EdgeKey, Vec<u32>> = FxHashMap::new();
    let mut junctions = Vec::new();
    for &key in &keys {
        let confirmed: Vec<(u32, f64)> = found[&key]
            .iter()
            .filter(|x| best.get(&x.1).is_some_and(|&(_, k)| k == key))
            .map(|x| (x.1, x.2))
            .collect();
        if confirmed.is_empty() {
            continue;
        }
        let walk = &walks[key.0];
        let (a, b) = (walk[key.1], walk[(key.1 + 1) % walk.len()]);
        splits.insert(key, confirmed.iter().map(|x| x.0).collect());
        junctions.push(TJunction {
            a,
            b,
            t_vertices: confirmed.iter().map(|x| x.0).collect(),
            offset: confirmed.iter().map(|x| x.1).fold(0.0, f64::max),
        });
    }
    if splits.is_empty() {
        return Stitched {
            stitched_walk,
            ..Default::default()
        };
    }
    let group = group_of(&splits);
    for &w in &group {
        stitched_walk[w] = true;
    }
    let remaining = walk_pieces(&stitch(walks, &group, &splits));
    Stitched {
        junctions,
        remaining,
        stitched_walk,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fig. 22 as a loop: edge 1–0 of one facet, 0–2–1 of two others, 2 at its middle.
    #[test]
    fn an_isolated_t_junction_is_all_crack() {
        let positions = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
        let walks = vec![vec![1, 0, 2]];
        let s = stitch_cracks(&walks, &positions, 0.01, |_, _, _| false);
        assert_eq!(s.junctions.len(), 1);
        assert_eq!((s.junctions[0].a, s.junctions[0].b), (1, 0));
        assert_eq!(s.junctions[0].t_vertices, vec![2]);
        assert!(s.remaining.is_empty());
    }

    #[test]
    fn a_t_vertex_off_the_line_within_tolerance_counts_and_beyond_it_does_not() {
        for (off, expected) in [(0.004, 1), (0.02, 0)] {
            let positions = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, off, 0.0]];
            let s = stitch_cracks(&[vec![1, 0, 2]], &positions, 0.01, |_, _, _| false);
            assert_eq!(s.junctions.len(), expected, "offset {off}");
        }
    }

    #[test]
    fn a_t_junction_from_the_border_leaves_the_border_and_two_on_one_edge_count() {
        // A pentagonal border 1-2-3-6-0 and, from its vertex 0, a crack: edge 5→0 of one
        // facet beside 0→4→7→5 of two others (T-vertices 4 and 7 on the edge). The
        // half-edge walk merges both into one loop through 0 twice.
        let positions = [
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [2.0, 2.0, 0.0],
            [0.0, 2.0, 0.0],
            [0.25, 0.25, 0.0],
            [1.0, 1.0, 0.0],
            [-0.5, 1.0, 0.0],
            [0.6, 0.6, 0.0],
        ];
        let walks = vec![vec![1, 2, 3, 6, 0, 4, 7, 5, 0]];
        let s = stitch_cracks(&walks, &positions, 0.01, |_, _, _| false);
        assert_eq!(s.junctions.len(), 1);
        assert_eq!((s.junctions[0].a, s.junctions[0].b), (5, 0));
        assert_eq!(s.junctions[0].t_vertices, vec![7, 4]);
        assert_eq!(s.remaining.len(), 1);
        assert_eq!(s.remaining[0].0.len(), 5);
        let mut border = s.remaining[0].0.clone();
        border.sort_unstable();
        assert_eq!(border, vec![0, 1, 2, 3, 6]);
    }

    #[test]
    fn a_vertex_near_an_edge_it_is_not_joined_to_is_no_crack() {
        // Two separate triangles' borders; a corner of the second touches the first's edge.
        let positions = [
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [1.0, -1.0, 0.0],
            [1.0, 0.0, 0.0],
            [2.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let walks = vec![vec![0, 1, 2], vec![3, 4, 5]];
        let s = stitch_cracks(&walks, &positions, 0.01, |_, _, _| false);
        assert!(s.junctions.is_empty());
        assert!(s.stitched_walk.iter().all(|&x| !x));
    }
}
