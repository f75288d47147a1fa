//! The C and C++ doors as an outside program meets them: scripts/install-cpp.sh installs the
//! library into a temporary prefix; the examples (examples/cpp) are built both ways — g++ with
//! `pkg-config --cflags --libs surfkit`, and CMake with `find_package(surfkit CONFIG)` — and
//! run; their results are compared with the Rust library's on the same inputs: EAT counts
//! and flaw sets on every fixture (as OpenMesh holds it), subdivision positions bit for bit
//! (double traits), fairing output (same iterates), and the accompanying test on the paper's
//! stamp. The native door checks (bad input, callbacks, 1000 create/free cycles of every
//! handle) run plainly and under AddressSanitizer + LeakSanitizer.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use surfkit::fair::{optimize, tubes, FairOptions};
use surfkit::mesh::io::{read_with, write, ReadOptions, WriteOptions};
use surfkit::mesh::PolygonMesh;
use surfkit::repair::check_fixes;
use surfkit::shapes::{stamp, StampFlaw, STAMP_STAGES};
use surfkit::subdiv::{refine_uniform, SubdivOptions};
use surfkit::topology::{scan, EatOptions, LocatorOptions, ModelCompanion};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// target/<profile>, where cargo put libsurfkit.so and libsurfkit.a for this test run.
fn built_libs() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let dir = exe.parent().unwrap().parent().unwrap().to_path_buf();
    assert!(
        dir.join("libsurfkit.so").exists(),
        "no libsurfkit.so in {}: `cargo test` does not build the C library, run \
         `cargo build --release --workspace` first (scripts/test.sh does)",
        dir.display()
    );
    dir
}

fn run(cmd: &mut Command) -> Output {
    let out = cmd.output().unwrap_or_else(|e| panic!("{cmd:?}: {e}"));
    out
}

fn ok(cmd: &mut Command) -> String {
    let out = run(cmd);
    assert!(
        out.status.success(),
        "{cmd:?} failed: {}\n{}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

struct Installed {
    _dir: tempfile::TempDir,
    prefix: PathBuf,
    bin: PathBuf,
}

impl Installed {
    fn new() -> Self {
        let dir = tempfile::tempdir().unwrap();
        let prefix = dir.path().join("prefix");
        ok(Command::new("bash")
            .arg(repo().join("scripts/install-cpp.sh"))
            .arg(&prefix)
            .env("SURFKIT_BUILT_LIBS", built_libs()));
        let bin = dir.path().join("bin");
        std::fs::create_dir_all(&bin).unwrap();
        Installed {
            _dir: dir,
            prefix,
            bin,
        }
    }

    fn pkg_config(&self) -> Vec<String> {
        let flags = ok(Command::new("pkg-config")
            .args(["--cflags", "--libs", "surfkit"])
            .env("PKG_CONFIG_PATH", self.prefix.join("lib/pkgconfig")));
        flags.split_whitespace().map(String::from).collect()
    }

    /// Compiles `source` with g++ and the flags pkg-config gives for surfkit.
    fn gxx(&self, source: &Path, name: &str, extra: &[&str]) -> PathBuf {
        let exe = self.bin.join(name);
        ok(Command::new("g++")
            // GCC 12 flags OpenMesh's own PropertyT::push_back (a default-constructed
            // VectorT) as maybe-uninitialized at -O1 and above: not surfkit's code.
            .args([
                "-std=c++17",
                "-O2",
                "-Wall",
                "-Wextra",
                "-Werror",
                "-Wno-maybe-uninitialized",
            ])
            .args(extra)
            .arg(source)
            .arg("-o")
            .arg(&exe)
            .args(self.pkg_config()));
        exe
    }

    fn command(&self, exe: &Path) -> Command {
        let mut c = Command::new(exe);
        c.env("LD_LIBRARY_PATH", self.prefix.join("lib"));
        c
    }
}

/// The exact coordinates the example wrote, one vertex a line (17 significant digits).
fn read_xyz(path: &Path) -> Vec<[f64; 3]> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| {
            let c: Vec<f64> = l.split_whitespace().map(|w| w.parse().unwrap()).collect();
            [c[0], c[1], c[2]]
        })
        .collect()
}

/// Index and values of the first differing vertex, if any.
fn first_difference(a: &[[f64; 3]], b: &[[f64; 3]]) -> Option<(usize, [f64; 3], [f64; 3])> {
    assert_eq!(a.len(), b.len(), "vertex counts differ");
    a.iter()
        .zip(b)
        .enumerate()
        .find(|(_, (p, q))| p != q)
        .map(|(i, (p, q))| (i, *p, *q))
}

