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

/// Boundary vertices grouped by position (equal coordinates, bit for bit). The vertices of a
/// group lie on the same edges at the same parameter, so an edge's candidates are sought
/// among positions first: a pile of coincident vertices is one position to test.
struct PositionGroups<'a> {
    /// The boundary vertices, sorted, and the group of each.
    vertices: &'a [u32],
    group: Vec<u32>,
    /// The coordinates of each group.
    at: Vec<[f64; 3]>,
}

impl<'a> PositionGroups<'a> {
    fn new(vertices: &'a [u32], positions: &[[f64; 3]]) -> Self {
        let mut index: FxHashMap<[u64; 3], u32> = FxHashMap::with_capacity(vertices.len());
        let mut at = Vec::new();
        let group = vertices
            .iter()
            .map(|&v| {
                let p = positions[v as usize];
                *index.entry(p.map(f64::to_bits)).or_insert_with(|| {
                    at.push(p);
                    (at.len() - 1) as u32
                })
            })
            .collect();
        PositionGroups {
            vertices,
            group,
            at,
        }
    }

    /// The group of boundary vertex `v`.
    fn of(&self, v: u32) -> u32 {
        self.group[self.vertices.partition_point(|&u| u < v)]
    }
}

/// Whether `hit(i)` holds for an index i of `sorted` (ordered by `key`) whose key is in
/// `keys` (sorted): walks the shorter of the two lists and searches the other.
fn any_keyed_in<T>(
    sorted: &[T],
    key: impl Fn(&T) -> u32,
    keys: &[u32],
    mut hit: impl FnMut(usize) -> bool,
) -> bool {
    if sorted.len() <= keys.len() {
        (0..sorted.len()).any(|i| keys.binary_search(&key(&sorted[i])).is_ok() && hit(i))
    } else {
        keys.iter().any(|&k| {
            let from = sorted.partition_point(|x| key(x) < k);
            (from..sorted.len())
                .take_while(|&i| key(&sorted[i]) == k)
                .any(&mut hit)
        })
    }
}

/// The boundary edges by position group, to tell without listing an edge's candidates
/// whether one of them could be confirmed as a T-vertex of it. A confirmed T-vertex has a
/// boundary edge to a neighbour in the edge's chain (an end of the edge or another
/// candidate: glued), and the facet on the edge does not use it.
struct Joins {
    /// Per group p, the groups q joined to it by a boundary edge, sorted:
    /// `pair_q[group_start[p]..group_start[p + 1]]`; per such pair i, the vertices of p on
    /// such an edge: `pair_v[pair_start[i]..pair_start[i + 1]]`.
    group_start: Vec<u32>,
    pair_q: Vec<u32>,
    pair_start: Vec<u32>,
    pair_v: Vec<u32>,
    /// Every boundary vertex's neighbours along boundary edges as (vertex, group of the
    /// neighbour, neighbour), sorted.
    neighbours: Vec<(u32, u32, u32)>,
}

impl Joins {
    /// From the walks' edges (a, b).
    fn new(edges: &[(u32, u32)], groups: &PositionGroups) -> Self {
        let mut boundary: Vec<(u32, u32)> = edges.iter().map(|&(a, b)| undirected(a, b)).collect();
        boundary.sort_unstable();
        boundary.dedup();
        let mut triples: Vec<(u32, u32, u32)> = Vec::with_capacity(2 * boundary.len());
        let mut neighbours: Vec<(u32, u32, u32)> = Vec::with_capacity(2 * boundary.len());
        for &(x, y) in &boundary {
            let (gx, gy) = (groups.of(x), groups.of(y));
            for (v, gv, u, gu) in [(x, gx, y, gy), (y, gy, x, gx)] {
                triples.push((gv, gu, v));
                neighbours.push((v, gu, u));
            }
        }
        triples.sort_unstable();
        triples.dedup();
        neighbours.sort_unstable();
        neighbours.dedup();
        let mut group_start = vec![0u32; groups.at.len() + 1];
        let (mut pair_q, mut pair_start, mut pair_v) = (Vec::new(), Vec::new(), Vec::new());
        let mut last = None;
        for &(p, q, v) in &triples {
            if last != Some((p, q)) {
                group_start[p as usize + 1] += 1;
                pair_q.push(q);
                pair_start.push(pair_v.len() as u32);
                last = Some((p, q));
            }
            pair_v.push(v);
        }
        pair_start.push(pair_v.len() as u32);
        for p in 0..groups.at.len() {
            group_start[p + 1] += group_start[p];
        }
        Joins {
            group_start,
            pair_q,
            pair_start,
            pair_v,
            neighbours,
        }
    }

