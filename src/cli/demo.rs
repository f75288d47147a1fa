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
use crate::report::html::{eat_page, html_escape, surface_page, write_html};
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

/// The demo's HTML reports, one per section, with the index page that links them.
struct Reports {
    index: PathBuf,
    sections: [(PathBuf, &'static str); 5],
}

impl Reports {
    fn in_folder(out: &Path) -> Self {
        Reports {
            index: out.join("index.html"),
            sections: [
                (
                    out.join("target_eat.html"),
                    "the built-in example and its holes (EAT)",
                ),
                (
                    out.join("stamp_eat.html"),
                    "the EAT on the flawed stamp, flaw by flaw",
                ),
                (
                    out.join("stamp_limit.html"),
                    "Catmull–Clark limit surface, mean curvature",
                ),
                (
                    out.join("kp2022_fill.html"),
                    "offset surface with holes, filled (KP 2022)",
                ),
                (
                    out.join("fair").join("tubes_fair.html"),
                    "Kiciak's fairing, before and after",
                ),
            ],
        }
    }

    /// The index: a plain page of links (no viewer), written last.
    fn write_index(&self) -> crate::Result<()> {
        let dir = self.index.parent().unwrap_or(Path::new("."));
        let mut items = String::new();
        for (path, what) in &self.sections {
            let href = path.strip_prefix(dir).unwrap_or(path).display().to_string();
            items.push_str(&format!(
                "<li><a href=\"{}\">{}</a></li>\n",
                html_escape(&href),
                html_escape(what)
            ));
        }
        let page = format!(
            "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>surfkit \
             demo</title><style>body{{font:15px system-ui,sans-serif;background:#303036;\
             color:#e6e6e6;margin:2em}}a{{color:#ffd84a}}</style></head><body><h1>surfkit \
             demo</h1><p>One report per section; each opens offline in this browser.</p><ol>\n\
             {items}</ol></body></html>\n"
        );
        crate::mesh::io::write_atomically(&self.index, |w| w.write_all(page.as_bytes()))
    }
}

pub fn run(args: &DemoArgs) -> crate::Result<ExitCode> {
    super::check_folder("--out", Some(&args.out))?;
    let reports = Reports::in_folder(&args.out);
    println!(
        "surfkit demo — open {} in a browser:",
        reports.index.display()
    );
    for (path, what) in &reports.sections {
        println!("  {}  ({what})", path.display());
    }
    println!();
    let source = Path::new(EXAMPLE_NAME);
    let mut mesh = parse(source, EXAMPLE, Format::Obj, &ReadOptions::default())?;
    let summary = MeshSummary::of(&mesh)?;
    println!("surfkit demo — built-in example");
    print!("{}", super::info::render(source, Format::Obj, &summary));
    let example_report = scan(&mesh, &EatOptions::default())?;
    let example_text = super::eat::render(EXAMPLE_NAME, &example_report, usize::MAX);
    std::fs::create_dir_all(&args.out).map_err(|e| Error::io(&args.out, e))?;
    write_html(
        &reports.sections[0].0,
        &eat_page(EXAMPLE_NAME, &mesh, &example_report, &example_text),
    )?;

    // Vertex valence as PLY quality, so MeshLab colours the mesh by it.
    let valences = build(&mesh)?.mesh.vertex_valences();
    mesh.quality = Some(valences.iter().map(|&v| f64::from(v)).collect());
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
    let stamp_text = super::eat::render("stamp.obj (built in)", &report, usize::MAX);
    write_html(
        &reports.sections[1].0,
        &eat_page("stamp.obj (built in)", &flawed, &report, &stamp_text),
    )?;
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
        "  {}  (the flawed stamp, stages as OBJ groups: try surfkit eat --stages groups --target \"{}\" on it)",
        stamp_path.display(),
        targets.join(";")
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
    write_html(
        &reports.sections[2].0,
        &surface_page(
            "limit surface of the repaired stamp",
            vec![("control faces".into(), repaired.face_count().to_string())],
            &[("limit surface", &sampled.mesh)],
            "mean curvature H",
            None,
        ),
    )?;
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
    let run =
        crate::fit::papers::kp2022::run(9, 500, 1e-9, 0, crate::fit::fill::FillVariant::Paper)?;
    println!(
        "  9 × 9 knots, 500 points, ε = 1e-9: Error₁ {:.3e} (paper 2.7695e-4), filled Error {:.3e} (paper 2.7216e-4), C¹ jump across the hole border {:.1e}",
        run.error1, run.error, run.c1_jump
    );
    println!("wrote:");
    let figures = crate::fit::papers::kp2022::figure_meshes(0)?;
    for path in crate::report::write_figures(&args.out, &figures)? {
        println!("  {}", path.display());
    }
    let panels: Vec<(&str, &crate::mesh::PolygonMesh)> =
        figures.iter().map(|(n, m)| (n.as_str(), m)).collect();
    write_html(
        &reports.sections[3].0,
        &surface_page(
            "KP 2022: offset surface with two holes, its approximation and the filling",
            vec![
                ("knots".into(), "9 × 9".into()),
                ("points".into(), "500".into()),
                (
                    "Error₁ (paper 2.7695e-4)".into(),
                    format!("{:.3e}", run.error1),
                ),
                (
                    "filled Error (paper 2.7216e-4)".into(),
                    format!("{:.3e}", run.error),
                ),
            ],
            &panels,
            "distance to the exact offset",
            None,
        ),
    )?;
    fairing(&args.out, &reports.sections[4].0)?;
    reports.write_index()?;
    println!("\nreports: {}", reports.index.display());
    Ok(ExitCode::SUCCESS)
}

/// Kiciak's shape optimization on the author's three-tube junction (359 vertices, issue 6):
/// the mean curvature before and after, and the files to look at.
fn fairing(out: &Path, html: &Path) -> crate::Result<()> {
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
    let html = super::fair::HtmlRequest {
        path: html,
        title: "Kiciak's fairing of a three-tube junction".into(),
        summary: super::html_pages::fair_summary("gen tubes (built in)", report, change, seconds),
        plot: Some(super::html_pages::fair_log_plot(report)),
    };
    let written = super::fair::write_results(
        &mesh,
        faired,
        Some(&samples_path),
        Some(&dir),
        Some(html),
        4,
        &options.representation,
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
