"""subdivide and the limit surface against the CLI's files, OpenSubdiv's crease rules
and an independent bicubic B-spline evaluation."""

from __future__ import annotations

import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest
from conftest import MESHES

import surfkit

QUAD_FIXTURES = ["catmark_torus.obj", "catmark_nonquads.obj", "spot.obj"]


def _random_grid(n: int, scale: float, seed: int) -> tuple[np.ndarray, surfkit.Mesh]:
    """An n × n quad grid of unit squares with random heights (normal, `scale`): its
    points (row j, column i at j (n + 1) + i) and the mesh."""
    rng = np.random.default_rng(seed)
    grid = np.array([[i, j, 0.0] for j in range(n + 1) for i in range(n + 1)], dtype=float)
    grid[:, 2] = rng.normal(scale=scale, size=len(grid))
    quads = [
        [j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i]
        for j in range(n)
        for i in range(n)
    ]
    return grid, surfkit.Mesh(grid, quads)


@pytest.mark.parametrize("name", QUAD_FIXTURES)
@pytest.mark.parametrize("boundary", ["edges-and-corners", "edges-only"])
def test_subdivide_is_the_cli_subdivide(name: str, boundary: str, cli: Path, tmp_path: Path):
    out = tmp_path / "refined.ply"
    subprocess.run(
        [cli, "subdivide", MESHES / name, "-l", "2", "-o", out, "--boundary", boundary],
        check=True,
        capture_output=True,
    )
    theirs = surfkit.read_mesh(out)
    ours = surfkit.subdivide(surfkit.read_mesh(MESHES / name), 2, boundary=boundary)
    assert isinstance(ours, surfkit.Mesh)
    np.testing.assert_array_equal(ours.face_indices, theirs.face_indices)
    np.testing.assert_array_equal(ours.face_offsets, theirs.face_offsets)
    # Binary PLY keeps the doubles the CLI computed.
    np.testing.assert_array_equal(ours.vertices, theirs.vertices)


def test_an_infinitely_sharp_crease_follows_the_cubic_b_spline_rules():
    """Along a sharp crease v0–v1–v2 the refined points are the curve's: edge points
    (v0 + v1) / 2, and the vertex point (v0 + 6 v1 + v2) / 8 (OpenSubdiv's crease rule)."""
    n = 4
    grid, mesh = _random_grid(n, 0.3, seed=7)
    row = [2 * (n + 1) + i for i in range(n + 1)]  # the middle row, an interior line
    creases = [(row[i], row[i + 1], 10.0) for i in range(n)]
    refined = surfkit.subdivide(mesh, 1, creases=creases)
    smooth = surfkit.subdivide(mesh, 1)
    p = refined.vertices
    v = grid[row]
    for k in range(1, n):  # interior vertices of the crease keep the curve's vertex rule
        np.testing.assert_allclose(p[row[k]], (v[k - 1] + 6 * v[k] + v[k + 1]) / 8, atol=1e-12)
    for k in range(n):  # its edge points are the midpoints
        mid = (v[k] + v[k + 1]) / 2
        assert np.min(np.linalg.norm(p - mid, axis=1)) < 1e-12
    # Without the crease the same vertices move off the curve.
    assert np.max(np.abs(smooth.vertices[row[1:n]] - p[row[1:n]])) > 1e-3


def _bspline_basis(t: float, order: int) -> np.ndarray:
    """The uniform cubic B-spline basis (or its derivative of `order`) at t ∈ [0, 1]."""
    s = 1 - t
    return [
        np.array([s**3, 3 * t**3 - 6 * t**2 + 4, -3 * t**3 + 3 * t**2 + 3 * t + 1, t**3]) / 6,
        np.array([-(s**2) / 2, 1.5 * t**2 - 2 * t, -1.5 * t**2 + t + 0.5, t**2 / 2]),
        np.array([s, 3 * t - 2, 1 - 3 * t, t]),
    ][order]


def test_the_limit_on_a_regular_patch_is_the_bicubic_b_spline():
    """A quad grid's interior face is a regular patch: the limit surface there is the
    bicubic B-spline of its 4 × 4 neighbourhood, evaluated here independently."""
    n = 5
    grid, mesh = _random_grid(n, 0.4, seed=3)
    rng = np.random.default_rng(4)
    face = 2 * n + 2  # rows and columns 1..4 of control points around it
    u, v = rng.uniform(size=20), rng.uniform(size=20)
    got = surfkit.limit(mesh, np.full(20, face), u, v, derivatives=2)
    control = np.array([[grid[(1 + r) * (n + 1) + 1 + c] for c in range(4)] for r in range(4)])
    for k in range(20):
        for name, (a, b) in {
            "position": (0, 0),
            "du": (1, 0),
            "dv": (0, 1),
            "duu": (2, 0),
            "duv": (1, 1),
            "dvv": (0, 2),
        }.items():
            bu, bv = _bspline_basis(u[k], a), _bspline_basis(v[k], b)
            expected = np.einsum("r,c,rcx->x", bv, bu, control)
            np.testing.assert_allclose(got[name][k], expected, atol=1e-12, err_msg=name)


