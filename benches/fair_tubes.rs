//! `cargo bench --bench fair_tubes`: Kiciak's shape optimization on the three-tube
//! junctions of the paper's sizes, from the raw generated mesh (harmonic disc interiors;
//! the time depends on the start), printed next to the paper's Table 1 seconds and the
//! author's BSTools times measured on this kind of machine (issue 6).
//!
//! Sizes (total vertices): `FAIR_BENCH_SIZES=359,1295,4895,1007,3743,14399,1677,6237,23997`
//! (default `359,1007`). Times are wall-clock on all cores (rayon; `RAYON_NUM_THREADS=1`
//! for one), the paper's and BSTools' on one core. OpenSubdiv's
//! isolation level around extraordinary vertices: `FAIR_BENCH_ISOLATION` (default 4);
//! `FAIR_BENCH_WARM_START=2` first optimizes at level 2 (see `FairOptions`);
//! `FAIR_BENCH_C_SPECIAL`: Cᵢ of the elements at special vertices (default: the
//! surface's). `FAIR_BENCH_SURFACES` (default `g2,catmull-clark`): each size on Kiciak's
//! G² surface and on the Catmull–Clark surface, one after the other.
//!
//! Each refined size is also run coarse-to-fine (`fair::optimize_levels`, as the paper's §6
//! did for figure 7): from the raw coarsest mesh of its family, optimized, refined, and
//! optimized again from the refined optimum; the time printed is the whole cascade's.
//! `FAIR_BENCH_LEVELS=0` skips these rows; `FAIR_BENCH_RAW=0` skips the raw-start rows of
//! refined sizes.

use std::time::Instant;

use surfkit::fair::{
    fixed_vertices, optimize, optimize_levels, refine_surface, tubes, FairOptions, Functional,
    MeshTopology, PatchRepresentation, RepresentationOptions, SurfaceKind, SurfaceRepresentation,
};

/// (vertices, tubes, m, rings, surface refinements, paper Table 1 seconds, BSTools seconds
/// on this kind of machine). The author's three-tube mesh (359 vertices) and its surface
/// refinements (1295, 4895: BSTools took 13.8 s, 112 s, and had not converged after
/// 1800 s at 4895), and Table 1's three- and five-tube junctions.
type Size = (usize, u32, u32, u32, u32, Option<f64>, Option<f64>);

const SIZES: [Size; 9] = [
    (359, 3, 4, 3, 0, None, Some(13.8)),
    (1295, 3, 4, 3, 1, None, Some(112.0)),
    (4895, 3, 4, 3, 2, None, Some(1800.0)),
    (1007, 3, 8, 2, 0, Some(75.0), None),
    (3743, 3, 8, 2, 1, Some(563.0), None),
    (14399, 3, 8, 2, 2, Some(2115.0), None),
    (1677, 5, 8, 2, 0, Some(129.0), None),
    (6237, 5, 8, 2, 1, Some(525.0), None),
    (23997, 5, 8, 2, 2, Some(3523.0), None),
];

/// CPU time of the whole process (all threads) in seconds, from `/proc/self/stat`;
/// `None` where unavailable.
fn cpu_seconds() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/self/stat").ok()?;
    let fields: Vec<&str> = text.rsplit(')').next()?.split_whitespace().collect();
    let ticks: f64 = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

/// F of `positions` with the end caps isolated at `isolation` levels (other options as
/// `representation`).
fn f_at_isolation(
    mesh: &surfkit::mesh::PolygonMesh,
    positions: &[[f64; 3]],
    representation: &RepresentationOptions,
    isolation: u32,
    c: f64,
) -> surfkit::Result<f64> {
    let topo = MeshTopology::new(mesh)?;
    let fixed = fixed_vertices(&topo, 3, &[])?;
    let special = topo.special_flags();
    let options = RepresentationOptions {
        isolation,
        ..representation.clone()
    };
    let rep = PatchRepresentation::new(mesh, &topo.boundary, &special, &options)?;
    Ok(Functional::new(&rep, &fixed, c).value(positions).f)
}