    /// The neighbours of `v` along boundary edges, as (v, group, neighbour), by group.
    fn neighbours_of(&self, v: u32) -> &[(u32, u32, u32)] {
        let from = self.neighbours.partition_point(|x| x.0 < v);
        let to = from + self.neighbours[from..].partition_point(|x| x.0 == v);
        &self.neighbours[from..to]
    }

    /// Whether boundary edge a–b, whose candidates are the vertices of the groups `on`
    /// (sorted), may have a confirmed T-vertex: false only where none can, because no
    /// candidate that the edge's facet does not use is joined by a boundary edge to a, to b
    /// or to another candidate.
    fn may_confirm(
        &self,
        a: u32,
        b: u32,
        on: &[u32],
        facet_uses: &impl Fn(u32, u32, u32) -> bool,
    ) -> bool {
        let free = |v: u32| !facet_uses(a, b, v);
        let to_an_end = [a, b].iter().any(|&end| {
            let list = self.neighbours_of(end);
            any_keyed_in(list, |x| x.1, on, |i| free(list[i].2))
        });
        to_an_end
            || on.iter().any(|&p| {
                let (from, to) = (
                    self.group_start[p as usize] as usize,
                    self.group_start[p as usize + 1] as usize,
                );
                let joined = &self.pair_q[from..to];
                any_keyed_in(
                    joined,
                    |&q| q,
                    on,
                    |i| {
                        let pair = from + i;
                        let (s, e) = (
                            self.pair_start[pair] as usize,
                            self.pair_start[pair + 1] as usize,
                        );
                        self.pair_v[s..e].iter().any(|&v| free(v))
                    },
                )
            })
    }
}

/// Median of the boundary edges' lengths (0 for none).
/// The walks' edges, the grid's cell (their median length) and their vertices, sorted:
/// what the candidate search starts from. `None` when no edge has a length or the
/// tolerance is not positive (no candidate then).
struct BoundaryScale {
    edges: Vec<(u32, u32)>,
    cell: f64,
    vertices: Vec<u32>,
}