fn read(path: &Path) -> PolygonMesh {
    read_with(
        path,
        &ReadOptions {
            keep_degenerate: true,
        },
    )
    .unwrap()
}

/// The example's EAT lines, as the Rust library gives them for `mesh`.
fn expected_eat_lines(mesh: &PolygonMesh) -> Vec<String> {
    let mut r = scan(
        mesh,
        &EatOptions {
            halfedge: true,
            ..Default::default()
        },
    )
    .unwrap();
    check_fixes(mesh, &mut r.flaws, LocatorOptions::default()).unwrap();
    let c = &r.counts;
    let mut lines = vec![format!(
        "eat V {} E {} F {} chi {} loops {} components {} genus {} flaws {}",
        c.vertices_referenced,
        c.edges,
        c.facets,
        c.euler_characteristic,
        c.boundary_loops,
        c.components,
        c.genus.unwrap_or(-1),
        r.flaws.len()
    )];
    for f in &r.flaws {
        let ids = |v: &[u32]| v.iter().map(|i| format!(" {i}")).collect::<String>();
        let fix = match f.fix_verified {
            None => "unchecked",
            Some(true) => "verified",
            Some(false) => "not verified",
        };
        lines.push(format!(
            "flaw {} v{} f{} fix {fix}",
            f.kind.name(),
            ids(&f.vertices),
            ids(&f.faces)
        ));
    }
    lines
}

/// The stamp as a drawing script for modeller_companion (`v`, `f`, and `check CHI` at each
/// stage's end), and where the library's registry stops: the first failing stage (1-based)
/// and the input ids of the facets since the last verified point.
fn stamp_script(flaws: &[StampFlaw]) -> (String, Option<(usize, Vec<u32>)>) {
    let mesh = stamp(flaws);
    let groups = mesh.groups.as_ref().unwrap();
    let mut script = String::new();
    for p in &mesh.positions {
        script.push_str(&format!("v {} {} {}\n", p[0], p[1], p[2]));
    }
    let mut reference = ModelCompanion::new();
    let mut stop: Option<(usize, Vec<u32>)> = None;
    for (f, corners) in mesh.faces().enumerate() {
        script.push('f');
        for c in corners {
            script.push_str(&format!(" {c}"));
        }
        script.push('\n');
        reference.register(corners, f as u32).unwrap();
        let stage_ends = f + 1 == mesh.face_count() || groups.of_face[f + 1] != groups.of_face[f];
        if stage_ends {
            let chi = STAMP_STAGES[groups.of_face[f] as usize].1;
            script.push_str(&format!("check {chi}\n"));
            let c = reference.checkpoint(chi);
            if !c.verified && stop.is_none() {
                stop = Some((
                    groups.of_face[f] as usize + 1,
                    c.since_last_verified.iter().map(|d| d.input_id).collect(),
                ));
            }
        }
    }
    (script, stop)
}

