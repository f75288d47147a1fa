"""Shared fixtures: the repository's meshes and the surfkit CLI built by scripts/test.sh."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

import surfkit

REPO = Path(__file__).resolve().parents[2]
MESHES = REPO / "fixtures" / "meshes"


def mesh_files() -> list[Path]:
    """Every fixture mesh (OBJ, PLY, OFF) of fixtures/meshes."""
    return sorted(p for p in MESHES.iterdir() if p.suffix in (".obj", ".ply", ".off"))


def polygons(mesh: surfkit.Mesh) -> list[list[int]]:
    """The corners of every face of `mesh`, as lists."""
    idx, off = mesh.face_indices, mesh.face_offsets
    return [idx[off[f] : off[f + 1]].tolist() for f in range(mesh.face_count)]


@pytest.fixture(scope="session")
def cli() -> Path:
    """The release binary the Rust suites built (SURFKIT_BIN overrides it)."""
    path = Path(os.environ.get("SURFKIT_BIN", REPO / "target" / "release" / "surfkit"))
    if not path.exists():
        pytest.fail(f"{path} is missing: build it with cargo build --release first")
    return path
