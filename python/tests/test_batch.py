"""surfkit.batch on a corpus of 500+ generated and real meshes: a 2-worker local Dask
cluster and a ProcessPoolExecutor give exactly the serial rows; files that cannot be read
are rows with their error; the command line resumes where its report stops."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import get_context
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from conftest import mesh_files, polygons
from distributed import Client, LocalCluster

import surfkit
from surfkit import batch
from surfkit._sandbox import Sandbox

VARIANTS = 42  # per fixture: 12 fixtures make 504 files


def _variant(mesh: surfkit.Mesh, k: int, rng: np.random.Generator) -> surfkit.Mesh | bytes:
    """Variant k of a mesh: as is, or with one flaw injected at a seeded random place, or
    a file no reader takes."""
    vertices = mesh.vertices
    faces = polygons(mesh)
    f = int(rng.integers(len(faces)))
    match k % 7:
        case 0:
            pass
        case 1:  # a hole (or a missing triangle)
            del faces[f]
        case 2:  # a duplicated facet
            faces.append(list(faces[f]))
        case 3:  # an inconsistently oriented facet
            faces[f] = faces[f][::-1]
        case 4:  # an unreferenced vertex
            vertices = np.vstack([vertices, rng.normal(size=(1, 3))])
        case 5:  # a vertex moved: the topology is unchanged
            vertices = vertices.copy()
            vertices[faces[f][0]] += rng.normal(scale=1e-3, size=3)
        case 6:  # not a mesh
            return rng.integers(0, 256, size=200, dtype=np.uint8).tobytes()
    return surfkit.Mesh(vertices, faces)


@pytest.fixture(scope="session")
def corpus(tmp_path_factory: pytest.TempPathFactory) -> list[str]:
    folder = tmp_path_factory.mktemp("corpus")
    rng = np.random.default_rng(17)
    paths = []
    for source in mesh_files():
        mesh = surfkit.read_mesh(source)
        for k in range(VARIANTS):
            path = folder / f"{source.stem}_{k:02d}.obj"
            made = _variant(mesh, k, rng)
            if isinstance(made, bytes):
                path.write_bytes(made)
            else:
                made.write(path)
            paths.append(str(path))
    assert len(paths) >= 500
    return paths


@pytest.fixture(scope="session")
def serial(corpus: list[str]) -> pd.DataFrame:
    return batch._frame([batch.scan_one(p) for p in corpus], corpus)


def _same(a: pd.DataFrame, b: pd.DataFrame) -> None:
    pd.testing.assert_frame_equal(
        a.drop(columns="seconds"), b.drop(columns="seconds"), check_dtype=False
    )


def test_a_two_worker_dask_cluster_gives_the_serial_rows(
    corpus: list[str], serial: pd.DataFrame
) -> None:
    with (
        LocalCluster(n_workers=2, threads_per_worker=1, processes=True) as cluster,
        Client(cluster) as client,
    ):
        # Each file in a worker's child process (the timeout's sandbox): the same rows.
        rows = batch.scan(corpus, client, timeout=120)
    _same(rows, serial)
    assert list(rows.columns) == batch.COLUMNS
    errors = rows["error"].notna()
    # Every non-mesh variant is a row with its error, and only those.
    assert errors.sum() == sum(1 for p in corpus if int(Path(p).stem[-2:]) % 7 == 6)
    assert rows.loc[errors, "error"].str.contains("InvalidInput").all()
    assert (rows.loc[~errors, "flaws_duplicated_facet"] > 0).sum() >= len(mesh_files())


def test_a_process_pool_gives_the_serial_rows(corpus: list[str], serial: pd.DataFrame) -> None:
    part = corpus[::5]
    # spawn: a forked child of a process whose threads (surfkit's, Dask's) hold locks can
    # deadlock; Python 3.14 makes this the default.
    with ProcessPoolExecutor(max_workers=2, mp_context=get_context("spawn")) as pool:
        rows = batch.scan(part, pool)
    _same(rows, serial[serial["path"].isin(part)].reset_index(drop=True))


def test_the_command_line_resumes(corpus: list[str], serial: pd.DataFrame, tmp_path: Path) -> None:
    folder = tmp_path / "meshes"
    folder.mkdir()
    first = [Path(p) for p in corpus[:14]]
    for p in first:
        (folder / p.name).write_bytes(p.read_bytes())
    out = tmp_path / "report.parquet"
    command = [sys.executable, "-m", "surfkit.batch", str(folder), "--out", str(out)]
    done = subprocess.run(command, check=False, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "14 files scanned, 0 already" in done.stderr
    for p in corpus[14:21]:
        (folder / Path(p).name).write_bytes(Path(p).read_bytes())
    done = subprocess.run(command, check=False, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "7 files scanned, 14 already" in done.stderr
    report = pd.read_parquet(out)
    assert len(report) == 21
    expected = serial.set_index(serial["path"].map(lambda p: Path(p).name))
    for _, row in report.iterrows():
        want = expected.loc[Path(row["path"]).name]
        assert row["euler_characteristic"] == want["euler_characteristic"] or (
            pd.isna(row["euler_characteristic"]) and pd.isna(want["euler_characteristic"])
        )
        assert (row["error"] is None or pd.isna(row["error"])) == pd.isna(want["error"])


@pytest.fixture(scope="module")
def slow_file(tmp_path_factory: pytest.TempPathFactory) -> str:
    """A 2M-triangle grid: its scan takes about a second here, far above 0.05 s."""
    n = 1000
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    v = (i * (n + 1) + j).ravel()
    quads = np.stack([v, v + 1, v + n + 2, v + n + 1], axis=1)
    triangles = np.vstack([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    g = np.arange(n + 1, dtype=float)
    vertices = np.stack([np.repeat(g, n + 1), np.tile(g, n + 1), np.zeros((n + 1) ** 2)], axis=1)
    path = tmp_path_factory.mktemp("slow") / "grid.ply"
    surfkit.Mesh(vertices, triangles).write(path)
    return str(path)


def test_a_file_past_the_timeout_is_a_row_and_the_next_file_is_scanned(
    corpus: list[str], serial: pd.DataFrame, slow_file: str
) -> None:
    rows = [batch.scan_one(p, timeout=t) for p, t in [(slow_file, 0.05), (corpus[0], 60)]]
    assert rows[0]["error"] == "timed out after 0.05 s (the scan was stopped)"
    assert rows[0]["euler_characteristic"] is None
    expected = serial[serial["path"] == corpus[0]].iloc[0]
    assert rows[1]["error"] is None
    assert rows[1]["euler_characteristic"] == expected["euler_characteristic"]


def test_a_scanning_process_that_dies_is_a_row(corpus: list[str], slow_file: str) -> None:
    sandbox = Sandbox()
    sandbox.scan(corpus[0], {}, 60)  # started
    pid = sandbox.pid
    assert pid is not None
    killer = threading.Timer(0.3, os.kill, (pid, signal.SIGKILL))
    killer.start()
    row = sandbox.scan(slow_file, {}, 60)
    killer.join()
    assert row["error"] == "the scanning process died (killed by signal 9 (SIGKILL))"
    assert row["path"] == slow_file
    after = sandbox.scan(corpus[0], {}, 60)  # a fresh child takes over
    assert after["error"] is None and sandbox.pid != pid
    sandbox.close()
