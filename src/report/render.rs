//! PNG pictures of a mesh coloured by its per-vertex quality (curvature maps, fit errors),
//! for people who would rather look than read: a small z-buffered rasterizer with an
//! oblique view, Lambert shading and a blue–white–red colour map.

use crate::mesh::vector::{cross, dot};
use std::path::Path;

use super::annotate::{draw_colour_bar, draw_text};
use crate::error::{Error, Result};
use crate::mesh::io::write_atomically;
use crate::mesh::PolygonMesh;

/// Picture options.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderOptions {
    pub width: u32,
    pub height: u32,
    /// Quality values mapped to the ends of the colour map; `None` uses the 2nd and 98th
    /// percentiles, symmetric about 0 when the values change sign.
    pub range: Option<(f64, f64)>,
    /// Azimuth and elevation of the view direction, in degrees (with `auto_view`, the
    /// view taken unless another shows the quality's structure clearly better).
    pub azimuth: f64,
    pub elevation: f64,
    /// Choose the view that shows most of the coloured structure (see [`best_view`]).
    pub auto_view: bool,
    /// Drawn at the top left.
    pub title: Option<String>,
    /// The quality's name, drawn over the colour bar (a mesh with quality gets a bar).
    pub quantity: Option<String>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            width: 800,
            height: 600,
            range: None,
            azimuth: 35.0,
            elevation: 30.0,
            auto_view: true,
            title: None,
            quantity: None,
        }
    }
}

/// Background colour: dark, so that the white middle of the colour map stands out.
pub const BACKGROUND: [u8; 3] = [48, 48, 54];

/// The colour of `t` in [0, 1] on a diverging blue–white–red map.
pub fn diverging_color(t: f64) -> [f64; 3] {
    let t = t.clamp(0.0, 1.0);
    if t < 0.5 {
        let s = t / 0.5;
        [0.23 + 0.77 * s, 0.30 + 0.70 * s, 0.75 + 0.25 * s]
    } else {
        let s = (t - 0.5) / 0.5;
        [1.0 - 0.29 * s, 1.0 - 0.98 * s, 1.0 - 0.85 * s]
    }
}

/// The finite values among `values`, sorted (for quantiles).
fn sorted_finite(values: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut finite: Vec<f64> = values.filter(|v| v.is_finite()).collect();
    finite.sort_by(f64::total_cmp);
    finite
}

/// The q-quantile of sorted values (nearest rank); None when there are none.
fn quantile(sorted: &[f64], q: f64) -> Option<f64> {
    (!sorted.is_empty()).then(|| sorted[((sorted.len() - 1) as f64 * q).round() as usize])
}

/// The smallest and largest finite values (what a colour bar's ends are labelled with);
/// None when there are none.
pub fn finite_extent(values: &[f64]) -> Option<(f64, f64)> {
    values
        .iter()
        .copied()
        .filter(|q| q.is_finite())
        .fold(None, |m: Option<(f64, f64)>, q| {
            Some(m.map_or((q, q), |(lo, hi)| (lo.min(q), hi.max(q))))
        })
}

/// The value range used for colouring (see [`RenderOptions::range`]).
pub fn color_range(values: &[f64]) -> (f64, f64) {
    let finite = sorted_finite(values.iter().copied());
    let (Some(lo), Some(hi)) = (quantile(&finite, 0.02), quantile(&finite, 0.98)) else {
        return (0.0, 1.0);
    };
    if lo < 0.0 && hi > 0.0 {
        let m = lo.abs().max(hi);
        (-m, m)
    } else if hi > lo {
        (lo, hi)
    } else {
        (lo - 0.5, lo + 0.5)
    }
}

/// One colour range for a before/after pair (fairing) in which both pictures show
/// structure: centred on the "after" values' median (the surface's typical value, white),
/// half-width the after values' 98th-percentile deviation from it. The after picture then
/// spans the colour map (a joint percentile range, dominated by the before values, left it
/// uniformly pale); the before picture, on the same scale, is coloured where it is as
/// smooth as the result and saturates where it deviates more — what fairing removed.
pub fn paired_color_range(before: &[f64], after: &[f64]) -> (f64, f64) {
    let Some(centre) = quantile(&sorted_finite(after.iter().copied()), 0.5) else {
        return color_range(before);
    };
    let deviations = sorted_finite(after.iter().map(|v| (v - centre).abs()));
    let half = quantile(&deviations, 0.98).unwrap_or(0.0);
    if half > 0.0 {
        (centre - half, centre + half)
    } else {
        (centre - 0.5, centre + 0.5)
    }
}

