//! Reports for people: pictures (PNG) of meshes coloured by per-vertex quality.

mod render;

pub use render::{color_range, diverging_color, render_png, render_rgb, RenderOptions};
