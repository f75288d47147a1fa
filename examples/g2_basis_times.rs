//! `cargo run --release --example g2_basis_times [K ...]`: how long the G² special
//! element's basis (the patch matrix of valence k) takes to compute, per valence (default
//! 3 and 5..=16) — paid once per valence per process, on the first special vertex of that
//! valence.

use std::time::Instant;

use surfkit::fair::PatchMatrix;

fn main() -> surfkit::Result<()> {
    let wanted: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let valences: Vec<usize> = if wanted.is_empty() {
        std::iter::once(3).chain(5..=16).collect()
    } else {
        wanted
    };
    println!("valence  seconds  inner dimension");
    for k in valences {
        let start = Instant::now();
        let basis = PatchMatrix::compute(k)?;
        println!(
            "{k:7}  {:7.3}  {}",
            start.elapsed().as_secs_f64(),
            basis.inner_dimension
        );
    }
    Ok(())
}
