//! `--html` reports read back: the data embedded in the page is the report's (every flaw in
//! order, positions relative to the view's origin, each kind's highlighted faces the union of
//! its flaws' faces), a fill's hole border lies on the hole cells' edges, and the options
//! fail cleanly where they cannot apply. The browser side is tests/browser.

use std::collections::BTreeSet;
use std::path::Path;
use std::process::{Command, Output};

use base64::engine::general_purpose::STANDARD;
use base64::Engine as _;
use serde_json::Value;

fn surfkit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_surfkit"))
}

fn run(args: &[&str]) -> Output {
    surfkit().args(args).output().unwrap()
}

/// The JSON embedded in a report page.
fn embedded(html: &Path) -> Value {
    let text = std::fs::read_to_string(html).unwrap();
    let start = text
        .find(r#"<script type="application/json" id="surfkit-data">"#)
        .unwrap();
    let body = &text[start..];
    let open = body.find('>').unwrap() + 1;
    let close = body.find("</script>").unwrap();
    serde_json::from_str(&body[open..close]).unwrap()
}

fn u32s(b64: &str) -> Vec<u32> {
    STANDARD
        .decode(b64)
        .unwrap()
        .chunks(4)
        .map(|c| u32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

fn f32s(b64: &str) -> Vec<f32> {
    STANDARD
        .decode(b64)
        .unwrap()
        .chunks(4)
        .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

#[test]
fn the_eat_page_carries_every_flaw_of_the_json_report() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["octagonal_pocket.ply", "catmark_nonman_edge100.obj"] {
        let mesh = crate::common::meshes_dir().join(name);
        let html = dir.path().join(format!("{name}.html"));
        let out = run(&[
            "eat",
            mesh.to_str().unwrap(),
            "--json",
            "--html",
            html.to_str().unwrap(),
        ]);
        assert!(matches!(out.status.code(), Some(0 | 3)), "{name}");
        let json: Value = serde_json::from_slice(&out.stdout).unwrap();
        let flaws = json["report"]["flaws"].as_array().unwrap();
        let page = &embedded(&html)["page"];
        let entries = page["flaws"].as_array().unwrap();
        assert_eq!(entries.len(), flaws.len(), "{name}");
        let view = &page["views"][0];
        let origin: Vec<f64> = serde_json::from_value(view["origin"].clone()).unwrap();
        for (i, (entry, flaw)) in entries.iter().zip(flaws).enumerate() {
            assert_eq!(entry["index"], i);
            assert_eq!(entry["kind"], flaw["kind"]);
            assert_eq!(entry["description"], flaw["description"]);
            assert_eq!(entry["fix"], flaw["suggested_fix"]);
            assert_eq!(entry["faces"], flaw["faces"]);
            for k in 0..3 {
                let p = flaw["position"][k].as_f64().unwrap();
                let local = entry["position"][k].as_f64().unwrap();
                assert!((local + origin[k] - p).abs() <= 1e-12 * (1.0 + p.abs()));
            }
        }
        // each kind's highlight is the union of its flaws' faces, in their order
        for highlight in view["highlights"].as_array().unwrap() {
            let kind = highlight["name"].as_str().unwrap();
            let expected: Vec<u32> = flaws
                .iter()
                .filter(|f| f["kind"] == kind)
                .flat_map(|f| f["faces"].as_array().unwrap().iter())
                .map(|f| f.as_u64().unwrap() as u32)
                .collect();
            assert_eq!(u32s(highlight["faces"].as_str().unwrap()), expected);
        }
        // the mesh is the file's: vertex and face counts
        let v = json["report"]["counts"]["vertices_in_file"]
            .as_u64()
            .unwrap();
        assert_eq!(view["mesh"]["vertices"].as_u64().unwrap(), v);
        let positions = f32s(view["mesh"]["positions"].as_str().unwrap());
        assert_eq!(positions.len() as u64, 3 * v);
    }
}

#[test]
fn html_takes_one_mesh_and_names_the_file_it_cannot_write() {
    let dir = tempfile::tempdir().unwrap();
    let meshes = crate::common::meshes_dir();
    let out = run(&[
        "eat",
        meshes.to_str().unwrap(),
        "--html",
        dir.path().join("r.html").to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--html writes the report of one mesh"));
    let missing = dir.path().join("no/such/folder/r.html");
    let out = run(&[
        "eat",
        meshes.join("spot.obj").to_str().unwrap(),
        "--html",
        missing.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no/such/folder"));
}

/// A height field z(u, v) sampled on a lattice outside an ellipse, as CSV rows u,v,u,v,z.
fn wave_csv(path: &Path) {
    let mut rows = String::from("u,v,x,y,z\n");
    for i in 0..40 {
        for j in 0..40 {
            let (u, v) = ((i as f64 + 0.5) / 40.0, (j as f64 + 0.5) / 40.0);
            if 4.0 * (u - 0.5f64).powi(2) + 9.0 * (v - 0.5f64).powi(2) > 0.25 {
                let z = 0.3 * (3.0 * u).sin() * (2.0 * v).cos();
                rows.push_str(&format!("{u},{v},{u},{v},{z}\n"));
            }
        }
    }
    std::fs::write(path, rows).unwrap();
}

#[test]
fn the_fill_page_draws_the_hole_border_on_the_hole_cells_edges() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("wave.csv");
    wave_csv(&csv);
    let html = dir.path().join("fill.html");
    let coefficients = dir.path().join("c.json");
    let out = run(&[
        "fill",
        csv.to_str().unwrap(),
        "--hole",
        "ellipse:0.5,0.5,4,9,0.25",
        "--coefficients",
        coefficients.to_str().unwrap(),
        "--html",
        html.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let c: Value = serde_json::from_str(&std::fs::read_to_string(&coefficients).unwrap()).unwrap();
    let hole: Vec<bool> = serde_json::from_value(c["hole_cells"].clone()).unwrap();
    let [nx, ny]: [usize; 2] = serde_json::from_value(c["summary"]["cells"].clone()).unwrap();
    let [u0, u1]: [f64; 2] = serde_json::from_value(c["summary"]["u_range"].clone()).unwrap();
    let [v0, v1]: [f64; 2] = serde_json::from_value(c["summary"]["v_range"].clone()).unwrap();
    let in_hole = |i: i64, j: i64| {
        i >= 0
            && j >= 0
            && (i as usize) < nx
            && (j as usize) < ny
            && hole[i as usize * ny + j as usize]
    };
    let page = &embedded(&html)["page"];
    let view = &page["views"][0];
    let origin: Vec<f64> = serde_json::from_value(view["origin"].clone()).unwrap();
    let lines = view["lines"].as_array().unwrap();
    assert_eq!(lines.len(), 1);
    let points = f32s(lines[0]["segments"].as_str().unwrap());
    assert!(!points.is_empty());
    let mut border_sides = BTreeSet::new();
    for segment in points.chunks(6) {
        // midpoint in (u, v) = (x, y) of the height field
        let u = 0.5 * (segment[0] + segment[3]) as f64 + origin[0];
        let v = 0.5 * (segment[1] + segment[4]) as f64 + origin[1];
        let (fu, fv) = (
            (u - u0) / (u1 - u0) * nx as f64,
            (v - v0) / (v1 - v0) * ny as f64,
        );
        let on_u_line = (fu - fu.round()).abs() < 1e-4;
        let on_v_line = (fv - fv.round()).abs() < 1e-4;
        assert!(
            on_u_line != on_v_line,
            "segment midpoint ({u}, {v}) is not on one cell line"
        );
        // the cells on either side: exactly one of them is in the hole
        let (a, b) = if on_u_line {
            let i = fu.round() as i64;
            let j = fv.floor() as i64;
            ((i - 1, j), (i, j))
        } else {
            let j = fv.round() as i64;
            let i = fu.floor() as i64;
            ((i, j - 1), (i, j))
        };
        assert!(in_hole(a.0, a.1) != in_hole(b.0, b.1), "({u}, {v})");
        border_sides.insert((a, b));
    }
    // and every side between a hole cell and another cell is drawn
    let mut expected = BTreeSet::new();
    for i in 0..nx as i64 {
        for j in 0..ny as i64 {
            if in_hole(i, j) {
                for (a, b) in [
                    ((i - 1, j), (i, j)),
                    ((i, j), (i + 1, j)),
                    ((i, j - 1), (i, j)),
                    ((i, j), (i, j + 1)),
                ] {
                    if in_hole(a.0, a.1) != in_hole(b.0, b.1) {
                        expected.insert((a, b));
                    }
                }
            }
        }
    }
    assert_eq!(border_sides, expected);
}
