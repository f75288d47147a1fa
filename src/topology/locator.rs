//! The flaw locator: every flaw of the registered facets, classified and placed.
//! (Beyond the paper, which only tells that χ is wrong since the last verified point.)

use crate::mesh::vector::{distance, mean};
use std::hash::BuildHasher;

use foldhash::{HashMap as FxHashMap, HashMapExt};

use super::cracks::stitch_cracks;
use super::flaw::{show_ids, show_measure, Flaw, FlawKind, LoopShape};
use super::registry::EatRegistry;
use super::structure::Structure;

/// The default crack tolerance: finds a T-vertex 0.5 % of the edge's length off the edge
/// (a float export of a T-junction) with a margin of two.
pub const DEFAULT_CRACK_TOLERANCE: f64 = 0.01;

/// Options of the locator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocatorOptions {
    /// Distance under which two distinct vertices count as coincident (0: same coordinates).
    pub weld_tolerance: f64,
    /// A boundary vertex within this fraction of a boundary edge's length of that edge
    /// (and not one of its ends) is a T-vertex on it: a crack.
    pub crack_tolerance: f64,
}

impl Default for LocatorOptions {
    fn default() -> Self {
        LocatorOptions {
            weld_tolerance: 0.0,
            crack_tolerance: DEFAULT_CRACK_TOLERANCE,
        }
    }
}

/// Boundary loops as vertex cycles. A boundary edge joins two nodes (vertex, fan of its
/// facet at that vertex); each loop is walked once through the nodes, so a pinch vertex
/// closes one loop per fan (as a half-edge walk does) and a non-orientable strip, whose
/// boundary half-edges do not chain head to tail, is still one loop. Each loop starts
/// along its first edge's boundary half-edge (opposite to the facet), so on an orientable
/// surface the loops run as OpenMesh's boundary walks do. A chain whose ends meet only
/// across a non-manifold edge is one loop, closed across that edge.
pub fn boundary_walks(registry: &EatRegistry, structure: &Structure) -> Vec<Vec<u32>> {
    let (offsets, corners) = registry.facet_arrays();
    let next_corner = |k: u32| {
        let f = structure.corner_facet[k as usize] as usize;
        if k + 1 == offsets[f + 1] {
            offsets[f]
        } else {
            k + 1
        }
    };
    // Per boundary edge: its two nodes, the first being where its boundary half-edge starts.
    let mut ends: Vec<[(u32, u32); 2]> = Vec::new();
    let mut at_node: FxHashMap<(u32, u32), Vec<u32>> = FxHashMap::new();
    for (e, item) in registry.edges().iter().enumerate() {
        if item.ec != 1 {
            continue;
        }
        let side = structure.first_side(e);
        let (ku, kw) = (side.corner, next_corner(side.corner));
        let from = (corners[kw as usize], structure.corner_fan[kw as usize]);
        let to = (corners[ku as usize], structure.corner_fan[ku as usize]);
        let id = ends.len() as u32;
        ends.push([from, to]);
        at_node.entry(from).or_default().push(id);
        at_node.entry(to).or_default().push(id);
    }
    let mut used = vec![false; ends.len()];
    let mut loops = Vec::new();
    for start in 0..ends.len() {
        if used[start] {
            continue;
        }
        used[start] = true;
        let origin = ends[start][0];
        let mut cycle = vec![origin.0];
        let mut at = ends[start][1];
        let mut step = |at: &mut (u32, u32)| {
            let e = at_node[at].iter().copied().find(|&e| !used[e as usize])?;
            used[e as usize] = true;
            let [p, q] = ends[e as usize];
            *at = if p == *at { q } else { p };
            Some(())
        };
        let mut closed = true;
        while at != origin {
            let here = at.0;
            if step(&mut at).is_none() {
                closed = false;
                break;
            }
            cycle.push(here);
        }
        if !closed {
            // An open chain (its ends meet only across an edge of three or more sides,
            // as the free border of a fin does): walked whole, the far end and then
            // back from the origin, and closed across that edge.
            let far = at.0;
            let mut back = Vec::new();
            let mut at = origin;
            while step(&mut at).is_some() {
                back.push(at.0);
            }
            back.reverse();
            back.append(&mut cycle);
            cycle = back;
            if cycle.first() != Some(&far) {
                cycle.push(far);
            }
        }
        loops.push(cycle);
    }
    loops
}

