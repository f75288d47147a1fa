//! EAT-TA: the registry of Liu et al. (2020) §3.2–3.3 — Facet, Edge and Vertex lists with
//! their counters, fed facet by facet.
//!
//! Readings of the paper chosen here (see `DESIGN.md`: the reading that makes the method
//! correct):
//! - `vc` counts the *edges* at a vertex, as §3.2 defines it, not the facets (Fig. 7's
//!   pseudocode increments it per facet, which differs on a boundary). It grows when a new
//!   edge at the vertex is registered.
//! - `ec` counts the facet *sides* on an edge (a facet running an edge twice counts twice).
//! - `fc` counts the facets with the same vertex set; every facet record still counts in
//!   F (a duplicated facet is a flaw to report, and F, E, V describe the file as written).
//! - Edges with both ends at the same vertex (a repeated corner) are not edges.

use foldhash::HashMap;

use crate::error::{Error, Result};
use crate::limits::{human_bytes, MemoryBudget};

/// A registered vertex: its input id and `vc`, the number of edges at it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct VertexItem {
    pub id: u32,
    pub vc: u32,
}

/// A registered edge (vertex ids with `a < b`): `ec` facet sides in all, `forward` of them
/// running a→b. `first_facet` is the facet that registered it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EdgeItem {
    pub a: u32,
    pub b: u32,
    pub ec: u32,
    pub forward: u32,
    pub first_facet: u32,
}

impl EdgeItem {
    /// Two facets that run the edge the same way (their orientations disagree).
    pub fn inconsistent(&self) -> bool {
        self.ec == 2 && (self.forward == 2 || self.forward == 0)
    }
}

/// What registering one facet did (the paper's per-facet output, Fig. 14/20/23/24).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FacetRegistration {
    /// The facet's index in the Facet list (its fID).
    pub facet: u32,
    /// `fc` of the facet's vertex set after this registration.
    pub fc: u32,
    /// The vIDs (Vertex-list positions) of the facet's corners.
    pub vertex_slots: Vec<u32>,
    /// The eIDs (Edge-list positions) of the facet's edges, in corner order.
    pub edge_slots: Vec<u32>,
}

const NONE: u32 = u32::MAX;

/// The three lists with counters. Facets are identified by registration order; vertices
/// by input id (every id seen gets a Vertex item on first use).
///
/// Look-ups go through per-vertex chains rather than hash tables: the edges whose smaller
/// end is `v` and the vertex sets whose smallest vertex is `v` are linked lists threaded
/// through arrays, a few entries long, that stay in cache for meshes written in any
/// sensible order (a hash table of millions of edges misses the cache on every facet).
#[derive(Debug, Default, Clone)]
pub struct EatRegistry {
    /// Vertex-list position of each input vertex id, or `u32::MAX` before its first use.
    slot_of_vertex: Vec<u32>,
    vertices: Vec<VertexItem>,
    edges: Vec<EdgeItem>,
    /// First edge whose smaller end is the vertex (by input id), and the next such edge.
    edge_head: Vec<u32>,
    edge_next: Vec<u32>,
    /// Facet list: corners as offsets + indices, and the facet's distinct-set id.
    facet_offsets: Vec<u32>,
    facet_corners: Vec<u32>,
    facet_set: Vec<u32>,
    /// Edge-list position of the edge leaving each corner (`u32::MAX` where the next corner
    /// repeats the vertex), parallel to `facet_corners`.
    corner_edge: Vec<u32>,
    /// Distinct vertex sets: the first set whose smallest vertex is the vertex (by input
    /// id), the next such set, a facet that has the set, and `fc` per set.
    set_head: Vec<u32>,
    set_next: Vec<u32>,
    set_facet: Vec<u32>,
    fc: Vec<u32>,
    /// Length of each vertex's edge and set chain. A vertex whose chain passes
    /// `HUB_CHAIN` (the centre of a fan of a million triangles) is looked up through
    /// `hub_edges` / `hub_sets` instead, which keeps registration linear on any input.
    edge_chain: Vec<u32>,
    set_chain: Vec<u32>,
    hub_edges: HashMap<u64, u32>,
    hub_sets: HashMap<Vec<u32>, u32>,
}

