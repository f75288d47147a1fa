"""surfkit.fair against `surfkit fair --json` on the same junction, and its callback."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

import surfkit


@pytest.fixture(scope="module")
def tubes(cli: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A three-tube junction of 359 vertices (`surfkit gen tubes`)."""
    path = tmp_path_factory.mktemp("fair") / "tubes.obj"
    subprocess.run([cli, "gen", "tubes", "--output", path], check=True, capture_output=True)
    return path


def test_fair_is_the_cli_fair(tubes: Path, cli: Path, tmp_path: Path):
    out = tmp_path / "faired.ply"
    run = subprocess.run(
        [cli, "fair", tubes, "-o", out, "--json"], check=True, capture_output=True, text=True
    )
    theirs = json.loads(run.stdout)["report"]
    iterations: list[dict] = []
    mesh, report = surfkit.fair(surfkit.read_mesh(tubes), callback=iterations.append)
    assert report["newton"]["converged"] and theirs["newton"]["converged"]
    for term in ("f", "s", "q"):
        assert report["final_terms"][term] == pytest.approx(theirs["final_terms"][term], rel=1e-9)
    assert report["newton"]["hessian_evaluations"] == theirs["newton"]["hessian_evaluations"]
    written = surfkit.read_mesh(out)
    extent = np.ptp(written.vertices, axis=0).max()
    np.testing.assert_allclose(mesh.vertices, written.vertices, rtol=0, atol=1e-9 * extent)
    np.testing.assert_array_equal(mesh.face_indices, written.face_indices)
    # The callback saw every iteration of the log, with the report's values.
    assert len(iterations) == len(report["log"]) > 0
    assert [it["iteration"] for it in iterations] == list(range(1, len(iterations) + 1))
    for seen, logged in zip(iterations, report["log"], strict=True):
        assert seen["f"] == logged["terms"]["f"]
        assert seen["gradient_norm"] == logged["gradient_norm"]
        assert seen["step"] == logged["step"]


def test_regularization_is_the_cli_regularization(tubes: Path, cli: Path, tmp_path: Path):
    run = subprocess.run(
        [cli, "fair", tubes, "-o", tmp_path / "c.ply", "--json", "--regularization", "0.01"],
        check=True,
        capture_output=True,
        text=True,
    )
    theirs = json.loads(run.stdout)["report"]
    _, report = surfkit.fair(surfkit.read_mesh(tubes), regularization=0.01)
    assert report["regularization"] == theirs["regularization"] == 0.01
    for term in ("f", "s", "q"):
        assert report["final_terms"][term] == pytest.approx(theirs["final_terms"][term], rel=1e-9)
    # F = S + C·c·Q, with c the paper's |E|²/D⁴.
    t = report["final_terms"]
    assert t["f"] == pytest.approx(t["s"] + 0.01 * report["c"] * t["q"], rel=1e-12)


def test_the_surface_is_the_cli_surface(tubes: Path, cli: Path, tmp_path: Path):
    for surface in ("g2", "catmull-clark"):
        run = subprocess.run(
            [cli, "fair", tubes, "-o", tmp_path / "s.ply", "--json", "--surface", surface],
            check=True,
            capture_output=True,
            text=True,
        )
        theirs = json.loads(run.stdout)["report"]
        _, report = surfkit.fair(surfkit.read_mesh(tubes), surface=surface)
        assert report["surface"] == theirs["surface"] == surface
        for term in ("f", "s", "q"):
            assert report["final_terms"][term] == pytest.approx(
                theirs["final_terms"][term], rel=1e-9
            )
    _, default = surfkit.fair(surfkit.read_mesh(tubes), max_iterations=1)
    assert default["surface"] == "g2"
    with pytest.raises(surfkit.InvalidInput, match="surface"):
        surfkit.fair(surfkit.read_mesh(tubes), surface="loop")


def test_the_callback_stops_the_run(tubes: Path):
    seen: list[float] = []

    def stop_after_two(info: dict) -> bool:
        seen.append(info["f"])
        return len(seen) == 2

    mesh, report = surfkit.fair(surfkit.read_mesh(tubes), callback=stop_after_two)
    assert len(seen) == 2 and len(report["log"]) == 2
    assert report["newton"]["cancelled"] and not report["newton"]["converged"]
    assert report["final_terms"]["f"] == pytest.approx(seen[-1], rel=1e-12)
    assert report["final_terms"]["f"] < report["newton"]["initial"]["f"]


