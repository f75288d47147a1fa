//! Curvature samples of the G² surface: a (K + 1) × (K + 1) grid per internal face with
//! the mean curvature as quality — the Catmull–Clark limit samples' layout and rules
//! (`subdiv::sample`), so the pictures, `--samples` files and HTML reports show the surface
//! that was optimized.

use super::surface::G2Surface;
use crate::error::{Error, Result};
use crate::fair::MeshTopology;
use crate::limits::MemoryBudget;
use crate::mesh::PolygonMesh;
use crate::subdiv::{assemble, grid_points, grid_samples, LimitSamples, MAX_SAMPLES};

/// Samples `mesh`'s G² surface on a `samples` × `samples` grid per internal face.
///
/// # Errors
/// [`Error::InvalidInput`] for `samples` out of 1..=256; errors of [`G2Surface::new`].
pub fn g2_samples(mesh: &PolygonMesh, samples: u32, memory: MemoryBudget) -> Result<LimitSamples> {
    if !(1..=MAX_SAMPLES).contains(&samples) {
        return Err(Error::InvalidInput(format!(
            "samples = {samples}; it must be between 1 and {MAX_SAMPLES}"
        )));
    }
    let topo = MeshTopology::new(mesh)?;
    let surface = G2Surface::new(mesh, &topo.boundary, &topo.special_flags(), memory)?;
    let grid = grid_points(samples);
    let faces = (0..mesh.face_count())
        .filter_map(|f| surface.evaluate(f, &mesh.positions, &grid))
        .map(|derivatives| grid_samples(samples, &derivatives));
    Ok(assemble(faces, samples))
}
