//! Procedural shapes surfkit builds itself: test models with a known topology and the
//! examples of the papers (the EAT stamp).

mod stamp;
mod torus;

pub use stamp::{stamp, StampFlaw, STAMP_STAGES};
pub use torus::grid_torus;
