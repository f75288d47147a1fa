//! The fairing of subdivision surfaces (Kiciak): the functional and its derivatives, both surfaces,
//! and the solvers against each other and against finite differences.

mod blocks;
#[path = "../common/mod.rs"]
mod common;
mod derivatives;
mod g2_basis;
mod g2_domain;
mod g2_surface;
mod multilevel;
mod optimize;
mod prepare;
mod q_domain;
mod special_elements;
mod tubes;
