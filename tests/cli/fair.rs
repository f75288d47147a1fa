//! `surfkit fair` as a user runs it: the optimized mesh, limit samples whose quality is the
//! mean curvature (checked against finite differences of limit positions), before/after
//! pictures, and fixed vertices from an id list or a MeshLab-style PLY selection.

use std::path::Path;
use std::process::Command;

use surfkit::fair::{fixed_vertices, read_fixed, tubes, MeshTopology, FLOOR_MARGIN, VCG_SELECTED};
use surfkit::mesh::io::{read, write};
use surfkit::mesh::PolygonMesh;
use surfkit::subdiv::{
    limit_surface, BoundaryInterpolation, PatchOptions, SubdivOptions, SurfacePoint,
};
use surfkit::tolerance::FINITE_DIFFERENCE;

fn surfkit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_surfkit"))
}

/// The smallest junction of three tubes (53 vertices, 17 free): quick to optimize.
fn small_junction() -> PolygonMesh {
    tubes(3, 1, 3).unwrap()
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Mean curvature at (u, v) of a ptex face from limit *positions* only: central
/// differences for the first and second derivatives, then H = (E N − 2 F M + G L) /
/// (2 (E G − F²)) with n = S_u × S_v / |S_u × S_v| (surfkit's sign convention).
fn mean_curvature_by_differences(
    position: &dyn Fn(f64, f64) -> [f64; 3],
    u: f64,
    v: f64,
    h: f64,
) -> f64 {
    let p = |du: f64, dv: f64| position(u + du * h, v + dv * h);
    let c = p(0.0, 0.0);
    let scale = |a: [f64; 3], s: f64| a.map(|x| x * s);
    let su = scale(sub(p(1.0, 0.0), p(-1.0, 0.0)), 0.5 / h);
    let sv = scale(sub(p(0.0, 1.0), p(0.0, -1.0)), 0.5 / h);
    let second = |a: [f64; 3], b: [f64; 3]| [0, 1, 2].map(|x| (a[x] - 2.0 * c[x] + b[x]) / (h * h));
    let suu = second(p(1.0, 0.0), p(-1.0, 0.0));
    let svv = second(p(0.0, 1.0), p(0.0, -1.0));
    let suv = scale(
        sub(
            sub(p(1.0, 1.0), p(1.0, -1.0)),
            sub(p(-1.0, 1.0), p(-1.0, -1.0)),
        ),
        0.25 / (h * h),
    );
    let n = cross(su, sv);
    let n = scale(n, 1.0 / dot(n, n).sqrt());
    let (e, f, g) = (dot(su, su), dot(su, sv), dot(sv, sv));
    let (l, m, nn) = (dot(suu, n), dot(suv, n), dot(svv, n));
    (e * nn - 2.0 * f * m + g * l) / (2.0 * (e * g - f * f))
}

#[test]
fn fair_writes_mesh_samples_and_figures() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("junction.obj");
    let mesh = small_junction();
    write(&input, &mesh, &Default::default()).unwrap();
    let output = dir.path().join("faired.obj");
    let samples = dir.path().join("samples.ply");
    let figures = dir.path().join("figures");
    let density = 5; // grid points at multiples of 0.2: never on a patch border (dyadic)
    let run = surfkit()
        .arg("fair")
        .arg(&input)
        .arg("-o")
        .arg(&output)
        .arg("--samples")
        .arg(&samples)
        .arg("--sample-density")
        .arg(density.to_string())
        .arg("--figures")
        .arg(&figures)
        .args(["--max-refinements", "0", "--json"])
        .args(["--surface", "catmull-clark"])
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    // --json: no progress bar, only the report on stdout.
    let report: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    assert!(report["report"]["newton"]["converged"].as_bool().unwrap());
    let s0 = report["shape"]["s_before"].as_f64().unwrap();
    assert_eq!(
        s0,
        report["report"]["newton"]["initial"]["s"].as_f64().unwrap()
    );
    for name in ["curvature_before.png", "curvature_after.png"] {
        let bytes = std::fs::read(figures.join(name)).unwrap();
        assert_eq!(&bytes[1..4], b"PNG", "{name}");
    }

    // The optimized mesh: same faces, fixed vertices bit-identical.
    let out = read(&output).unwrap();
    crate::common::assert_faces_and_boundary_rings_kept(&mesh, &out);

    // The samples: one (K+1)² grid per internal face, in face order; positions are limit
    // points of the optimized mesh, quality its mean curvature.
    let sampled = read(&samples).unwrap();
    let quality = sampled.quality.as_ref().unwrap();
    let surface = limit_surface(
        &out,
        &SubdivOptions {
            boundary: BoundaryInterpolation::None,
            ..Default::default()
        },
        &PatchOptions::default(),
    )
    .unwrap();
    let n = density + 1;
    let internal: Vec<u32> = (0..out.face_count() as u32)
        .filter(|&f| {
            surface
                .locate(&SurfacePoint {
                    ptex_face: f,
                    u: 0.5,
                    v: 0.5,
                })
                .is_ok()
        })
        .collect();
    assert!(!internal.is_empty());
    assert_eq!(sampled.vertex_count(), internal.len() * n * n);
    let mut checked = 0;
    for (block, &face) in internal.iter().enumerate() {
        let position = |u: f64, v: f64| {
            surface
                .evaluate(&[SurfacePoint {
                    ptex_face: face,
                    u,
                    v,
                }])
                .unwrap()[0]
                .position
        };
        // Interior grid points only: the differences stay inside the face.
        for j in 1..density {
            for i in 1..density {
                let (u, v) = (i as f64 / density as f64, j as f64 / density as f64);
                let k = block * n * n + j * n + i;
                assert_eq!(sampled.positions[k], position(u, v), "sample {k}");
                let h = quality[k];
                assert!(h.is_finite());
                let fd = mean_curvature_by_differences(&position, u, v, 1e-4);
                assert!(
                    (h - fd).abs() <= FINITE_DIFFERENCE * h.abs().max(1.0),
                    "sample {k}: quality {h}, finite differences {fd}"
                );
                checked += 1;
            }
        }
    }
    assert_eq!(checked, internal.len() * (density - 1) * (density - 1));
}