/// Bytes kept per vertex id up to the largest id seen: the five arrays indexed by id
/// (`slot_of_vertex`, `edge_head`, `set_head`, `edge_chain`, `set_chain`, a `u32` each).
pub const BYTES_PER_VERTEX_ID: u64 = 20;

/// Chain length past which a vertex's edges and vertex sets are also kept in hash maps.
const HUB_CHAIN: u32 = 32;

/// The key of edge {lo, hi} in `hub_edges`.
fn edge_key(lo: u32, hi: u32) -> u64 {
    (u64::from(lo) << 32) | u64::from(hi)
}

/// A vertex set's key in `hub_sets`: its distinct vertices, sorted.
fn set_key(corners: &[u32]) -> Vec<u32> {
    let mut key = corners.to_vec();
    key.sort_unstable();
    key.dedup();
    key
}

/// Whether two corner lists have the same vertex set.
fn same_vertex_set(a: &[u32], b: &[u32]) -> bool {
    a.iter().all(|v| b.contains(v)) && b.iter().all(|v| a.contains(v))
}

impl EatRegistry {
    pub fn new() -> Self {
        EatRegistry {
            facet_offsets: vec![0],
            ..Default::default()
        }
    }

    /// A registry with room for about `vertices`, `facets` and `corners`.
    pub fn with_capacity(vertices: usize, facets: usize, corners: usize) -> Self {
        let mut r = EatRegistry::new();
        r.slot_of_vertex.reserve(vertices);
        r.vertices.reserve(vertices);
        r.edges.reserve(corners / 2 + 16);
        r.edge_next.reserve(corners / 2 + 16);
        r.edge_head.reserve(vertices);
        r.set_head.reserve(vertices);
        r.edge_chain.reserve(vertices);
        r.set_chain.reserve(vertices);
        r.facet_offsets.reserve(facets + 1);
        r.facet_corners.reserve(corners);
        r.corner_edge.reserve(corners);
        r.facet_set.reserve(facets);
        r.set_next.reserve(facets);
        r.set_facet.reserve(facets);
        r.fc.reserve(facets);
        r
    }

    /// EAT-TA (Fig. 7): registers a facet, its new vertices and new edges, and increments
    /// the counters; returns what it did (the paper's per-facet output). O(arity) expected
    /// time. Every facet is counted, degenerate or not.
    pub fn register_facet(&mut self, corners: &[u32]) -> FacetRegistration {
        let facet = self.register(corners);
        let start = self.facet_offsets[facet as usize] as usize;
        FacetRegistration {
            facet,
            fc: self.facet_counter(facet as usize),
            vertex_slots: corners
                .iter()
                .map(|&v| self.slot_of_vertex[v as usize])
                .collect(),
            edge_slots: self.corner_edge[start..start + corners.len()]
                .iter()
                .copied()
                .filter(|&e| e != NONE)
                .collect(),
        }
    }

    /// EAT-TA without the per-facet report: returns the facet's position (fID).
    pub fn register(&mut self, corners: &[u32]) -> u32 {
        let facet = self.facet_count() as u32;
        for &v in corners {
            self.register_vertex(v);
        }
        let n = corners.len();
        for k in 0..n {
            let (a, b) = (corners[k], corners[(k + 1) % n]);
            if a == b || n < 2 {
                self.corner_edge.push(NONE);
                continue;
            }
            let slot = match self.edge_slot(a, b) {
                Some(slot) => slot,
                None => self.new_edge(a.min(b), a.max(b), facet),
            };
            let e = &mut self.edges[slot as usize];
            e.ec += 1;
            if a < b {
                e.forward += 1;
            }
            self.corner_edge.push(slot);
        }
        let set = self.vertex_set_of(corners, facet);
        self.fc[set as usize] += 1;
        self.facet_set.push(set);
        self.facet_corners.extend_from_slice(corners);
        self.facet_offsets.push(self.facet_corners.len() as u32);
        facet
    }

