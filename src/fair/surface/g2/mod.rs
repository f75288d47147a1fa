//! Kiciak's curvature-continuous surface (paper §3): bicubic B-spline patches for ordinary
//! elements and, for each special element (the Sabin net round a vertex of valence k ≠ 4),
//! k polynomial patches of degree (9, 9) over a planar domain Ω_k. Built so far: the domain
//! net and Ω_k's boundary and area ([`domain_net`]), the curves that divide Ω_k into the k
//! patch domains ([`division_curve`]).

pub(crate) mod division_curve;
pub(crate) mod domain_net;