/// Median edge length of the registered edges (0 for none).
pub fn median_edge_length(registry: &EatRegistry, positions: &[[f64; 3]]) -> f64 {
    // f32 halves the memory of this 1-per-edge array; a median needs no more precision.
    // Lengths are kept over a power of two near the largest coordinate (exact), so that
    // lengths beyond f32's range (3.4e38) or below it (1e-45) keep their value.
    let largest = positions
        .iter()
        .flatten()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let scale = if largest > 0.0 && largest.is_finite() {
        power_of_two_below(largest)
    } else {
        1.0
    };
    let mut lengths: Vec<f32> = registry
        .edges()
        .iter()
        .map(|e| (distance(positions[e.a as usize], positions[e.b as usize]) / scale) as f32)
        .collect();
    if lengths.is_empty() {
        return 0.0;
    }
    let mid = lengths.len() / 2;
    f64::from(*lengths.select_nth_unstable_by(mid, f32::total_cmp).1) * scale
}

/// Perimeter, vector area and tininess of a closed polygon.
///
/// Both measures are finite whenever they are representable, also for coordinates near
/// ±f64::MAX: lengths come from [`distance`], and a vector area whose cross products
/// overflow is summed again from the first point (half-differences, which cannot
/// overflow, scaled by a power of two near the largest: exact). A measure beyond f64's
/// range (a triangle with 1e308 coordinates has an area near 1e616) is +∞, which reports
/// show as such (JSON: `"Infinity"`), never as a silent `null`; the flaw's topology and
/// position stay exact. Elsewhere the area is ½‖Σ pᵢ × pᵢ₊₁‖ as always, bit for bit.
pub fn loop_shape(cycle: &[u32], positions: &[[f64; 3]], median_edge: f64) -> LoopShape {
    let n = cycle.len();
    let point = |k: usize| positions[cycle[k % n] as usize];
    let perimeter = (0..n)
        .map(|k| distance(point(k), point(k + 1)))
        .sum::<f64>();
    let vector_area = |at: &dyn Fn(usize) -> [f64; 3]| {
        let mut cross = [0.0; 3];
        for k in 0..n {
            let (p, q) = (at(k), at(k + 1));
            cross[0] += p[1] * q[2] - p[2] * q[1];
            cross[1] += p[2] * q[0] - p[0] * q[2];
            cross[2] += p[0] * q[1] - p[1] * q[0];
        }
        0.5 * (cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]).sqrt()
    };
    let mut area = vector_area(&point);
    if !area.is_finite() && n > 0 {
        let origin = point(0);
        let half = |k: usize| {
            let p = point(k);
            [
                0.5 * p[0] - 0.5 * origin[0],
                0.5 * p[1] - 0.5 * origin[1],
                0.5 * p[2] - 0.5 * origin[2],
            ]
        };
        let largest = (0..n).flat_map(half).fold(0.0f64, |m, x| m.max(x.abs()));
        if largest > 0.0 && largest.is_finite() {
            // Scaled half-differences lie in (-2, 2): their cross products cannot overflow.
            let scale = power_of_two_below(largest);
            let scaled = |k: usize| half(k).map(|x| x / scale);
            // Halving took a factor 4 off the area; (a·s)·s, not a·s²: s² alone may
            // overflow where the area does not.
            area = 4.0 * vector_area(&scaled) * scale * scale;
        }
    }
    LoopShape {
        edges: n,
        perimeter,
        area,
        tiny: below_squared(area, 0.01, median_edge) || perimeter < 0.5 * median_edge,
    }
}

/// The power of two at or below `x` (finite, positive): dividing by it is exact.
fn power_of_two_below(x: f64) -> f64 {
    2f64.powi(x.log2().floor() as i32)
}

