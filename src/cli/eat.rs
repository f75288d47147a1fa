//! `surfkit eat <mesh>`: the Euler Accompanying Test and the flaw list.
//!
//! Exit status: 0 when every test point is verified and no `--fail-on` flaw is found,
//! 3 when a test point fails or a `--fail-on` flaw is present, 1 on an error.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use crate::error::{Error, Result};
use crate::mesh::io::{read_with, write, ReadOptions, WriteOptions};
use crate::mesh::PolygonMesh;
use crate::report::html::{eat_page, write_html};
use crate::topology::{
    mark_flaws, scan, show_measure, stage_ends, test_points, EatOptions, EatReport, FlawKind,
    LocatorOptions, StageSource, TargetTopology,
};

/// Exit status when the mesh fails the test.
pub const TEST_FAILED: u8 = 3;

/// Flaws (and facets) the text report inside an HTML page lists; the page's own flaw list
/// has them all, and a million-flaw text would only make the file heavier.
const HTML_TEXT_FLAWS: usize = 200;

#[derive(clap::Args, Debug)]
pub struct EatArgs {
    /// The mesh (.obj, .ply, .off or .stl); several files or folders (searched recursively for
    /// .obj, .ply, .off and .stl) are scanned in parallel with one summary line per file.
    #[arg(required = true, num_args = 1..)]
    pub meshes: Vec<PathBuf>,
    /// Test points at the end of each OBJ `g` group or `o` object.
    #[arg(long, value_parser = ["groups", "objects"])]
    pub stages: Option<String>,
    /// Test points after these facet counts, e.g. 840,2410,5366.
    #[arg(long, value_delimiter = ',', conflicts_with = "stages")]
    pub test_points: Vec<usize>,
    /// A test point every N facets (N ≥ 1).
    #[arg(long, conflicts_with_all = ["stages", "test_points"],
          value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..))]
    pub every: Option<usize>,
    /// Expected χ per stage (or one value for the whole mesh), e.g. -1,0,1,2.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true, conflicts_with_all = ["target", "reference"])]
    pub expect: Vec<i64>,
    /// Target topology per stage, e.g. "genus=0,boundaries=3;genus=0" (χ = Σ 2 − 2g − b).
    #[arg(long, conflicts_with = "reference")]
    pub target: Option<String>,
    /// A reference mesh whose χ the whole mesh must have.
    #[arg(long)]
    pub reference: Option<PathBuf>,
    /// Distance under which distinct vertices count as coincident (default: same coordinates).
    #[arg(long, default_value_t = 0.0, value_parser = super::non_negative_finite)]
    pub weld_tolerance: f64,
    /// A boundary vertex within this fraction of a boundary edge's length of that edge (and
    /// joined to the edge's other side) is a T-vertex on it: a crack. In (0, 1).
    #[arg(long, default_value_t = crate::topology::DEFAULT_CRACK_TOLERANCE,
          value_parser = super::open_unit_interval)]
    pub crack_tolerance: f64,
    /// Exit with status 3 when flaws of these kinds are found (comma separated, or "any").
    #[arg(long, value_delimiter = ',')]
    pub fail_on: Vec<String>,
    /// Write the mesh with flawed vertices coloured (and the flaw kind as quality) here.
    #[arg(long)]
    pub mark: Option<PathBuf>,
    /// Write a self-contained HTML report here (one mesh): the mesh with its flaws
    /// highlighted by kind, boundary loops as lines, and the flaw list (a click centres the
    /// view on a flaw and shows its description and fix). Opens offline in any browser.
    #[arg(long)]
    pub html: Option<PathBuf>,
    /// How many flaws and facets to list in the human summary.
    #[arg(long, default_value_t = 20)]
    pub show: usize,
    /// Skip building the OpenMesh half-edge structure.
    #[arg(long)]
    pub no_halfedge: bool,
    /// Do not check the suggested fixes by applying them to a copy (`surfkit repair`)
    /// and scanning the result again (done only when there are flaws).
    #[arg(long)]
    pub no_fix_check: bool,
    /// Print the JSON report (schema in README.md) instead of text.
    #[arg(long, conflicts_with = "jsonl")]
    pub json: bool,
    /// One JSON object per file on its own line, streamed as each file finishes, then a
    /// summary line (any number of files or folders).
    #[arg(long)]
    pub jsonl: bool,
    /// Files scanned at once in folder mode (default: one per core).
    #[arg(long, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..=1024))]
    pub jobs: Option<usize>,
}

impl EatArgs {
    /// Whether the command scans many files (several inputs, a folder, or `--jsonl`).
    pub fn many(&self) -> bool {
        self.jsonl || self.meshes.len() > 1 || self.meshes.iter().any(|p| p.is_dir())
    }
}

