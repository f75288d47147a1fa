"""Plain Newton against the multilevel method on large tube junctions (issue 18): `surfkit
fair` from the raw refined junction, one process per size and method, with its wall time,
peak RSS (from wait4), Hessian passes (the fine level's exact Hessians + its passes of the
Gauss–Newton part alone + the coarse stage's Hessians the multilevel method starts from),
conjugate-gradient iterations, the fine Cholesky factors ("LLt") the
multilevel method fell back to where its V-cycle stagnated, the gradient reduction reached
(against the input's gradient) and F there (the five-tube junctions have several local
minima), how much the optimum shrinks the extraordinary vertices' neighbourhoods (EV/med,
extraordinary_edge_ratio, of the input and of each optimum), the two methods side by
side, then the issue's goals.

    .venv/bin/python benches/fair_ceiling.py [SIZE ...] [--surface g2|catmull-clark]
        [--methods plain,multilevel] [--timeout SECONDS] [--plain-timeout SECONDS]
        [--coarse-start] [--reports DIR]

SIZE is t3r2 (14 399 vertices), t5r2 (23 997), t3r3 (56 447), t5r3 (94 077) or t3r4
(223 487); default all five. A run longer than --timeout (default 2700 s, the issue's 45
minutes) is stopped and shown as "> T", and one surfkit refuses (the memory check) has its
reason printed below the table; --plain-timeout (default: --timeout) stops the
plain method's runs sooner, so that one run of all sizes fits in an evening.
--coarse-start gives the multilevel method's runs `surfkit fair --coarse-start` (nested
iteration). --reports DIR keeps every run's JSON report, its iterations included, and its
faired mesh. No peer runs in the same process: BSTools's multilevel method is documented
at 72 009 free vertices in about 6 h 20 min (not measured here).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import subprocess
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
CLI = REPO / "target" / "release" / "surfkit"
SIZES = {
    "t3r2": ["--n", "3", "--refine", "2"],
    "t5r2": ["--n", "5", "--refine", "2"],
    "t3r3": ["--n", "3", "--refine", "3"],
    "t5r3": ["--n", "5", "--refine", "3"],
    "t3r4": ["--n", "3", "--refine", "4"],
}


@dataclass
class Run:
    wall: float
    peak_gb: float
    report: dict | None  # None when stopped at the timeout or refused
    error: str = ""  # why surfkit refused the run (its message), if it did
    # The faired mesh's extraordinary_edge_ratio (NaN when the run did not finish).
    extraordinary: float = math.nan

    @property
    def converged(self) -> bool:
        return self.report is not None and self.report["newton"]["converged"]

    @property
    def at_floor(self) -> bool:
        """Stopped above the tolerance at the gradient's floor for double coordinates."""
        return self.report is not None and self.report["newton"]["stalled"]

    def cells(self) -> str:
        if self.error:
            return f"{'refused':>9}  (reason below the table)"
        if self.report is None:
            return f"> {self.wall:7.0f}  {self.peak_gb:5.2f}    (stopped)"
        newton = self.report["newton"]
        g0 = self.report["initial_gradient_norm"]
        ratio = self.report["final_gradient_norm"] / g0
        floor = newton.get("coordinate_floor")
        floor_cell = f"{floor / g0:.1e}" if floor else "   -   "
        chose_rounding = any(it["step"] == "lattice_rounding" for it in newton["iterations"])
        mark = "*" if self.at_floor else "r" if chose_rounding else " "
        gauss_newton_only = newton.get("gauss_newton_only_evaluations", 0)
        hessians = (
            f"{newton['hessian_evaluations']}+{gauss_newton_only}+{coarse_hessians(self.report)}"
        )
        return (
            f"{self.wall:9.1f}  {self.peak_gb:5.2f}  {hessians:>11}"
            f"  {newton['cg_iterations']:5}  {newton['fine_factorizations']:3}  {ratio:.1e}{mark}"
            f" {floor_cell}"
            f"  {self.report['final_terms']['f']:10.4f}"
            f"  {self.extraordinary:5.2f}"
        )


