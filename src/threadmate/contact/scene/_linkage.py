"""Points grouped by single linkage: chains of steps no longer than a separation.

The mechanics' contact set groups the touch points of a lowered pose so
(:mod:`threadmate.contact.mechanics`); the grouping is compiled, and warmed with the
scene's other kernels (:mod:`._warm`).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ..._compiled import compiled

__all__ = ["single_linkage"]


def single_linkage(points: NDArray[np.float64], separation: float) -> NDArray[np.intp]:
    """Label points (0, 1, ... by first appearance) linked in chains of steps no longer
    than ``separation``: the distinct contacts of a lowered pose
    (:class:`threadmate.contact.Mechanics`).

    A contact set passes one point per cell of a sixteenth of the linkage, so there are
    few (tens to a few hundred): every pair is tested, compiled (:func:`_linked`). A
    broad patch (more than :data:`EVERY_PAIR`; a flat face on a flat face) is joined a
    cell of a grid at a time, the cells' diagonal a little under the linkage, and
    neighbouring cells at their first link (:func:`_linked_in_grid`).
    """
    n = len(points)
    if n == 1:
        return np.zeros(1, dtype=np.intp)
    points = np.ascontiguousarray(points, dtype=float)
    if n <= EVERY_PAIR:
        return _linked(points, float(separation))
    # The grid (:func:`_linked_in_grid`): cells whose diagonal is a little shorter than
    # the separation, two empty layers round them (a neighbour's key never wraps into
    # another row), one integer key per cell, the points in the keys' order.
    cell = np.floor((points - points.min(axis=0)) / (separation / math.sqrt(3.0) * (1 - 1e-9)))
    cell = cell.astype(np.int64) + 2
    size = cell.max(axis=0) + 3
    key = (cell[:, 0] * size[1] + cell[:, 1]) * size[2] + cell[:, 2]
    order = np.argsort(key)
    return _linked_in_grid(points, float(separation), key[order], order, size[1], size[2])


#: Most points grouped by testing every pair (:func:`single_linkage`).
EVERY_PAIR = 400


@compiled
def _root(parent: NDArray[np.intp], a: int) -> int:
    """The root of ``a``'s tree in a union-find forest."""
    while parent[a] != a:
        a = parent[a]
    return a


@compiled
def _first_at_least(values: NDArray[np.int64], value: int) -> int:
    """The first index of the sorted ``values`` holding ``value`` or more (bisection)."""
    lo, hi = 0, values.shape[0]
    while lo < hi:
        mid = (lo + hi) // 2
        if values[mid] < value:
            lo = mid + 1
        else:
            hi = mid
    return lo


@compiled
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
def _linked_in_grid(
    points: NDArray[np.float64],
    separation: float,
    sorted_key: NDArray[np.int64],
    order: NDArray[np.int64],
    rows: int,
    layers: int,
) -> NDArray[np.intp]:
    """:func:`single_linkage` of many points, by a grid of cells whose diagonal is a little
    shorter than ``separation`` (each point's cell's key, ``(i * rows + j) * layers + k``,
    in ``order``): the points of one cell are all linked (joined at once), two points
    that close lie in cells at most two apart along each axis, and two such cells not
    yet joined are joined at the first pair of their points that is linked (each cell
    being one group, one link joins them). The groups are those of every pair tested
    (:func:`_linked`); a patch of many points, a few cells, costs a few tests."""
    n = points.shape[0]
    parent = np.arange(n)
    # Each cell's points (a run of ``order``): joined to its first.
    starts = np.empty(n + 1, dtype=np.int64)
    cells = 1
    starts[0] = 0
    for r in range(1, n):
        if sorted_key[r] != sorted_key[r - 1]:
            starts[cells] = r
            cells += 1
    starts[cells] = n
    for c in range(cells):
        head = order[starts[c]]
        for r in range(starts[c] + 1, starts[c + 1]):
            a, b = _root(parent, head), _root(parent, order[r])
            if a != b:
                parent[max(a, b)] = min(a, b)
    reach = separation * separation
    for c in range(cells):
        k = sorted_key[starts[c]]
        for d0 in range(-2, 3):
            for d1 in range(-2, 3):
                for d2 in range(-2, 3):
                    other = k + (d0 * rows + d1) * layers + d2
                    if other <= k:  # (each pair of cells once)
                        continue
                    at = _first_at_least(sorted_key, other)
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
