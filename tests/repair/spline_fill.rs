//! `repair --fill-holes` with the 2022 paper's filled spline: on a height field with a round
//! hole the new vertices lie on the surface the data sample (known exactly here), far
//! closer than a fan's centroid; where the surroundings are not a height field, or the
//! loop is an outer border, the hole gets a fan and the change says why.

use surfkit::mesh::PolygonMesh;
use surfkit::repair::{repair, HoleFill, RepairOptions};
use surfkit::topology::{scan, EatOptions, FlawKind};

fn height(x: f64, y: f64) -> f64 {
    0.3 * (3.0 * x).sin() * (2.0 * y).cos() + 0.2 * x * x
}

/// An n × n grid of [0, 1]² lifted to `height`, triangulated, without the triangles whose
/// centroid lies within `radius` of `centre` (unreferenced vertices dropped).
fn holed_height_field(n: usize, centre: [f64; 2], radius: f64) -> PolygonMesh {
    let id = |i: usize, j: usize| (i * (n + 1) + j) as u32;
    let mut positions = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
            positions.push([x, y, height(x, y)]);
        }
    }
    let mut faces = Vec::new();
    for i in 0..n {
        for j in 0..n {
            for t in [
                [id(i, j), id(i + 1, j), id(i + 1, j + 1)],
                [id(i, j), id(i + 1, j + 1), id(i, j + 1)],
            ] {
                let c =
                    [0, 1].map(|k| t.iter().map(|&v| positions[v as usize][k]).sum::<f64>() / 3.0);
                if (c[0] - centre[0]).hypot(c[1] - centre[1]) > radius {
                    faces.push(t.to_vec());
                }
            }
        }
    }
    let mut used = vec![u32::MAX; positions.len()];
    let mut kept = Vec::new();
    for f in &mut faces {
        for v in f.iter_mut() {
            if used[*v as usize] == u32::MAX {
                used[*v as usize] = kept.len() as u32;
                kept.push(positions[*v as usize]);
            }
            *v = used[*v as usize];
        }
    }
    PolygonMesh::from_polygons(kept, &faces)
}

fn fill(max_hole_edges: usize, hole_fill: HoleFill) -> RepairOptions {
    RepairOptions {
        kinds: vec![FlawKind::Hole],
        max_hole_edges,
        hole_fill,
        ..RepairOptions::default()
    }
}

#[test]
fn a_hole_in_a_height_field_is_filled_on_the_surface() {
    let mesh = holed_height_field(40, [0.5, 0.45], 0.15);
    let before = scan(&mesh, &EatOptions::default()).unwrap();
    assert_eq!(before.counts.boundary_loops, 2);
    // The inner hole only (the outer border has 160 edges).
    let repaired = repair(&mesh, &fill(100, HoleFill::Spline)).unwrap();
    let after = scan(&repaired.mesh, &EatOptions::default()).unwrap();
    assert_eq!(after.counts.boundary_loops, 1);
    assert_eq!(after.counts.euler_characteristic, 1, "a disc");
    assert!(
        after.flaws.iter().all(|f| f.kind == FlawKind::Hole),
        "{:?}",
        after.flaws
    );
    assert_eq!(repaired.changes.len(), 1);
    assert!(
        repaired.changes[0].description.contains("filled spline"),
        "{}",
        repaired.changes[0].description
    );
    let new = &repaired.mesh.positions[mesh.vertex_count()..];
    assert!(new.len() > 50, "{} interior points", new.len());
    let worst = new
        .iter()
        .map(|p| (p[2] - height(p[0], p[1])).abs())
        .fold(0.0, f64::max);
    // The surface spans 0.45 in height: within 0.1 % of it.
    assert!(worst < 5e-4, "spline fill off the surface by {worst}");
    // Each new vertex lies inside the hole.
    assert!(new.iter().all(|p| (p[0] - 0.5).hypot(p[1] - 0.45) < 0.16));

    // A fan's centroid is far off the same surface: the spline is what makes it smooth.
    let fan = repair(&mesh, &fill(100, HoleFill::Fan)).unwrap();
    let c = fan.mesh.positions[mesh.vertex_count()];
    let fan_off = (c[2] - height(c[0], c[1])).abs();
    eprintln!(
        "{} spline vertices at most {worst:.2e} off the surface; the fan's centroid {fan_off:.2e}",
        new.len()
    );
    assert!(fan_off > 20.0 * worst);
}

#[test]
fn an_outer_border_gets_a_fan_and_says_why() {
    let mesh = holed_height_field(12, [0.5, 0.5], 0.0);
    let repaired = repair(&mesh, &fill(100, HoleFill::Spline)).unwrap();
    assert_eq!(repaired.changes.len(), 1);
    let said = &repaired.changes[0].description;
    assert!(
        said.contains("fan") && said.contains("outer border"),
        "{said}"
    );
    let after = scan(&repaired.mesh, &EatOptions::default()).unwrap();
    assert_eq!(after.counts.euler_characteristic, 2, "closed into a sphere");
    assert!(after.flaws.is_empty(), "{:?}", after.flaws);
}

#[test]
fn a_hole_whose_surroundings_fold_gets_a_fan_and_says_why() {
    // A closed tube (a torus of 32 × 8 quads) with a hole through the whole width of one
    // quad row: its three rings wrap round the tube, which is no height field.
    let torus = surfkit::shapes::grid_torus(32, 8, false);
    let faces: Vec<Vec<u32>> = torus
        .faces()
        .enumerate()
        .filter(|(f, _)| !(8..12).contains(f))
        .map(|(_, c)| c.to_vec())
        .collect();
    let mesh = PolygonMesh::from_polygons(torus.positions.clone(), &faces);
    let repaired = repair(&mesh, &fill(100, HoleFill::Spline)).unwrap();
    assert_eq!(repaired.changes.len(), 1, "{:?}", repaired.changes);
    let said = &repaired.changes[0].description;
    assert!(
        said.contains("fan") && said.contains("not a height field"),
        "{said}"
    );
    let after = scan(&repaired.mesh, &EatOptions::default()).unwrap();
    assert_eq!(after.counts.euler_characteristic, 0, "a torus again");
    assert!(after.flaws.is_empty(), "{:?}", after.flaws);
}
