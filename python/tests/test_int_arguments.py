"""Every int parameter of the Python API, given an int outside what it takes (negative,
past its Rust type, past its documented range), raises surfkit.InvalidInput naming the
argument and the range it takes — not PyO3's bare OverflowError."""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from conftest import MESHES

import surfkit

U32 = 2**32 - 1
U64 = 2**64 - 1
I64 = (-(2**63), 2**63 - 1)


def _torus() -> surfkit.Mesh:
    return surfkit.read_mesh(MESHES / "catmark_torus.obj")


def _data() -> tuple[np.ndarray, np.ndarray]:
    """A plane z = u + v sampled on a 6 × 6 grid of [0, 1]²."""
    u, v = np.meshgrid(np.linspace(0, 1, 6), np.linspace(0, 1, 6))
    uv = np.stack([u.ravel(), v.ravel()], axis=1)
    return uv, np.stack([uv[:, 0], uv[:, 1], uv[:, 0] + uv[:, 1]], axis=1)


def _registry_add(input_id: int) -> Any:
    return surfkit.EatRegistry().add_facet([0, 1, 2], input_id)


def _limit_surface(**options: Any) -> surfkit.LimitSurface:
    return surfkit.LimitSurface(_torus(), **options)


def _fill(**options: Any) -> surfkit.Spline:
    uv, xyz = _data()
    return surfkit.fill(uv, xyz, **options)


def _shape_fill(**options: Any) -> surfkit.Spline:
    """A BFS C¹ fill of an elliptic hole kept positive (the shape options' calls)."""
    return _fill(
        hole=[("ellipse", (0.5, 0.5, 1, 1, 0.04))], space="bfs-c1", shape=["positive"], **options
    )


def _fit_parallel(**options: Any) -> surfkit.Spline:
    uv, xyz = _data()
    normals = np.tile([0.0, 0.0, 1.0], (len(uv), 1))
    return surfkit.fit_parallel(uv, xyz, uv, normals, tau=1.0, **options)


# (call with the bad value, the argument's name in the message, lowest, highest, bad values)
CASES: list[tuple[str, Callable[[int], Any], str, int, int, tuple[int, ...]]] = [
    (
        "eat test point facets",
        lambda x: surfkit.eat(_torus(), test_points=[(x, 0)]),
        "test_points[0] facet count",
        0,
        U64,
        (-1, 2**64),
    ),
    (
        "eat test point chi",
        lambda x: surfkit.eat(_torus(), test_points=[(4, x)]),
        "test_points[0] expected χ",
        *I64,
        (2**63, -(2**63) - 1),
    ),
    ("eat target", lambda x: surfkit.eat(_torus(), target=x), "target", *I64, (2**63, -(2**70))),
    ("registry input_id", _registry_add, "input_id", 0, U32, (-1, 2**32, 2**64)),
    (
        "registry checkpoint",
        lambda x: surfkit.EatRegistry().checkpoint(x),
        "expected_chi",
        *I64,
        (2**63, -(2**63) - 1),
    ),
    (
        "crease vertex",
        lambda x: surfkit.subdivide(_torus(), 1, creases=[(0, x, 2.0)]),
        "crease 0: vertex",
        0,
        U32,
        (-1, 2**32, 2**64),
    ),
    (
        "corner vertex",
        lambda x: surfkit.subdivide(_torus(), 1, corners=[(x, 2.0)]),
        "corner 0: vertex",
        0,
        U32,
        (-1, 2**64),
    ),
    (
        "limit surface crease vertex",
        lambda x: _limit_surface(creases=[(x, 1, 2.0)]),
        "crease 0: vertex",
        0,
        U32,
        (-1, 2**64),
    ),
    (
        "max_isolation",
        lambda x: _limit_surface(max_isolation=x),
        "max_isolation",
        0,
        U32,
        (-1, 2**32),
    ),
    (
        "limit max_isolation",
        lambda x: surfkit.limit(_torus(), [0], 0.5, 0.5, max_isolation=x),
        "max_isolation",
        0,
        U32,
        (-1, 2**64),
    ),
    (
        "ptex_faces",
        lambda x: _limit_surface().ptex_faces(x),
        "face",
        0,
        U64,
        (-1, 2**64),
    ),
    (
        "evaluate derivatives",
        lambda x: _limit_surface().evaluate([0], 0.5, 0.5, derivatives=x, curvature=False),
        "derivatives",
        0,
        3,
        (-1, 4, 2**64),
    ),
    (
        "fair boundary_rings",
        lambda x: surfkit.fair(_torus(), boundary_rings=x),
        "boundary_rings",
        0,
        U32,
        (-1, 2**32),
    ),
    (
        "fair max_refinements",
        lambda x: surfkit.fair(_torus(), max_refinements=x),
        "max_refinements",
        0,
        U32,
        (-1, 2**64),
    ),
    (
        "fair isolation",
        lambda x: surfkit.fair(_torus(), isolation=x),
        "isolation",
        0,
        U32,
        (-1, 2**32),
    ),
    ("fair nodes", lambda x: surfkit.fair(_torus(), nodes=x), "nodes", 0, U64, (-1, 2**64)),
    ("fill cells u", lambda x: _fill(cells=(x, 4)), "cells[0]", 0, U64, (-1, 2**64)),
    ("fit cells v", lambda x: surfkit.fit(*_data(), cells=(4, x)), "cells[1]", 0, U64, (-5,)),
    (
        "fill shape_component",
        lambda x: _shape_fill(shape_component=x),
        "shape_component",
        0,
        2,
        (-1, 3, 2**64),
    ),
    (
        "fill shape_lattice",
        lambda x: _shape_fill(shape_lattice=x),
        "shape_lattice",
        0,
        U64,
        (-1, 2**64),
    ),
    (
        "spline derivative order",
        lambda x: _fill(cells=(4, 4))._native.derivative(np.array([[0.5, 0.5]]), x, 0),
        "u order",
        0,
        U64,
        (-1, 2**64),
    ),
    ("fit_parallel cells", lambda x: _fit_parallel(cells=(3, x)), "cells[1]", 0, U64, (-1,)),
    ("fit_parallel m", lambda x: _fit_parallel(m=x), "m", 0, U64, (-3, 2**64)),
    (
        "set_max_memory",
        surfkit.set_max_memory,
        "size",
        1 << 20,
        U64,
        (-1, 1000, 2**64),
    ),
]


