//! `surfkit fill --shape …`: the 2024 shape-preserving filling from the command line. The
//! data are exact polynomials whose unconstrained fill leaves the required shape inside the
//! hole; the constrained fill is checked by evaluating the written surface (PLY samples or
//! the spline itself), not by reading the solver's report. Bad combinations of options are
//! refused with messages that say what is wrong.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use surfkit::fit::data::ScatteredData;
use surfkit::fit::pipeline::{fit_and_fill, FitSetup, HoleSource, SpaceKind};
use surfkit::fit::shape::{ShapeConstraints, Tau};
use surfkit::fit::FillVariant;
use surfkit::linalg::qp::QP_FEASIBILITY;
use surfkit::tolerance::FINITE_DIFFERENCE;

fn surfkit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_surfkit"))
}

/// Height-field data z = f(u, v) on a 49 × 49 lattice of [0, 1]², without the points of
/// (7/48, 41/48)²: on 6 × 6 cells the cells 1..=4 × 1..=4 hold no data, so the hole H_h is
/// [1/6, 5/6]² (16 cells, 3 × 3 free nodes).
fn data(f: &dyn Fn(f64, f64) -> f64) -> ScatteredData {
    data_with_gap(f, true)
}

/// As [`data`], with the gap or without it (`gap = false`: the whole lattice).
fn data_with_gap(f: &dyn Fn(f64, f64) -> f64, gap: bool) -> ScatteredData {
    let mut d = ScatteredData::default();
    for i in 0..49 {
        for j in 0..49 {
            let (u, v) = (i as f64 / 48.0, j as f64 / 48.0);
            if gap && (8..=40).contains(&i) && (8..=40).contains(&j) {
                continue;
            }
            d.params.push([u, v]);
            d.points.push([u, v, f(u, v)]);
        }
    }
    d
}

