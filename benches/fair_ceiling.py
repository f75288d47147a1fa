"""Where plain Newton's ceiling is (issue 18, first part): `surfkit fair` from the raw
refined tube junctions, one process per size, with its wall time, peak RSS (from wait4),
Hessian and factorization time and count, and the gradient reduction reached.

    .venv/bin/python benches/fair_ceiling.py [SIZE ...]

SIZE is t3r2 (14 399 vertices), t5r2 (23 997), t3r3 (56 447), t5r3 (94 077) or t3r4
(225 023); default t3r2 t5r2 t3r3 t5r3. No peer runs in the same process: BSTools's
multilevel method is documented at 72 009 free vertices in about 6 h 20 min (not measured
here).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
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


def run_measured(args: list[str]) -> tuple[str, float, float]:
    """stdout, wall seconds and peak RSS (GB) of one child process."""
    start = time.monotonic()
    with subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL) as child:
        out = child.stdout.read() if child.stdout else b""
        _, status, usage = os.wait4(child.pid, 0)
        child.returncode = os.waitstatus_to_exitcode(status)
    return out.decode(), time.monotonic() - start, usage.ru_maxrss / 1e6


def main() -> None:
    names = sys.argv[1:] or ["t3r2", "t5r2", "t3r3", "t5r3"]
    print(f"fair_ceiling {time.strftime('%Y-%m-%d')} (plain Newton, raw start, all cores)")
    print("size    vertices  free     wall s  peak GB  Hessians (s)  factorizations (s)  |g|/|g0|")
    for name in names:
        with tempfile.TemporaryDirectory() as tmp:
            mesh = Path(tmp) / f"{name}.obj"
            subprocess.run(
                [
                    str(CLI),
                    "gen",
                    "tubes",
                    "--size",
                    "8",
                    "--rings",
                    "2",
                    *SIZES[name],
                    "-o",
                    str(mesh),
                ],
                check=True,
                capture_output=True,
            )
            out, wall, peak = run_measured(
                [str(CLI), "fair", str(mesh), "-o", str(Path(tmp) / "out.obj"), "--json"]
            )
            report = json.loads(out)["report"]
            newton = report["newton"]
            ratio = report["final_gradient_norm"] / newton["initial_gradient_norm"]
            print(
                f"{name:6} {report['vertices']:9} {report['free_vertices']:6} {wall:9.1f} "
                f"{peak:8.2f}  {newton['hessian_evaluations']:3} ({newton['hessian_seconds']:6.1f})"
                f"  {newton['factorizations']:3} ({newton['factorization_seconds']:6.1f})"
                f"       {ratio:.1e}",
                flush=True,
            )


if __name__ == "__main__":
    main()
