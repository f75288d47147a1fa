//! Un-subdivision: recognizing a quad mesh as one Catmull–Clark refinement of a coarser
//! mesh, and the refinement's stencils — the coarse space of the multilevel solver.
//!
//! Why: a control mesh at production density is almost always a refinement (a designer's
//! cage subdivided, `gen tubes --refine`, [`prepare`](crate::fair::prepare)'s own
//! refinements), and Catmull–Clark refinement is the prolongation a curvature functional
//! wants: refining a coarse control mesh does not change its limit surface, so the coarse
//! space holds exactly the coarser surfaces, and its stencils reproduce cubics (a
//! fourth-order energy needs prolongation and restriction of orders summing past 4,
//! which linear interpolation does not give).
//!
//! Every quad of a refinement has one corner of each kind — a vertex point (V), an edge
//! point (E), the face point (F), an edge point — with V and F opposite. Colouring the
//! corners so, from one quad outwards, recovers the coarse mesh: its vertices are the V
//! corners, its faces the F corners with every quad around them present.

use std::collections::VecDeque;

use crate::fair::preparation::surface_refine::boundary_flags;

/// What a fine vertex is in the coarse mesh's refinement.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// A vertex point: a coarse vertex, moved.
    Vertex,
    /// An edge point: of the coarse edge between its two V neighbours.
    Edge,
    /// A face point: of the coarse face around it.
    Face,
}

/// Faces over `vertex_count` vertices (positions are not needed to coarsen).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FaceList {
    pub vertex_count: usize,
    pub faces: Vec<Vec<u32>>,
}

/// A mesh recognized as the refinement of a coarser one.
#[derive(Debug, Clone)]
pub struct Coarsening {
    /// The coarse mesh: a face per F vertex whose quads all exist.
    pub coarse: FaceList,
    /// Each fine vertex as a combination of coarse vertices: Catmull–Clark's rule where
    /// the coarse neighbourhood is complete, else the average of its nearest coarse
    /// vertices (a V vertex: itself).
    pub stencils: Vec<Vec<(u32, f64)>>,
}

/// Vertex → faces incidence, with the corner index.
struct Incidence {
    start: Vec<usize>,
    entries: Vec<(u32, u8)>,
}

impl Incidence {
    fn new(mesh: &FaceList) -> Self {
        let mut start = vec![0usize; mesh.vertex_count + 1];
        for f in &mesh.faces {
            for &v in f {
                start[v as usize + 1] += 1;
            }
        }
        for k in 0..mesh.vertex_count {
            start[k + 1] += start[k];
        }
        let mut next = start.clone();
        let mut entries = vec![(0, 0); start[mesh.vertex_count]];
        for (fi, f) in mesh.faces.iter().enumerate() {
            for (k, &v) in f.iter().enumerate() {
                entries[next[v as usize]] = (fi as u32, k as u8);
                next[v as usize] += 1;
            }
        }
        Incidence { start, entries }
    }

    fn of(&self, v: usize) -> &[(u32, u8)] {
        &self.entries[self.start[v]..self.start[v + 1]]
    }
}

