//! The optimizer on a valence-5 disc, the author's three-tube junction (359 vertices), the
//! paper's figure-7 junction (1007) and Table 1's five tubes (1677), a few seconds each in
//! release, and its largest five tubes (23997, about two minutes; `cargo bench --bench
//! fair_tubes` has the other sizes): S and the spread of H
//! fall, the gradient converges below 1e-8 of its initial norm, fixed vertices are
//! bit-identical and topology and vertex order are the input's. Coarse-to-fine
//! ([`optimize_levels`]) reaches the same minimum as a raw start on the refined mesh.

use surfkit::fair::{
    fixed_vertices, optimize, optimize_levels, refine_surface, sector_disc, tubes, FairOptions,
    Functional, LmMatrix, LmSearch, MeshTopology, NewtonReport, RepresentationOptions, StepKind,
    SurfaceKind, SurfaceRepresentation,
};
use surfkit::fair::{ulp, FLOOR_MARGIN, NEWTON_AFTER_DECREASE, SLOW_NEAR_STEPS};

fn statistics(mesh: &surfkit::mesh::PolygonMesh, options: &RepresentationOptions) -> (f64, f64) {
    let topo = MeshTopology::new(mesh).unwrap();
    let fixed = fixed_vertices(&topo, 3, &[]).unwrap();
    let special = topo.special_flags();
    let rep = SurfaceRepresentation::new(mesh, &topo.boundary, &special, options).unwrap();
    let f = Functional::new(&rep, &fixed, 1.0);
    let s = f.value(&mesh.positions).s;
    (s, f.mean_curvature_statistics(&mesh.positions).1)
}

#[test]
fn fair_optimize_valence_5_disc() {
    // A smooth height field over a skewed parameterization: F falls mostly through Q here
    // (S may rise), so only F is asserted to fall.
    let options = RepresentationOptions {
        isolation: 2,
        nodes: 3,
        ..RepresentationOptions::default()
    };
    check(&sector_disc(5, 5).unwrap(), options, false);
}

#[test]
fn fair_optimize_three_tubes() {
    check(
        &tubes(3, 4, 3).unwrap(),
        RepresentationOptions::default(),
        true,
    );
}

#[test]
fn fair_optimize_figure_7_junction() {
    // Issue 6's acceptance case: n_V = 1007, 719 free.
    check(
        &tubes(3, 8, 2).unwrap(),
        RepresentationOptions::default(),
        true,
    );
}

#[test]
fn fair_optimize_five_tubes() {
    // Table 1's first five-tube size (1677 vertices, saddles of valence 10).
    check(
        &tubes(5, 8, 2).unwrap(),
        RepresentationOptions::default(),
        true,
    );
}

#[test]
fn fair_optimize_largest_five_tubes() {
    // Table 1's largest five-tube size (23997 vertices, 22077 free) from the raw refined
    // mesh, about two minutes on two cores: with Cᵢ = 1 at the special elements it did
    // not converge (the parameterization drifted toward the saddles, see
    // `DEFAULT_C_SPECIAL`).
    check(
        &refine_surface(&tubes(5, 8, 2).unwrap(), 2).unwrap(),
        RepresentationOptions::default(),
        true,
    );
}

#[test]
fn fair_optimize_levels_reach_the_raw_start_minimum() {
    let coarse = tubes(3, 4, 3).unwrap();
    let fine = refine_surface(&coarse, 1).unwrap();
    let options = FairOptions {
        max_refinements: 0,
        ..FairOptions::default()
    };
    let (direct, direct_report) = optimize(&fine, &options).unwrap();
    let run = optimize_levels(&coarse, 1, &options).unwrap();
    let (cascaded, levels) = (run.optimized, run.levels);
    assert_eq!(run.raw.positions, fine.positions);
    assert_eq!(levels.len(), 2);
    let finest = &levels[1].report;
    eprintln!(
        "raw start: F {:.9e}, {} Hessians; coarse-to-fine: F {:.9e}, {} + {} Hessians",
        direct_report.final_terms.f,
        direct_report.newton.hessian_evaluations,
        finest.final_terms.f,
        levels[0].report.newton.hessian_evaluations,
        finest.newton.hessian_evaluations
    );
    assert!(direct_report.newton.converged && finest.newton.converged);
    assert!(finest.final_gradient_norm <= 1e-8 * finest.initial_gradient_norm);
    let (f0, f1) = (direct_report.final_terms.f, finest.final_terms.f);
    assert!((f0 - f1).abs() <= 1e-9 * f0, "F {f0} vs {f1}");
    let fixed = crate::common::assert_faces_and_boundary_rings_kept(&fine, &cascaded);
    let mut largest: f64 = 0.0;
    for (v, _) in fixed.iter().enumerate().filter(|(_, &held)| !held) {
        for a in 0..3 {
            largest = largest.max((cascaded.positions[v][a] - direct.positions[v][a]).abs());
        }
    }
    // The same minimizer, not just the same value.
    assert!(largest < 1e-4, "free vertices differ by {largest}");
    let err = optimize_levels(
        &coarse,
        1,
        &FairOptions {
            fixed: vec![100],
            ..options
        },
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("fixed vertices") && err.contains("refinement"),
        "{err}"
    );
}

