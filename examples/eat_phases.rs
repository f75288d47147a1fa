//! Times the EAT scan on a generated torus of SCALE² million triangles (profiling aid):
//! `SCALE=2 cargo run --release --example eat_phases [phases]`.
use std::time::Instant;
use surfkit::shapes::grid_torus;
use surfkit::topology::*;
fn main() {
    let scale: u32 = std::env::var("SCALE")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    let mesh = grid_torus(1000 * scale, 500 * scale, true);
    if std::env::args().any(|a| a == "phases") {
        let t = Instant::now();
        let mut c = ModelCompanion::with_capacity(
            mesh.vertex_count(),
            mesh.face_count(),
            mesh.face_indices.len(),
        );
        for (f, corners) in mesh.faces().enumerate() {
            c.register(corners, f as u32).unwrap();
        }
        println!("registry {:?}", t.elapsed());
        let t = Instant::now();
        let s = Structure::of(c.registry());
        println!("structure {:?}", t.elapsed());
        let t = Instant::now();
        let _ = boundary_walks(c.registry(), &s);
        println!("walks {:?}", t.elapsed());
        return;
    }
    let t = Instant::now();
    let r = scan(&mesh, &EatOptions::default()).unwrap();
    println!("scan {:?} ({} flaws)", t.elapsed(), r.flaws.len());
}
