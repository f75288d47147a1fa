//! The basis of Kiciak's curvature-continuous special elements as surfkit builds it (issue
//! 20), checked against facts that do not depend on how it is built: rows sum to one
//! (affine invariance); functions linear in Ω_k's coordinates are reproduced (the domain
//! net maps to the domain patches δ); the space has the dimension Kiciak's construction
//! gives (n′ + 16k, `eghole.tex`); and the surface of an arbitrary Sabin net is curvature
//! continuous — position, normal and both principal curvatures agree on both sides of every
//! join between two special patches and between a special patch and its bicubic
//! neighbour, and the mean curvature at the centre is the same from all k patches.

use surfkit::fair::{g2_basis_cache, patch_derivatives, DomainNet, PatchMatrix};

const VALENCES: [usize; 5] = [3, 5, 6, 8, 10];

/// Kiciak's dimension of the extended space for a k-sided hole whose domain is divided at
/// equal angles (h = pairs of opposite division directions): n′ + 16k with
/// n′ = 6 + max{k, h+4} + max{2k, 2h+5}.
fn kiciak_dimension(k: usize) -> usize {
    let h = if k % 2 == 0 { k / 2 } else { 0 };
    6 + k.max(h + 4) + (2 * k).max(2 * h + 5) + 16 * k
}

/// A Sabin net in space: the domain net lifted onto a wavy graph, its points shifted by a
/// deterministic pseudo-random amount.
fn spatial_net(net: &DomainNet) -> Vec<[f64; 3]> {
    net.points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let noise = |seed: usize| ((i * 7919 + seed * 104729) % 1000) as f64 / 1000.0 - 0.5;
            [
                p[0] + 0.1 * noise(1),
                p[1] + 0.1 * noise(2),
                0.3 * (p[0] * 0.9).sin() * (p[1] * 0.7).cos() + 0.05 * p[0] * p[1] + 0.1 * noise(3),
            ]
        })
        .collect()
}

