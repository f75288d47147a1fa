//! Speed of the discrete smoothing spline (2022 (8)) on 500, 5 000 and 50 000 points with
//! 9 × 9 and 16 × 16 cells, biquadratic and bicubic, and — when python3 with scipy is
//! installed — FITPACK's LSQBivariateSpline (kx = ky = 2, 3, same interior knots) on the
//! same points in the same run: time and relative L² error on 5 000 random points.
//! Data: the generalized offset s_f of the 2022 paper's example, three components.

use std::hint::black_box;
use std::io::Write;
use std::time::Instant;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use surfkit::fit::paper_kp2022::offset;
use surfkit::fit::smoothing::{smoothing_spline, SmoothingOptions};
use surfkit::spline::{Partition, Space, TensorSpace};

const EPSILON: f64 = 1e-9;

fn points(n: usize, seed: u64) -> (Vec<[f64; 2]>, Vec<[f64; 3]>) {
    let mut rng = StdRng::seed_from_u64(seed);
    let off = offset();
    let p: Vec<[f64; 2]> = (0..n).map(|_| [rng.random(), rng.random()]).collect();
    let v = p
        .iter()
        .map(|q| off.point(q[0], q[1]).expect("regular surface"))
        .collect();
    (p, v)
}

fn space(cells: usize, degree: usize) -> TensorSpace<surfkit::spline::BSpline1d> {
    let part = Partition::uniform(0.0, 1.0, cells).expect("partition");
    TensorSpace::bspline(part.clone(), part, degree).expect("space")
}

fn fit(s: &dyn Space, p: &[[f64; 2]], v: &[[f64; 3]]) -> surfkit::fit::SmoothingFit {
    smoothing_spline(
        s,
        p,
        v,
        &[],
        &SmoothingOptions {
            epsilon: EPSILON,
            m: 2,
            domain: None,
        },
    )
    .expect("fit")
}

fn relative_error(
    s: &dyn Space,
    f: &surfkit::fit::SmoothingFit,
    xi: &[[f64; 2]],
    truth: &[[f64; 3]],
) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for (p, t) in xi.iter().zip(truth) {
        let a = f.spline.eval(s, p[0], p[1], 0, 0).expect("inside");
        num += (0..3).map(|k| (a[k] - t[k]).powi(2)).sum::<f64>();
        den += (0..3).map(|k| t[k] * t[k]).sum::<f64>();
    }
    (num / den).sqrt()
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("smoothing_spline");
    g.sample_size(10);
    for cells in [9, 16] {
        for degree in [2, 3] {
            let s = space(cells, degree);
            for n in [500, 5_000, 50_000] {
                let (p, v) = points(n, 1);
                g.bench_with_input(
                    BenchmarkId::new(format!("deg{degree}_{cells}x{cells}"), n),
                    &n,
                    |b, _| b.iter(|| black_box(fit(&s, &p, &v))),
                );
            }
        }
    }
    g.finish();
    compare_with_fitpack();
}

const SCIPY: &str = r#"
import json, sys, time
import numpy as np
from scipy.interpolate import LSQBivariateSpline
d = np.loadtxt(sys.argv[1], delimiter=",")
e = np.loadtxt(sys.argv[2], delimiter=",")
cells, k = int(sys.argv[3]), int(sys.argv[4])
t = np.linspace(0, 1, cells + 1)[1:-1]
best = None
for _ in range(3):
    t0 = time.perf_counter()
    fits = [LSQBivariateSpline(d[:, 0], d[:, 1], d[:, 2 + c], t, t, kx=k, ky=k, bbox=[0, 1, 0, 1]) for c in range(3)]
    dt = time.perf_counter() - t0
    best = dt if best is None else min(best, dt)
a = np.stack([f.ev(e[:, 0], e[:, 1]) for f in fits], axis=1)
err = np.sqrt(((a - e[:, 2:]) ** 2).sum() / (e[:, 2:] ** 2).sum())
print(json.dumps({"time": best, "error": float(err)}))
"#;

fn write_csv(path: &std::path::Path, p: &[[f64; 2]], v: &[[f64; 3]]) {
    let mut f = std::fs::File::create(path).expect("temp file");
    for (a, b) in p.iter().zip(v) {
        writeln!(f, "{},{},{},{},{}", a[0], a[1], b[0], b[1], b[2]).expect("write");
    }
}

fn compare_with_fitpack() {
    let ok = std::process::Command::new("python3")
        .args(["-c", "import scipy"])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false);
    if !ok {
        eprintln!("python3 with scipy not found: FITPACK comparison skipped");
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let (xi, truth) = points(5_000, 99);
    let eval = dir.path().join("eval.csv");
    write_csv(&eval, &xi, &truth);
    println!(
        "\n{:>6} {:>4} {:>7} | {:>10} {:>10} | {:>10} {:>10} | time ratio fitpack/surfkit",
        "cells", "deg", "points", "surfkit s", "error", "fitpack s", "error"
    );
    for cells in [9, 16] {
        for degree in [2, 3] {
            let s = space(cells, degree);
            for n in [500, 5_000, 50_000] {
                let (p, v) = points(n, 1);
                let data = dir.path().join("data.csv");
                write_csv(&data, &p, &v);
                let mut best = f64::INFINITY;
                let mut f = fit(&s, &p, &v);
                for _ in 0..3 {
                    let t0 = Instant::now();
                    f = fit(&s, &p, &v);
                    best = best.min(t0.elapsed().as_secs_f64());
                }
                let ours = relative_error(&s, &f, &xi, &truth);
                let out = std::process::Command::new("python3")
                    .args(["-c", SCIPY])
                    .arg(&data)
                    .arg(&eval)
                    .arg(cells.to_string())
                    .arg(degree.to_string())
                    .output()
                    .expect("python3");
                let text = String::from_utf8_lossy(&out.stdout);
                let j: serde_json::Value = match serde_json::from_str(text.trim()) {
                    Ok(j) => j,
                    Err(_) => {
                        eprintln!("FITPACK failed: {}", String::from_utf8_lossy(&out.stderr));
                        continue;
                    }
                };
                let (ft, fe) = (
                    j["time"].as_f64().unwrap_or(f64::NAN),
                    j["error"].as_f64().unwrap_or(f64::NAN),
                );
                println!(
                    "{:>6} {:>4} {:>7} | {:>10.3e} {:>10.3e} | {:>10.3e} {:>10.3e} | {:.2}",
                    format!("{cells}x{cells}"),
                    degree,
                    n,
                    best,
                    ours,
                    ft,
                    fe,
                    ft / best
                );
            }
        }
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
