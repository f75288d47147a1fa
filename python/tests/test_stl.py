"""STL, which has no vertex indices, read by surfkit (corners welded by their 32-bit
coordinates) against pymeshlab's reading of the same file: every fixture mesh written as
binary and as ASCII STL by pymeshlab, then read by both."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pymeshlab
import pytest
from conftest import mesh_files
from test_eat import fan_triangles

import surfkit


@pytest.mark.parametrize("binary", [True, False], ids=["binary", "ascii"])
@pytest.mark.parametrize("path", mesh_files(), ids=lambda p: p.name)
def test_surfkit_welds_stl_as_meshlab_does(path: Path, binary: bool, tmp_path: Path) -> None:
    polygons = surfkit.read_mesh(path)
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(polygons.vertices, fan_triangles(polygons).astype(np.int32)))
    stl = tmp_path / "mesh.stl"
    ms.save_current_mesh(str(stl), binary=binary)
    ms.load_new_mesh(str(stl))
    theirs = ms.current_mesh()
    ours = surfkit.read_mesh(stl)
    # Both number the welded corners by first appearance and keep the facets in order.
    assert ours.face_offsets.tolist() == list(range(0, 3 * theirs.face_number() + 1, 3))
    np.testing.assert_array_equal(
        ours.face_indices.reshape(-1, 3), theirs.face_matrix().astype(np.uint32)
    )
    # MeshLab holds floats; surfkit the digits of an ASCII file, the floats of a binary one.
    ours_as_float = ours.vertices.astype(np.float32)
    np.testing.assert_array_equal(ours_as_float, theirs.vertex_matrix().astype(np.float32))
    if binary:
        np.testing.assert_array_equal(ours.vertices, ours_as_float.astype(np.float64))
    ours_counts = surfkit.eat(ours, check_fixes=False)
    theirs_counts = ms.get_topological_measures()
    for key in ("vertices_number", "edges_number", "faces_number", "boundary_edges"):
        assert ours_counts[key] == theirs_counts[key], key
