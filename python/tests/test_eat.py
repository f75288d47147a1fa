"""surfkit.eat against the CLI's JSON, pymeshlab's topological measures and trimesh, on
every fixture mesh; the differences from pymeshlab are the documented ones."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import numpy as np
import pymeshlab
import pytest
import trimesh
from conftest import MESHES, mesh_files

import surfkit


def fan_triangles(mesh: surfkit.Mesh) -> np.ndarray:
    """Every polygon as a fan of triangles from its first corner (MeshLab's meshes are
    triangles: both tools then see the same faces)."""
    idx, off = mesh.face_indices, mesh.face_offsets
    tris = [
        [idx[off[f]], idx[off[f] + k], idx[off[f] + k + 1]]
        for f in range(len(off) - 1)
        for k in range(1, int(off[f + 1] - off[f]) - 1)
    ]
    return np.asarray(tris, dtype=np.int64).reshape(-1, 3)


@pytest.mark.parametrize("path", mesh_files(), ids=lambda p: p.name)
def test_the_report_is_the_cli_report(path: Path, cli: Path) -> None:
    out = subprocess.run([cli, "eat", path, "--json"], check=False, capture_output=True, text=True)
    assert out.returncode in (0, 3), out.stderr
    expected = json.loads(out.stdout)["report"]
    got = surfkit.eat(surfkit.read_mesh(path))
    assert got["report"] == expected
    assert got["euler_characteristic"] == expected["counts"]["euler_characteristic"]
    assert [f["kind"] for f in got["flaws"]] == [f["kind"] for f in expected["flaws"]]
    for f, e in zip(got["flaws"], expected["flaws"], strict=True):
        assert f["vertices"].dtype == np.uint32
        assert f["vertices"].tolist() == e["vertices"]
        assert f["faces"].tolist() == e["faces"]


@pytest.mark.parametrize("path", mesh_files(), ids=lambda p: p.name)
def test_pymeshlab_agrees_where_its_definitions_do(path: Path) -> None:
    polygons = surfkit.read_mesh(path)
    triangles = fan_triangles(polygons)
    ours = surfkit.eat(surfkit.Mesh(polygons.vertices, triangles), check_fixes=False)
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(polygons.vertices, triangles.astype(np.int32)))
    theirs = ms.get_topological_measures()
    assert len(theirs) == 13
    for key in theirs:
        if key == "number_holes" and not theirs["is_mesh_two_manifold"]:
            # MeshLab does not count holes on a non-manifold mesh: -1.
            assert theirs[key] == -1
        elif key == "non_two_manifold_edges" and ours["report"]["counts"]["duplicated_facets"]:
            # MeshLab walks a non-manifold edge's faces through its face-face adjacency,
            # which a duplicated facet breaks: it then counts every (edge, face) pair.
            pairs = sum(len(f["faces"]) for f in ours["flaws"] if f["kind"] == "non_manifold_edge")
            assert theirs[key] == pairs, key
        else:
            assert ours[key] == theirs[key], key


@pytest.mark.parametrize("path", mesh_files(), ids=lambda p: p.name)
def test_trimesh_agrees_on_euler_number_and_watertightness(path: Path) -> None:
    polygons = surfkit.read_mesh(path)
    triangles = fan_triangles(polygons)
    ours = surfkit.eat(surfkit.Mesh(polygons.vertices, triangles), check_fixes=False)
    # process=False: trimesh keeps the vertices as given (no merging by position).
    t = trimesh.Trimesh(polygons.vertices, triangles, process=False)
    # Both count the referenced vertices only.
    assert t.euler_number == ours["euler_characteristic"]
    assert ours["vertices_referenced"] + ours["unreferenced_vertices"] == len(polygons.vertices)
    watertight = ours["boundary_edges"] == 0 and ours["non_two_manifold_edges"] == 0
    assert t.is_watertight == watertight


def test_test_points_and_target() -> None:
    torus = surfkit.read_mesh(MESHES / "catmark_torus.obj")
    assert surfkit.eat(torus, target=0)["verified"]
    failed = surfkit.eat(torus, target=2)
    assert not failed["verified"]
    assert failed["test_points"] == [
        {
            "label": "whole mesh",
            "facets": 32,
            "expected_euler_characteristic": 2,
            "euler_characteristic": 0,
            "verified": False,
        }
    ]
    staged = surfkit.eat(torus, test_points=[(16, 0), (32, 0)])
    assert len(staged["test_points"]) == 2
    with pytest.raises(surfkit.InvalidInput, match="not both"):
        surfkit.eat(torus, target=0, test_points=[(32, 0)])


def prefix_euler_characteristic(mesh: surfkit.Mesh, facets: int) -> int:
    """V − E + F of the first `facets` faces, counted here (vertices and undirected edges
    they use)."""
    idx, off = mesh.face_indices, mesh.face_offsets
    faces = [list(idx[off[f] : off[f + 1]]) for f in range(facets)]
    vertices = {v for face in faces for v in face}
    edges = {
        frozenset((face[k], face[(k + 1) % len(face)])) for face in faces for k in range(len(face))
    }
    return len(vertices) - len(edges) + facets


def test_test_points_short_of_the_face_count_are_checked_where_given() -> None:
    torus = surfkit.read_mesh(MESHES / "catmark_torus.obj")
    chi = {f: prefix_euler_characteristic(torus, f) for f in (4, 8)}
    one = surfkit.eat(torus, test_points=[(4, chi[4])])
    assert [(p["facets"], p["expected_euler_characteristic"]) for p in one["test_points"]] == [
        (4, chi[4])
    ]
    assert one["test_points"][0]["euler_characteristic"] == chi[4] and one["verified"]
    wrong = surfkit.eat(torus, test_points=[(4, chi[4] + 1)])
    assert not wrong["verified"] and wrong["test_points"][0]["facets"] == 4
    two = surfkit.eat(torus, test_points=[(4, chi[4]), (8, chi[8])])
    assert [p["facets"] for p in two["test_points"]] == [4, 8] and two["verified"]
    assert two["euler_characteristic"] == 0


def test_every_form_of_faces_gives_the_same_mesh() -> None:
    v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0]], dtype=np.float64)
    quads = surfkit.Mesh(v, np.array([[0, 1, 2, 3]]))
    lists = surfkit.Mesh(v, [[0, 1, 2, 3], [1, 4, 2]])
    flat = surfkit.Mesh(
        v, (np.array([0, 1, 2, 3, 1, 4, 2], np.uint32), np.array([0, 4, 7], np.uint32))
    )
    assert quads.face_offsets.tolist() == [0, 4]
    assert lists.face_indices.tolist() == flat.face_indices.tolist() == [0, 1, 2, 3, 1, 4, 2]
    assert lists.face_offsets.tolist() == flat.face_offsets.tolist() == [0, 4, 7]
    assert np.array_equal(lists.vertices, v)
    assert surfkit.eat(lists)["euler_characteristic"] == 5 - 6 + 2


def test_from_trimesh_and_pymeshlab() -> None:
    box = trimesh.creation.box()
    ours = surfkit.eat(surfkit.Mesh.from_trimesh(box))
    assert ours["genus"] == 0 and ours["euler_characteristic"] == 2
    pm = pymeshlab.Mesh(np.asarray(box.vertices), np.asarray(box.faces, dtype=np.int32))
    assert surfkit.eat(surfkit.Mesh.from_pymeshlab(pm))["faces_number"] == 12


@pytest.mark.parametrize(
    ("vertices", "faces", "message"),
    [
        (np.zeros((3, 2)), [[0, 1, 2]], r"shape \(n, 3\)"),
        (np.zeros((3, 3)), [[0, 1, 5]], "face 0 refers to vertex 5"),
        (
            np.array([[0, 0, np.nan], [1, 0, 0], [0, 1, 0]]),
            [[0, 1, 2]],
            "vertex 0 has a non-finite",
        ),
        (np.zeros((3, 3)), [[0, 1, -2]], "entry 2 is negative"),
        (np.zeros((3, 3)), np.array([[0, 1, 2.5]]), "must be integers"),
        (np.zeros((3, 3)), np.zeros((2, 2, 3), dtype=int), r"\(m, k\) array"),
        (np.array([["a", "b", "c"]]), [[0, 0, 0]], "must be numbers"),
        (np.zeros((3, 3)), [[0, 1, 2**40]], "beyond 32-bit"),
    ],
)
def test_bad_arrays_raise_invalid_input(vertices: object, faces: object, message: str) -> None:
    with pytest.raises(surfkit.InvalidInput, match=message):
        surfkit.Mesh(vertices, faces)


def test_an_empty_mesh_is_a_mesh() -> None:
    empty = surfkit.Mesh(np.zeros((0, 3)), [])
    measures = surfkit.eat(empty)
    assert measures["faces_number"] == 0 and measures["flaws"] == []


def test_options_are_checked() -> None:
    torus = surfkit.read_mesh(MESHES / "catmark_torus.obj")
    with pytest.raises(surfkit.InvalidInput, match="weld_tolerance"):
        surfkit.eat(torus, weld_tolerance=float("nan"))


def test_files_round_trip_and_bad_files_name_the_line(tmp_path: Path) -> None:
    torus = surfkit.read_mesh(MESHES / "catmark_torus.obj")
    out = tmp_path / "torus.ply"
    torus.write(out)
    back = surfkit.read_mesh(out)
    assert np.array_equal(back.vertices, torus.vertices)
    assert back.face_indices.tolist() == torus.face_indices.tolist()
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
    with pytest.raises(surfkit.InvalidInput, match="bad.obj"):
        surfkit.read_mesh(bad)
    with pytest.raises(surfkit.SurfkitError, match="missing.obj"):
        surfkit.read_mesh(tmp_path / "missing.obj")


def test_degenerate_facets_are_read_and_counted_as_the_cli_counts(tmp_path: Path, cli: Path):
    """read_mesh keeps a face that repeats a vertex (and one of 2 corners), as the CLI and
    the C door read files: eat counts them as flaws instead of refusing the file."""
    for name, faces in [("repeat.obj", "f 1 2 3\nf 1 2 1\n"), ("two.obj", "f 1 2 3\nf 3 4\n")]:
        path = tmp_path / name
        path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n" + faces)
        got = surfkit.eat(surfkit.read_mesh(path))
        out = subprocess.run(
            [cli, "eat", path, "--json"], check=False, capture_output=True, text=True
        )
        assert out.returncode in (0, 3), out.stderr
        expected = json.loads(out.stdout)["report"]
        assert expected["counts"]["degenerate_facets"] == 1
        assert got["report"]["counts"]["degenerate_facets"] == 1
        assert got["report"] == expected
        assert "degenerate_facet" in [f["kind"] for f in got["flaws"]]
