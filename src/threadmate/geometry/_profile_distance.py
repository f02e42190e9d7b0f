"""The distance from points to a thread profile, compiled
(:meth:`threadmate.geometry.Profile.distance`).

Every mesh generated is measured against the exact profile at several points of each
triangle (:func:`threadmate.geometry.mesh_deviation`): one loop over the points, the three
pitches around each and the profile's pieces. Apart from :mod:`._profile` so that the
package imports without numba until a distance is asked.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from .._compiled import compiled

__all__ = ["profile_distance"]


@compiled
def profile_distance(
    t: NDArray[np.float64],
    r: NDArray[np.float64],
    pitch: float,
    p0: NDArray[np.float64],
    d: NDArray[np.float64],
    inv_dd: NDArray[np.float64],
    centre: NDArray[np.float64],
    rho: NDArray[np.float64],
    lo: NDArray[np.float64],
    hi: NDArray[np.float64],
    side: NDArray[np.float64],
    bulge: NDArray[np.float64],
) -> NDArray[np.float64]:
    """:meth:`~threadmate.geometry.Profile.distance` of wrapped ``t`` and ``r`` over the
    profile's pieces (``Profile._pieces``), each point against the pieces of its own pitch
    and the two beside it. A NaN coordinate gives NaN. Compiled, ``math.hypot`` is the C
    library's, as numpy's ``hypot``; without numba, Python's own may differ in the last
    bit."""
    out = np.empty(t.shape[0])
    for i in range(t.shape[0]):
        if t[i] != t[i] or r[i] != r[i]:
            out[i] = np.nan
            continue
        best = np.inf
        for k in range(3):
            u = t[i] + (k - 1) * pitch
            for j in range(p0.shape[0]):
                du = u - p0[j, 0]
                dr = r[i] - p0[j, 1]
                w = min(max((du * d[j, 0] + dr * d[j, 1]) * inv_dd[j], 0.0), 1.0)
                a, b = du - w * d[j, 0], dr - w * d[j, 1]
                # ``hypot`` only where it can be the least: a sum of squares a billionth
                # above the least's square is farther by far more than the two differ in
                # rounding.
                if a * a + b * b <= best * best * (1.0 + 1e-9):
                    v = math.hypot(a, b)
                    if v < best:
                        best = v
            for j in range(rho.shape[0]):
                # The nearest point of an arc's circle is on the ray from its centre
                # through the point; it is the arc's when it lies within the arc's span
                # of u and on the arc's side of the centre (above it at the major corner,
                # below at the minor). Elsewhere an end point is nearest, and the end
                # points are pieces of their own.
                du = u * side[j] - centre[j, 0]  # the negative side mirrored onto u >= 0
                dr = r[i] - centre[j, 1]
                dist = math.hypot(du, dr)
                if not dist > 0.0 or dr * bulge[j] < 0.0:
                    continue
                qu = centre[j, 0] + rho[j] * du / dist
                if qu >= lo[j] and qu <= hi[j]:
                    v = abs(dist - rho[j])
                    if v < best:
                        best = v
        out[i] = best
    return out
