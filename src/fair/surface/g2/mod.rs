//! Kiciak's curvature-continuous surface (paper §3): bicubic B-spline patches for ordinary
//! elements and, for each special element (the Sabin net round a vertex of valence k ≠ 4),
//! k polynomial patches of degree (9, 9) over a planar domain Ω_k. [`basis`] builds the
//! special element of each valence (the patch matrix); the rest applies it to a mesh:
//! [`sabin_net`] (a special vertex's net in the mesh), [`surface`] (the whole surface,
//! face by face), [`representation`] (its quadrature rows for the optimizer), [`samples`]
//! (its curvature samples) and [`bezier_export`] (its Bézier patches as JSON).

pub(crate) mod basis;
pub(crate) mod bezier_export;
pub(crate) mod representation;
pub(crate) mod sabin_net;
pub(crate) mod samples;
pub(crate) mod surface;
