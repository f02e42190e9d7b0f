"""Contact location from intersecting triangle pairs (thesis 3.5-3.6, vectorised).

Two intersecting triangles meet along a segment of the line where their planes cross. The
thesis bounds that line by the bolt triangle, then by the nut triangle, and takes the
midpoint; we do the same in one step for all pairs at once: each triangle's crossing of the
other's plane is an interval of the common line, and the intersection segment is the
overlap of the two intervals.

Distinct contacts are clusters of pairs separated in space. The rule: single linkage on
the END POINTS of the intersection segments with the link distance ``separation``
(default a quarter of the pitch). The segments of one contact chain end to end along the
closed curve where the two meshes cross, so linking end points (not midpoints) keeps one
contact whole however long its triangles are (flank triangles of a fine mesh are thin
slivers up to a flank's length); two contacts are distinct when no chain of segment end
points joins them in steps shorter than ``separation``.

A contact's location is the point of its intersection segments nearest to the
length-weighted mean of their midpoints. The mean is the thesis's average of midpoints
(weighted, so that a sliver pair that barely touches does not pull it); snapping it onto
the segments keeps the location on both meshes even when the crossing curve is curved or
long (a flank lying on a flank), where the mean itself would float off both surfaces.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

__all__ = [
    "IntersectionSegments",
    "intersection_segments",
    "cluster_segments",
    "cluster_location",
    "touch_points",
]

_EDGES = ((0, 1), (1, 2), (2, 0))


@dataclass(frozen=True)
class IntersectionSegments:
    """Intersection segments of ``n`` triangle pairs (fixed frame).

    Attributes
    ----------
    start, end : (n, 3) arrays
        Segment end points. For a pair whose triangles do not actually cross (the
        collision query reports pairs that only touch, within rounding, the thesis's
        fourth case, or the triangles are coplanar) both are the midpoint of the closest
        points of the two triangles: where they touch.
    valid : (n,) bool array
        Whether the pair has a proper intersection segment.
    """

    start: NDArray[np.float64]
    end: NDArray[np.float64]
    valid: NDArray[np.bool_]

    @property
    def midpoint(self) -> NDArray[np.float64]:
        """Segment midpoints."""
        return 0.5 * (self.start + self.end)

    @property
    def length(self) -> NDArray[np.float64]:
        """Segment lengths (0 for pairs without a proper segment)."""
        return np.linalg.norm(self.end - self.start, axis=-1)

    def __len__(self) -> int:
        return len(self.valid)


def _plane_crossing(
    tri: NDArray[np.float64],
    normal: NDArray[np.float64],
    offset: NDArray[np.float64],
    direction: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
    """Where each triangle's edges cross the other triangle's plane.

    Returns the crossing points ``(n, 3, 3)``, their parameters along ``direction``
    (``(n, 3)``, +inf/-inf-free: invalid ones are NaN) and the validity mask.
    """
    s = np.einsum("nij,nj->ni", tri, normal) - offset[:, None]  # signed plane distances
    pts = np.empty((len(tri), 3, 3))
    ok = np.zeros((len(tri), 3), dtype=bool)
    for k, (i, j) in enumerate(_EDGES):
        si, sj = s[:, i], s[:, j]
        crosses = (si * sj < 0.0) | ((si == 0.0) & (sj != 0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            w = np.where(crosses, si / (si - sj), 0.0)
        pts[:, k] = tri[:, i] + w[:, None] * (tri[:, j] - tri[:, i])
        ok[:, k] = crosses
    par = np.einsum("nkj,nj->nk", pts, direction)
    return pts, par, ok


def intersection_segments(
    bolt_tris: NDArray[np.float64], nut_tris: NDArray[np.float64]
) -> IntersectionSegments:
    """Intersection segments of bolt/nut triangle pairs (each ``(n, 3, 3)``, fixed frame).

    Parameters
    ----------
    bolt_tris, nut_tris : (n, 3, 3) arrays
        Vertices of the paired triangles, in the same frame.

    Returns
    -------
    IntersectionSegments
    """
    a = np.asarray(bolt_tris, dtype=float).reshape(-1, 3, 3)
    b = np.asarray(nut_tris, dtype=float).reshape(-1, 3, 3)
    na = np.cross(a[:, 1] - a[:, 0], a[:, 2] - a[:, 0])
    nb = np.cross(b[:, 1] - b[:, 0], b[:, 2] - b[:, 0])
    d = np.cross(na, nb)
    dn = np.linalg.norm(d, axis=-1)
    scale = np.linalg.norm(na, axis=-1) * np.linalg.norm(nb, axis=-1)
    skew = dn > 1e-12 * np.maximum(scale, 1e-300)
    d = d / np.where(dn > 0, dn, 1.0)[:, None]

    pa, ta, oka = _plane_crossing(a, nb, np.einsum("nj,nj->n", nb, b[:, 0]), d)
    pb, tb, okb = _plane_crossing(b, na, np.einsum("nj,nj->n", na, a[:, 0]), d)
    big = np.inf
    ta_lo = np.where(oka, ta, big)
    ta_hi = np.where(oka, ta, -big)
    tb_lo = np.where(okb, tb, big)
    tb_hi = np.where(okb, tb, -big)
    ia_lo, ia_hi = ta_lo.argmin(1), ta_hi.argmax(1)
    ib_lo, ib_hi = tb_lo.argmin(1), tb_hi.argmax(1)
    rows = np.arange(len(a))
    a_lo, a_hi = ta_lo[rows, ia_lo], ta_hi[rows, ia_hi]
    b_lo, b_hi = tb_lo[rows, ib_lo], tb_hi[rows, ib_hi]
    # The overlap of the two intervals: its low end is the larger of the two low ends.
    start = np.where((a_lo >= b_lo)[:, None], pa[rows, ia_lo], pb[rows, ib_lo])
    end = np.where((a_hi <= b_hi)[:, None], pa[rows, ia_hi], pb[rows, ib_hi])
    lo = np.maximum(a_lo, b_lo)
    hi = np.minimum(a_hi, b_hi)
    valid = skew & oka.any(1) & okb.any(1) & np.isfinite(lo) & np.isfinite(hi) & (lo <= hi)
    fallback = np.zeros((len(a), 3))
    if not valid.all():
        fallback[~valid] = touch_points(a[~valid], b[~valid])
    start = np.where(valid[:, None], start, fallback)
    end = np.where(valid[:, None], end, fallback)
    return IntersectionSegments(start, end, valid)


def _closest_on_segments(
    p0: NDArray[np.float64],
    p1: NDArray[np.float64],
    q0: NDArray[np.float64],
    q1: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Closest points of segment pairs (vectorised; Ericson, Real-Time Collision Detection
    5.1.9), returned as (points on p, points on q)."""
    d1, d2, r = p1 - p0, q1 - q0, p0 - q0
    a = np.einsum("...j,...j->...", d1, d1)
    e = np.einsum("...j,...j->...", d2, d2)
    f = np.einsum("...j,...j->...", d2, r)
    c = np.einsum("...j,...j->...", d1, r)
    b = np.einsum("...j,...j->...", d1, d2)
    denom = a * e - b * b
    tiny = 1e-300
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(denom > tiny, np.clip((b * f - c * e) / denom, 0, 1), 0.0)
        t = np.where(e > tiny, (b * s + f) / e, 0.0)
        s = np.where(t < 0, np.where(a > tiny, np.clip(-c / a, 0, 1), 0.0), s)
        s = np.where(t > 1, np.where(a > tiny, np.clip((b - c) / a, 0, 1), 0.0), s)
        t = np.clip(t, 0, 1)
    return p0 + s[..., None] * d1, q0 + t[..., None] * d2