#[test]
fn fair_optimize_paper_steps_and_default_steps_reach_the_same_minimum() {
    // The paper's steps (full Newton steps, else the Levenberg–Marquardt trajectory over
    // the exact Hessian, eq. 8–9), the default ones (the trajectory over the Gauss–Newton
    // part, no Newton trial after a step that lowered F by more than 2 %, halved Newton
    // steps first) and the default ones with a Newton trial after every step take different
    // paths (figure-10 junction, 1677 vertices, all starting with Levenberg–Marquardt
    // steps) to the same minimizer. Under the paper's weight C = 1 the last path takes
    // halved Newton steps (with C = 0.01 it goes from Levenberg–Marquardt straight to full
    // Newton steps here).
    let mesh = tubes(5, 8, 2).unwrap();
    let run = |lm_matrix, newton_halvings, newton_after_decrease| {
        let mut options = FairOptions {
            max_refinements: 0,
            regularization: 1.0,
            ..FairOptions::default()
        };
        options.newton.lm_matrix = lm_matrix;
        options.newton.newton_halvings = newton_halvings;
        options.newton.newton_after_decrease = newton_after_decrease;
        // A Newton trial after every step: none skipped after failed ones either.
        options.newton.newton_backoff = newton_after_decrease < 1.0;
        optimize(&mesh, &options).unwrap()
    };
    let (paper, paper_report) = run(LmMatrix::Exact, 0, 1.0);
    let (default, report) = run(LmMatrix::GaussNewton, 4, NEWTON_AFTER_DECREASE);
    let (halved, halved_report) = run(LmMatrix::GaussNewton, 4, 1.0);
    let kinds = |r: &surfkit::fair::FairReport| -> Vec<StepKind> {
        r.newton.iterations.iter().map(|it| it.step).collect()
    };
    for (name, r) in [
        ("paper", &paper_report),
        ("default", &report),
        ("trial after every step", &halved_report),
    ] {
        eprintln!(
            "{name}: F {:.9e}, {} Hessians + {} Gauss–Newton ({} alone), {:?}",
            r.final_terms.f,
            r.newton.hessian_evaluations,
            r.newton.gauss_newton_evaluations,
            r.newton.gauss_newton_only_evaluations,
            kinds(r)
        );
        assert!(r.newton.converged, "{name}");
    }
    assert_eq!(paper_report.newton.gauss_newton_evaluations, 0);
    assert!(!kinds(&paper_report).contains(&StepKind::DampedNewton));
    assert!(report.newton.gauss_newton_evaluations > 0);
    assert!(kinds(&halved_report).contains(&StepKind::DampedNewton));
    let f0 = paper_report.final_terms.f;
    for (other, r) in [(&default, &report), (&halved, &halved_report)] {
        let f1 = r.final_terms.f;
        assert!((f0 - f1).abs() <= 1e-9 * f0, "F {f0} vs {f1}");
        let largest =
            crate::common::largest_coordinate_difference(&paper.positions, &other.positions);
        assert!(largest < 1e-4, "vertices differ by {largest}");
    }
}