#[test]
fn cpp_examples_built_with_pkg_config_and_cmake_agree_with_the_library() {
    let installed = Installed::new();
    let examples = repo().join("examples/cpp");
    let pipeline = installed.gxx(
        &examples.join("openmesh_pipeline.cc"),
        "openmesh_pipeline",
        &[],
    );
    let companion = installed.gxx(
        &examples.join("modeller_companion.cc"),
        "modeller_companion",
        &[],
    );

    // CMake: find_package(surfkit CONFIG REQUIRED) + target_link_libraries(surfkit::surfkit).
    let build = installed.bin.join("cmake-build");
    ok(Command::new("cmake")
        .arg("-S")
        .arg(&examples)
        .arg("-B")
        .arg(&build)
        .arg(format!(
            "-DCMAKE_PREFIX_PATH={}",
            installed.prefix.display()
        )));
    ok(Command::new("cmake").arg("--build").arg(&build));
    for exe in [&pipeline, &build.join("openmesh_pipeline")] {
        assert!(exe.exists());
    }

    // The tube junction to fair (the generator's 359-vertex three-tube topology), with
    // coordinates rounded to float: OpenMesh's OBJ reader parses floats, and both sides
    // must start from the same mesh.
    let work = tempfile::tempdir().unwrap();
    let tubes_path = work.path().join("tubes.obj");
    let mut junction = tubes(3, 4, 3).unwrap();
    for p in &mut junction.positions {
        *p = p.map(|c| c as f32 as f64);
    }
    write(&tubes_path, &junction, &WriteOptions::default()).unwrap();

    let mut fixtures: Vec<PathBuf> = std::fs::read_dir(repo().join("fixtures/meshes"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            matches!(
                p.extension().and_then(|e| e.to_str()),
                Some("obj" | "ply" | "off")
            )
        })
        .collect();
    fixtures.sort();
    assert!(fixtures.len() >= 10);
    let mut faired_once = false;
    for (k, fixture) in fixtures.iter().enumerate() {
        // Both builds of the example on alternate fixtures: they must behave alike.
        let exe = if k % 2 == 0 {
            pipeline.clone()
        } else {
            build.join("openmesh_pipeline")
        };
        let out = work.path().join(format!("out{k}"));
        std::fs::create_dir_all(&out).unwrap();
        let result = run(installed
            .command(&exe)
            .arg(fixture)
            .arg(&tubes_path)
            .arg(&out));
        let stdout = String::from_utf8_lossy(&result.stdout).to_string();
        let stderr = String::from_utf8_lossy(&result.stderr).to_string();
        let held_path = out.join("held.obj");
        if !held_path.exists() {
            // OpenMesh itself could not read the file: a clean error, no crash.
            assert_eq!(
                result.status.code(),
                Some(1),
                "{}: {stderr}",
                fixture.display()
            );
            assert!(
                stderr.contains("cannot read"),
                "{}: {stderr}",
                fixture.display()
            );
            continue;
        }
        let mut held = read(&held_path);
        held.positions = read_xyz(&out.join("held.xyz"));
        let lines: Vec<&str> = stdout.lines().collect();
        let expected = expected_eat_lines(&held);
        assert_eq!(
            &lines[..expected.len().min(lines.len())],
            &expected.iter().map(String::as_str).collect::<Vec<_>>()[..],
            "{}: EAT through the C++ layer differs from the library\n{stderr}",
            fixture.display()
        );
        match refine_uniform(&held, 2, &SubdivOptions::default()) {
            Ok(fine) => {
                assert!(result.status.success(), "{}: {stderr}", fixture.display());
                let cpp = read(&out.join("subdivided.obj"));
                assert_eq!(cpp.face_offsets, fine.face_offsets, "{}", fixture.display());
                assert_eq!(cpp.face_indices, fine.face_indices, "{}", fixture.display());
                let exact = read_xyz(&out.join("subdivided.xyz"));
                assert_eq!(
                    first_difference(&exact, &fine.positions),
                    None,
                    "{}: not bit-identical",
                    fixture.display()
                );
            }
            Err(e) => {
                // The library refuses the mesh; the C++ layer must say so, not crash.
                assert_eq!(result.status.code(), Some(1), "{}", fixture.display());
                assert!(
                    stderr.contains("surfkit error"),
                    "{}: {stderr} (library: {e})",
                    fixture.display()
                );
                continue;
            }
        }
        if !faired_once {
            let tubes_held = junction.clone();
            let options = FairOptions {
                max_refinements: 0,
                ..FairOptions::default()
            };
            let (optimized, report) = optimize(&tubes_held, &options).unwrap();
            assert!(report.newton.converged);
            let cpp = read(&out.join("faired.obj"));
            assert_eq!(
                cpp.face_indices, tubes_held.face_indices,
                "topology untouched"
            );
            let exact = read_xyz(&out.join("faired.xyz"));
            assert_eq!(
                first_difference(&exact, &optimized.positions),
                None,
                "the C++ fair is not the library's"
            );
            let line = lines.iter().find(|l| l.starts_with("fair ")).unwrap();
            assert!(
                line.starts_with(&format!(
                    "fair converged 1 iterations {}",
                    report.newton.iterations.len()
                )),
                "{line}"
            );
            faired_once = true;
        }
    }
    assert!(faired_once, "no fixture reached the fairing step");

    // The accompanying test on the paper's stamp, clean and with each of its flaws.
    for flaws in [
        vec![],
        vec![StampFlaw::TinyTriangle],
        vec![StampFlaw::NarrowQuad],
        vec![StampFlaw::Crack],
    ] {
        let (script, expected_stop) = stamp_script(&flaws);
        let path = work.path().join("stamp.txt");
        std::fs::write(&path, script).unwrap();
        for exe in [&companion, &build.join("modeller_companion")] {
            let result = run(installed.command(exe).arg(&path));
            let stdout = String::from_utf8_lossy(&result.stdout).to_string();
            match &expected_stop {
                None => {
                    assert!(result.status.success(), "{flaws:?}: {stdout}");
                    assert_eq!(
                        stdout.matches(" verified").count(),
                        STAMP_STAGES.len(),
                        "{stdout}"
                    );
                }
                Some((stage, suspects)) => {
                    assert_eq!(result.status.code(), Some(3), "{flaws:?}: {stdout}");
                    assert!(
                        stdout.contains(&format!("test point {stage}: "))
                            && stdout.contains("FAILED"),
                        "{stdout}"
                    );
                    let line = stdout.lines().find(|l| l.starts_with("suspects")).unwrap();
                    let got: Vec<u32> = line
                        .split_whitespace()
                        .skip(1)
                        .map(|w| w.parse().unwrap())
                        .collect();
                    assert_eq!(&got, suspects, "{flaws:?}");
                }
            }
        }
    }
}

