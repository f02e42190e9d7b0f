"""Oriented-bounding-box trees of triangles, and the compiled query of the triangle pairs
of two of them that cross.

The collision queries (:class:`._collision.CollisionPair`) ask two things of the bolt at
a pose against the nut's sectors: whether any bolt triangle crosses a nut triangle, and
every pair that does. A threaded pair lies close all round its circumference, so each
query descends deep into both trees, and an enumeration meets tens to thousands of
crossing pairs. Asked through python-fcl, every pair comes back as a Python object with
two numpy arrays and each sector is its own call; here one compiled call walks the
sectors' trees and returns the pairs as integers.

The trees are FCL's kind of box: each node's box oriented along the principal axes of
its triangles' vertices (their covariance), down to leaves of :data:`LEAF_SIZE`
triangles. Where FCL splits a node's triangles at the mean of their centroids along the
box's major axis, here the split is chosen by the surface-area heuristic of ray-tracing
trees (:func:`_split`): across each of the box's axes, the plane that leaves the two
children the least surface, weighted by their triangles. A thread's triangles run round
the helix, long and thin, the major axis is a poor guess at the cut that keeps the
children small, and the walk tests far fewer box pairs for the better cut
(docs/validation.md). Which pairs cross is the triangle test's answer whatever the tree
(a box holds its triangles), so the answers are those of any tree.

A query works in the bolt's frame, as FCL's mesh traversal does: the nut's boxes and
triangles are moved into it (lazily, once per query each: a box when the walk first meets
it, a leaf's triangles when its box first meets a bolt leaf's), a pair of boxes is kept
unless one of the 15 axes of the separating-axis test parts them (with FCL's allowance
of 1e-6 on the rotation's entries, which only keeps more pairs), the larger box (by its
diagonal) is split first, and two leaves' triangles cross unless one of the 17 axes of
RAPID's triangle test (Gottschalk, Lin and Manocha, SIGGRAPH 1996: the two normals, the
nine products of their edges and the six in-plane edge normals) separates them,
touching counting as crossing. These are the tests python-fcl applies, and on the
queries of the default parts' searches the two return the same pairs
(``tests/test_contact.py`` checks it at poses of its own).

A lowering asks two questions of nearly one pose: whether the bolt is free at the top of
its bracket, and which pairs cross at its foot a little lower. One walk answers both
(:meth:`CrossingQuery.below`): each nut box is swept between the two poses (its
half-extents grown by half the shift along each axis, which holds it at either pose), and
a leaf's triangles are tested at each; the walk stops at the first pair crossing at the
top. Near contact the two walks would visit nearly the same boxes. Such a walk keeps the
leaf pairs whose swept boxes met: the pairs crossing at any pose between the two are
among them, and :func:`_among` finds them by the triangle test alone.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from ..._compiled import compiled, inlined

__all__ = ["PAIR_KEY", "CrossingQuery", "ObbForest", "obb_forest", "unique_face_pairs"]

#: Box pairs a query's walk holds at once: far more than two trees' depths need.
_STACK = 4096
#: Most triangles in a leaf. Two (FCL has one): a leaf of two saves the walk its deepest
#: level of box tests for more triangle tests, which the surface-area split's trees gain
#: by (FCL's lost by it); three or more cost more (docs/validation.md).
LEAF_SIZE = 2
#: What a query asks (:func:`_crossing`): every crossing pair, whether any, or whether any
#: in each tree of the nut asked.
ALL, ANY, EACH = 0, 1, 2
#: Multiplier of the bolt face in a pair's integer key (above any nut face count).
PAIR_KEY = 1 << 31
#: Slack (spec units) of a box swept between two poses: it holds the box at either pose
#: as another query computes it, whatever the rounding.
_SWEPT_SLACK = 1e-12
#: Bins of the centroids along each box axis whose boundaries are a node's candidate
#: split planes (:func:`_split`).
SPLIT_BINS = 16


class ObbForest(NamedTuple):
    """Trees of oriented boxes over groups of a mesh's triangles, in one set of arrays.

    Attributes
    ----------
    centre, axes, extent : ndarray
        Each node's box: its centre ``(n, 3)``, its axes as the columns of ``(n, 3, 3)``
        and its half-extents along them ``(n, 3)``, in the mesh's frame.
    left, right : ndarray of int64
        Each node's children (-1 at a leaf).
    leaf, size : ndarray of int64
        A leaf's first triangle (a row of ``triangles``) and how many it holds, from
        that row on (at most :data:`LEAF_SIZE`); -1 and 0 at an inner node.
    triangles : ndarray
        The triangles' vertices ``(m, 3, 3)``, in the trees' order (a leaf's together).
    faces : ndarray of int64
        Each triangle's face in the mesh.
    roots : ndarray of int64
        Each tree's root node, in the groups' order.
    """

    centre: NDArray[np.float64]
    axes: NDArray[np.float64]
    extent: NDArray[np.float64]
    left: NDArray[np.int64]
    right: NDArray[np.int64]
    leaf: NDArray[np.int64]
    size: NDArray[np.int64]
    triangles: NDArray[np.float64]
    faces: NDArray[np.int64]
    roots: NDArray[np.int64]


@compiled
def _fit(
    tri: NDArray[np.float64], order: NDArray[np.int64], lo: int, hi: int
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """The box of the triangles ``order[lo:hi]``: centre, axes (columns, by decreasing
    variance of the vertices along them) and half-extents."""
    n = 3 * (hi - lo)
    mean = np.zeros(3)
    for k in range(lo, hi):
        for v in range(3):
            for a in range(3):
                mean[a] += tri[order[k], v, a]
    mean /= n
    cov = np.zeros((3, 3))
    for k in range(lo, hi):
        for v in range(3):
            for a in range(3):
                da = tri[order[k], v, a] - mean[a]
                for b in range(3):
                    cov[a, b] += da * (tri[order[k], v, b] - mean[b])
    _, vectors = np.linalg.eigh(cov)
    axes = np.empty((3, 3))
    for c in range(3):
        for a in range(3):
            axes[a, c] = vectors[a, 2 - c]
    low = np.full(3, np.inf)
    high = np.full(3, -np.inf)
    for k in range(lo, hi):
        for v in range(3):
            for c in range(3):
                p = 0.0
                for a in range(3):
                    p += tri[order[k], v, a] * axes[a, c]
                low[c] = min(low[c], p)
                high[c] = max(high[c], p)
    centre = np.zeros(3)
    extent = np.empty(3)
    for c in range(3):
        extent[c] = 0.5 * (high[c] - low[c])
        middle = 0.5 * (low[c] + high[c])
        for a in range(3):
            centre[a] += axes[a, c] * middle
    return centre, axes, extent


@compiled
def _split(
    tri: NDArray[np.float64],
    order: NDArray[np.int64],
    lo: int,
    hi: int,
    axes: NDArray[np.float64],
    along: NDArray[np.float64],
    span: NDArray[np.float64],
    bins: NDArray[np.float64],
) -> float:
    """The plane that splits the triangles ``order[lo:hi]`` of a node (axes: its box's):
    ``along[k]`` set to each one's centroid along the chosen box axis, the plane's
    position on it returned (the triangles below it go left).

    Of :data:`SPLIT_BINS` - 1 planes evenly spaced across the centroids' range along each
    of the box's three axes, the one whose two children's boxes (their extents along the
    node's axes) have the least surface, each weighted by its triangles: the
    surface-area heuristic, as ray-tracing trees are built. A query descends into a pair
    of boxes the more often the larger their surfaces. Where the centroids coincide along
    every axis, the mean along the major axis (the order's middle then splits).
    """
    nb = bins.shape[0]
    # Each triangle's least and greatest extent along the axes, and its centroid's.
    for k in range(lo, hi):
        t = order[k]
        for d in range(3):
            p0 = tri[t, 0, 0] * axes[0, d] + tri[t, 0, 1] * axes[1, d] + tri[t, 0, 2] * axes[2, d]
            p1 = tri[t, 1, 0] * axes[0, d] + tri[t, 1, 1] * axes[1, d] + tri[t, 1, 2] * axes[2, d]
            p2 = tri[t, 2, 0] * axes[0, d] + tri[t, 2, 1] * axes[1, d] + tri[t, 2, 2] * axes[2, d]
            span[k, d, 0] = min(p0, p1, p2)
            span[k, d, 1] = max(p0, p1, p2)
            span[k, d, 2] = (p0 + p1 + p2) / 3.0
    best, best_axis, best_plane = np.inf, -1, 0.0
    for c in range(3):
        low, high = np.inf, -np.inf
        for k in range(lo, hi):
            low = min(low, span[k, c, 2])
            high = max(high, span[k, c, 2])
        if not high > low:
            continue
        width = (high - low) / nb
        # Per bin: count, then the least and greatest extent along each axis.
        for b in range(nb):
            bins[b, 0] = 0.0
            for d in range(3):
                bins[b, 1 + d] = np.inf
                bins[b, 4 + d] = -np.inf
        for k in range(lo, hi):
            b = min(int((span[k, c, 2] - low) / width), nb - 1)
            bins[b, 0] += 1.0
            for d in range(3):
                bins[b, 1 + d] = min(bins[b, 1 + d], span[k, d, 0])
                bins[b, 4 + d] = max(bins[b, 4 + d], span[k, d, 1])
        # The children's costs at each cut: the left's in a sweep up (kept in column 7),
        # the right's in a sweep down.
        n, f0, f1, f2, e0, e1, e2 = 0.0, np.inf, np.inf, np.inf, -np.inf, -np.inf, -np.inf
        for b in range(nb - 1):
            if bins[b, 0] > 0:
                n += bins[b, 0]
                f0, f1, f2 = min(f0, bins[b, 1]), min(f1, bins[b, 2]), min(f2, bins[b, 3])
                e0, e1, e2 = max(e0, bins[b, 4]), max(e1, bins[b, 5]), max(e2, bins[b, 6])
            x, y, z = e0 - f0, e1 - f1, e2 - f2
            bins[b, 7] = n * (x * y + y * z + z * x) if n > 0 else np.inf
        n, f0, f1, f2, e0, e1, e2 = 0.0, np.inf, np.inf, np.inf, -np.inf, -np.inf, -np.inf
        for b in range(nb - 1, 0, -1):
            if bins[b, 0] > 0:
                n += bins[b, 0]
                f0, f1, f2 = min(f0, bins[b, 1]), min(f1, bins[b, 2]), min(f2, bins[b, 3])
                e0, e1, e2 = max(e0, bins[b, 4]), max(e1, bins[b, 5]), max(e2, bins[b, 6])
            if n > 0:  # the cut below bin b
                x, y, z = e0 - f0, e1 - f1, e2 - f2
                cost = bins[b - 1, 7] + n * (x * y + y * z + z * x)
                if cost < best:
                    best, best_axis, best_plane = cost, c, low + b * width
    if best_axis < 0:  # every centroid at one place along each axis
        best_axis = 0
        best_plane = 0.0
        for k in range(lo, hi):
            best_plane += span[k, 0, 2]
        best_plane /= hi - lo
    for k in range(lo, hi):
        along[k] = span[k, best_axis, 2]
    return best_plane


@compiled
def _build(
    tri: NDArray[np.float64], groups: NDArray[np.int64]
) -> tuple[
    NDArray[np.float64],
    NDArray[np.float64],
    NDArray[np.float64],
    NDArray[np.int64],
    NDArray[np.int64],
    NDArray[np.int64],
    NDArray[np.int64],
    NDArray[np.int64],
    NDArray[np.int64],
]:
    """The trees over consecutive runs of ``tri`` (run ``g`` ends at ``groups[g]``): the
    nodes' arrays as :class:`ObbForest` has them, the roots, and the order of ``tri`` in
    which each leaf's triangles are consecutive."""
    m = tri.shape[0]
    count = 2 * m - len(groups)  # the most nodes (one triangle per leaf)
    centre = np.empty((count, 3))
    axes = np.empty((count, 3, 3))
    extent = np.empty((count, 3))
    left = np.full(count, -1, np.int64)
    right = np.full(count, -1, np.int64)
    leaf = np.full(count, -1, np.int64)
    size = np.zeros(count, np.int64)
    roots = np.empty(len(groups), np.int64)
    order = np.arange(m)
    stack = np.empty((count, 3), np.int64)
    along = np.empty(m)
    span = np.empty((m, 3, 3))
    bins = np.empty((SPLIT_BINS, 8))
    used = 0
    start = 0
    for g in range(len(groups)):
        roots[g] = used
        stack[0, 0], stack[0, 1], stack[0, 2] = used, start, groups[g]
        used += 1
        depth = 1
        while depth > 0:
            depth -= 1
            node, lo, hi = stack[depth, 0], stack[depth, 1], stack[depth, 2]
            c, ax, ex = _fit(tri, order, lo, hi)
            # Element by element: a row assigned whole compiles numba's shape checks,
            # seconds of a first run's compile.
            for a in range(3):
                centre[node, a] = c[a]
                extent[node, a] = ex[a]
                for b in range(3):
                    axes[node, a, b] = ax[a, b]
            if hi - lo <= LEAF_SIZE:
                leaf[node], size[node] = lo, hi - lo
                continue
            plane = _split(tri, order, lo, hi, ax, along, span, bins)
            i, j = lo, hi - 1
            while i <= j:
                if along[i] < plane:
                    i += 1
                else:
                    order[i], order[j] = order[j], order[i]
                    along[i], along[j] = along[j], along[i]
                    j -= 1
            mid = i if lo < i < hi else (lo + hi) // 2
            left[node], right[node] = used, used + 1
            stack[depth, 0], stack[depth, 1], stack[depth, 2] = used, lo, mid
            stack[depth + 1, 0], stack[depth + 1, 1], stack[depth + 1, 2] = used + 1, mid, hi
            used += 2
            depth += 2
        start = groups[g]
    return (
        centre[:used],
        axes[:used],
        extent[:used],
        left[:used],
        right[:used],
        leaf[:used],
        size[:used],
        roots,
        order,
    )


def obb_forest(
    vertices: NDArray[np.float64], faces: NDArray[np.int64], groups: list[NDArray[np.int64]]
) -> ObbForest:
    """One tree per group of a mesh's faces (each group a non-empty array of face
    numbers)."""
    ids = np.concatenate([np.asarray(g, dtype=np.int64) for g in groups])
    tri = np.ascontiguousarray(np.asarray(vertices, dtype=float)[np.asarray(faces)[ids]])
    ends = np.cumsum([len(g) for g in groups]).astype(np.int64)
    centre, axes, extent, left, right, leaf, size, roots, order = _build(tri, ends)
    # The triangles in the trees' order: a leaf's together, and the walk's reads near one
    # another.
    return ObbForest(centre, axes, extent, left, right, leaf, size, tri[order], ids[order], roots)


@inlined
def _spans(
    p2: NDArray[np.float64],
    p3: NDArray[np.float64],
    q: NDArray[np.float64],
    u: NDArray[np.float64],
    v: NDArray[np.float64],
) -> tuple[float, float, float, float, float, float, float]:
    """The axis ``u x v`` (its three components) and the spans of the triangles ``(0, p2,
    p3)`` and ``q`` (its vertices the rows) along it: ``x, y, z, lo_p, hi_p, lo_q, hi_q``."""
    x = u[1] * v[2] - u[2] * v[1]
    y = u[2] * v[0] - u[0] * v[2]
    z = u[0] * v[1] - u[1] * v[0]
    a2 = x * p2[0] + y * p2[1] + z * p2[2]
    a3 = x * p3[0] + y * p3[1] + z * p3[2]
    b1 = x * q[0, 0] + y * q[0, 1] + z * q[0, 2]
    b2 = x * q[1, 0] + y * q[1, 1] + z * q[1, 2]
    b3 = x * q[2, 0] + y * q[2, 1] + z * q[2, 2]
    return x, y, z, min(0.0, a2, a3), max(0.0, a2, a3), min(b1, b2, b3), max(b1, b2, b3)


@inlined
def _apart(
    p2: NDArray[np.float64],
    p3: NDArray[np.float64],
    q: NDArray[np.float64],
    u: NDArray[np.float64],
    v: NDArray[np.float64],
) -> bool:
    """Whether the axis ``u x v`` separates the triangles ``(0, p2, p3)`` and ``q`` (its
    vertices the rows) strictly (a zero axis separates nothing)."""
    _, _, _, lo_p, hi_p, lo_q, hi_q = _spans(p2, p3, q, u, v)
    return lo_p > hi_q or lo_q > hi_p


#: RAPID's 17 axes, each the cross product of two rows of :func:`_cross`'s scratch (its
#: rows: the edges ``e0 e1 e2 f0 f1 f2`` and the normals ``n m``): the two normals, the
#: nine products of edges, and the in-plane edge normals.
_AXES = np.array(
    [[0, 1], [3, 4]]
    + [[i, 3 + j] for i in range(3) for j in range(3)]
    + [pair for i in range(3) for pair in ([i, 6], [3 + i, 7])],
    dtype=np.int64,
)


@inlined
def _scratch(p: NDArray[np.float64], q: NDArray[np.float64], w: NDArray[np.float64]) -> None:
    """Fill the rows of a triangle test's scratch ``w``: ``p``'s second and third vertices
    and ``q``'s three, relative to ``p``'s first (as FCL has them), then the edges ``e0 e1
    e2 f0 f1 f2`` and the normals ``n m``."""
    p2, p3, qs, d = w[0], w[1], w[2:5], w[5:13]
    for a in range(3):
        o = p[0, a]
        p2[a] = p[1, a] - o
        p3[a] = p[2, a] - o
        for v in range(3):
            qs[v, a] = q[v, a] - o
    for a in range(3):
        d[0, a], d[1, a], d[2, a] = p2[a], p3[a] - p2[a], -p3[a]
        d[3, a], d[4, a], d[5, a] = qs[1, a] - qs[0, a], qs[2, a] - qs[1, a], qs[0, a] - qs[2, a]
    d[6, 0] = d[0, 1] * d[1, 2] - d[0, 2] * d[1, 1]
    d[6, 1] = d[0, 2] * d[1, 0] - d[0, 0] * d[1, 2]
    d[6, 2] = d[0, 0] * d[1, 1] - d[0, 1] * d[1, 0]
    d[7, 0] = d[3, 1] * d[4, 2] - d[3, 2] * d[4, 1]
    d[7, 1] = d[3, 2] * d[4, 0] - d[3, 0] * d[4, 2]
    d[7, 2] = d[3, 0] * d[4, 1] - d[3, 1] * d[4, 0]


@compiled
def _cross(p: NDArray[np.float64], q: NDArray[np.float64], w: NDArray[np.float64]) -> bool:
    """Whether the triangles ``p`` and ``q`` (``(3, 3)`` each) intersect or touch: no axis
    of RAPID's 17 (:data:`_AXES`) separates them (``w``: ``(13, 3)`` scratch, or more). (One
    call of the inlined test in a loop: each call is compiled in full.)"""
    _scratch(p, q, w)
    p2, p3, qs, d = w[0], w[1], w[2:5], w[5:13]
    for k in range(len(_AXES)):
        if _apart(p2, p3, qs, d[_AXES[k, 0]], d[_AXES[k, 1]]):
            return False
    return True


@inlined
def _apart_over(
    p2: NDArray[np.float64],
    p3: NDArray[np.float64],
    q: NDArray[np.float64],
    u: NDArray[np.float64],
    v: NDArray[np.float64],
    lift: NDArray[np.float64],
) -> bool:
    """:func:`_apart` of the triangle ``(0, p2, p3)`` and the prism the triangle ``q``
    sweeps moved by ``lift``: ``q``'s span along the axis grown by the lift's."""
    x, y, z, lo_p, hi_p, lo_q, hi_q = _spans(p2, p3, q, u, v)
    s = x * lift[0] + y * lift[1] + z * lift[2]
    return lo_p > hi_q + max(0.0, s) or lo_q + min(0.0, s) > hi_p


#: The axes of :func:`_cross_over`, each the cross product of two rows of its scratch
#: (its rows: the edges ``e0 e1 e2 f0 f1 f2``, the normals ``n m`` and the lift ``l``):
#: the triangle's normal, the prism's faces (the swept triangle's normal, its edges times
#: the lift), the products of the edges and the lift with the triangle's edges, and the
#: in-plane normals of the triangle's and the swept triangle's edges (and the lift's), which
#: part flat figures.
_AXES_OVER = np.array(
    [[0, 1], [3, 4]]
    + [[3 + j, 8] for j in range(3)]
    + [[i, 3 + j] for i in range(3) for j in range(3)]
    + [[i, 8] for i in range(3)]
    + [pair for i in range(3) for pair in ([i, 6], [3 + i, 7])]
    + [[8, 7]],
    dtype=np.int64,
)


@compiled
def _cross_over(
    p: NDArray[np.float64],
    q: NDArray[np.float64],
    lift: NDArray[np.float64],
    w: NDArray[np.float64],
) -> bool:
    """Whether the triangle ``p`` meets the triangle ``q`` moved by ``t lift`` for some
    ``t`` in [0, 1]: no axis of :data:`_AXES_OVER` parts ``p`` from the prism ``q`` sweeps
    (the separating-axis test of two convex bodies, exact but for the rounding of
    touching; ``w``: ``(14, 3)`` scratch, its rows as :func:`_cross`'s and the lift)."""
    _scratch(p, q, w)
    p2, p3, qs, d = w[0], w[1], w[2:5], w[5:14]
    for a in range(3):
        d[8, a] = lift[a]
    for k in range(len(_AXES_OVER)):
        if _apart_over(p2, p3, qs, d[_AXES_OVER[k, 0]], d[_AXES_OVER[k, 1]], lift):
            return False
    return True


@inlined
def _disjoint(
    ca: NDArray[np.float64],
    ua: NDArray[np.float64],
    ea: NDArray[np.float64],
    cb: NDArray[np.float64],
    ub: NDArray[np.float64],
    eb: NDArray[np.float64],
) -> bool:
    """Whether the boxes ``a`` and ``b`` (centre, axes as columns, half-extents; in one
    frame) are parted by one of the 15 axes of the separating-axis test. (Unrolled: an
    array made here would be allocated at every one of a query's many box pairs.)"""
    d0, d1, d2 = cb[0] - ca[0], cb[1] - ca[1], cb[2] - ca[2]
    t0 = ua[0, 0] * d0 + ua[1, 0] * d1 + ua[2, 0] * d2
    t1 = ua[0, 1] * d0 + ua[1, 1] * d1 + ua[2, 1] * d2
    t2 = ua[0, 2] * d0 + ua[1, 2] * d1 + ua[2, 2] * d2
    # b's axes in a's: r_ij = a_i . b_j, and |r_ij| with FCL's allowance.
    r00 = ua[0, 0] * ub[0, 0] + ua[1, 0] * ub[1, 0] + ua[2, 0] * ub[2, 0]
    r01 = ua[0, 0] * ub[0, 1] + ua[1, 0] * ub[1, 1] + ua[2, 0] * ub[2, 1]
    r02 = ua[0, 0] * ub[0, 2] + ua[1, 0] * ub[1, 2] + ua[2, 0] * ub[2, 2]
    r10 = ua[0, 1] * ub[0, 0] + ua[1, 1] * ub[1, 0] + ua[2, 1] * ub[2, 0]
    r11 = ua[0, 1] * ub[0, 1] + ua[1, 1] * ub[1, 1] + ua[2, 1] * ub[2, 1]
    r12 = ua[0, 1] * ub[0, 2] + ua[1, 1] * ub[1, 2] + ua[2, 1] * ub[2, 2]
    r20 = ua[0, 2] * ub[0, 0] + ua[1, 2] * ub[1, 0] + ua[2, 2] * ub[2, 0]
    r21 = ua[0, 2] * ub[0, 1] + ua[1, 2] * ub[1, 1] + ua[2, 2] * ub[2, 1]
    r22 = ua[0, 2] * ub[0, 2] + ua[1, 2] * ub[1, 2] + ua[2, 2] * ub[2, 2]
    s00, s01, s02 = abs(r00) + 1e-6, abs(r01) + 1e-6, abs(r02) + 1e-6
    s10, s11, s12 = abs(r10) + 1e-6, abs(r11) + 1e-6, abs(r12) + 1e-6
    s20, s21, s22 = abs(r20) + 1e-6, abs(r21) + 1e-6, abs(r22) + 1e-6
    a0, a1, a2 = ea[0], ea[1], ea[2]
    b0, b1, b2 = eb[0], eb[1], eb[2]
    return (
        # a's axes
        abs(t0) > a0 + b0 * s00 + b1 * s01 + b2 * s02
        or abs(t1) > a1 + b0 * s10 + b1 * s11 + b2 * s12
        or abs(t2) > a2 + b0 * s20 + b1 * s21 + b2 * s22
        # b's axes
        or abs(t0 * r00 + t1 * r10 + t2 * r20) > b0 + a0 * s00 + a1 * s10 + a2 * s20
        or abs(t0 * r01 + t1 * r11 + t2 * r21) > b1 + a0 * s01 + a1 * s11 + a2 * s21
        or abs(t0 * r02 + t1 * r12 + t2 * r22) > b2 + a0 * s02 + a1 * s12 + a2 * s22
        # a_0 x b_j
        or abs(t2 * r10 - t1 * r20) > a1 * s20 + a2 * s10 + b1 * s02 + b2 * s01
        or abs(t2 * r11 - t1 * r21) > a1 * s21 + a2 * s11 + b0 * s02 + b2 * s00
        or abs(t2 * r12 - t1 * r22) > a1 * s22 + a2 * s12 + b0 * s01 + b1 * s00
        # a_1 x b_j
        or abs(t0 * r20 - t2 * r00) > a0 * s20 + a2 * s00 + b1 * s12 + b2 * s11
        or abs(t0 * r21 - t2 * r01) > a0 * s21 + a2 * s01 + b0 * s12 + b2 * s10
        or abs(t0 * r22 - t2 * r02) > a0 * s22 + a2 * s02 + b0 * s11 + b1 * s10
        # a_2 x b_j
        or abs(t1 * r00 - t0 * r10) > a0 * s10 + a1 * s00 + b1 * s22 + b2 * s21
        or abs(t1 * r01 - t0 * r11) > a0 * s11 + a1 * s01 + b0 * s22 + b2 * s20
        or abs(t1 * r02 - t0 * r12) > a0 * s12 + a1 * s02 + b0 * s21 + b1 * s20
    )


@inlined
def _moved(
    rt: NDArray[np.float64],
    tt: NDArray[np.float64],
    x: NDArray[np.float64],
    out: NDArray[np.float64],
) -> None:
    """``out = rt @ x + tt`` for a point ``x``."""
    for a in range(3):
        out[a] = rt[a, 0] * x[0] + rt[a, 1] * x[1] + rt[a, 2] * x[2] + tt[a]


#: A forest's arrays as :func:`_crossing` takes them: centre, axes, extent, left, right,
#: leaf, size, triangles (:class:`ObbForest`).
_Arrays = tuple[
    NDArray[np.float64],
    NDArray[np.float64],
    NDArray[np.float64],
    NDArray[np.int64],
    NDArray[np.int64],
    NDArray[np.int64],
    NDArray[np.int64],
    NDArray[np.float64],
]


@compiled
def _crossing(
    b: _Arrays,
    b_root: int,
    n: _Arrays,
    n_roots: NDArray[np.int64],
    rotation: NDArray[np.float64],
    origin: NDArray[np.float64],
    mode: int,
    out: NDArray[np.int64],
    moved: tuple[
        NDArray[np.float64],
        NDArray[np.float64],
        NDArray[np.float64],
        NDArray[np.int64],
        NDArray[np.float64],
        NDArray[np.float64],
    ],
    stamp: int,
    above: NDArray[np.float64],
    kept: NDArray[np.int64],
    free: bool,
) -> int:
    """The crossing pairs of the bolt tree at ``b_root`` (the bolt's frame) at the pose
    ``(rotation, origin)`` and the nut trees at ``n_roots`` (the fixed frame), in that
    order: ``out[k] = (bolt triangle, nut triangle, position in n_roots)`` (rows of the
    forests' ``triangles``); returns how many (those past ``out``'s rows are counted, not
    written). ``mode``: :data:`ALL` pairs, :data:`ANY` (the first only), or :data:`EACH`
    tree's first.

    Where ``above`` differs from ``origin`` (a second origin, the bolt as rotated), the
    walk asks also whether the bolt at that pose crosses the nut: its boxes hold the nut's
    at both poses, and a leaf's triangles are tested at both. At the first pair crossing
    there, ``out[0]`` is that pair and the walk returns -1; else it returns the pairs at
    ``origin`` (in :data:`ALL` mode). The two answers are those of two queries; where the
    pose ``above`` is known ``free``, the first is not asked. Such a walk keeps the leaf
    pairs whose swept boxes meet, ``(bolt node, nut node, position in
    n_roots)``, in ``kept[1:]`` (their count in ``kept[0, 0]``, those past its rows
    counted, not written): every pair crossing at an origin between the two is among
    them (:func:`_among`).

    ``moved`` holds the nut's boxes and triangles moved into the bolt's frame (centres,
    axes, triangles), per node the ``stamp`` of the query that moved its box and that of
    the query that moved its leaf's triangles (a box is moved once, when the walk first
    meets it, a leaf's triangles when its box first meets a bolt leaf's), and the boxes
    swept to the pose ``above`` (centres, half-extents)."""
    bc, ba, be, bl, br, bleaf, bsize, btri = b
    nc, na, ne, nl, nr, nleaf, nsize, ntri = n
    mc, ma, mtri, seen, sc, se = moved
    rt = rotation.T.copy()
    tt = np.empty(3)
    tu = np.empty(3)
    for a in range(3):
        tt[a] = -(rt[a, 0] * origin[0] + rt[a, 1] * origin[1] + rt[a, 2] * origin[2])
        tu[a] = -(rt[a, 0] * above[0] + rt[a, 1] * above[1] + rt[a, 2] * above[2])
    swept = tu[0] != tt[0] or tu[1] != tt[1] or tu[2] != tt[2]
    u = np.empty(3)  # the nut's shift in the bolt's frame from the one pose to the other
    for a in range(3):
        u[a] = tu[a] - tt[a]
    # The nut's boxes as tested: swept between the two poses, or at the one.
    cj, ej = (sc, se) if swept else (mc, ne)
    w = np.empty((13, 3))
    lifted = np.empty((3, 3))
    stack = np.empty((_STACK, 2), np.int64)
    count = 0
    kept[0, 0] = 0
    for k in range(len(n_roots)):
        stack[0, 0], stack[0, 1] = b_root, n_roots[k]
        depth = 1
        while depth > 0:
            depth -= 1
            i, j = stack[depth, 0], stack[depth, 1]
            if seen[j, 0] != stamp:
                _moved(rt, tt, nc[j], mc[j])
                for c in range(3):
                    for a in range(3):
                        ma[j, a, c] = rt[a, 0] * na[j, 0, c] + rt[a, 1] * na[j, 1, c]
                        ma[j, a, c] += rt[a, 2] * na[j, 2, c]
                if swept:
                    for c in range(3):
                        along = u[0] * ma[j, 0, c] + u[1] * ma[j, 1, c] + u[2] * ma[j, 2, c]
                        se[j, c] = ne[j, c] + 0.5 * abs(along) + _SWEPT_SLACK
                        sc[j, c] = mc[j, c] + 0.5 * u[c]
                seen[j, 0] = stamp
            # (One call of the inlined test: each call is compiled in full.)
            if _disjoint(bc[i], ba[i], be[i], cj[j], ma[j], ej[j]):
                continue
            bi, nj = bleaf[i], nleaf[j]
            if bi >= 0 and nj >= 0:
                if seen[j, 1] != stamp:  # (most leaves met are parted by their boxes)
                    for q in range(nj, nj + nsize[j]):
                        for v in range(3):
                            _moved(rt, tt, ntri[q, v], mtri[q, v])
                    seen[j, 1] = stamp
                if swept:
                    row = kept[0, 0] + 1
                    if row < len(kept):
                        kept[row, 0], kept[row, 1], kept[row, 2] = i, j, k
                    kept[0, 0] = row
                first = False  # (EACH: this tree's first pair found)
                lift = swept and not free
                for q in range(nj, nj + nsize[j]):
                    if lift:
                        for v in range(3):
                            _moved(rt, tu, ntri[q, v], lifted[v])
                    for p in range(bi, bi + bsize[i]):
                        if lift and _cross(btri[p], lifted, w):
                            out[0, 0], out[0, 1], out[0, 2] = p, q, k
                            return -1
                        if _cross(btri[p], mtri[q], w):
                            if count < len(out):
                                out[count, 0], out[count, 1], out[count, 2] = p, q, k
                            count += 1
                            if mode == ANY:
                                return count
                            if mode == EACH:
                                depth, first = 0, True
                                break
                    if first:
                        break
                continue
            # The larger box (by its diagonal) is split first, as FCL does.
            if nj >= 0 or (
                bi < 0
                and be[i, 0] ** 2 + be[i, 1] ** 2 + be[i, 2] ** 2
                > ne[j, 0] ** 2 + ne[j, 1] ** 2 + ne[j, 2] ** 2
            ):
                stack[depth, 0], stack[depth, 1] = bl[i], j
                stack[depth + 1, 0], stack[depth + 1, 1] = br[i], j
            else:
                stack[depth, 0], stack[depth, 1] = i, nl[j]
                stack[depth + 1, 0], stack[depth + 1, 1] = i, nr[j]
            depth += 2
    return count


@compiled
def _among(
    b: _Arrays,
    n: _Arrays,
    nodes: NDArray[np.int64],
    rotation: NDArray[np.float64],
    origin: NDArray[np.float64],
    mode: int,
    out: NDArray[np.int64],
    drop: float,
) -> int:
    """The crossing pairs of the leaf pairs ``nodes`` (rows ``(bolt node, nut node,
    tag)``), the bolt at the pose ``(rotation, origin)``: ``out[k] = (bolt triangle, nut
    triangle, tag)``; returns how many (as :func:`_crossing`: those past ``out``'s rows
    counted, not written; in :data:`ANY` ``mode`` the first only). Each pair is tested as
    :func:`_crossing` tests it, the nut's triangles moved into the bolt's frame by the same
    arithmetic: a walk at this pose that reaches those leaves finds the same pairs. With
    a ``drop`` (fixed frame), the pairs that meet as the bolt is lowered from the pose by
    up to that: in the bolt's frame the nut rises along the fixed vertical, and each nut
    triangle sweeps a prism (:func:`_cross_over`)."""
    bleaf, bsize, btri = b[5], b[6], b[7]
    nleaf, nsize, ntri = n[5], n[6], n[7]
    rt = rotation.T.copy()
    tt = np.empty(3)
    lift = np.empty(3)
    for a in range(3):
        tt[a] = -(rt[a, 0] * origin[0] + rt[a, 1] * origin[1] + rt[a, 2] * origin[2])
        lift[a] = rt[a, 2] * drop
    w = np.empty((14, 3))
    moved = np.empty((3, 3))
    count = 0
    for r in range(len(nodes)):
        i, j = nodes[r, 0], nodes[r, 1]
        for q in range(nleaf[j], nleaf[j] + nsize[j]):
            for v in range(3):
                _moved(rt, tt, ntri[q, v], moved[v])
            for p in range(bleaf[i], bleaf[i] + bsize[i]):
                if (
                    _cross_over(btri[p], moved, lift, w)
                    if drop > 0.0
                    else _cross(btri[p], moved, w)
                ):
                    if count < len(out):
                        out[count, 0], out[count, 1], out[count, 2] = p, q, nodes[r, 2]
                    count += 1
                    if mode == ANY:
                        return count
    return count


def _arrays(forest: ObbForest) -> _Arrays:
    """A forest's arrays as :func:`_crossing` takes them."""
    f = forest
    return (f.centre, f.axes, f.extent, f.left, f.right, f.leaf, f.size, f.triangles)


class CrossingQuery:
    """The crossing pairs of a bolt's trees and a nut's forest (:func:`_crossing`), with the
    buffers a query reuses.

    Parameters
    ----------
    nut : ObbForest
        The nut's trees, in the fixed frame.
    """

    def __init__(self, nut: ObbForest) -> None:
        self.nut = nut
        self._n = _arrays(nut)
        self._moved = (
            np.empty_like(nut.centre),
            np.empty_like(nut.axes),
            np.empty_like(nut.triangles),
            np.zeros((len(nut.centre), 2), dtype=np.int64),
            np.empty_like(nut.centre),
            np.empty_like(nut.extent),
        )
        self._stamp = 0
        self._out = np.empty((1024, 3), dtype=np.int64)
        self._kept = np.empty((4097, 3), dtype=np.int64)

    def __call__(
        self,
        bolt: ObbForest,
        tree: int,
        trees: NDArray[np.int64],
        rotation: NDArray[np.float64],
        origin: NDArray[np.float64],
        mode: int = ALL,
    ) -> NDArray[np.int64]:
        """``(bolt face, nut face, position in trees)`` of each crossing pair of the bolt's
        tree ``tree`` at the pose ``(rotation, origin)`` and the nut's ``trees`` (indices
        of its roots), asked in that order; in :data:`ANY` or :data:`EACH` ``mode``, the
        first pair found (of each tree)."""
        found, rows = self._walk(bolt, tree, trees, rotation, origin, mode, origin, True)
        return rows

    def among(
        self,
        bolt: ObbForest,
        nodes: NDArray[np.int64],
        rotation: NDArray[np.float64],
        origin: NDArray[np.float64],
        mode: int = ALL,
        drop: float = 0.0,
    ) -> NDArray[np.int64]:
        """``(bolt face, nut face, tag)`` of each crossing pair of the leaf pairs ``nodes``
        (rows ``(bolt node, nut node, tag)``, as :meth:`below` keeps them) at the pose
        ``(rotation, origin)``; in :data:`ANY` ``mode``, the first pair found. With a
        ``drop``, the pairs that meet as the bolt is lowered from that pose by up to it
        (:func:`_among`; those it meets within the drop, and any only touching at its ends
        within rounding)."""
        b = _arrays(bolt)
        rotation = np.ascontiguousarray(rotation, dtype=float)
        origin = np.ascontiguousarray(origin, dtype=float)
        while True:
            found = _among(b, self._n, nodes, rotation, origin, mode, self._out, float(drop))
            if found <= len(self._out):
                break
            self._out = np.empty((2 * found, 3), dtype=np.int64)
        return self._faces(bolt, self._out[:found])

    def below(
        self,
        bolt: ObbForest,
        tree: int,
        trees: NDArray[np.int64],
        rotation: NDArray[np.float64],
        origin: NDArray[np.float64],
        above: NDArray[np.float64],
        free: bool = False,
    ) -> tuple[bool, NDArray[np.int64], NDArray[np.int64]]:
        """Whether the bolt at ``(rotation, above)`` crosses the nut's ``trees`` (not asked
        where it is known ``free``), and, where it does not, the crossing pairs at
        ``(rotation, origin)`` (as :meth:`__call__`); where it does, the first pair found
        there. One walk answers both. And the leaf pairs whose boxes, swept between the
        two origins, met: ``(bolt node, nut node, position in trees)`` rows, among which
        lie the pairs crossing at any origin between (:meth:`among`; empty where
        ``above`` crosses)."""
        found, rows = self._walk(bolt, tree, trees, rotation, origin, ALL, above, free)
        kept = self._kept[1 : 1 + self._kept[0, 0]] if found >= 0 else self._kept[:0]
        return found < 0, rows, kept.copy()

    def _walk(
        self,
        bolt: ObbForest,
        tree: int,
        trees: NDArray[np.int64],
        rotation: NDArray[np.float64],
        origin: NDArray[np.float64],
        mode: int,
        above: NDArray[np.float64],
        free: bool,
    ) -> tuple[int, NDArray[np.int64]]:
        b = _arrays(bolt)
        roots = self.nut.roots[trees]
        rotation = np.ascontiguousarray(rotation, dtype=float)
        origin = np.ascontiguousarray(origin, dtype=float)
        above = np.ascontiguousarray(above, dtype=float)
        while True:
            self._stamp += 1
            found = _crossing(
                b,
                int(bolt.roots[tree]),
                self._n,
                roots,
                rotation,
                origin,
                mode,
                self._out,
                self._moved,
                self._stamp,
                above,
                self._kept,
                free,
            )
            if found < 0:
                break
            if found > len(self._out):
                self._out = np.empty((2 * found, 3), dtype=np.int64)
            elif self._kept[0, 0] >= len(self._kept):
                self._kept = np.empty((2 * self._kept[0, 0] + 1, 3), dtype=np.int64)
            else:
                break
        rows = self._out[:1] if found < 0 else self._out[:found]  # -1: the pair at ``above``
        return found, self._faces(bolt, rows)

    def _faces(self, bolt: ObbForest, rows: NDArray[np.int64]) -> NDArray[np.int64]:
        """``rows`` of triangles (the forests' rows) as the meshes' faces."""
        faces = np.empty_like(rows)
        faces[:, 0] = bolt.faces[rows[:, 0]]
        faces[:, 1] = self.nut.faces[rows[:, 1]]
        faces[:, 2] = rows[:, 2]
        return faces


@compiled
def unique_face_pairs(found: NDArray[np.int64]) -> NDArray[np.int64]:
    """The distinct ``(bolt_face, nut_face)`` pairs of a query's rows (faces, as
    :meth:`CrossingQuery.__call__` gives them), sorted bolt face major: one integer key
    each (bolt face times :data:`PAIR_KEY` plus nut face), whose sort orders them as the
    rows' lexicographic order would. Compiled: asked at every query, of a few hundred
    rows, where numpy's per-call cost is most of the work."""
    keys = np.empty(found.shape[0], dtype=np.int64)
    for i in range(found.shape[0]):
        keys[i] = found[i, 0] * PAIR_KEY + found[i, 1]
    keys.sort()
    m = 0
    for i in range(keys.shape[0]):
        if m == 0 or keys[i] != keys[m - 1]:
            keys[m] = keys[i]
            m += 1
    pairs = np.empty((m, 2), dtype=np.int64)
    for i in range(m):
        pairs[i, 0] = keys[i] // PAIR_KEY
        pairs[i, 1] = keys[i] % PAIR_KEY
    return pairs