/// The coarse mesh of `mesh`, if `mesh` has the connectivity of a Catmull–Clark
/// refinement (quads only, every quad V–E–F–E): `None` otherwise.
pub fn coarsen(mesh: &FaceList) -> Option<Coarsening> {
    if mesh.faces.is_empty() || mesh.faces.iter().any(|f| f.len() != 4) {
        return None;
    }
    let incidence = Incidence::new(mesh);
    let on_boundary = boundary_flags(mesh.faces.iter().map(Vec::as_slice), mesh.vertex_count);
    let mut roles: Vec<Option<Role>> = vec![None; mesh.vertex_count];
    let mut face_done = vec![false; mesh.faces.len()];
    for seed in 0..mesh.faces.len() {
        if face_done[seed] {
            continue;
        }
        // The four ways to colour the seed quad; keep one that colours its whole
        // component consistently, preferring coarse faces that are quads (a refined
        // quad mesh also reads as the refinement of its dual, with V and F swapped; only
        // internal F corners count, a boundary one has lost quads).
        let mut best: Option<(usize, Vec<Option<Role>>, Vec<bool>)> = None;
        for choice in 0..4 {
            let mut trial_roles = roles.clone();
            let mut trial_done = face_done.clone();
            let (v, f) = if choice < 2 { (0, 2) } else { (1, 3) };
            let (v, f) = if choice % 2 == 0 { (v, f) } else { (f, v) };
            if colour_component(
                mesh,
                &incidence,
                seed,
                [v, f],
                &mut trial_roles,
                &mut trial_done,
            ) {
                let odd_faces = (0..mesh.vertex_count)
                    .filter(|&x| {
                        roles[x].is_none()
                            && trial_roles[x] == Some(Role::Face)
                            && !on_boundary[x]
                            && incidence.of(x).len() != 4
                    })
                    .count();
                if best.as_ref().is_none_or(|b| odd_faces < b.0) {
                    best = Some((odd_faces, trial_roles, trial_done));
                }
            }
        }
        let (_, r, d) = best?;
        roles = r;
        face_done = d;
    }
    // Vertices on no face are coarse vertices of their own.
    let roles: Vec<Role> = roles
        .into_iter()
        .map(|r| r.unwrap_or(Role::Vertex))
        .collect();
    let mut coarse_id = vec![u32::MAX; mesh.vertex_count];
    let mut coarse_count = 0u32;
    for (v, role) in roles.iter().enumerate() {
        if *role == Role::Vertex {
            coarse_id[v] = coarse_count;
            coarse_count += 1;
        }
    }
    // The coarse face of each F vertex, in the fine faces' orientation: quad
    // (F, e_next, V, e_prev) is followed by the quad whose e_next is this one's e_prev.
    let mut coarse_face_of = vec![None; mesh.vertex_count];
    let mut faces = Vec::new();
    for v in 0..mesh.vertex_count {
        if roles[v] != Role::Face {
            continue;
        }
        let quads: Vec<[u32; 3]> = incidence
            .of(v)
            .iter()
            .map(|&(fi, k)| {
                let q = &mesh.faces[fi as usize];
                let k = k as usize;
                [q[(k + 1) % 4], q[(k + 2) % 4], q[(k + 3) % 4]]
            })
            .collect();
        let mut cycle = Vec::with_capacity(quads.len());
        let mut current = 0;
        for _ in 0..quads.len() {
            cycle.push(coarse_id[quads[current][1] as usize]);
            let e_prev = quads[current][2];
            match quads.iter().position(|q| q[0] == e_prev) {
                Some(next) => current = next,
                None => break,
            }
        }
        if cycle.len() == quads.len() && current == 0 && cycle.len() >= 3 {
            coarse_face_of[v] = Some(faces.len());
            faces.push(cycle);
        }
    }
    let coarse = FaceList {
        vertex_count: coarse_count as usize,
        faces,
    };
    let stencils = (0..mesh.vertex_count)
        .map(|v| {
            stencil(
                mesh,
                &incidence,
                &roles,
                &coarse_id,
                &coarse_face_of,
                &coarse,
                v,
            )
        })
        .collect();
    Some(Coarsening { coarse, stencils })
}

