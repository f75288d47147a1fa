"""surfkit from Python: the quality of surface models on numpy arrays.

``surfkit.Mesh(vertices, faces)`` takes vertices as an (n, 3) array and faces as an (m, k)
integer array, a list of polygons of any arity, or an ``(indices, offsets)`` pair.

- ``surfkit.eat(mesh)``: the Euler Accompanying Test, a dict with pymeshlab's
  ``get_topological_measures`` keys (surfkit's values, see README "Use from Python") plus
  the Euler characteristic, the components, the test points and every flaw with its
  vertices and faces as numpy arrays; ``surfkit.EatRegistry`` for modelling scripts that
  add facets one by one with test points.
- ``surfkit.subdivide`` (Catmull–Clark through OpenSubdiv), ``surfkit.limit`` and
  ``surfkit.LimitSurface`` (positions, derivatives, normals and curvatures of the limit
  surface), ``surfkit.fair`` (Kiciak's shape optimization, with a per-iteration callback).
- ``surfkit.fit`` / ``surfkit.fill`` (Kouibia & Pasadas 2022 and 2024: smoothing splines,
  generalized offsets, hole filling, shape-preserving filling) and ``surfkit.fit_parallel``
  (2004: parallelism conditions), each a ``Spline`` to evaluate.

Errors raise ``surfkit.SurfkitError`` subclasses carrying the message of the Rust library;
the GIL is released during the work. ``surfkit.set_max_memory`` sets the memory limit work
is checked against before it allocates (``ResourceLimit`` beyond it).
"""

from __future__ import annotations

import json
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from surfkit import _surfkit
from surfkit._arrays import ids, points
from surfkit._surfkit import (
    InvalidInput,
    Mesh,
    ResourceLimit,
    SolverError,
    SurfkitError,
    TopologyError,
    __version__,
    eat_json,
    max_memory,
    read_mesh,
)

__all__ = [
    "EatRegistry",
    "InvalidInput",
    "LimitSurface",
    "Mesh",
    "ResourceLimit",
    "SolverError",
    "Spline",
    "SurfkitError",
    "TopologyError",
    "__version__",
    "eat",
    "fair",
    "fill",
    "fit",
    "fit_parallel",
    "limit",
    "max_memory",
    "read_mesh",
    "set_max_memory",
    "subdivide",
]


