"""Stability of the contact state (thesis 4.2, made precise).

Quantities, all in the spec's units:

- ``interference``: depth of interference at the third stage's pose, computed from the
  EXACT bodies: the largest :meth:`ThreadBody.depth` (distance inside the material) of
  points of the bolt mesh inside the exact nut and of points of the nut mesh inside the
  exact bolt. The points are every mesh vertex within ``radius`` (a quarter pitch) of
  the contacts' intersection segments plus a barycentric sampling (15 points) of
  every intersecting triangle, so edge-on-edge embedding between vertices is seen too.
  Mesh points lie within the mesh deviation of the exact surface, so values below a few
  chord tolerances are noise.
- ``origin_drop``: height of the bolt origin at the second stage minus that at the third.
- ``pivot_offset``: distance from the compliance centre to the pivot axis (the line
  through the two contacts of the second stage).

Classes, decided in this order:

1. ``no-contact``: the first stage found nothing, or the second did;
2. ``in-phase``: the bolt dropped into the nut: at the first contact its whole tip face
   (every point of its tip rim) lies below the nut's top face by more than the feature
   tolerance, so it came down inside the bore until flank met flank. The snap (for an
   upright bolt, the in-phase window of the planar analysis); the later stages are not run;
3. ``quasi-stable`` (two-point): the pivot axis passes within ``quasi_tolerance``
   (default a tenth of the pitch) of the compliance centre, where the axial load has
   (almost) no moment about it;
4. ``no-contact``: the third stage found nothing within its range;
5. ``stable`` (three-point): the third contact is reached with ``interference`` within
   ``interference_tolerance`` (default four chord tolerances);
6. ``unstable`` (two-point): otherwise; the third contact needed the bolt to embed. The
   thesis's strict case is ``interference > origin_drop`` (embedded deeper than the origin
   dropped); an embedding that the drop exceeds still is not a rest pose of rigid bodies,
   so it is reported ``unstable`` too, and the record keeps both numbers.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from ..geometry import Pose, ThreadBody

__all__ = ["interference_depth", "classify", "pivot_offset"]

# Barycentric sample of a triangle: 15 points (a 4-division grid).
_N = 4
_BARY = np.array([(i, j, _N - i - j) for i in range(_N + 1) for j in range(_N + 1 - i)],
                 dtype=float) / _N


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


def interference_depth(bolt: ThreadBody, nut: ThreadBody, pose: Pose,
                       bolt_vertices: NDArray[np.float64], bolt_tree: cKDTree,
                       nut_vertices: NDArray[np.float64], nut_tree: cKDTree,
                       bolt_tris_b: NDArray[np.float64], nut_tris_f: NDArray[np.float64],
                       ends_f: NDArray[np.float64], radius: float) -> float:
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


def pivot_offset(p1: NDArray[np.float64], p2: NDArray[np.float64],
                 centre: NDArray[np.float64]) -> float:
    """Distance from ``centre`` to the line through ``p1`` and ``p2``."""
    a = np.asarray(p2, float) - np.asarray(p1, float)
    n = np.linalg.norm(a)
    if n == 0:
        return float(np.linalg.norm(np.asarray(centre, float) - p1))
    return float(np.linalg.norm(np.cross(np.asarray(centre, float) - p1, a / n)))


def classify(*, first_found: bool, in_phase: bool, second_found: bool, offset: float,
             third_found: bool, interference: float, quasi_tolerance: float,
             interference_tolerance: float) -> str:
    """The classification rules of the module docstring, in order."""
    if not first_found:
        return "no-contact"
    if in_phase:
        return "in-phase"
    if not second_found:
        return "no-contact"
    if offset <= quasi_tolerance:
        return "quasi-stable"
    if not third_found:
        return "no-contact"
    if interference <= interference_tolerance:
        return "stable"
    return "unstable"
