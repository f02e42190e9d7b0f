"""Points grouped by single linkage: chains of steps no longer than a separation.

The mechanics' contact set groups the touch points of a lowered pose so
(:mod:`threadmate.contact.mechanics`); the grouping is compiled, and warmed with the
scene's other kernels (:mod:`._warm`).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ..._compiled import compiled, inlined

__all__ = ["single_linkage"]


def single_linkage(points: NDArray[np.float64], separation: float) -> NDArray[np.intp]:
    """Label points (0, 1, ... by first appearance) linked in chains of steps no longer
    than ``separation``: the distinct contacts of a lowered pose
    (:class:`threadmate.contact.Mechanics`).

    A contact set passes one point per cell of a sixteenth of the linkage, so there are
    few (tens to a few hundred): every pair is tested, compiled (:func:`_linked`). A
    broad patch (more than :data:`EVERY_PAIR`; a flat face on a flat face) tests only the
    pairs in neighbouring cells of a grid as coarse as the linkage (:func:`_linked_in_grid`).
    """
    n = len(points)
    if n == 1:
        return np.zeros(1, dtype=np.intp)
    points = np.ascontiguousarray(points, dtype=float)
    if n <= EVERY_PAIR:
        return _linked(points, float(separation))
    return _linked_in_grid(points, float(separation))


#: Most points grouped by testing every pair (:func:`single_linkage`).
EVERY_PAIR = 400


@inlined
def _root(parent: NDArray[np.intp], a: int) -> int:
    """The root of ``a``'s tree in a union-find forest."""
    while parent[a] != a:
        a = parent[a]
    return a


@inlined
def _labelled(parent: NDArray[np.intp]) -> NDArray[np.intp]:
    """The union-find forest's components, labelled 0, 1, ... by first appearance."""
    n = parent.shape[0]
    labels = np.empty(n, dtype=np.intp)
    named = np.full(n, -1, dtype=np.intp)
    count = 0
    for i in range(n):
        root = _root(parent, i)
        if named[root] < 0:
            named[root] = count
            count += 1
        labels[i] = named[root]
    return labels


@compiled
def _linked(points: NDArray[np.float64], separation: float) -> NDArray[np.intp]:
    """:func:`single_linkage` of a few hundred points: every pair no farther apart than
    ``separation`` joined (union-find), the components labelled by first appearance."""
    n = points.shape[0]
    parent = np.arange(n)
    reach = separation * separation
    for i in range(n):
        for j in range(i + 1, n):
            dx = points[i, 0] - points[j, 0]
            dy = points[i, 1] - points[j, 1]
            dz = points[i, 2] - points[j, 2]
            if dx * dx + dy * dy + dz * dz <= reach:
                a, b = _root(parent, i), _root(parent, j)
                if a != b:
                    parent[max(a, b)] = min(a, b)
    return _labelled(parent)


@compiled
def _linked_in_grid(points: NDArray[np.float64], separation: float) -> NDArray[np.intp]:
    """:func:`single_linkage` of many points, by a grid of cells whose diagonal is a little
    shorter than ``separation``: the points of one cell are all linked (joined at once),
    two points that close lie in cells at most two apart along each axis, and two such
    cells not yet joined are joined at the first pair of their points that is linked
    (each cell being one group, one link joins them). The groups are those of every pair
    tested (:func:`_linked`); a patch of many points, a few cells, costs a few tests."""
    n = points.shape[0]
    step = separation / math.sqrt(3.0) * (1.0 - 1e-9)
    low = np.empty(3)
    for a in range(3):
        low[a] = points[:, a].min()
    cell = np.empty((n, 3), dtype=np.int64)
    for i in range(n):
        for a in range(3):
            cell[i, a] = int(np.floor((points[i, a] - low[a]) / step)) + 2
    # (Two empty layers each side: a neighbour's key never wraps into another row.)
    size = np.empty(3, dtype=np.int64)
    for a in range(3):
        size[a] = cell[:, a].max() + 3
    key = (cell[:, 0] * size[1] + cell[:, 1]) * size[2] + cell[:, 2]
    order = np.argsort(key, kind="mergesort")
    sorted_key = key[order]
    parent = np.arange(n)
    # Each cell's points (a run of ``order``): joined to its first.
    starts = [0]
    for r in range(1, n):
        if sorted_key[r] != sorted_key[r - 1]:
            starts.append(r)
    starts.append(n)
    for c in range(len(starts) - 1):
        head = order[starts[c]]
        for r in range(starts[c] + 1, starts[c + 1]):
            a, b = _root(parent, head), _root(parent, order[r])
            if a != b:
                parent[max(a, b)] = min(a, b)
    reach = separation * separation
    for c in range(len(starts) - 1):
        k = sorted_key[starts[c]]
        for d0 in range(-2, 3):
            for d1 in range(-2, 3):
                for d2 in range(-2, 3):
                    other = k + (d0 * size[1] + d1) * size[2] + d2
                    if other <= k:  # (each pair of cells once)
                        continue
                    at = np.searchsorted(sorted_key, other)
                    if at >= n or sorted_key[at] != other:
                        continue
                    end = at
                    while end < n and sorted_key[end] == other:
                        end += 1
                    if _root(parent, order[starts[c]]) == _root(parent, order[at]):
                        continue
                    joined = False
                    for r in range(starts[c], starts[c + 1]):
                        i = order[r]
                        for q in range(at, end):
                            j = order[q]
                            dx = points[i, 0] - points[j, 0]
                            dy = points[i, 1] - points[j, 1]
                            dz = points[i, 2] - points[j, 2]
                            if dx * dx + dy * dy + dz * dz <= reach:
                                a, b = _root(parent, i), _root(parent, j)
                                parent[max(a, b)] = min(a, b)
                                joined = True
                                break
                        if joined:
                            break
    return _labelled(parent)
