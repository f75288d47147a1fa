//! The functional F = S + c Q (paper eq. 2–5): the densities of S and Q, the scalars they
//! are written over (automatic differentiation), their assembly into F, its gradient and
//! Hessian, and the before/after figures measured with it.

pub(crate) mod evaluation;
pub(crate) mod q_density;
pub(crate) mod s_density;
pub(crate) mod statistics;
pub(crate) mod tangent;