def _vertex_on_face(
    v: NDArray[np.float64], tri: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Projections of vertices ``v`` (n, 3, 3) onto the planes of ``tri`` (n, 3, 3), with
    their distances (inf where the projection falls outside the triangle)."""
    e0, e1 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    n = np.cross(e0, e1)
    nn = np.einsum("nj,nj->n", n, n)
    w = v - tri[:, None, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        h = np.einsum("nkj,nj->nk", w, n) / nn[:, None]
        proj = v - h[..., None] * n[:, None]
        q = proj - tri[:, None, 0]
        d00, d01, d11 = (e0 * e0).sum(1), (e0 * e1).sum(1), (e1 * e1).sum(1)
        d20 = np.einsum("nkj,nj->nk", q, e0)
        d21 = np.einsum("nkj,nj->nk", q, e1)
        den = (d00 * d11 - d01 * d01)[:, None]
        bv = (d11[:, None] * d20 - d01[:, None] * d21) / den
        bw = (d00[:, None] * d21 - d01[:, None] * d20) / den
    inside = (bv >= 0) & (bw >= 0) & (bv + bw <= 1) & (nn[:, None] > 0)
    dist = np.where(inside, np.abs(h) * np.sqrt(nn)[:, None], np.inf)
    return proj, dist


def touch_points(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """Midpoints of the closest points of triangle pairs ``a``, ``b`` (each (n, 3, 3)).

    The closest points of two disjoint triangles are a vertex and its projection inside
    the other triangle, or the closest points of two edges; all 15 candidates are tried.
    """
    cands, dists = [], []
    for v, tri in ((a, b), (b, a)):
        proj, dist = _vertex_on_face(v, tri)
        cands.append(0.5 * (v + proj))
        dists.append(dist)
    for i, j in _EDGES:
        for k, m in _EDGES:
            pa, pb = _closest_on_segments(a[:, i], a[:, j], b[:, k], b[:, m])
            cands.append(0.5 * (pa + pb)[:, None])
            dists.append(np.linalg.norm(pa - pb, axis=-1)[:, None])
    pts = np.concatenate(cands, axis=1)
    dist = np.nan_to_num(np.concatenate(dists, axis=1), nan=np.inf)
    return pts[np.arange(len(a)), dist.argmin(1)]


def cluster_segments(segments: IntersectionSegments, separation: float) -> NDArray[np.intp]:
    """Label each pair with its distinct contact (0, 1, ...; see the module docstring).

    Labels are ordered by first appearance, so they are stable for a given pair order.
    """
    n = len(segments)
    if n == 0:
        return np.empty(0, dtype=np.intp)
    pts = np.concatenate([segments.start, segments.end])
    labels: NDArray[np.integer]
    if n <= 64:  # a few pairs: union-find beats building a sparse graph
        links = cKDTree(pts).query_pairs(separation, output_type="ndarray").reshape(-1, 2)
        parent = list(range(n))

        def root(i: int) -> int:
            while parent[i] != i:
                parent[i] = parent[parent[i]]
                i = parent[i]
            return i

        for a, b in (links % n).tolist():  # end k + n belongs to pair k
            ra, rb = root(a), root(b)
            if ra != rb:
                parent[max(ra, rb)] = min(ra, rb)
        labels = np.array([root(i) for i in range(n)])
    else:
        point = _linked(pts, separation)
        # A segment joins its two ends' components.
        joined = _components(int(point.max()) + 1, np.column_stack([point[:n], point[n:]]))
        labels = joined[point[:n]]
    _, first, inverse = np.unique(labels, return_index=True, return_inverse=True)
    order = np.argsort(np.argsort(first))
    return order[inverse].astype(np.intp)


def _components(count: int, links: NDArray[np.integer]) -> NDArray[np.int32]:
    graph = coo_matrix((np.ones(len(links)), (links[:, 0], links[:, 1])), shape=(count, count))
    return connected_components(graph, directed=False)[1]


def _linked(pts: NDArray[np.float64], separation: float) -> NDArray[np.int32]:
    """Component label of each point, points within ``separation`` being linked.

    Dense contact patches (a tip face flat on the top face: thousands of points) would
    give millions of links at the full separation. Components at half of it are found
    first (a quarter of the links in a plane), then merged where two come within the
    separation; should many remain, the links at the full separation are used.
    """
    tree = cKDTree(pts)
    half = tree.query_pairs(separation / 2, output_type="ndarray").reshape(-1, 2)
    labels = _components(len(pts), half)
    count = labels.max() + 1
    if count == 1:
        return labels
    if count > 8:
        full = tree.query_pairs(separation, output_type="ndarray").reshape(-1, 2)
        return _components(len(pts), full)
    groups = [np.flatnonzero(labels == k) for k in range(count)]
    trees = [cKDTree(pts[g]) for g in groups]
    merge = []
    for i in range(count):
        for j in range(i + 1, count):
            dist, _ = trees[j].query(pts[groups[i]], distance_upper_bound=separation)
            if np.isfinite(dist).any():
                merge.append((i, j))
    return _components(count, np.array(merge, dtype=np.intp).reshape(-1, 2))[labels]


def cluster_location(segments: IntersectionSegments) -> NDArray[np.float64]:
    """Location of one contact from its pairs' segments (see the module docstring)."""
    mid = segments.midpoint
    w = segments.length
    if not segments.valid.any():
        return mid.mean(0)
    w = np.where(segments.valid, w, 0.0)
    # A pair that only touches at a point still counts, slightly.
    w = w + 1e-3 * (w.max() if w.max() > 0 else 1.0) * segments.valid
    centre = (w[:, None] * mid).sum(0) / w.sum()
    s0, s1 = segments.start[segments.valid], segments.end[segments.valid]
    seg = s1 - s0
    ll = np.einsum("ij,ij->i", seg, seg)
    with np.errstate(divide="ignore", invalid="ignore"):
        u = np.clip(np.where(ll > 0, np.einsum("ij,ij->i", centre - s0, seg) / ll, 0.0), 0, 1)
    near = s0 + u[:, None] * seg
    return near[np.argmin(np.linalg.norm(near - centre, axis=1))]