/// Colours the component of quad `seed` from its corners `v_f` = [V corner, F corner];
/// false on a contradiction.
fn colour_component(
    mesh: &FaceList,
    incidence: &Incidence,
    seed: usize,
    v_f: [usize; 2],
    roles: &mut [Option<Role>],
    done: &mut [bool],
) -> bool {
    let q = &mesh.faces[seed];
    let assign = |roles: &mut [Option<Role>], v: u32, role: Role| match roles[v as usize] {
        Some(r) => r == role,
        None => {
            roles[v as usize] = Some(role);
            true
        }
    };
    if !(assign(roles, q[v_f[0]], Role::Vertex)
        && assign(roles, q[v_f[1]], Role::Face)
        && assign(roles, q[(v_f[0] + 1) % 4], Role::Edge)
        && assign(roles, q[(v_f[0] + 3) % 4], Role::Edge))
    {
        return false;
    }
    let mut queue = VecDeque::from([seed]);
    while let Some(fi) = queue.pop_front() {
        if done[fi] {
            continue;
        }
        let q = &mesh.faces[fi];
        // A corner known to be V or F decides the quad.
        let Some(k) =
            (0..4).find(|&k| matches!(roles[q[k] as usize], Some(Role::Vertex) | Some(Role::Face)))
        else {
            continue;
        };
        let other = match roles[q[k] as usize] {
            Some(Role::Vertex) => Role::Face,
            _ => Role::Vertex,
        };
        let here = roles[q[k] as usize].expect("found");
        let pattern = [
            (k, here),
            ((k + 2) % 4, other),
            ((k + 1) % 4, Role::Edge),
            ((k + 3) % 4, Role::Edge),
        ];
        for (corner, role) in pattern {
            if !assign(roles, q[corner], role) {
                return false;
            }
        }
        done[fi] = true;
        // An edge point of a refinement lies on at most 4 quads.
        if q.iter()
            .any(|&v| roles[v as usize] == Some(Role::Edge) && incidence.of(v as usize).len() > 4)
        {
            return false;
        }
        queue.extend(
            q.iter()
                .flat_map(|&v| incidence.of(v as usize).iter().map(|&(f, _)| f as usize)),
        );
    }
    true
}

/// The stencil of fine vertex `v` over coarse vertices.
fn stencil(
    mesh: &FaceList,
    incidence: &Incidence,
    roles: &[Role],
    coarse_id: &[u32],
    coarse_face_of: &[Option<usize>],
    coarse: &FaceList,
    v: usize,
) -> Vec<(u32, f64)> {
    let quads = incidence.of(v);
    // The corners of v's quads at offset `d` from v.
    let around = |d: usize| -> Vec<u32> {
        let mut out: Vec<u32> = quads
            .iter()
            .map(|&(fi, k)| mesh.faces[fi as usize][(k as usize + d) % 4])
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    };
    let face_point = |f: u32| -> Option<Vec<(u32, f64)>> {
        coarse_face_of[f as usize].map(|cf| {
            let face = &coarse.faces[cf];
            let w = 1.0 / face.len() as f64;
            face.iter().map(|&c| (c, w)).collect()
        })
    };
    let average = |vs: &[u32]| -> Vec<(u32, f64)> {
        let w = 1.0 / vs.len() as f64;
        vs.iter().map(|&x| (coarse_id[x as usize], w)).collect()
    };
    let mut out = match roles[v] {
        Role::Face => face_point(v as u32).unwrap_or_else(|| average(&around(2))),
        Role::Edge => {
            let neighbours: Vec<u32> = around(1).into_iter().chain(around(3)).collect();
            let mut vs: Vec<u32> = neighbours
                .iter()
                .copied()
                .filter(|&x| roles[x as usize] == Role::Vertex)
                .collect();
            let mut fs: Vec<u32> = neighbours
                .iter()
                .copied()
                .filter(|&x| roles[x as usize] == Role::Face)
                .collect();
            vs.sort_unstable();
            vs.dedup();
            fs.sort_unstable();
            fs.dedup();
            let faces: Option<Vec<_>> = fs.iter().map(|&f| face_point(f)).collect();
            match faces {
                // E = (a + b + F₁ + F₂) / 4.
                Some(faces) if vs.len() == 2 && faces.len() == 2 && quads.len() == 4 => {
                    let mut s = vec![
                        (coarse_id[vs[0] as usize], 0.25),
                        (coarse_id[vs[1] as usize], 0.25),
                    ];
                    for face in faces {
                        s.extend(face.into_iter().map(|(c, w)| (c, 0.25 * w)));
                    }
                    s
                }
                _ => average(&vs),
            }
        }
        Role::Vertex => {
            let c = coarse_id[v];
            let edges = around(1);
            let diagonal = around(2);
            let n = quads.len();
            // Interior: as many edge neighbours as quads, every quad's coarse face whole.
            let faces: Option<Vec<_>> = diagonal.iter().map(|&f| face_point(f)).collect();
            let ring: Option<Vec<u32>> = edges
                .iter()
                .map(|&e| other_vertex(mesh, incidence, roles, e, v as u32))
                .collect();
            match (faces, ring) {
                (Some(faces), Some(ring))
                    if n >= 3 && edges.len() == n && faces.len() == n && ring.len() == n =>
                {
                    // V' = F̄/n + 2R̄/n + (n − 3)v/n, R̄ the mean of the edge midpoints.
                    let n = n as f64;
                    let mut s = vec![(c, (n - 3.0) / n + 1.0 / n)];
                    for e in ring {
                        s.push((coarse_id[e as usize], 1.0 / (n * n)));
                    }
                    for face in faces {
                        s.extend(face.into_iter().map(|(x, w)| (x, w / (n * n))));
                    }
                    s
                }
                _ => vec![(c, 1.0)],
            }
        }
    };
    // Merge repeated coarse vertices.
    out.sort_unstable_by_key(|e| e.0);
    let mut merged: Vec<(u32, f64)> = Vec::with_capacity(out.len());
    for (c, w) in out {
        match merged.last_mut() {
            Some(last) if last.0 == c => last.1 += w,
            _ => merged.push((c, w)),
        }
    }
    merged
}