impl BoundaryScale {
    fn of(walks: &[Vec<u32>], positions: &[[f64; 3]], tolerance: f64) -> Option<Self> {
        let edges: Vec<(u32, u32)> = walks
            .iter()
            .flat_map(|w| (0..w.len()).map(move |k| (w[k], w[(k + 1) % w.len()])))
            .collect();
        let cell = median_length(&edges, positions);
        if cell.is_nan() || cell <= 0.0 || tolerance <= 0.0 {
            return None;
        }
        let mut vertices: Vec<u32> = walks.iter().flatten().copied().collect();
        vertices.sort_unstable();
        vertices.dedup();
        Some(BoundaryScale {
            edges,
            cell,
            vertices,
        })
    }
}

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
/// within `tolerance` × its length of it, with their parameters along it — on the edges
/// where one of them may be confirmed. A candidate is confirmed only where it is glued to a
/// neighbour in the edge's chain and the edge's facet does not use it; an edge without a
/// candidate that could be both is left out, as [`stitch_found`] would confirm nothing on
/// it (and what it confirms elsewhere does not depend on it).
///
/// The edges are first tested against the positions of the boundary vertices, then listed
/// vertex by vertex only where [`Joins::may_confirm`] allows a confirmed T-vertex: thousands
/// of coincident boundary vertices on thousands of coincident edges (a pile of degenerate
/// facets) cost a test per edge, not a candidate per vertex and edge.
fn candidates(
    walks: &[Vec<u32>],
    positions: &[[f64; 3]],
    tolerance: f64,
    facet_uses: &impl Fn(u32, u32, u32) -> bool,
) -> FxHashMap<EdgeKey, Vec<OnEdge>> {
    let mut found = FxHashMap::new();
    let Some(BoundaryScale {
        edges,
        cell,
        vertices,
    }) = BoundaryScale::of(walks, positions, tolerance)
    else {
        return found;
    };
    let groups = PositionGroups::new(&vertices, positions);
    let group_ids: Vec<u32> = (0..groups.at.len() as u32).collect();
    // The same cells as the vertices' grid below, so the same positions come near an edge.
    let group_grid = VertexGrid::new(&group_ids, &groups.at, cell);
    // Both built at the first edge that needs them (most meshes have no candidate at all).
    let mut joins: Option<Joins> = None;
    let mut vertex_grid: Option<VertexGrid> = None;
    let (mut near, mut on_groups) = (Vec::new(), Vec::new());
    for (w, walk) in walks.iter().enumerate() {
        for k in 0..walk.len() {
            let (a, b) = (walk[k], walk[(k + 1) % walk.len()]);
            let (pa, pb) = (positions[a as usize], positions[b as usize]);
            let reach = tolerance * distance(pa, pb);
            // The positions on the edge: a vertex is a candidate exactly where its position
            // is (the edge's ends are never, being within `reach` of themselves).
            group_grid.near_segment(pa, pb, reach, &mut near);
            on_groups.clear();
            on_groups.extend(
                near.iter()
                    .copied()
                    .filter(|&g| foot_on_segment(groups.at[g as usize], pa, pb, reach).is_some()),
            );
            if on_groups.is_empty() {
                continue;
            }
            on_groups.sort_unstable();
            let built = joins.get_or_insert_with(|| Joins::new(&edges, &groups));
            if !built.may_confirm(a, b, &on_groups, facet_uses) {
                continue;
            }
            let grid =
                vertex_grid.get_or_insert_with(|| VertexGrid::new(&vertices, positions, cell));
            let on = on_edge(grid, positions, (a, b), reach, &mut near);
            if !on.is_empty() {
                found.insert((w, k), on);
            }
        }
    }
    found
}

/// The boundary vertices of `grid` within `reach` of edge a–b's inside, other than its ends,
/// by their place along it, each once: the edge's candidates.
fn on_edge(
    grid: &VertexGrid,
    positions: &[[f64; 3]],
    (a, b): (u32, u32),
    reach: f64,
    near: &mut Vec<u32>,
) -> Vec<OnEdge> {
    let (pa, pb) = (positions[a as usize], positions[b as usize]);
    grid.near_segment(pa, pb, reach, near);
    let mut on: Vec<OnEdge> = near
        .iter()
        .filter(|&&v| v != a && v != b)
        .filter_map(|&v| {
            foot_on_segment(positions[v as usize], pa, pb, reach)
                .map(|(t, off)| (t, v, off / distance(pa, pb)))
        })
        .collect();
    on.sort_by(|x, y| x.0.total_cmp(&y.0));
    on.dedup_by_key(|x| x.1);
    on
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
    let found = candidates(walks, positions, tolerance, &facet_uses);
    stitch_found(walks, &found, facet_uses)
}

/// The undirected edges of the walks.
fn boundary_edges(walks: &[Vec<u32>]) -> foldhash::HashSet<(u32, u32)> {
    walks
        .iter()
        .flat_map(|w| (0..w.len()).map(move |k| undirected(w[k], w[(k + 1) % w.len()])))
        .collect()
}