/// Each vertex's pixel coordinates and depth, and the direction towards the viewer.
type Projected = (Vec<(f64, f64, f64)>, [f64; 3]);

/// The view of `mesh` from (azimuth, elevation) in degrees on a w × h screen.
fn project_view(
    mesh: &PolygonMesh,
    (azimuth, elevation): (f64, f64),
    w: usize,
    h: usize,
) -> Option<Projected> {
    let (lo, hi) = mesh.bounding_box()?;
    let (az, el) = (azimuth.to_radians(), elevation.to_radians());
    // View basis: right, up, towards the viewer.
    let toward = [el.cos() * az.cos(), el.cos() * az.sin(), el.sin()];
    let right = [-az.sin(), az.cos(), 0.0];
    let up = cross(toward, right);
    let center = [
        0.5 * (lo[0] + hi[0]),
        0.5 * (lo[1] + hi[1]),
        0.5 * (lo[2] + hi[2]),
    ];
    let radius =
        0.5 * ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2) + (hi[2] - lo[2]).powi(2)).sqrt();
    let scale = 0.95 * (w.min(h) as f64) / (2.0 * radius.max(f64::MIN_POSITIVE));
    let project = |p: &[f64; 3]| {
        let d = [p[0] - center[0], p[1] - center[1], p[2] - center[2]];
        (
            w as f64 / 2.0 + scale * dot(d, right),
            h as f64 / 2.0 - scale * dot(d, up),
            dot(d, toward),
        )
    };
    Some((mesh.positions.iter().map(project).collect(), toward))
}

/// Faces the view search rasterizes at most (every k-th face beyond): the score needs
/// the picture's proportions, not its detail.
const VIEW_SEARCH_FACES: usize = 40_000;

/// The view that shows most of the quality's structure: of 8 azimuths × 5 elevations
/// (and the requested view), the one whose small depth-tested picture holds the largest
/// sum of |t − t̃| over its pixels, t the colour-map coordinate and t̃ its median — how far
/// the colours stand out from the surface's typical colour (a hole's border, a saddle).
/// The requested view is kept unless another scores 10 % more, so pictures stay put where
/// they already show the feature.
pub fn best_view(mesh: &PolygonMesh, options: &RenderOptions) -> (f64, f64) {
    let requested = (options.azimuth, options.elevation);
    let Some(q) = &mesh.quality else {
        return requested;
    };
    let (lo, hi) = options.range.unwrap_or_else(|| color_range(q));
    let t = |v: f64| ((v - lo) / (hi - lo)).clamp(0.0, 1.0);
    let mut finite: Vec<f64> = q.iter().copied().filter(|v| v.is_finite()).map(t).collect();
    if finite.is_empty() {
        return requested;
    }
    let middle = finite.len() / 2;
    let typical = *finite.select_nth_unstable_by(middle, f64::total_cmp).1;
    let salience: Vec<f64> = q
        .iter()
        .map(|&v| {
            if v.is_finite() {
                (t(v) - typical).abs()
            } else {
                0.0
            }
        })
        .collect();
    let (w, h) = (96usize, 72usize);
    let stride = mesh.face_count().div_ceil(VIEW_SEARCH_FACES).max(1);
    let score = |view: (f64, f64)| {
        let Some((screen, _)) = project_view(mesh, view, w, h) else {
            return 0.0;
        };
        let mut depth = vec![f64::NEG_INFINITY; w * h];
        let mut seen = vec![0.0; w * h];
        for face in mesh.faces().step_by(stride).filter(|f| f.len() >= 3) {
            for k in 1..face.len() - 1 {
                let tri = [face[0] as usize, face[k] as usize, face[k + 1] as usize];
                fill_triangle(&screen, &tri, &mut depth, w, h, |px, b| {
                    seen[px] = (0..3).map(|i| b[i] * salience[tri[i]]).sum();
                });
            }
        }
        seen.iter().sum::<f64>()
    };
    let mut best = (requested, score(requested));
    let threshold = 1.1 * best.1;
    for elevation in [-60.0, -30.0, 0.0, 30.0, 60.0] {
        for a in 0..8 {
            let view = (45.0 * f64::from(a) + 22.5, elevation);
            let s = score(view);
            if s > best.1.max(threshold) {
                best = (view, s);
            }
        }
    }
    best.0
}

