"""fit, fill and fit_parallel against the CLI (`surfkit fit/fill --json`, `surfkit paper
kp2004-example2`), exact polynomials and finite differences."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

import surfkit


def _data(n: int = 400, seed: int = 5) -> tuple[np.ndarray, np.ndarray]:
    """Scattered samples of a smooth surface over [0, 1]² (corners included, so the
    parameter rectangle is the unit square)."""
    rng = np.random.default_rng(seed)
    uv = np.vstack([[[0, 0], [1, 0], [0, 1], [1, 1]], rng.uniform(size=(n - 4, 2))])
    u, v = uv[:, 0], uv[:, 1]
    xyz = np.stack([u, v, np.sin(2 * u) * np.cos(3 * v) + 0.3 * u * v], axis=1)
    return uv, xyz


def _csv(path: Path, uv: np.ndarray, xyz: np.ndarray) -> Path:
    np.savetxt(path, np.hstack([uv, xyz]), delimiter=",", header="u,v,x,y,z", comments="")
    return path


def _cli_samples(
    cli: Path, command: list, tmp_path: Path, resolution: int
) -> tuple[dict, np.ndarray]:
    out = tmp_path / "sampled.ply"
    run = subprocess.run(
        [cli, *command, "--output", out, "--resolution", str(resolution), "--json"],
        check=True,
        capture_output=True,
        text=True,
    )
    return json.loads(run.stdout), surfkit.read_mesh(out).vertices


def _same_report(ours: object, theirs: object, where: str = "report") -> None:
    """`surfkit fit/fill --json` prints the fit's report: the binding's is the same, key for
    key, numbers to 1e-9 (the CLI and the binding are two routes into one solve)."""
    if isinstance(theirs, dict):
        assert isinstance(ours, dict) and ours.keys() == theirs.keys(), where
        for key in theirs:
            _same_report(ours[key], theirs[key], f"{where}.{key}")
    elif isinstance(theirs, list):
        assert isinstance(ours, list) and len(ours) == len(theirs), where
        for k, (a, b) in enumerate(zip(ours, theirs, strict=True)):
            _same_report(a, b, f"{where}[{k}]")
    elif isinstance(theirs, float):
        assert ours == pytest.approx(theirs, rel=1e-9), where
    else:
        assert ours == theirs, where


@pytest.mark.parametrize("space", ["biquadratic", "bicubic", "bfs-c1"])
def test_fit_is_the_cli_fit(space: str, cli: Path, tmp_path: Path):
    uv, xyz = _data()
    csv = _csv(tmp_path / "data.csv", uv, xyz)
    theirs, samples = _cli_samples(
        cli, ["fit", csv, "--space", space, "--cells", "6,5"], tmp_path, 9
    )
    spline = surfkit.fit(uv, xyz, space=space, cells=(6, 5))
    _same_report(spline.report, theirs)
    g = np.linspace(0, 1, 10)
    uu, vv = np.meshgrid(g, g)
    ours = spline.evaluate(uu, vv).reshape(-1, 3)
    assert _nearest(ours, samples) < 1e-6


def _nearest(points: np.ndarray, cloud: np.ndarray) -> float:
    """The largest distance from a point of `points` to the nearest of `cloud`."""
    d = np.linalg.norm(points[:, None, :] - cloud[None, :, :], axis=2)
    return float(d.min(axis=1).max())


def test_fill_is_the_cli_fill(cli: Path, tmp_path: Path):
    uv, xyz = _data(600)
    inside = (uv[:, 0] - 0.5) ** 2 + (uv[:, 1] - 0.5) ** 2 <= 0.05
    uv, xyz = uv[~inside], xyz[~inside]
    csv = _csv(tmp_path / "data.csv", uv, xyz)
    hole = "ellipse:0.5,0.5,1,1,0.05"
    theirs, samples = _cli_samples(
        cli, ["fill", csv, "--hole", hole, "--cells", "8,8"], tmp_path, 11
    )
    spline = surfkit.fill(uv, xyz, hole=[("ellipse", (0.5, 0.5, 1, 1, 0.05))], cells=(8, 8))
    assert spline.report["fill"] is not None
    _same_report(spline.report, theirs)
    g = np.linspace(0, 1, 12)
    uu, vv = np.meshgrid(g, g)
    assert _nearest(spline.evaluate(uu, vv).reshape(-1, 3), samples) < 1e-6


@pytest.mark.parametrize("space", ["biquadratic", "bicubic", "bfs-c1"])
def test_a_linear_surface_is_reproduced_with_its_derivatives(space: str):
    """Every space holds the linear polynomials and the smoothing term vanishes on them:
    the fit is the polynomial, derivatives included (second derivatives zero)."""
    rng = np.random.default_rng(11)
    uv = np.vstack([[[0, 0], [2, 0], [0, 1], [2, 1]], rng.uniform([0, 0], [2, 1], (200, 2))])
    a = np.array([[1.0, 0.5, -2.0], [0.25, 3.0, 1.5], [0.7, -1.0, 0.2]])  # rows: 1, u, v
    xyz = a[0] + np.outer(uv[:, 0], a[1]) + np.outer(uv[:, 1], a[2])
    spline = surfkit.fit(uv, xyz, space=space, cells=(5, 4))
    u, v = rng.uniform(0, 2, 50), rng.uniform(0, 1, 50)
    d = spline.evaluate(u, v, derivatives=2)
    exact = a[0] + np.outer(u, a[1]) + np.outer(v, a[2])
    np.testing.assert_allclose(d["position"], exact, atol=1e-8)
    np.testing.assert_allclose(d["du"], np.broadcast_to(a[1], (50, 3)), atol=1e-7)
    np.testing.assert_allclose(d["dv"], np.broadcast_to(a[2], (50, 3)), atol=1e-7)
    for name in ("duu", "duv", "dvv"):
        np.testing.assert_allclose(d[name], 0, atol=1e-6)


def test_derivatives_are_those_of_the_values():
    uv, xyz = _data()
    spline = surfkit.fit(uv, xyz, space="bicubic", cells=(6, 6))
    u, v, h = np.full(5, 0.43), np.linspace(0.1, 0.9, 5), 1e-5
    d = spline.evaluate(u, v, derivatives=1)
    np.testing.assert_allclose(
        (spline.evaluate(u + h, v) - spline.evaluate(u - h, v)) / (2 * h), d["du"], atol=1e-6
    )
    np.testing.assert_allclose(
        (spline.evaluate(u, v + h) - spline.evaluate(u, v - h)) / (2 * h), d["dv"], atol=1e-6
    )


def test_an_offset_is_the_cli_offset(cli: Path, tmp_path: Path):
    uv, xyz = _data()
    csv = _csv(tmp_path / "data.csv", uv, xyz)
    theirs, samples = _cli_samples(
        cli, ["fit", csv, "--cells", "6,6", "--offset", "0;0;0.1*u"], tmp_path, 7
    )
    spline = surfkit.fit(
        uv, xyz, cells=(6, 6), offset=lambda u, v: np.stack([0 * u, 0 * u, 0.1 * u], axis=1)
    )
    _same_report(spline.report, theirs)
    g = np.linspace(0, 1, 8)
    uu, vv = np.meshgrid(g, g)
    assert _nearest(spline.evaluate(uu, vv).reshape(-1, 3), samples) < 1e-6


def test_shape_preserving_fill_keeps_the_sign():
    """2024 §4: data of a positive bump with a hole at its foot; with the condition
    "positive" the filled z stays ≥ 0 at the constraint lattice."""
    rng = np.random.default_rng(2)
    uv = np.vstack([[[0, 0], [1, 0], [0, 1], [1, 1]], rng.uniform(size=(800, 2))])
    z = np.maximum(0.0, 0.2 - ((uv[:, 0] - 0.3) ** 2 + (uv[:, 1] - 0.3) ** 2)) ** 2
    xyz = np.stack([uv[:, 0], uv[:, 1], z], axis=1)
    keep = (uv[:, 0] - 0.75) ** 2 + (uv[:, 1] - 0.75) ** 2 > 0.03
    hole = [("ellipse", (0.75, 0.75, 1, 1, 0.03))]
    spline = surfkit.fill(
        uv[keep], xyz[keep], hole=hole, space="bfs-c1", shape=["positive"], shape_lattice=4
    )
    report = spline.report["shape"]
    assert report is not None
    g = np.linspace(0.6, 0.9, 7)
    uu, vv = np.meshgrid(g, g)
    inside = (uu - 0.75) ** 2 + (vv - 0.75) ** 2 <= 0.03
    assert spline.evaluate(uu[inside], vv[inside])[:, 2].min() >= -1e-9


def _kp2004_example2() -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The 2004 paper's example 2: x₀(u, v) = (u, v, e^(−(u−½)²−(v−½)²)) on [0, 1]², nine
    data points on a 3 × 3 lattice, B the 50 × 50 cell centres (README, kp2004)."""
    k = np.arange(9)
    a = np.stack([(k // 3) / 2.0, (k % 3) / 2.0], axis=1)
    a1, a2 = a[:, 0], a[:, 1]
    values = np.stack(
        [
            -0.1 + 0.5 * a1,
            -0.1 + 0.5 * a2,
            0.9065
            + 0.686 * (a1 - a1**2 + a2 - a2**2)
            + 1.608 * (a1 * a2 - a1**2 * a2 - a1 * a2**2 + a1**2 * a2**2),
        ],
        axis=1,
    )
    i = np.arange(2500)
    b = np.stack([(i // 50 + 0.5) / 50, (i % 50 + 0.5) / 50], axis=1)
    e = np.exp(-((b[:, 0] - 0.5) ** 2) - (b[:, 1] - 0.5) ** 2)
    n = np.stack([2 * (b[:, 0] - 0.5) * e, 2 * (b[:, 1] - 0.5) * e, np.ones(2500)], axis=1)
    return a, values, b, n / np.linalg.norm(n, axis=1, keepdims=True)


def test_fit_parallel_is_the_papers_example_2(cli: Path):
    run = subprocess.run(
        [cli, "paper", "kp2004-example2", "--json"], check=True, capture_output=True, text=True
    )
    rows = [json.loads(line) for line in run.stdout.splitlines() if line.startswith("{")]
    a, values, b, normals = _kp2004_example2()
    pis = []
    for row in rows:
        spline = surfkit.fit_parallel(a, values, b, normals, tau=row["tau"])
        r = spline.report
        assert r["system_dimension"] == row["system_dimension"] == 1323
        assert r["pi_per_point"] == pytest.approx(row["pi_per_point"], rel=1e-6)
        assert r["data_misfit"] == pytest.approx(row["data_misfit"], rel=1e-6, abs=1e-15)
        pis.append(r["pi_per_point"])
    # The paper's point: Π falls as τ grows.
    assert all(p > q for p, q in zip(pis, pis[1:], strict=False))


def test_bad_fit_input_is_named():
    uv, xyz = _data()
    bad = xyz.copy()
    bad[17, 1] = np.nan
    with pytest.raises(surfkit.InvalidInput, match="row 17"):
        surfkit.fit(uv, bad)
    with pytest.raises(surfkit.InvalidInput, match=r"shape \(n, 3\)"):
        surfkit.fit(uv, xyz[:, :2])
    with pytest.raises(surfkit.InvalidInput, match="space"):
        surfkit.fit(uv, xyz, space="nurbs")
    with pytest.raises(surfkit.InvalidInput, match="epsilon"):
        surfkit.fit(uv, xyz, epsilon=0)
    with pytest.raises(surfkit.InvalidInput, match="hole shape 0"):
        surfkit.fill(uv, xyz, hole=[("circle", (0.5, 0.5, 0.1))])
    with pytest.raises(surfkit.InvalidInput, match="shape condition"):
        surfkit.fill(uv, xyz, hole="cells-without-data", space="bfs-c1", shape=["positive-u"])
    spline = surfkit.fit(uv, xyz)
    with pytest.raises(surfkit.InvalidInput, match=r"point 1 \(u 2"):
        spline.evaluate([0.5, 2.0], [0.5, 0.5])