@pytest.mark.parametrize("name", ["catmark_torus.obj", "catmark_nonquads.obj"])
def test_limit_samples_are_the_cli_curvature_map(name: str, cli: Path, tmp_path: Path):
    """`surfkit limit --samples 3` writes one (K+1)² grid per ptex face with the mean
    curvature as quality: the binding gives the same positions and curvature there."""
    out = tmp_path / "map.ply"
    subprocess.run(
        [cli, "limit", MESHES / name, "-o", out, "--samples", "3"],
        check=True,
        capture_output=True,
    )
    samples = surfkit.read_mesh(out)
    surface = surfkit.LimitSurface(surfkit.read_mesh(MESHES / name))
    k = 3
    per_face = (k + 1) ** 2
    faces = np.repeat(np.arange(surface.ptex_face_count), per_face)
    local = np.tile(np.arange(per_face), surface.ptex_face_count)
    u, v = (local % (k + 1)) / k, (local // (k + 1)) / k
    got = surface.evaluate(faces, u, v)
    np.testing.assert_allclose(got["position"], samples.vertices, rtol=0, atol=1e-5)
    assert samples.vertex_count == len(faces)


def test_derivatives_are_those_of_the_positions():
    """Central differences of the positions match the first and second derivatives near
    an extraordinary vertex too (inside an end-cap patch)."""
    mesh = surfkit.read_mesh(MESHES / "catmark_nonquads.obj")
    surface = surfkit.LimitSurface(mesh)
    h = 1e-4
    faces = np.arange(0, surface.ptex_face_count, 3)
    u = np.full(faces.size, 0.37)
    v = np.full(faces.size, 0.61)
    d = surface.evaluate(faces, u, v)
    at = lambda du, dv: surface.evaluate(faces, u + du, v + dv, derivatives=0)["position"]  # noqa: E731
    np.testing.assert_allclose((at(h, 0) - at(-h, 0)) / (2 * h), d["du"], atol=1e-6)
    np.testing.assert_allclose((at(0, h) - at(0, -h)) / (2 * h), d["dv"], atol=1e-6)
    np.testing.assert_allclose(
        (at(h, 0) - 2 * d["position"] + at(-h, 0)) / h**2, d["duu"], atol=2e-4
    )
    # Curvature from the fundamental forms, computed here.
    n = np.cross(d["du"], d["dv"])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    e, f, g = (
        np.einsum("ij,ij->i", a, b)
        for a, b in [(d["du"], d["du"]), (d["du"], d["dv"]), (d["dv"], d["dv"])]
    )
    l_, m, nn = (np.einsum("ij,ij->i", a, n) for a in (d["duu"], d["duv"], d["dvv"]))
    mean = (e * nn - 2 * f * m + g * l_) / (2 * (e * g - f * f))
    np.testing.assert_allclose(d["normal"], n, atol=1e-12)
    np.testing.assert_allclose(d["mean_curvature"], mean, rtol=1e-9, atol=1e-12)
    np.testing.assert_array_less(d["k2"] - 1e-12, d["k1"])


def test_bad_limit_points_are_named():
    surface = surfkit.LimitSurface(surfkit.read_mesh(MESHES / "catmark_torus.obj"))
    with pytest.raises(surfkit.InvalidInput, match="point 1: ptex face 100000"):
        surface.evaluate([0, 100000], [0.5, 0.5], [0.5, 0.5])
    with pytest.raises(surfkit.InvalidInput, match=r"point 0: \(u, v\) = \(1.5"):
        surface.evaluate([0], [1.5], [0.5])
    with pytest.raises(surfkit.InvalidInput, match="one entry per point"):
        surface.evaluate([0, 1], [0.5, 0.5, 0.5], [0.5, 0.5])
    with pytest.raises(surfkit.InvalidInput, match="boundary"):
        surfkit.subdivide(surfkit.read_mesh(MESHES / "catmark_torus.obj"), 1, boundary="sharp")
    with pytest.raises(surfkit.InvalidInput, match="sharpness"):
        surfkit.subdivide(
            surfkit.read_mesh(MESHES / "catmark_torus.obj"), 1, creases=[(0, 1, float("nan"))]
        )


def test_out_of_range_levels_are_named():
    torus = surfkit.read_mesh(MESHES / "catmark_torus.obj")
    for bad in (-1, 2**32, 2**70):
        with pytest.raises(surfkit.InvalidInput, match=f"levels {bad} is out of range"):
            surfkit.subdivide(torus, bad)


def test_a_limit_surface_is_used_and_dropped_on_other_threads(monkeypatch: pytest.MonkeyPatch):
    unraisable = []
    monkeypatch.setattr(sys, "unraisablehook", unraisable.append)
    torus = surfkit.read_mesh(MESHES / "catmark_torus.obj")
    surface = surfkit.LimitSurface(torus)
    here = surface.evaluate([0, 1], 0.5, 0.5)
    with ThreadPoolExecutor(2) as pool:
        there = [pool.submit(surface.evaluate, [0, 1], 0.5, 0.5) for _ in range(4)]
        for future in there:
            np.testing.assert_array_equal(future.result()["position"], here["position"])
        made = pool.submit(surfkit.LimitSurface, torus).result()
        np.testing.assert_array_equal(made.evaluate([0, 1], 0.5, 0.5)["k1"], here["k1"])
        holder = [surface]
        del surface
        pool.submit(holder.clear).result()  # the last reference goes on the worker
    del made
    assert unraisable == []