/// An ASCII PLY of `mesh` with one extra integer vertex property.
fn ply_with_vertex_property(path: &Path, mesh: &PolygonMesh, name: &str, values: &[i64]) {
    let mut text = format!(
        "ply\nformat ascii 1.0\ncomment selection test\nelement vertex {}\n\
         property float x\nproperty float y\nproperty float z\nproperty int {name}\n\
         element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        mesh.vertex_count(),
        mesh.face_count()
    );
    for (p, x) in mesh.positions.iter().zip(values) {
        text += &format!("{} {} {} {x}\n", p[0], p[1], p[2]);
    }
    for f in mesh.faces() {
        text += &format!(
            "{} {}\n",
            f.len(),
            f.iter()
                .map(|v| v.to_string())
                .collect::<Vec<_>>()
                .join(" ")
        );
    }
    std::fs::write(path, text).unwrap();
}

#[test]
fn fair_fixed_from_a_meshlab_selection() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = small_junction();
    let topo = MeshTopology::new(&mesh).unwrap();
    let free: Vec<u32> = fixed_vertices(&topo, 3, &[])
        .unwrap()
        .iter()
        .enumerate()
        .filter(|(_, &f)| !f)
        .map(|(v, _)| v as u32)
        .collect();
    // Select two free vertices; other bits (VISITED 0x10, BORDER 0x100) elsewhere must not
    // count as a selection.
    let chosen = [free[0], free[free.len() / 2]];
    let flags: Vec<i64> = (0..mesh.vertex_count() as u32)
        .map(|v| {
            if chosen.contains(&v) {
                VCG_SELECTED | 0x0100
            } else {
                0x0010 | 0x0100
            }
        })
        .collect();
    let selection = dir.path().join("selection.ply");
    ply_with_vertex_property(&selection, &mesh, "flags", &flags);
    assert_eq!(read_fixed(&selection, mesh.vertex_count()).unwrap(), chosen);

    let input = dir.path().join("junction.obj");
    write(&input, &mesh, &Default::default()).unwrap();
    let output = dir.path().join("faired.obj");
    let run = surfkit()
        .arg("fair")
        .arg(&input)
        .arg("-o")
        .arg(&output)
        .arg("--fixed")
        .arg(&selection)
        .args(["--max-refinements", "0", "--json"])
        .args(["--surface", "catmull-clark"])
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let report: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    assert_eq!(
        report["report"]["free_vertices"].as_u64().unwrap() as usize,
        free.len() - chosen.len()
    );
    let out = read(&output).unwrap();
    for &v in &chosen {
        assert_eq!(out.positions[v as usize], mesh.positions[v as usize]);
    }
    // Free vertices that were not selected moved.
    assert!(free
        .iter()
        .filter(|v| !chosen.contains(v))
        .any(|&v| out.positions[v as usize] != mesh.positions[v as usize]));
}