fn write_csv(dir: &Path, name: &str, d: &ScatteredData) -> PathBuf {
    let mut text = String::from("u,v,x,y,z\n");
    for (p, x) in d.params.iter().zip(&d.points) {
        text += &format!("{},{},{},{},{}\n", p[0], p[1], x[0], x[1], x[2]);
    }
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// z = (u − ½)² + (v − ½)² − 0.02: positive on ∂H_h (≥ 1/9 − 0.02) but −0.02 at the centre.
/// A quadratic satisfies Δ²z = 0 and lies in the BFS space, so the unconstrained fill is z.
fn bowl(u: f64, v: f64) -> f64 {
    (u - 0.5).powi(2) + (v - 0.5).powi(2) - 0.02
}

fn run(args: &[&str], csv: &Path) -> Output {
    surfkit().arg("fill").arg(csv).args(args).output().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The sampled surface's z at the vertices strictly inside H_h = (1/6, 5/6)².
fn z_in_hole(ply: &Path) -> Vec<f64> {
    let m = surfkit::mesh::io::read(ply).unwrap();
    let inside = |t: f64| t > 1.0 / 6.0 + 1e-12 && t < 5.0 / 6.0 - 1e-12;
    let z: Vec<f64> = m
        .positions
        .iter()
        .filter(|p| inside(p[0]) && inside(p[1]))
        .map(|p| p[2])
        .collect();
    assert!(z.iter().all(|x| x.is_finite()));
    z
}

fn min(z: &[f64]) -> f64 {
    z.iter().copied().fold(f64::INFINITY, f64::min)
}

#[test]
fn positivity_holds_where_the_unconstrained_fill_goes_negative() {
    let dir = tempfile::tempdir().unwrap();
    let csv = write_csv(dir.path(), "bowl.csv", &data(&bowl));
    let base = ["--space", "bfs-c1", "--cells", "6,6", "--hole-from-data"];
    // Resolution 24 samples [0, 1] every 1/24: the nodes (every 4th sample) and the 3 × 3
    // lattice of constraint points in each cell (offsets ¼, ½, ¾ of a cell) — exactly the
    // points where positivity is imposed.
    let sample = |extra: &[&str], name: &str, res: &str| -> Vec<f64> {
        let ply = dir.path().join(name);
        let ply_arg = ply.display().to_string();
        let args = [
            &base[..],
            extra,
            &["--resolution", res, "--output", &ply_arg],
        ]
        .concat();
        let o = run(&args, &csv);
        assert!(o.status.success(), "{}", stderr(&o));
        z_in_hole(&ply)
    };
    // The default (2022) fill goes negative inside the hole.
    let paper2022 = sample(&[], "fill2022.ply", "24");
    assert!(min(&paper2022) < 0.0, "{}", min(&paper2022));
    // The 2024 fill with a condition that is inactive on z (x = u is increasing in u) is
    // the unconstrained minimizer of |v|₂ with σ₁'s boundary dofs: the bowl itself, −0.02
    // at the centre (σ₁ fits the exact data to ε's level).
    let free = sample(
        &["--shape", "increasing-u", "--shape-component", "x"],
        "free.ply",
        "24",
    );
    assert_eq!(free.len(), 15 * 15);
    surfkit::assert_near!(min(&free), bowl(0.5, 0.5), FINITE_DIFFERENCE);
    surfkit::assert_near!(free[free.len() / 2], bowl(0.5, 0.5), FINITE_DIFFERENCE);
    let pos = sample(&["--shape", "positive"], "pos.ply", "24");
    assert!(
        min(&pos) >= -QP_FEASIBILITY,
        "constrained fill negative at a constraint point: {}",
        min(&pos)
    );
    // Between constraint points positivity is not imposed (a C¹ surface that is ≥ 0 on a
    // lattice of spacing δ may dip by O(δ²) between its points); on this bowl the minimum
    // sits on the free node at the centre, and a dense lattice (every 1/240) finds no
    // negative value either.
    let dense = sample(&["--shape", "positive"], "dense.ply", "240");
    assert!(min(&dense) >= -QP_FEASIBILITY, "{}", min(&dense));
}

/// z = −81(u − ½)⁵ − 0.3(u − ½): strictly decreasing in u (∂z/∂u ≤ −0.3), steep at the
/// hole's sides u = 1/6, 5/6 (−5.3) and flat in the middle. The hole holds no data, and the
/// unconstrained fill — the minimizer of |v|₂ with σ₁'s nodal dofs on ∂H_h — follows its
/// steep sides and overshoots: in one dimension the cubic with these end values and slopes
/// has slope 1.5·secant − ¼(sum of end slopes) = 1 − 0.3 = +0.7 at the centre.
fn wave(u: f64, _v: f64) -> f64 {
    -81.0 * (u - 0.5).powi(5) - 0.3 * (u - 0.5)
}

fn setup(shape: ShapeConstraints) -> FitSetup {
    FitSetup {
        space: SpaceKind::BfsC1,
        cells: [6, 6],
        epsilon: 1e-9,
        hole: HoleSource::CellsWithoutData,
        variant: FillVariant::Paper,
        shape: Some(shape),
    }
}

/// ∂σ/∂u of the filled surface's z at (u, v).
fn dz_du(out: &surfkit::fit::pipeline::FitOutcome, u: f64, v: f64) -> f64 {
    out.fill
        .as_ref()
        .unwrap()
        .eval(out.space.as_ref(), u, v, 1, 0)
        .unwrap()[2]
}

#[test]
fn decreasing_in_u_with_tau_minus_one_where_the_unconstrained_fill_increases() {
    let d = data(&wave);
    let inactive = ShapeConstraints {
        component: 0,
        value: None,
        slope_x: Some(Tau::Plus),
        slope_y: None,
        extra_per_side: 3,
        extra_points: vec![],
    };
    let free = fit_and_fill(&d, &setup(inactive)).unwrap();
    assert_eq!(free.summary.hole_cells, 16);
    assert!(dz_du(&free, 0.5, 0.5) > 0.0);

    let decreasing = ShapeConstraints {
        component: 2,
        value: None,
        slope_x: Some(Tau::Minus),
        slope_y: None,
        extra_per_side: 3,
        extra_points: vec![],
    };
    let out = fit_and_fill(&d, &setup(decreasing.clone())).unwrap();
    // The constraint points: every 1/24 (nodes and the 3 × 3 lattice of each cell).
    let lattice = |n: usize| -> Vec<f64> {
        (1..n)
            .map(|i| 1.0 / 6.0 + (2.0 / 3.0) * i as f64 / n as f64)
            .collect()
    };
    let mut worst = f64::NEG_INFINITY;
    for &u in &lattice(16) {
        for &v in &lattice(16) {
            worst = worst.max(dz_du(&out, u, v));
        }
    }
    assert!(
        worst <= QP_FEASIBILITY,
        "∂z/∂u = {worst} > 0 at a constraint point"
    );
    // Filled by nodal interpolation on ∂H_h: σ is C¹ across the border (to round-off).
    let f = out.summary.fill.as_ref().unwrap();
    assert!(
        f.c0_jump <= FINITE_DIFFERENCE && f.c1_jump <= FINITE_DIFFERENCE,
        "{f:?}"
    );
    let sh = out.summary.shape.as_ref().unwrap();
    assert!(sh.max_violation <= sh.tolerance, "{sh:?}");
    // Between constraint points monotonicity is not imposed: on a dense lattice (every
    // 1/240 of the hole) ∂z/∂u may be positive there, by O(δ) for constraint spacing δ
    // (∂z/∂u is C⁰ with bounded slope). Refining the constraint lattice must shrink it.
    let dense_max = |k: usize| -> f64 {
        let out = fit_and_fill(
            &d,
            &setup(ShapeConstraints {
                extra_per_side: k,
                ..decreasing.clone()
            }),
        )
        .unwrap();
        let mut m = f64::NEG_INFINITY;
        for &u in &lattice(160) {
            for &v in &lattice(160) {
                m = m.max(dz_du(&out, u, v));
            }
        }
        m
    };
    let over: Vec<f64> = [3, 7, 15].iter().map(|&k| dense_max(k)).collect();
    // (Measured: 0.013, 0.0026, 0.0013 — against +0.85 at the centre without the condition.)
    let unconstrained = dz_du(&free, 0.5, 0.5);
    assert!(over[0] < unconstrained / 10.0, "{over:?}");
    assert!(over[1] < over[0] && over[2] < over[1], "{over:?}");
}

#[test]
fn bad_combinations_are_refused_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let csv = write_csv(dir.path(), "bowl.csv", &data(&bowl));
    let points = dir.path().join("points.csv");
    // Line 1 is a header, line 2 in the hole, line 3 outside it (cell 0 holds data).
    std::fs::write(&points, "u,v\n0.5,0.5\n0.05,0.5\n").unwrap();
    let bad_points = dir.path().join("bad_points.csv");
    std::fs::write(&bad_points, "0.5,0.5\n0.4;x\n").unwrap();
    let p = points.display().to_string();
    let bp = bad_points.display().to_string();
    let bfs = ["--space", "bfs-c1", "--cells", "6,6", "--hole-from-data"];
    let cases: Vec<(Vec<&str>, String)> = vec![
        (
            vec!["--cells", "6,6", "--hole-from-data", "--shape", "positive"],
            "need the Bogner–Fox–Schmit C¹ space (bfs-c1), not Biquadratic".into(),
        ),
        (
            vec!["--space", "bfs-c1", "--cells", "6,6", "--shape", "positive"],
            "shape constraints apply to the filled hole".into(),
        ),
        (
            [&bfs[..], &["--shape", "positive", "--shape", "negative"]].concat(),
            "--shape positive and negative contradict each other (the sign of σ)".into(),
        ),
        (
            [
                &bfs[..],
                &["--shape", "increasing-v", "--shape", "decreasing-v"],
            ]
            .concat(),
            "--shape increasing-v and decreasing-v contradict each other (monotonicity in v)"
                .into(),
        ),
        (
            [&bfs[..], &["--shape-points", &p]].concat(),
            "--shape-points needs at least one --shape condition".into(),
        ),
        (
            [&bfs[..], &["--shape", "positive", "--exact-c1"]].concat(),
            "shape constraints and the exact-C¹ variant are exclusive".into(),
        ),
        (
            [&bfs[..], &["--shape", "positive", "--offset", "0;0;0.1"]].concat(),
            "--shape with --offset is not supported".into(),
        ),
        (
            [&bfs[..], &["--shape", "positive", "--shape-points", &p]].concat(),
            format!("{p} line 3: constraint point (0.05, 0.5) is not in the hole H_h (16 cells)"),
        ),
        (
            [&bfs[..], &["--shape", "positive", "--shape-points", &bp]].concat(),
            format!("{bp}: line 2: expected two finite numbers u,v, got \"0.4;x\""),
        ),
    ];
    for (args, want) in cases {
        let o = run(&args, &csv);
        assert_eq!(
            o.status.code(),
            Some(1),
            "{args:?} should fail: {}",
            stderr(&o)
        );
        assert!(
            stderr(&o).contains(&want),
            "{args:?}: expected {want:?} in {:?}",
            stderr(&o)
        );
    }
}

#[test]
fn shape_conditions_the_data_contradict_exit_with_status_3() {
    // The bowl decreases in u on the hole's left side: increasing-u contradicts the
    // boundary data. The command ran; its goal cannot be met: status 3, not 1.
    let dir = tempfile::tempdir().unwrap();
    let csv = write_csv(dir.path(), "bowl.csv", &data(&bowl));
    let o = run(
        &[
            "--space",
            "bfs-c1",
            "--cells",
            "6,6",
            "--hole-from-data",
            "--shape",
            "increasing-u",
        ],
        &csv,
    );
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(stderr(&o).contains("contradict the shape conditions (τ∂v/∂x ≥ 0 with τ = +1 on z)"));
}

#[test]
fn a_hole_without_free_coefficients_violated_by_its_border_is_infeasible() {
    // 5 × 5 cells, a hole of one cell [0.4, 0.6]²: every node of it is on its border, so σ
    // there is fixed by σ₁. z = (u − ½)² + (v − ½)² − 0.03 is −0.01 at its corners: no
    // freedom can make it positive, and that is an error, not a silent result.
    let d = data_with_gap(&|u, v| bowl(u, v) - 0.01, false);
    let mut setup = setup(ShapeConstraints {
        component: 2,
        value: Some(Tau::Plus),
        slope_x: None,
        slope_y: None,
        extra_per_side: 3,
        extra_points: vec![],
    });
    setup.cells = [5, 5];
    setup.hole = HoleSource::Shapes(surfkit::fit::Hole {
        shapes: vec![surfkit::fit::HoleShape::Polygon(vec![
            [0.45, 0.45],
            [0.55, 0.45],
            [0.55, 0.55],
            [0.45, 0.55],
        ])],
    });
    let err = fit_and_fill(&d, &setup)
        .err()
        .expect("must fail")
        .to_string();
    assert!(
        err.contains("infeasible") && err.contains("the hole has no free coefficient"),
        "{err}"
    );
}