pub(super) fn expected_chis(args: &EatArgs) -> Result<Vec<i64>> {
    if !args.expect.is_empty() {
        return Ok(args.expect.clone());
    }
    if let Some(t) = &args.target {
        return target_chis(t);
    }
    if let Some(r) = &args.reference {
        let reference = read_with(
            r,
            &ReadOptions {
                keep_degenerate: true,
            },
        )?;
        let report = scan(&reference, &EatOptions::default())?;
        return Ok(vec![report.statistics.euler_characteristic]);
    }
    // Test points are only reported where a χ is checked: without one they would be
    // dropped in silence and the command would pass.
    let placed = [
        ("--stages", args.stages.is_some()),
        ("--test-points", !args.test_points.is_empty()),
        ("--every", args.every.is_some()),
    ];
    if let Some((option, _)) = placed.iter().find(|(_, given)| *given) {
        return Err(unchecked_test_points(
            option,
            "--expect, --target or --reference",
        ));
    }
    Ok(Vec::new())
}

/// The χ of each stage of a `--target` (`;` between stages).
pub(super) fn target_chis(target: &str) -> Result<Vec<i64>> {
    target
        .split(';')
        .map(|s| TargetTopology::parse(s).map(|t| t.euler_characteristic()))
        .collect()
}

/// The refusal of test points placed by `option` with no χ to check at them (they would
/// be dropped in silence and the command would pass); `remedies` the options that give one.
pub(super) fn unchecked_test_points(option: &str, remedies: &str) -> Error {
    Error::InvalidInput(format!(
        "{option} places test points but no χ is given to check at them: add {remedies}"
    ))
}

pub(super) fn fail_kinds(names: &[String]) -> Result<Vec<FlawKind>> {
    let mut kinds = Vec::new();
    for n in names {
        if n == "any" {
            kinds.extend(FlawKind::ALL);
        } else {
            kinds.push(FlawKind::from_name(n).ok_or_else(|| {
                let all: Vec<&str> = FlawKind::ALL.iter().map(|k| k.name()).collect();
                Error::InvalidInput(format!(
                    "--fail-on: unknown flaw kind {n:?} (kinds: {}, any)",
                    all.join(", ")
                ))
            })?);
        }
    }
    Ok(kinds)
}

/// The scan of one file with the command's options: the mesh, its report, and the
/// `--fail-on` kinds found in it.
pub(super) fn scan_file(
    path: &Path,
    args: &EatArgs,
    expected: &[i64],
    fail_on: &[FlawKind],
) -> Result<(PolygonMesh, EatReport, Vec<FlawKind>)> {
    let mesh = read_with(
        path,
        &ReadOptions {
            keep_degenerate: true,
        },
    )?;
    let source = match (&args.stages, args.test_points.is_empty(), args.every) {
        (Some(s), _, _) if s == "groups" => StageSource::Groups,
        (Some(_), _, _) => StageSource::Objects,
        (None, false, _) => StageSource::FacetCounts(args.test_points.clone()),
        (None, true, Some(n)) => StageSource::Every(n),
        _ => StageSource::Whole,
    };
    let ends = stage_ends(&mesh, &source)?;
    let options = EatOptions {
        test_points: test_points(&ends, expected)?,
        locator: LocatorOptions {
            weld_tolerance: args.weld_tolerance,
            crack_tolerance: args.crack_tolerance,
        },
        halfedge: !args.no_halfedge,
    };
    let mut report = scan(&mesh, &options)?;
    if !args.no_fix_check {
        crate::repair::check_fixes(&mesh, &mut report.flaws, options.locator)?;
    }
    let failing_kinds: Vec<FlawKind> = report
        .flaw_counts()
        .into_iter()
        .map(|(k, _)| k)
        .filter(|k| fail_on.contains(k))
        .collect();
    Ok((mesh, report, failing_kinds))
}

pub fn run(args: &EatArgs) -> Result<ExitCode> {
    if args.many() {
        if args.html.is_some() {
            return Err(Error::InvalidInput(
                "--html writes the report of one mesh: give one file (not a folder, several \
                 files or --jsonl)"
                    .into(),
            ));
        }
        return super::eat_folder::run(args);
    }
    let path = &args.meshes[0];
    super::check_paths(
        &[Some(path), args.reference.as_deref()],
        &[
            ("--mark", args.mark.as_deref()),
            ("--html", args.html.as_deref()),
        ],
    )?;
    let fail_on = fail_kinds(&args.fail_on)?;
    let expected = expected_chis(args)?;
    let (mesh, report, failing_kinds) = scan_file(path, args, &expected, &fail_on)?;
    if let Some(out) = &args.mark {
        write(
            out,
            &mark_flaws(&mesh, &report.flaws),
            &WriteOptions::default(),
        )?;
    }
    let name = path.display().to_string();
    if let Some(out) = &args.html {
        // the page lists every flaw; its folded text report the first HTML_TEXT_FLAWS
        let text = render(&name, &report, HTML_TEXT_FLAWS);
        write_html(out, &eat_page(&name, &mesh, &report, &text))?;
    }
    if args.json {
        super::print_json(&serde_json::json!({
            "file": path,
            "verified": report.verified(),
            "failing_flaw_kinds": failing_kinds,
            "marked_mesh": args.mark,
            "html": args.html,
            "report": report,
        }))?;
    } else {
        print!("{}", render(&name, &report, args.show));
        if let Some(out) = &args.mark {
            println!(
                "wrote {} (flawed vertices coloured; quality = flaw kind number)",
                out.display()
            );
        }
        if let Some(out) = &args.html {
            println!("wrote {} (open it in a browser)", out.display());
        }
    }
    let failed = !report.verified() || !failing_kinds.is_empty();
    Ok(if failed {
        ExitCode::from(TEST_FAILED)
    } else {
        ExitCode::SUCCESS
    })
}