/// A binary PLY (little or big endian) of vertices only, float x y z and int flags.
fn binary_flags_ply(mesh: &PolygonMesh, flags: &[i32], big_endian: bool) -> Vec<u8> {
    let mut bytes = format!(
        "ply\nformat binary_{}_endian 1.0\nelement vertex {}\nproperty float x\n\
         property float y\nproperty float z\nproperty int flags\nend_header\n",
        if big_endian { "big" } else { "little" },
        mesh.vertex_count()
    )
    .into_bytes();
    for (p, &f) in mesh.positions.iter().zip(flags) {
        for x in p {
            let x = *x as f32;
            bytes.extend(if big_endian {
                x.to_be_bytes()
            } else {
                x.to_le_bytes()
            });
        }
        bytes.extend(if big_endian {
            f.to_be_bytes()
        } else {
            f.to_le_bytes()
        });
    }
    bytes
}

#[test]
fn fair_selection_binary_ply() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = small_junction();
    let nv = mesh.vertex_count();
    let flags: Vec<i32> = (0..nv as i32)
        .map(|v| if v % 7 == 0 { 0x0020 | 0x0008 } else { 0x0200 })
        .collect();
    let expected: Vec<u32> = (0..nv as u32).filter(|v| v % 7 == 0).collect();
    for big_endian in [false, true] {
        let path = dir.path().join(format!("sel_{big_endian}.ply"));
        let bytes = binary_flags_ply(&mesh, &flags, big_endian);
        std::fs::write(&path, &bytes).unwrap();
        assert_eq!(read_fixed(&path, nv).unwrap(), expected);
        // Cut inside the last vertex: a parse error naming the file and the element.
        std::fs::write(&path, &bytes[..bytes.len() - 2]).unwrap();
        let err = read_fixed(&path, nv).unwrap_err().to_string();
        assert!(err.contains(&format!("sel_{big_endian}.ply")), "{err}");
        assert!(err.contains("vertex"), "{err}");
    }
}

#[test]
fn fair_selection_properties_and_errors() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = small_junction();
    let nv = mesh.vertex_count();
    // `selected`: nonzero; `quality`: > 0.
    let path = dir.path().join("selected.ply");
    let mask: Vec<i64> = (0..nv as i64).map(|v| i64::from(v % 10 == 3)).collect();
    ply_with_vertex_property(&path, &mesh, "selected", &mask);
    let expected: Vec<u32> = (0..nv as u32).filter(|v| v % 10 == 3).collect();
    assert_eq!(read_fixed(&path, nv).unwrap(), expected);
    let path = dir.path().join("quality.ply");
    let quality: Vec<i64> = (0..nv as i64)
        .map(|v| if v == 7 { 2 } else { -1 })
        .collect();
    ply_with_vertex_property(&path, &mesh, "quality", &quality);
    assert_eq!(read_fixed(&path, nv).unwrap(), vec![7]);
    // A PLY of another mesh, or without a selection property: errors naming the file.
    let err = read_fixed(&path, nv + 1).unwrap_err().to_string();
    assert!(
        err.contains("quality.ply") && err.contains(&nv.to_string()),
        "{err}"
    );
    let plain = dir.path().join("plain.ply");
    write(&plain, &mesh, &Default::default()).unwrap();
    let err = read_fixed(&plain, nv).unwrap_err().to_string();
    assert!(err.contains("plain.ply") && err.contains("flags"), "{err}");

    // Text ids: whitespace, commas and comments; errors name file, line and entry.
    let ids = dir.path().join("ids.txt");
    std::fs::write(&ids, "# held\n3, 5\n8 # and this\n").unwrap();
    assert_eq!(read_fixed(&ids, nv).unwrap(), vec![3, 5, 8]);
    std::fs::write(&ids, "3 5\n8 53\n").unwrap();
    let err = read_fixed(&ids, nv).unwrap_err().to_string();
    assert!(
        err.contains("ids.txt") && err.contains("line 2") && err.contains("entry 4"),
        "{err}"
    );
    assert!(err.contains("vertex 53 does not exist"), "{err}");
    std::fs::write(&ids, "3 -5\n").unwrap();
    let err = read_fixed(&ids, nv).unwrap_err().to_string();
    assert!(err.contains("entry 2") && err.contains("\"-5\""), "{err}");

    // The command reports it as an error, not a panic.
    let input = dir.path().join("junction.obj");
    write(&input, &mesh, &Default::default()).unwrap();
    let run = surfkit()
        .arg("fair")
        .arg(&input)
        .arg("-o")
        .arg(dir.path().join("out.obj"))
        .arg("--fixed")
        .arg(&ids)
        .output()
        .unwrap();
    assert!(!run.status.success());
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        stderr.starts_with("surfkit: error:") && stderr.contains("ids.txt"),
        "{stderr}"
    );
}