/// `options` with the colour range settled for `mesh` (computed once: it sorts every
/// quality value, and the view search, the colouring and the bar all need it).
fn with_range(mesh: &PolygonMesh, options: &RenderOptions) -> RenderOptions {
    RenderOptions {
        range: options
            .range
            .or_else(|| mesh.quality.as_deref().map(color_range)),
        ..options.clone()
    }
}

/// Renders `mesh` coloured by `mesh.quality` (grey without) into an RGB image, row-major.
pub fn render_rgb(mesh: &PolygonMesh, options: &RenderOptions) -> Vec<u8> {
    let options = &with_range(mesh, options);
    let (w, h) = (options.width as usize, options.height as usize);
    let mut image: Vec<u8> = BACKGROUND.iter().copied().cycle().take(w * h * 3).collect();
    let view = if options.auto_view {
        best_view(mesh, options)
    } else {
        (options.azimuth, options.elevation)
    };
    let Some((screen, toward)) = project_view(mesh, view, w, h) else {
        return image;
    };
    let (qlo, qhi) = options.range.unwrap_or((0.0, 1.0));
    let vertex_color = |v: usize| match &mesh.quality {
        Some(q) if q[v].is_finite() => diverging_color((q[v] - qlo) / (qhi - qlo)),
        _ => [0.75, 0.75, 0.75],
    };
    let mut depth = vec![f64::NEG_INFINITY; w * h];
    for face in mesh.faces() {
        if face.len() < 3 {
            continue;
        }
        // Face normal (Newell) for shading; both sides lit.
        let mut n = [0.0; 3];
        for k in 0..face.len() {
            let (p, q) = (
                mesh.positions[face[k] as usize],
                mesh.positions[face[(k + 1) % face.len()] as usize],
            );
            n[0] += (p[1] - q[1]) * (p[2] + q[2]);
            n[1] += (p[2] - q[2]) * (p[0] + q[0]);
            n[2] += (p[0] - q[0]) * (p[1] + q[1]);
        }
        let len = dot(n, n).sqrt();
        let light = if len > 0.0 {
            0.35 + 0.65 * (dot(n, toward) / len).abs()
        } else {
            0.35
        };
        for k in 1..face.len() - 1 {
            let tri = [face[0] as usize, face[k] as usize, face[k + 1] as usize];
            fill_triangle(&screen, &tri, &mut depth, w, h, |px, b| {
                let mut c = [0.0; 3];
                for (i, &v) in tri.iter().enumerate() {
                    let vc = vertex_color(v);
                    for ch in 0..3 {
                        c[ch] += b[i] * vc[ch];
                    }
                }
                for ch in 0..3 {
                    image[px * 3 + ch] = (255.0 * (c[ch] * light).clamp(0.0, 1.0)) as u8;
                }
            });
        }
    }
    image
}

/// Rasterizes one triangle with a depth test, calling `shade(pixel, barycentrics)`.
fn fill_triangle(
    screen: &[(f64, f64, f64)],
    tri: &[usize; 3],
    depth: &mut [f64],
    w: usize,
    h: usize,
    mut shade: impl FnMut(usize, [f64; 3]),
) {
    let [a, b, c] = tri.map(|i| screen[i]);
    let area = (b.0 - a.0) * (c.1 - a.1) - (c.0 - a.0) * (b.1 - a.1);
    if area.abs() < 1e-12 {
        return;
    }
    let x0 = a.0.min(b.0).min(c.0).floor().max(0.0) as usize;
    let x1 = (a.0.max(b.0).max(c.0).ceil() as usize).min(w.saturating_sub(1));
    let y0 = a.1.min(b.1).min(c.1).floor().max(0.0) as usize;
    let y1 = (a.1.max(b.1).max(c.1).ceil() as usize).min(h.saturating_sub(1));
    for y in y0..=y1 {
        for x in x0..=x1 {
            let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
            let wa = ((b.0 - px) * (c.1 - py) - (c.0 - px) * (b.1 - py)) / area;
            let wb = ((c.0 - px) * (a.1 - py) - (a.0 - px) * (c.1 - py)) / area;
            let wc = 1.0 - wa - wb;
            if wa < 0.0 || wb < 0.0 || wc < 0.0 {
                continue;
            }
            let z = wa * a.2 + wb * b.2 + wc * c.2;
            let i = y * w + x;
            if z > depth[i] {
                depth[i] = z;
                shade(i, [wa, wb, wc]);
            }
        }
    }
}