def eat(
    mesh: Mesh,
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
    report = json.loads(
        eat_json(
            mesh,
            weld_tolerance=float(weld_tolerance),
            crack_tolerance=float(crack_tolerance),
            halfedge=bool(halfedge),
            check_fixes=bool(check_fixes),
            test_points=[(int(f), int(chi)) for f, chi in (test_points or [])],
            target=None if target is None else int(target),
        )
    )
    return _measures(mesh, report)


def _faces_using(mesh: Mesh, vertices: set[int]) -> int:
    """The number of faces with a corner at one of `vertices`."""
    if not vertices:
        return 0
    offsets = mesh.face_offsets.astype(np.int64)
    face_of_corner = np.repeat(np.arange(len(offsets) - 1), np.diff(offsets))
    hit = np.isin(mesh.face_indices, np.fromiter(vertices, dtype=np.uint32))
    return int(np.unique(face_of_corner[hit]).size)


def _measures(mesh: Mesh, report: dict[str, Any]) -> dict[str, Any]:
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


class EatRegistry:
    """The accompanying test of a model built facet by facet (Liu et al. 2020 §3.4).

    ``add_facet(ids)`` registers a facet as the modelling script makes it and returns the
    paper's per-facet output (``facet``, ``fc``, ``vertex_slots``, ``edge_slots``);
    ``checkpoint(expected_chi)`` compares χ so far with what the model should have: when it
    differs, ``since_last_verified`` lists the facets added since the last verified point
    with their counters — where to look. Vertex ids must stay below ``vertex_count``
    (default 2²⁴; an id is a size claim, raise it as the model grows); an id whose items
    (20 bytes per id up to the largest) would pass ``max_memory()`` raises
    ``ResourceLimit``. A registry may be used and dropped on any thread.
    """

    def __init__(self, vertex_count: int | None = None) -> None:
        self._native = _surfkit.EatRegistry(vertex_count)

    @property
    def vertex_count(self) -> int:
        return int(self._native.vertex_count)

    @vertex_count.setter
    def vertex_count(self, count: int) -> None:
        self._native.vertex_count = int(count)

    def add_facet(self, corners: Sequence[int] | np.ndarray, input_id: int | None = None) -> dict:
        """Registers one facet (EAT-TA); ``input_id`` names it in reports (default: its
        position)."""
        return self._native.add_facet([int(c) for c in corners], input_id)

    def statistics(self) -> dict[str, int]:
        """V, E, F and χ so far (EAT-SA): ``vertices``, ``edges``, ``facets``,
        ``euler_characteristic``."""
        return json.loads(self._native.statistics_json())

    def checkpoint(self, expected_chi: int) -> dict[str, Any]:
        """A test point: ``verified``, ``statistics``, ``last_verified_facets`` and, on a
        mismatch, ``since_last_verified`` (each facet's ``facet``, ``input_id``, ``fc``,
        ``vertices`` as (id, vc) and ``edges`` as (eID, ec))."""
        return json.loads(self._native.checkpoint_json(int(expected_chi)))


Creases = Sequence[tuple[int, int, float]] | None
Corners = Sequence[tuple[int, float]] | None


def _sharp(creases: Creases, corners: Corners) -> tuple[list, list]:
    crease_list = [(int(a), int(b), float(s)) for a, b, s in (creases or [])]
    corner_list = [(int(v), float(s)) for v, s in (corners or [])]
    return crease_list, corner_list


def subdivide(
    mesh: Mesh,
    levels: int,
    *,
    boundary: str = "edges-and-corners",
    creases: Creases = None,
    corners: Corners = None,
    creasing: str = "uniform",
) -> Mesh:
    """``levels`` uniform Catmull–Clark refinements through OpenSubdiv, as ``surfkit
    subdivide``: a quad mesh whose first vertices are the control vertices.

    ``boundary``: "edges-and-corners" (default), "edges-only" (as CGAL) or "none";
    ``creases``: (v0, v1, sharpness) per edge; ``corners``: (v, sharpness); sharpness ≥ 10
    is infinitely sharp; ``creasing``: "uniform" or "chaikin".
    """
    crease_list, corner_list = _sharp(creases, corners)
    return _surfkit.subdivide(
        mesh,
        int(levels),
        boundary=boundary,
        creases=crease_list,
        corners=corner_list,
        creasing=creasing,
    )


class LimitSurface:
    """The Catmull–Clark limit surface of a control mesh as bicubic patches (OpenSubdiv's
    feature-adaptive patch table, end caps after ``max_isolation`` levels).

    Points are (ptex face, u, v) with (u, v) in [0, 1]²: on an all-quad mesh the ptex face
    is the face id; an n-gon has n ptex faces, ``ptex_faces(face)`` gives (first, count).
    Build it once to evaluate many points, from any thread (``evaluate`` releases the GIL).
    """

    def __init__(
        self,
        mesh: Mesh,
        *,
        max_isolation: int = 4,
        boundary: str = "edges-and-corners",
        creases: Creases = None,
        corners: Corners = None,
        creasing: str = "uniform",
    ) -> None:
        crease_list, corner_list = _sharp(creases, corners)
        self._native = _surfkit.LimitSurface(
            mesh,
            max_isolation=int(max_isolation),
            boundary=boundary,
            creases=crease_list,
            corners=corner_list,
            creasing=creasing,
        )

    @property
    def ptex_face_count(self) -> int:
        return int(self._native.ptex_face_count)

    def ptex_faces(self, face: int) -> tuple[int, int]:
        """(first, count) of control face ``face``'s ptex faces."""
        return self._native.ptex_faces(int(face))

    def evaluate(
        self,
        faces: Any,
        u: Any,
        v: Any,
        *,
        derivatives: int = 2,
        curvature: bool | None = None,
    ) -> dict[str, np.ndarray]:
        """Positions (``position``, (n, 3)) and derivatives with respect to the ptex face's
        (u, v) up to order ``derivatives`` (``du``, ``dv``; ``duu``, ``duv``, ``dvv``;
        ``duuu`` … ``dvvv``); with ``curvature`` (default: when ``derivatives`` ≥ 2) also
        ``normal`` (S_u × S_v normalized), ``mean_curvature``, ``gaussian_curvature``,
        ``k1`` ≥ ``k2`` (positive where the surface bends towards the normal). A point
        without a normal (vanishing tangents) raises ``TopologyError`` naming it."""
        face_ids = ids(np.atleast_1d(faces), "faces")
        us = np.ascontiguousarray(np.atleast_1d(u), dtype=np.float64).reshape(-1)
        vs = np.ascontiguousarray(np.atleast_1d(v), dtype=np.float64).reshape(-1)
        if us.size == 1 and face_ids.size > 1:
            us = np.full(face_ids.size, us[0])
        if vs.size == 1 and face_ids.size > 1:
            vs = np.full(face_ids.size, vs[0])
        with_curvature = derivatives >= 2 if curvature is None else bool(curvature)
        return self._native.evaluate(
            face_ids, us, vs, derivatives=int(derivatives), curvature=with_curvature
        )


def limit(
    mesh: Mesh,
    face_ids: Any,
    u: Any,
    v: Any,
    *,
    derivatives: int = 2,
    curvature: bool | None = None,
    max_isolation: int = 4,
    boundary: str = "edges-and-corners",
    creases: Creases = None,
    corners: Corners = None,
    creasing: str = "uniform",
) -> dict[str, np.ndarray]:
    """The limit surface at points (ptex face, u, v): ``LimitSurface(mesh, ...).evaluate``
    in one call (build a ``LimitSurface`` to evaluate several batches)."""
    surface = LimitSurface(
        mesh,
        max_isolation=max_isolation,
        boundary=boundary,
        creases=creases,
        corners=corners,
        creasing=creasing,
    )
    return surface.evaluate(face_ids, u, v, derivatives=derivatives, curvature=curvature)


def fair(
    mesh: Mesh,
    *,
    fixed: Sequence[int] | np.ndarray | None = None,
    callback: Callable[[dict[str, Any]], bool | None] | None = None,
    boundary_rings: int | None = None,
    max_refinements: int | None = None,
    relative_gradient: float | None = None,
    max_iterations: int | None = None,
    surface: str | None = None,
    isolation: int | None = None,
    nodes: int | None = None,
    c_special: float | None = None,
    regularization: float | None = None,
    method: str | None = None,
    coarse_start: bool = False,
) -> tuple[Mesh, dict[str, Any]]:
    """Kiciak's shape optimization of a control mesh, as ``surfkit fair`` (options left at
    None keep its defaults). ``surface`` is ``"g2"`` (the default: the paper's
    curvature-continuous surface) or ``"catmull-clark"`` (``surfkit fair --surface``);
    ``report["surface"]`` names the one optimized. ``regularization`` is C in
    F = S + C·c·Q (``surfkit fair --regularization``). ``method`` is ``"auto"`` (the
    default: by size), ``"plain"`` or ``"multilevel"`` (``surfkit fair --method``);
    ``report["method"]`` names the one that ran. ``coarse_start=True`` starts the
    multilevel method from the optimum of the mesh the input un-subdivides to, refined
    (``surfkit fair --coarse-start``): faster on the junctions measured, but it may end in
    another local minimum; not used with ``fixed`` vertices. ``report["coarse_start"]``
    is that stage's report (``used``: whether the fine iteration started there), None when
    it did not run.

    Returns the optimized mesh (the input's topology and vertex order unless the method had
    to refine it, see ``report["refinements"]``) and the report, whose ``log`` lists every
    iteration (F, S, Q, ‖∇F‖, step kind). ``callback(info)`` runs after every iteration
    with the same fields; returning True stops the run (the positions reached are returned,
    ``report["newton"]["cancelled"]`` is set); an exception it raises stops the run and is
    raised here. A run that stops without converging is not an error: read
    ``report["newton"]["converged"]``, and ``report["newton"]["stalled"]`` for a run that
    stopped within twice ``report["newton"]["coordinate_floor"]``, the gradient norm that
    rounding the coordinates to the nearest doubles leaves, after choosing their rounding
    (which goes below it where it can).
    """
    fixed_ids = [] if fixed is None else [int(x) for x in ids(fixed, "fixed")]
    optimized, text = _surfkit.fair_json(
        mesh,
        fixed=fixed_ids,
        boundary_rings=boundary_rings,
        max_refinements=max_refinements,
        relative_gradient=relative_gradient,
        max_iterations=max_iterations,
        surface=surface,
        isolation=isolation,
        nodes=nodes,
        c_special=c_special,
        regularization=regularization,
        method=method,
        coarse_start=coarse_start,
        callback=callback,
    )
    report = json.loads(text)
    stages = [report["warm_start"]] if report.get("warm_start") else []
    stages.append(report["newton"])
    report["log"] = [it for stage in stages for it in stage["iterations"]]
    return optimized, report


def set_max_memory(size: int | str | None) -> None:
    """Sets the memory limit of this process's surfkit calls, as ``surfkit fair
    --max-memory`` and the C door's ``surfkit_set_max_memory``: bytes (at least 1 MiB), a
    size such as ``"512M"`` or ``"12G"`` (binary units), or None for the default, half of
    the machine's memory. Work whose planned size passes it (a fairing problem's solver, a
    subdivision's levels, an ``EatRegistry``'s vertex ids) raises ``ResourceLimit``, naming
    its size and what fits, before it allocates. Calls already running keep their limit."""
    _surfkit.set_max_memory(size)


class Spline:
    """A solved spline surface (u, v) → (x, y, z) on the data's parameter rectangle."""

    def __init__(self, native: Any) -> None:
        self._native = native
        self.report: dict[str, Any] = json.loads(native.report_json())

    def evaluate(self, u: Any, v: Any, derivatives: int = 0) -> Any:
        """σ at (u, v) (scalars or arrays of one shape): with ``derivatives`` = 0 an array
        of shape ``u.shape + (3,)``; with 1 or 2 a dict with ``position``, ``du``, ``dv``
        (and ``duu``, ``duv``, ``dvv``). A point outside the rectangle raises
        ``InvalidInput`` naming it."""
        if derivatives not in (0, 1, 2):
            raise InvalidInput(f"derivatives {derivatives} must be 0, 1 or 2")
        uu, vv = np.broadcast_arrays(np.asarray(u, dtype=np.float64), np.asarray(v, np.float64))
        shape = uu.shape
        uv = np.ascontiguousarray(np.stack([uu.reshape(-1), vv.reshape(-1)], axis=1))
        orders = {"position": (0, 0)}
        if derivatives >= 1:
            orders |= {"du": (1, 0), "dv": (0, 1)}
        if derivatives >= 2:
            orders |= {"duu": (2, 0), "duv": (1, 1), "dvv": (0, 2)}
        values = {
            name: self._native.derivative(uv, a, b).reshape(*shape, 3)
            for name, (a, b) in orders.items()
        }
        return values["position"] if derivatives == 0 else values

    def coefficients(self) -> dict[str, Any]:
        """The solved coefficients as ``surfkit fit --coefficients`` writes them."""
        return json.loads(self._native.coefficients_json())


HoleShapes = Sequence[tuple[str, Any]]


def _hole_shapes(hole: HoleShapes | None) -> list[tuple[str, list[float]]]:
    """("ellipse", (cu, cv, a, b, level)) / ("polygon", [(u, v), …]) as flat number lists."""
    shapes = []
    for i, shape in enumerate(hole or []):
        if not (isinstance(shape, tuple | list) and len(shape) == 2 and isinstance(shape[0], str)):
            raise InvalidInput(
                f"hole shape {i}: expected ('ellipse', (cu, cv, a, b, level)) or "
                f"('polygon', [(u, v), ...]), got {shape!r}"
            )
        kind, numbers = shape
        shapes.append((kind, [float(x) for x in np.asarray(numbers, dtype=np.float64).ravel()]))
    return shapes


_TAU = {None: 0, "positive": 1, "negative": -1, "increasing": 1, "decreasing": -1}


def fit(
    uv: Any,
    xyz: Any,
    *,
    space: str = "biquadratic",
    cells: tuple[int, int] = (8, 8),
    epsilon: float = 1e-9,
    offset: Callable[[np.ndarray, np.ndarray], Any] | None = None,
) -> Spline:
    """The discrete smoothing variational spline of data ``uv`` (n, 2) → ``xyz`` (n, 3) on
    the data's parameter rectangle (Kouibia & Pasadas 2022 §3), as ``surfkit fit``.

    ``space``: "biquadratic" (C¹, 2022), "bicubic" (C²) or "bfs-c1" (Bogner–Fox–Schmit,
    2024); ``offset(u, v)`` → (n, 3) distances (d₁, d₂, d₃) fits the generalized offset
    f + d₁e₁ + d₂e₂ + d₃n of the data's surface instead (2022 (3)).
    """
    return fill(uv, xyz, space=space, cells=cells, epsilon=epsilon, offset=offset)


def fill(
    uv: Any,
    xyz: Any,
    *,
    hole: HoleShapes | str | None = None,
    space: str = "biquadratic",
    cells: tuple[int, int] = (8, 8),
    epsilon: float = 1e-9,
    exact_c1: bool = False,
    offset: Callable[[np.ndarray, np.ndarray], Any] | None = None,
    shape: Sequence[str] | None = None,
    shape_component: int = 2,
    shape_lattice: int = 3,
    shape_points: Any = None,
) -> Spline:
    """The smoothing spline and the filling of its hole, as ``surfkit fill``.

    ``hole``: shapes ``("ellipse", (cu, cv, a, b, level))`` for a(u−cu)² + b(v−cv)² ≤ level
    and ``("polygon", [(u, v), …])``, or ``"cells-without-data"``. ``exact_c1`` keeps σ in
    the spline space (C¹ across the border) instead of the paper's constraints (14).
    ``shape`` (2024 §4, needs ``space="bfs-c1"``): conditions among "positive",
    "negative", "increasing-u", "decreasing-u", "increasing-v", "decreasing-v" on component
    ``shape_component`` (0 x, 1 y, 2 z), imposed at the hole's free nodes, a
    ``shape_lattice`` × ``shape_lattice`` lattice per hole cell and ``shape_points``.
    """
    params = points(uv, 2, "uv")
    values = points(xyz, 3, "xyz")
    from_data = hole == "cells-without-data"
    if isinstance(hole, str) and not from_data:
        raise InvalidInput(f"hole {hole!r}: give shapes or 'cells-without-data'")
    shapes = [] if (hole is None or from_data) else _hole_shapes(hole)  # type: ignore[arg-type]
    distances = None
    if offset is not None:
        distances = points(
            np.asarray(offset(params[:, 0].copy(), params[:, 1].copy()), dtype=np.float64),
            3,
            "offset distances",
        )
    shape_args = None
    if shape:
        conditions = {"value": 0, "u": 0, "v": 0}
        for condition in shape:
            word, _, variable = condition.partition("-")
            key = variable or "value"
            valid = (word in ("positive", "negative")) == (key == "value")
            if not valid or word not in _TAU or key not in conditions or conditions[key] != 0:
                raise InvalidInput(f"shape condition {condition!r} is unknown or repeated")
            conditions[key] = _TAU[word]
        extra = (
            np.zeros((0, 2)) if shape_points is None else points(shape_points, 2, "shape_points")
        )
        shape_args = (
            int(shape_component),
            conditions["value"],
            conditions["u"],
            conditions["v"],
            int(shape_lattice),
            extra,
        )
    native = _surfkit.fit_spline(
        params,
        values,
        space_name=space,
        cells=(int(cells[0]), int(cells[1])),
        epsilon=float(epsilon),
        hole_shapes=shapes,
        hole_from_data=from_data,
        exact_c1=bool(exact_c1),
        offset_distances=distances,
        shape=shape_args,
    )
    return Spline(native)


def fit_parallel(
    uv: Any,
    xyz: Any,
    b_uv: Any,
    normals: Any,
    *,
    tau: float,
    cells: tuple[int, int] = (6, 6),
    epsilon: float = 1e-7,
    m: int = 3,
) -> Spline:
    """The discrete smoothing variational spline with parallelism conditions (Kouibia &
    Pasadas 2004 §4) on Bogner–Fox–Schmit C² elements: minimizes
    Σ‖y(a) − pₐ‖² + τ Σ_b Σᵢ ⟨Dᵢy(b), N(b)⟩² + ε|y|²ₘ (4.3), data ``uv`` → ``xyz``,
    ``normals`` the reference surface's unit normals N at ``b_uv``; τ = 0 is the plain
    smoothing spline. The report has ``pi_per_point`` (Π / |B|) and ``data_misfit``.
    """
    native = _surfkit.fit_parallel(
        points(uv, 2, "uv"),
        points(xyz, 3, "xyz"),
        points(b_uv, 2, "b_uv"),
        points(normals, 3, "normals"),
        cells=(int(cells[0]), int(cells[1])),
        epsilon=float(epsilon),
        tau=float(tau),
        m=int(m),
    )
    return Spline(native)
