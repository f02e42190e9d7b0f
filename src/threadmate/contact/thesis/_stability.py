"""Classification of the fixed-pivot contact states by the thesis's own criteria (4.2).

The contact stages (:mod:`._stages`) are the thesis's FIXED-PIVOT procedure: each stage
turns the bolt about an axis fixed in space (the nut's tangent at the first contact, then
the pivot axis through the two contacts) and the compliance holding the bolt is ignored.
The classes below are the thesis's criteria of its section 4.2 ("Contact Embedment
Analysis") applied to that procedure, so that its results compare like for like. They are
not the physical model: rest states of the bolt under its load and compliance are the
mechanics' (``threadmate settle`` / ``threadmate search``).

Quantities, all in the spec's units:

- ``interference``: depth of interference (embedding) at the third stage's pose, computed
  from the EXACT bodies: the largest :meth:`ThreadBody.depth` (distance inside the
  material) of points of the bolt mesh inside the exact nut and of points of the nut mesh
  inside the exact bolt. The points are every mesh vertex within ``radius`` (a quarter
  pitch) of the contacts' intersection segments plus a barycentric sampling (15 points) of
  every intersecting triangle, so edge-on-edge embedding between vertices is seen too.
  Mesh points lie within the mesh deviation of the exact surface, so values below a few
  chord tolerances are noise: ``interference_tolerance`` (default four mesh-deviation
  bounds) is the floor below which no embedding is resolved.
- ``origin_drop``: height of the bolt origin at the second stage minus that at the third
  (positive down).
- ``pivot_offset``: distance from the compliance centre to the pivot axis (the line
  through the two contacts of the second stage).
- ``rolling`` (the thesis's *rolling* axis, reported beside the class): the pivot axis
  "acquires more triangles at one or both of the original points once rotation about the
  pivot axis commences", i.e. a pivot contact (either of the second stage's two contacts)
  has more triangle pairs at the third stage than at the second (:func:`is_rolling`).

Classes, decided in this order:

1. ``no-contact``: the first stage found nothing, or the second did;
2. ``in-phase``: the bolt dropped into the nut: at the first contact its whole tip face
   (every point of its tip rim) lies below the nut's top face by more than the feature
   tolerance, so it came down inside the bore until flank met flank. The snap (for an
   upright bolt, the in-phase window of the planar analysis); the later stages are not run;
3. ``quasi-stable`` (quasi-stable two-point, thesis 4.2.2): the pivot axis passes within
   ``quasi_tolerance`` (default a tenth of the pitch) of the compliance centre, where the
   axial load has (almost) no moment about it;
4. ``no-contact``: the third stage found nothing within its range;
5. ``unstable`` (unstable two-point, thesis 4.2.1): the third contact was reached with an
   ``interference`` LARGER than ``origin_drop``: the bolt embedded in the nut deeper than
   its origin dropped, "we located a third contact point by doing something impossible".
   An interference within ``interference_tolerance`` (mesh noise) counts as none, so the
   rule is ``interference > max(origin_drop, interference_tolerance)``;
6. ``stable`` (stable three-point, thesis 4.2.3): otherwise; the origin dropped at least as
   much as the bolt embedded (it released potential energy).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from ...geometry import Pose, ThreadBody
from ..scene import IN_PHASE, NO_CONTACT, QUASI_STABLE, STABLE, UNSTABLE

__all__ = ["interference_depth", "classify", "pivot_offset", "is_rolling"]

# Barycentric sample of a triangle: 15 points (a 4-division grid).
_N = 4
_BARY = (
    np.array([(i, j, _N - i - j) for i in range(_N + 1) for j in range(_N + 1 - i)], dtype=float)
    / _N
)


def _sample(tris: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.einsum("kv,nvj->nkj", _BARY, tris).reshape(-1, 3)


def _within(tree: cKDTree, points: NDArray[np.float64], radius: float) -> NDArray[np.intp]:
    """Indices of the tree's points within ``radius`` of any of ``points``."""
    # Ends closer than a thousandth of the radius find the same neighbours, near enough.
    points = np.unique(np.round(points / (1e-3 * radius)), axis=0) * (1e-3 * radius)
    found = tree.query_ball_point(points, radius + 1e-3 * radius, return_sorted=False)
    if len(found) == 0:
        return np.empty(0, dtype=np.intp)
    return np.unique(np.concatenate([np.asarray(f, dtype=np.intp) for f in found]))


def interference_depth(
    bolt: ThreadBody,
    nut: ThreadBody,
    pose: Pose,
    bolt_vertices: NDArray[np.float64],
    bolt_tree: cKDTree,
    nut_vertices: NDArray[np.float64],
    nut_tree: cKDTree,
    bolt_tris_b: NDArray[np.float64],
    nut_tris_f: NDArray[np.float64],
    ends_f: NDArray[np.float64],
    radius: float,
) -> float:
    """Depth of interference at ``pose`` (see the module docstring).

    ``bolt_tris_b`` are the intersecting bolt triangles in the bolt frame, ``nut_tris_f``
    the nut's in F, ``ends_f`` the intersection segment ends in F.
    """
    if len(ends_f) == 0:
        return 0.0
    ends_b = pose.to_bolt(ends_f)
    ib = _within(bolt_tree, ends_b, radius)
    i_n = _within(nut_tree, ends_f, radius)
    pts_b = np.concatenate([bolt_vertices[ib].reshape(-1, 3), _sample(bolt_tris_b)])
    pts_n = np.concatenate([nut_vertices[i_n].reshape(-1, 3), _sample(nut_tris_f)])
    d_bolt_in_nut = nut.depth(pose.to_fixed(pts_b)) if len(pts_b) else np.zeros(1)
    d_nut_in_bolt = bolt.depth(pose.to_bolt(pts_n)) if len(pts_n) else np.zeros(1)
    return float(max(d_bolt_in_nut.max(initial=0.0), d_nut_in_bolt.max(initial=0.0)))


def pivot_offset(
    p1: NDArray[np.float64], p2: NDArray[np.float64], centre: NDArray[np.float64]
) -> float:
    """Distance from ``centre`` to the line through ``p1`` and ``p2``."""
    a = np.asarray(p2, float) - np.asarray(p1, float)
    n = np.linalg.norm(a)
    if n == 0:
        return float(np.linalg.norm(np.asarray(centre, float) - p1))
    return float(np.linalg.norm(np.cross(np.asarray(centre, float) - p1, a / n)))


def is_rolling(second_pairs: Sequence[int], third_pairs: Sequence[int]) -> bool:
    """The thesis's rolling axis: a pivot contact gained triangle pairs from the second
    stage (``second_pairs``, one count per pivot contact) to the third (``third_pairs``,
    the same contacts in the same order)."""
    return any(b > a for a, b in zip(second_pairs, third_pairs, strict=True))


def classify(
    *,
    first_found: bool,
    in_phase: bool,
    second_found: bool,
    offset: float,
    third_found: bool,
    interference: float,
    origin_drop: float,
    quasi_tolerance: float,
    interference_tolerance: float,
) -> str:
    """The classification rules of the module docstring, in order."""
    if not first_found:
        return NO_CONTACT
    if in_phase:
        return IN_PHASE
    if not second_found:
        return NO_CONTACT
    if offset <= quasi_tolerance:
        return QUASI_STABLE
    if not third_found:
        return NO_CONTACT
    if interference > max(origin_drop, interference_tolerance):
        return UNSTABLE
    return STABLE