    fn new_edge(&mut self, a: u32, b: u32, facet: u32) -> u32 {
        let slot = self.edges.len() as u32;
        self.edges.push(EdgeItem {
            a,
            b,
            ec: 0,
            forward: 0,
            first_facet: facet,
        });
        self.edge_next.push(self.edge_head[a as usize]);
        self.edge_head[a as usize] = slot;
        let chain = &mut self.edge_chain[a as usize];
        *chain += 1;
        if *chain > HUB_CHAIN {
            if *chain == HUB_CHAIN + 1 {
                let mut e = slot;
                while e != NONE {
                    let item = &self.edges[e as usize];
                    self.hub_edges.insert(edge_key(item.a, item.b), e);
                    e = self.edge_next[e as usize];
                }
            } else {
                self.hub_edges.insert(edge_key(a, b), slot);
            }
        }
        self.vertices[self.slot_of_vertex[a as usize] as usize].vc += 1;
        self.vertices[self.slot_of_vertex[b as usize] as usize].vc += 1;
        slot
    }

    /// The distinct-vertex-set id of `corners` (a new set if it is the first facet with
    /// these vertices).
    fn vertex_set_of(&mut self, corners: &[u32], facet: u32) -> u32 {
        let Some(&min) = corners.iter().min() else {
            // A facet with no corners: a set of its own.
            self.set_next.push(NONE);
            self.set_facet.push(facet);
            self.fc.push(0);
            return (self.fc.len() - 1) as u32;
        };
        if self.set_chain[min as usize] > HUB_CHAIN {
            let key = set_key(corners);
            if let Some(&set) = self.hub_sets.get(&key) {
                return set;
            }
            let set = self.new_set(min, facet);
            self.hub_sets.insert(key, set);
            return set;
        }
        let mut s = self.set_head[min as usize];
        while s != NONE {
            let f = self.set_facet[s as usize] as usize;
            let other = &self.facet_corners
                [self.facet_offsets[f] as usize..self.facet_offsets[f + 1] as usize];
            if same_vertex_set(corners, other) {
                return s;
            }
            s = self.set_next[s as usize];
        }
        let set = self.new_set(min, facet);
        if self.set_chain[min as usize] > HUB_CHAIN {
            // The chain just became long: every set on it goes into the map (the facet
            // being registered is not in the facet list yet).
            let mut s = set;
            while s != NONE {
                let f = self.set_facet[s as usize];
                let key = if f == facet {
                    set_key(corners)
                } else {
                    set_key(self.facet(f as usize))
                };
                self.hub_sets.insert(key, s);
                s = self.set_next[s as usize];
            }
        }
        set
    }

    /// A new vertex set first seen on `facet`, chained under its smallest vertex `min`.
    fn new_set(&mut self, min: u32, facet: u32) -> u32 {
        let set = self.fc.len() as u32;
        self.set_next.push(self.set_head[min as usize]);
        self.set_head[min as usize] = set;
        self.set_chain[min as usize] += 1;
        self.set_facet.push(facet);
        self.fc.push(0);
        set
    }

    /// Makes room for vertex ids up to `max_id`: the arrays indexed by id grow to
    /// `max_id + 1` entries ([`BYTES_PER_VERTEX_ID`] each) whatever the real vertex count,
    /// so an id is a size claim, checked against `budget` before anything is allocated.
    /// Registering facets whose ids have room never allocates by id.
    ///
    /// # Errors
    /// [`Error::ResourceLimit`] naming the id and the memory it needs, when that passes
    /// `budget` or the allocation fails.
    pub fn reserve_vertex_ids(&mut self, max_id: u32, budget: MemoryBudget) -> Result<()> {
        let len = max_id as usize + 1;
        if len <= self.id_capacity() {
            return Ok(());
        }
        let bytes = len as u64 * BYTES_PER_VERTEX_ID;
        let refuse = |advice: String| Error::ResourceLimit {
            what: format!(
                "vertex id {max_id} (the EAT registry keeps {BYTES_PER_VERTEX_ID} bytes per id \
                 up to the largest: {})",
                human_bytes(bytes)
            ),
            limit: budget.get(),
            advice,
        };
        if bytes > budget.get() {
            return Err(refuse(format!(
                "number the vertices densely from 0; ids below {} fit",
                budget.items(BYTES_PER_VERTEX_ID)
            )));
        }
        let failed = |_| refuse("the allocation failed".into());
        let additional = len - self.slot_of_vertex.len();
        self.slot_of_vertex
            .try_reserve(additional)
            .map_err(failed)?;
        self.edge_head.try_reserve(additional).map_err(failed)?;
        self.set_head.try_reserve(additional).map_err(failed)?;
        self.edge_chain.try_reserve(additional).map_err(failed)?;
        self.set_chain.try_reserve(additional).map_err(failed)?;
        Ok(())
    }

