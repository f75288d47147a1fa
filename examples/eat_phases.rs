//! Times the phases of the EAT scan on a generated 1M-triangle torus (profiling aid).
use std::time::Instant;
use surfkit::shapes::grid_torus;
use surfkit::topology::*;
fn main() {
    let scale: u32 = std::env::var("SCALE")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    let mesh = grid_torus(1000 * scale, 500 * scale, true);
    let t = Instant::now();
    let mut c = ModelCompanion::with_capacity(
        mesh.vertex_count(),
        mesh.face_count(),
        mesh.face_indices.len(),
    );
    for (f, corners) in mesh.faces().enumerate() {
        c.register_facet(corners, f as u32);
    }
    println!("registry {:?}", t.elapsed());
    let t = Instant::now();
    let s = Structure::of(c.registry());
    println!("structure {:?}", t.elapsed());
    let t = Instant::now();
    let _ = boundary_walks(c.registry(), &s);
    println!("walks {:?}", t.elapsed());
    let t = Instant::now();
    let r = scan(&mesh, &EatOptions::default()).unwrap();
    println!("scan {:?} {}", t.elapsed(), r.flaws.len());
}
