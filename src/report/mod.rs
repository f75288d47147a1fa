//! Reports for people: pictures (PNG) of meshes coloured by per-vertex quality.

mod figures;
mod render;

pub use figures::write_figures;
pub use render::{color_range, diverging_color, render_png, render_rgb, RenderOptions, BACKGROUND};
