//! Surface representations: how the optimized surface depends on the control vertices —
//! at each quadrature point of each element, its derivatives as fixed linear combinations
//! of control vertices (paper eq. 1) — and the samples that show it.

pub(crate) mod any_representation;
pub(crate) mod curvature_map;
pub(crate) mod g2;
pub(crate) mod quadrature;
pub(crate) mod representation;
pub(crate) mod shared_tables;
pub(crate) mod sub_representation;
