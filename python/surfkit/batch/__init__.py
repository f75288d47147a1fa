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

MESH_SUFFIXES = (".obj", ".ply", ".off", ".stl")

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


def error_row(path: str, message: str, seconds: float) -> dict:
    """The row of a file whose scan did not give one: only its error and time."""
    row: dict[str, Any] = dict.fromkeys(COLUMNS)
    row.update(path=path, error=message, seconds=seconds)
    return row


def _failed_row(path: str, error: BaseException) -> dict:
    """The row of a task that died outside scan_one (a crashed or killed worker)."""
    return error_row(path, f"{type(error).__name__}: {error}", float("nan"))


def scan_many(
    paths: list[str], options: dict[str, Any] | None = None, timeout: float | None = None
) -> list[dict]:
    """The rows of several files, one after the other (one task of :func:`scan`)."""
    return [scan_one(p, options, timeout) for p in paths]


def _chunks(paths: list[str], size: int | None) -> list[list[str]]:
    """``paths`` cut into tasks: a task costs the scheduler about as much as scanning a
    small file, so files go ``size`` at a time (by default n / 64, 1 to 32)."""
    if size is None:
        size = max(1, min(32, len(paths) // 64))
    if size < 1:
        raise surfkit.InvalidInput(f"chunk_size {size} must be at least 1")
    return [paths[i : i + size] for i in range(0, len(paths), size)]


def _rows(
    paths: list[str],
    client: Any,
    options: dict[str, Any],
    timeout: float | None,
    chunk_size: int | None,
) -> Iterator[dict]:
    """Rows in completion order, a chunk of files per ``client.submit``."""
    futures = {
        client.submit(scan_many, chunk, options, timeout): chunk
        for chunk in _chunks(paths, chunk_size)
    }
    try:
        from distributed import as_completed as dask_completed

        dask_futures = all(not isinstance(f, Future) for f in futures)
    except ImportError:
        dask_futures = False
    if dask_futures:
        # Results come with the completions, in batches, not one round trip per task.
        for future, rows in dask_completed(list(futures), with_results=True, raise_errors=False):
            if future.status == "error":
                yield from (_failed_row(p, future.exception()) for p in futures[future])
            else:
                yield from rows
        return
    from concurrent.futures import as_completed

    for future in as_completed(list(futures)):
        try:
            yield from future.result()
        except Exception as e:  # the worker died (a crash in a reader, out of memory)
            yield from (_failed_row(p, e) for p in futures[future])


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
    chunk_size: int | None = None,
    **eat_options: Any,
) -> pd.DataFrame:
    """Scans every file of ``paths`` (see the module docstring); rows in the given order.
    ``timeout``: seconds one file may take (see :func:`scan_one`); None: no limit, the
    scan runs in the worker itself. ``chunk_size``: files per task (default n / 64, 1 to
    32; a task costs the scheduler about what a small file costs to scan)."""
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
            return scan(
                order,
                local,
                progress=progress,
                timeout=timeout,
                chunk_size=chunk_size,
                **eat_options,
            )
    rows = []
    for k, row in enumerate(_rows(order, client, eat_options, timeout, chunk_size), start=1):
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
