//! `surfkit demo`: surfkit's main job on a built-in example, for a first look.
//!
//! The example is `target.obj` (a quad-dominant open surface with six holes, from the
//! trimesh test models, MIT; see fixtures/README.md), compiled into the binary; then the
//! EAT stamp, a limit surface, the KP 2022 hole filling, and Kiciak's shape optimization
//! of the author's three-tube junction (generated).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use crate::error::Error;
use crate::halfedge::{build, HalfEdgeTopology, MeshSummary};
use crate::mesh::io::{parse, write, Format, ReadOptions, WriteOptions};
use crate::report::{render_png, RenderOptions};
use crate::shapes::{stamp, StampFlaw};
use crate::subdiv::{
    limit_surface, refine_uniform, sample_limit, PatchOptions, SampleOptions, SubdivOptions,
};
use crate::topology::{
    mark_flaws, scan, stage_ends, test_points, EatOptions, StageSource, TargetTopology,
};

const EXAMPLE_NAME: &str = "target.obj";
const EXAMPLE: &[u8] = include_bytes!("../../fixtures/meshes/target.obj");

#[derive(clap::Args, Debug)]
pub struct DemoArgs {
    /// Folder for the files the demo writes.
    #[arg(long, default_value = "surfkit-demo")]
    pub out: PathBuf,
}

pub fn run(args: &DemoArgs) -> crate::Result<ExitCode> {
    super::check_folder("--out", Some(&args.out))?;
    let source = Path::new(EXAMPLE_NAME);
    let mut mesh = parse(source, EXAMPLE, Format::Obj, &ReadOptions::default())?;
    let summary = MeshSummary::of(&mesh)?;
    println!("surfkit demo — built-in example");
    print!("{}", super::info::render(source, Format::Obj, &summary));

    // Vertex valence as PLY quality, so MeshLab colours the mesh by it.
    let valences = build(&mesh)?.mesh.vertex_valences();
    mesh.quality = Some(valences.iter().map(|&v| f64::from(v)).collect());
    std::fs::create_dir_all(&args.out).map_err(|e| Error::io(&args.out, e))?;
    let written = [
        args.out.join("target_valence.ply"),
        args.out.join("target.off"),
    ];
    for path in &written {
        write(path, &mesh, &WriteOptions::default())?;
    }
    println!("wrote:");
    println!(
        "  {}  (binary PLY, vertex valence as quality: open it in MeshLab and colour by quality)",
        written[0].display()
    );
    println!("  {}  (OFF)", written[1].display());

    // The Euler Accompanying Test on the built-in stamp, drawn in four stages with the
    // three flaws of the paper's §4.1–4.3 injected.
    println!("\n— Euler Accompanying Test on the built-in stamp (with the paper's three flaws) —");
    let flawed = stamp(&[
        StampFlaw::TinyTriangle,
        StampFlaw::NarrowQuad,
        StampFlaw::Crack,
    ]);
    let targets = [
        "genus=0,boundaries=3",
        "genus=0,boundaries=2",
        "genus=0,boundaries=1",
        "genus=0",
    ];
    let expected: Vec<i64> = targets
        .iter()
        .map(|t| TargetTopology::parse(t).map(|t| t.euler_characteristic()))
        .collect::<crate::Result<_>>()?;
    let ends = stage_ends(&flawed, &StageSource::Groups)?;
    let options = EatOptions {
        test_points: test_points(&ends, &expected)?,
        halfedge: true,
        ..Default::default()
    };
    let report = scan(&flawed, &options)?;
    print!("{}", super::eat::render("stamp.obj (built in)", &report, 6));
    let stamp_path = args.out.join("stamp.obj");
    let marked_path = args.out.join("stamp_flaws.ply");
    write(&stamp_path, &flawed, &WriteOptions::default())?;
    write(
        &marked_path,
        &mark_flaws(&flawed, &report.flaws),
        &WriteOptions::default(),
    )?;
    println!("wrote:");
    println!(
        "  {}  (the flawed stamp, stages as OBJ groups: try surfkit eat --stages groups on it)",
        stamp_path.display()
    );
    println!(
        "  {}  (flawed vertices coloured for MeshLab)",
        marked_path.display()
    );

    // Catmull–Clark with OpenSubdiv: the stamp's limit surface and its curvature map.
    println!("\n— Catmull–Clark limit surface of the (repaired) stamp with OpenSubdiv —");
    let repaired = stamp(&[]);
    let surface = limit_surface(
        &repaired,
        &SubdivOptions::default(),
        &PatchOptions::default(),
    )?;
    let sampled = sample_limit(&surface, &SampleOptions { samples: 4 })?;
    let refined = refine_uniform(&repaired, 2, &SubdivOptions::default())?;
    let curvature_path = args.out.join("stamp_limit_curvature.ply");
    let picture_path = args.out.join("stamp_limit_curvature.png");
    let refined_path = args.out.join("stamp_level2.obj");
    write(&curvature_path, &sampled.mesh, &WriteOptions::default())?;
    let options = RenderOptions {
        title: Some("limit surface of the repaired stamp".to_string()),
        quantity: Some("mean curvature H".to_string()),
        ..RenderOptions::default()
    };
    render_png(&sampled.mesh, &picture_path, &options)?;
    write(&refined_path, &refined, &WriteOptions::default())?;
    let regular = surface.patches().iter().filter(|p| p.regular).count();
    println!(
        "  {} control faces → {} bicubic patches ({} regular, {} B-spline end caps); 2 uniform levels → {} quads",
        repaired.face_count(),
        surface.patches().len(),
        regular,
        surface.patches().len() - regular,
        refined.face_count()
    );
    println!("wrote:");
    println!(
        "  {}  (limit samples, mean curvature as quality)",
        curvature_path.display()
    );
    println!(
        "  {}  (picture of the curvature map)",
        picture_path.display()
    );
    println!(
        "  {}  (two levels of Catmull–Clark)",
        refined_path.display()
    );

    // Hole filling with a biquadratic smoothing spline (Kouibia & Pasadas 2022, §6 example).
    println!(
        "\n— Offset surface with two elliptic holes: smoothing spline and hole filling (KP 2022) —"
    );
    let run = crate::fit::paper_kp2022::run(9, 500, 1e-9, 0, crate::fit::fill::FillVariant::Paper)?;
    println!(
        "  9 × 9 knots, 500 points, ε = 1e-9: Error₁ {:.3e} (paper 2.7695e-4), filled Error {:.3e} (paper 2.7216e-4), C¹ jump across the hole border {:.1e}",
        run.error1, run.error, run.c1_jump
    );
    println!("wrote:");
    for path in
        crate::report::write_figures(&args.out, &crate::fit::paper_kp2022::figure_meshes(0)?)?
    {
        println!("  {}", path.display());
    }
    fairing(&args.out)?;
    Ok(ExitCode::SUCCESS)
}