/// `a < c·m²`, also where m² overflows (then as a / m < c·m).
fn below_squared(a: f64, c: f64, m: f64) -> bool {
    let bound = c * m * m;
    if bound.is_finite() || m <= 0.0 {
        a < bound
    } else {
        a / m < c * m
    }
}

/// Classifies one boundary loop: missing triangle or quad, or hole. A loop that is the
/// whole border of one facet (an isolated facet) is a hole: adding the reversed facet
/// would only duplicate it.
fn loop_flaw(
    cycle: Vec<u32>,
    positions: &[[f64; 3]],
    median_edge: f64,
    component: Option<u32>,
    own_facet: Option<u32>,
    joined_at: Option<&NonManifoldEdgeSides>,
) -> Flaw {
    let shape = loop_shape(&cycle, positions, median_edge);
    let n = cycle.len();
    let position = mean(cycle.iter().map(|&v| positions[v as usize]));
    if let (None, Some(edge)) = (own_facet, joined_at) {
        // Filling such a loop would put one more facet on the edge: the separation is
        // the fix, and its own flaw (the non-manifold edge) carries it, checked.
        let [a, b] = edge.ends;
        return Flaw {
            kind: FlawKind::Hole,
            description: format!(
                "boundary loop of {n} edges through both ends of non-manifold edge {{{a}, {b}}}, perimeter {}: the borders of facets that meet on that edge, joined by the walk — not a hole to fill",
                show_measure(shape.perimeter)
            ),
            vertices: cycle,
            faces: edge.faces.clone(),
            position,
            shape: Some(shape),
            component,
            fix_verified: None,
            suggested_fix: format!(
                "separate the facets of edge {{{a}, {b}}} (the non_manifold_edge flaw's fix: surfkit repair --only non_manifold_edge), then scan again; what is left is the border of the pieces"
            ),
        };
    }
    if let Some(f) = own_facet {
        return Flaw {
            kind: FlawKind::Hole,
            description: format!(
                "boundary loop of {n} edges around facet {f} alone (an isolated facet, or one hanging on a non-manifold edge), perimeter {}",
                show_measure(shape.perimeter)
            ),
            vertices: cycle,
            faces: vec![f],
            position,
            shape: Some(shape),
            component,
            fix_verified: None,
            suggested_fix: format!(
                "delete facet {f} if it is debris; otherwise its border is the surface's"
            ),
        };
    }
    let (kind, fix) = match n {
        3 => (
            FlawKind::MissingTriangle,
            format!("add the facet {:?}", cycle.iter().rev().collect::<Vec<_>>()),
        ),
        4 => (
            FlawKind::MissingQuad,
            format!("add the facet {:?}", cycle.iter().rev().collect::<Vec<_>>()),
        ),
        _ => (
            FlawKind::Hole,
            format!(
                "fill the hole (surfkit repair --fill-holes {n}, or a smooth patch with surfkit fill), or leave it if the target surface has this boundary"
            ),
        ),
    };
    Flaw {
        kind,
        description: format!(
            "boundary loop of {n} edges, perimeter {}, area {}{}",
            show_measure(shape.perimeter),
            show_measure(shape.area),
            if shape.tiny {
                " (tiny: easy to miss on screen)"
            } else {
                ""
            }
        ),
        vertices: cycle,
        faces: Vec::new(),
        position,
        shape: Some(shape),
        component,
        fix_verified: None,
        suggested_fix: fix,
    }
}

/// A non-manifold edge: its ends and the input ids of the facets on it.
struct NonManifoldEdgeSides {
    ends: [u32; 2],
    faces: Vec<u32>,
}

/// The edges of more than two facets.
fn non_manifold_edge_sides(
    registry: &EatRegistry,
    structure: &Structure,
    facet_id: impl Fn(u32) -> u32,
) -> Vec<NonManifoldEdgeSides> {
    registry
        .edges()
        .iter()
        .enumerate()
        .filter(|(_, item)| item.ec > 2)
        .map(|(e, item)| NonManifoldEdgeSides {
            ends: [item.a, item.b],
            faces: structure.sides_of(e).map(|s| facet_id(s.facet)).collect(),
        })
        .collect()
}

