//! Kiciak's curvature-continuous surface as the optimizer sees it ([`Representation`]):
//! every face off the special vertices is the bicubic B-spline patch of its 4 × 4 net (an
//! ordinary element); the k faces round a special vertex are one special element, k
//! degree-(9, 9) patches given by the valence's patch matrix applied to the Sabin net.
//! At a special patch's quadrature points the derivatives are taken in Ω_k's coordinates
//! (through δ_s, weight |det Dδ_s|), where the paper integrates S and Q; S does not depend
//! on the parameterization, Q does.

use super::basis::bernstein::{bernstein_derivatives, COEFFICIENTS, ORDER};
use super::basis::domain_derivatives::InverseChainRule;
use super::basis::patch_matrix::{map_derivatives, PatchMatrix};
use super::sabin_net::SabinNet;
use super::surface::{FacePatch, G2Surface};
use crate::error::{Error, Result};
use crate::fair::surface::quadrature::gauss_legendre;
use crate::fair::surface::representation::{
    check_weights, push_bicubic_points, QuadraturePoint, Representation, RepresentationOptions,
    DERIVATIVES, DERIVATIVE_ORDERS,
};
use crate::fair::surface::shared_tables::SharedTables;
use crate::mesh::PolygonMesh;
use rayon::prelude::*;
use std::sync::Arc;

/// The G² surface's quadrature rows.
pub struct G2Representation {
    vertex_count: usize,
    element_count: usize,
    points: Vec<QuadraturePoint>,
    /// The surface the rows describe.
    pub surface: G2Surface,
}

/// Appends the quadrature points of sector `s`'s patch of the special element `net`.
fn push_special_points(
    points: &mut Vec<QuadraturePoint>,
    tables: &SharedTables,
    basis: &PatchMatrix,
    net: &SabinNet,
    s: usize,
    rule: &[(f64, f64)],
    c: f64,
) -> Result<()> {
    // (net index, mesh vertex) of the columns the surface depends on, in the net's order
    // (see `QuadraturePoint::vertices`)
    let columns: Vec<(usize, u32)> = net
        .vertices
        .iter()
        .enumerate()
        .filter_map(|(i, v)| v.map(|v| (i, v)))
        .collect();
    let vertices: Arc<[u32]> = columns.iter().map(|&(_, v)| v).collect();
    let domain = &basis.sectors[s];
    for &(u, wu) in rule {
        for &(v, wv) in rule {
            let chain = InverseChainRule::new(map_derivatives(domain, u, v)).ok_or_else(|| {
                Error::InvalidInput(format!(
                    "valence {}: domain patch {s} is singular at ({u}, {v})",
                    basis.k
                ))
            })?;
            let (bu, bv) = (bernstein_derivatives(u), bernstein_derivatives(v));
            // derivatives in Ω_k's coordinates of each Bézier basis function
            let rows: Vec<[f64; DERIVATIVES]> = (0..COEFFICIENTS)
                .map(|i| {
                    let (a, b) = (i / ORDER, i % ORDER);
                    chain.apply(&DERIVATIVE_ORDERS.map(|(ru, rv)| bu[ru][a] * bv[rv][b]))
                })
                .collect();
            let coefficients = columns
                .iter()
                .map(|&(column, _)| {
                    let mut d = [0.0; DERIVATIVES];
                    for (i, row) in rows.iter().enumerate() {
                        let m = basis.matrix[(s * COEFFICIENTS + i, column)];
                        if m != 0.0 {
                            for (x, r) in d.iter_mut().zip(row) {
                                *x += m * r;
                            }
                        }
                    }
                    d
                })
                .collect();
            let area = wu * wv * chain.jacobian;
            points.push(QuadraturePoint {
                weight_s: area,
                weight_q: area * c,
                vertices: Arc::clone(&vertices),
                coefficients: tables.share(coefficients),
            });
        }
    }
    Ok(())
}

impl G2Representation {
    /// Builds the rows of `mesh`'s G² surface ([`G2Surface`]). Elements are the internal
    /// quads (all corners off the boundary), as for the Catmull–Clark surface; a special
    /// element counts as its k faces. `options.nodes` Gauss–Legendre nodes per direction on
    /// every patch; Q weighted by `c_ordinary` on ordinary elements and `c_special` on
    /// special ones (`isolation`, `end_caps` and `q_domain` do not apply).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for a bad option; errors of [`G2Surface::new`].
    pub fn new(
        mesh: &PolygonMesh,
        boundary: &[bool],
        special: &[bool],
        options: &RepresentationOptions,
    ) -> Result<Self> {
        check_weights(options)?;
        let surface = G2Surface::new(mesh, boundary, special, options.memory)?;
        Self::on_surface(surface, mesh.vertex_count(), options)
    }

    /// The same surface's rows under other `options` (other nodes, say), without building
    /// the surface again.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for a bad option.
    pub fn with_options(&self, options: &RepresentationOptions) -> Result<Self> {
        check_weights(options)?;
        Self::on_surface(self.surface.clone(), self.vertex_count, options)
    }

    fn on_surface(
        surface: G2Surface,
        vertex_count: usize,
        options: &RepresentationOptions,
    ) -> Result<Self> {
        let rule = gauss_legendre(options.nodes)?;
        let tables = SharedTables::default();
        // Each element's points on its own (in parallel), concatenated in face order.
        let per_element = surface
            .faces
            .par_iter()
            .filter_map(Option::as_ref)
            .map(|patch| {
                let mut points = Vec::new();
                match patch {
                    FacePatch::Bicubic(rows) => push_bicubic_points(
                        &mut points,
                        &tables,
                        rows,
                        &rule,
                        1.0,
                        true,
                        options.c_ordinary,
                    ),
                    FacePatch::Special { element, sector } => push_special_points(
                        &mut points,
                        &tables,
                        &surface.bases[*element],
                        &surface.special_elements[*element],
                        *sector,
                        &rule,
                        options.c_special,
                    )?,
                }
                Ok(points)
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(G2Representation {
            vertex_count,
            element_count: per_element.len(),
            points: per_element.into_iter().flatten().collect(),
            surface,
        })
    }
}

impl Representation for G2Representation {
    fn vertex_count(&self) -> usize {
        self.vertex_count
    }
    fn points(&self) -> &[QuadraturePoint] {
        &self.points
    }
    fn element_count(&self) -> usize {
        self.element_count
    }
}
