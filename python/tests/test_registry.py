"""EatRegistry, the accompanying test of a modelling script, against the CLI's report."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import pytest
from conftest import mesh_files, polygons

import surfkit


@pytest.mark.parametrize("path", mesh_files(), ids=lambda p: p.name)
def test_facet_by_facet_gives_the_cli_counts(path: Path, cli: Path):
    out = subprocess.run([cli, "eat", path, "--json"], check=True, capture_output=True, text=True)
    counts = json.loads(out.stdout)["report"]["counts"]
    mesh = surfkit.read_mesh(path)
    registry = surfkit.EatRegistry(vertex_count=mesh.vertex_count)
    for f, corners in enumerate(polygons(mesh)):
        assert registry.add_facet(corners)["facet"] == f
    s = registry.statistics()
    assert (s["vertices"], s["edges"], s["facets"]) == (
        counts["vertices_referenced"],
        counts["edges"],
        counts["facets"],
    )
    assert s["euler_characteristic"] == counts["euler_characteristic"]
    point = registry.checkpoint(counts["euler_characteristic"])
    assert point["verified"] and point["since_last_verified"] == []


def test_a_forgotten_facet_fails_the_test_point_and_names_the_stage():
    """A tetrahedron drawn in two stages whose second stage forgets a face: the test point
    after it fails (χ 1, not 2) and lists the two facets added since the last verified
    point with their counters (the paper's Fig. 14 information)."""
    registry = surfkit.EatRegistry()
    first = registry.add_facet([0, 1, 2], input_id=10)
    assert first == {"facet": 0, "fc": 1, "vertex_slots": [0, 1, 2], "edge_slots": [0, 1, 2]}
    assert registry.checkpoint(1)["verified"]
    registry.add_facet([0, 3, 1], input_id=11)
    registry.add_facet([1, 3, 2], input_id=12)
    point = registry.checkpoint(2)
    assert not point["verified"]
    assert point["statistics"]["euler_characteristic"] == 1
    assert point["last_verified_facets"] == 1
    assert [f["input_id"] for f in point["since_last_verified"]] == [11, 12]
    registry.add_facet([0, 2, 3], input_id=13)
    assert registry.checkpoint(2)["verified"]


def test_vertex_ids_are_bounded():
    registry = surfkit.EatRegistry(vertex_count=4)
    with pytest.raises(surfkit.InvalidInput, match="vertex 4, but the registry is for vertex"):
        registry.add_facet([0, 1, 4])
    with pytest.raises(surfkit.InvalidInput, match="vertex -1"):
        registry.add_facet([0, -1, 2])
    with pytest.raises(surfkit.InvalidInput, match="no corners"):
        registry.add_facet([])
    registry.vertex_count = 5
    assert registry.add_facet([0, 1, 4])["facet"] == 0
    with pytest.raises(surfkit.InvalidInput, match="32-bit"):
        surfkit.EatRegistry(vertex_count=2**33)
