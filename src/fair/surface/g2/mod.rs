//! Kiciak's curvature-continuous surface (paper §3): bicubic B-spline patches for ordinary
//! elements and, for each special element (the Sabin net round a vertex of valence k ≠ 4),
//! k polynomial patches of degree (9, 9) over a planar domain Ω_k. Built so far: the domain
//! net and Ω_k's boundary and area ([`domain_net`]), the curves that divide Ω_k into the k
//! patch domains ([`division_curve`]), the degree-9 Bernstein basis with its derivatives
//! ([`bernstein`]) and the inverse chain rule that turns a patch's parametric derivatives
//! into derivatives in Ω_k's coordinates through a domain patch ([`domain_derivatives`]).

pub(crate) mod bernstein;
pub(crate) mod division_curve;
pub(crate) mod domain_derivatives;
pub(crate) mod domain_net;
