//! The raw-polygon topology of the registered facets, computed from the registry alone (no
//! half-edge structure, so nothing is refused): which facet sides run each edge, fans of
//! facets at each vertex, edge-connected components, boundary loops, orientation.
//!
//! Definitions follow `fixtures/meshes/REFERENCE.json` (measured there by a raw-polygon
//! script and cross-checked with MeshLab and trimesh).

use super::disjoint_sets::DisjointSets;
use super::registry::EatRegistry;
use crate::mesh::io::repeated_vertex;

const NONE: u32 = u32::MAX;

/// One side of an edge: the facet, the corner the edge leaves from, and whether the facet
/// runs the edge from its smaller to its larger vertex id.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EdgeSide {
    pub facet: u32,
    pub corner: u32,
    pub forward: bool,
}

/// Everything the flaw locator and the statistics need, computed once.
#[derive(Debug, Clone)]
pub struct Structure {
    /// Edge sides grouped by edge: sides of edge `e` are `sides[side_offsets[e]..side_offsets[e+1]]`,
    /// each packed as its corner with the `forward` flag in the top bit (4 bytes a side:
    /// the structure of a 4M-triangle mesh is touched once per scan, memory is time).
    pub side_offsets: Vec<u32>,
    sides: Vec<u32>,
    /// Facet of each corner.
    pub corner_facet: Vec<u32>,
    /// The fan (a representative corner) each corner's facet belongs to at its vertex.
    pub corner_fan: Vec<u32>,
    /// Edge-connected component of each facet, numbered from 0 in facet order.
    pub facet_component: Vec<u32>,
    pub component_count: u32,
    /// Vertex ids (input ids) with more than one fan of facets.
    pub non_manifold_vertices: Vec<u32>,
    /// Number of fans at each non-manifold vertex (parallel to `non_manifold_vertices`).
    pub fans: Vec<u32>,
    /// Boundary loop (connected piece of the boundary-edge graph) of each edge, or NONE.
    pub edge_loop: Vec<u32>,
    pub boundary_loop_count: u32,
    /// Per component: consistently orientable (None where a non-manifold edge blocks the question).
    pub component_orientable: Vec<Option<bool>>,
}

const FORWARD: u32 = 1 << 31;

fn unpack(packed: u32, corner_facet: &[u32]) -> EdgeSide {
    let corner = packed & !FORWARD;
    EdgeSide {
        facet: corner_facet[corner as usize],
        corner,
        forward: packed & FORWARD != 0,
    }
}

impl Structure {
    /// The facet sides of edge `edge`.
    pub fn sides_of(&self, edge: usize) -> impl ExactSizeIterator<Item = EdgeSide> + '_ {
        self.sides[self.side_offsets[edge] as usize..self.side_offsets[edge + 1] as usize]
            .iter()
            .map(|&p| unpack(p, &self.corner_facet))
    }

    /// The first facet side of edge `edge` (every registered edge has one).
    pub fn first_side(&self, edge: usize) -> EdgeSide {
        unpack(
            self.sides[self.side_offsets[edge] as usize],
            &self.corner_facet,
        )
    }

    /// Computes the structure of everything registered so far. O(corners · α).
    pub fn of(registry: &EatRegistry) -> Structure {
        let (offsets, corners) = registry.facet_arrays();
        let corner_edge = registry.corner_edges();
        let edges = registry.edges();
        let facet_count = registry.facet_count();

        let mut corner_facet = vec![0u32; corners.len()];
        for f in 0..facet_count {
            corner_facet[offsets[f] as usize..offsets[f + 1] as usize].fill(f as u32);
        }

        // Edge sides, grouped by edge (counting sort: edge e has ec sides).
        let mut side_offsets = Vec::with_capacity(edges.len() + 1);
        side_offsets.push(0u32);
        for e in edges {
            side_offsets.push(side_offsets.last().unwrap() + e.ec);
        }
        assert!(corners.len() < FORWARD as usize, "more than 2^31 corners");
        let mut fill = side_offsets.clone();
        let mut sides = vec![0u32; *side_offsets.last().unwrap() as usize];
        for (k, &e) in corner_edge.iter().enumerate() {
            if e == NONE {
                continue;
            }
            let forward = if corners[k] == edges[e as usize].a {
                FORWARD
            } else {
                0
            };
            sides[fill[e as usize] as usize] = k as u32 | forward;
            fill[e as usize] += 1;
        }
        drop(fill);

        let layout = Layout {
            offsets,
            corners,
            corner_facet: &corner_facet,
            side_offsets: &side_offsets,
            sides: &sides,
        };
        // Fans (per corner) and components (per facet) are independent: side by side.
        let ((corner_fan, non_manifold_vertices, fans), components) = rayon::join(
            || fans_of(&layout, edges.len()),
            || components_of(&layout, edges, facet_count),
        );
        let (
            facet_component,
            component_count,
            edge_loop,
            boundary_loop_count,
            component_orientable,
        ) = components;

        Structure {
            side_offsets,
            sides,
            corner_facet,
            corner_fan,
            facet_component,
            component_count,
            non_manifold_vertices,
            fans,
            edge_loop,
            boundary_loop_count,
            component_orientable,
        }
    }
}

