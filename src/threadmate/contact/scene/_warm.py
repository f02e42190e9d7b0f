"""The scene's compiled kernels warmed: each compiled, or loaded from numba's on-disk
cache, by one small call, in either of two orders.

On a machine whose cache is empty, every process that asks the kernels compiles them:
a pool's workers each do the same seconds of work at once. Two workers that warm them
in opposite orders share it instead: numba looks in its on-disk cache at a kernel's
first call, so a kernel one worker has compiled and saved, the other loads; they meet
about halfway. With the cache warm, each call only loads what the work would load
anyway.

Each call passes arguments of the types the work passes (C-ordered float64 and int64
arrays), so that it compiles the very signature the work asks for
(``tests/test_compiled.py`` checks that the work compiles no second one).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ...geometry import bolt_body, spec_from_designation
from ._kernels import (
    KINK,
    EdgeCurve,
    _arrays,
    crossing_of_edges,
    kink_height,
    kink_heights,
    signed_distance,
    vertical_touch,
)
from ._obb import ALL, ANY, CrossingQuery, ObbForest, obb_forest

__all__ = ["warm_kernels"]


def _triangles() -> tuple[np.ndarray, np.ndarray]:
    """Two small triangles, one above the other."""
    low = np.array([[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]])
    return low + [0.0, 0.0, 0.5], low


def _leaf() -> ObbForest:
    """A forest of one tree of one leaf, made here (not by the trees' build, which the
    other order warms first)."""
    tri = _triangles()[1]
    return ObbForest(
        centre=np.array([[0.5, 0.5, 0.0]]),
        axes=np.eye(3)[None].copy(),
        extent=np.array([[0.5, 0.5, 0.0]]),
        left=np.full(1, -1, dtype=np.int64),
        right=np.full(1, -1, dtype=np.int64),
        leaf=np.zeros(1, dtype=np.int64),
        size=np.ones(1, dtype=np.int64),
        triangles=tri,
        faces=np.zeros(1, dtype=np.int64),
        roots=np.zeros(1, dtype=np.int64),
    )


def _trees() -> None:
    top, low = _triangles()
    vertices = np.concatenate([top, low]).reshape(-1, 3)
    obb_forest(vertices, np.arange(6, dtype=np.int64).reshape(2, 3), [np.arange(2)])


def _walks() -> None:
    forest = _leaf()
    query = CrossingQuery(forest)
    trees, rotation = np.zeros(1, dtype=np.int64), np.eye(3)
    query(forest, 0, trees, rotation, np.zeros(3), ANY)
    query.below(forest, 0, trees, rotation, np.zeros(3), np.array([0.0, 0.0, 1.0]))
    query.among(forest, np.zeros((1, 3), dtype=np.int64), rotation, np.zeros(3), ALL)


def _touch() -> None:
    vertical_touch(*_triangles())


def _exact() -> None:
    body = bolt_body(spec_from_designation("1/4-20 UNC-2A/2B"))
    kink_height(body, 0.0, 0.0)
    kink_heights(body, np.zeros(2), 0.0)
    p = np.zeros((1, 3))
    signed_distance(body, p, np.arctan2(p[:, 1], p[:, 0]))
    got = _arrays(body)
    kink = EdgeCurve(KINK, got.prof, got.env, got.rise, float(body.lead), 0.0, 0.0, 0.0)
    crossing_of_edges(kink, kink, np.eye(3), np.zeros(3), 0.0, 1.0)


#: The kernels' calls, in the forward order: the trees' build and the walk, the two
#: dearest to compile, at either end.
_STEPS: tuple[Callable[[], None], ...] = (_trees, _touch, _exact, _walks)


def warm_kernels(reverse: bool = False) -> None:
    """Compile (or load from numba's cache) the scene's kernels, in the forward order or
    ``reverse`` (module docstring): give the workers of a pool alternate orders."""
    for step in reversed(_STEPS) if reverse else _STEPS:
        step()
