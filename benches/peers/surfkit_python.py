"""surfkit from Python, timed inside one interpreter for benches/python_door.rs.

Usage:
  surfkit_python.py eat FILE REPEATS   -> {"eat": median s of surfkit.eat(mesh) on a mesh
                                          already read, "counts": the same without the
                                          OpenMesh structure and the fix check, and for each
                                          "<name>_threads": two scans on a ThreadPoolExecutor
                                          of 2 threads over one}
  surfkit_python.py scan WORKERS FILE... -> {"start": s to start a local Dask cluster,
                                          "scan": s of surfkit.batch.scan on it (defaults),
                                          "counts": s without the OpenMesh structure and the
                                          fix check, "errors"}
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
    from distributed import Client, LocalCluster
    from surfkit import batch

    t0 = time.perf_counter()
    with (
        LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True
        ) as cluster,
        Client(cluster) as client,
    ):
        client.run(lambda: __import__("surfkit"))  # workers ready, surfkit imported
        t1 = time.perf_counter()
        rows = batch.scan(paths, client)
        t2 = time.perf_counter()
        counted = batch.scan(paths, client, halfedge=False, check_fixes=False)
        t3 = time.perf_counter()
    errors = int(rows["error"].notna().sum() + counted["error"].notna().sum())
    print(
        json.dumps(
            {"start": t1 - t0, "scan": t2 - t1, "counts": t3 - t2, "errors": errors}
        )
    )


if __name__ == "__main__":
    if sys.argv[1] == "eat":
        eat(sys.argv[2], int(sys.argv[3]))
    else:
        scan(int(sys.argv[2]), sys.argv[3:])