#[test]
fn fair_optimize_gauss_newton_parts_alone_reach_the_same_minimum_with_fewer_hessians() {
    // Table 1's five tubes (1677 vertices) from the raw mesh: a Newton trial after every
    // Levenberg–Marquardt step (`newton_after_decrease` 1, the paper's rule) and none after
    // a step that lowered F by more than 2 % (the default), where the pass evaluates the
    // Gauss–Newton part alone. Same minimum; the default's exact Hessians are fewer.
    let after_decrease = |newton_after_decrease: f64| {
        move |o: &mut FairOptions| {
            o.newton.newton_after_decrease = newton_after_decrease;
            o.newton.newton_backoff = newton_after_decrease < 1.0;
        }
    };
    let mesh = tubes(5, 8, 2).unwrap();
    let runs = same_minimum(
        &mesh,
        &[RepresentationOptions::default()],
        after_decrease(1.0),
        after_decrease(NEWTON_AFTER_DECREASE),
    );
    let (_, every_newton, newton) = &runs[0];
    eprintln!(
        "Newton trial after every step: {} Hessians; default: {} Hessians + {} Gauss–Newton \
         parts alone",
        every_newton.hessian_evaluations,
        newton.hessian_evaluations,
        newton.gauss_newton_only_evaluations
    );
    assert_eq!(every_newton.gauss_newton_only_evaluations, 0);
    assert!(newton.gauss_newton_only_evaluations > 0);
    assert!(newton.hessian_evaluations < every_newton.hessian_evaluations);
}

#[test]
fn fair_optimize_newton_backoff_reaches_the_same_minimum_with_fewer_hessians() {
    // After a Newton trial that failed, skipping the exact Hessian for the next 1, 2, 4, …
    // passes after damped steps (the default) against a trial after every damped step
    // that lowered F by little. Fewer exact Hessians (measured 2026-11-28: 3 against 4 on
    // the G² surface, 5 against 7 on the Catmull–Clark one).
    let runs = same_minimum_on_both_surfaces(
        |o| o.newton.newton_backoff = false,
        |o| o.newton.newton_backoff = true,
    );
    for (surface, every, backoff) in runs {
        eprintln!(
            "{surface:?}: a trial after every small damped step: {} Hessians + {} \
             Gauss–Newton; backoff: {} + {}",
            every.hessian_evaluations,
            every.gauss_newton_evaluations,
            backoff.hessian_evaluations,
            backoff.gauss_newton_evaluations
        );
        assert!(backoff.hessian_evaluations < every.hessian_evaluations);
    }
}

#[test]
fn fair_optimize_frugal_lm_search_reaches_the_same_minimum_with_fewer_set_ups() {
    // The Levenberg–Marquardt searches that stop following the trajectory where a trial
    // gains less than 1 % and climb ν by 16 against the exhaustive ones (the default).
    // Fewer set-ups of H + νI with 3 × 3 nodes far from the minimum (measured 2026-11-28:
    // 33 against 37 on the G² surface, 36 against 40 on the Catmull–Clark one), the
    // setting it was chosen in and is tested in. Not with the 2 × 2 nodes that are the
    // default since 2026-11-29: there the G² run took 55 set-ups against 41.
    let three_nodes = |o: &mut FairOptions| o.far_hessian_nodes = Some(3);
    let runs = same_minimum_on_both_surfaces(
        |o| {
            three_nodes(o);
            o.newton.lm_search = LmSearch::Exhaustive
        },
        |o| {
            three_nodes(o);
            o.newton.lm_search = LmSearch::Frugal
        },
    );
    for (surface, exhaustive, frugal) in runs {
        eprintln!(
            "{surface:?}: exhaustive: {} set-ups, {} iterations; frugal: {} set-ups, {} \
             iterations",
            exhaustive.factorizations,
            exhaustive.iterations.len(),
            frugal.factorizations,
            frugal.iterations.len()
        );
        assert!(frugal.factorizations < exhaustive.factorizations);
    }
}

#[test]
fn fair_optimize_geodesic_acceleration_reaches_the_same_minimum_in_fewer_damped_steps() {
    // Levenberg–Marquardt steps bent by their geodesic acceleration against straight ones
    // (the default). Fewer damped steps on both surfaces (measured 2026-11-28: 9 against 12
    // on each, with 44 and 46 set-ups of H + νI against 37 and 40).
    let runs = same_minimum_on_both_surfaces(
        |o| o.newton.geodesic_acceleration = false,
        |o| o.newton.geodesic_acceleration = true,
    );
    let damped = |r: &NewtonReport| {
        r.iterations
            .iter()
            .filter(|it| it.step == StepKind::LevenbergMarquardt)
            .count()
    };
    for (surface, straight, bent) in runs {
        eprintln!(
            "{surface:?}: straight: {} damped steps, {} set-ups; bent: {} damped steps ({} \
             trials bent), {} set-ups",
            damped(&straight),
            straight.factorizations,
            damped(&bent),
            bent.accelerated_trials,
            bent.factorizations
        );
        assert_eq!(straight.accelerated_trials, 0);
        assert!(!straight.geodesic_acceleration && bent.geodesic_acceleration);
        assert!(bent.accelerated_trials > 0);
        assert!(damped(&bent) < damped(&straight));
    }
}

