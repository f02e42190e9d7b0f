"""How far a bolt triangle comes down before it meets a nut triangle (exact, vectorised).

Lowering the bolt by ``d`` along -Z brings a bolt point ``a`` onto a nut point ``b`` when
``a_xy = b_xy`` and ``d = a_z - b_z``. Over the overlap of two triangles' projections on
the XY plane, ``a_z - b_z`` is a linear function, so its least value, the drop at which
the two first touch, sits at a vertex of the overlap polygon: a vertex of one triangle
inside the other's projection, or a crossing of two edges' projections. Every candidate
is evaluated and the least kept. A pair whose projections do not overlap never touches
(``inf``).

This turns one python-fcl pair enumeration below a collision-free pose into the exact
drop at which the meshes first touch, and the vertical gap of every other contact within
that depth, without bisection.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["vertical_touch"]

#: The end of each triangle edge that starts at vertex 0, 1, 2: edges (0, 1), (1, 2), (2, 0).
_NEXT = [1, 2, 0]


def _inside(
    tri: NDArray[np.float64], pts: NDArray[np.float64]
) -> tuple[NDArray[np.bool_], NDArray[np.float64]]:
    """Which of ``pts`` (n, k, 2) lie in the XY projection of ``tri`` (n, 3, 3), and the
    triangle's height there (NaN outside or for an edge-on triangle)."""
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    e0, e1 = (b - a)[:, :2], (c - a)[:, :2]
    det = e0[:, 0] * e1[:, 1] - e0[:, 1] * e1[:, 0]
    scale = np.einsum("ij,ij->i", e0, e0) + np.einsum("ij,ij->i", e1, e1)
    ok = np.abs(det) > 1e-12 * np.maximum(scale, 1e-300)
    safe = np.where(ok, det, 1.0)[:, None]
    w = pts - a[:, None, :2]
    u = (w[..., 0] * e1[:, None, 1] - w[..., 1] * e1[:, None, 0]) / safe
    v = (e0[:, None, 0] * w[..., 1] - e0[:, None, 1] * w[..., 0]) / safe
    inside = ok[:, None] & (u >= 0) & (v >= 0) & (u + v <= 1)
    z = a[:, None, 2] + u * (b - a)[:, None, 2] + v * (c - a)[:, None, 2]
    return inside, np.where(inside, z, np.nan)


def vertical_touch(
    bolt_tris: NDArray[np.float64], nut_tris: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Drop at which each bolt triangle first meets its nut triangle, and where.

    Parameters
    ----------
    bolt_tris, nut_tris : (n, 3, 3) arrays
        Paired triangles in the fixed frame, the bolt's at the pose lowering starts from.

    Returns
    -------
    drop : (n,) array
        Least downward translation of the bolt triangle that makes it touch the nut
        triangle (``inf`` when their projections do not overlap; negative when they
        already cross at the starting pose).
    point : (n, 3) array
        The touching point on the nut triangle (fixed frame; NaN with an ``inf`` drop).
    """
    a = np.asarray(bolt_tris, dtype=float).reshape(-1, 3, 3)
    b = np.asarray(nut_tris, dtype=float).reshape(-1, 3, 3)
    n = len(a)
    cands_d, cands_p = [], []
    # Bolt vertices over the nut triangle.
    inside, zb = _inside(b, a[:, :, :2])
    cands_d.append(np.where(inside, a[:, :, 2] - zb, np.inf))
    cands_p.append(np.concatenate([a[:, :, :2], zb[..., None]], axis=-1))
    # Nut vertices under the bolt triangle.
    inside, za = _inside(a, b[:, :, :2])
    cands_d.append(np.where(inside, za - b[:, :, 2], np.inf))
    cands_p.append(b)
    # Crossings of edge projections: all nine edge pairs at once, bolt edge (i, j) by nut
    # edge (k, m) in row-major order (the order of the candidates decides ties).
    p = a[:, :, None, :]  # (n, 3, 1, 3): bolt edge starts
    r = (a[:, _NEXT] - a)[:, :, None, :]
    q = b[:, None, :, :]  # (n, 1, 3, 3): nut edge starts
    s = (b[:, _NEXT] - b)[:, None, :, :]
    den = r[..., 0] * s[..., 1] - r[..., 1] * s[..., 0]
    ok = np.abs(den) > 1e-14 * np.maximum(
        np.hypot(r[..., 0], r[..., 1]) * np.hypot(s[..., 0], s[..., 1]), 1e-300
    )
    safe = np.where(ok, den, 1.0)
    w = q - p
    t = (w[..., 0] * s[..., 1] - w[..., 1] * s[..., 0]) / safe
    u = (w[..., 0] * r[..., 1] - w[..., 1] * r[..., 0]) / safe
    hit = ok & (t >= 0) & (t <= 1) & (u >= 0) & (u <= 1)
    za = p[..., 2] + t * r[..., 2]
    pt = q + u[..., None] * s
    cands_d.append(np.where(hit, za - pt[..., 2], np.inf).reshape(n, 9))
    cands_p.append(pt.reshape(n, 9, 3))
    d = np.concatenate(cands_d, axis=1)
    pts = np.concatenate(cands_p, axis=1)
    best = np.argmin(d, axis=1)
    rows = np.arange(n)
    drop = d[rows, best]
    point = np.where(np.isfinite(drop)[:, None], pts[rows, best], np.nan)
    return drop, point
