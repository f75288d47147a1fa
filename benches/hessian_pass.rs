//! `cargo bench --bench hessian_pass`: the time of one pass of each kind the optimizer
//! makes (F's gradient; the Hessians, exact, Gauss–Newton alone and both, at the near and
//! the far nodes) on the raw three-tube junctions of `surfkit gen tubes --size 8 --rings 2
//! --refine K`, so that a pass's growth with the vertices is seen apart from the path:
//! a run's Hessian seconds mix the kinds differently at each size (issue 18).
//!
//! The peer of each size is the first size's figure scaled linearly by the free vertices
//! (the column "linear"): a pass is a sum over patches, so its work is linear. Refinements
//! `HESSIAN_BENCH_REFINE=2,3,4` (default `2,3`; 4 is the 223 487-vertex junction),
//! surface `HESSIAN_BENCH_SURFACE` (`catmull-clark`, default, or `g2`). The gradient is
//! F's, at F's nodes; the near and far nodes are `surfkit fair`'s defaults
//! ([`FairOptions::hessian_node_counts`]). Each figure is the median of three passes after a
//! warm-up one, wall-clock on all cores.

mod support;

use surfkit::fair::{
    fixed_vertices, refine_surface, tubes, FairOptions, Functional, HessianKind, MeshTopology,
    RepresentationOptions, SurfaceKind, SurfaceRepresentation,
};

fn env_list(name: &str, default: &str) -> Vec<u32> {
    std::env::var(name)
        .unwrap_or_else(|_| default.into())
        .split(',')
        .filter_map(|s| s.trim().parse().ok())
        .collect()
}

fn main() -> surfkit::Result<()> {
    let refinements = env_list("HESSIAN_BENCH_REFINE", "2,3");
    let surface = match std::env::var("HESSIAN_BENCH_SURFACE").as_deref() {
        Ok("g2") => SurfaceKind::G2,
        _ => SurfaceKind::CatmullClark,
    };
    let passes: [(&str, Option<HessianKind>, bool); 5] = [
        ("gradient", None, false),
        ("exact + GN, near", Some(HessianKind::Both), false),
        ("exact, near", Some(HessianKind::Exact), false),
        ("GN, near", Some(HessianKind::GaussNewton), false),
        ("GN, far", Some(HessianKind::GaussNewton), true),
    ];
    println!("surface {surface:?}; seconds per pass (median of 3), and per free vertex");
    println!(
        "| vertices (free) | pass | seconds | µs per free vertex | linear from the first size |"
    );
    println!("| --- | --- | --- | --- | --- |");
    let mut first: Option<(usize, Vec<f64>)> = None;
    for refine in refinements {
        let mesh = refine_surface(&tubes(3, 8, 2)?, refine)?;
        let topo = MeshTopology::new(&mesh)?;
        let fixed = fixed_vertices(&topo, 3, &[])?;
        let fair = FairOptions {
            representation: match surface {
                SurfaceKind::CatmullClark => RepresentationOptions::catmull_clark(),
                _ => RepresentationOptions::default(),
            },
            ..FairOptions::default()
        };
        let special = topo.special_flags();
        let f_rep =
            SurfaceRepresentation::new(&mesh, &topo.boundary, &special, &fair.representation)?;
        // As `fair::optimize` does: a representation of fewer nodes only where the Hessians
        // take fewer than F.
        let (near_rep, far_rep) =
            fair.hessian_representations(&f_rep, &mesh, &topo.boundary, &special)?;
        let near_rep = near_rep.as_ref().unwrap_or(&f_rep);
        let f = Functional::new(&f_rep, &fixed, 1.0);
        let near = Functional::new(near_rep, &fixed, 1.0);
        let far = Functional::new(far_rep.as_ref().unwrap_or(near_rep), &fixed, 1.0);
        let free = near.free_count();
        let positions = &mesh.positions;
        let mut seconds = Vec::new();
        for (name, kind, use_far) in passes {
            let functional = match (kind, use_far) {
                (None, _) => &f,
                (Some(_), true) => &far,
                (Some(_), false) => &near,
            };
            let s = support::median_seconds(3, || match kind {
                Some(kind) => {
                    std::hint::black_box(functional.hessians(positions, kind));
                }
                None => {
                    std::hint::black_box(functional.gradient(positions));
                }
            });
            let linear = first.as_ref().map_or(String::from("—"), |(n, s0)| {
                format!("{:.3} s", s0[seconds.len()] * free as f64 / *n as f64)
            });
            println!(
                "| {} ({free}) | {name} | {s:.3} | {:.2} | {linear} |",
                mesh.positions.len(),
                1e6 * s / free as f64
            );
            seconds.push(s);
        }
        if first.is_none() {
            first = Some((free, seconds));
        }
    }
    Ok(())
}
