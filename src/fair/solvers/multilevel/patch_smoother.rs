//! The V-cycle's smoother: additive Schwarz over vertex patches, Σ_p R_pᵀ A_pp⁻¹ R_p,
//! each patch a vertex with every vertex of its faces (its ring).
//!
//! Why patches rather than the 3 × 3 block diagonal: the slow modes of the block-Jacobi
//! V-cycle are tangential slides of the control mesh, which S (a geometric energy) does not
//! see and only c·Q restrains (a probe at the optima of the refined three-tube junctions:
//! ten times c lowered the residual after 100 iterations to 0.6 of it, a tenth of it
//! raised it sixfold). A slide that keeps the surface moves a vertex together with its ring, so a
//! smoother that relaxes one vertex at a time cannot reduce it, on any level: with patch
//! smoothing on every smoothed level the probe's residual after 50 iterations fell from
//! 1.9 to 6.7·10⁻⁴ at 54 143 free vertices (from 5.8·10⁻³ to 1.9·10⁻¹³ at 13 247), where
//! patches on the finest level alone reached only 1.4·10⁻² after 100
//! (docs/fairing-at-scale-log.md, twenty-fourth session).
//!
//! A patch per vertex made each V-cycle three times the block smoother's and its set-up
//! twice, more than the iterations saved (56k junction: 189.1 s against 138.5 s); a cover
//! of the vertices by a quarter of the patches, on the Newton steps alone (the
//! Levenberg–Marquardt solves, shifted, converge in a few block-smoothed iterations), is
//! what the solver uses ([`super::solver`]).

use rayon::prelude::*;

use super::block_csr::Prolongation;
use super::symmetric_csr::SymmetricCsr;
use crate::mesh::PolygonMesh;

/// A patch keeps at most this many vertices (the vertex first, then its ring in order): a
/// ring of valence 12 has 25; larger ones are cut, which only weakens the smoother there.
const MAX_PATCH_VERTICES: usize = 25;

/// The patches of one level, by vertex (unknown) index, with where each vertex's share of
/// the patch solutions lies.
#[derive(Debug)]
pub struct Patches {
    /// The last power iteration's vector on this level: the next set-up's bound starts
    /// there (the matrices of one run differ little).
    pub power_start: std::sync::Mutex<Option<Vec<f64>>>,
    start: Vec<usize>,
    vertices: Vec<u32>,
    /// Per vertex, the positions (in patch-vertex order, as `vertices`) of its copies.
    member_start: Vec<usize>,
    members: Vec<u32>,
}

impl Patches {
    /// Patches from lists of vertices, each list's first the patch's own vertex: those of
    /// a greedy cover (see [`cover`]).
    pub fn from_lists(lists: Vec<Vec<u32>>, vertex_count: usize) -> Self {
        let lists = cover(lists, vertex_count);
        let mut start = Vec::with_capacity(lists.len() + 1);
        start.push(0);
        let mut vertices = Vec::new();
        for list in lists {
            vertices.extend(list);
            start.push(vertices.len());
        }
        let mut member_start = vec![0usize; vertex_count + 1];
        for &v in &vertices {
            member_start[v as usize + 1] += 1;
        }
        for k in 0..vertex_count {
            member_start[k + 1] += member_start[k];
        }
        let mut next = member_start.clone();
        let mut members = vec![0u32; vertices.len()];
        for (position, &v) in vertices.iter().enumerate() {
            members[next[v as usize]] = position as u32;
            next[v as usize] += 1;
        }
        Patches {
            power_start: std::sync::Mutex::new(None),
            start,
            vertices,
            member_start,
            members,
        }
    }

    /// The finest level's patches: every free vertex with the free vertices of its faces.
    pub fn of_mesh(mesh: &PolygonMesh, free_index: &[u32], free_count: usize) -> Self {
        let mut lists: Vec<Vec<u32>> = vec![Vec::new(); free_count];
        for &i in free_index.iter().filter(|&&i| i != u32::MAX) {
            lists[i as usize].push(i);
        }
        for face in mesh.faces() {
            for &v in face {
                let i = free_index[v as usize];
                if i == u32::MAX {
                    continue;
                }
                for &w in face {
                    let j = free_index[w as usize];
                    if j != u32::MAX && j != i {
                        lists[i as usize].push(j);
                    }
                }
            }
        }
        for list in &mut lists {
            dedup_after_first(list);
        }
        Patches::from_lists(lists, free_count)
    }

    /// A coarse level's patches through the prolongation `p` into it: each coarse vertex
    /// with the coarse vertices of the stencil in which it weighs most, alone (its vertex
    /// point's, which reaches its ring).
    pub fn of_prolongation(p: &Prolongation) -> Self {
        let mut lists: Vec<Vec<u32>> = (0..p.coarse_count as u32).map(|c| vec![c]).collect();
        for i in 0..p.fine_count() {
            let row: Vec<(usize, f64)> = p.row(i).collect();
            let Some(&(top, weight)) = row.iter().max_by(|a, b| a.1.total_cmp(&b.1)) else {
                continue;
            };
            if row.iter().filter(|e| e.1 == weight).count() == 1 {
                lists[top].extend(
                    row.iter()
                        .map(|e| e.0 as u32)
                        .filter(|&c| c as usize != top),
                );
            }
        }
        for list in &mut lists {
            dedup_after_first(list);
        }
        Patches::from_lists(lists, p.coarse_count)
    }

