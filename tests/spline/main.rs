//! The Kouibia–Pasadas spline problems: shape-preserving fill and the 2004 paper's figures.

mod fill_shape;
mod kp2004_figures;
