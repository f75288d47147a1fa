//! The page model of an HTML report and the writer that embeds it, with the viewer, in one
//! file.

use std::path::Path;

use serde::Serialize;

use super::scene::View;
use crate::error::Result;
use crate::mesh::io::write_atomically;
use crate::report::{colour_of, finite_extent};

const TEMPLATE: &str = include_str!("assets/page.html");
const STYLE: &str = include_str!("assets/viewer.css");
const SCRIPT: &str = include_str!("assets/viewer.js");

/// How surfaces are lit: flat shading shows a polygon mesh's facets (and flaws in them);
/// smooth shading with per-vertex normals shows a sampled surface, and is what isophotes and
/// reflection lines need.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Shading {
    Flat,
    Smooth,
}

/// The colour bar of the views' quality: its labels are the quality's minimum and maximum,
/// each drawn in the colour `range` gives it (as the PNG pictures' bar).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ColourBar {
    pub quantity: String,
    pub min: f64,
    pub max: f64,
    /// The values mapped to the ends of the colour map.
    pub range: (f64, f64),
    /// `min` and `max` as the PNG bar prints them.
    pub min_label: String,
    pub max_label: String,
}

impl ColourBar {
    /// The bar of `values` (non-finite ones skipped) coloured under `range`.
    pub fn new(quantity: &str, values: &[f64], range: (f64, f64)) -> Option<Self> {
        let (min, max) = finite_extent(values)?;
        Some(ColourBar {
            quantity: quantity.to_string(),
            min,
            max,
            range,
            min_label: crate::report::label(min),
            max_label: crate::report::label(max),
        })
    }
}

/// One entry of the flaw list: what the viewer centres on when it is clicked.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FlawEntry {
    /// Index in the `--json` report's `flaws`.
    pub index: usize,
    pub kind: String,
    pub description: String,
    pub fix: String,
    pub fix_verified: Option<bool>,
    /// Representative point, in the view's coordinates (the mesh's, less the view origin).
    pub position: [f64; 3],
    /// Radius of the flaw's elements around `position` (what the camera frames).
    pub radius: f64,
    pub faces: Vec<u32>,
    pub vertices: Vec<u32>,
    /// The vertices are a closed boundary loop, drawn as lines.
    pub closed_loop: bool,
}

/// A legend line: a flaw kind (or overlay) and its colour.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LegendEntry {
    pub name: String,
    pub colour: [u8; 3],
    pub count: usize,
}

/// A line plot (the optimization log), drawn as SVG by the page.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Plot {
    pub title: String,
    pub x_label: String,
    /// Logarithmic y axis (values ≤ 0 are left out).
    pub log_y: bool,
    pub series: Vec<Series>,
}

/// One curve of a [`Plot`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Series {
    pub name: String,
    pub colour: [u8; 3],
    pub x: Vec<f64>,
    pub y: Vec<f64>,
}

/// A whole report page.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HtmlPage {
    pub title: String,
    /// Key–value lines shown at the top of the side panel.
    pub summary: Vec<(String, String)>,
    /// Preformatted text (the command's text summary), shown folded.
    pub text: Option<String>,
    pub shading: Shading,
    /// Azimuth and elevation (degrees, z up) of the first view, as the PNG pictures'.
    pub initial_view: (f64, f64),
    /// Side by side, one camera for all.
    pub views: Vec<View>,
    pub legend: Vec<LegendEntry>,
    pub flaws: Vec<FlawEntry>,
    pub colour_bar: Option<ColourBar>,
    pub plot: Option<Plot>,
}

/// The colour map the pictures use, as 256 RGB entries (the viewer's lookup texture), so the
/// page and the PNG give a value the same colour.
fn colour_map() -> Vec<[u8; 3]> {
    (0..256)
        .map(|i| colour_of(i as f64 / 255.0, (0.0, 1.0)))
        .collect()
}

/// JSON safe inside a `<script>` element: every `<` written `\u003c` (valid JSON in any
/// string), so that a `</script>` or `<!--` in a description cannot end or confuse it.
fn script_safe_json(value: &impl Serialize) -> Result<String> {
    let json = serde_json::to_string(value).map_err(|e| {
        crate::error::Error::InvalidInput(format!("HTML report: cannot encode the page: {e}"))
    })?;
    Ok(json.replace('<', "\\u003c"))
}

/// Writes `page` as one self-contained HTML file (atomically: the old file or the whole new
/// one, never part of it).
pub fn write_html(path: &Path, page: &HtmlPage) -> Result<()> {
    #[derive(Serialize)]
    struct Embedded<'a> {
        page: &'a HtmlPage,
        colour_map: Vec<[u8; 3]>,
        generator: String,
    }
    let data = script_safe_json(&Embedded {
        page,
        colour_map: colour_map(),
        generator: format!("surfkit {}", env!("CARGO_PKG_VERSION")),
    })?;
    let title = html_escape(&page.title);
    let (head, rest) = TEMPLATE
        .split_once("{{DATA}}")
        .expect("page.html holds {{DATA}}");
    write_atomically(path, |out| {
        let head = head
            .replace("{{TITLE}}", &title)
            .replace("{{STYLE}}", STYLE);
        out.write_all(head.as_bytes())?;
        out.write_all(data.as_bytes())?;
        out.write_all(rest.replace("{{SCRIPT}}", SCRIPT).as_bytes())
    })
}

/// Text made safe between HTML tags.
pub fn html_escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_closing_script_tag_in_the_data_cannot_end_the_script() {
        let json = script_safe_json(&"flaw </script><script>alert(1)").unwrap();
        assert!(!json.contains("</"));
        let back: String = serde_json::from_str(&json).unwrap();
        assert_eq!(back, "flaw </script><script>alert(1)");
    }

    #[test]
    fn the_colour_map_is_the_pictures() {
        let map = colour_map();
        assert_eq!(map.len(), 256);
        assert_eq!(map[0], crate::report::colour_of(0.0, (0.0, 1.0)));
        assert_eq!(map[255], crate::report::colour_of(1.0, (0.0, 1.0)));
    }
}
