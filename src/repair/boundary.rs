//! Fixes on the boundary: split the edge of each crack at its T-vertices, close missing
//! triangles and quads with the facet they lack, and (on request) holes up to a number of
//! edges with the 2022 paper's filled spline where their surroundings are a height field,
//! or a fan around their centroid. Each new facet runs opposite to the loop's facets, so
//! it agrees with their orientation.

use foldhash::{HashMap as FxHashMap, HashMapExt};

use super::change::{Action, Change};
use super::editable::Editable;
use super::spline_fill::{spline_fill, Corner, VertexFacets};
use super::HoleFill;
use crate::topology::{show_ids, Flaw, FlawKind};

/// Directed edges of the live facets → the facet ids running them.
fn directed_edges(mesh: &Editable) -> FxHashMap<(u32, u32), Vec<u32>> {
    let mut edges: FxHashMap<(u32, u32), Vec<u32>> = FxHashMap::new();
    for e in mesh.edges() {
        edges.entry((e.from, e.to)).or_default().push(e.facet);
    }
    edges
}

/// Inserts each crack's T-vertices into the facet that uses its edge. `facet_ids` maps the
/// facet positions of the mesh the flaws were found on to facet ids.
pub fn split_cracks(
    mesh: &mut Editable,
    facet_ids: &[u32],
    flaws: &[Flaw],
    changes: &mut Vec<Change>,
) {
    for flaw in flaws.iter().filter(|f| f.kind == FlawKind::Crack) {
        let (a, b) = (flaw.vertices[0], flaw.vertices[1]);
        let ts = &flaw.vertices[2..];
        let Some(&facet) = flaw.faces.first() else {
            continue;
        };
        let f = facet_ids[facet as usize];
        let Some(corners) = mesh.faces[f as usize].as_mut() else {
            continue;
        };
        let n = corners.len();
        let Some(k) = (0..n).find(|&k| {
            let (p, q) = (corners[k], corners[(k + 1) % n]);
            (p, q) == (a, b) || (p, q) == (b, a)
        }) else {
            continue;
        };
        // T-vertices are ordered from a to b: reversed where the facet runs b → a.
        let mut insert: Vec<u32> = ts.to_vec();
        if corners[k] == b {
            insert.reverse();
        }
        let at = k + 1;
        corners.splice(at..at, insert.iter().copied());
        changes.push(Change::new(
            FlawKind::Crack,
            Action::SplitEdge,
            vec![f],
            [a, b].iter().chain(ts).copied().collect(),
            format!(
                "edge {{{a}, {b}}} of facet {f} split at vertices {}",
                show_ids(ts)
            ),
        ));
    }
}

/// The loop's cycle turned to run opposite to the facets along it (None where its facets
/// disagree, as on a non-orientable strip, or no facet is found).
fn closing_cycle(
    cycle: &[u32],
    edges: &FxHashMap<(u32, u32), Vec<u32>>,
) -> Option<(Vec<u32>, u32)> {
    let n = cycle.len();
    let (mut along, mut against, mut beside) = (0, 0, None);
    for k in 0..n {
        let (p, q) = (cycle[k], cycle[(k + 1) % n]);
        if let Some(fs) = edges.get(&(p, q)) {
            along += 1;
            beside = beside.max(fs.iter().copied().max());
        }
        if let Some(fs) = edges.get(&(q, p)) {
            against += 1;
            beside = beside.max(fs.iter().copied().max());
        }
    }
    match (along, against) {
        (0, 0) => None,
        (a, 0) if a > 0 => Some((cycle.iter().rev().copied().collect(), beside?)),
        (0, _) => Some((cycle.to_vec(), beside?)),
        _ => None,
    }
}

/// Closes missing triangles and quads, and holes of up to `max_hole_edges` edges.
pub fn close_loops(
    mesh: &mut Editable,
    flaws: &[Flaw],
    max_hole_edges: usize,
    fill: HoleFill,
    changes: &mut Vec<Change>,
) {
    let edges = directed_edges(mesh);
    let mut around: Option<VertexFacets> = None;
    for flaw in flaws {
        let small = matches!(flaw.kind, FlawKind::MissingTriangle | FlawKind::MissingQuad);
        let hole = flaw.kind == FlawKind::Hole
            && flaw.vertices.len() <= max_hole_edges
            && flaw.faces.is_empty(); // not the border of an isolated facet
        if !(small || hole) {
            continue;
        }
        let Some((cycle, beside)) = closing_cycle(&flaw.vertices, &edges) else {
            continue;
        };
        if small || cycle.len() <= 4 {
            let f = mesh.add_facet(cycle.clone(), beside);
            changes.push(Change::new(
                flaw.kind,
                Action::AddFacet,
                vec![f],
                cycle.clone(),
                format!("facet {f} {cycle:?} added in the loop beside facet {beside}"),
            ));
            continue;
        }
        let mut why_fan = None;
        if fill == HoleFill::Spline {
            let around =
                around.get_or_insert_with(|| VertexFacets::new(mesh.positions.len(), &mesh.faces));
            match spline_fill(&cycle, &mesh.positions, &mesh.faces, around) {
                Ok(filling) => {
                    let ids: Vec<u32> = filling
                        .points
                        .iter()
                        .map(|&p| mesh.add_vertex(p, None))
                        .collect();
                    let id = |c: Corner| match c {
                        Corner::Border(k) => cycle[k],
                        Corner::Interior(k) => ids[k],
                    };
                    let added: Vec<u32> = filling
                        .triangles
                        .iter()
                        .map(|t| mesh.add_facet(t.map(id).to_vec(), beside))
                        .collect();
                    changes.push(Change::new(
                        FlawKind::Hole,
                        Action::AddFacet,
                        added.clone(),
                        ids.iter().chain(&cycle).copied().collect(),
                        format!(
                            "hole of {} edges filled with {} triangles and {} new vertices on \
                             the 2022 paper's filled spline (biquadratic, {c} × {c} cells, {} \
                             surrounding vertices fitted)",
                            cycle.len(),
                            added.len(),
                            ids.len(),
                            filling.data_points,
                            c = filling.cells,
                        ),
                    ));
                    continue;
                }
                Err(why) => why_fan = Some(why),
            }
        }
        let n = cycle.len() as f64;
        let centre = [0, 1, 2].map(|k| {
            cycle
                .iter()
                .map(|&v| mesh.positions[v as usize][k])
                .sum::<f64>()
                / n
        });
        let c = mesh.add_vertex(centre, None);
        let mut added = Vec::new();
        for k in 0..cycle.len() {
            let (p, q) = (cycle[k], cycle[(k + 1) % cycle.len()]);
            added.push(mesh.add_facet(vec![p, q, c], beside));
        }
        changes.push(Change::new(
            FlawKind::Hole,
            Action::AddFacet,
            added,
            std::iter::once(c).chain(cycle.iter().copied()).collect(),
            format!(
                "hole of {} edges closed by a fan of triangles around a new vertex {c} at its \
                 centroid{}",
                cycle.len(),
                why_fan.map_or(String::new(), |why| format!(" (no spline fill: {why})"))
            ),
        ));
    }
}