/// Writes the picture of [`render_rgb`] as a PNG, atomically.
///
/// # Errors
/// [`Error::Io`] when the file cannot be written; [`Error::InvalidInput`] for a zero size.
pub fn render_png(mesh: &PolygonMesh, path: &Path, options: &RenderOptions) -> Result<()> {
    if options.width == 0 || options.height == 0 {
        return Err(Error::InvalidInput(
            "a picture needs a width and height of at least 1".into(),
        ));
    }
    let options = &with_range(mesh, options);
    let mut image = render_rgb(mesh, options);
    let mut texts: Vec<(&str, String)> = Vec::new();
    if let Some(title) = &options.title {
        draw_text(
            &mut image,
            options.width as usize,
            8,
            8,
            title,
            [230, 230, 230],
        );
        texts.push(("Title", title.clone()));
    }
    let extent = finite_extent(mesh.quality.as_deref().unwrap_or(&[]));
    if let (Some(range), Some(extent)) = (options.range, extent) {
        let quantity = options.quantity.as_deref().unwrap_or("quality");
        draw_colour_bar(
            &mut image,
            options.width,
            options.height,
            extent,
            range,
            quantity,
        );
        // The labels in full precision, for programs that read the picture.
        texts.push(("surfkit:quantity", quantity.to_string()));
        texts.push((
            "surfkit:colour-bar",
            format!("{:e} {:e}", extent.0, extent.1),
        ));
        texts.push((
            "surfkit:colour-range",
            format!("{:e} {:e}", range.0, range.1),
        ));
    }
    write_atomically(path, |out| {
        let mut encoder = png::Encoder::new(out, options.width, options.height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        // iTXt (UTF-8): titles name files, quantities use mathematical signs.
        for (key, text) in &texts {
            encoder
                .add_itxt_chunk((*key).to_string(), text.clone())
                .map_err(std::io::Error::other)?;
        }
        let mut writer = encoder.write_header().map_err(std::io::Error::other)?;
        writer
            .write_image_data(&image)
            .map_err(std::io::Error::other)?;
        writer.finish().map_err(std::io::Error::other)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_paired_range_spans_the_after_values_and_saturates_the_before_values_beyond() {
        // before: wide undulations; after: small ones about another level
        let before: Vec<f64> = (0..1000)
            .map(|i| -1.0 + 4.0 * ((i as f64) * 0.1).sin())
            .collect();
        let after: Vec<f64> = (0..1000)
            .map(|i| -0.5 + 0.1 * ((i as f64) * 0.1).sin())
            .collect();
        let (lo, hi) = paired_color_range(&before, &after);
        let median_after = {
            let mut a = after.clone();
            a.sort_by(f64::total_cmp);
            a[500]
        };
        assert!((0.5 * (lo + hi) - median_after).abs() < 1e-12);
        let inside = |v: &f64| (lo..=hi).contains(v);
        assert!(after.iter().filter(|v| inside(v)).count() >= 980);
        // the after values' extremes reach the map's ends: sin's amplitude 0.1 about −0.5
        assert!((hi - lo - 0.2).abs() < 0.01, "[{lo}, {hi}]");
        // the before picture: coloured where it is as smooth, saturated on both sides
        assert!(before.iter().any(inside));
        assert!(before.iter().any(|&v| v < lo) && before.iter().any(|&v| v > hi));
    }

    #[test]
    fn colour_map_ends_and_middle() {
        assert_eq!(diverging_color(0.5), [1.0, 1.0, 1.0]);
        assert!(
            diverging_color(0.0)[2] > diverging_color(0.0)[0],
            "low values are blue"
        );
        assert!(
            diverging_color(1.0)[0] > diverging_color(1.0)[2],
            "high values are red"
        );
        assert_eq!(color_range(&[-1.0, 3.0, 0.5]), (-3.0, 3.0));
    }

    #[test]
    fn a_square_fills_the_middle_of_the_picture() {
        let mut m = PolygonMesh::from_polygons(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
            ],
            &[vec![0u32, 1, 2, 3]],
        );
        m.quality = Some(vec![1.0; 4]);
        let options = RenderOptions {
            width: 40,
            height: 40,
            azimuth: 0.0,
            elevation: 90.0,
            ..Default::default()
        };
        let img = render_rgb(&m, &options);
        let at = |x: usize, y: usize| &img[(y * 40 + x) * 3..(y * 40 + x) * 3 + 3];
        assert_ne!(at(20, 20), &BACKGROUND, "the square covers the centre");
        assert_eq!(at(0, 0), &BACKGROUND, "the corner stays background");
    }
}
