//! Reports for people: pictures (PNG) of meshes coloured by per-vertex quality, with a
//! title and a colour bar, and self-contained HTML pages with an interactive viewer.

mod annotate;
mod figures;
pub mod html;
mod render;

pub use annotate::{colour_bar_box, colour_of, label};
pub use figures::write_figures;
pub use render::{
    best_view, color_range, diverging_color, finite_extent, paired_color_range, render_png,
    render_rgb, RenderOptions, BACKGROUND,
};