/// The V neighbour of edge point `e` other than `v`.
fn other_vertex(
    mesh: &FaceList,
    incidence: &Incidence,
    roles: &[Role],
    e: u32,
    v: u32,
) -> Option<u32> {
    incidence
        .of(e as usize)
        .iter()
        .flat_map(|&(fi, k)| {
            let q = &mesh.faces[fi as usize];
            [q[(k as usize + 1) % 4], q[(k as usize + 3) % 4]]
        })
        .find(|&x| x != v && roles[x as usize] == Role::Vertex)
}

#[cfg(test)]
mod tests {
    use faer::linalg::solvers::Solve;
    use faer::{Mat, Side};

    use super::*;
    use crate::fair::{refine_surface, tubes, MeshTopology};
    use crate::mesh::PolygonMesh;
    use crate::subdiv::{refine_uniform, SubdivOptions};

    fn face_list(mesh: &PolygonMesh) -> FaceList {
        FaceList {
            vertex_count: mesh.vertex_count(),
            faces: mesh.faces().map(<[u32]>::to_vec).collect(),
        }
    }

    /// A cube with every vertex moved off symmetry (a stencil with a wrong weight cannot
    /// hide behind equal coordinates).
    fn cube() -> PolygonMesh {
        let positions = (0..8)
            .map(|k| {
                let b = |bit: usize| ((k >> bit) & 1) as f64;
                [
                    b(0) + 0.13 * (k as f64).sin(),
                    b(1) + 0.07 * (k as f64 * 1.7).cos(),
                    b(2) - 0.11 * (k as f64 * 0.6).sin(),
                ]
            })
            .collect();
        let faces = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        PolygonMesh::from_polygons(positions, &faces)
    }