#[test]
fn door_checks_pass_plainly_and_under_address_and_leak_sanitizer() {
    let installed = Installed::new();
    let source = repo().join("capi/tests/native/door_checks.cc");
    let plain = installed.gxx(&source, "door_checks", &[]);
    let stdout = ok(&mut installed.command(&plain));
    assert!(stdout.starts_with("ok: "), "{stdout}");
    let asan = installed.gxx(
        &source,
        "door_checks_asan",
        &["-g", "-fsanitize=address", "-fno-omit-frame-pointer"],
    );
    // OpenMesh's own std::cerr target of omerr(), dropped once when surfkit routes omerr
    // into its capture (OpenMesh's disconnect never frees it): one allocation made inside
    // libOpenMeshCore, not per call. Every other leak fails the test.
    let suppressions = installed.bin.join("lsan.supp");
    std::fs::write(&suppressions, "leak:libOpenMeshCore.so\n").unwrap();
    let stdout = ok(installed
        .command(&asan)
        .env("ASAN_OPTIONS", "detect_leaks=1:abort_on_error=0")
        .env(
            "LSAN_OPTIONS",
            format!(
                "suppressions={}:print_suppressions=0",
                suppressions.display()
            ),
        ));
    assert!(stdout.starts_with("ok: "), "{stdout}");
}

#[test]
fn spline_fits_through_the_cpp_layer_equal_the_library() {
    use surfkit::fit::data::ScatteredData;
    use surfkit::fit::fill::FillVariant;
    use surfkit::fit::pipeline::{fit_and_fill, FitSetup, HoleSource, SpaceKind};
    use surfkit::fit::shape::{ShapeConstraints, Tau};

    let installed = Installed::new();
    let exe = installed.gxx(
        &repo().join("capi/tests/native/fit_check.cc"),
        "fit_check",
        &[],
    );
    // A positive height field sampled on a 30 × 30 grid with a disc of no data (the hole).
    let mut data = ScatteredData::default();
    let mut csv = String::new();
    for j in 0..30 {
        for i in 0..30 {
            let (u, v) = (i as f64 / 29.0, j as f64 / 29.0);
            if (u - 0.5).powi(2) + (v - 0.5).powi(2) < 0.04 {
                continue;
            }
            let z = 0.2 + (u - 0.3).powi(2) + 0.5 * (v * 3.0).sin().powi(2);
            data.params.push([u, v]);
            data.points.push([u, v, z]);
            csv.push_str(&format!("{u:?},{v:?},{u:?},{v:?},{z:?}\n"));
        }
    }
    let work = tempfile::tempdir().unwrap();
    let path = work.path().join("data.csv");
    std::fs::write(&path, csv).unwrap();
    for (space, code, cells, hole, shape) in [
        (SpaceKind::Biquadratic, 0, 6, false, false),
        (SpaceKind::Bicubic, 1, 5, true, false),
        (SpaceKind::BfsC1, 2, 5, true, true),
    ] {
        let setup = FitSetup {
            space,
            cells: [cells, cells],
            epsilon: 1e-9,
            hole: if hole {
                HoleSource::CellsWithoutData
            } else {
                HoleSource::None
            },
            variant: FillVariant::Paper,
            shape: shape.then(|| ShapeConstraints {
                component: 2,
                value: Some(Tau::Plus),
                slope_x: None,
                slope_y: None,
                extra_per_side: 2,
                extra_points: Vec::new(),
            }),
        };
        let outcome = fit_and_fill(&data, &setup).unwrap();
        assert_eq!(outcome.fill.is_some(), hole, "{space:?}");
        let mut expected = Vec::new();
        for j in 0..=10 {
            for i in 0..=10 {
                expected.push(outcome.eval(i as f64 / 10.0, j as f64 / 10.0).unwrap());
            }
        }
        let stdout = ok(installed.command(&exe).arg(&path).args([
            code.to_string(),
            cells.to_string(),
            (hole as u8).to_string(),
            (shape as u8).to_string(),
        ]));
        let got: Vec<[f64; 3]> = stdout
            .lines()
            .map(|l| {
                let c: Vec<f64> = l.split_whitespace().map(|w| w.parse().unwrap()).collect();
                [c[0], c[1], c[2]]
            })
            .collect();
        assert_eq!(first_difference(&got, &expected), None, "{space:?}");
    }
}
