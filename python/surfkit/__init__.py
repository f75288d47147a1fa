"""surfkit from Python: the Euler Accompanying Test on numpy meshes.

``surfkit.Mesh(vertices, faces)`` takes vertices as an (n, 3) array and faces as an (m, k)
integer array, a list of polygons of any arity, or an ``(indices, offsets)`` pair;
``surfkit.eat(mesh)`` returns a dict with pymeshlab's ``get_topological_measures`` keys
(surfkit's values, see README "Python") plus the Euler characteristic, the components, the
test points and every flaw with its vertices and faces as numpy arrays. Errors raise
``surfkit.SurfkitError`` subclasses carrying the message of the Rust library; the GIL is
released during the work.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from typing import Any, Self

import numpy as np

from surfkit._surfkit import (
    InvalidInput,
    ResourceLimit,
    SolverError,
    SurfkitError,
    TopologyError,
    __version__,
    eat_json,
    read_mesh,
)
from surfkit._surfkit import Mesh as _NativeMesh

__all__ = [
    "InvalidInput",
    "Mesh",
    "ResourceLimit",
    "SolverError",
    "SurfkitError",
    "TopologyError",
    "__version__",
    "eat",
    "read_mesh",
]

Faces = np.ndarray | Sequence[Sequence[int]] | tuple[np.ndarray, np.ndarray]


def _faces_to_arrays(faces: Faces) -> tuple[np.ndarray, np.ndarray]:
    """(indices, offsets) as uint32 from any of the accepted face forms."""
    if (
        isinstance(faces, tuple)
        and len(faces) == 2
        and all(isinstance(a, np.ndarray) and a.ndim == 1 for a in faces)
    ):
        indices, offsets = faces
        return _ids(indices, "face indices"), _ids(offsets, "face offsets")
    if isinstance(faces, np.ndarray):
        if faces.ndim != 2:
            raise InvalidInput(f"faces must be an (m, k) array, not of shape {faces.shape}")
        m, k = faces.shape
        return (
            _ids(faces.reshape(-1), "faces"),
            np.arange(0, m * k + 1, k, dtype=np.uint32) if k > 0 else np.zeros(m + 1, np.uint32),
        )
    lengths = [len(f) for f in faces]
    offsets = np.zeros(len(lengths) + 1, dtype=np.int64)
    np.cumsum(lengths, out=offsets[1:])
    flat = [i for f in faces for i in f]
    return _ids(np.asarray(flat, dtype=np.int64), "faces"), _ids(offsets, "face offsets")


def _ids(a: np.ndarray, what: str) -> np.ndarray:
    """Non-negative integer ids below 2³² as uint32, or InvalidInput naming the entry."""
    a = np.asarray(a)
    if a.size == 0:
        return a.astype(np.uint32)
    if not np.issubdtype(a.dtype, np.integer):
        raise InvalidInput(f"{what} must be integers, not {a.dtype}")
    low, high = int(a.min()), int(a.max())
    if low < 0:
        raise InvalidInput(f"{what}: entry {int(np.argmin(a))} is negative ({low})")
    if high > np.iinfo(np.uint32).max:
        raise InvalidInput(f"{what}: entry {int(np.argmax(a))} ({high}) is beyond 32-bit ids")
    return a.astype(np.uint32, copy=False)


class Mesh(_NativeMesh):
    """A polygon mesh: ``Mesh(vertices, faces)`` (see the module docstring)."""

    def __new__(cls, vertices: Any, faces: Faces) -> Self:
        v = np.asarray(vertices)
        if v.ndim != 2 or v.shape[1] != 3:
            raise InvalidInput(f"vertices must have shape (n, 3), not {v.shape}")
        if not (np.issubdtype(v.dtype, np.floating) or np.issubdtype(v.dtype, np.integer)):
            raise InvalidInput(f"vertices must be numbers, not {v.dtype}")
        indices, offsets = _faces_to_arrays(faces)
        return super().__new__(cls, np.ascontiguousarray(v, dtype=np.float64), indices, offsets)

    @classmethod
    def from_trimesh(cls, mesh: Any) -> Mesh:
        """A mesh from a ``trimesh.Trimesh`` (its vertices and triangles, as trimesh holds them)."""
        return cls(np.asarray(mesh.vertices), np.asarray(mesh.faces))

    @classmethod
    def from_pymeshlab(cls, mesh: Any) -> Mesh:
        """A mesh from a ``pymeshlab.Mesh`` (its vertex and face matrices)."""
        return cls(mesh.vertex_matrix(), mesh.face_matrix())


def eat(
    mesh: _NativeMesh,
    *,
    test_points: Sequence[tuple[int, int]] | None = None,
    target: int | None = None,
    weld_tolerance: float = 0.0,
    crack_tolerance: float = 0.01,
    halfedge: bool = True,
    check_fixes: bool = True,
) -> dict[str, Any]:
    """The Euler Accompanying Test, as ``surfkit eat --json`` runs it.

    ``test_points``: (facet count, expected χ) pairs; ``target``: the whole mesh's expected
    χ. The dict has pymeshlab's ``get_topological_measures`` keys with surfkit's values
    (``vertices_number`` counts every vertex of the mesh, ``number_holes`` is the number of
    boundary loops, ``genus`` is -1 unless every component is a closed orientable manifold),
    plus ``euler_characteristic``, ``components``, ``test_points``, ``verified``, ``flaws``
    (each with ``vertices`` and ``faces`` as uint32 arrays) and ``report`` (the CLI's JSON).
    """
    if test_points is not None and target is not None:
        raise InvalidInput("give test_points or target, not both")
    facets: list[int] = []
    expected: list[int] = []
    if test_points is not None:
        for f, chi in test_points:
            facets.append(int(f))
            expected.append(int(chi))
    elif target is not None:
        expected.append(int(target))
    report = json.loads(
        eat_json(
            mesh,
            weld_tolerance=float(weld_tolerance),
            crack_tolerance=float(crack_tolerance),
            halfedge=bool(halfedge),
            check_fixes=bool(check_fixes),
            test_point_facets=facets,
            expected_chi=expected,
        )
    )
    return _measures(mesh, report)


def _faces_using(mesh: _NativeMesh, vertices: set[int]) -> int:
    """The number of faces with a corner at one of `vertices`."""
    if not vertices:
        return 0
    offsets = mesh.face_offsets.astype(np.int64)
    face_of_corner = np.repeat(np.arange(len(offsets) - 1), np.diff(offsets))
    hit = np.isin(mesh.face_indices, np.fromiter(vertices, dtype=np.uint32))
    return int(np.unique(face_of_corner[hit]).size)


def _measures(mesh: _NativeMesh, report: dict[str, Any]) -> dict[str, Any]:
    """pymeshlab's keys (surfkit's values) and surfkit's own, from the report's JSON."""
    c = report["counts"]
    flaws = [
        {
            **f,
            "vertices": np.asarray(f["vertices"], dtype=np.uint32),
            "faces": np.asarray(f["faces"], dtype=np.uint32),
        }
        for f in report["flaws"]
    ]

    def incident(kind: str, key: str) -> int:
        return len({int(x) for f in flaws if f["kind"] == kind for x in f[key]})

    manifold = c["non_manifold_edges"] == 0 and c["non_manifold_vertices"] == 0
    return {
        "vertices_number": c["vertices_in_file"],
        "edges_number": c["edges"],
        "faces_number": c["facets"],
        "boundary_edges": c["boundary_edges"],
        "connected_components_number": c["components"],
        "is_mesh_two_manifold": manifold,
        "non_two_manifold_edges": c["non_manifold_edges"],
        "non_two_manifold_vertices": c["non_manifold_vertices"],
        "incident_faces_on_non_two_manifold_edges": incident("non_manifold_edge", "faces"),
        "incident_faces_on_non_two_manifold_vertices": _faces_using(
            mesh,
            {int(v) for f in flaws if f["kind"] == "non_manifold_vertex" for v in f["vertices"]},
        ),
        "unreferenced_vertices": c["unreferenced_vertices"],
        "number_holes": c["boundary_loops"],
        "genus": c["genus"] if c["genus"] is not None else -1,
        "euler_characteristic": c["euler_characteristic"],
        "vertices_referenced": c["vertices_referenced"],
        "components": report["components"],
        "test_points": [
            {
                "label": point["label"],
                "facets": point["facets"],
                "expected_euler_characteristic": point["expected"],
                "euler_characteristic": check["statistics"]["euler_characteristic"],
                "verified": check["verified"],
            }
            for point, check in report["checkpoints"]
        ],
        "verified": report["first_failure"] is None,
        "flaws": flaws,
        "report": report,
    }
