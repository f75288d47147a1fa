//! The representation of the surface the options choose ([`SurfaceKind`]), as one type
//! the functional and the solvers take.

use crate::error::Result;
use crate::fair::surface::g2::representation::G2Representation;
use crate::fair::surface::representation::{
    PatchRepresentation, QuadraturePoint, Representation, RepresentationOptions, SurfaceKind,
};
use crate::mesh::PolygonMesh;

/// Either surface's quadrature rows.
pub enum SurfaceRepresentation {
    CatmullClark(PatchRepresentation),
    G2(Box<G2Representation>),
}

impl SurfaceRepresentation {
    /// The rows of `mesh`'s surface of kind `options.surface`.
    ///
    /// # Errors
    /// Those of [`PatchRepresentation::new`] or [`G2Representation::new`].
    pub fn new(
        mesh: &PolygonMesh,
        boundary: &[bool],
        special: &[bool],
        options: &RepresentationOptions,
    ) -> Result<Self> {
        Ok(match options.surface {
            SurfaceKind::CatmullClark => SurfaceRepresentation::CatmullClark(
                PatchRepresentation::new(mesh, boundary, special, options)?,
            ),
            SurfaceKind::G2 => SurfaceRepresentation::G2(Box::new(G2Representation::new(
                mesh, boundary, special, options,
            )?)),
        })
    }
}

impl SurfaceRepresentation {
    /// The same mesh's surface under other `options` of the same kind (other nodes, say);
    /// the G² surface is not built again.
    ///
    /// # Errors
    /// As [`SurfaceRepresentation::new`].
    pub fn with_options(
        &self,
        mesh: &PolygonMesh,
        boundary: &[bool],
        special: &[bool],
        options: &RepresentationOptions,
    ) -> Result<Self> {
        match self {
            SurfaceRepresentation::G2(r) if options.surface == SurfaceKind::G2 => Ok(
                SurfaceRepresentation::G2(Box::new(r.with_options(options)?)),
            ),
            _ => Self::new(mesh, boundary, special, options),
        }
    }
}

impl Representation for SurfaceRepresentation {
    fn vertex_count(&self) -> usize {
        match self {
            SurfaceRepresentation::CatmullClark(r) => r.vertex_count(),
            SurfaceRepresentation::G2(r) => r.vertex_count(),
        }
    }
    fn points(&self) -> &[QuadraturePoint] {
        match self {
            SurfaceRepresentation::CatmullClark(r) => r.points(),
            SurfaceRepresentation::G2(r) => r.points(),
        }
    }
    fn element_count(&self) -> usize {
        match self {
            SurfaceRepresentation::CatmullClark(r) => r.element_count(),
            SurfaceRepresentation::G2(r) => r.element_count(),
        }
    }
}