/// Table 1's five tubes refined once (6237 vertices, the multilevel method) from the raw
/// mesh on both surfaces: [`same_minimum`] on each, per surface.
fn same_minimum_on_both_surfaces(
    before: impl Fn(&mut FairOptions),
    after: impl Fn(&mut FairOptions),
) -> Vec<(SurfaceKind, NewtonReport, NewtonReport)> {
    let mesh = refine_surface(&tubes(5, 8, 2).unwrap(), 1).unwrap();
    let surfaces = [
        RepresentationOptions::default(),
        RepresentationOptions::catmull_clark(),
    ];
    same_minimum(&mesh, &surfaces, before, after)
}

/// `mesh` optimized from its raw positions on each of `surfaces` (no refinement), with the
/// default options changed by `before` and by `after`: asserts that both runs converge to
/// the same minimum (F to 1e-9, vertices to 1e-6 of the bounding box's diagonal) and
/// returns their Newton reports, per surface.
fn same_minimum(
    mesh: &surfkit::mesh::PolygonMesh,
    surfaces: &[RepresentationOptions],
    before: impl Fn(&mut FairOptions),
    after: impl Fn(&mut FairOptions),
) -> Vec<(SurfaceKind, NewtonReport, NewtonReport)> {
    let (lo, hi) = mesh.bounding_box().unwrap();
    let diagonal = (0..3).map(|a| (hi[a] - lo[a]).powi(2)).sum::<f64>().sqrt();
    let mut reports = Vec::new();
    for representation in surfaces {
        let run = |change: &dyn Fn(&mut FairOptions)| {
            let mut options = FairOptions {
                max_refinements: 0,
                representation: representation.clone(),
                ..FairOptions::default()
            };
            change(&mut options);
            optimize(mesh, &options).unwrap()
        };
        let (first, first_report) = run(&before);
        let (second, second_report) = run(&after);
        assert!(first_report.newton.converged && second_report.newton.converged);
        let (f0, f1) = (first_report.final_terms.f, second_report.final_terms.f);
        assert!((f0 - f1).abs() <= 1e-9 * f0, "F {f0} vs {f1}");
        let largest =
            crate::common::largest_coordinate_difference(&first.positions, &second.positions);
        assert!(largest < 1e-6 * diagonal, "vertices differ by {largest}");
        reports.push((
            representation.surface,
            first_report.newton,
            second_report.newton,
        ));
    }
    reports
}

fn check(mesh: &surfkit::mesh::PolygonMesh, representation: RepresentationOptions, s_falls: bool) {
    let mesh = mesh.clone();
    let options = FairOptions {
        max_refinements: 0,
        representation,
        ..FairOptions::default()
    };
    let start = std::time::Instant::now();
    let (out, report) = optimize(&mesh, &options).unwrap();
    let seconds = start.elapsed().as_secs_f64();
    let (s0, sd0) = statistics(&mesh, &options.representation);
    let (s1, sd1) = statistics(&out, &options.representation);
    eprintln!(
        "{} vertices: {} free, S {s0:.6e} -> {s1:.6e} (factor {:.2}), std H {sd0:.4e} -> \
         {sd1:.4e}, |g| {:.3e} -> {:.3e}, {} iterations, {} Hessians, {seconds:.2} s",
        mesh.vertex_count(),
        report.free_vertices,
        s0 / s1,
        report.initial_gradient_norm,
        report.final_gradient_norm,
        report.newton.iterations.len(),
        report.newton.hessian_evaluations
    );
    for it in &report.newton.iterations {
        eprintln!("{}", serde_json::to_string(it).unwrap());
    }
    assert!(report.newton.converged);
    assert!(report.final_gradient_norm <= 1e-8 * report.initial_gradient_norm);
    assert!(report.final_gradient_norm <= 1e-8 * report.newton.initial_gradient_norm);
    assert!(report.final_terms.f < report.newton.initial.f);
    if s_falls {
        assert!(s1 < s0);
        assert!(sd1 < sd0);
    }
    assert_eq!(report.refinements, 0);
    crate::common::assert_faces_and_boundary_rings_kept(&mesh, &out);
    let topo = MeshTopology::new(&mesh).unwrap();
    assert_eq!(
        MeshTopology::new(&out).unwrap().euler_characteristic(),
        topo.euler_characteristic()
    );
}