/// The arrays both halves of [`Structure::of`] read.
struct Layout<'a> {
    offsets: &'a [u32],
    corners: &'a [u32],
    corner_facet: &'a [u32],
    side_offsets: &'a [u32],
    sides: &'a [u32],
}

impl Layout<'_> {
    /// The corner after `k` in its facet.
    fn next_corner(&self, k: u32) -> u32 {
        let f = self.corner_facet[k as usize] as usize;
        if k + 1 == self.offsets[f + 1] {
            self.offsets[f]
        } else {
            k + 1
        }
    }

    fn sides_of(&self, e: usize) -> impl Iterator<Item = EdgeSide> + '_ {
        self.sides[self.side_offsets[e] as usize..self.side_offsets[e + 1] as usize]
            .iter()
            .map(|&p| unpack(p, self.corner_facet))
    }
}

/// Fans: corners at the same vertex joined through a shared edge at that vertex, and the
/// corners of one (degenerate) facet that repeat a vertex, since fans are of facets. Returns
/// each corner's fan (a representative corner) and the vertices with more than one fan,
/// with their fan counts.
fn fans_of(layout: &Layout, edge_count: usize) -> (Vec<u32>, Vec<u32>, Vec<u32>) {
    let corners = layout.corners;
    let mut corner_sets = DisjointSets::new(corners.len());
    for facet in layout.offsets.windows(2) {
        let range = facet[0]..facet[1];
        if repeated_vertex(&corners[range.start as usize..range.end as usize]).is_none() {
            continue;
        }
        // A degenerate facet (rare): its corners at one vertex, joined.
        let mut by_vertex: Vec<(u32, u32)> = range.map(|k| (corners[k as usize], k)).collect();
        by_vertex.sort_unstable();
        for w in by_vertex.windows(2).filter(|w| w[0].0 == w[1].0) {
            corner_sets.union(w[0].1, w[1].1);
        }
    }
    for e in 0..edge_count {
        let mut sides = layout.sides_of(e);
        let Some(first) = sides.next() else {
            continue;
        };
        let (fa, fb) = (first.corner, layout.next_corner(first.corner));
        let (first_a, first_b) = if first.forward { (fa, fb) } else { (fb, fa) };
        for side in sides {
            let (ka, kb) = (side.corner, layout.next_corner(side.corner));
            let (at_a, at_b) = if side.forward { (ka, kb) } else { (kb, ka) };
            corner_sets.union(first_a, at_a);
            corner_sets.union(first_b, at_b);
        }
    }
    let max_vertex = corners.iter().copied().max().map_or(0, |m| m as usize + 1);
    let corner_fan = corner_sets.into_roots();
    let mut first_root = vec![NONE; max_vertex];
    let mut fan_roots: std::collections::BTreeMap<u32, Vec<u32>> = Default::default();
    for (k, &v) in corners.iter().enumerate() {
        let root = corner_fan[k];
        let first = &mut first_root[v as usize];
        if *first == NONE {
            *first = root;
        } else if *first != root {
            let roots = fan_roots.entry(v).or_insert_with(|| vec![*first]);
            if !roots.contains(&root) {
                roots.push(root);
            }
        }
    }
    let (non_manifold_vertices, fans) = fan_roots
        .into_iter()
        .map(|(v, r)| (v, r.len() as u32))
        .unzip();
    (corner_fan, non_manifold_vertices, fans)
}