/// Position, normal and principal curvatures from a parametric surface's derivatives
/// (value, ∂u, ∂v, ∂uu, ∂uv, ∂vv per coordinate).
fn geometry(d: [[f64; 6]; 3]) -> ([f64; 3], [f64; 3], [f64; 2]) {
    let get = |o: usize| [d[0][o], d[1][o], d[2][o]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let (pu, pv) = (get(1), get(2));
    let n = [
        pu[1] * pv[2] - pu[2] * pv[1],
        pu[2] * pv[0] - pu[0] * pv[2],
        pu[0] * pv[1] - pu[1] * pv[0],
    ];
    let len = dot(n, n).sqrt();
    let n = n.map(|x| x / len);
    let (e, f, g) = (dot(pu, pu), dot(pu, pv), dot(pv, pv));
    let (l, m, nn) = (dot(get(3), n), dot(get(4), n), dot(get(5), n));
    let det = e * g - f * f;
    let gauss = (l * nn - m * m) / det;
    let mean = (e * nn - 2.0 * f * m + g * l) / (2.0 * det);
    let root = (mean * mean - gauss).max(0.0).sqrt();
    (get(0), n, [mean + root, mean - root])
}

/// Derivatives (value, u, v, uu, uv, vv) of special patch `s` at (u, v), per coordinate.
fn special(patches: &[[Vec<f64>; 3]], s: usize, u: f64, v: f64) -> [[f64; 6]; 3] {
    std::array::from_fn(|c| {
        let d = patch_derivatives(&patches[s][c], u, v);
        [d[0], d[1], d[2], d[3], d[4], d[5]]
    })
}

/// Uniform cubic B-spline basis and its first two derivatives at t.
fn spline(t: f64) -> [[f64; 4]; 3] {
    let s = 1.0 - t;
    [
        [
            s * s * s / 6.0,
            (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0,
            (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
            t * t * t / 6.0,
        ],
        [
            -s * s / 2.0,
            1.5 * t * t - 2.0 * t,
            -1.5 * t * t + t + 0.5,
            t * t / 2.0,
        ],
        [s, 3.0 * t - 2.0, 1.0 - 3.0 * t, t],
    ]
}

/// Derivatives of the bicubic ring patch over sector `s`'s lattice face [a0, a0+1] ×
/// [b0, b0+1] at local (x, y) ∈ [0, 1]², in the lattice directions (a, b).
fn ring(
    net: &DomainNet,
    points: &[[f64; 3]],
    s: usize,
    a0: i32,
    b0: i32,
    x: f64,
    y: f64,
) -> [[f64; 6]; 3] {
    let (nx, ny) = (spline(x), spline(y));
    let orders = [(0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2)];
    std::array::from_fn(|c| {
        orders.map(|(ra, rb)| {
            let mut sum = 0.0;
            for i in 0..4 {
                for l in 0..4 {
                    let p = points[net.vertex(s, a0 - 1 + i as i32, b0 - 1 + l as i32)];
                    sum += nx[ra][i] * ny[rb][l] * p[c];
                }
            }
            sum
        })
    })
}

fn assert_same(what: &str, a: ([f64; 3], [f64; 3], [f64; 2]), b: ([f64; 3], [f64; 3], [f64; 2])) {
    let scale = 1.0 + a.2[0].abs().max(a.2[1].abs());
    for i in 0..3 {
        assert!(
            (a.0[i] - b.0[i]).abs() < 1e-8,
            "{what}: position {:?} vs {:?}",
            a.0,
            b.0
        );
        assert!(
            (a.1[i] - b.1[i]).abs() < 1e-8,
            "{what}: normal {:?} vs {:?}",
            a.1,
            b.1
        );
    }
    for i in 0..2 {
        assert!(
            (a.2[i] - b.2[i]).abs() < 1e-8 * scale,
            "{what}: principal curvatures {:?} vs {:?}",
            a.2,
            b.2
        );
    }
}

#[test]
fn the_basis_sums_to_one_reproduces_the_domain_and_has_kiciaks_dimension() {
    for k in VALENCES {
        let basis = PatchMatrix::compute(k).unwrap();
        let net = DomainNet::new(k);
        let m = &basis.matrix;
        let mut worst_sum = 0.0f64;
        let mut worst_linear = 0.0f64;
        for i in 0..m.nrows() {
            let sum: f64 = (0..m.ncols()).map(|v| m[(i, v)]).sum();
            worst_sum = worst_sum.max((sum - 1.0).abs());
            let (s, c) = (i / 100, i % 100);
            for coordinate in 0..2 {
                let image: f64 = (0..m.ncols())
                    .map(|v| m[(i, v)] * net.points[v][coordinate])
                    .sum();
                let want = basis.sectors[s].patch[coordinate][c];
                worst_linear = worst_linear.max((image - want).abs());
            }
        }
        println!(
            "k = {k}: partition of unity {worst_sum:.1e}, linear precision {worst_linear:.1e}, \
             dimension {} (Kiciak {})",
            basis.inner_dimension,
            kiciak_dimension(k)
        );
        assert!(worst_sum < 1e-9, "k = {k}: rows sum to 1 ± {worst_sum:e}");
        assert!(
            worst_linear < 1e-9,
            "k = {k}: linear precision {worst_linear:e}"
        );
        assert_eq!(basis.inner_dimension, kiciak_dimension(k), "k = {k}");
    }
}

#[test]
fn the_surface_of_any_sabin_net_is_curvature_continuous() {
    let ts = [0.05, 0.3, 0.5, 0.71, 0.95];
    for k in VALENCES {
        let basis = PatchMatrix::compute(k).unwrap();
        let net = DomainNet::new(k);
        let points = spatial_net(&net);
        let m = &basis.matrix;
        let patches: Vec<[Vec<f64>; 3]> = (0..k)
            .map(|s| {
                std::array::from_fn(|c| {
                    (0..100)
                        .map(|i| {
                            (0..m.ncols())
                                .map(|v| m[(100 * s + i, v)] * points[v][c])
                                .sum()
                        })
                        .collect()
                })
            })
            .collect();
        for s in 0..k {
            let prev = (s + k - 1) % k;
            for &t in &ts {
                // division curve s: sector s's v = 0 side, sector s−1's u = 0 side
                assert_same(
                    &format!("k {k} curve {s} t {t}"),
                    geometry(special(&patches, s, t, 0.0)),
                    geometry(special(&patches, prev, 0.0, t)),
                );
                // ring: u = 1 against face [1, 2] × [0, 1] at a = 1, b = t
                assert_same(
                    &format!("k {k} sector {s} ring side u = 1, t {t}"),
                    geometry(special(&patches, s, 1.0, t)),
                    geometry(ring(&net, &points, s, 1, 0, 0.0, t)),
                );
                // ring: v = 1 against face [0, 1] × [1, 2] at a = t, b = 1
                assert_same(
                    &format!("k {k} sector {s} ring side v = 1, t {t}"),
                    geometry(special(&patches, s, t, 1.0)),
                    geometry(ring(&net, &points, s, 0, 1, t, 0.0)),
                );
            }
        }
        let centre: Vec<f64> = (0..k)
            .map(|s| {
                let [a, b] = geometry(special(&patches, s, 0.0, 0.0)).2;
                0.5 * (a + b)
            })
            .collect();
        let spread = centre
            .iter()
            .fold(0.0f64, |m, h| m.max((h - centre[0]).abs()));
        println!(
            "k = {k}: mean curvature at the centre {:.6} (spread {spread:.1e})",
            centre[0]
        );
        assert!(spread < 1e-8 * (1.0 + centre[0].abs()), "k {k}: {centre:?}");
    }
}

#[test]
fn the_domain_patches_are_regular_with_the_authors_jacobian_range() {
    // The notes (`../shared/notes/kiciak-g2-construction.md`), from the author's program:
    // after scaling Ω_k to area k, det Dδ ∈ [0.34, 1.75] for all k ≤ 16.
    let (mut low, mut high) = (f64::INFINITY, 0.0f64);
    for k in (3..=16).filter(|&k| k != 4) {
        let net = DomainNet::new(k);
        let domain = surfkit::fair::sector_domain(&net, 0).unwrap();
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        for i in 0..=40 {
            for j in 0..=40 {
                let (u, v) = (i as f64 / 40.0, j as f64 / 40.0);
                let d = surfkit::fair::map_derivatives(&domain, u, v);
                let det = d[0][0] * d[1][1] - d[0][1] * d[1][0];
                lo = lo.min(det);
                hi = hi.max(det);
            }
        }
        println!("k = {k}: det Dδ ∈ [{lo:.3}, {hi:.3}]");
        low = low.min(lo);
        high = high.max(hi);
    }
    println!("all k: det Dδ ∈ [{low:.3}, {high:.3}]");
    assert!(
        (low - 0.34).abs() < 0.005 && (high - 1.75).abs() < 0.005,
        "[{low}, {high}]"
    );
}

#[test]
fn the_basis_does_not_depend_on_the_thread_count() {
    // computed inside pools of one and two threads: bit-identical (faer would split its
    // factorizations by the pool's size)
    let in_pool = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| PatchMatrix::compute(5).unwrap())
    };
    let (one, two) = (in_pool(1), in_pool(2));
    let m = &one.matrix;
    for i in 0..m.nrows() {
        for j in 0..m.ncols() {
            assert_eq!(
                m[(i, j)].to_bits(),
                two.matrix[(i, j)].to_bits(),
                "({i}, {j})"
            );
        }
    }
}

#[test]
fn the_stored_basis_is_the_computed_one_and_a_damaged_file_is_ignored() {
    let dir = tempfile::tempdir().unwrap();
    let k = 5;
    assert!(g2_basis_cache::load(dir.path(), k).is_none(), "empty cache");
    let computed = PatchMatrix::compute(k).unwrap();
    g2_basis_cache::store(dir.path(), &computed).unwrap();
    // Reproducible: computed again, the basis is the stored one bit for bit.
    let stored = g2_basis_cache::load(dir.path(), k).expect("just stored");
    assert!(g2_basis_cache::identical(
        &stored,
        &PatchMatrix::compute(k).unwrap()
    ));
    assert_eq!(stored.sectors.len(), k);
    assert!(
        g2_basis_cache::load(dir.path(), 6).is_none(),
        "another valence"
    );
    // One flipped bit, a cut, one byte more: each file is refused (recomputed by the caller).
    let path = g2_basis_cache::file(dir.path(), k);
    let bytes = std::fs::read(&path).unwrap();
    let mut flipped = bytes.clone();
    flipped[bytes.len() / 2] ^= 4;
    let mut longer = bytes.clone();
    longer.push(0);
    for damaged in [flipped, bytes[..bytes.len() - 9].to_vec(), longer] {
        std::fs::write(&path, damaged).unwrap();
        assert!(g2_basis_cache::load(dir.path(), k).is_none());
    }
}

#[test]
fn a_regular_net_reproduces_the_bicubic_b_spline_surface() {
    // k = 4: the domain net is the square lattice and the special element's four patches
    // must be the bicubic B-spline surface of the net. Checked on nets that are the
    // B-spline control values of bicubic polynomials f (spacing h: c = (1 − h²∂ₓₓ/6)
    // (1 − h²∂ᵧᵧ/6) f at the lattice points), whose B-spline surface is f itself: each
    // patch must be f ∘ δ_s. f lies in V and is triharmonic (Δ³f = 0), so it is the exact
    // Ritz solution; the basis integrates the energy's degree-14 integrands with the
    // author's composite 2-point Gauss rule (8 intervals), exact only to degree 3, so f is
    // reproduced to that rule's accuracy, not to round-off: 2.3e-7 measured, 1.0e-8 with
    // 16 intervals (the rule's h⁴ order).
    let basis = PatchMatrix::compute(4).unwrap();
    let net = DomainNet::new(4);
    let centre = net.points[0];
    let h = net
        .points
        .iter()
        .map(|p| ((p[0] - centre[0]).powi(2) + (p[1] - centre[1]).powi(2)).sqrt())
        .filter(|&d| d > 1e-9)
        .fold(f64::INFINITY, f64::min);
    for seed in 0..3 {
        // f = Σ a_ij x^i y^j, i, j ≤ 3, with deterministic pseudo-random coefficients.
        let a: Vec<f64> = (0..16usize)
            .map(|i| {
                (((i + 5 * seed) * 7919 % 1000) as f64 / 500.0 - 1.0)
                    / 4f64.powi((i / 4 + i % 4) as i32)
            })
            .collect();
        let power = |t: f64, n: i32| if n < 0 { 0.0 } else { t.powi(n) };
        // ∂ₓ^r ∂ᵧ^q f at (x, y)
        let f = |x: f64, y: f64, r: i32, q: i32| -> f64 {
            let falling = |n: i32, k: i32| (0..k).map(|j| (n - j) as f64).product::<f64>();
            (0..16)
                .map(|i| {
                    let (ei, ej) = ((i / 4) as i32, (i % 4) as i32);
                    a[i] * falling(ei, r) * power(x, ei - r) * falling(ej, q) * power(y, ej - q)
                })
                .sum()
        };
        let values: Vec<f64> = net
            .points
            .iter()
            .map(|p| {
                let (x, y) = (p[0], p[1]);
                f(x, y, 0, 0) - h * h / 6.0 * (f(x, y, 2, 0) + f(x, y, 0, 2))
                    + h.powi(4) / 36.0 * f(x, y, 2, 2)
            })
            .collect();
        let m = &basis.matrix;
        let mut worst = 0.0f64;
        for (s, sector) in basis.sectors.iter().enumerate() {
            let coefficients: Vec<f64> = (0..100)
                .map(|c| {
                    (0..m.ncols())
                        .map(|v| m[(100 * s + c, v)] * values[v])
                        .sum()
                })
                .collect();
            for i in 0..=6 {
                for j in 0..=6 {
                    let (u, v) = (i as f64 / 6.0, j as f64 / 6.0);
                    let x = patch_derivatives(&sector.patch[0], u, v)[0];
                    let y = patch_derivatives(&sector.patch[1], u, v)[0];
                    let got = patch_derivatives(&coefficients, u, v)[0];
                    worst = worst.max((got - f(x, y, 0, 0)).abs());
                }
            }
        }
        println!("k = 4, polynomial {seed}: spacing {h}, largest difference {worst:.1e}");
        assert!(worst < 1e-6, "k = 4: {worst:e}");
    }
}
