"""Times trimesh loading a mesh file (process=False: no merging, as surfkit reads; an STL
file's corners are then merged with merge_vertices, as surfkit welds them).

Usage: trimesh_load.py FILE REPEATS  ->  prints one JSON line with the median and minimum
seconds of REPEATS loads (after one warm-up) and the loaded counts.
"""
import json
import statistics
import sys
import time

import trimesh


def load(path):
    mesh = trimesh.load(path, process=False)
    if path.lower().endswith(".stl"):
        mesh.merge_vertices()
    return mesh


def main():
    path, repeats = sys.argv[1], int(sys.argv[2])
    mesh = load(path)
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        mesh = load(path)
        times.append(time.perf_counter() - t0)
    print(json.dumps({
        "median_s": statistics.median(times),
        "min_s": min(times),
        "vertices": len(mesh.vertices),
        "faces": len(mesh.faces),
        "trimesh": trimesh.__version__,
    }))


if __name__ == "__main__":
    main()