fn main() -> surfkit::Result<()> {
    let wanted: Vec<usize> = std::env::var("FAIR_BENCH_SIZES")
        .unwrap_or_else(|_| "359,1007".into())
        .split(',')
        .filter_map(|s| s.trim().parse().ok())
        .collect();
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
        "wall s",
        "ref s"
    );
    let surfaces: Vec<SurfaceKind> = std::env::var("FAIR_BENCH_SURFACES")
        .unwrap_or_else(|_| "g2,catmull-clark".into())
        .split(',')
        .filter_map(|s| match s.trim() {
            "g2" => Some(SurfaceKind::G2),
            "catmull-clark" => Some(SurfaceKind::CatmullClark),
            _ => None,
        })
        .collect();
    for &(nv, n, m, rings, levels, paper, bstools) in SIZES.iter().filter(|s| wanted.contains(&s.0))
    {
        for &surface in &surfaces {
            let mesh = refine_surface(&tubes(n, m, rings)?, levels)?;
            assert_eq!(mesh.vertex_count(), nv, "the generator's sizes changed");
            println!("surface {}", surface.name());
            let mut options = FairOptions {
                max_refinements: 0,
                representation: match surface {
                    SurfaceKind::G2 => RepresentationOptions::default(),
                    SurfaceKind::CatmullClark => RepresentationOptions::catmull_clark(),
                },
                ..FairOptions::default()
            };
            if let Some(level) = std::env::var("FAIR_BENCH_ISOLATION")
                .ok()
                .and_then(|s| s.parse().ok())
            {
                options.representation.isolation = level;
            }
            if let Some(c) = std::env::var("FAIR_BENCH_C_SPECIAL")
                .ok()
                .and_then(|s| s.parse().ok())
            {
                options.representation.c_special = c;
            }
            if let Some(level) = std::env::var("FAIR_BENCH_WARM_START")
                .ok()
                .and_then(|s| s.parse().ok())
            {
                options.warm_start_isolation = Some(level);
            }
            let raw = std::env::var("FAIR_BENCH_RAW").map_or(true, |v| v != "0");
            if raw || levels == 0 {
                raw_start(&mesh, n, levels, &options, paper, bstools)?;
            }
            let cascade = std::env::var("FAIR_BENCH_LEVELS").map_or(true, |v| v != "0");
            if cascade && levels > 0 {
                coarse_to_fine(&tubes(n, m, rings)?, levels, &options, paper.or(bstools))?;
            }
        }
    }
    Ok(())
}