#[test]
fn demo_shows_fairing_of_the_three_tube_junction() {
    let dir = tempfile::tempdir().unwrap();
    let run = surfkit()
        .args(["demo", "--out"])
        .arg(dir.path())
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let text = String::from_utf8_lossy(&run.stdout);
    let fair = dir.path().join("fair");
    for name in [
        "tubes.obj",
        "tubes_faired.obj",
        "tubes_faired_samples.ply",
        "curvature_before.png",
        "curvature_after.png",
    ] {
        assert!(fair.join(name).is_file(), "{name} missing");
        assert!(text.contains(name), "{name} not listed:\n{text}");
    }
    let mesh = tubes(3, 4, 3).unwrap();
    let faired = read(&fair.join("tubes_faired.obj")).unwrap();
    assert_eq!(faired.face_indices, mesh.face_indices);
    assert_ne!(faired.positions, mesh.positions);
    assert!(
        text.contains("S = ∫|∇H|²") && text.contains("std H"),
        "{text}"
    );
}

#[test]
fn cli_fair_levels_write_the_finest_level() {
    let dir = tempfile::tempdir().unwrap();
    let coarse = small_junction();
    let input = dir.path().join("coarse.obj");
    write(&input, &coarse, &Default::default()).unwrap();
    let output = dir.path().join("fine.ply");
    let run = surfkit()
        .args([
            "fair",
            "--surface",
            "catmull-clark",
            "--levels",
            "1",
            "--json",
            "-o",
        ])
        .arg(&output)
        .arg(&input)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let report: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    let levels = report["levels"].as_array().unwrap();
    assert_eq!(levels.len(), 2);
    let fine = surfkit::fair::refine_surface(&coarse, 1).unwrap();
    assert_eq!(
        levels[1]["report"]["vertices"].as_u64().unwrap() as usize,
        fine.vertex_count()
    );
    for level in levels {
        assert!(level["report"]["newton"]["converged"].as_bool().unwrap());
    }
    let out = read(&output).unwrap();
    let fixed = crate::common::assert_faces_and_boundary_rings_kept(&fine, &out);
    assert!(fixed.iter().any(|&f| !f));
}

#[test]
fn fair_exit_status_says_whether_it_converged() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("junction.obj");
    write(&input, &small_junction(), &Default::default()).unwrap();
    let run = |extra: &[&str], out: &str| {
        let out = dir.path().join(out);
        let o = surfkit()
            .arg("fair")
            .arg(&input)
            .arg("-o")
            .arg(&out)
            .args(["--quiet", "--json", "--surface", "catmull-clark"])
            .args(extra)
            .output()
            .unwrap();
        let report: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        (o, report, out)
    };
    let (done, report, _) = run(&[], "done.obj");
    assert_eq!(done.status.code(), Some(0));
    assert_eq!(report["report"]["newton"]["converged"], true);
    // Two iterations do not reach 1e-8 of the initial gradient on this junction: the
    // positions reached are written, and the status says the goal was not met.
    let (short, report, out) = run(&["--max-iterations", "2"], "short.obj");
    assert_eq!(short.status.code(), Some(3));
    assert_eq!(report["report"]["newton"]["converged"], false);
    assert_eq!(
        report["report"]["newton"]["iterations"]
            .as_array()
            .unwrap()
            .len(),
        2
    );
    let said = String::from_utf8_lossy(&short.stderr);
    assert!(
        said.contains("not converged") && said.contains("after 2 iterations"),
        "{said}"
    );
    assert_eq!(
        read(&out).unwrap().vertex_count(),
        small_junction().vertex_count()
    );
    // A tolerance below what double coordinates can hold (‖g‖ of the minimum rounded to
    // nearest, the coordinate floor, is ~10⁻¹⁶ of ‖g₀‖ here, and a chosen rounding does
    // not gain a hundred times that): the run stops near that floor, says so, and
    // succeeds, having done what double coordinates allow.
    let (floored, report, _) = run(&["--tolerance", "1e-18"], "floor.obj");
    assert_eq!(floored.status.code(), Some(0));
    let newton = &report["report"]["newton"];
    assert_eq!(
        (&newton["converged"], &newton["stalled"]),
        (&false.into(), &true.into())
    );
    let floor = newton["coordinate_floor"].as_f64().unwrap();
    let (g0, g) = (
        report["report"]["initial_gradient_norm"].as_f64().unwrap(),
        report["report"]["final_gradient_norm"].as_f64().unwrap(),
    );
    assert!(
        g <= FLOOR_MARGIN * floor && floor > 1e-18 * g0,
        "‖g‖ {g:e}, floor {floor:e}"
    );
    let said = String::from_utf8_lossy(&floored.stderr);
    assert!(said.contains("the floor of f64 coordinates"), "{said}");
}
