//! The reproductions of the papers' tables and figures, one file per paper: each builds
//! the paper's problem from its text, runs the solvers of [`crate::fit`] on it and
//! returns the rows the paper prints, so that `surfkit paper` and the tests can compare.

pub mod kp2004;
pub mod kp2022;
pub mod kpo2024;