Positions = list[tuple[float, float, float]]
Edges = dict[tuple[int, int], int]


def read_obj(path: Path) -> tuple[Positions, Edges]:
    """An OBJ file's vertex positions and its edges, each with the number of its faces."""
    positions: Positions = []
    edges: Edges = {}
    with path.open() as obj:
        for line in obj:
            if line.startswith("v "):
                x, y, z = line.split()[1:4]
                positions.append((float(x), float(y), float(z)))
            elif line.startswith("f "):
                face = [int(token.split("/")[0]) - 1 for token in line.split()[1:]]
                for a, b in zip(face, face[1:] + face[:1]):
                    key = (min(a, b), max(a, b))
                    edges[key] = edges.get(key, 0) + 1
    return positions, edges


def extraordinary_edge_ratio(positions: Positions, edges: Edges) -> float:
    """Mean length of the edges at the interior vertices of valence other than 4 over the
    median edge length: how far the optimum shrinks (or grows) the neighbourhoods of the
    extraordinary vertices against the rest of the mesh (NaN for a mesh without any)."""
    valence = [0] * len(positions)
    boundary = [False] * len(positions)
    for (a, b), faces in edges.items():
        valence[a] += 1
        valence[b] += 1
        if faces == 1:
            boundary[a] = boundary[b] = True
    extraordinary = [not boundary[v] and valence[v] != 4 for v in range(len(positions))]
    lengths = {e: math.dist(positions[e[0]], positions[e[1]]) for e in edges}
    at = [length for (a, b), length in lengths.items() if extraordinary[a] or extraordinary[b]]
    if not at:
        return math.nan
    median = sorted(lengths.values())[len(lengths) // 2]
    return sum(at) / len(at) / median


def coarse_hessians(report: dict) -> int:
    """Hessians of the coarse stages (nested iteration) below the fine level."""
    stage = report.get("coarse_start")
    if stage is None:
        return 0
    inner = stage["report"]
    return inner["newton"]["hessian_evaluations"] + coarse_hessians(inner)


def run_measured(args: list[str], timeout: float) -> Run:
    """One child process: wall seconds, peak RSS and its JSON report (None if stopped)."""
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        start = time.monotonic()
        child = subprocess.Popen(args, stdout=out, stderr=err)
        while True:
            pid, status, usage = os.wait4(child.pid, os.WNOHANG)
            if pid:
                break
            if time.monotonic() - start > timeout:
                child.kill()
                _, status, usage = os.wait4(child.pid, 0)
                return Run(time.monotonic() - start, usage.ru_maxrss / 1e6, None)
            time.sleep(0.5)
        wall = time.monotonic() - start
        child.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        text = out.read()
        if not text:
            err.seek(0)
            return Run(wall, usage.ru_maxrss / 1e6, None, err.read().decode().strip())
        return Run(wall, usage.ru_maxrss / 1e6, json.loads(text)["report"])


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("sizes", nargs="*", default=list(SIZES))
    parser.add_argument("--surface", default="g2", choices=["g2", "catmull-clark"])
    parser.add_argument("--methods", default="plain,multilevel")
    parser.add_argument("--timeout", type=float, default=2700.0)
    parser.add_argument("--plain-timeout", type=float, default=None)
    parser.add_argument("--coarse-start", action="store_true")
    parser.add_argument(
        "--reports",
        type=Path,
        default=None,
        help="folder for every run's JSON report (<size>-<method>.json: its iterations)",
    )
    args = parser.parse_args()
    if args.reports:
        args.reports.mkdir(parents=True, exist_ok=True)
    timeouts = {"plain": args.plain_timeout or args.timeout}
    methods = args.methods.split(",")
    print(
        f"fair_ceiling {time.strftime('%Y-%m-%d')}: {args.surface} surface, raw refined "
        f"junctions, {os.cpu_count()} cores, tolerance 1e-8, timeout {args.timeout:.0f} s "
        f"(plain: {timeouts['plain']:.0f} s), coarse start: {args.coarse_start}"
    )
    header = "    wall s  peak GB  H+GN+coarse  CG  LLt  |g|/|g0|  floor   F reached  EV/med"
    print("size   vertices   free  EV/med  " + "  ".join(f"{m:>10}:{header}" for m in methods))
    results: dict[str, dict[str, Run]] = {}
    vertices: dict[str, int] = {}
    for name in args.sizes:
        with tempfile.TemporaryDirectory() as tmp:
            mesh = Path(tmp) / f"{name}.obj"
            subprocess.run(
                [str(CLI), "gen", "tubes", "--size", "8", "--rings", "2", *SIZES[name]]
                + ["-o", str(mesh)],
                check=True,
                capture_output=True,
            )
            input_positions, input_edges = read_obj(mesh)
            extraordinary_input = extraordinary_edge_ratio(input_positions, input_edges)
            row = {}
            for method in methods:
                row[method] = run_measured(
                    [str(CLI), "fair", str(mesh), "-o", str(Path(tmp) / "out.obj"), "--json"]
                    + ["--method", method, "--surface", args.surface]
                    + (["--coarse-start"] if args.coarse_start and method != "plain" else []),
                    timeouts.get(method, args.timeout),
                )
                # The mesh is a temporary file: its path says nothing in the table.
                row[method].error = row[method].error.removeprefix(f"surfkit: error: {mesh}: ")
                if row[method].report is None:
                    continue
                faired = Path(tmp) / "out.obj"
                row[method].extraordinary = extraordinary_edge_ratio(*read_obj(faired))
                if args.reports:
                    path = args.reports / f"{name}-{method}.json"
                    path.write_text(json.dumps(row[method].report, indent=1))
                    shutil.copyfile(faired, path.with_suffix(".obj"))
            results[name] = row
            known = next((r.report for r in row.values() if r.report is not None), None)
            # Every run refused or stopped: the vertices from the mesh itself, the free
            # ones unknown (the preparation decides them).
            vertices[name] = known["vertices"] if known else len(input_positions)
            free = str(known["free_vertices"]) if known else "-"
            print(
                f"{name:6} {vertices[name]:8} {free:>6}  {extraordinary_input:6.2f}  "
                + "  ".join(f"{'':>10} {row[m].cells()}" for m in methods),
                flush=True,
            )
    print(
        "floor: the gradient's floor for double coordinates (|H u|, u their rounding to"
        " nearest) over |g0|; r: reached with the rounding chosen at that floor; *: stopped"
        " there, above the tolerance, even so; EV/med: mean length of the edges at the"
        " extraordinary vertices over the median edge length, of the input and of the optimum"
    )
    for name, row in results.items():
        for method, run in row.items():
            if run.error:
                print(f"refused, {name} {method}: {run.error}")
    if set(methods) >= {"plain", "multilevel"}:
        print("speed-up of the multilevel method (plain wall / multilevel wall):")
        for name, row in results.items():
            plain, multilevel = row["plain"], row["multilevel"]
            if plain.error or multilevel.report is None:
                continue
            bound = ">" if plain.report is None else ""
            print(f"  {name}: {bound}{plain.wall / multilevel.wall:.2f}x")
    if "multilevel" in methods:
        converged = [(vertices[n], r["multilevel"].wall) for n, r in results.items()]
        converged = [
            c
            for c, n in zip(converged, results)
            if results[n]["multilevel"].converged or results[n]["multilevel"].at_floor
        ]
        if len(converged) >= 2:
            (n0, t0), (n1, t1) = converged[0], converged[-1]
            exponent = math.log(t1 / t0) / math.log(n1 / n0)
            print(
                f"multilevel time grows as n^{exponent:.2f} from {n0} to {n1} vertices"
                " (runs converged or at the floor)"
            )


if __name__ == "__main__":
    main()