@pytest.fixture(scope="module")
def refined(cli: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The junction refined once (3743 vertices, 3167 free; one coarser level)."""
    path = tmp_path_factory.mktemp("fair") / "refined.obj"
    subprocess.run(
        [cli, "gen", "tubes", "--size", "8", "--rings", "2", "--refine", "1", "--output", path],
        check=True,
        capture_output=True,
    )
    return path


def fair_refined(
    cli: Path, refined: Path, out: Path, *options: str
) -> subprocess.CompletedProcess[str]:
    """`surfkit fair` on the refined junction as it is (no refinement), with `options`."""
    return subprocess.run(
        [cli, "fair", refined, "-o", out, "--max-refinements", "0", *options],
        check=False,
        capture_output=True,
        text=True,
    )


def test_the_method_is_chosen_by_keyword(refined: Path):
    # Both methods reach the same minimum, and the report names the one that ran.
    mesh = surfkit.read_mesh(refined)
    _, plain = surfkit.fair(mesh, method="plain", max_refinements=0)
    _, multilevel = surfkit.fair(mesh, method="multilevel", max_refinements=0)
    assert (plain["method"], multilevel["method"]) == ("plain", "multilevel")
    assert multilevel["multilevel_sizes"] == [3167, 911]
    assert plain["newton"]["converged"] and multilevel["newton"]["converged"]
    assert multilevel["final_terms"]["f"] == pytest.approx(plain["final_terms"]["f"], rel=1e-9)
    assert plain["coarse_start"] is None and multilevel["coarse_start"] is None


def test_the_coarse_start_is_the_cli_coarse_start(refined: Path, cli: Path, tmp_path: Path):
    run = fair_refined(
        cli, refined, tmp_path / "o.obj", "--method", "multilevel", "--coarse-start", "--json"
    )
    assert run.returncode == 0, run.stderr
    theirs = json.loads(run.stdout)["report"]
    _, report = surfkit.fair(
        surfkit.read_mesh(refined), method="multilevel", max_refinements=0, coarse_start=True
    )
    stage, their_stage = report["coarse_start"], theirs["coarse_start"]
    assert stage is not None and their_stage is not None
    # The coarse problem: the mesh the junction un-subdivides to (911 vertices, the
    # multilevel method's coarse level), optimized alone.
    assert stage["report"]["vertices"] == their_stage["report"]["vertices"] == 911
    assert stage["used"] == their_stage["used"]
    assert stage["start_f"] == pytest.approx(their_stage["start_f"], rel=1e-9)
    assert report["newton"]["converged"] and theirs["newton"]["converged"]
    assert report["final_terms"]["f"] == pytest.approx(theirs["final_terms"]["f"], rel=1e-9)


def test_the_memory_limit_is_the_cli_max_memory(refined: Path, cli: Path, tmp_path: Path):
    # The default is half of the machine's memory (MemTotal of /proc/meminfo).
    meminfo = Path("/proc/meminfo").read_text()
    total_kib = int(
        next(line for line in meminfo.splitlines() if line.startswith("MemTotal:")).split()[1]
    )
    assert surfkit.max_memory() == total_kib * 1024 // 2
    run = fair_refined(
        cli, refined, tmp_path / "o.obj", "--method", "plain", "--max-memory", "400M"
    )
    assert run.returncode != 0 and not (tmp_path / "o.obj").exists()
    mesh = surfkit.read_mesh(refined)
    try:
        surfkit.set_max_memory("400M")
        assert surfkit.max_memory() == 400 << 20
        with pytest.raises(surfkit.ResourceLimit) as refused:
            surfkit.fair(mesh, method="plain", max_refinements=0)
        surfkit.set_max_memory(400 << 20)
        assert surfkit.max_memory() == 400 << 20
    finally:
        surfkit.set_max_memory(None)
    message = str(refused.value)
    assert "fairing 3167 free vertices" in message and "memory limit of 400 MiB" in message
    assert message in run.stderr
    assert surfkit.max_memory() == total_kib * 1024 // 2
    for bad, says in (
        (1000, "size 1000 is out of range: it must be an integer from 1048576"),
        ("12Q", "unknown unit"),
        (1.5, "give bytes"),
    ):
        with pytest.raises(surfkit.InvalidInput, match=says):
            surfkit.set_max_memory(bad)
    assert surfkit.max_memory() == total_kib * 1024 // 2


def test_an_exception_in_the_callback_is_raised(tubes: Path):
    def fail(info: dict) -> None:
        raise KeyError("from the callback")

    with pytest.raises(KeyError, match="from the callback"):
        surfkit.fair(surfkit.read_mesh(tubes), callback=fail)


def test_bad_fair_options_are_refused(tubes: Path):
    mesh = surfkit.read_mesh(tubes)
    with pytest.raises(surfkit.InvalidInput, match="fixed vertex 100000 out of range"):
        surfkit.fair(mesh, fixed=[100000])
    with pytest.raises(surfkit.InvalidInput, match="relative_gradient"):
        surfkit.fair(mesh, relative_gradient=2.0)
    for bad in (0.0, -1.0, float("nan")):
        with pytest.raises(surfkit.InvalidInput, match="regularization"):
            surfkit.fair(mesh, regularization=bad)
    with pytest.raises(surfkit.InvalidInput, match='method "fast": use "auto"'):
        surfkit.fair(mesh, method="fast")
    for bad in (-1, 2**64):
        with pytest.raises(surfkit.InvalidInput, match=f"max_iterations {bad} is out of range"):
            surfkit.fair(mesh, max_iterations=bad)
    # 359 vertices: no coarser level for the multilevel method.
    with pytest.raises(surfkit.InvalidInput, match="needs a coarser level"):
        surfkit.fair(mesh, method="multilevel", max_refinements=0)
    closed = surfkit.read_mesh(Path(__file__).parents[2] / "fixtures/meshes/catmark_torus.obj")
    with pytest.raises(surfkit.SurfkitError):
        surfkit.fair(closed)


def test_a_tolerance_below_the_coordinates_floor_stops_there(tubes: Path):
    """10⁻¹⁸ of ‖g₀‖ is below what double coordinates hold (the rounded minimum's ‖g‖ is
    ~10⁻¹⁶ of it here): the run stops at that floor, within twice it (FLOOR_MARGIN), and
    says so in the report, without an error."""
    _, report = surfkit.fair(surfkit.read_mesh(tubes), relative_gradient=1e-18)
    newton = report["newton"]
    assert newton["stalled"] and not newton["converged"] and not newton["stuck"]
    floor = newton["coordinate_floor"]
    assert floor > 1e-18 * report["initial_gradient_norm"]
    assert report["final_gradient_norm"] <= 2 * floor