    /// A triangular prism: two triangles, three quads (its refinement has F corners of
    /// valence 3).
    fn prism() -> PolygonMesh {
        let positions = vec![
            [0.0, 0.0, 0.0],
            [1.1, 0.1, 0.0],
            [0.2, 0.9, 0.1],
            [0.1, 0.0, 1.2],
            [1.0, 0.2, 1.0],
            [0.3, 1.1, 0.9],
        ];
        let faces: Vec<Vec<u32>> = vec![
            vec![0, 2, 1],
            vec![3, 4, 5],
            vec![0, 1, 4, 3],
            vec![1, 2, 5, 4],
            vec![2, 0, 3, 5],
        ];
        PolygonMesh::from_polygons(positions, &faces)
    }

    /// The largest residual of the least-squares fit of coarse positions c to the fine
    /// ones through the stencils (S c ≈ fine): zero only if the stencils are the refinement
    /// that made the fine mesh.
    fn stencil_residual(fine: &PolygonMesh, c: &Coarsening) -> f64 {
        let (m, n) = (fine.vertex_count(), c.coarse.vertex_count);
        let s = Mat::from_fn(m, n, |i, j| {
            c.stencils[i]
                .iter()
                .find(|e| e.0 as usize == j)
                .map_or(0.0, |e| e.1)
        });
        let x = Mat::from_fn(m, 3, |i, a| fine.positions[i][a]);
        let normal = s.transpose() * &s;
        let coarse = normal
            .llt(Side::Lower)
            .expect("full column rank")
            .solve(s.transpose() * &x);
        let r = &s * &coarse - &x;
        (0..m)
            .flat_map(|i| (0..3).map(move |a| (i, a)))
            .fold(0.0f64, |worst, (i, a)| worst.max(r[(i, a)].abs()))
    }

    #[test]
    fn a_refined_closed_mesh_coarsens_to_its_cage_and_opensubdiv_s_rules() {
        for (name, cage) in [("cube", cube()), ("prism", prism())] {
            let fine = refine_uniform(&cage, 1, &SubdivOptions::default()).unwrap();
            let c = coarsen(&face_list(&fine)).expect("a refinement");
            assert_eq!(c.coarse.vertex_count, cage.vertex_count(), "{name}");
            assert_eq!(c.coarse.faces.len(), cage.face_count(), "{name}");
            let mut sizes: Vec<usize> = c.coarse.faces.iter().map(Vec::len).collect();
            let mut expected: Vec<usize> = cage.faces().map(<[u32]>::len).collect();
            sizes.sort_unstable();
            expected.sort_unstable();
            assert_eq!(sizes, expected, "{name}");
            // Every fine vertex of a closed refinement has its whole Catmull–Clark rule.
            let residual = stencil_residual(&fine, &c);
            assert!(residual < 1e-12, "{name}: residual {residual:e}");
            for s in &c.stencils {
                assert!((s.iter().map(|e| e.1).sum::<f64>() - 1.0).abs() < 1e-14);
            }
        }
    }

    #[test]
    fn the_author_s_refinement_coarsens_to_the_internal_vertices() {
        // `refine_surface` drops the boundary ring: the V corners are the coarse mesh's
        // internal vertices, and the fine vertices whose whole rule is present fit it.
        let cage = tubes(3, 4, 3).unwrap();
        let fine = refine_surface(&cage, 1).unwrap();
        let c = coarsen(&face_list(&fine)).expect("a refinement");
        let boundary = MeshTopology::new(&cage).unwrap().boundary;
        let boundary_count = boundary.iter().filter(|&&b| b).count();
        assert_eq!(c.coarse.vertex_count, cage.vertex_count() - boundary_count);
        // Its faces: the cage's faces without a boundary vertex.
        let internal_faces = cage
            .faces()
            .filter(|f| f.iter().all(|&v| !boundary[v as usize]))
            .count();
        assert_eq!(c.coarse.faces.len(), internal_faces);
    }

    #[test]
    fn a_mesh_that_is_no_refinement_is_refused() {
        // The cube's face diagonals join its four even corners pairwise: no V/F colouring.
        assert!(coarsen(&face_list(&cube())).is_none());
        assert!(coarsen(&face_list(&prism())).is_none(), "triangles");
    }
}