@pytest.mark.parametrize(
    ("call", "name", "low", "high", "bad"),
    [pytest.param(*case[1:], id=case[0]) for case in CASES],
)
def test_an_int_out_of_range_is_invalid_input_naming_the_argument(
    call: Callable[[int], Any], name: str, low: int, high: int, bad: tuple[int, ...]
) -> None:
    limit = surfkit.max_memory()
    for value in bad:
        expected = f"{name} {value} is out of range: it must be an integer from {low} to {high}"
        with pytest.raises(surfkit.InvalidInput, match=re.escape(expected)):
            call(value)
    assert surfkit.max_memory() == limit


@pytest.mark.parametrize("vertex", [-1, 3, 2**64])
def test_a_registry_corner_out_of_range_names_the_facet_and_the_bound(vertex: int) -> None:
    registry = surfkit.EatRegistry(vertex_count=3)
    registry.add_facet([0, 1, 2])
    expected = (
        f"facet 7 refers to vertex {vertex}, but the registry is for vertex ids 0..3 "
        "(set vertex_count to raise it)"
    )
    with pytest.raises(surfkit.InvalidInput, match=re.escape(expected)):
        registry.add_facet([0, vertex, 2], input_id=7)
    assert registry.statistics()["facets"] == 1


def test_ints_within_range_still_work() -> None:
    torus = _torus()
    staged = surfkit.eat(torus, test_points=[(16, 0), (32, 0)])["test_points"]
    assert [point["facets"] for point in staged] == [16, 32]
    assert surfkit.eat(torus, target=0)["verified"]
    registry = surfkit.EatRegistry()
    assert registry.add_facet([0, 1, 2], U32)["facet"] == 0
    assert registry.checkpoint(1)["verified"]
    surface = surfkit.LimitSurface(torus, max_isolation=2)
    assert surface.ptex_faces(3) == (3, 1)
    assert set(surface.evaluate([0], 0.5, 0.5, derivatives=3, curvature=False)) >= {"duuu"}
    centre = np.array([[0.5, 0.5]])
    spline = _fill(cells=(4, 4))._native
    assert spline.derivative(centre, 1, 0)[0] == pytest.approx([1, 0, 1], abs=1e-8)
    with pytest.raises(surfkit.InvalidInput, match="above the spline's degree"):
        spline.derivative(centre, 0, 2**40)
    fine = surfkit.subdivide(torus, 1, creases=[(0, 1, 2.0)], corners=[(2, 3.0)])
    assert fine.face_count == 4 * torus.face_count
