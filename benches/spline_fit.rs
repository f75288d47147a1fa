//! Speed of the discrete smoothing spline (2022 (8)) on 500, 5 000 and 50 000 points with
//! 9 × 9 and 16 × 16 cells, biquadratic and bicubic, next to FITPACK (scipy, from the .venv
//! of `scripts/setup.sh` or `SURFKIT_PYTHON`): LSQBivariateSpline (kx = ky = 2, 3, same
//! interior knots) and SmoothBivariateSpline (kx = ky = 2, 3, s explained at
//! [`compare_with_fitpack`]) on the same points in the same run: time and relative L²
//! error on 5 000 other random points. `cargo bench --bench spline_fit`.
//! Data: the generalized offset s_f of the 2022 paper's example, three components.

mod support;

use std::hint::black_box;
use std::io::Write;
use std::time::Instant;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use surfkit::fit::papers::kp2022::offset;
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

fn write_csv(path: &std::path::Path, p: &[[f64; 2]], v: &[[f64; 3]]) {
    let mut f = std::fs::File::create(path).expect("temp file");
    for (a, b) in p.iter().zip(v) {
        writeln!(f, "{},{},{},{},{}", a[0], a[1], b[0], b[1], b[2]).expect("write");
    }
}

/// Σₐ (σ(a) − pₐ)² per component: the residual our spline leaves on its data.
fn residual_sums(
    s: &dyn Space,
    f: &surfkit::fit::SmoothingFit,
    p: &[[f64; 2]],
    v: &[[f64; 3]],
) -> [f64; 3] {
    let mut r = [0.0; 3];
    for (a, t) in p.iter().zip(v) {
        let x = f.spline.eval(s, a[0], a[1], 0, 0).expect("inside");
        for k in 0..3 {
            r[k] += (x[k] - t[k]).powi(2);
        }
    }
    r
}

/// One FITPACK run through `benches/peers/scipy_spline_fit.py`: (time, error, note).
fn fitpack(args: &[String]) -> Option<(f64, f64, String)> {
    match support::python_peer("scipy_spline_fit.py", args) {
        Ok(j) => {
            let knots = j["interior_knots"][0].to_string();
            let warn = j["warnings"]
                .as_array()
                .map(|w| {
                    w.iter()
                        .filter_map(|x| x.as_str())
                        .collect::<Vec<_>>()
                        .join("; ")
                })
                .unwrap_or_default();
            Some((
                j["time"].as_f64()?,
                j["error"].as_f64()?,
                if warn.is_empty() {
                    format!("knots {knots}")
                } else {
                    format!("knots {knots}, FITPACK: {warn}")
                },
            ))
        }
        Err(e) => {
            eprintln!("FITPACK peer failed: {e}");
            None
        }
    }
}

/// surfkit next to FITPACK on the same points in the same run: LSQBivariateSpline with the
/// same uniform interior knots, and SmoothBivariateSpline with
/// s = the per-component residual sum of squares our spline leaves on the data. The data are
/// exact samples of a smooth surface, so there is no noise level to set s from; asking
/// FITPACK for the residual our ε = 1e-9 fit reaches compares like with like — the same
/// fidelity to the data — and lets it choose its own knots to get there (it adds knots
/// until Σ residual² ≤ s, or stops at its knot limit with a warning, which is printed).
fn compare_with_fitpack() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (xi, truth) = points(5_000, 99);
    let eval = dir.path().join("eval.csv");
    write_csv(&eval, &xi, &truth);
    println!(
        "\nsame points, same run; time = best of 3 for the three components; error = relative L² on 5 000 other points"
    );
    println!(
        "{:>6} {:>3} {:>6} | {:>9} {:>9} | {:>9} {:>9} {:>6} | {:>9} {:>9} {:>6} | smooth: knots per side",
        "cells", "deg", "points", "surfkit s", "error", "LSQ s", "error", "ratio", "Smooth s", "error", "ratio"
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
                let rss = residual_sums(&s, &f, &p, &v);
                let common = |method: &str| -> Vec<String> {
                    vec![
                        data.display().to_string(),
                        eval.display().to_string(),
                        cells.to_string(),
                        degree.to_string(),
                        method.to_string(),
                    ]
                };
                let lsq = fitpack(&common("lsq"));
                let mut smooth_args = common("smooth");
                smooth_args.push(format!("{:e},{:e},{:e}", rss[0], rss[1], rss[2]));
                let smooth = fitpack(&smooth_args);
                let col = |r: &Option<(f64, f64, String)>| match r {
                    Some((t, e, _)) => format!("{t:>9.2e} {e:>9.2e} {:>6.2}", t / best),
                    None => format!("{:>9} {:>9} {:>6}", "-", "-", "-"),
                };
                println!(
                    "{:>6} {:>3} {:>6} | {:>9.2e} {:>9.2e} | {} | {} | {}",
                    format!("{cells}x{cells}"),
                    degree,
                    n,
                    best,
                    ours,
                    col(&lsq),
                    col(&smooth),
                    smooth.as_ref().map_or(String::new(), |s| s.2.clone())
                );
            }
        }
    }
    println!("ratio = FITPACK time / surfkit time (> 1: surfkit faster)");
}

criterion_group!(benches, bench);
criterion_main!(benches);