/// [`stitch_cracks`] once the candidates are `found`.
fn stitch_found(
    walks: &[Vec<u32>],
    found: &FxHashMap<EdgeKey, Vec<OnEdge>>,
    facet_uses: impl Fn(u32, u32, u32) -> bool,
) -> Stitched {
    let mut stitched_walk = vec![false; walks.len()];
    if found.is_empty() {
        return Stitched {
            stitched_walk,
            ..Default::default()
        };
    }
    let boundary = boundary_edges(walks);
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
    use rand::rngs::StdRng;
    use rand::{Rng, SeedableRng};

    /// The candidates as first written: every vertex near every edge, listed (quadratic on
    /// piles of coincident vertices) — the oracle the filtered search must agree with.
    fn candidates_by_listing(
        walks: &[Vec<u32>],
        positions: &[[f64; 3]],
        tolerance: f64,
    ) -> FxHashMap<EdgeKey, Vec<OnEdge>> {
        let mut found = FxHashMap::new();
        let Some(BoundaryScale { cell, vertices, .. }) =
            BoundaryScale::of(walks, positions, tolerance)
        else {
            return found;
        };
        let grid = VertexGrid::new(&vertices, positions, cell);
        let mut near = Vec::new();
        for (w, walk) in walks.iter().enumerate() {
            for k in 0..walk.len() {
                let (a, b) = (walk[k], walk[(k + 1) % walk.len()]);
                let (pa, pb) = (positions[a as usize], positions[b as usize]);
                let reach = tolerance * distance(pa, pb);
                let on = on_edge(&grid, positions, (a, b), reach, &mut near);
                if !on.is_empty() {
                    found.insert((w, k), on);
                }
            }
        }
        found
    }

    /// Walks of 3 to 6 vertices on a small lattice of points (on lines, at midpoints, a
    /// hair off them), many vertices coincident: T-junctions, piles and ties everywhere.
    /// `facet_uses` as if each walk were the border of one facet.
    #[test]
    fn the_filtered_search_stitches_what_listing_every_candidate_stitches() {
        let mut rng = StdRng::seed_from_u64(0xc4ac);
        let (mut junctions, mut ties, mut left_out) = (0, 0, 0);
        for case in 0..3000 {
            let points: Vec<[f64; 3]> = (0..rng.random_range(3..12))
                .map(|_| {
                    let hair = if rng.random_bool(0.2) { 0.003 } else { 0.0 };
                    [
                        f64::from(rng.random_range(0..5u8)) * 0.5,
                        f64::from(rng.random_range(0..3u8)) + hair,
                        if rng.random_bool(0.1) { 1.0 } else { 0.0 },
                    ]
                })
                .collect();
            let positions: Vec<[f64; 3]> = (0..rng.random_range(4..40))
                .map(|_| points[rng.random_range(0..points.len())])
                .collect();
            let n = positions.len() as u32;
            let walks: Vec<Vec<u32>> = (0..rng.random_range(1..12))
                .map(|_| {
                    let len = rng.random_range(3..7usize).min(n as usize);
                    let mut walk: Vec<u32> = Vec::new();
                    while walk.len() < len {
                        let v = rng.random_range(0..n);
                        if !walk.contains(&v) {
                            walk.push(v);
                        }
                    }
                    walk
                })
                .collect();
            let facet_uses = |a: u32, b: u32, t: u32| {
                walks.iter().any(|w| {
                    let m = w.len();
                    w.contains(&t)
                        && (0..m).any(|k| undirected(w[k], w[(k + 1) % m]) == undirected(a, b))
                })
            };
            for tolerance in [0.01, 0.2] {
                let listed = candidates_by_listing(&walks, &positions, tolerance);
                let filtered = candidates(&walks, &positions, tolerance, &facet_uses);
                // The filtered edges are listed exactly as before; only edges are left out.
                for (key, on) in &filtered {
                    assert_eq!(Some(on), listed.get(key), "case {case}");
                }
                left_out += listed.len() - filtered.len();
                ties += listed
                    .values()
                    .filter(|on| on.windows(2).any(|w| w[0].0 == w[1].0))
                    .count();
                let old = stitch_found(&walks, &listed, facet_uses);
                let new = stitch_cracks(&walks, &positions, tolerance, facet_uses);
                assert_eq!(new.junctions, old.junctions, "case {case}");
                assert_eq!(new.remaining, old.remaining, "case {case}");
                assert_eq!(new.stitched_walk, old.stitched_walk, "case {case}");
                junctions += new.junctions.len();
            }
        }
        // The cases exercise what they are for.
        assert!(
            junctions > 1000 && ties > 1000 && left_out > 1000,
            "{junctions} junctions, {ties} ties, {left_out} edges left out"
        );
    }

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
