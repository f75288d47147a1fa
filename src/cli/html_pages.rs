//! What the surface commands put in their HTML reports (`--html`): the summary lines and,
//! for `fair`, the optimization log as a plot. The pages themselves are
//! [`crate::report::html`]'s.

use crate::fair::{FairReport, ShapeChange};
use crate::report::html::{Plot, Series};

/// Summary lines of a fairing run.
pub(super) fn fair_summary(
    input: &str,
    report: &FairReport,
    change: &ShapeChange,
    seconds: f64,
) -> Vec<(String, String)> {
    let n = &report.newton;
    let status = if n.converged {
        "converged".to_string()
    } else {
        n.status_note().trim().trim_matches(['(', ')']).to_string()
    };
    vec![
        ("mesh".into(), input.to_string()),
        (
            "vertices".into(),
            format!("{} ({} free)", report.vertices, report.free_vertices),
        ),
        (
            "S = ∫|∇H|²".into(),
            format!("{:.6e} → {:.6e}", change.s_before, change.s_after),
        ),
        (
            "std H".into(),
            format!("{:.4e} → {:.4e}", change.std_h_before, change.std_h_after),
        ),
        (
            "F = S + C·c·Q".into(),
            format!(
                "{:.6e} → {:.6e}",
                report.initial_terms.f, report.final_terms.f
            ),
        ),
        (
            "C, c".into(),
            format!("{}, {:.4e}", report.regularization, report.c),
        ),
        (
            "|g|/|g₀|".into(),
            format!(
                "{:.3e}",
                report.final_gradient_norm / report.initial_gradient_norm
            ),
        ),
        (
            "Newton iterations".into(),
            format!(
                "{} ({} Hessians)",
                n.iterations.len(),
                n.hessian_evaluations
            ),
        ),
        ("time".into(), format!("{seconds:.2} s")),
        ("status".into(), status),
    ]
}

/// The optimization log: |g|/|g₀| and F/F₀ per iteration (iteration 0 the start), g₀ and
/// F₀ the input's (the multilevel method's coarse start lowers them before iteration 0).
pub(super) fn fair_log_plot(report: &FairReport) -> Plot {
    let n = &report.newton;
    let (g0, f0) = (report.initial_gradient_norm, report.initial_terms.f);
    let x: Vec<f64> = (0..=n.iterations.len()).map(|i| i as f64).collect();
    let gradient = std::iter::once(n.initial_gradient_norm / g0)
        .chain(n.iterations.iter().map(|it| it.gradient_norm / g0))
        .collect();
    let f = std::iter::once(n.initial.f / f0)
        .chain(n.iterations.iter().map(|it| it.terms.f / f0))
        .collect();
    Plot {
        title: "optimization log".into(),
        x_label: "Newton / Levenberg–Marquardt iteration".into(),
        log_y: true,
        series: vec![
            Series {
                name: "|g| / |g₀|".into(),
                colour: [255, 200, 60],
                x: x.clone(),
                y: gradient,
            },
            Series {
                name: "F / F₀".into(),
                colour: [90, 180, 255],
                x,
                y: f,
            },
        ],
    }
}
