//! Kiciak's curvature-continuous surface (paper §3): bicubic B-spline patches for ordinary
//! elements and, for each special element (the Sabin net round a vertex of valence k ≠ 4),
//! k polynomial patches of degree (9, 9) over a planar domain Ω_k. [`domain_net`] (the
//! eigen-net, Ω_k's border and area), [`division_curve`] (the curves dividing Ω_k into the
//! k patch domains), [`sides`] (how a patch is joined along its four sides),
//! [`auxiliary`] (the patches along the division curves), [`junction`] (the domain patches
//! δ_s and the junction functions), [`space`] (the C² space V as linear conditions),
//! [`patch_matrix`] (the Ritz basis per valence), [`sabin_net`] (a special vertex's net in a
//! mesh), [`surface`] (the whole surface, face by face), [`samples`] (its curvature samples), [`bezier_export`] (its Bézier patches as
//! JSON), [`representation`] (its
//! quadrature rows for the optimizer), [`domain_derivatives`] (the inverse chain rule through
//! δ), [`polynomial`] and [`bernstein`] (Bernstein forms).

pub(crate) mod auxiliary;
pub(crate) mod bernstein;
pub(crate) mod bezier_export;
pub(crate) mod division_curve;
pub(crate) mod domain_derivatives;
pub(crate) mod domain_net;
pub(crate) mod junction;
pub(crate) mod patch_matrix;
pub(crate) mod polynomial;
pub(crate) mod representation;
pub(crate) mod sabin_net;
pub(crate) mod samples;
pub(crate) mod sides;
pub(crate) mod space;
pub(crate) mod surface;
