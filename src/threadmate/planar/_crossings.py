"""Where the two flush outlines cross: the piecewise machinery of the planar analysis.

With the bolt flush on the nut (roll = pitch = 0, tip face in ``z = 0``) at phase ``phi``,
both outlines in F are profiles of one axial coordinate. At the F-angle ``theta`` let
``tau = -hand * lead * theta / (2 pi)`` (the nut's ``t`` there, conventions.md). The bolt's
point at that angle has bolt-frame angle ``theta - phi``, so its ``t`` is ``tau + sigma``
with the *phase shift*

    sigma = hand * lead * phi / 360            (phi in degrees).

So the nut's top outline is ``R_n(tau)`` and the bolt's tip outline is
``R_b(tau + sigma)``; their difference ``d(tau) = R_b(tau + sigma) - R_n(tau)`` has period
one pitch in ``tau`` (``1 / starts`` of a turn in ``theta``), and the bolt's outline lies
outside the nut's where ``d > 0``.

Each profile is made of flats and flanks (straight in the ``(tau, R)`` plane) and fillet
arcs (circles there), with breakpoints known exactly from the profile. Between the merged
breakpoints of the two outlines each outline is a single piece:

* flat or flank against flat or flank: ``d`` is linear, its root closed form (the thesis's
  eq. 2.16-2.17 for flank against flank, in our conventions);
* a fillet arc on either side: ``d`` has at most one stationary point on the piece (two
  circle arcs, or an arc and a line, have equal slopes at most once), found by
  :func:`scipy.optimize.brentq` on ``d'``; it splits the piece into at most two monotone
  brackets, each holding at most one root, found by :func:`scipy.optimize.brentq` on ``d``.

The brackets therefore come from the exact breakpoints, never from sampling.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING, overload

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import brentq

from .._angles import SQRT3, TWO_PI, wrap_phase
from ..geometry import Profile, bolt_profile, nut_profile, wrap_t

if TYPE_CHECKING:
    from ..geometry import ThreadSpec

__all__ = ["OutlinePair", "outline_pair"]

#: Relative (to the pitch) tolerance on ``d`` below which the outlines count as touching.
TOUCH_TOL = 1e-10
#: Relative offset used to read a region or slope on one side of an exact breakpoint.
SIDE_STEP = 1e-12


def profile_inverse(profile: Profile, radius: float) -> list[float]:
    """Every ``t`` in ``[-p/2, p/2)`` where the profile's radius equals ``radius``.

    Closed form on each monotone piece: the flank is a line, each fillet a circle. Where
    the radius equals a flat's, the flat's two ends are returned (the crossing can only
    reach a region boundary there).
    """
    a1, a2, a3, a4 = profile.breakpoints
    r_hi, r_lo = profile.r_hi, profile.r_lo
    span = r_hi - r_lo
    eps = 1e-13 * max(span, profile.pitch)
    if radius > r_hi + eps or radius < r_lo - eps:
        return []
    us: list[float] = []
    if abs(radius - r_hi) <= eps:
        us.append(a1)
    elif abs(radius - r_lo) <= eps:
        us.append(a4)
    else:
        r_a2 = float(profile.radius(a2))
        r_a3 = float(profile.radius(a3))
        if radius >= r_a2:  # crest-side (major corner) fillet arc
            cu, cr = profile.centre_hi
            rho = profile.fillet_hi
            us.append(cu + math.sqrt(max(rho * rho - (radius - cr) ** 2, 0.0)))
        elif radius <= r_a3:  # root-side (minor corner) fillet arc
            cu, cr = profile.centre_lo
            rho = profile.fillet_lo
            us.append(cu - math.sqrt(max(rho * rho - (radius - cr) ** 2, 0.0)))
        else:  # flank: R = pd/2 + sqrt3 (p/4 - u)
            us.append(profile.pitch / 4 + (profile.pitch_diameter / 2 - radius) / SQRT3)
    out = {float(wrap_t(s * u, profile.pitch)) for u in us for s in (1.0, -1.0)}
    return sorted(out)


@dataclass(frozen=True)
class _Scan:
    """The merged breakpoints of one phase shift and what is known on each piece."""

    points: np.ndarray  # breakpoints, -p/2 ... p/2
    values: np.ndarray  # d at the breakpoints
    linear: np.ndarray  # per piece: neither outline on a fillet arc
    stationary: dict[int, tuple[float, float]]  # arc piece -> (tau, d) of its extremum


@dataclass(frozen=True)
class Stretch:
    """An interval of ``tau`` (``start < end``, ``end`` may pass ``p/2``) where the bolt's
    outline lies outside the nut's (or, at the window edge, on it)."""

    start: float
    end: float