#[test]
fn fair_optimize_cancelled_by_the_observer_stops_where_an_iteration_limit_would() {
    // A caller's cancel (the C and Python doors' callbacks) after the second iteration
    // returns the same iterate, bit for bit, as a run limited to two iterations.
    let mesh = tubes(3, 4, 3).unwrap();
    let options = FairOptions {
        max_refinements: 0,
        ..FairOptions::default()
    };
    let mut seen = 0;
    let (cancelled, report) = surfkit::fair::optimize_observed(&mesh, &options, &mut |_, _| {
        seen += 1;
        if seen == 2 {
            std::ops::ControlFlow::Break(())
        } else {
            std::ops::ControlFlow::Continue(())
        }
    })
    .unwrap();
    assert!(report.newton.cancelled && !report.newton.converged);
    assert_eq!(report.newton.iterations.len(), 2);
    let mut limited_options = options.clone();
    limited_options.newton.max_iterations = 2;
    let (limited, limited_report) = optimize(&mesh, &limited_options).unwrap();
    assert!(!limited_report.newton.cancelled);
    assert_eq!(limited_report.newton.iterations.len(), 2);
    assert_eq!(cancelled.positions, limited.positions);
}

#[test]
fn fair_optimize_regularization_weights_q_by_c_times_c() {
    // F = S + C·c·Q: the optimum under C = 0.01 (the author's program) is a stationary point
    // of the functional built here with weight 0.01·c, and lets S fall below C = 1's.
    let mesh = tubes(3, 4, 3).unwrap();
    let run = |regularization| {
        optimize(
            &mesh,
            &FairOptions {
                max_refinements: 0,
                regularization,
                ..FairOptions::default()
            },
        )
        .unwrap()
    };
    let (_, paper) = run(1.0);
    let (faired, author) = run(0.01);
    assert!(paper.newton.converged && author.newton.converged);
    assert_eq!((paper.regularization, author.regularization), (1.0, 0.01));
    assert_eq!(paper.c, author.c, "c = |E|²/D⁴ does not depend on C");
    let t = author.final_terms;
    assert!((t.f - (t.s + 0.01 * author.c * t.q)).abs() <= 1e-12 * t.f);
    assert!(
        t.s < paper.final_terms.s,
        "S {} vs {}",
        t.s,
        paper.final_terms.s
    );

    let topo = MeshTopology::new(&mesh).unwrap();
    let fixed = fixed_vertices(&topo, 3, &[]).unwrap();
    let special = topo.special_flags();
    let options = RepresentationOptions::default();
    let rep = SurfaceRepresentation::new(&mesh, &topo.boundary, &special, &options).unwrap();
    let functional = Functional::new(&rep, &fixed, 0.01 * author.c);
    let norm = |g: &[f64]| g.iter().map(|x| x * x).sum::<f64>().sqrt();
    let (start, g0) = functional.gradient(&mesh.positions);
    let (end, g) = functional.gradient(&faired.positions);
    assert!((start.f - author.newton.initial.f).abs() <= 1e-12 * start.f);
    assert!((end.f - t.f).abs() <= 1e-12 * t.f);
    assert!(
        norm(&g) <= 1e-8 * norm(&g0),
        "‖g‖ {} of {}",
        norm(&g),
        norm(&g0)
    );

    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let err = optimize(
            &mesh,
            &FairOptions {
                regularization: bad,
                ..FairOptions::default()
            },
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("regularization"), "{err}");
    }
}

