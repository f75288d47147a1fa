//! Every PNG surfkit writes explains itself: a title, and a colour bar whose end labels are
//! the minimum and maximum of the written quality and whose pixels are the colours the
//! picture gives those values — read back from the PNG (its pixels and its text chunks, the
//! labels in full precision) and compared with the quality itself.

use std::path::Path;
use std::process::Command;

use surfkit::mesh::PolygonMesh;
use surfkit::report::{colour_bar_box, colour_of, render_png, RenderOptions};

struct Picture {
    width: u32,
    rgb: Vec<u8>,
    texts: Vec<(String, String)>,
}

fn read_png(path: &Path) -> Picture {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut rgb = vec![0; reader.output_buffer_size().unwrap()];
    let frame = reader.next_frame(&mut rgb).unwrap();
    assert_eq!(frame.color_type, png::ColorType::Rgb);
    let texts = reader
        .info()
        .utf8_text
        .iter()
        .map(|t| (t.keyword.clone(), t.get_text().unwrap()))
        .collect();
    Picture {
        width: frame.width,
        rgb,
        texts,
    }
}

impl Picture {
    fn text(&self, key: &str) -> &str {
        &self.texts.iter().find(|(k, _)| k == key).unwrap().1
    }

    fn pixel(&self, x: usize, y: usize) -> [u8; 3] {
        let i = (y * self.width as usize + x) * 3;
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }

    fn pair(&self, key: &str) -> (f64, f64) {
        let v: Vec<f64> = self
            .text(key)
            .split(' ')
            .map(|x| x.parse().unwrap())
            .collect();
        (v[0], v[1])
    }

    /// Checks the bar against the written quality `q`: labels = min/max, the top and
    /// bottom rows the colours of max and min, each row the colour of its value.
    fn check_bar(&self, q: &[f64], height: u32) {
        let min = q.iter().copied().fold(f64::INFINITY, f64::min);
        let max = q.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        assert_eq!(self.pair("surfkit:colour-bar"), (min, max));
        let range = self.pair("surfkit:colour-range");
        let (x0, y0, x1, y1) = colour_bar_box(self.width, height);
        for x in x0..x1 {
            assert_eq!(self.pixel(x, y0), colour_of(max, range), "top of the bar");
            assert_eq!(
                self.pixel(x, y1 - 1),
                colour_of(min, range),
                "bottom of the bar"
            );
        }
        let rows = y1 - y0;
        for row in 0..rows {
            let value = max - (max - min) * row as f64 / (rows - 1) as f64;
            assert_eq!(
                self.pixel(x0 + 8, y0 + row),
                colour_of(value, range),
                "row {row}"
            );
        }
    }
}

/// A wavy grid whose quality has a few outliers: the colour range (2nd–98th percentile)
/// lies strictly inside [min, max], so the bar shows saturated ends.
fn grid_with_quality() -> PolygonMesh {
    let n = 30;
    let mut positions = Vec::new();
    let mut quality = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (x, y) = (i as f64 / 10.0, j as f64 / 10.0);
            positions.push([x, y, 0.2 * (3.0 * x).sin()]);
            quality.push(if (i, j) == (3, 4) {
                40.0
            } else {
                (2.0 * x).cos() - y
            });
        }
    }
    let faces: Vec<[u32; 4]> = (0..n - 1)
        .flat_map(|j| (0..n - 1).map(move |i| (i, j)))
        .map(|(i, j)| {
            let v = |i: usize, j: usize| (j * n + i) as u32;
            [v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)]
        })
        .collect();
    let mut mesh = PolygonMesh::from_polygons(positions, &faces);
    mesh.quality = Some(quality);
    mesh
}

#[test]
fn the_colour_bar_is_labelled_with_the_quality_and_shows_its_colours() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = grid_with_quality();
    let path = dir.path().join("grid.png");
    let options = RenderOptions {
        title: Some("a wavy grid".into()),
        quantity: Some("cos 2x − y".into()),
        ..RenderOptions::default()
    };
    render_png(&mesh, &path, &options).unwrap();
    let picture = read_png(&path);
    assert_eq!(picture.text("Title"), "a wavy grid");
    assert_eq!(picture.text("surfkit:quantity"), "cos 2x − y");
    let q = mesh.quality.as_ref().unwrap();
    picture.check_bar(q, options.height);
    let (lo, hi) = picture.pair("surfkit:colour-range");
    let (min, max) = picture.pair("surfkit:colour-bar");
    assert!(
        min < lo && hi < max,
        "the outlier saturates: [{lo}, {hi}] in [{min}, {max}]"
    );
    // The title's pixels are drawn (text colour at the top left).
    let lit = (8..8 + 8 * 11).any(|x| (8..16).any(|y| picture.pixel(x, y) == [230, 230, 230]));
    assert!(lit, "title drawn");
}