    /// The most patches any vertex lies in: λ_max of the smoother's M⁻¹A where A is
    /// diagonal, and a floor of its estimate (a power iteration misses the few vertices
    /// around an extraordinary one, where the most patches overlap).
    pub fn most_overlapping(&self) -> usize {
        self.member_start
            .windows(2)
            .map(|w| w[1] - w[0])
            .max()
            .unwrap_or(0)
    }

    fn patch(&self, p: usize) -> &[u32] {
        &self.vertices[self.start[p]..self.start[p + 1]]
    }

    fn count(&self) -> usize {
        self.start.len() - 1
    }
}

/// The lists, each cut to [`MAX_PATCH_VERTICES`], whose own vertex no list kept before
/// holds: every vertex in a patch, with about a quarter of the patches on a refined mesh
/// (there the face points' 3 × 3 patches, overlapping by one row; a mesh's vertices come
/// from OpenSubdiv face points first). Measured against every vertex's patch, both on
/// every solve of the 14 399-vertex three-tube junction's run (2026-11-29): 81 CG
/// iterations against 99, at 0.043 s against 0.094 s each.
fn cover(lists: Vec<Vec<u32>>, vertex_count: usize) -> Vec<Vec<u32>> {
    let mut covered = vec![false; vertex_count];
    lists
        .into_iter()
        .filter_map(|mut list| {
            list.truncate(MAX_PATCH_VERTICES);
            let &own = list.first()?;
            if covered[own as usize] {
                return None;
            }
            for &v in &list {
                covered[v as usize] = true;
            }
            Some(list)
        })
        .collect()
}

/// Removes repeated entries of `list`, keeping its first in place and the rest sorted.
fn dedup_after_first(list: &mut Vec<u32>) {
    if list.len() > 1 {
        let first = list[0];
        list[1..].sort_unstable();
        list.dedup();
        list.retain(|&v| v != first);
        list.insert(0, first);
    }
}

/// The patches' Cholesky factors of one matrix A + shift·I: applies s Σ_p R_pᵀ A_pp⁻¹ R_p.
pub struct PatchSmoother {
    pub patches: std::sync::Arc<Patches>,
    /// Packed lower factors, row by row, from `factor_start[p]`.
    factor_start: Vec<usize>,
    factors: Vec<f64>,
}

impl PatchSmoother {
    /// The factors of `a` + `shift`·I on `patches`; `None` if a patch matrix is not
    /// positive definite.
    pub fn new(a: &SymmetricCsr, shift: f64, patches: std::sync::Arc<Patches>) -> Option<Self> {
        let mut factor_start = Vec::with_capacity(patches.count() + 1);
        factor_start.push(0);
        for p in 0..patches.count() {
            let m = 3 * patches.patch(p).len();
            factor_start.push(factor_start[p] + m * (m + 1) / 2);
        }
        let mut factors = vec![0.0; *factor_start.last().expect("starts at 0")];
        let mut slices = Vec::with_capacity(patches.count());
        let mut rest = factors.as_mut_slice();
        for p in 0..patches.count() {
            let (head, tail) = rest.split_at_mut(factor_start[p + 1] - factor_start[p]);
            slices.push(head);
            rest = tail;
        }
        let positive = slices.into_par_iter().enumerate().all(|(p, packed)| {
            gather_patch_matrix(a, shift, patches.patch(p), packed);
            cholesky_packed(packed, 3 * patches.patch(p).len())
        });
        positive.then_some(PatchSmoother {
            patches,
            factor_start,
            factors,
        })
    }

    /// s Σ_p R_pᵀ A_pp⁻¹ R_p r.
    pub fn apply(&self, r: &[f64], s: f64) -> Vec<f64> {
        let patches = &self.patches;
        let mut solutions = vec![0.0; 3 * patches.vertices.len()];
        let mut slices = Vec::with_capacity(patches.count());
        let mut rest = solutions.as_mut_slice();
        for p in 0..patches.count() {
            let (head, tail) = rest.split_at_mut(3 * (patches.start[p + 1] - patches.start[p]));
            slices.push(head);
            rest = tail;
        }
        slices.into_par_iter().enumerate().for_each(|(p, y)| {
            for (k, &v) in patches.patch(p).iter().enumerate() {
                y[3 * k..3 * k + 3].copy_from_slice(&r[3 * v as usize..3 * v as usize + 3]);
            }
            solve_packed(
                &self.factors[self.factor_start[p]..self.factor_start[p + 1]],
                y,
            );
        });
        let mut out = vec![0.0; r.len()];
        out.par_chunks_mut(3).enumerate().for_each(|(v, out)| {
            for &position in &patches.members[patches.member_start[v]..patches.member_start[v + 1]]
            {
                let k = 3 * position as usize;
                for a in 0..3 {
                    out[a] += s * solutions[k + a];
                }
            }
        });
        out
    }
}

