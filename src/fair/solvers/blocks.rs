//! The blocks of the domain-decomposition method (paper §5, fig. 6): seed vertices chosen
//! among the free vertices by farthest-point sampling in edge distance, a discrete Voronoi
//! diagram of the seeds grown by breadth-first search over the mesh edges, and each region
//! extended by a few rings so that neighbouring blocks overlap ("making rather wide
//! overlaps" helps the rate of convergence). Farthest-point seeds give regions of small
//! diameter relative to their size, which the paper asks for.

use std::collections::VecDeque;

use crate::error::{Error, Result};
use crate::fair::preparation::topology::MeshTopology;

/// Free vertices of each block (sorted vertex ids), covering every free vertex.
///
/// `count` seeds, regions grown over all mesh edges (fixed vertices relay the search, so
/// regions follow the surface), then each region's free vertices extended by `overlap`
/// rings of edges.
///
/// # Errors
/// [`Error::InvalidInput`] when `count` is 0 or exceeds the number of free vertices, when
/// `fixed` does not have one flag per vertex, or when a connected part of the free vertices
/// gets no seed (`count` smaller than the number of such parts).
pub fn voronoi_blocks(
    topo: &MeshTopology,
    fixed: &[bool],
    count: usize,
    overlap: u32,
) -> Result<Vec<Vec<u32>>> {
    let n = topo.neighbours.len();
    if fixed.len() != n {
        return Err(Error::InvalidInput(format!(
            "{} fixed flags for {n} vertices",
            fixed.len()
        )));
    }
    let free: Vec<u32> = (0..n as u32).filter(|&v| !fixed[v as usize]).collect();
    if count == 0 {
        return Err(Error::InvalidInput(
            "the block method needs at least one block".into(),
        ));
    }
    if count > free.len() {
        return Err(Error::InvalidInput(format!(
            "{count} blocks asked for but only {} free vertices",
            free.len()
        )));
    }
    let seeds = farthest_point_seeds(topo, &free, count);
    let owner = voronoi(topo, &seeds);
    let mut blocks: Vec<Vec<u32>> = vec![Vec::new(); count];
    for &v in &free {
        let b = owner[v as usize];
        if b == u32::MAX {
            return Err(Error::InvalidInput(format!(
                "free vertex {v} is not connected to any of the {count} block seeds; \
                 use at least one block per connected part of the free vertices"
            )));
        }
        blocks[b as usize].push(v);
    }
    Ok(blocks
        .into_iter()
        .map(|region| extend(topo, fixed, region, overlap))
        .collect())
}

/// Farthest-point sampling: the first seed is the free vertex farthest from the fixed ones
/// (or the first free vertex when nothing is fixed), each next one the free vertex
/// farthest in edge distance from the seeds so far (unreachable counts as farthest, so
/// every connected part gets a seed while seeds remain).
fn farthest_point_seeds(topo: &MeshTopology, free: &[u32], count: usize) -> Vec<u32> {
    let n = topo.neighbours.len();
    let fixed_sources = (0..n as u32).filter(|v| free.binary_search(v).is_err());
    let from_fixed = topo.distances(fixed_sources);
    let first = free
        .iter()
        .copied()
        .max_by_key(|&v| (from_fixed[v as usize], std::cmp::Reverse(v)))
        .expect("count ≥ 1 free vertex");
    let mut seeds = vec![first];
    let mut dist = topo.distances([first]);
    while seeds.len() < count {
        let next = free
            .iter()
            .copied()
            .max_by_key(|&v| (dist[v as usize], std::cmp::Reverse(v)))
            .expect("free vertices");
        if dist[next as usize] == 0 {
            break; // cannot happen while count ≤ free vertices; kept for safety
        }
        seeds.push(next);
        topo.lower_distances(&mut dist, [next]);
    }
    seeds
}

/// The discrete Voronoi diagram: the seed index of each vertex (`u32::MAX` unreachable),
/// by a multi-source BFS (ties go to the seed whose wave arrives first).
fn voronoi(topo: &MeshTopology, seeds: &[u32]) -> Vec<u32> {
    let mut owner = vec![u32::MAX; topo.neighbours.len()];
    let mut queue = VecDeque::new();
    for (b, &s) in seeds.iter().enumerate() {
        owner[s as usize] = b as u32;
        queue.push_back(s);
    }
    while let Some(v) = queue.pop_front() {
        for &w in &topo.neighbours[v as usize] {
            if owner[w as usize] == u32::MAX {
                owner[w as usize] = owner[v as usize];
                queue.push_back(w);
            }
        }
    }
    owner
}

/// `region` with the free vertices within `rings` edges of it, sorted.
fn extend(topo: &MeshTopology, fixed: &[bool], region: Vec<u32>, rings: u32) -> Vec<u32> {
    let mut dist = vec![u32::MAX; topo.neighbours.len()];
    let mut queue = VecDeque::new();
    for &v in &region {
        dist[v as usize] = 0;
        queue.push_back(v);
    }
    let mut out = region;
    while let Some(v) = queue.pop_front() {
        let d = dist[v as usize] + 1;
        if d > rings {
            continue;
        }
        for &w in &topo.neighbours[v as usize] {
            if dist[w as usize] == u32::MAX {
                dist[w as usize] = d;
                queue.push_back(w);
                if !fixed[w as usize] {
                    out.push(w);
                }
            }
        }
    }
    out.sort_unstable();
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fair::{fixed_vertices, tubes};

    #[test]
    fn blocks_cover_free_vertices_and_overlap() {
        let mesh = tubes(3, 4, 3).unwrap();
        let topo = MeshTopology::new(&mesh).unwrap();
        let fixed = fixed_vertices(&topo, 3, &[]).unwrap();
        let free = fixed.iter().filter(|&&f| !f).count();
        let plain = voronoi_blocks(&topo, &fixed, 6, 0).unwrap();
        // Without overlap the regions partition the free vertices.
        assert_eq!(plain.iter().map(Vec::len).sum::<usize>(), free);
        let wide = voronoi_blocks(&topo, &fixed, 6, 2).unwrap();
        let mut covered = vec![0; mesh.vertex_count()];
        for (b, block) in wide.iter().enumerate() {
            assert!(plain[b].iter().all(|v| block.binary_search(v).is_ok()));
            for &v in block {
                assert!(!fixed[v as usize]);
                covered[v as usize] += 1;
            }
        }
        assert!((0..mesh.vertex_count()).all(|v| fixed[v] || covered[v] >= 1));
        assert!(covered.iter().any(|&c| c >= 2));
        assert!(voronoi_blocks(&topo, &fixed, 0, 1).is_err());
        assert!(voronoi_blocks(&topo, &fixed, free + 1, 1).is_err());
        assert_eq!(voronoi_blocks(&topo, &fixed, free, 0).unwrap().len(), free);
    }
}