/// Components (facets joined through shared edges), boundary loops (pieces of the graph
/// of one-sided edges) and orientability per component.
#[allow(clippy::type_complexity)]
fn components_of(
    layout: &Layout,
    edges: &[super::registry::EdgeItem],
    facet_count: usize,
) -> (Vec<u32>, u32, Vec<u32>, u32, Vec<Option<bool>>) {
    let mut facet_sets = DisjointSets::new(facet_count);
    for e in 0..edges.len() {
        let mut sides = layout.sides_of(e);
        let Some(first) = sides.next() else {
            continue;
        };
        for side in sides {
            facet_sets.union(first.facet, side.facet);
        }
    }
    let mut facet_component = vec![NONE; facet_count];
    let mut label = vec![NONE; facet_count];
    let mut component_count = 0;
    for (f, component) in facet_component.iter_mut().enumerate() {
        let r = facet_sets.find(f as u32) as usize;
        if label[r] == NONE {
            label[r] = component_count;
            component_count += 1;
        }
        *component = label[r];
    }
    let max_vertex = layout
        .corners
        .iter()
        .copied()
        .max()
        .map_or(0, |m| m as usize + 1);
    let mut vertex_sets = DisjointSets::new(max_vertex);
    for e in edges.iter().filter(|e| e.ec == 1) {
        vertex_sets.union(e.a, e.b);
    }
    let mut loop_label = vec![NONE; max_vertex];
    let mut boundary_loop_count = 0;
    let edge_loop = edges
        .iter()
        .map(|e| {
            if e.ec != 1 {
                return NONE;
            }
            let r = vertex_sets.find(e.a) as usize;
            if loop_label[r] == NONE {
                loop_label[r] = boundary_loop_count;
                boundary_loop_count += 1;
            }
            loop_label[r]
        })
        .collect();
    let component_orientable = orientability(
        facet_count,
        &facet_component,
        component_count,
        layout.side_offsets,
        layout.sides,
        layout.corner_facet,
    );
    (
        facet_component,
        component_count,
        edge_loop,
        boundary_loop_count,
        component_orientable,
    )
}

/// Whether each component's facets can be flipped to agree across every two-sided edge:
/// union–find with a parity bit ("flip relative to the root"); two facets running an edge
/// the same way must differ in flip, and a contradiction makes the component
/// non-orientable. None for components with an edge of three or more sides.
fn orientability(
    facet_count: usize,
    facet_component: &[u32],
    component_count: u32,
    side_offsets: &[u32],
    sides: &[u32],
    corner_facet: &[u32],
) -> Vec<Option<bool>> {
    let mut result = vec![Some(true); component_count as usize];
    let mut flips = ParitySets::new(facet_count);
    for e in 0..side_offsets.len() - 1 {
        let packed = &sides[side_offsets[e] as usize..side_offsets[e + 1] as usize];
        let s: [EdgeSide; 2] = match packed.len() {
            2 => [
                unpack(packed[0], corner_facet),
                unpack(packed[1], corner_facet),
            ],
            n if n > 2 => {
                let c = facet_component[unpack(packed[0], corner_facet).facet as usize];
                result[c as usize] = None;
                continue;
            }
            _ => continue,
        };
        {
            {
                let differ = s[0].forward == s[1].forward;
                if !flips.union(s[0].facet, s[1].facet, differ) {
                    let c = facet_component[s[0].facet as usize] as usize;
                    if result[c].is_some() {
                        result[c] = Some(false);
                    }
                }
            }
        }
    }
    result
}

/// Union–find whose elements carry a parity relative to their root.
struct ParitySets {
    parent: Vec<u32>,
    parity: Vec<bool>,
}

impl ParitySets {
    fn new(n: usize) -> Self {
        ParitySets {
            parent: (0..n as u32).collect(),
            parity: vec![false; n],
        }
    }

