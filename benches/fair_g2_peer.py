"""Kiciak's G² surface against the author's own program (issue 20), in one run.

    .venv/bin/python benches/fair_g2_peer.py [--meshes 3,4,5] [--sweep]

For each of the author's meshes fixtures/meshes/kiciak_trojnik{3,4,5}.obj (359, 1295, 4895
vertices), `surfkit fair` on the G² surface from the raw mesh — C = 0.01, 8 × 8 nodes per
element (the author's final F; his optimizer takes its Hessians at 6 × 6) — on all cores
and on one (RAYON_NUM_THREADS=1), with F, S, Newton iterations and wall time; then the
peer in the same run when BSTOOLS_G2MBL names an executable that runs BSTools' optimizer
(`g2mbl_InitBlSurfaceOptLMTd` / `g2mbl_IterBlSurfaceOptLMTd`, C = 0.01, nkn1 = 6,
nkn2 = 8, its own fixed vertices: boundary and two rings) on an OBJ given as its argument
and prints one JSON line with "F", "S_8", "iterations", "converged" and "seconds". BSTools
is LGPL C (radek-p/BSTools); build it and such a driver yourself beside this repository —
nothing of it is part of surfkit. It runs on one core (taskset -c 1).

--sweep: the regularization weight side by side — S after optimization, Newton iterations
and convergence for C ∈ {1, 0.1, 0.01} on both surfaces (default nodes, 4 × 4).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
CLI = REPO / "target" / "release" / "surfkit"
# surfkit's times are the median of this many runs (a run of 0.5 s varies by ±20 % on a
# shared 2-core machine); the peer's runs take 10–600 s and run once.
RUNS = 3


def mesh_path(level: str) -> Path:
    return REPO / "fixtures" / "meshes" / f"kiciak_trojnik{level}.obj"


def surfkit_fair(
    mesh: Path, extra: list[str], threads: int | None, cache: Path | None = None
) -> tuple[dict, float]:
    """One `surfkit fair` run; `cache` names the folder of its G² basis cache."""
    env = dict(os.environ)
    if threads is not None:
        env["RAYON_NUM_THREADS"] = str(threads)
    if cache is not None:
        env["SURFKIT_CACHE_DIR"] = str(cache)
    with tempfile.TemporaryDirectory() as tmp:
        start = time.monotonic()
        run = subprocess.run(
            [str(CLI), "fair", str(mesh), "-o", str(Path(tmp) / "out.obj"), "--json"]
            + ["--quiet", *extra],
            capture_output=True,
            text=True,
            env=env,
            check=False,
        )
        seconds = time.monotonic() - start
    if run.returncode not in (0, 3):
        raise SystemExit(f"surfkit fair {mesh.name} failed: {run.stderr}")
    return json.loads(run.stdout)["report"], seconds


def bstools(mesh: Path) -> dict | None:
    driver = os.environ.get("BSTOOLS_G2MBL")
    if not driver:
        return None
    start = time.monotonic()
    run = subprocess.run(
        ["taskset", "-c", "1", driver, str(mesh)],
        capture_output=True,
        text=True,
        check=False,
    )
    wall = time.monotonic() - start
    lines = [line for line in run.stdout.splitlines() if line.startswith("{")]
    if run.returncode != 0 or not lines:
        raise SystemExit(f"BSTools driver on {mesh.name} failed: {run.stderr[-500:]}")
    result = json.loads(lines[-1])
    result.setdefault("seconds", wall)
    return result


def peer_table(levels: list[str]) -> None:
    print(f"fair_g2_peer {time.strftime('%Y-%m-%d')}: raw start, C = 0.01, F and S at 8×8 nodes")
    print(
        "surfkit's default Hessian nodes (4 × 4); 'cold': its basis cache empty (the basis"
        " computed in the run), else stored by an earlier run"
    )
    print(
        "mesh       vertices  surfkit F   S        iters  s (2 cores)  s (1 core)  s (cold)"
        "   BSTools F   S        iters  s (1 core)  ratio 2c/1c/cold"
    )
    with tempfile.TemporaryDirectory() as warm:
        for level in levels:
            peer_row(level, Path(warm))


def peer_row(level: str, warm: Path) -> None:
    mesh = mesh_path(level)
    args = ["--nodes", "8"]
    colds = []
    for _ in range(RUNS):
        with tempfile.TemporaryDirectory() as empty:
            colds.append(surfkit_fair(mesh, args, None, Path(empty))[1])
    report, _ = surfkit_fair(mesh, args, None, warm)
    wall = statistics.median(surfkit_fair(mesh, args, None, warm)[1] for _ in range(RUNS))
    wall1 = statistics.median(surfkit_fair(mesh, args, 1, warm)[1] for _ in range(RUNS))
    cold = statistics.median(colds)
    terms = report["final_terms"]
    iters = len(report["newton"]["iterations"])
    row = (
        f"trojnik{level}  {report['vertices']:8d}  {terms['f']:10.6f}  {terms['s']:7.4f}"
        f"  {iters:5d}  {wall:11.2f}  {wall1:10.2f}  {cold:8.2f}"
    )
    peer = bstools(mesh)
    if peer is None:
        row += "   (BSTOOLS_G2MBL not set: no peer run)"
    else:
        row += (
            f"   {peer['F']:10.6f}  {peer.get('S_8', float('nan')):7.4f}"
            f"  {peer['iterations']:5d}  {peer['seconds']:10.2f}"
            f"  {peer['seconds'] / wall:5.1f}×/{peer['seconds'] / wall1:4.1f}×"
            f"/{peer['seconds'] / cold:4.1f}×"
        )
        if not peer.get("converged", True):
            row += " (BSTools not converged)"
    print(row, flush=True)


def sweep(levels: list[str]) -> None:
    print(
        f"\nregularization sweep {time.strftime('%Y-%m-%d')}: S after, Newton iterations, converged"
    )
    print("mesh       surface         C      S before    S after    F after   iters  conv  s")
    for level in levels:
        for surface in ("g2", "catmull-clark"):
            for c in ("1", "0.1", "0.01"):
                report, wall = surfkit_fair(
                    mesh_path(level), ["--surface", surface, "--regularization", c], None
                )
                n = report["newton"]
                print(
                    f"trojnik{level}  {surface:14s} {c:5s}  {n['initial']['s']:10.4f}"
                    f"  {report['final_terms']['s']:9.4f}  {report['final_terms']['f']:9.4f}"
                    f"  {len(n['iterations']):5d}  {n['converged']!s:5s} {wall:6.1f}",
                    flush=True,
                )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--meshes", default="3,4,5")
    parser.add_argument("--sweep", action="store_true")
    args = parser.parse_args()
    levels = args.meshes.split(",")
    peer_table(levels)
    if args.sweep:
        sweep(levels)


if __name__ == "__main__":
    main()
