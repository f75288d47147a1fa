//! The variational problems of the Kouibia–Pasadas papers, written against
//! `spline::Space`: the generalized offset (2022 (3)), the discrete smoothing spline
//! (2022 §3, 2024 §3), hole filling with boundary constraints (2022 §4), shape-preserving
//! filling (2024 §4), fitting with parallelism conditions (2004 §4) and the
//! reproductions of the papers' tables. Each entry point is a function of inputs and an
//! options struct that returns the solved spline and a report.

pub mod data;
pub mod expr;
pub mod fill;
pub mod hole;
mod hole_border;
pub mod offset;
pub mod papers;
pub mod parallel;
pub mod pipeline;
pub mod sample;
pub mod shape;
pub mod smoothing;
pub mod surface;

pub use fill::{fill_hole, FillOptions, FillReport, FillVariant, HoleFill};
pub use hole::{Hole, HoleShape};
pub use offset::{unit_normal, GeneralizedOffset, ParametricSurface};
pub use parallel::{parallel_fit, ParallelFit, ParallelOptions};
pub use smoothing::{smoothing_spline, DerivativeData, SmoothingFit, SmoothingOptions};
pub use surface::VectorSpline;