/// The packed lower triangle of (A + shift·I) restricted to `vertices`, row by row.
fn gather_patch_matrix(a: &SymmetricCsr, shift: f64, vertices: &[u32], packed: &mut [f64]) {
    for (li, &i) in vertices.iter().enumerate() {
        for (lj, &j) in vertices.iter().enumerate().take(li + 1) {
            let block = a.block(i, j);
            for x in 0..3 {
                let row = 3 * li + x;
                for y in 0..3 {
                    let column = 3 * lj + y;
                    if column > row {
                        continue;
                    }
                    let mut value = block.map_or(0.0, |b| b[x][y]);
                    if row == column {
                        value += shift;
                    }
                    packed[row * (row + 1) / 2 + column] = value;
                }
            }
        }
    }
}

/// In place, the Cholesky factor L (A = L Lᵀ) of the packed lower triangle of an m × m
/// matrix; false unless positive definite. Hand-written for packed storage of tens of
/// thousands of matrices of at most 75 rows (not measured against faer's dense LLᵀ).
fn cholesky_packed(packed: &mut [f64], m: usize) -> bool {
    let at = |r: usize, c: usize| r * (r + 1) / 2 + c;
    for j in 0..m {
        let mut d = packed[at(j, j)];
        for k in 0..j {
            d -= packed[at(j, k)] * packed[at(j, k)];
        }
        if !(d > 0.0 && d.is_finite()) {
            return false;
        }
        let d = d.sqrt();
        packed[at(j, j)] = d;
        for i in j + 1..m {
            let mut t = packed[at(i, j)];
            for k in 0..j {
                t -= packed[at(i, k)] * packed[at(j, k)];
            }
            packed[at(i, j)] = t / d;
        }
    }
    true
}

/// y ← (L Lᵀ)⁻¹ y for the packed factor L.
fn solve_packed(packed: &[f64], y: &mut [f64]) {
    let m = y.len();
    let at = |r: usize, c: usize| r * (r + 1) / 2 + c;
    for i in 0..m {
        let row = &packed[at(i, 0)..at(i, i)];
        let t: f64 = row.iter().zip(&y[..i]).map(|(l, y)| l * y).sum();
        y[i] = (y[i] - t) / packed[at(i, i)];
    }
    for i in (0..m).rev() {
        y[i] /= packed[at(i, i)];
        let yi = y[i];
        for (k, yk) in y[..i].iter_mut().enumerate() {
            *yk -= packed[at(i, k)] * yi;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packed_cholesky_solves_as_the_dense_matrix() {
        // A = B Bᵀ + I for a fixed B: solve, then multiply back.
        let m = 7;
        let b: Vec<f64> = (0..m * m)
            .map(|k| ((k * 37 % 11) as f64 - 5.0) / 3.0)
            .collect();
        let dense: Vec<Vec<f64>> = (0..m)
            .map(|i| {
                (0..m)
                    .map(|j| {
                        (0..m).map(|k| b[i * m + k] * b[j * m + k]).sum::<f64>()
                            + f64::from(u8::from(i == j))
                    })
                    .collect()
            })
            .collect();
        let mut packed: Vec<f64> = (0..m)
            .flat_map(|i| (0..=i).map(|j| dense[i][j]).collect::<Vec<_>>())
            .collect();
        assert!(cholesky_packed(&mut packed, m));
        let rhs: Vec<f64> = (0..m).map(|i| (i as f64).sin() + 0.5).collect();
        let mut x = rhs.clone();
        solve_packed(&packed, &mut x);
        for i in 0..m {
            let back: f64 = (0..m).map(|j| dense[i][j] * x[j]).sum();
            assert!((back - rhs[i]).abs() < 1e-10, "{back} {}", rhs[i]);
        }
    }

    #[test]
    fn an_indefinite_patch_matrix_is_refused() {
        // [[1, 2], [2, 1]] has eigenvalues 3 and −1.
        let mut packed = vec![1.0, 2.0, 1.0];
        assert!(!cholesky_packed(&mut packed, 2));
    }

    #[test]
    fn every_vertex_finds_its_copies() {
        // A path 0 – 1 – 2 – 3 – 4, each vertex's list with its neighbours: the cover keeps
        // the patches of 0, 2 and 4.
        let lists = (0..5u32)
            .map(|v| {
                std::iter::once(v)
                    .chain([v.wrapping_sub(1), v + 1].into_iter().filter(|&w| w < 5))
                    .collect()
            })
            .collect();
        let patches = Patches::from_lists(lists, 5);
        assert_eq!(patches.count(), 3);
        let copies = |v: usize| {
            patches.members[patches.member_start[v]..patches.member_start[v + 1]]
                .iter()
                .map(|&k| patches.vertices[k as usize])
                .collect::<Vec<_>>()
        };
        assert_eq!(copies(0), vec![0]);
        assert_eq!(copies(1), vec![1, 1]);
        assert_eq!(copies(2), vec![2]);
        assert_eq!(copies(3), vec![3, 3]);
        assert_eq!(copies(4), vec![4]);
        assert_eq!(patches.most_overlapping(), 2);
    }
}
