//! `surfkit repair <in> <out>`: applies the fixes the EAT suggests, re-runs the EAT on the
//! result and says whether it is verified.
//!
//! Exit status: 0 when the result is verified (no flaw of the repaired kinds left, and the
//! target χ met at every test point when one is given), 3 when it is not (also when the
//! repair deleted every facet of the input), 1 on an error.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use super::eat::{target_chis, unchecked_test_points, TEST_FAILED};
use crate::error::{Error, Result};
use crate::mesh::io::{read_with, write, ReadOptions, WriteOptions};
use crate::mesh::PolygonMesh;
use crate::repair::{repair_located, Change, HoleFill, RepairOptions, Repaired};
use crate::topology::{
    mark_flaws, scan, stage_ends, test_points, EatOptions, EatReport, Flaw, FlawKind,
    LocatorOptions, StageSource,
};

/// How holes are closed (see `repair::HoleFill`).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum FillWith {
    /// The 2022 paper's filled spline over the hole's plane where the surroundings are a
    /// height field (new vertices on the spline); a fan elsewhere, saying why.
    Spline,
    /// Triangles around a new vertex at the border's centroid.
    Fan,
}

#[derive(clap::Args, Debug)]
pub struct RepairArgs {
    /// The mesh to repair (.obj, .ply, .off or .stl); it is never modified.
    pub input: PathBuf,
    /// Where to write the repaired mesh.
    pub output: PathBuf,
    /// Repair only these flaw kinds (comma separated; default: every kind but `hole`).
    #[arg(long, value_delimiter = ',')]
    pub only: Vec<String>,
    /// Also close holes of up to N edges (see --fill-with).
    #[arg(long, value_name = "N",
          value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(3..=1_000_000))]
    pub fill_holes: Option<usize>,
    /// How --fill-holes closes a hole of more than 4 edges.
    #[arg(long, value_enum, default_value_t = FillWith::Spline, requires = "fill_holes")]
    pub fill_with: FillWith,
    /// Distance under which distinct vertices are welded (default: same coordinates).
    #[arg(long, default_value_t = 0.0, value_parser = super::non_negative_finite)]
    pub weld_tolerance: f64,
    /// A boundary vertex within this fraction of a boundary edge's length of it is a
    /// T-vertex (a crack) to split the edge at. In (0, 1).
    #[arg(long, default_value_t = crate::topology::DEFAULT_CRACK_TOLERANCE,
          value_parser = super::open_unit_interval)]
    pub crack_tolerance: f64,
    /// Test points at the end of each OBJ `g` group or `o` object (checked on the result).
    #[arg(long, value_parser = ["groups", "objects"])]
    pub stages: Option<String>,
    /// Target topology per stage (or for the whole mesh), e.g. "genus=0,boundaries=1".
    #[arg(long, conflicts_with = "expect")]
    pub target: Option<String>,
    /// Expected χ per stage (or one value for the whole mesh).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub expect: Vec<i64>,
    /// Write the repaired mesh with the changed vertices coloured here (quality = the
    /// number of the flaw kind each change repaired).
    #[arg(long)]
    pub mark: Option<PathBuf>,
    /// How many changes to list in the text summary.
    #[arg(long, default_value_t = 20)]
    pub show: usize,
    /// Print a JSON report instead of text.
    #[arg(long)]
    pub json: bool,
}

fn kinds(args: &RepairArgs) -> Result<Vec<FlawKind>> {
    if args.only.is_empty() {
        let mut kinds = RepairOptions::default().kinds;
        if args.fill_holes.is_some() {
            kinds.push(FlawKind::Hole);
        }
        return Ok(kinds);
    }
    args.only
        .iter()
        .map(|n| {
            FlawKind::from_name(n).ok_or_else(|| {
                let all: Vec<&str> = FlawKind::ALL.iter().map(|k| k.name()).collect();
                Error::InvalidInput(format!(
                    "--only: unknown flaw kind {n:?} (kinds: {})",
                    all.join(", ")
                ))
            })
        })
        .collect()
}

fn expected(args: &RepairArgs) -> Result<Vec<i64>> {
    let expected = match &args.target {
        Some(t) => target_chis(t)?,
        None => args.expect.clone(),
    };
    if expected.is_empty() && args.stages.is_some() {
        return Err(unchecked_test_points("--stages", "--expect or --target"));
    }
    Ok(expected)
}

/// The EAT with the command's test points on `mesh`.
fn check(mesh: &PolygonMesh, args: &RepairArgs, locator: LocatorOptions) -> Result<EatReport> {
    let source = match args.stages.as_deref() {
        Some("groups") => StageSource::Groups,
        Some(_) => StageSource::Objects,
        None => StageSource::Whole,
    };
    let ends = stage_ends(mesh, &source)?;
    scan(
        mesh,
        &EatOptions {
            test_points: test_points(&ends, &expected(args)?)?,
            locator,
            halfedge: false,
        },
    )
}

/// The changed vertices of the written mesh as flaws of the kind each change repaired
/// (for `--mark`).
fn changed_vertices(changes: &[Change]) -> Vec<Flaw> {
    changes
        .iter()
        .map(|c| Flaw {
            kind: c.kind,
            vertices: c.vertices_after.iter().flatten().copied().collect(),
            faces: Vec::new(),
            position: [0.0; 3],
            shape: None,
            component: None,
            description: String::new(),
            fix_verified: None,
            suggested_fix: String::new(),
        })
        .collect()
}

