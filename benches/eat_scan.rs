//! The full EAT scan (registry, statistics, structure, flaw location) on generated 1M- and
//! 4M-triangle meshes, next to pymeshlab's `get_topological_measures()` on the same mesh
//! in memory, in one run. File loading is excluded on both sides.
//!
//! `cargo bench --bench eat_scan` (pymeshlab from the .venv of `scripts/setup.sh`).

mod support;

use surfkit::mesh::io::{write, WriteOptions};
use surfkit::shapes::grid_torus;
use surfkit::topology::{scan, EatOptions};

fn main() {
    println!(
        "EAT full scan vs pymeshlab get_topological_measures (in memory, same meshes, same run)"
    );
    println!(
        "{:>10} {:>12} {:>22} {:>12} {:>18} {:>18}",
        "triangles",
        "surfkit",
        "surfkit + OpenMesh",
        "pymeshlab",
        "pymeshlab/surfkit",
        "pymeshlab/(+OM)"
    );
    for (nu, nv, repeats) in [(1000u32, 500u32, 5usize), (2000, 1000, 3)] {
        let mesh = grid_torus(nu, nv, true);
        let path = support::data_dir().join(format!("torus_{}.ply", mesh.face_count()));
        if !path.exists() {
            write(&path, &mesh, &WriteOptions::default()).unwrap();
        }
        let plain = EatOptions::default();
        let with_openmesh = EatOptions {
            halfedge: true,
            ..Default::default()
        };
        let report = scan(&mesh, &plain).unwrap();
        assert_eq!(report.statistics.euler_characteristic, 0, "a torus");
        let ours = support::median_seconds(repeats, || {
            scan(&mesh, &plain).unwrap();
        });
        let ours_om = support::median_seconds(repeats, || {
            scan(&mesh, &with_openmesh).unwrap();
        });
        let peer = support::python_peer(
            "pymeshlab_topology.py",
            &[path.display().to_string(), repeats.to_string()],
        );
        let (pm, r1, r2) = match &peer {
            Ok(v) => {
                let t = v["median_s"].as_f64().unwrap();
                (
                    format!("{:.0} ms", t * 1e3),
                    format!("{:.1}", t / ours),
                    format!("{:.1}", t / ours_om),
                )
            }
            Err(e) => (format!("n/a ({e})"), "n/a".into(), "n/a".into()),
        };
        println!(
            "{:>10} {:>9.0} ms {:>19.0} ms {:>12} {:>18} {:>18}",
            mesh.face_count(),
            ours * 1e3,
            ours_om * 1e3,
            pm,
            r1,
            r2
        );
    }
}