/// Every flaw of the registered facets. `vertex_count` is the number of vertices in the
/// input (to find the unreferenced ones); `facet_ids` maps Facet-list positions to input ids.
pub fn locate(
    registry: &EatRegistry,
    structure: &Structure,
    positions: &[[f64; 3]],
    facet_ids: &[u32],
    options: &LocatorOptions,
) -> Vec<Flaw> {
    let geometry = GeometryFacts::of(registry, positions, options);
    locate_with(registry, structure, positions, facet_ids, &geometry).0
}

/// What the locator needs from the geometry alone (not from the structure), so that it can
/// be computed while the structure is being built.
pub struct GeometryFacts {
    pub median_edge: f64,
    /// (vertex, earlier coincident vertex) pairs.
    pub coincident: Vec<(u32, u32)>,
    pub crack_tolerance: f64,
}

impl GeometryFacts {
    pub fn of(registry: &EatRegistry, positions: &[[f64; 3]], options: &LocatorOptions) -> Self {
        GeometryFacts {
            median_edge: median_edge_length(registry, positions),
            coincident: coincident_pairs(registry, positions, options.weld_tolerance),
            crack_tolerance: options.crack_tolerance,
        }
    }
}

/// [`locate`] with the geometric facts already computed; also returns the component of
/// each boundary walk (the loops the topology counts, before T-junctions are stitched).
pub fn locate_with(
    registry: &EatRegistry,
    structure: &Structure,
    positions: &[[f64; 3]],
    facet_ids: &[u32],
    geometry: &GeometryFacts,
) -> (Vec<Flaw>, Vec<Option<u32>>) {
    let mut flaws = Vec::new();
    let median = geometry.median_edge;
    let (offsets, corners) = registry.facet_arrays();
    let facet_id = |f: u32| facet_ids.get(f as usize).copied().unwrap_or(f);
    let pos = |v: u32| positions[v as usize];

    // Boundary loops, located by walking; T-junctions stitched to show what they hide.
    let walks = boundary_walks(registry, structure);
    let component_of_walk = |cycle: &[u32]| {
        let (&a, &b) = (cycle.first()?, cycle.get(1).or(cycle.first())?);
        let e = registry.edge_slot(a, b)?;
        Some(structure.facet_component[structure.first_side(e as usize).facet as usize])
    };
    let walk_components: Vec<Option<u32>> = walks.iter().map(|w| component_of_walk(w)).collect();
    // The facet alone on a loop's edges, when the loop is exactly that facet's border.
    let own_facet = |cycle: &[u32]| {
        let (&a, &b) = (cycle.first()?, cycle.get(1)?);
        let f = structure
            .first_side(registry.edge_slot(a, b)? as usize)
            .facet as usize;
        let face = &corners[offsets[f] as usize..offsets[f + 1] as usize];
        let mut x = face.to_vec();
        let mut y = cycle.to_vec();
        // A degenerate facet's repeated corner is no edge of its border.
        x.sort_unstable();
        x.dedup();
        y.sort_unstable();
        (x == y).then(|| facet_id(f as u32))
    };
    let facet_uses = |a: u32, b: u32, t: u32| {
        registry.edge_slot(a, b).is_some_and(|e| {
            structure.sides_of(e as usize).any(|s| {
                let f = s.facet as usize;
                corners[offsets[f] as usize..offsets[f + 1] as usize].contains(&t)
            })
        })
    };
    let stitched = stitch_cracks(&walks, positions, geometry.crack_tolerance, facet_uses);
    for j in &stitched.junctions {
        let faces: Vec<u32> = registry
            .edge_slot(j.a, j.b)
            .map(|e| {
                structure
                    .sides_of(e as usize)
                    .map(|s| facet_id(s.facet))
                    .collect()
            })
            .unwrap_or_default();
        let mut vertices = vec![j.a, j.b];
        vertices.extend(&j.t_vertices);
        let (a, b, ts) = (j.a, j.b, &j.t_vertices);
        flaws.push(Flaw {
            kind: FlawKind::Crack,
            position: mean(ts.iter().map(|&v| pos(v))),
            shape: None,
            component: registry.edge_slot(a, b).map(|e| {
                structure.facet_component[structure.first_side(e as usize).facet as usize]
            }),
            description: format!(
                "boundary vertices {} lie on edge {{{a}, {b}}} ({}) but facet {faces:?} does not use them: a crack (T-junction)",
                show_ids(ts),
                if j.offset == 0.0 {
                    "on its line".to_string()
                } else {
                    format!("up to {:.3} % of its length off it", 100.0 * j.offset)
                }
            ),
            fix_verified: None,
            suggested_fix: format!(
                "split edge {{{a}, {b}}} at vertices {} in facet {faces:?} (insert them between its corners {a} and {b})",
                show_ids(ts)
            ),
            vertices,
            faces,
        });
    }
    let non_manifold = non_manifold_edge_sides(registry, structure, facet_id);
    let mut non_manifold_at: FxHashMap<u32, Vec<usize>> = FxHashMap::new();
    for (i, e) in non_manifold.iter().enumerate() {
        non_manifold_at.entry(e.ends[0]).or_default().push(i);
    }
    let joined_at = |cycle: &[u32]| {
        if non_manifold.is_empty() {
            return None;
        }
        let on_loop: foldhash::HashSet<u32> = cycle.iter().copied().collect();
        cycle
            .iter()
            .filter_map(|v| non_manifold_at.get(v))
            .flatten()
            .map(|&i| &non_manifold[i])
            .find(|e| on_loop.contains(&e.ends[1]))
    };
    for (w, cycle) in walks.iter().enumerate() {
        if !stitched.stitched_walk[w] {
            let own = own_facet(cycle);
            flaws.push(loop_flaw(
                cycle.clone(),
                positions,
                median,
                walk_components[w],
                own,
                joined_at(cycle),
            ));
        }
    }
    for (cycle, w) in stitched.remaining.iter().cloned() {
        let own = own_facet(&cycle);
        let joined = joined_at(&cycle);
        flaws.push(loop_flaw(
            cycle,
            positions,
            median,
            walk_components[w],
            own,
            joined,
        ));
    }

    for (e, item) in registry.edges().iter().enumerate() {
        let first = structure.first_side(e);
        if item.ec > 2 {
            let faces: Vec<u32> = structure.sides_of(e).map(|s| facet_id(s.facet)).collect();
            flaws.push(Flaw {
                kind: FlawKind::NonManifoldEdge,
                vertices: vec![item.a, item.b],
                position: mean([pos(item.a), pos(item.b)].into_iter()),
                shape: None,
                component: Some(structure.facet_component[first.facet as usize]),
                description: format!("edge {{{}, {}}} has {} facet sides (ec = {})", item.a, item.b, item.ec, item.ec),
                fix_verified: None,
                suggested_fix: format!(
                    "keep two of the facets {} on this edge; give the others their own copies of vertices {} and {}, or delete duplicates",
                    show_ids(&faces), item.a, item.b
                ),
                faces,
            });
        } else if item.inconsistent() {
            let faces: Vec<u32> = structure.sides_of(e).map(|s| facet_id(s.facet)).collect();
            flaws.push(Flaw {
                kind: FlawKind::InconsistentOrientation,
                vertices: vec![item.a, item.b],
                position: mean([pos(item.a), pos(item.b)].into_iter()),
                shape: None,
                component: Some(structure.facet_component[first.facet as usize]),
                description: format!(
                    "facets {faces:?} both run edge {{{}, {}}} the same way",
                    item.a, item.b
                ),
                fix_verified: None,
                suggested_fix: format!(
                    "reverse the corner order of facet {} (and its side of the surface)",
                    faces[1]
                ),
                faces,
            });
        }
    }

    // A crack whose edge ends on a border splits the fan at that end in two: the crack
    // is the flaw there, and stitching it joins the fans again.
    let crack_ends: foldhash::HashSet<u32> =
        stitched.junctions.iter().flat_map(|j| [j.a, j.b]).collect();
    for (&v, &fans) in structure.non_manifold_vertices.iter().zip(&structure.fans) {
        if fans == 2 && crack_ends.contains(&v) {
            continue;
        }
        flaws.push(Flaw {
            kind: FlawKind::NonManifoldVertex,
            vertices: vec![v],
            faces: Vec::new(),
            position: pos(v),
            shape: None,
            component: None,
            description: format!("vertex {v} joins {fans} separate fans of facets"),
            fix_verified: None,
            suggested_fix: format!("give each fan at vertex {v} its own copy of the vertex, or fill the gap between the fans"),
        });
    }

    // Duplicated and degenerate facets.
    for (f, &set) in registry.facet_sets().iter().enumerate() {
        let face = &corners[offsets[f] as usize..offsets[f + 1] as usize];
        let first = registry.first_facet_of_set(set);
        if first != f as u32 {
            flaws.push(Flaw {
                kind: FlawKind::DuplicatedFacet,
                vertices: face.to_vec(),
                faces: vec![facet_id(f as u32), facet_id(first)],
                position: mean(face.iter().map(|&v| pos(v))),
                shape: None,
                component: Some(structure.facet_component[f]),
                description: format!(
                    "facet {} has the vertices of facet {} (fc = {})",
                    facet_id(f as u32),
                    facet_id(first),
                    registry.facet_counter(f)
                ),
                fix_verified: None,
                suggested_fix: format!("delete facet {}", facet_id(f as u32)),
            });
        }
        if crate::mesh::io::degeneracy(face).is_some() {
            flaws.push(Flaw {
                kind: FlawKind::DegenerateFacet,
                vertices: face.to_vec(),
                faces: vec![facet_id(f as u32)],
                position: mean(face.iter().map(|&v| pos(v))),
                shape: None,
                component: Some(structure.facet_component[f]),
                description: format!(
                    "facet {} has corners {}: fewer than 3 or a repeated vertex",
                    facet_id(f as u32),
                    show_ids(face)
                ),
                fix_verified: None,
                suggested_fix: format!(
                    "delete facet {} or remove its repeated corner",
                    facet_id(f as u32)
                ),
            });
        }
    }

    // Unreferenced and coincident vertices.
    for (v, p) in positions.iter().enumerate() {
        if registry.vertex(v as u32).is_none() {
            flaws.push(Flaw {
                kind: FlawKind::UnreferencedVertex,
                vertices: vec![v as u32],
                faces: Vec::new(),
                position: *p,
                shape: None,
                component: None,
                description: format!("vertex {v} is used by no facet"),
                fix_verified: None,
                suggested_fix: format!("delete vertex {v}"),
            });
        }
    }
    for &(v, u) in &geometry.coincident {
        flaws.push(Flaw {
            kind: FlawKind::CoincidentVertices,
            vertices: vec![v, u],
            faces: Vec::new(),
            position: pos(v),
            shape: None,
            component: None,
            description: format!("vertex {v} is at the place of vertex {u} but not welded to it"),
            fix_verified: None,
            suggested_fix: format!("weld vertex {v} into vertex {u}"),
        });
    }
    (flaws, walk_components)
}