    /// Root of `i` and the parity of `i` relative to it (with path compression).
    fn find(&mut self, i: u32) -> (u32, bool) {
        let (mut root, mut total) = (i, false);
        while self.parent[root as usize] != root {
            total ^= self.parity[root as usize];
            root = self.parent[root as usize];
        }
        // Second pass: point the path at the root with each node's parity to the root.
        let (mut x, mut acc) = (i, total);
        while self.parent[x as usize] != root && x != root {
            let (next, old) = (self.parent[x as usize], self.parity[x as usize]);
            self.parent[x as usize] = root;
            self.parity[x as usize] = acc;
            acc ^= old;
            x = next;
        }
        (root, total)
    }

    /// Records that `a` and `b` differ in parity (`differ`) or agree; false on a contradiction.
    fn union(&mut self, a: u32, b: u32, differ: bool) -> bool {
        let ((ra, pa), (rb, pb)) = (self.find(a), self.find(b));
        if ra == rb {
            return (pa ^ pb) == differ;
        }
        self.parent[rb as usize] = ra;
        self.parity[rb as usize] = pa ^ pb ^ differ;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn registry(faces: &[&[u32]]) -> EatRegistry {
        let mut r = EatRegistry::new();
        for f in faces {
            r.register_facet(f);
        }
        r
    }

    #[test]
    fn bow_tie_has_one_pinch_vertex_and_one_boundary_loop() {
        let r = registry(&[&[0, 1, 2], &[0, 3, 4]]);
        let s = Structure::of(&r);
        assert_eq!(s.non_manifold_vertices, vec![0]);
        assert_eq!(s.fans, vec![2]);
        assert_eq!(s.component_count, 2);
        assert_eq!(s.boundary_loop_count, 1);
    }

    #[test]
    fn a_facet_repeating_a_vertex_is_one_fan_there() {
        // One facet is one fan of facets, however often it holds the vertex: small facets
        // (by pairs) and large ones (sorted) alike.
        let mut large: Vec<u32> = (0..40).collect();
        large.push(7);
        for facet in [vec![0, 1, 2, 0], vec![0, 0, 1], vec![0, 1, 0, 2], large] {
            let s = Structure::of(&registry(&[&facet]));
            assert!(s.non_manifold_vertices.is_empty(), "{facet:?}");
        }
        // Beside a facet that touches it only there, the vertex is a pinch again.
        let s = Structure::of(&registry(&[&[0, 1, 2, 0], &[0, 3, 4]]));
        assert_eq!((s.non_manifold_vertices, s.fans), (vec![0], vec![2]));
    }

    #[test]
    fn moebius_strip_is_not_orientable() {
        // A strip of 5 quads whose ends are glued with a half twist.
        let r = registry(&[
            &[0, 1, 6, 5],
            &[1, 2, 7, 6],
            &[2, 3, 8, 7],
            &[3, 4, 9, 8],
            &[4, 5, 0, 9],
        ]);
        let s = Structure::of(&r);
        assert_eq!(s.component_count, 1);
        assert_eq!(s.component_orientable, vec![Some(false)]);
        assert_eq!(s.boundary_loop_count, 1);
        assert!(s.non_manifold_vertices.is_empty());
    }

    #[test]
    fn parity_sets_find_contradictions() {
        let mut p = ParitySets::new(4);
        assert!(p.union(0, 1, true));
        assert!(p.union(1, 2, true));
        assert!(p.union(0, 2, false));
        assert!(!p.union(2, 0, true));
        assert!(p.union(3, 0, true));
        assert!(p.find(3).1 ^ p.find(2).1);
    }

    #[test]
    fn cube_is_orientable_and_closed() {
        let r = registry(&[
            &[0, 1, 3, 2],
            &[2, 3, 5, 4],
            &[4, 5, 7, 6],
            &[6, 7, 1, 0],
            &[1, 7, 5, 3],
            &[6, 0, 2, 4],
        ]);
        let s = Structure::of(&r);
        assert_eq!(s.component_orientable, vec![Some(true)]);
        assert_eq!(s.boundary_loop_count, 0);
    }
}
