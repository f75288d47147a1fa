//! The basis of a special element of valence k, computed once per valence: the domain
//! net and Ω_k ([`domain_net`]), the division curves ([`division_curve`]) and their
//! auxiliary patches ([`auxiliary`]), how a patch's sides are joined ([`sides`]), the
//! domain patches δ_s with the junction functions ([`junction`]), the C² space V as linear
//! conditions ([`space`]), and its Ritz basis, the patch matrix ([`patch_matrix`]); with
//! the Bernstein forms ([`bernstein`], [`polynomial`]) and the inverse chain rule through δ
//! ([`domain_derivatives`]). The patch matrices are kept on disk between runs
//! ([`disk_cache`]).

pub(crate) mod auxiliary;
pub(crate) mod bernstein;
pub mod disk_cache;
pub(crate) mod division_curve;
pub(crate) mod domain_derivatives;
pub(crate) mod domain_net;
pub(crate) mod junction;
pub(crate) mod patch_matrix;
pub(crate) mod polynomial;
pub(crate) mod sides;
pub(crate) mod space;
