"""``python -m surfkit.batch DIR --out report.parquet``: the EAT over every mesh file of a
folder on a local Dask cluster, resumable (see :mod:`surfkit.batch`). Kept apart from the
package so that the functions the workers run are pickled by reference to it."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

import pandas as pd

from surfkit.batch import COLUMNS, mesh_paths, scan


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m surfkit.batch",
        description="The Euler Accompanying Test over every mesh file of a folder, on Dask.",
    )
    parser.add_argument("folder", type=Path)
    parser.add_argument("--out", type=Path, required=True, help="the report (.parquet or .csv)")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--weld-tolerance", type=float, default=0.0)
    parser.add_argument("--no-fix-check", action="store_true")
    parser.add_argument(
        "--timeout",
        type=float,
        default=300.0,
        help="seconds one file may take before its scan is stopped (0: no limit)",
    )
    args = parser.parse_args(argv)
    if not args.folder.is_dir():
        parser.error(f"{args.folder}: not a folder")
    if args.out.suffix not in (".parquet", ".csv"):
        parser.error(f"{args.out}: the report must be .parquet or .csv")
    if not args.out.parent.is_dir():
        parser.error(f"{args.out.parent}: the output folder does not exist")
    if args.workers < 1:
        parser.error("--workers must be at least 1")
    if args.timeout < 0:
        parser.error("--timeout must be ≥ 0")
    read = pd.read_parquet if args.out.suffix == ".parquet" else pd.read_csv
    before = read(args.out) if args.out.exists() else pd.DataFrame(columns=COLUMNS)
    known = set(before["path"].astype(str))
    todo = [p for p in mesh_paths(args.folder) if p not in known]
    options = {"weld_tolerance": args.weld_tolerance, "check_fixes": not args.no_fix_check}
    if todo:
        from distributed import Client, LocalCluster

        with (
            LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True) as cluster,
            Client(cluster) as client,
        ):
            found = scan(todo, client, progress=True, timeout=args.timeout or None, **options)
        frames = [f for f in (before, found) if len(f)]
        report = pd.concat(frames, ignore_index=True) if len(frames) > 1 else found
        temporary = args.out.with_name(args.out.name + ".partial")
        if args.out.suffix == ".parquet":
            report.to_parquet(temporary, index=False)
        else:
            report.to_csv(temporary, index=False)
        temporary.replace(args.out)
    failed = int(before["error"].notna().sum()) if len(before) else 0
    if todo:
        failed += int(found["error"].notna().sum())
    print(
        f"{len(todo)} files scanned, {len(known)} already in {args.out}, {failed} with an error",
        file=sys.stderr,
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
