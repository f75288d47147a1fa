"""Array conversions shared by the bindings: every accepted form of vertices and faces
brought to the arrays the native module takes (float64 (n, 3) positions, uint32 corner
indices and face offsets), with ``InvalidInput`` naming what is wrong."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from surfkit._surfkit import InvalidInput

Faces = np.ndarray | Sequence[Sequence[int]] | tuple[np.ndarray, np.ndarray]


def mesh_arrays(vertices: Any, faces: Faces) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(positions, indices, offsets) of ``Mesh(vertices, faces)``."""
    v = np.asarray(vertices)
    if v.ndim != 2 or v.shape[1] != 3:
        raise InvalidInput(f"vertices must have shape (n, 3), not {v.shape}")
    if not (np.issubdtype(v.dtype, np.floating) or np.issubdtype(v.dtype, np.integer)):
        raise InvalidInput(f"vertices must be numbers, not {v.dtype}")
    indices, offsets = faces_to_arrays(faces)
    return np.ascontiguousarray(v, dtype=np.float64), indices, offsets


def faces_to_arrays(faces: Faces) -> tuple[np.ndarray, np.ndarray]:
    """(indices, offsets) as uint32 from any of the accepted face forms."""
    if (
        isinstance(faces, tuple)
        and len(faces) == 2
        and all(isinstance(a, np.ndarray) and a.ndim == 1 for a in faces)
    ):
        indices, offsets = faces
        return ids(indices, "face indices"), ids(offsets, "face offsets")
    if isinstance(faces, np.ndarray):
        if faces.ndim != 2:
            raise InvalidInput(f"faces must be an (m, k) array, not of shape {faces.shape}")
        m, k = faces.shape
        return (
            ids(faces.reshape(-1), "faces"),
            np.arange(0, m * k + 1, k, dtype=np.uint32) if k > 0 else np.zeros(m + 1, np.uint32),
        )
    lengths = [len(f) for f in faces]
    offsets = np.zeros(len(lengths) + 1, dtype=np.int64)
    np.cumsum(lengths, out=offsets[1:])
    flat = [i for f in faces for i in f]
    return ids(np.asarray(flat, dtype=np.int64), "faces"), ids(offsets, "face offsets")


def ids(a: Any, what: str) -> np.ndarray:
    """Non-negative integer ids below 2³² as uint32, or InvalidInput naming the entry."""
    a = np.asarray(a)
    if a.size == 0:
        return a.astype(np.uint32).reshape(-1)
    if not np.issubdtype(a.dtype, np.integer):
        raise InvalidInput(f"{what} must be integers, not {a.dtype}")
    low, high = int(a.min()), int(a.max())
    if low < 0:
        raise InvalidInput(f"{what}: entry {int(np.argmin(a))} is negative ({low})")
    if high > np.iinfo(np.uint32).max:
        raise InvalidInput(f"{what}: entry {int(np.argmax(a))} ({high}) is beyond 32-bit ids")
    return np.ascontiguousarray(a, dtype=np.uint32).reshape(-1)


def points(a: Any, columns: int, what: str) -> np.ndarray:
    """A contiguous float64 (n, columns) array, or InvalidInput; the native side names a
    row that is not finite."""
    x = np.asarray(a)
    if x.ndim != 2 or x.shape[1] != columns:
        raise InvalidInput(f"{what} must have shape (n, {columns}), not {x.shape}")
    if not (np.issubdtype(x.dtype, np.floating) or np.issubdtype(x.dtype, np.integer)):
        raise InvalidInput(f"{what} must be numbers, not {x.dtype}")
    return np.ascontiguousarray(x, dtype=np.float64)