/// The human summary: statistics in the paper's screenshot style, test points, components,
/// and the flaws.
pub fn render(name: &str, report: &EatReport, show: usize) -> String {
    let mut out = String::new();
    let s = &report.statistics;
    let _ = writeln!(out, "EAT {name}");
    let _ = writeln!(out, "vertex number ***{}***vertex number", s.vertices);
    let _ = writeln!(out, "edge number ***{}***edge number", s.edges);
    let _ = writeln!(out, "facet number ***{}***facet number", s.facets);
    let _ = writeln!(
        out,
        "Euler characteristic***{}***Euler characteristic",
        s.euler_characteristic
    );
    for (i, (point, c)) in report.checkpoints.iter().enumerate() {
        let _ = writeln!(
            out,
            "test point {} \"{}\" after {} facets: V {} E {} F {} χ {} (expected {}) {}",
            i + 1,
            point.label,
            point.facets,
            c.statistics.vertices,
            c.statistics.edges,
            c.statistics.facets,
            c.statistics.euler_characteristic,
            c.expected_euler_characteristic,
            if c.verified { "verified" } else { "FAILED" }
        );
    }
    if let Some(i) = report.first_failure {
        let c = &report.checkpoints[i].1;
        let _ = writeln!(
            out,
            "first failing test point: {}; {} facets since the last verified point (after facet {}):",
            i + 1,
            c.since_last_verified.len(),
            c.last_verified_facets
        );
        for d in c.since_last_verified.iter().take(show) {
            let vs: String = d
                .vertices
                .iter()
                .map(|(v, vc)| format!("{v}**{vc}**"))
                .collect();
            let es: Vec<String> = d
                .edges
                .iter()
                .map(|(e, ec)| format!("{e}**{ec}**"))
                .collect();
            let _ = writeln!(
                out,
                "  facet {} (fc {}): {vs}  edges {}",
                d.input_id,
                d.fc,
                es.join(" ")
            );
        }
    }
    let c = &report.counts;
    let _ = writeln!(
        out,
        "components {}  boundary loops {} (walk {})  genus {}",
        c.components,
        c.boundary_loops,
        c.boundary_loops_walk
            .map_or("undefined".into(), |w| w.to_string()),
        genus_text(report)
    );
    for (i, comp) in report.components.iter().enumerate().take(show) {
        let _ = writeln!(
            out,
            "  component {i}: V {} E {} F {} χ {} loops {} {} genus {}",
            comp.vertices,
            comp.edges,
            comp.facets,
            comp.euler_characteristic,
            comp.boundary_loops,
            match comp.orientable {
                Some(true) => "orientable",
                Some(false) => "non-orientable",
                None => "orientation undefined",
            },
            comp.genus
                .map_or("-".into(), |g| if comp.orientable == Some(false) {
                    format!("{g} (cross-caps)")
                } else {
                    g.to_string()
                })
        );
    }
    if let Some(h) = &report.halfedge {
        let _ = writeln!(
            out,
            "OpenMesh half-edge structure: {} facets accepted, {} refused",
            h.accepted,
            h.refused.len()
        );
    }
    if report.flaws.is_empty() {
        let _ = writeln!(out, "no flaws found");
    } else {
        let counts: Vec<String> = report
            .flaw_counts()
            .iter()
            .map(|(k, n)| format!("{n} {}", k.name()))
            .collect();
        let _ = writeln!(out, "{} flaws: {}", report.flaws.len(), counts.join(", "));
        for f in report.flaws.iter().take(show) {
            let p = f.position;
            let _ = writeln!(
                out,
                "  {} at ({}, {}, {}): {}\n    fix{}: {}",
                f.kind.name(),
                show_measure(p[0]),
                show_measure(p[1]),
                show_measure(p[2]),
                f.description,
                match f.fix_verified {
                    Some(true) => " (checked by applying it)",
                    Some(false) => " (applying it did NOT remove the flaw)",
                    None => "",
                },
                f.suggested_fix
            );
        }
        if report.flaws.len() > show {
            let _ = writeln!(
                out,
                "  … {} more (--show N, or --json)",
                report.flaws.len() - show
            );
        }
    }
    out
}

/// The whole mesh's genus as the summaries print it.
pub(super) fn genus_text(report: &EatReport) -> String {
    let c = &report.counts;
    match (c.genus, c.non_orientable_genus) {
        (Some(g), _) => g.to_string(),
        (None, Some(k)) => format!("non-orientable {k}"),
        _ if report
            .components
            .iter()
            .any(|c| c.orientable == Some(false))
            && report.components.iter().all(|c| c.manifold) =>
        {
            "per component (orientable and non-orientable)".into()
        }
        _ => "undefined (non-manifold)".into(),
    }
}
