"""pymeshlab over files, as a data-set loop does it: load each file and ask for
get_topological_measures(); a file that fails is counted and the loop goes on.

Usage: pymeshlab_files.py FILE... -> one JSON line: files, errors, seconds (the loop,
without the interpreter's start-up, which the caller measures as part of the process).
"""
import json
import sys
import time

import pymeshlab


def main() -> None:
    t0 = time.perf_counter()
    errors = 0
    for path in sys.argv[1:]:
        ms = pymeshlab.MeshSet()
        try:
            ms.load_new_mesh(path)
            ms.get_topological_measures()
        except pymeshlab.PyMeshLabException:
            errors += 1
    print(json.dumps({"files": len(sys.argv) - 1, "errors": errors,
                      "seconds": time.perf_counter() - t0}))


if __name__ == "__main__":
    main()
