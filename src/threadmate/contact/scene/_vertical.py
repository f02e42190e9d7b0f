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

__all__ = ["vertical_rise", "vertical_touch"]

#: The end of each triangle edge that starts at vertex 0, 1, 2: edges (0, 1), (1, 2), (2, 0).
_NEXT = [1, 2, 0]


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
    # Vertices inside the other triangle's projection, both ways in one pass (most calls
    # are of a few pairs, where numpy's per-call overhead is the cost): bolt vertices over
    # the nut triangle in rows :n, nut vertices under the bolt triangle in rows n:.
    tri = np.concatenate([b, a])
    pts = np.concatenate([a, b])
    o = tri[:, 0]
    e0, e1 = tri[:, 1] - o, tri[:, 2] - o
    e00, e01, e10, e11 = e0[:, 0], e0[:, 1], e1[:, 0], e1[:, 1]
    det = e00 * e11 - e01 * e10
    scale = (e00 * e00 + e01 * e01) + (e10 * e10 + e11 * e11)
    ok = np.abs(det) > 1e-12 * np.maximum(scale, 1e-300)  # not seen edge-on
    safe = np.where(ok, det, 1.0)[:, None]
    w0 = pts[..., 0] - o[:, None, 0]
    w1 = pts[..., 1] - o[:, None, 1]
    u = (w0 * e11[:, None] - w1 * e10[:, None]) / safe
    v = (e00[:, None] * w1 - e01[:, None] * w0) / safe
    inside = ok[:, None] & (u >= 0) & (v >= 0) & (u + v <= 1)
    z = o[:, None, 2] + u * e0[:, None, 2] + v * e1[:, None, 2]  # the triangle's height
    drop_in = pts[..., 2] - z
    drop_in[n:] *= -1.0  # the bolt triangle's height over the nut vertex
    drop_in = np.where(inside, drop_in, np.inf)
    # Crossings of edge projections: all nine edge pairs at once, bolt edge (i, j) by nut
    # edge (k, m) in row-major order (the order of the candidates decides ties).
    p = a[:, :, None, :]  # (n, 3, 1, 3): bolt edge starts
    r = (a[:, _NEXT] - a)[:, :, None, :]
    q = b[:, None, :, :]  # (n, 1, 3, 3): nut edge starts
    s = (b[:, _NEXT] - b)[:, None, :, :]
    r0, r1, s0, s1 = r[..., 0], r[..., 1], s[..., 0], s[..., 1]
    den = r0 * s1 - r1 * s0
    ok = np.abs(den) > 1e-14 * np.maximum(np.hypot(r0, r1) * np.hypot(s0, s1), 1e-300)
    safe = np.where(ok, den, 1.0)
    w = q - p
    w0, w1 = w[..., 0], w[..., 1]
    t = (w0 * s1 - w1 * s0) / safe
    u = (w0 * r1 - w1 * r0) / safe
    hit = ok & (t >= 0) & (t <= 1) & (u >= 0) & (u <= 1)
    za = p[..., 2] + t * r[..., 2]
    pt = q + u[..., None] * s
    d = np.concatenate(
        [drop_in[:n], drop_in[n:], np.where(hit, za - pt[..., 2], np.inf).reshape(n, 9)], axis=1
    )
    pts = np.concatenate(
        [np.concatenate([a[:, :, :2], z[:n, :, None]], axis=-1), b, pt.reshape(n, 9, 3)], axis=1
    )
    best = np.argmin(d, axis=1)
    rows = np.arange(n)
    drop = d[rows, best]
    point = np.where(np.isfinite(drop)[:, None], pts[rows, best], np.nan)
    return drop, point


def vertical_rise(
    bolt_tris: NDArray[np.float64], nut_tris: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Rise at which each bolt triangle first meets its nut triangle above it, and where:
    :func:`vertical_touch` of the pair mirrored in the XY plane (a rise is a drop there)."""
    flip = np.array([1.0, 1.0, -1.0])
    rise, point = vertical_touch(
        np.asarray(bolt_tris, dtype=float) * flip, np.asarray(nut_tris, dtype=float) * flip
    )
    return rise, point * flip
