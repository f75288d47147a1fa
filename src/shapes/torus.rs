//! A torus sampled on a regular grid: closed, genus 1, any size — the large inputs of the
//! benches (10k to millions of faces) are generated, not stored.

use crate::mesh::PolygonMesh;

/// A torus (radii 3 and 1) of `nu × nv` vertices: `nu · nv` quads, or twice as many
/// triangles when `triangles` is set.
pub fn grid_torus(nu: u32, nv: u32, triangles: bool) -> PolygonMesh {
    let mut positions = Vec::with_capacity((nu * nv) as usize);
    for i in 0..nu {
        for j in 0..nv {
            let (a, b) = (
                std::f64::consts::TAU * f64::from(i) / f64::from(nu),
                std::f64::consts::TAU * f64::from(j) / f64::from(nv),
            );
            let r = 3.0 + b.cos();
            positions.push([r * a.cos(), r * a.sin(), b.sin()]);
        }
    }
    let mut mesh = PolygonMesh {
        positions,
        ..Default::default()
    };
    let faces = (nu * nv) as usize * if triangles { 2 } else { 1 };
    mesh.face_offsets.reserve(faces);
    mesh.face_indices
        .reserve(faces * if triangles { 3 } else { 4 });
    let id = |i: u32, j: u32| (i % nu) * nv + (j % nv);
    for i in 0..nu {
        for j in 0..nv {
            let (p, q, r, s) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if triangles {
                mesh.push_face(&[p, q, r]);
                mesh.push_face(&[p, r, s]);
            } else {
                mesh.push_face(&[p, q, r, s]);
            }
        }
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_of_a_closed_genus_one_grid() {
        let m = grid_torus(12, 8, true);
        assert_eq!((m.vertex_count(), m.face_count()), (96, 192));
        let q = grid_torus(12, 8, false);
        assert_eq!(q.face_count(), 96);
    }
}