    /// How many vertex ids have room without allocating (see
    /// [`reserve_vertex_ids`](Self::reserve_vertex_ids)).
    pub fn id_capacity(&self) -> usize {
        [
            self.slot_of_vertex.capacity(),
            self.edge_head.capacity(),
            self.set_head.capacity(),
            self.edge_chain.capacity(),
            self.set_chain.capacity(),
        ]
        .into_iter()
        .min()
        .unwrap_or(0)
    }

    fn register_vertex(&mut self, v: u32) -> u32 {
        let i = v as usize;
        if i >= self.slot_of_vertex.len() {
            self.slot_of_vertex.resize(i + 1, NONE);
            self.edge_head.resize(i + 1, NONE);
            self.set_head.resize(i + 1, NONE);
            self.edge_chain.resize(i + 1, 0);
            self.set_chain.resize(i + 1, 0);
        }
        if self.slot_of_vertex[i] == u32::MAX {
            self.slot_of_vertex[i] = self.vertices.len() as u32;
            self.vertices.push(VertexItem { id: v, vc: 0 });
        }
        self.slot_of_vertex[i]
    }

    pub fn vertex_count(&self) -> usize {
        self.vertices.len()
    }

    pub fn edge_count(&self) -> usize {
        self.edges.len()
    }

    pub fn facet_count(&self) -> usize {
        self.facet_offsets.len() - 1
    }

    pub fn vertices(&self) -> &[VertexItem] {
        &self.vertices
    }

    pub fn edges(&self) -> &[EdgeItem] {
        &self.edges
    }

    /// The Vertex item of input vertex `v`, if registered.
    pub fn vertex(&self, v: u32) -> Option<&VertexItem> {
        let slot = *self.slot_of_vertex.get(v as usize)?;
        self.vertices.get(slot as usize)
    }

    /// The Edge-list position of the edge {a, b}, if registered.
    pub fn edge_slot(&self, a: u32, b: u32) -> Option<u32> {
        let (lo, hi) = (a.min(b), a.max(b));
        if *self.edge_chain.get(lo as usize)? > HUB_CHAIN {
            return self.hub_edges.get(&edge_key(lo, hi)).copied();
        }
        let mut e = *self.edge_head.get(lo as usize)?;
        while e != NONE {
            if self.edges[e as usize].b == hi {
                return Some(e);
            }
            e = self.edge_next[e as usize];
        }
        None
    }

    /// The corners of facet `f` (registration order).
    pub fn facet(&self, f: usize) -> &[u32] {
        &self.facet_corners[self.facet_offsets[f] as usize..self.facet_offsets[f + 1] as usize]
    }

    /// `fc` of facet `f`'s vertex set, and whether `f` is its first facet.
    pub fn facet_counter(&self, f: usize) -> u32 {
        self.fc[self.facet_set[f] as usize]
    }

    /// The first facet registered with vertex set `set`.
    pub fn first_facet_of_set(&self, set: u32) -> u32 {
        self.set_facet[set as usize]
    }

    /// The distinct-vertex-set id of each facet (equal ids: duplicated facets).
    pub fn facet_sets(&self) -> &[u32] {
        &self.facet_set
    }

    /// Facet list as offsets + corners.
    pub fn facet_arrays(&self) -> (&[u32], &[u32]) {
        (&self.facet_offsets, &self.facet_corners)
    }