/// Kiciak's shape optimization on the author's three-tube junction (359 vertices, issue 6):
/// the mean curvature before and after, and the files to look at.
fn fairing(out: &Path) -> crate::Result<()> {
    println!(
        "\n— Shape optimization of a Catmull–Clark surface (Kiciak): junction of three tubes —"
    );
    let mesh = crate::fair::tubes(3, 4, 3)?;
    let dir = out.join("fair");
    std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
    let input_path = dir.join("tubes.obj");
    write(&input_path, &mesh, &WriteOptions::default())?;
    let options = crate::fair::FairOptions::default();
    println!(
        "  {} vertices, {} quads, two saddles of valence 6; Newton to |g| ≤ {:.0e}·|g0| …",
        mesh.vertex_count(),
        mesh.face_count(),
        options.newton.relative_gradient
    );
    let run = super::fair::optimize_with_progress(&mesh, 0, &options, true)?;
    let (faired, report, change, seconds) = (&run.after, run.report(), &run.change, run.seconds);
    let faired_path = dir.join("tubes_faired.obj");
    write(&faired_path, faired, &WriteOptions::default())?;
    let samples_path = dir.join("tubes_faired_samples.ply");
    let written = super::fair::write_results(
        &mesh,
        faired,
        Some(&samples_path),
        Some(&dir),
        4,
        options.representation.isolation,
    )?;
    let iterations = report.newton.iterations.len();
    println!(
        "  S = ∫|∇H|² {:.4e} → {:.4e} ({:.2}× smaller), std H {:.4} → {:.4}, {} free \
         vertices, {iterations} Newton iterations ({} Hessians), {seconds:.1} s{}",
        change.s_before,
        change.s_after,
        change.s_before / change.s_after,
        change.std_h_before,
        change.std_h_after,
        report.free_vertices,
        report.newton.hessian_evaluations,
        report.newton.status_note()
    );
    println!("wrote:");
    println!(
        "  {}  (the control mesh: surfkit gen tubes)",
        input_path.display()
    );
    println!(
        "  {}  (optimized control mesh, same faces and vertex order)",
        faired_path.display()
    );
    println!(
        "  {}  (limit samples, mean curvature as quality)",
        samples_path.display()
    );
    for path in &written.figures {
        println!(
            "  {}  (curvature map, one colour scale for both)",
            path.display()
        );
    }
    Ok(())
}
