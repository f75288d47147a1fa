//! `cargo bench --bench fair_tubes`: Kiciak's shape optimization on the three-tube
//! junctions of the paper's sizes, from the raw generated mesh (harmonic disc interiors;
//! the time depends on the start), printed next to the paper's Table 1 seconds and the
//! author's BSTools times measured on this kind of machine (issue 6).
//!
//! Sizes: `FAIR_BENCH_SIZES=359,1007,3743,14399` (default `359,1007`).

use std::time::Instant;

use surfkit::fair::{
    fixed_vertices, optimize, tubes, FairOptions, Functional, MeshTopology, PatchRepresentation,
};

/// (vertices, m, rings, paper Table 1 seconds, BSTools seconds on this machine).
type Size = (usize, u32, u32, Option<f64>, Option<f64>);

const SIZES: [Size; 4] = [
    (359, 4, 3, None, Some(13.8)),
    (1007, 8, 2, Some(75.0), None),
    (3743, 16, 3, Some(563.0), None),
    (14399, 32, 5, Some(2115.0), None),
];

fn main() -> surfkit::Result<()> {
    let wanted: Vec<usize> = std::env::var("FAIR_BENCH_SIZES")
        .unwrap_or_else(|_| "359,1007".into())
        .split(',')
        .filter_map(|s| s.trim().parse().ok())
        .collect();
    faer::set_global_parallelism(faer::Par::Seq);
    println!(
        "{:>6} {:>6} {:>5} {:>5} {:>12} {:>12} {:>7} {:>10} {:>10} {:>9} {:>8} {:>8}",
        "n_V",
        "free",
        "iter",
        "n_H",
        "S before",
        "S after",
        "factor",
        "std H 0",
        "std H 1",
        "|g|/|g0|",
        "time s",
        "paper s"
    );
    for &(nv, m, rings, paper, bstools) in SIZES.iter().filter(|s| wanted.contains(&s.0)) {
        let mesh = tubes(3, m, rings)?;
        let options = FairOptions {
            max_refinements: 0,
            ..FairOptions::default()
        };
        let start = Instant::now();
        let (out, report) = optimize(&mesh, &options)?;
        let seconds = start.elapsed().as_secs_f64();
        let topo = MeshTopology::new(&mesh)?;
        let fixed = fixed_vertices(&topo, 3, &[])?;
        let mut special = vec![false; nv];
        for v in topo.special_vertices() {
            special[v as usize] = true;
        }
        let rep =
            PatchRepresentation::new(&mesh, &topo.boundary, &special, &options.representation)?;
        let f = Functional::new(&rep, &fixed, report.c);
        let (s0, s1) = (f.value(&mesh.positions).s, f.value(&out.positions).s);
        let (sd0, sd1) = (
            f.mean_curvature_statistics(&mesh.positions).1,
            f.mean_curvature_statistics(&out.positions).1,
        );
        let reference = paper.or(bstools);
        println!(
            "{:>6} {:>6} {:>5} {:>5} {:>12.5e} {:>12.5e} {:>7.2} {:>10.4e} {:>10.4e} {:>9.2e} {:>8.1} {:>8}{}",
            nv,
            report.free_vertices,
            report.newton.iterations.len(),
            report.newton.hessian_evaluations,
            s0,
            s1,
            s0 / s1,
            sd0,
            sd1,
            report.final_gradient_norm / report.newton.initial_gradient_norm,
            seconds,
            reference.map_or("-".into(), |r| format!("{r:.1}")),
            match (paper, bstools) {
                (Some(p), _) => format!("  (Table 1; ratio {:.2})", p / seconds),
                (None, Some(b)) => format!("  (BSTools here; ratio {:.2})", b / seconds),
                _ => String::new(),
            }
        );
    }
    Ok(())
}