#[test]
fn fair_optimize_hessians_at_fewer_nodes_reach_the_same_minimum() {
    // The author's three-tube mesh on the G² surface with F at 8 × 8 nodes: Newton with
    // Hessians at 8 × 8, at 4 × 4 and at 2 × 2 nodes throughout, and at the defaults (4 × 4,
    // 3 × 3 far from the minimum), F and its gradient at 8 × 8 throughout, converges to the
    // same minimum; only the steps differ.
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/fixtures/meshes/kiciak_trojnik3.obj"
    );
    let mesh = surfkit::mesh::io::read(std::path::Path::new(path)).unwrap();
    let run = |hessian_nodes, far_hessian_nodes| {
        let options = FairOptions {
            representation: RepresentationOptions {
                nodes: 8,
                ..RepresentationOptions::default()
            },
            hessian_nodes,
            far_hessian_nodes,
            ..FairOptions::default()
        };
        optimize(&mesh, &options).unwrap()
    };
    let (exact, exact_report) = run(None, None);
    assert!(exact_report.newton.converged);
    let diagonal = {
        let (lo, hi) = exact.positions.iter().fold(
            ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]),
            |(lo, hi), p| {
                (
                    std::array::from_fn(|a| lo[a].min(p[a])),
                    std::array::from_fn(|a| hi[a].max(p[a])),
                )
            },
        );
        (0..3).map(|a| (hi[a] - lo[a]).powi(2)).sum::<f64>().sqrt()
    };
    let defaults = FairOptions::default();
    for (nodes, far) in [
        (4, 4),
        (2, 2),
        (
            defaults.hessian_nodes.unwrap(),
            defaults.far_hessian_nodes.unwrap(),
        ),
    ] {
        let (out, report) = run(Some(nodes), Some(far));
        eprintln!(
            "Hessians at {nodes}×{nodes}, {far}×{far} far: F {:.12e} ({} iterations; 8×8: F {:.12e}, {})",
            report.final_terms.f,
            report.newton.iterations.len(),
            exact_report.final_terms.f,
            exact_report.newton.iterations.len()
        );
        assert!(report.newton.converged);
        let (f0, f1) = (exact_report.final_terms.f, report.final_terms.f);
        assert!((f0 - f1).abs() <= 1e-9 * f0, "F {f0} vs {f1}");
        let largest =
            crate::common::largest_coordinate_difference(&exact.positions, &out.positions);
        assert!(largest <= 1e-6 * diagonal, "vertices differ by {largest}");
    }
}

#[test]
fn fair_optimize_near_hessians_rise_to_fs_nodes_only_where_fewer_slow_newton() {
    // The default near Hessians (3 × 3 nodes, F at 4 × 4) against F's own nodes throughout.
    // On the 53-vertex junction's Catmull–Clark surface the 3 × 3 model leaves ‖g‖ at about
    // 0.7 of its value a Newton step (30 iterations without the rise, 2026-12-07), so after
    // `SLOW_NEAR_STEPS` such steps the near Hessians take F's nodes, and the run ends in
    // about as many iterations as F's nodes take (12 and 13 measured). On the author's
    // 4895-vertex mesh (both surfaces) they stay at 3 × 3. The same minimum every time.
    let small = tubes(3, 1, 3).unwrap();
    let own_nodes = |o: &mut FairOptions| o.hessian_nodes = None;
    let runs = same_minimum(
        &small,
        &[RepresentationOptions::catmull_clark()],
        own_nodes,
        |_| {},
    );
    let (_, own, default) = &runs[0];
    eprintln!(
        "53 vertices: F's nodes {} iterations, default {} (raised: {})",
        own.iterations.len(),
        default.iterations.len(),
        default.near_hessians_raised
    );
    assert!(default.near_hessians_raised);
    assert!(default.iterations.len() <= own.iterations.len() + SLOW_NEAR_STEPS);
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/fixtures/meshes/kiciak_trojnik5.obj"
    );
    let author = surfkit::mesh::io::read(std::path::Path::new(path)).unwrap();
    let surfaces = [
        RepresentationOptions::default(),
        RepresentationOptions::catmull_clark(),
    ];
    for (surface, own, default) in same_minimum(&author, &surfaces, own_nodes, |_| {}) {
        eprintln!(
            "{surface:?}, 4895 vertices: F's nodes {} iterations, default {}",
            own.iterations.len(),
            default.iterations.len()
        );
        assert!(!default.near_hessians_raised);
    }
}

/// `positions` with every coordinate of the vertices `moving` one ulp up or down, the
/// direction from the bits of a multiplicative hash of its index.
fn one_ulp_moves(positions: &[[f64; 3]], moving: &[bool]) -> Vec<[f64; 3]> {
    let mut out = positions.to_vec();
    for (v, p) in out.iter_mut().enumerate().filter(|(v, _)| moving[*v]) {
        for (a, x) in p.iter_mut().enumerate() {
            let hash = ((3 * v + a) as u64 + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15);
            *x += if hash >> 63 == 1 { ulp(*x) } else { -ulp(*x) };
        }
    }
    out
}

