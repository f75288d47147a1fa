"""surfkit from Python, timed inside one interpreter for benches/python_door.rs.

Usage:
  surfkit_python.py eat FILE REPEATS   -> {"eat": median s of surfkit.eat(mesh) on a mesh
                                          already read, "counts": the same without the
                                          OpenMesh structure and the fix check, and for each
                                          "<name>_threads": two scans on a ThreadPoolExecutor
                                          of 2 threads over one}
  surfkit_python.py scan WORKERS FILE... -> seconds of surfkit.batch.scan on a local
                                          Dask cluster ("dask", "dask_counts": without the
                                          OpenMesh structure and the fix check) and on a
                                          spawn ProcessPoolExecutor ("pool", "pool_counts"),
                                          each with its start ("dask_start", "pool_start")
"""

from __future__ import annotations

import json
import sys
import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from functools import partial
from statistics import median

import surfkit


def eat(path: str, repeats: int) -> None:
    mesh = surfkit.read_mesh(path)

    def timed(f: Callable[[], object]) -> float:
        t0 = time.perf_counter()
        f()
        return time.perf_counter() - t0

    out = {}
    for name, options in [
        ("eat", {}),
        ("counts", {"halfedge": False, "check_fixes": False}),
    ]:
        scan = partial(surfkit.eat, **options)
        scan(mesh)  # warm-up
        out[name] = median(timed(lambda scan=scan: scan(mesh)) for _ in range(repeats))
        with ThreadPoolExecutor(max_workers=2) as pool:
            one = median(
                timed(lambda scan=scan: list(pool.map(scan, [mesh])))
                for _ in range(repeats)
            )
            two = median(
                timed(lambda scan=scan: list(pool.map(scan, [mesh, mesh])))
                for _ in range(repeats)
            )
        out[f"{name}_threads"] = two / one
    print(json.dumps(out))


def scan(workers: int, paths: list[str]) -> None:
    from concurrent.futures import ProcessPoolExecutor
    from multiprocessing import get_context

    from distributed import Client, LocalCluster
    from surfkit import batch

    counts = {"halfedge": False, "check_fixes": False}
    out: dict[str, float] = {}
    errors = 0

    def run(name: str, client: object) -> None:
        nonlocal errors
        for suffix, options in [("", {}), ("_counts", counts)]:
            t0 = time.perf_counter()
            rows = batch.scan(paths, client, **options)
            out[name + suffix] = time.perf_counter() - t0
            errors += int(rows["error"].notna().sum())

    t0 = time.perf_counter()
    with (
        LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True
        ) as cluster,
        Client(cluster) as client,
    ):
        client.run(
            lambda: __import__("surfkit.batch")
        )  # workers ready, surfkit imported
        out["dask_start"] = time.perf_counter() - t0
        run("dask", client)
    t0 = time.perf_counter()
    with ProcessPoolExecutor(workers, mp_context=get_context("spawn")) as pool:
        list(
            pool.map(batch.scan_many, [[]] * workers)
        )  # workers ready, surfkit imported
        out["pool_start"] = time.perf_counter() - t0
        run("pool", pool)
    out["errors"] = errors
    print(json.dumps(out))


if __name__ == "__main__":
    if sys.argv[1] == "eat":
        eat(sys.argv[2], int(sys.argv[3]))
    else:
        scan(int(sys.argv[2]), sys.argv[3:])
