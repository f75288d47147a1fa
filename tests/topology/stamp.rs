//! The paper's storyline (Liu et al. 2020 §4) replayed on surfkit's stamp model: the four
//! stages end at χ = −1, 0, 1, 2 (§4.4), and each of the three flaws of §4.1–4.3 makes
//! the stage it is drawn in fail, and is located.

use surfkit::shapes::{stamp, StampFlaw};
use surfkit::topology::{scan, EatReport, FlawKind};

fn run(flaws: &[StampFlaw]) -> EatReport {
    let mesh = stamp(flaws);
    scan(&mesh, &crate::common::stamp_stages(&mesh)).unwrap()
}

#[test]
fn the_stamp_is_drawn_in_four_verified_stages() {
    let report = run(&[]);
    let chis: Vec<i64> = report
        .checkpoints
        .iter()
        .map(|(_, c)| c.statistics.euler_characteristic)
        .collect();
    assert_eq!(chis, vec![-1, 0, 1, 2]);
    assert!(report.verified());
    assert!(report.flaws.is_empty(), "{:?}", report.flaw_counts());
    assert_eq!(report.components.len(), 1);
    assert_eq!(report.components[0].genus, Some(0));
    // Triangles, quads, pentagons and hexagons, as in the paper's model.
    let mesh = stamp(&[]);
    let hist = mesh.arity_histogram();
    assert!(
        hist[3] > 0 && hist[4] > 0 && hist[5] > 0 && hist[6] > 0,
        "{hist:?}"
    );
}

#[test]
fn the_tiny_unfilled_triangle_fails_stage_two_and_is_located() {
    let report = run(&[StampFlaw::TinyTriangle]);
    assert_eq!(report.first_failure, Some(1));
    let (_, c) = &report.checkpoints[1];
    assert_eq!(c.statistics.euler_characteristic, -1);
    assert!(!c.since_last_verified.is_empty());
    let found: Vec<_> = report
        .flaws
        .iter()
        .filter(|f| f.kind == FlawKind::MissingTriangle)
        .collect();
    assert_eq!(found.len(), 1, "{:?}", report.flaw_counts());
    assert!(found[0].shape.as_ref().unwrap().tiny);
    assert_eq!(report.flaws.len(), 1);
}

#[test]
fn the_narrow_unfilled_quad_fails_stage_three_and_is_located() {
    let report = run(&[StampFlaw::NarrowQuad]);
    assert_eq!(report.first_failure, Some(2));
    assert_eq!(report.checkpoints[2].1.statistics.euler_characteristic, 0);
    let found: Vec<_> = report
        .flaws
        .iter()
        .filter(|f| f.kind == FlawKind::MissingQuad)
        .collect();
    assert_eq!(found.len(), 1, "{:?}", report.flaw_counts());
    assert!(found[0].shape.as_ref().unwrap().tiny);
}

#[test]
fn the_pentagon_written_as_a_quad_is_a_crack_in_stage_two() {
    let clean = run(&[]);
    let report = run(&[StampFlaw::Crack]);
    assert_eq!(report.first_failure, Some(1));
    let (ok, bad) = (
        &clean.checkpoints[1].1.statistics,
        &report.checkpoints[1].1.statistics,
    );
    // Same V and F; one edge more, so χ one less (the paper's 4083 against 4082 edges).
    assert_eq!((bad.vertices, bad.facets), (ok.vertices, ok.facets));
    assert_eq!(bad.edges, ok.edges + 1);
    let cracks: Vec<_> = report
        .flaws
        .iter()
        .filter(|f| f.kind == FlawKind::Crack)
        .collect();
    assert_eq!(cracks.len(), 1, "{:?}", report.flaw_counts());
    assert_eq!(
        cracks[0].vertices.len(),
        3,
        "long edge and the skipped vertex"
    );
    // The new facets since the last verified point include the quad, with an edge of ec 1.
    let since = &report.checkpoints[1].1.since_last_verified;
    assert!(since
        .iter()
        .any(|d| d.vertices.len() == 4 && d.edges.iter().any(|&(_, ec)| ec == 1)));
}

#[test]
fn the_three_flaws_together_fail_at_the_first_one() {
    let report = run(&[
        StampFlaw::TinyTriangle,
        StampFlaw::NarrowQuad,
        StampFlaw::Crack,
    ]);
    assert_eq!(report.first_failure, Some(1));
    let kinds: Vec<FlawKind> = report.flaws.iter().map(|f| f.kind).collect();
    for k in [
        FlawKind::MissingTriangle,
        FlawKind::MissingQuad,
        FlawKind::Crack,
    ] {
        assert!(kinds.contains(&k), "{k:?} missing from {kinds:?}");
    }
}
