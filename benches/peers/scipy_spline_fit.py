"""FITPACK (scipy.interpolate) fits of the same scattered data as benches/spline_fit.rs.

Usage: scipy_spline_fit.py DATA.csv EVAL.csv CELLS K METHOD [S0,S1,S2]
  DATA.csv / EVAL.csv: lines u,v,x,y,z on [0, 1]^2 (fit data / exact values to compare with)
  METHOD lsq:    LSQBivariateSpline with the CELLS-1 uniform interior knots of surfkit's space
  METHOD smooth: SmoothBivariateSpline with smoothing factor S_c for component c (FITPACK
                 chooses its own knots until sum of squared residuals <= S_c)
Prints one JSON line: best-of-3 time for the three components, relative L2 error on EVAL,
the interior knots FITPACK used, and any warning it gave.
"""
import json
import sys
import time
import warnings

import numpy as np
from scipy.interpolate import LSQBivariateSpline, SmoothBivariateSpline

d = np.loadtxt(sys.argv[1], delimiter=",")
e = np.loadtxt(sys.argv[2], delimiter=",")
cells, k, method = int(sys.argv[3]), int(sys.argv[4]), sys.argv[5]
s = [float(x) for x in sys.argv[6].split(",")] if method == "smooth" else None
t = np.linspace(0, 1, cells + 1)[1:-1]


def fit(c):
    if method == "lsq":
        return LSQBivariateSpline(d[:, 0], d[:, 1], d[:, 2 + c], t, t, kx=k, ky=k, bbox=[0, 1, 0, 1])
    return SmoothBivariateSpline(d[:, 0], d[:, 1], d[:, 2 + c], kx=k, ky=k, bbox=[0, 1, 0, 1], s=s[c])


best, caught = None, []
for _ in range(3):
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        t0 = time.perf_counter()
        fits = [fit(c) for c in range(3)]
        dt = time.perf_counter() - t0
    caught = [str(x.message).split("\n")[0].strip() for x in w]
    best = dt if best is None else min(best, dt)
a = np.stack([f.ev(e[:, 0], e[:, 1]) for f in fits], axis=1)
err = np.sqrt(((a - e[:, 2:]) ** 2).sum() / (e[:, 2:] ** 2).sum())
knots = [[len(f.get_knots()[0]) - 2 * (k + 1), len(f.get_knots()[1]) - 2 * (k + 1)] for f in fits]
print(json.dumps({"time": best, "error": float(err), "interior_knots": knots, "warnings": sorted(set(caught))}))
