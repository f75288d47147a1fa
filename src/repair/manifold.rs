//! Non-manifold edges and vertices: the facets on an edge of three or more sides are paired
//! (facets running it in opposite directions first), and at each vertex the facets joined
//! through manifold edges and those pairs form fans; every fan but the first (the one with
//! the earliest facet) gets its own copy of the vertex. A fin on an edge, or a facet
//! touching the surface at one vertex, comes apart from it; two sheets crossing at an
//! edge become two sheets.

use foldhash::{HashMap as FxHashMap, HashMapExt, HashSet as FxHashSet};

use super::change::{Action, Change};
use super::editable::Editable;
use crate::topology::disjoint_sets::DisjointSets;
use crate::topology::{show_ids, FlawKind};

/// A fan at a vertex: its root in the disjoint sets, and its corners.
type Fan = (u32, Vec<u32>);

/// One side of an edge: the facet's corner at the edge's smaller vertex and at the larger,
/// and whether it runs from the smaller to the larger.
#[derive(Clone, Copy)]
struct Side {
    at_lo: u32,
    at_hi: u32,
    forward: bool,
}

/// Pairs the sides of a non-manifold edge: opposite directions first, in facet order.
fn pair_sides(sides: &[Side]) -> Vec<(usize, usize)> {
    let mut free: Vec<usize> = (0..sides.len()).collect();
    let mut pairs = Vec::new();
    while let Some(i) = free.first().copied() {
        free.remove(0);
        let partner = free
            .iter()
            .position(|&j| sides[j].forward != sides[i].forward)
            .or(if free.is_empty() { None } else { Some(0) });
        if let Some(p) = partner {
            pairs.push((i, free.remove(p)));
        }
    }
    pairs
}

/// Splits vertices into one copy per fan. `edges`: split at the ends of non-manifold
/// edges; `vertices`: split where fans meet at a vertex only.
pub fn split_fans(mesh: &mut Editable, edges: bool, vertices: bool, changes: &mut Vec<Change>) {
    // Corners of the live facets, numbered.
    let mut corner_of: Vec<(u32, usize)> = Vec::new();
    let mut first_corner = vec![u32::MAX; mesh.faces.len()];
    for (f, c) in mesh.faces.iter().enumerate() {
        if let Some(c) = c {
            first_corner[f] = corner_of.len() as u32;
            corner_of.extend((0..c.len()).map(|i| (f as u32, i)));
        }
    }
    let mut by_edge: FxHashMap<(u32, u32), Vec<Side>> = FxHashMap::new();
    for e in mesh.edges() {
        let base = first_corner[e.facet as usize];
        let (kp, kq) = (base + e.corner as u32, base + e.next_corner as u32);
        let forward = e.from < e.to;
        let (at_lo, at_hi) = if forward { (kp, kq) } else { (kq, kp) };
        by_edge
            .entry((e.from.min(e.to), e.from.max(e.to)))
            .or_default()
            .push(Side {
                at_lo,
                at_hi,
                forward,
            });
    }
    let mut sets = DisjointSets::new(corner_of.len());
    let mut nm_ends: FxHashSet<u32> = FxHashSet::default();
    for (&(lo, hi), sides) in &by_edge {
        let pairs = if sides.len() <= 2 || !edges {
            (1..sides.len()).map(|j| (0, j)).collect()
        } else {
            nm_ends.insert(lo);
            nm_ends.insert(hi);
            pair_sides(sides)
        };
        for (i, j) in pairs {
            sets.union(sides[i].at_lo, sides[j].at_lo);
            sets.union(sides[i].at_hi, sides[j].at_hi);
        }
    }
    // Per vertex: its fans (root → corners), the first kept.
    let mut fans: FxHashMap<u32, Vec<Fan>> = FxHashMap::new();
    for (k, &(f, i)) in corner_of.iter().enumerate() {
        let v = mesh.faces[f as usize].as_ref().map_or(0, |c| c[i]);
        let root = sets.find(k as u32);
        let list = fans.entry(v).or_default();
        match list.iter_mut().find(|(r, _)| *r == root) {
            Some((_, ks)) => ks.push(k as u32),
            None => list.push((root, vec![k as u32])),
        }
    }
    let mut split: Vec<(u32, Vec<Fan>)> = fans.into_iter().filter(|(_, l)| l.len() > 1).collect();
    split.sort_unstable_by_key(|(v, _)| *v);
    for (v, mut list) in split {
        let at_edge = nm_ends.contains(&v);
        if !(at_edge || vertices) {
            continue;
        }
        list.sort_unstable_by_key(|(_, ks)| ks.iter().map(|&k| corner_of[k as usize].0).min());
        for (_, ks) in list.into_iter().skip(1) {
            let copy = mesh.add_vertex(mesh.positions[v as usize], Some(v));
            let mut facets: Vec<u32> = Vec::new();
            for k in ks {
                let (f, i) = corner_of[k as usize];
                if let Some(c) = mesh.faces[f as usize].as_mut() {
                    c[i] = copy;
                }
                facets.push(f);
            }
            facets.sort_unstable();
            facets.dedup();
            changes.push(Change::new(
                if at_edge {
                    FlawKind::NonManifoldEdge
                } else {
                    FlawKind::NonManifoldVertex
                },
                Action::SplitVertex,
                facets.clone(),
                vec![v, copy],
                format!(
                    "facets {} get vertex {copy}, a copy of vertex {v}, as their own fan",
                    show_ids(&facets)
                ),
            ));
        }
    }
}
