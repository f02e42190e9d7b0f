"""References for the mesh tests, written out here independently of the mesh generator and
of ``threadmate.geometry``'s profile code (conventions.md).

- :class:`ExactProfile`: a body's axial profile, the sharp V clamped to the flats with
  circular fillets tangent to flank and flat, its inverse and the integral of its square;
- :data:`INSIDE_WEIGHTS`: barycentric points inside a triangle at which a mesh's
  distance to the exact surface is sampled;
- :func:`meridian_angles`, :func:`meridian_gap`: the half-planes through the axis that
  hold a mesh's lateral edges, and how close a bolt's come to a nut's at a phase.
"""

from __future__ import annotations

import math

import numpy as np

from threadmate.geometry import TessellatedBody, ThreadSpec

SQ3 = math.sqrt(3.0)
# Gauss-Legendre nodes and weights on [-1, 1]: exact to rounding for the profile's smooth
# pieces (polynomials, circle arcs well inside their radius, square roots of them).
GL_X, GL_W = np.polynomial.legendre.leggauss(48)

#: Points inside a triangle (barycentric weights): centroid, edge midpoints, and three
#: points between the centroid and the corners.
INSIDE_WEIGHTS = np.array(
    [
        [1 / 3, 1 / 3, 1 / 3],
        [0.5, 0.5, 0.0],
        [0.0, 0.5, 0.5],
        [0.5, 0.0, 0.5],
        [0.6, 0.2, 0.2],
        [0.2, 0.6, 0.2],
        [0.2, 0.2, 0.6],
    ]
)


class ExactProfile:
    """``R(u)``, ``u = |t|`` in ``[0, p/2]``: flat, fillet, 60-degree flank, fillet, flat,
    non-increasing from ``r_hi`` to ``r_lo`` (conventions.md, for either body).

    Each fillet is the circle of radius rho tangent to the flat and to the flank line
    ``sqrt3 u + r = c`` (``c = pd/2 + sqrt3 p/4``); its centre lies rho from both.
    """

    def __init__(self, spec: ThreadSpec, body: str) -> None:
        b = getattr(spec, body)
        p = self.p = spec.pitch
        c = self.c = b.pitch_diameter / 2 + SQ3 * p / 4
        self.r_hi = min(b.major / 2, c)
        self.r_lo = max(b.minor / 2, b.pitch_diameter / 2 - SQ3 * p / 4)
        self.rho_hi = b.crest_fillet if body == "bolt" else b.root_fillet
        self.rho_lo = b.root_fillet if body == "bolt" else b.crest_fillet
        # Centre of the high fillet: r = r_hi - rho and (c - sqrt3 u - r) / 2 = rho.
        self.rc_hi = self.r_hi - self.rho_hi
        self.uc_hi = (c - self.rc_hi - 2 * self.rho_hi) / SQ3
        self.rc_lo = self.r_lo + self.rho_lo
        self.uc_lo = (c - self.rc_lo + 2 * self.rho_lo) / SQ3
        self.ut_hi = self.uc_hi + self.rho_hi * SQ3 / 2  # tangent points on the flank
        self.ut_lo = self.uc_lo - self.rho_lo * SQ3 / 2
        #: The corners of the profile's pieces in ``u``: fillet starts and tangent points.
        self.corners = (self.uc_hi, self.ut_hi, self.ut_lo, self.uc_lo)
        self.pieces = [0.0, *self.corners, p / 2]
        self.radii = [float(self.radius(u)) for u in self.pieces]  # non-increasing

    def radius(self, u):
        u = np.abs(np.asarray(u, dtype=float))
        flank = self.c - SQ3 * u
        hi = self.rc_hi + np.sqrt(np.clip(self.rho_hi**2 - (u - self.uc_hi) ** 2, 0, None))
        lo = self.rc_lo - np.sqrt(np.clip(self.rho_lo**2 - (u - self.uc_lo) ** 2, 0, None))
        return np.select(
            [u <= self.uc_hi, u <= self.ut_hi, u <= self.ut_lo, u <= self.uc_lo],
            [np.full_like(u, self.r_hi), hi, flank, lo],
            np.full_like(u, self.r_lo),
        )

    def of_t(self, t):
        """``R(t)`` for any axial coordinate (wrapped into one pitch)."""
        t = np.asarray(t, dtype=float)
        return self.radius(t - self.p * np.round(t / self.p))

    def inverse(self, r):
        """The ``u`` where ``R(u) = r`` (``r_lo < r < r_hi``), in closed form per piece."""
        r = np.asarray(r, dtype=float)
        arc_hi = self.uc_hi + np.sqrt(np.clip(self.rho_hi**2 - (r - self.rc_hi) ** 2, 0, None))
        arc_lo = self.uc_lo - np.sqrt(np.clip(self.rho_lo**2 - (self.rc_lo - r) ** 2, 0, None))
        return np.select(
            [r >= self.radii[2], r >= self.radii[3]], [arc_hi, (self.c - r) / SQ3], arc_lo
        )

    def square_integral(self, u):
        """``G(u) = int_0^u R^2``, Gauss-Legendre on each smooth piece."""
        u = np.atleast_1d(np.asarray(u, dtype=float))
        total = np.zeros_like(u)
        for lo, hi in zip(self.pieces[:-1], self.pieces[1:], strict=True):
            top = np.clip(u, lo, hi)
            half = (top - lo) / 2
            x = lo + half[:, None] * (GL_X + 1)
            total += half * (self.radius(x) ** 2 @ GL_W)
        return total


def meridian_angles(tb: TessellatedBody) -> np.ndarray:
    """Angles of the half-planes through the axis that hold a lateral mesh edge."""
    v = np.asarray(tb.mesh.vertices)
    e = tb.mesh.edges_unique
    a, b = v[e[:, 0]], v[e[:, 1]]
    ta, tb_ = np.arctan2(a[:, 1], a[:, 0]), np.arctan2(b[:, 1], b[:, 0])
    ra, rb = np.hypot(a[:, 0], a[:, 1]), np.hypot(b[:, 0], b[:, 1])
    meridional = (np.abs(np.sin(ta - tb_)) < 1e-12) & (ra > 0) & (rb > 0) & (a[:, 2] != b[:, 2])
    return np.unique(np.round(ta[meridional], 12))


def meridian_gap(bolt: np.ndarray, nut: np.ndarray, phase: float) -> float:
    """Smallest angle (rad) between a bolt meridian turned by ``phase`` (degrees) about
    the axis and a nut meridian (both from :func:`meridian_angles`)."""
    shifted = np.mod(bolt + math.radians(phase) + np.pi, 2 * np.pi) - np.pi
    gap = np.abs(shifted[:, None] - nut[None, :])
    return float(np.minimum(gap, 2 * np.pi - gap).min())