#[test]
fn fair_optimize_stops_at_the_floor_of_its_coordinates() {
    // 10⁴ from the origin, the author's three-tube junction's coordinates keep 12 digits
    // fewer of its size: its minimum's ‖g‖, rounded to nearest, is ~2·10⁻¹² of ‖g₀‖
    // (measured when this test was written). A tolerance of 10⁻¹⁶ asks for more than
    // even a chosen rounding gives: the run must stop there (`stalled`, not `stuck`, not
    // the iteration limit), at the minimum a tolerance it can meet reaches.
    const FAR: f64 = 1e4;
    let mut mesh = tubes(3, 4, 3).unwrap();
    for p in &mut mesh.positions {
        for c in p.iter_mut() {
            *c += FAR;
        }
    }
    let run = |relative_gradient| {
        let mut options = FairOptions {
            max_refinements: 0,
            ..FairOptions::default()
        };
        options.newton.relative_gradient = relative_gradient;
        optimize(&mesh, &options).unwrap()
    };
    let (_, met) = run(1e-10);
    assert!(met.newton.converged && !met.newton.stalled && !met.newton.stuck);
    let (out, report) = run(1e-16);
    let n = &report.newton;
    let floor = n.coordinate_floor.expect("a fresh Hessian gives the floor");
    assert!(floor > 1e-16 * n.initial_gradient_norm, "floor {floor:e}");
    assert!(n.stalled && !n.converged && !n.stuck, "{n:?}");
    assert!(report.final_gradient_norm <= FLOOR_MARGIN * floor);
    assert!(n.iterations.len() < FairOptions::default().newton.max_iterations);
    let (f_met, f) = (met.final_terms.f, report.final_terms.f);
    assert!((f - f_met).abs() <= 1e-12 * f_met, "F {f} vs {f_met}");
    // Before it stopped, the run chose its rounding and went below the floor of rounding
    // to nearest; a tolerance between the two is met (converged, not stalled).
    assert!(
        n.iterations
            .iter()
            .any(|it| it.step == StepKind::LatticeRounding),
        "{:?}",
        n.iterations
    );
    assert!(n.lattice_sweeps > 0, "{n:?}");
    let reached = report.final_gradient_norm;
    assert!(reached < floor, "‖g‖ {reached:e}, floor {floor:e}");
    let between = (reached * floor).sqrt() / n.initial_gradient_norm;
    let (below, below_report) = run(between);
    assert!(
        below_report.newton.converged && !below_report.newton.stalled,
        "{:?}",
        below_report.newton
    );

    // The floor is ‖H u‖ for a rounding u of RMS ulp/√12: moving each free coordinate by
    // one ulp must change the gradient (evaluated, not multiplied) by √12 times that,
    // give or take the spread of random signs.
    let topo = MeshTopology::new(&mesh).unwrap();
    let fixed = fixed_vertices(&topo, 3, &[]).unwrap();
    let special = topo.special_flags();
    let options = RepresentationOptions::default();
    let rep = SurfaceRepresentation::new(&mesh, &topo.boundary, &special, &options).unwrap();
    let functional = Functional::new(&rep, &fixed, report.regularization * report.c);
    let free: Vec<bool> = fixed.iter().map(|f| !f).collect();
    // The stored positions hold that gradient: ‖∇F‖ evaluated afresh from them.
    let norm = |g: &[f64]| g.iter().map(|x| x * x).sum::<f64>().sqrt();
    let stored = norm(&functional.gradient(&below.positions).1);
    assert!(
        stored <= between * n.initial_gradient_norm,
        "stored ‖g‖ {stored:e} against {:e}",
        between * n.initial_gradient_norm
    );
    let (_, g) = functional.gradient(&out.positions);
    let (_, moved) = functional.gradient(&one_ulp_moves(&out.positions, &free));
    let change = g
        .iter()
        .zip(&moved)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        .sqrt();
    let ratio = change / (12f64.sqrt() * floor);
    assert!((0.5..2.0).contains(&ratio), "‖Δg‖ / (√12 floor) = {ratio}");
}