/// Referenced vertices (in id order) that lie within `tolerance` of an earlier referenced
/// vertex, as (vertex, earlier vertex). Exact coordinates when `tolerance` is 0.
pub fn coincident_pairs(
    registry: &EatRegistry,
    positions: &[[f64; 3]],
    tolerance: f64,
) -> Vec<(u32, u32)> {
    // Input ids in increasing order, found through the id → slot map (no sort).
    let ids = (0..positions.len() as u32).filter(|&v| registry.vertex(v).is_some());
    let mut pairs = Vec::new();
    if tolerance <= 0.0 {
        // +0.0 folds -0.0 into 0.0: the same place.
        let key = |v: u32| positions[v as usize].map(|c| (c + 0.0).to_bits());
        let state = foldhash::fast::FixedState::default();
        // The table holds vertex ids only (4 bytes a slot, keys read from `positions`): a
        // table of millions of full keys costs more in cache misses and fresh pages than
        // the hashing itself. Sized up front: rehashing doubles what it touches.
        let mut seen: hashbrown::HashTable<u32> =
            hashbrown::HashTable::with_capacity(registry.vertices().len());
        for v in ids {
            let k = key(v);
            let hash = state.hash_one(k);
            match seen.find(hash, |&u| key(u) == k) {
                Some(&u) => pairs.push((v, u)),
                None => {
                    seen.insert_unique(hash, v, |&u| state.hash_one(key(u)));
                }
            }
        }
        return pairs;
    }
    let cell = |p: [f64; 3]| p.map(|c| (c / tolerance).floor() as i64);
    let mut grid: FxHashMap<[i64; 3], Vec<u32>> = FxHashMap::new();
    for v in ids {
        let p = positions[v as usize];
        let c = cell(p);
        let mut found = None;
        'search: for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(list) = grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) {
                        if let Some(&u) = list
                            .iter()
                            .find(|&&u| distance(positions[u as usize], p) <= tolerance)
                        {
                            found = Some(u);
                            break 'search;
                        }
                    }
                }
            }
        }
        match found {
            Some(u) => pairs.push((v, u)),
            None => grid.entry(c).or_default().push(v),
        }
    }
    pairs
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangle(points: [[f64; 3]; 3]) -> LoopShape {
        loop_shape(&[0, 1, 2], &points, 1.0)
    }

    #[test]
    fn loop_measures_are_plain_where_nothing_overflows() {
        let shape = triangle([[0.0, 0.0, 0.0], [3.0, 0.0, 0.0], [0.0, 4.0, 0.0]]);
        assert_eq!((shape.perimeter, shape.area), (12.0, 6.0));
    }

    #[test]
    fn loop_measures_are_finite_wherever_representable() {
        // The cross products' squares overflow (1e616), the area (5e307) does not.
        let shape = triangle([[0.0; 3], [1e154, 0.0, 0.0], [0.0, 1e154, 0.0]]);
        assert!((shape.area / 5e307 - 1.0).abs() < 1e-14, "{shape:?}");
        assert!(shape.perimeter.is_finite());
        // Far from the origin: every term p × q overflows (1e320), the small triangle's
        // area (½ 1e300) does not, and is measured from its first corner without
        // cancellation.
        let (o, h) = (1e160, 1e150);
        let shape = triangle([[o, o, o], [o + h, o, o], [o, o + h, o]]);
        let side = (o + h) - o; // h as rounded next to o (exact: Sterbenz)
        assert!(
            (shape.area / (0.5 * side * side) - 1.0).abs() < 1e-14,
            "{shape:?}"
        );
    }

    #[test]
    fn loop_measures_beyond_f64_are_infinite_not_nan() {
        // surfkit eat huge.obj: its centroid is finite, its measures are not representable.
        let points = [[1e308, 1e308, 1e308], [-1e308, 0.0, 0.0], [0.0, 1e308, 0.0]];
        let shape = triangle(points);
        assert_eq!(shape.perimeter, f64::INFINITY);
        assert_eq!(shape.area, f64::INFINITY);
        assert!(!shape.tiny);
        let c = mean(points.iter().copied());
        assert!(c.iter().all(|x| x.is_finite()), "{c:?}");
    }

    #[test]
    fn tininess_holds_where_the_squared_median_overflows() {
        // 0.01 · (1e200)² = 1e398 overflows; every finite area is below it.
        assert!(below_squared(f64::MAX, 0.01, 1e200));
        assert!(!below_squared(f64::INFINITY, 0.01, 1e200));
        assert!(!below_squared(f64::MAX, 0.01, 1e150));
        assert!(!below_squared(1.0, 0.01, 0.0));
    }
}
