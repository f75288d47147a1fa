"""EatRegistry, the accompanying test of a modelling script, against the CLI's report."""

from __future__ import annotations

import json
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
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
    for bad in (-5, 2**64):
        with pytest.raises(surfkit.InvalidInput, match=f"vertex_count {bad} is out of range"):
            surfkit.EatRegistry(bad)
        with pytest.raises(surfkit.InvalidInput, match=f"vertex_count {bad} is out of range"):
            registry.vertex_count = bad


def test_a_far_vertex_id_is_refused_within_the_memory_limit():
    """The registry keeps an item per vertex id up to the largest (20 bytes each): an id
    near 2³² (80 GiB of items) raises ResourceLimit naming it under a 64 MiB limit, and
    registers nothing, instead of aborting the interpreter."""
    registry = surfkit.EatRegistry(2**32 - 1)
    surfkit.set_max_memory(64 << 20)
    try:
        with pytest.raises(surfkit.ResourceLimit, match=r"vertex id 4294967294 .*80 GiB"):
            registry.add_facet([0, 1, 2**32 - 2])
        assert registry.statistics()["facets"] == 0
        assert registry.add_facet([0, 1, 2])["facet"] == 0
    finally:
        surfkit.set_max_memory(None)
    assert registry.statistics() == {
        "vertices": 3,
        "edges": 3,
        "facets": 1,
        "euler_characteristic": 1,
    }


def test_a_registry_is_used_and_dropped_on_other_threads(monkeypatch: pytest.MonkeyPatch):
    unraisable = []
    monkeypatch.setattr(sys, "unraisablehook", unraisable.append)
    registry = surfkit.EatRegistry()
    with ThreadPoolExecutor(2) as pool:
        assert pool.submit(registry.add_facet, [0, 1, 2]).result()["facet"] == 0
        assert pool.submit(registry.checkpoint, 1).result()["verified"]
        made = pool.submit(surfkit.EatRegistry).result()
        made.add_facet([0, 1, 2])
        holder = [registry]
        pool.submit(holder.clear).result()  # the last reference goes on the worker
    del registry
    assert made.statistics()["facets"] == 1
    del made
    assert unraisable == []
