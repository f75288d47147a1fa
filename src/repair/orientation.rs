//! Consistent orientation: across every edge of two facets the facets must run it in
//! opposite directions. Per edge-connected component, facets are flipped relative to each
//! other by a breadth-first walk; the orientation kept is the one that reverses fewer
//! facets. A non-orientable component (a Möbius strip) is left as it is.

use std::collections::VecDeque;

use foldhash::{HashMap as FxHashMap, HashMapExt};

use super::change::{Action, Change};
use super::editable::Editable;
use crate::topology::FlawKind;

pub fn orient(mesh: &mut Editable, changes: &mut Vec<Change>) {
    let mut by_edge: FxHashMap<(u32, u32), Vec<(u32, bool)>> = FxHashMap::new();
    for e in mesh.edges() {
        by_edge
            .entry((e.from.min(e.to), e.from.max(e.to)))
            .or_default()
            .push((e.facet, e.from < e.to));
    }
    // Neighbours through two-sided edges, with whether they must differ in flip.
    let mut neighbours: Vec<Vec<(u32, bool)>> = vec![Vec::new(); mesh.faces.len()];
    for sides in by_edge.values().filter(|s| s.len() == 2) {
        let ((f, a), (g, b)) = (sides[0], sides[1]);
        if f != g {
            neighbours[f as usize].push((g, a == b));
            neighbours[g as usize].push((f, a == b));
        }
    }
    let mut flip: Vec<Option<bool>> = vec![None; mesh.faces.len()];
    for start in 0..mesh.faces.len() {
        if mesh.faces[start].is_none() || flip[start].is_some() {
            continue;
        }
        let mut component = vec![start as u32];
        let mut orientable = true;
        flip[start] = Some(false);
        let mut queue = VecDeque::from([start as u32]);
        while let Some(f) = queue.pop_front() {
            let here = flip[f as usize].unwrap_or(false);
            for &(g, differ) in &neighbours[f as usize] {
                let want = here ^ differ;
                match flip[g as usize] {
                    None => {
                        flip[g as usize] = Some(want);
                        component.push(g);
                        queue.push_back(g);
                    }
                    Some(have) if have != want => orientable = false,
                    Some(_) => {}
                }
            }
        }
        if !orientable {
            continue;
        }
        let flipped = component
            .iter()
            .filter(|&&f| flip[f as usize] == Some(true))
            .count();
        let reverse_flipped = 2 * flipped <= component.len();
        component.sort_unstable();
        for f in component {
            if (flip[f as usize] == Some(true)) == reverse_flipped {
                if let Some(c) = mesh.faces[f as usize].as_mut() {
                    c.reverse();
                }
                changes.push(Change::new(
                    FlawKind::InconsistentOrientation,
                    Action::ReverseFacet,
                    vec![f],
                    Vec::new(),
                    format!("facet {f} reversed to agree with its neighbours"),
                ));
            }
        }
    }
}
