//! `surfkit paper kp2004-example{1,2} --figures DIR`: the 2004 paper's figures (x₀, the fit
//! without parallelism τ = 0, the fit with τ = 10) are written as PLY + PNG, read back, and
//! the sampled fit is checked against the spline and the report at the data sites.

use std::path::Path;
use std::process::Command;

use surfkit::fit::papers::kp2004::{Kp2004Problem, FIGURE_RESOLUTION, TAU};
use surfkit::tolerance::{near, ROUND_OFF};

const NAMES: [&str; 3] = ["reference", "tau0", "tau10"];

/// Reads a written PNG's size (decoding it whole, so a truncated file fails).
fn png_size(path: &Path) -> (u32, u32) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    (info.width, info.height)
}

#[test]
fn the_cli_writes_three_readable_figures_per_example() {
    let dir = tempfile::tempdir().unwrap();
    let n = FIGURE_RESOLUTION + 1;
    for which in [1, 2] {
        let out = Command::new(env!("CARGO_BIN_EXE_surfkit"))
            .args(["paper", &format!("kp2004-example{which}"), "--figures"])
            .arg(dir.path())
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        for name in NAMES {
            let stem = dir.path().join(format!("kp2004_example{which}_{name}"));
            let mesh = surfkit::mesh::io::read(&stem.with_extension("ply")).unwrap();
            assert_eq!(mesh.vertex_count(), n * n, "{name}");
            assert_eq!(mesh.face_count(), FIGURE_RESOLUTION * FIGURE_RESOLUTION);
            assert!(mesh.positions.iter().flatten().all(|x| x.is_finite()));
            // The fits carry the local parallelism defect (a norm) as quality; x₀ none.
            match &mesh.quality {
                Some(q) => {
                    assert_ne!(name, "reference");
                    assert_eq!(q.len(), n * n);
                    assert!(q.iter().all(|x| x.is_finite() && *x >= 0.0));
                }
                None => assert_eq!(name, "reference"),
            }
            let (w, h) = png_size(&stem.with_extension("png"));
            assert!(w > 0 && h > 0);
        }
    }
}

#[test]
fn the_sampled_fits_pass_through_the_spline_at_the_data_sites() {
    // FIGURE_RESOLUTION is a multiple of 6, so every data site a is a sample point; there
    // the figure's vertex is s(a), and Σ‖vertex − pₐ‖² is the fit's reported misfit.
    let dir = tempfile::tempdir().unwrap();
    for which in [1, 2] {
        let problem = Kp2004Problem::new(which).unwrap();
        let figures = problem.figures(TAU, FIGURE_RESOLUTION).unwrap();
        let written = surfkit::report::write_figures(dir.path(), &figures).unwrap();
        assert_eq!(written.len(), 6);
        let [lo, hi] = problem.range;
        let res = FIGURE_RESOLUTION as f64;
        for (k, tau) in [(1, 0.0), (2, TAU)] {
            let fit = problem.fit(tau).unwrap();
            let mesh = surfkit::mesh::io::read(&written[2 * k]).unwrap();
            let mut misfit = 0.0;
            for (a, p) in problem.a_points.iter().zip(&problem.values) {
                let (i, j) = (
                    ((a[0] - lo) / (hi - lo) * res).round() as usize,
                    ((a[1] - lo) / (hi - lo) * res).round() as usize,
                );
                let vertex = mesh.positions[i * (FIGURE_RESOLUTION + 1) + j];
                let s = fit.spline.eval(&problem.space, a[0], a[1], 0, 0).unwrap();
                for c in 0..3 {
                    assert!(
                        near(vertex[c], s[c], ROUND_OFF),
                        "example {which} τ = {tau} at {a:?}: {vertex:?} vs {s:?}"
                    );
                }
                misfit += (0..3).map(|c| (vertex[c] - p[c]).powi(2)).sum::<f64>();
            }
            assert!(
                near(misfit, fit.data_misfit, ROUND_OFF),
                "example {which} τ = {tau}: {misfit} vs {}",
                fit.data_misfit
            );
        }
    }
}
