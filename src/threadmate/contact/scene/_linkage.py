"""Points grouped by single linkage: chains of steps no longer than a separation.

The mechanics' contact set groups the touch points of a lowered pose so
(:mod:`threadmate.contact.mechanics`); the grouping of a few hundred points is compiled,
and warmed with the scene's other kernels (:mod:`._warm`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from ..._compiled import compiled

__all__ = ["single_linkage"]


def single_linkage(points: NDArray[np.float64], separation: float) -> NDArray[np.intp]:
    """Label points (0, 1, ... by first appearance) linked in chains of steps no longer
    than ``separation``: the distinct contacts of a lowered pose
    (:class:`threadmate.contact.Mechanics`).

    A contact set passes one point per cell of a sixteenth of the linkage, so there are
    few (tens to a few hundred): every pair is tested, compiled (:func:`_linked`). A
    broad patch (more than 400) takes its links from a k-d tree, as a sparse graph.
    """
    n = len(points)
    if n == 1:
        return np.zeros(1, dtype=np.intp)
    if n <= 400:
        return _linked(np.ascontiguousarray(points, dtype=float), float(separation))
    pairs = cKDTree(points).query_pairs(separation, output_type="ndarray").reshape(-1, 2)
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    labels = connected_components(graph, directed=False)[1]
    # Renumber by first appearance.
    _, first, inverse = np.unique(labels, return_index=True, return_inverse=True)
    return np.argsort(np.argsort(first))[inverse].astype(np.intp)


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
                a, b = i, j
                while parent[a] != a:
                    a = parent[a]
                while parent[b] != b:
                    b = parent[b]
                if a != b:
                    parent[max(a, b)] = min(a, b)
    labels = np.empty(n, dtype=np.intp)
    named = np.full(n, -1, dtype=np.intp)
    count = 0
    for i in range(n):
        root = i
        while parent[root] != root:
            root = parent[root]
        if named[root] < 0:
            named[root] = count
            count += 1
        labels[i] = named[root]
    return labels