/// Runs the CLI and asserts it succeeded (stderr in the message).
fn run_surfkit(args: &[&std::ffi::OsStr]) {
    let out = Command::new(env!("CARGO_BIN_EXE_surfkit"))
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn limit_writes_a_picture_whose_bar_matches_its_samples() {
    let dir = tempfile::tempdir().unwrap();
    let ply = dir.path().join("samples.ply");
    let input = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/fixtures/meshes/catmark_torus.obj"
    );
    run_surfkit(&[
        "limit".as_ref(),
        input.as_ref(),
        "-o".as_ref(),
        ply.as_os_str(),
    ]);
    let samples = surfkit::mesh::io::read(&ply).unwrap();
    let picture = read_png(&ply.with_extension("png"));
    assert_eq!(picture.text("surfkit:quantity"), "mean curvature H");
    assert!(picture.text("Title").contains("catmark_torus.obj"));
    picture.check_bar(
        samples.quality.as_ref().unwrap(),
        RenderOptions::default().height,
    );
}

/// A UV sphere whose quality is non-zero only on its bottom cap (z < −0.6).
fn sphere_with_bottom_feature() -> PolygonMesh {
    let (rings, segments) = (24usize, 48usize);
    let mut positions = vec![[0.0, 0.0, 1.0]];
    for r in 1..rings {
        let theta = std::f64::consts::PI * r as f64 / rings as f64;
        for s in 0..segments {
            let phi = 2.0 * std::f64::consts::PI * s as f64 / segments as f64;
            positions.push([
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            ]);
        }
    }
    positions.push([0.0, 0.0, -1.0]);
    let south = positions.len() as u32 - 1;
    let at = |r: usize, s: usize| (1 + (r - 1) * segments + s % segments) as u32;
    let mut faces: Vec<Vec<u32>> = Vec::new();
    for s in 0..segments {
        faces.push(vec![0, at(1, s), at(1, s + 1)]);
        faces.push(vec![south, at(rings - 1, s + 1), at(rings - 1, s)]);
        for r in 1..rings - 1 {
            faces.push(vec![at(r, s), at(r + 1, s), at(r + 1, s + 1), at(r, s + 1)]);
        }
    }
    let quality = positions.iter().map(|p| (-p[2] - 0.6).max(0.0)).collect();
    let mut mesh = PolygonMesh::from_polygons(positions, &faces);
    mesh.quality = Some(quality);
    mesh
}

/// Pixels of the picture in the colour map's red half, well away from white and grey.
fn red_pixels(picture: &Picture, height: u32) -> usize {
    let (x0, ..) = colour_bar_box(picture.width, height);
    (0..height as usize)
        .flat_map(|y| (0..x0.saturating_sub(8)).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let [r, g, b] = picture.pixel(x, y);
            i32::from(r) - i32::from(b) > 60 && i32::from(r) - i32::from(g) > 60
        })
        .count()
}

#[test]
fn the_automatic_view_turns_to_the_feature() {
    // Seen from above (the fixed default view) the sphere's coloured cap is hidden; the
    // automatic view looks from below and shows it.
    let dir = tempfile::tempdir().unwrap();
    let mesh = sphere_with_bottom_feature();
    let count = |auto_view: bool| {
        let path = dir.path().join(format!("sphere_{auto_view}.png"));
        let options = RenderOptions {
            auto_view,
            ..RenderOptions::default()
        };
        render_png(&mesh, &path, &options).unwrap();
        red_pixels(&read_png(&path), options.height)
    };
    let (fixed, automatic) = (count(false), count(true));
    assert_eq!(fixed, 0, "the default view looks from above");
    assert!(
        automatic > 2000,
        "{automatic} red pixels from the automatic view"
    );
}

#[test]
fn fair_figures_share_a_scale_on_which_the_faired_surface_shows_structure() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("tubes.obj");
    let run = run_surfkit;
    run(&[
        "gen".as_ref(),
        "tubes".as_ref(),
        "-o".as_ref(),
        mesh.as_os_str(),
    ]);
    let figures = dir.path().join("figures");
    let samples = dir.path().join("after.ply");
    run(&[
        "fair".as_ref(),
        mesh.as_os_str(),
        "-o".as_ref(),
        dir.path().join("faired.obj").as_os_str(),
        "--quiet".as_ref(),
        "--samples".as_ref(),
        samples.as_os_str(),
        "--figures".as_ref(),
        figures.as_os_str(),
    ]);
    let before = read_png(&figures.join("curvature_before.png"));
    let after = read_png(&figures.join("curvature_after.png"));
    let (lo, hi) = after.pair("surfkit:colour-range");
    assert_eq!(before.pair("surfkit:colour-range"), (lo, hi));
    // the faired surface's values (2nd to 98th percentile) span most of the colour map,
    // not a pale sliver of it
    let mut h = surfkit::mesh::io::read(&samples).unwrap().quality.unwrap();
    h.sort_by(f64::total_cmp);
    let at = |q: f64| h[((h.len() - 1) as f64 * q).round() as usize];
    let spread = (at(0.98) - at(0.02)) / (hi - lo);
    assert!(
        spread > 0.6,
        "the after values span {spread} of the colour range"
    );
    // the unfaired values reach beyond it on both sides: saturated where fairing changed most
    let (bmin, bmax) = before.pair("surfkit:colour-bar");
    assert!(
        bmin < lo && hi < bmax,
        "the before values saturate beyond the range"
    );
}