    /// Per corner, the Edge-list position of the edge to the next corner (`u32::MAX` for
    /// none), parallel to the corners of [`facet_arrays`](Self::facet_arrays).
    pub fn corner_edges(&self) -> &[u32] {
        &self.corner_edge
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed fan of `n` triangles around `hub` with rim vertices `rim(k)`, its facet 7
    /// written twice (the second time rotated) and one spoke facet reversed.
    fn fan(n: u32, hub: u32, rim: impl Fn(u32) -> u32) -> Vec<Vec<u32>> {
        let mut facets: Vec<Vec<u32>> = (0..n)
            .map(|k| vec![hub, rim(k), rim((k + 1) % n)])
            .collect();
        facets.push(vec![rim(7), rim(8), hub]);
        facets[20].reverse();
        facets
    }

    #[test]
    fn a_hub_past_the_chain_length_counts_as_through_the_chains() {
        // The hub as vertex 0 (its 300 edges and sets go into the hash maps) and as the
        // last vertex (every chain stays short): the same counts, edge by edge.
        let n = 300;
        let hubbed = fan(n, 0, |k| k + 1);
        let chained = fan(n, n, |k| k);
        let relabel = |v: u32| if v == 0 { n } else { v - 1 };
        let (mut a, mut b) = (EatRegistry::new(), EatRegistry::new());
        for (fa, fb) in hubbed.iter().zip(&chained) {
            a.register(fa);
            b.register(fb);
        }
        assert!(a.edge_chain[0] > HUB_CHAIN && !a.hub_edges.is_empty() && !a.hub_sets.is_empty());
        assert!(b.hub_edges.is_empty() && b.hub_sets.is_empty());
        assert_eq!(
            (a.vertex_count(), a.edge_count(), a.facet_count()),
            (301, 600, 301)
        );
        assert_eq!(
            (b.vertex_count(), b.edge_count(), b.facet_count()),
            (301, 600, 301)
        );
        for e in a.edges() {
            let other = b.edge_slot(relabel(e.a), relabel(e.b)).expect("same edge");
            let o = &b.edges()[other as usize];
            assert_eq!(e.ec, o.ec, "edge {:?}", (e.a, e.b));
        }
        for f in 0..a.facet_count() {
            assert_eq!(a.facet_counter(f), b.facet_counter(f), "facet {f}");
        }
        assert_eq!(a.facet_counter(7), 2);
        assert_eq!(a.facet_counter(300), 2);
    }

    #[test]
    fn a_vertex_id_past_the_memory_budget_is_refused_before_allocating() {
        let mut r = EatRegistry::new();
        let budget = MemoryBudget::bytes(1 << 20);
        let err = r.reserve_vertex_ids(u32::MAX - 1, budget).unwrap_err();
        let message = err.to_string();
        assert!(matches!(err, Error::ResourceLimit { .. }), "{message}");
        assert!(message.contains("vertex id 4294967294"), "{message}");
        assert!(message.contains("80 GiB") && message.contains("ids below 52428 fit"));
        assert_eq!(r.id_capacity(), 0);
        r.reserve_vertex_ids(52_427, budget).unwrap();
        assert!(r.id_capacity() >= 52_428);
        // Room already made is not checked again, so growth by one id costs nothing.
        r.reserve_vertex_ids(1000, MemoryBudget::bytes(0)).unwrap();
        r.register(&[0, 52_427, 7]);
        assert_eq!(r.vertex_count(), 3);
    }

    #[test]
    fn counters_on_two_triangles() {
        let mut r = EatRegistry::new();
        let a = r.register_facet(&[0, 1, 2]);
        assert_eq!(a.edge_slots, vec![0, 1, 2]);
        let b = r.register_facet(&[2, 1, 3]);
        assert_eq!(
            (r.vertex_count(), r.edge_count(), r.facet_count()),
            (4, 5, 2)
        );
        // Vertex 1 and 2 have 3 edges each, 0 and 3 two.
        let vc: Vec<u32> = [0, 1, 2, 3]
            .iter()
            .map(|&v| r.vertex(v).unwrap().vc)
            .collect();
        assert_eq!(vc, vec![2, 3, 3, 2]);
        let shared = r.edge_slot(1, 2).unwrap();
        assert_eq!(r.edges()[shared as usize].ec, 2);
        assert!(!r.edges()[shared as usize].inconsistent());
        assert_eq!(b.fc, 1);
        assert_eq!(r.register_facet(&[1, 2, 0]).fc, 2);
        assert!(r.edges()[shared as usize].ec == 3);
    }

    #[test]
    fn repeated_corner_registers_no_loop_edge() {
        let mut r = EatRegistry::new();
        r.register_facet(&[0, 1, 1, 2]);
        assert_eq!(r.edge_count(), 3);
    }
}