fn counts_line(report: &EatReport) -> String {
    let c = &report.counts;
    format!(
        "V {} E {} F {} χ {}  boundary loops {}  components {}  genus {}",
        c.vertices_referenced,
        c.edges,
        c.facets,
        c.euler_characteristic,
        c.boundary_loops,
        c.components,
        super::eat::genus_text(report)
    )
}

fn render(
    args: &RepairArgs,
    before: &EatReport,
    after: &EatReport,
    repaired: &Repaired,
    left: &[&Flaw],
    emptied: bool,
) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "repair {} → {}",
        args.input.display(),
        args.output.display()
    );
    let _ = writeln!(out, "before: {}", counts_line(before));
    let _ = writeln!(out, "after:  {}", counts_line(after));
    let flaws = |r: &EatReport| {
        let c: Vec<String> = r
            .flaw_counts()
            .iter()
            .map(|(k, n)| format!("{n} {}", k.name()))
            .collect();
        if c.is_empty() {
            "none".to_string()
        } else {
            c.join(", ")
        }
    };
    let _ = writeln!(out, "flaws before: {}", flaws(before));
    let _ = writeln!(out, "flaws after:  {}", flaws(after));
    let _ = writeln!(out, "{} changes:", repaired.changes.len());
    for c in repaired.changes.iter().take(args.show) {
        let _ = writeln!(out, "  {}: {}", c.kind.name(), c.description);
    }
    if repaired.changes.len() > args.show {
        let _ = writeln!(
            out,
            "  … {} more (--show N, or --json)",
            repaired.changes.len() - args.show
        );
    }
    if repaired.uvs_dropped {
        let _ = writeln!(
            out,
            "note: texture coordinates were dropped (facets changed)"
        );
    }
    if emptied {
        let hint = if args.weld_tolerance > 0.0 {
            format!(
                " — is --weld-tolerance {} as large as the mesh?",
                args.weld_tolerance
            )
        } else {
            String::new()
        };
        let _ = writeln!(
            out,
            "NOT verified: the repair deleted every facet of the input{hint}"
        );
    } else if left.is_empty() && after.verified() {
        let _ = writeln!(
            out,
            "verified: the EAT of the result has none of the repaired flaws"
        );
    } else {
        let _ = writeln!(
            out,
            "NOT verified: {} flaws of the repaired kinds left{}",
            left.len(),
            if after.verified() {
                ""
            } else {
                ", and a test point fails"
            }
        );
        for f in left.iter().take(args.show) {
            let _ = writeln!(out, "  {}: {}", f.kind.name(), f.description);
        }
    }
    out
}

pub fn run(args: &RepairArgs) -> Result<ExitCode> {
    super::check_paths(
        &[Some(&args.input)],
        &[
            ("OUTPUT", Some(&args.output)),
            ("--mark", args.mark.as_deref()),
        ],
    )?;
    let options = RepairOptions {
        kinds: kinds(args)?,
        max_hole_edges: args.fill_holes.unwrap_or(0),
        hole_fill: match args.fill_with {
            FillWith::Spline => HoleFill::Spline,
            FillWith::Fan => HoleFill::Fan,
        },
        locator: LocatorOptions {
            weld_tolerance: args.weld_tolerance,
            crack_tolerance: args.crack_tolerance,
        },
    };
    let mesh = read_with(
        &args.input,
        &ReadOptions {
            keep_degenerate: true,
        },
    )?;
    let before = scan(
        &mesh,
        &EatOptions {
            locator: options.locator,
            ..Default::default()
        },
    )?;
    let repaired = repair_located(&mesh, &before.flaws, &options)?;
    let after = check(&repaired.mesh, args, options.locator)?;
    write(&args.output, &repaired.mesh, &WriteOptions::default())?;
    if let Some(mark) = &args.mark {
        let marked = mark_flaws(&repaired.mesh, &changed_vertices(&repaired.changes));
        write(mark, &marked, &WriteOptions::default())?;
    }
    let left = repaired.remaining(&after, &options);
    // No flaw is left on no facets at all: a repair that deleted every facet (a weld
    // tolerance as large as the mesh welds it into one point) is no verified result.
    let emptied = mesh.face_count() > 0 && repaired.mesh.face_count() == 0;
    let verified = left.is_empty() && after.verified() && !emptied;
    if args.json {
        super::print_json(&serde_json::json!({
            "input": args.input,
            "output": args.output,
            "verified": verified,
            "deleted_every_facet": emptied,
            "before": { "counts": before.counts, "flaw_counts": counts_by_name(&before) },
            "after": {
                "counts": after.counts,
                "flaw_counts": counts_by_name(&after),
                "checkpoints": after.checkpoints,
            },
            "changes": repaired.changes,
            "remaining_flaws": left,
            "uvs_dropped": repaired.uvs_dropped,
            "marked_mesh": args.mark,
        }))?;
    } else {
        print!(
            "{}",
            render(args, &before, &after, &repaired, &left, emptied)
        );
    }
    Ok(if verified {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(TEST_FAILED)
    })
}

fn counts_by_name(r: &EatReport) -> std::collections::BTreeMap<&'static str, usize> {
    r.flaw_counts()
        .into_iter()
        .map(|(k, n)| (k.name(), n))
        .collect()
}
