//! Pages of the surface commands (`fair`, `limit`, `fill`): sampled surfaces coloured by one
//! quantity under one colour scale, side by side, with a colour bar; callers add overlays
//! (data points, a hole's border) and plots (the optimization log).

use super::page::{ColourBar, HtmlPage, Shading};
use super::scene::View;
use crate::mesh::PolygonMesh;
use crate::report::{best_view, color_range, RenderOptions};

/// A page of `panels` (name, sampled surface with per-vertex quality), all coloured under
/// one range — `range`, or the pictures' percentile range of all their values together —
/// so that they are compared colour for colour.
pub fn surface_page(
    title: &str,
    summary: Vec<(String, String)>,
    panels: &[(&str, &PolygonMesh)],
    quantity: &str,
    range: Option<(f64, f64)>,
) -> HtmlPage {
    let values: Vec<f64> = panels
        .iter()
        .flat_map(|(_, m)| m.quality.iter().flatten().copied())
        .collect();
    let range = range.unwrap_or_else(|| color_range(&values));
    // The view the pictures would choose for the first surface under this range.
    let initial_view = panels.first().map_or((35.0, 30.0), |(_, mesh)| {
        best_view(
            mesh,
            &RenderOptions {
                range: Some(range),
                ..RenderOptions::default()
            },
        )
    });
    let views = panels
        .iter()
        .map(|(name, mesh)| View::new(name, mesh))
        .collect();
    HtmlPage {
        title: title.to_string(),
        summary,
        text: None,
        shading: Shading::Smooth,
        initial_view,
        views,
        legend: Vec::new(),
        flaws: Vec::new(),
        colour_bar: ColourBar::new(quantity, &values, range),
        plot: None,
    }
}
