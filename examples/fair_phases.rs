//! Times the parts of one optimizer iteration (value, gradient, Hessian, factorization) on
//! a generated three-tube junction (profiling aid):
//! `cargo run --release --example fair_phases [m rings]` (default 8 2: 1007 vertices).
use std::time::Instant;
use surfkit::fair::*;

fn main() -> surfkit::Result<()> {
    let args: Vec<u32> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let (m, rings) = (*args.first().unwrap_or(&8), *args.get(1).unwrap_or(&2));
    let mesh = tubes(3, m, rings)?;
    let topo = MeshTopology::new(&mesh)?;
    let fixed = fixed_vertices(&topo, 3, &[])?;
    let special = topo.special_flags();
    let t = Instant::now();
    let rep = PatchRepresentation::new(
        &mesh,
        &topo.boundary,
        &special,
        &RepresentationOptions::default(),
    )?;
    println!(
        "{} vertices, {} elements, {} quadrature points, representation {:?}",
        mesh.vertex_count(),
        rep.element_count(),
        rep.points().len(),
        t.elapsed()
    );
    let f = Functional::new(&rep, &fixed, 1.0);
    let x = &mesh.positions;
    let t = Instant::now();
    let v = f.value(x);
    println!("value {:?} (F {:e})", t.elapsed(), v.f);
    let t = Instant::now();
    let _ = f.gradient(x);
    println!("gradient {:?}", t.elapsed());
    let repeats: usize = std::env::var("HESSIANS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    let t = Instant::now();
    let (_, g, h) = f.hessian(x);
    for _ in 1..repeats {
        let _ = f.hessian(x);
    }
    println!(
        "hessian {:?} each ({} blocks)",
        t.elapsed() / repeats as u32,
        h.blocks.len()
    );
    let mut factorizer = Factorizer::new(f.free_count());
    let t = Instant::now();
    let factor = factorizer.factor(&h, 1e6);
    println!("first factor {:?}", t.elapsed());
    let t = Instant::now();
    let factor2 = factorizer.factor(&h, 1e6);
    println!("second factor {:?}", t.elapsed());
    if let (Ok(a), Ok(_)) = (factor, factor2) {
        let t = Instant::now();
        let _ = a.newton_step(&g);
        println!("solve {:?}", t.elapsed());
    }
    Ok(())
}