/// The raw-start row: optimize `mesh` as generated (or surface-refined) and print the
/// figures next to the reference's.
fn raw_start(
    mesh: &surfkit::mesh::PolygonMesh,
    n: u32,
    levels: u32,
    options: &FairOptions,
    paper: Option<f64>,
    bstools: Option<f64>,
) -> surfkit::Result<()> {
    let nv = mesh.vertex_count();
    let start = Instant::now();
    let cpu0 = cpu_seconds();
    let (out, report) = optimize(mesh, options)?;
    let wall = start.elapsed().as_secs_f64();
    let cpu = match (cpu0, cpu_seconds()) {
        (Some(a), Some(b)) => b - a,
        _ => f64::NAN,
    };
    let topo = MeshTopology::new(mesh)?;
    let fixed = fixed_vertices(&topo, 3, &[])?;
    let special = topo.special_flags();
    let rep = SurfaceRepresentation::new(mesh, &topo.boundary, &special, &options.representation)?;
    let f = Functional::new(&rep, &fixed, report.c);
    let (s0, s1) = (f.value(&mesh.positions).s, f.value(&out.positions).s);
    let (sd0, sd1) = (
        f.mean_curvature_statistics(&mesh.positions).1,
        f.mean_curvature_statistics(&out.positions).1,
    );
    let reference = paper.or(bstools);
    // How much the adaptive isolation level moves F, next to what the optimization
    // gained (issue 6: the end-cap choice must not matter at that scale).
    let levels_of_isolation: &[u32] = match options.representation.surface {
        SurfaceKind::CatmullClark => &[3, 4, 5],
        SurfaceKind::G2 => &[],
    };
    let isolation: Vec<String> = levels_of_isolation
        .iter()
        .map(|&l| {
            let f0 = f_at_isolation(mesh, &mesh.positions, &options.representation, l, report.c)?;
            let f1 = f_at_isolation(mesh, &out.positions, &options.representation, l, report.c)?;
            Ok(format!("isolation {l}: F {f0:.6e} -> {f1:.6e}"))
        })
        .collect::<surfkit::Result<_>>()?;
    println!(
        "{:>6} {:>6} {:>5} {:>5} {:>12.5e} {:>12.5e} {:>7.2} {:>10.4e} {:>10.4e} {:>9.2e} {:>8.1} {:>8}{}",
        nv,
        report.free_vertices,
        report.newton.iterations.len()
            + report.warm_start.as_ref().map_or(0, |w| w.iterations.len()),
        report.newton.hessian_evaluations
            + report.warm_start.as_ref().map_or(0, |w| w.hessian_evaluations),
        s0,
        s1,
        s0 / s1,
        sd0,
        sd1,
        report.final_gradient_norm / report.initial_gradient_norm,
        wall,
        reference.map_or("-".into(), |r| format!("{r:.1}")),
        match (paper, bstools) {
            (Some(p), _) => format!("  (Table 1, one core; ratio {:.2})", p / wall),
            (None, Some(b)) if nv == 4895 => format!(
                "  (BSTools here: not converged after {b:.0} s; ratio > {:.2})",
                b / wall
            ),
            (None, Some(b)) => format!("  (BSTools here, one core; ratio {:.2})", b / wall),
            _ => String::new(),
        }
    );
    println!(
        "        {}; converged {} at the coordinates' floor {} stuck {}; CPU {cpu:.1} s on {} threads, {:.1} s in {} Hessians \
         and {} Gauss–Newton parts, {:.1} s in {} factorizations; {}",
        if levels > 0 {
            format!("{n} tubes refined {levels}x")
        } else {
            format!("{n} tubes raw")
        },
        report.newton.converged,
        report.newton.stalled,
        report.newton.stuck,
        rayon::current_num_threads(),
        report.newton.hessian_seconds,
        report.newton.hessian_evaluations,
        report.newton.gauss_newton_evaluations,
        report.newton.factorization_seconds,
        report.newton.factorizations,
        isolation.join("; ")
    );
    Ok(())
}

/// The coarse-to-fine row: the whole cascade's wall time against the reference, and what
/// each level took.
fn coarse_to_fine(
    coarse: &surfkit::mesh::PolygonMesh,
    levels: u32,
    options: &FairOptions,
    reference: Option<f64>,
) -> surfkit::Result<()> {
    let start = Instant::now();
    let reports = optimize_levels(coarse, levels, options)?.levels;
    let wall = start.elapsed().as_secs_f64();
    let finest = &reports.last().expect("level 0 is always there").report;
    let per_level: Vec<String> = reports
        .iter()
        .map(|l| {
            format!(
                "level {} ({} v): {} Hessians, {:.1} s{}",
                l.level,
                l.report.vertices,
                l.report.newton.hessian_evaluations,
                l.seconds,
                l.report.newton.status_note()
            )
        })
        .collect();
    println!(
        "{:>6} coarse-to-fine from {} vertices: F {:.6e}, |g|/|g0| {:.2e}, wall {:.1} s{}; {}",
        finest.vertices,
        coarse.vertex_count(),
        finest.final_terms.f,
        finest.final_gradient_norm / finest.initial_gradient_norm,
        wall,
        reference.map_or(String::new(), |r| format!(" (ratio {:.2})", r / wall)),
        per_level.join("; ")
    );
    Ok(())
}