class OutlinePair:
    """The bolt's tip outline and the nut's top outline of one spec, in ``tau``.

    Parameters
    ----------
    bolt, nut : Profile
        The two exact profiles.
    lead : float
        Axial advance per turn.
    hand : int
        +1 right hand, -1 left hand.
    starts : int
        Number of thread starts.
    """

    def __init__(self, bolt: Profile, nut: Profile, lead: float, hand: int, starts: int):
        self.bolt = bolt
        self.nut = nut
        self.thread_pitch = bolt.pitch
        self.lead = lead
        self.hand = hand
        self.starts = starts
        self.tol = TOUCH_TOL * self.thread_pitch
        self.bolt_edges = self._edges(bolt)
        self.nut_edges = self._edges(nut)
        self._scans: dict[float, _Scan] = {}

    def _edges(self, profile: Profile) -> np.ndarray:
        pts = [e for _, a, b in profile.region_bounds() for e in (a, b)]
        return np.unique(wrap_t(np.asarray(pts), self.thread_pitch))

    # -- phase <-> shift ---------------------------------------------------------------
    def shift(self, phase: float) -> float:
        """The phase shift ``sigma`` (length) of a phase in degrees."""
        return self.hand * self.lead * phase / 360.0

    def phase(self, sigma: float) -> float:
        """The phase in degrees of a phase shift ``sigma`` (inverse of :meth:`shift`)."""
        return 360.0 * sigma / (self.hand * self.lead)

    def thetas(self, tau: float) -> list[float]:
        """The F-angles (radians, in ``[0, 2 pi)``) at which the nut's ``t`` is ``tau``:
        one per start."""
        base = -TWO_PI * tau / (self.hand * self.lead)
        out = [wrap_phase(base + TWO_PI * j / self.starts, TWO_PI) for j in range(self.starts)]
        return [0.0 if th >= TWO_PI else th for th in out]

    # -- the difference and its slope ---------------------------------------------------
    @overload
    def d(self, tau: float, sigma: float) -> float: ...
    @overload
    def d(self, tau: np.ndarray, sigma: float) -> np.ndarray: ...

    def d(self, tau: ArrayLike, sigma: float) -> float | np.ndarray:
        """``R_b(tau + sigma) - R_n(tau)``: positive where the bolt's outline is outside."""
        out = self.bolt.radius(np.asarray(tau) + sigma) - self.nut.radius(tau)
        return float(out) if np.ndim(out) == 0 else out

    def d_slope(self, tau: float, sigma: float) -> float:
        """``d'(tau)``: the difference of the two profile slopes."""
        return float(self.bolt.slope(tau + sigma) - self.nut.slope(tau))

    # -- pieces ------------------------------------------------------------------------
    def _is_arc(self, profile: Profile, t: np.ndarray) -> np.ndarray:
        u = np.abs(wrap_t(t, self.thread_pitch))
        a1, a2, a3, a4 = profile.breakpoints
        return ((u > a1) & (u <= a2)) | ((u > a3) & (u <= a4))

    def pieces(self, sigma: float) -> _Scan:
        """The merged breakpoints over one pitch ``[-p/2, p/2]`` with ``d`` there, which
        pieces involve a fillet arc, and each arc piece's stationary point of ``d``."""
        key = float(sigma)
        hit = self._scans.get(key)
        if hit is not None:
            return hit
        h = self.thread_pitch / 2
        pts = np.unique(
            np.concatenate(
                [self.nut_edges, wrap_t(self.bolt_edges - sigma, self.thread_pitch), [-h, h]]
            )
        )
        keep = np.concatenate([np.diff(pts) > 1e-15 * self.thread_pitch, [True]])
        keep[0] = True
        pts = pts[keep]
        pts[-1] = h
        mid = 0.5 * (pts[:-1] + pts[1:])
        arc = self._is_arc(self.nut, mid) | self._is_arc(self.bolt, mid + sigma)
        values = self.d(pts, sigma)
        stationary: dict[int, tuple[float, float]] = {}
        for i in np.flatnonzero(arc):
            m = self._stationary(float(pts[i]), float(pts[i + 1]), sigma)
            if m is not None:
                stationary[int(i)] = (m, self.d(m, sigma))
        scan = _Scan(pts, values, ~arc, stationary)
        if len(self._scans) > 16:
            self._scans.clear()
        self._scans[key] = scan
        return scan

    def _stationary(self, lo: float, hi: float, sigma: float) -> float | None:
        """The one stationary point of ``d`` inside an arc piece, if ``d'`` changes sign."""
        w = hi - lo
        a, b = lo + 1e-9 * w, hi - 1e-9 * w
        ga, gb = self.d_slope(a, sigma), self.d_slope(b, sigma)
        if ga == 0.0 or gb == 0.0 or (ga > 0) == (gb > 0):
            return None
        return brentq(
            self.d_slope,
            a,
            b,
            args=(sigma,),
            xtol=1e-15 * self.thread_pitch,
            rtol=4 * np.finfo(float).eps,
        )

    def roots(self, sigma: float) -> list[float]:
        """Every ``tau`` in ``[-p/2, p/2)`` where the outlines cross or touch."""
        scan = self.pieces(sigma)
        pts, values = scan.points, scan.values
        found: list[float] = [float(t) for t, v in zip(pts, values, strict=True) if v == 0.0]
        for i in range(len(pts) - 1):
            lo, hi, dlo, dhi = float(pts[i]), float(pts[i + 1]), values[i], values[i + 1]
            if scan.linear[i]:
                if dlo * dhi < 0.0:
                    # d is exactly linear here: the closed-form crossing.
                    found.append(lo + dlo * (hi - lo) / (dlo - dhi))
                continue
            cuts = [(lo, dlo), (hi, dhi)]
            if i in scan.stationary:
                m, dm = scan.stationary[i]
                cuts.insert(1, (m, dm))
                if dm == 0.0:
                    found.append(m)
            for (a, da), (b, db) in zip(cuts[:-1], cuts[1:], strict=True):
                if da * db < 0.0:
                    found.append(
                        brentq(
                            self.d,
                            a,
                            b,
                            args=(sigma,),
                            xtol=1e-15 * self.thread_pitch,
                            rtol=4 * np.finfo(float).eps,
                        )
                    )
        h = self.thread_pitch / 2
        found = sorted(float(wrap_t(r, self.thread_pitch)) for r in found)
        out: list[float] = []
        for r in found:
            if not out or r - out[-1] > 1e-13 * self.thread_pitch:
                out.append(r)
        if len(out) > 1 and out[0] + self.thread_pitch - out[-1] <= 1e-13 * self.thread_pitch:
            out.pop()
        return [r if r < h else r - self.thread_pitch for r in out]

    def maximum(self, sigma: float) -> tuple[float, float]:
        """``(max d, tau at the max)`` over one pitch, from breakpoints and stationary
        points (exact up to the root finder's tolerance)."""
        scan = self.pieces(sigma)
        i = int(np.argmax(scan.values))
        best, where = float(scan.values[i]), float(scan.points[i])
        for m, dm in scan.stationary.values():
            if dm > best:
                best, where = dm, m
        return best, where

    # -- overlap ------------------------------------------------------------------------
    def overlap(self, sigma: float) -> list[Stretch]:
        """The stretches of ``tau`` (one pitch) where ``d > 0``, between sign changes."""
        roots = self.roots(sigma)
        if not roots:
            return []
        ends = [*roots, roots[0] + self.thread_pitch]
        positive = [
            self.d(0.5 * (a + b), sigma) > 0.0 for a, b in zip(ends[:-1], ends[1:], strict=True)
        ]
        if all(positive):
            return []
        # Start the walk at a negative segment so that no stretch is cut at the seam.
        k = positive.index(False)
        n = len(roots)
        out: list[Stretch] = []
        start: float | None = None
        for i in range(k, k + n):
            a = roots[i % n] + self.thread_pitch * (i // n)
            if positive[i % n] and start is None:
                start = a
            elif not positive[i % n] and start is not None:
                out.append(Stretch(start, a))
                start = None
        if start is not None:
            out.append(Stretch(start, roots[k] + self.thread_pitch * (1 + k // n)))
        return out

    def coincident(self, sigma: float) -> list[Stretch]:
        """The stretches where the outlines coincide (``|d| <= tol`` over whole pieces):
        the line contact of equal flanks at the in-phase window's edge."""
        scan = self.pieces(sigma)
        pts, values = scan.points, scan.values
        n = len(pts) - 1
        flags = []
        for i in range(n):
            mid = self.d(0.5 * (pts[i] + pts[i + 1]), sigma)
            flags.append(max(abs(values[i]), abs(values[i + 1]), abs(mid)) <= self.tol)
        if not any(flags):
            return []
        if all(flags):
            return [Stretch(float(pts[0]), float(pts[0]) + self.thread_pitch)]
        k = flags.index(False)
        out: list[Stretch] = []
        start = end = 0.0
        open_ = False
        for i in range(k, k + n):
            shift = self.thread_pitch * (i // n)
            if flags[i % n]:
                if not open_:
                    start, open_ = float(pts[i % n]) + shift, True
                end = float(pts[i % n + 1]) + shift
            elif open_:
                out.append(Stretch(start, end))
                open_ = False
        if open_:
            out.append(Stretch(start, end))
        return out


@lru_cache(maxsize=64)
def outline_pair(spec: ThreadSpec) -> OutlinePair:
    """The (cached) outline pair of a spec."""
    return OutlinePair(
        bolt_profile(spec), nut_profile(spec), spec.lead, spec.handedness, spec.starts
    )
