//! The three-tube junction generator: counts of the author's mesh (issue 6), χ, manifold and
//! consistently oriented, one boundary loop per tube end, special vertices.

use std::collections::HashMap;

use surfkit::fair::{condition_violation, fixed_vertices, tubes, MeshTopology};

#[test]
fn fair_tubes_author_mesh_counts() {
    let mesh = tubes(3, 4, 3).unwrap();
    assert_eq!(mesh.vertex_count(), 359);
    assert_eq!(mesh.face_count(), 336);
    assert!(mesh.faces().all(|f| f.len() == 4));
    let topo = MeshTopology::new(&mesh).unwrap();
    // Genus 0 with three boundary loops: χ = 2 − 3.
    assert_eq!(topo.euler_characteristic(), -1);
    assert_eq!(topo.boundary_vertices().len(), 48);
    let special = topo.special_vertices();
    assert_eq!(special.len(), 2);
    assert!(special.iter().all(|&v| topo.valence(v as usize) == 6));
    assert!(condition_violation(&mesh, &topo).is_none());
    // Every directed edge at most once: orientable and consistently oriented.
    let mut directed: HashMap<(u32, u32), u32> = HashMap::new();
    for f in mesh.faces() {
        for c in 0..4 {
            *directed.entry((f[c], f[(c + 1) % 4])).or_insert(0) += 1;
        }
    }
    assert!(directed.values().all(|&n| n == 1));
    // Three boundary loops of 16 vertices: boundary edges form cycles, count components.
    let boundary_edges: Vec<(u32, u32)> = directed
        .keys()
        .filter(|&&(a, b)| !directed.contains_key(&(b, a)))
        .copied()
        .collect();
    assert_eq!(boundary_edges.len(), 48);
    let next: HashMap<u32, u32> = boundary_edges.iter().copied().collect();
    let mut seen = std::collections::HashSet::new();
    let mut loops = Vec::new();
    for &(a, _) in &boundary_edges {
        if seen.contains(&a) {
            continue;
        }
        let (mut v, mut len) = (a, 0);
        while seen.insert(v) {
            v = next[&v];
            len += 1;
        }
        loops.push(len);
    }
    assert_eq!(loops, vec![16, 16, 16]);
}

#[test]
fn fair_tubes_figure_7_mesh() {
    let mesh = tubes(3, 8, 2).unwrap();
    assert_eq!(mesh.vertex_count(), 1007);
    let topo = MeshTopology::new(&mesh).unwrap();
    assert_eq!(topo.euler_characteristic(), -1);
    let fixed = fixed_vertices(&topo, 3, &[]).unwrap();
    assert_eq!(fixed.iter().filter(|&&f| !f).count(), 719);
}

#[test]
fn fair_tubes_rejects_bad_arguments() {
    assert!(tubes(5, 4, 3).is_err());
    assert!(tubes(3, 0, 3).is_err());
}
