"""Times pymeshlab's get_topological_measures() on a mesh already in memory.

Usage: pymeshlab_topology.py FILE REPEATS -> one JSON line: median and minimum seconds of
REPEATS calls (after one warm-up), the loading time (not part of the measure), and the
measures of the last call.
"""
import json
import statistics
import sys
import time

import pymeshlab


def main():
    path, repeats = sys.argv[1], int(sys.argv[2])
    ms = pymeshlab.MeshSet()
    t0 = time.perf_counter()
    ms.load_new_mesh(path)
    load = time.perf_counter() - t0
    measures = ms.get_topological_measures()
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        measures = ms.get_topological_measures()
        times.append(time.perf_counter() - t0)
    print(json.dumps({
        "median_s": statistics.median(times),
        "min_s": min(times),
        "load_s": load,
        "measures": {k: (v if isinstance(v, (int, float, bool)) else str(v)) for k, v in measures.items()},
    }))


if __name__ == "__main__":
    main()
