//! What the optimization changed, in the paper's terms: S (eq. 2–3) and the spread of the
//! mean curvature H before and after, measured on the same quadrature as the optimizer
//! (one source of truth for "the mean curvature is more even"), for summaries and reports.

use crate::error::{Error, Result};
use crate::fair::{
    fixed_vertices, FairOptions, Functional, MeshTopology, Representation, SurfaceRepresentation,
};
use crate::mesh::PolygonMesh;

/// S and the area-weighted mean and standard deviation of H, before and after.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ShapeChange {
    pub s_before: f64,
    pub s_after: f64,
    pub mean_h_before: f64,
    pub mean_h_after: f64,
    pub std_h_before: f64,
    pub std_h_after: f64,
}

/// S and the statistics of H (area-weighted over the quadrature points where S is
/// integrated, see [`Functional::mean_curvature_statistics`]) of `prepared`, the mesh the
/// optimizer started from (after preparation), and of `optimized`, what it returned with
/// `options` and the constant `c` of eq. 4 (the report's).
///
/// # Errors
/// [`Error::InvalidInput`] if the two meshes do not have the same vertex count; errors of
/// the representation.
pub fn shape_change(
    prepared: &PolygonMesh,
    optimized: &PolygonMesh,
    options: &FairOptions,
    c: f64,
) -> Result<ShapeChange> {
    if prepared.vertex_count() != optimized.vertex_count() {
        return Err(Error::InvalidInput(format!(
            "the optimized mesh has {} vertices, the prepared input {}",
            optimized.vertex_count(),
            prepared.vertex_count()
        )));
    }
    let topo = MeshTopology::new(prepared)?;
    let fixed = fixed_vertices(&topo, options.boundary_rings, &options.fixed)?;
    let special = topo.special_flags();
    let rep =
        SurfaceRepresentation::new(prepared, &topo.boundary, &special, &options.representation)?;
    let functional = Functional::new(&rep, &fixed, c);
    Ok(ShapeChange::measured(
        &functional,
        &prepared.positions,
        &optimized.positions,
    ))
}

impl ShapeChange {
    /// S and the statistics of H under `functional` at `before` and `after`.
    pub fn measured<R: Representation>(
        functional: &Functional<'_, R>,
        before: &[[f64; 3]],
        after: &[[f64; 3]],
    ) -> ShapeChange {
        let s = [before, after].map(|x| functional.value(x).s);
        ShapeChange::with_s(functional, before, after, s)
    }

    /// [`ShapeChange::measured`] where S before and after (`s`) is known already.
    pub fn with_s<R: Representation>(
        functional: &Functional<'_, R>,
        before: &[[f64; 3]],
        after: &[[f64; 3]],
        [s_before, s_after]: [f64; 2],
    ) -> ShapeChange {
        let (mean_h_before, std_h_before) = functional.mean_curvature_statistics(before);
        let (mean_h_after, std_h_after) = functional.mean_curvature_statistics(after);
        ShapeChange {
            s_before,
            s_after,
            mean_h_before,
            mean_h_after,
            std_h_before,
            std_h_after,
        }
    }
}
