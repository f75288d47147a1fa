"""Corpus scans: the EAT over many mesh files on Dask (or any executor), one row per file.

``scan(paths, client=None, **eat_options)`` returns a pandas DataFrame with ``path``, every
scalar key of :func:`surfkit.eat`'s dict, ``flaws_<kind>`` counts, ``seconds`` and ``error``
(the message of a file that failed; the other rows are kept). ``client`` is a Dask
``distributed.Client`` (a cluster's or a local one), a ``concurrent.futures`` executor, or
anything else with ``submit(fn, *args)`` returning futures with ``result()`` (Ray's
``ray.util.ActorPool`` does not qualify; wrap ``ray.remote`` tasks in an executor); with
``None`` a local Dask cluster of one single-threaded worker process per core runs the scan.
A ``ProcessPoolExecutor`` needs the "spawn" (or "forkserver") start method: surfkit and
Dask run threads, which a forked child inherits in whatever state they were.

``timeout=`` seconds bounds each file: its scan then runs in a child process of the worker
(``surfkit._sandbox``), killed when it passes the limit and replaced when it crashes, so a
file that hangs or crashes a reader is a row with its error and the worker lives on.

``python -m surfkit.batch DIR --out report.parquet`` does the same from a shell, with a
progress line on standard error, 300 s per file at most (``--timeout``); files already in
the output are skipped (resumable).
"""

from __future__ import annotations

import os
import sys
import threading
import time
from collections.abc import Iterable, Iterator
from concurrent.futures import Future
from pathlib import Path
from typing import Any

import pandas as pd

import surfkit
from surfkit._sandbox import Sandbox
from surfkit._surfkit import FLAW_KINDS

MESH_SUFFIXES = (".obj", ".ply", ".off")

#: The scalar keys of surfkit.eat's dict kept per file, in column order.
SCALAR_KEYS = [
    "vertices_number",
    "edges_number",
    "faces_number",
    "boundary_edges",
    "connected_components_number",
    "is_mesh_two_manifold",
    "non_two_manifold_edges",
    "non_two_manifold_vertices",
    "incident_faces_on_non_two_manifold_edges",
    "incident_faces_on_non_two_manifold_vertices",
    "unreferenced_vertices",
    "number_holes",
    "genus",
    "euler_characteristic",
    "vertices_referenced",
    "verified",
]

COLUMNS = ["path", *SCALAR_KEYS, *(f"flaws_{k}" for k in FLAW_KINDS), "seconds", "error"]


_SANDBOXES = threading.local()


def scan_one(
    path: str | os.PathLike[str],
    options: dict[str, Any] | None = None,
    timeout: float | None = None,
) -> dict:
    """One file's row; a file surfkit cannot read or scan is a row with its ``error``.

    With ``timeout`` (seconds) the scan runs in a child process of this one (one per
    thread, reused from file to file) that is killed when it passes the limit or replaced
    when it dies: a file that hangs or crashes a reader is a row with its error.
    """
    if timeout is not None:
        if not timeout > 0:
            raise surfkit.InvalidInput(f"timeout {timeout} must be a number of seconds > 0")
        sandbox = getattr(_SANDBOXES, "sandbox", None)
        if sandbox is None:
            sandbox = _SANDBOXES.sandbox = Sandbox()
        return sandbox.scan(str(path), options or {}, timeout)
    start = time.perf_counter()
    row: dict[str, Any] = dict.fromkeys(COLUMNS)
    row["path"] = str(path)
    try:
        measures = surfkit.eat(surfkit.read_mesh(path), **(options or {}))
    except Exception as e:  # every failure is the file's row, never the end of the run
        row["error"] = f"{type(e).__name__}: {e}"
    else:
        for key in SCALAR_KEYS:
            row[key] = measures[key]
        for kind in FLAW_KINDS:
            row[f"flaws_{kind}"] = sum(f["kind"] == kind for f in measures["flaws"])
    row["seconds"] = time.perf_counter() - start
    return row


def _failed_row(path: str, error: BaseException) -> dict:
    """The row of a task that died outside scan_one (a crashed or killed worker)."""
    row: dict[str, Any] = dict.fromkeys(COLUMNS)
    row.update(path=path, error=f"{type(error).__name__}: {error}", seconds=float("nan"))
    return row


def _rows(
    paths: list[str], client: Any, options: dict[str, Any], timeout: float | None
) -> Iterator[dict]:
    """Rows in completion order through ``client.submit``."""
    futures = {client.submit(scan_one, p, options, timeout): p for p in paths}
    try:
        from distributed import as_completed as dask_completed

        dask_futures = all(not isinstance(f, Future) for f in futures)
    except ImportError:
        dask_futures = False
    if dask_futures:
        done: Iterable[Any] = dask_completed(list(futures))
    else:
        from concurrent.futures import as_completed

        done = as_completed(list(futures))
    for future in done:
        try:
            yield future.result()
        except Exception as e:  # the worker died (a crash in a reader, out of memory)
            yield _failed_row(futures[future], e)


def _frame(rows: list[dict], order: list[str]) -> pd.DataFrame:
    """Rows in the order of ``order`` (the input paths), typed columns."""
    frame = pd.DataFrame(rows, columns=COLUMNS)
    frame["path"] = pd.Categorical(frame["path"], categories=order, ordered=True)
    frame = frame.sort_values("path").reset_index(drop=True)
    frame["path"] = frame["path"].astype(str)
    return frame


def scan(
    paths: Iterable[str | os.PathLike[str]],
    client: Any = None,
    *,
    progress: bool = False,
    timeout: float | None = None,
    **eat_options: Any,
) -> pd.DataFrame:
    """Scans every file of ``paths`` (see the module docstring); rows in the given order.
    ``timeout``: seconds one file may take (see :func:`scan_one`); None: no limit, the
    scan runs in the worker itself."""
    order = [str(p) for p in paths]
    if len(set(order)) != len(order):
        raise surfkit.InvalidInput("paths: a file is listed twice")
    if client is None:
        from distributed import Client, LocalCluster

        with (
            LocalCluster(
                n_workers=os.cpu_count() or 1, threads_per_worker=1, processes=True
            ) as cluster,
            Client(cluster) as local,
        ):
            return scan(order, local, progress=progress, timeout=timeout, **eat_options)
    rows = []
    for k, row in enumerate(_rows(order, client, eat_options, timeout), start=1):
        rows.append(row)
        if progress:
            _progress(k, len(order))
    return _frame(rows, order)


def _progress(done: int, total: int) -> None:
    width = 40
    filled = width * done // max(total, 1)
    sys.stderr.write(f"\r[{'#' * filled}{'.' * (width - filled)}] {done}/{total} files")
    if done == total:
        sys.stderr.write("\n")
    sys.stderr.flush()


def mesh_paths(folder: Path) -> list[str]:
    """The mesh files under ``folder`` (recursively), sorted."""
    return sorted(
        str(p) for p in folder.rglob("*") if p.is_file() and p.suffix.lower() in MESH_SUFFIXES
    )
