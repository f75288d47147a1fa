//! A small test shape: a disc of quads around one vertex of any valence (a Sabin net,
//! paper §3), lifted onto a smooth non-symmetric height field so that F has work to do.

use crate::error::{Error, Result};
use crate::mesh::PolygonMesh;

/// A disc of `valence` sectors, each a `rings` × `rings` grid of quads, around a centre
/// vertex (vertex 0) of the given valence; planar coordinates on a skewed polar grid of
/// unit radius per ring, height `z = 0.1 (x² − 0.5 y²) + 0.05 x y + 0.02 x³`.
///
/// # Errors
/// [`Error::InvalidInput`] unless `valence ≥ 3` and `rings ≥ 1`.
pub fn sector_disc(valence: u32, rings: u32) -> Result<PolygonMesh> {
    if valence < 3 || rings == 0 {
        return Err(Error::InvalidInput(format!(
            "a sector disc needs valence ≥ 3 and rings ≥ 1 (got {valence}, {rings})"
        )));
    }
    let (k, r) = (valence, rings);
    // Vertex ids: 0 centre; then per sector s its spoke (i, 0), i = 1..=r; then the
    // interior (i, j), i, j = 1..=r.
    let spoke = |s: u32, i: u32| 1 + (s % k) * r + (i - 1);
    let interior = |s: u32, i: u32, j: u32| 1 + k * r + s * r * r + (i - 1) * r + (j - 1);
    let id = |s: u32, i: u32, j: u32| match (i, j) {
        (0, 0) => 0,
        (_, 0) => spoke(s, i),
        (0, _) => spoke(s + 1, j),
        _ => interior(s, i, j),
    };
    let nv = 1 + k * r + k * r * r;
    let mut positions = vec![[0.0; 3]; nv as usize];
    let angle = |s: u32| 2.0 * std::f64::consts::PI * f64::from(s) / f64::from(k);
    for s in 0..k {
        let (a, b) = (angle(s), angle(s + 1));
        for i in 0..=r {
            for j in 0..=r {
                let (fi, fj) = (f64::from(i), f64::from(j));
                let x = fi * a.cos() + fj * b.cos();
                let y = fi * a.sin() + fj * b.sin();
                let z = 0.1 * (x * x - 0.5 * y * y) + 0.05 * x * y + 0.02 * x * x * x;
                positions[id(s, i, j) as usize] = [x, y, z];
            }
        }
    }
    let mut faces = Vec::new();
    for s in 0..k {
        for i in 0..r {
            for j in 0..r {
                faces.push([
                    id(s, i, j),
                    id(s, i + 1, j),
                    id(s, i + 1, j + 1),
                    id(s, i, j + 1),
                ]);
            }
        }
    }
    Ok(PolygonMesh::from_polygons(positions, &faces))
}
