//! Self-contained HTML reports: one file holding the report's data and a small WebGL
//! viewer, so that a person opens it in any browser, offline, and looks at the flaws or the
//! surface instead of reading numbers.
//!
//! The viewer is hand-written (`assets/viewer.js`, no third-party script): it draws one
//! indexed triangle buffer per view with WebGL 2 (32-bit indices, flat or smooth shading, a
//! colour map by per-vertex quality, isophotes and reflection lines in the fragment shader),
//! which is all a report needs; three.js would add its minified build (several hundred kB)
//! to every file and a bundler to the build, for the same single draw call per view.
//!
//! - `page`: the page model (views, overlays, flaw list, colour bar, plot) and the writer;
//! - `scene`: meshes and overlays as the compact arrays the viewer uploads;
//! - `eat_page`, `surface_page`: the pages of `surfkit eat` and of the surface commands.

mod eat_page;
mod page;
mod scene;
mod surface_page;

pub use eat_page::{eat_page, kind_colour};
pub use page::{
    html_escape, write_html, ColourBar, FlawEntry, HtmlPage, LegendEntry, Plot, Series, Shading,
};
pub use scene::{Highlight, Lines, MeshData, Points, View};
pub use surface_page::surface_page;
