//! `cargo bench --bench hessian_pass`: the time of one pass of each kind the optimizer
//! makes (F's gradient; the Hessians, exact, Gauss–Newton alone and both, at the near and
//! the far nodes) on the raw three-tube junctions of `surfkit gen tubes --size 8 --rings 2
//! --refine K`, so that a pass's growth with the vertices is seen apart from the path:
//! a run's Hessian seconds mix the kinds differently at each size (issue 18).
//!
//! The peer of each size is the first size's figure scaled linearly by the free vertices
//! (the column "linear"): a pass is a sum over patches, so its work is linear. Refinements
//! `HESSIAN_BENCH_REFINE=2,3,4` (default `2,3`; 4 is the 223 487-vertex junction),
//! surface `HESSIAN_BENCH_SURFACE` (`catmull-clark`, default, or `g2`). The near and far
//! nodes are `surfkit fair`'s defaults. Each figure is the median of three passes after a
//! warm-up one, wall-clock on all cores.

mod support;

use surfkit::fair::{
    fixed_vertices, refine_surface, tubes, Functional, HessianKind, MeshTopology,
    RepresentationOptions, SurfaceKind, SurfaceRepresentation, DEFAULT_FAR_HESSIAN_NODES,
    DEFAULT_HESSIAN_NODES,
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
        let options = match surface {
            SurfaceKind::CatmullClark => RepresentationOptions::catmull_clark(),
            _ => RepresentationOptions::default(),
        };
        // As `fair::optimize` caps them: near at most F's nodes, far at most the near ones.
        let near_nodes = DEFAULT_HESSIAN_NODES.min(options.nodes);
        let near_options = RepresentationOptions {
            nodes: near_nodes,
            ..options.clone()
        };
        let far_options = RepresentationOptions {
            nodes: DEFAULT_FAR_HESSIAN_NODES.min(near_nodes),
            ..options
        };
        let special = topo.special_flags();
        let near = SurfaceRepresentation::new(&mesh, &topo.boundary, &special, &near_options)?;
        let far = SurfaceRepresentation::new(&mesh, &topo.boundary, &special, &far_options)?;
        let near = Functional::new(&near, &fixed, 1.0);
        let far = Functional::new(&far, &fixed, 1.0);
        let free = near.free_count();
        let positions = &mesh.positions;
        let mut seconds = Vec::new();
        for (name, kind, use_far) in passes {
            let functional = if use_far { &far } else { &near };
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
