"""Trimming a body's mesh by its bolt point's or nut countersink's envelope.

A bolt's point or a nut's countersink trims the thread by a surface of revolution, the
envelope ``r = e(z)``: the lateral surface becomes ``min(R, e)`` (bolt) or ``max(R, e)``
(nut), with a ridge where the two meet. On a meridian the ridge points (kinks) solve
``h(tau) = s``, ``h(tau) = Z(R(tau)) - tau`` with ``Z`` the envelope's inverse; each chain
holds them exactly, the stations where the thread bounds the material, and on a sphere
latitude stations (a cone is straight along a meridian, so trimmed stations are dropped).
The ridge must also be kept whole between meridians, which the zipper alone does not do:
a triangle across it misses it by about the kink angle times the kink's shift from one
meridian to the next (5 to 7 chords of 2e-5 in on a 1/4-20 chamfer or round). So

* the strip is zipped piecewise between kinks of the same branch of the ridge (an
  interval of ``h`` between its extrema), joined by an edge; a sphere's pieces in height,
  along its latitudes;
* meridians are inserted where the ridge crosses a station's helix (the profile
  polyline's corners, which the ridge would otherwise cut) and at the extrema of ``h``
  (tangencies of thread and envelope, where kinks appear in pairs), so that between
  neighbouring meridians every branch is on both or on neither;
* the end face at the envelope's end lies wholly inside it, its outline a circle, so it
  needs no crossings (they stay at the far end).

A body without an envelope has no ridge and none of these insertions. The inserted
meridians depend on each body's own profile and envelope, so the measures of
:mod:`._mesh_plan` (bolt and nut on meridians of their own) hold as well.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._angles import TWO_PI
from ._body import ThreadBody
from ._ends import Envelope
from ._profile import Profile

__all__ = [
    "KINK_TOL",
    "Trim",
    "envelope_reach",
    "enveloped",
    "meridian_kinks",
    "trim_plan",
    "trimmed_chain",
]

# -- envelopes -----------------------------------------------------------------------------
# Two kink roots (or a kink and a vertex) closer than this, in pitches, are one vertex; an
# inserted meridian's rounding stays far below it.
KINK_TOL = 1e-10


@dataclass(frozen=True)
class Trim:
    """How a point's or countersink's envelope trims the thread, over one pitch.

    On a meridian with shift ``s`` the thread meets the envelope (a *kink* of the lateral
    surface) where ``h(tau) = Z(R(tau)) - tau = s``, ``Z`` the envelope's inverse
    (the height at which its radius is ``r``). ``grid`` holds ``tau`` in ``[-p/2, p/2)``:
    the profile's stations and the extrema of ``h`` (tangencies of envelope and thread),
    so ``h`` is monotone between neighbours and every grid interval holds at most one kink
    per meridian; ``h`` its values there. ``levels`` are the heights of a sphere's
    latitude stations (empty for a cone, which is straight along its meridians).
    """

    envelope: Envelope
    side: int  # +1: material where r <= envelope (bolt); -1: r >= envelope (nut)
    grid: NDArray[np.float64]
    h: NDArray[np.float64]
    levels: NDArray[np.float64]
    profile: Profile

    def height(self, tau: NDArray[np.float64]) -> NDArray[np.float64]:
        """``Z(R(tau))``: the height at which the envelope has the thread's radius."""
        return _envelope_height(self.envelope, self.profile.radius(tau))

    def lateral(self, tau: NDArray[np.float64], z: NDArray[np.float64]) -> NDArray[np.float64]:
        """Radius of the trimmed lateral surface at helix coordinate ``tau``, height ``z``."""
        r, e = self.profile.radius(tau), self.envelope.radius(z)
        return np.minimum(r, e) if self.side > 0 else np.maximum(r, e)

    def trimmed(self, tau: NDArray[np.float64], z: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Where the envelope, not the thread, bounds the material (strictly)."""
        return self.side * (self.profile.radius(tau) - self.envelope.radius(z)) > 0


def _envelope_height(env: Envelope, r: ArrayLike) -> NDArray[np.float64]:
    """The height at which ``env`` has radius ``r`` (monotone over its span)."""
    r = np.asarray(r, dtype=float)
    if env.kind == "cone":
        return (r - env.r0) / env.slope_rz
    return env.z0 - np.sqrt(np.maximum(env.rho * env.rho - r * r, 0.0))


def envelope_reach(env: Envelope) -> float:
    """Largest ``radius x |n_r|`` over the envelope's span (its circumferential sagitta
    per unit of ``dtheta^2 / 8``, measured along its normal)."""
    r = float(np.max(np.abs(env.radius(np.array([env.z_lo, env.z_hi])))))
    if env.kind == "cone":
        return r / math.hypot(1.0, env.slope_rz)
    return r * r / env.rho


def enveloped(body: ThreadBody, z: float) -> bool:
    """Whether the end plane at ``z`` lies wholly inside the envelope (its outline is the
    envelope's circle)."""
    env = body.envelope
    if env is None:
        return False
    e = float(env.radius(z))
    if not math.isfinite(e):
        return False
    return e <= body.profile.r_lo if env.side > 0 else e >= body.profile.r_hi


def _bisect(
    f: Callable[[NDArray[np.float64]], NDArray[np.float64]],
    a: NDArray[np.float64],
    b: NDArray[np.float64],
) -> NDArray[np.float64]:
    """Roots of ``f`` bracketed elementwise by ``[a, b]`` (to rounding)."""
    fa = f(a)
    for _ in range(64):
        m = 0.5 * (a + b)
        fm = f(m)
        same = np.sign(fm) == np.sign(fa)
        a, fa, b = np.where(same, m, a), np.where(same, fm, fa), np.where(same, b, m)
    return 0.5 * (a + b)


def trim_plan(
    body: ThreadBody, stations: NDArray[np.float64], latitude_chord: float
) -> Trim | None:
    """The envelope's trim of ``body`` (None without one): see :class:`Trim`.

    ``latitude_chord`` is the share of the chord a sphere's latitude polyline may take
    (:func:`._mesh_plan.shares`); a cone has no latitudes and ignores it.
    """
    env = body.envelope
    if env is None:
        return None
    profile = body.profile
    p = profile.pitch

    def slope(t: NDArray[np.float64]) -> NDArray[np.float64]:  # dh/dtau
        z = _envelope_height(env, profile.radius(t))
        d = profile.slope(t) / env.slope(z) - 1.0
        return np.where(np.abs(d) <= 1e-9, 0.0, d)  # a flank parallel to a cone: flat h

    # Extrema of h inside the station intervals: sign changes of dh/dtau on a fine sample.
    lo = stations
    hi = np.append(stations[1:], stations[0] + p)
    w = np.linspace(1e-9, 1.0 - 1e-9, 33)
    t = lo[:, None] + (hi - lo)[:, None] * w[None, :]
    sign = np.sign(slope(t))
    i, k = np.nonzero(sign[:, :-1] * sign[:, 1:] < 0)
    extra = _bisect(slope, t[i, k], t[i, k + 1])
    extra = extra - p * np.floor(extra / p + 0.5)
    grid = np.sort(np.concatenate([stations, extra]))
    grid = grid[np.concatenate([[True], np.diff(grid) > 1e-9 * p])]
    h = _envelope_height(env, profile.radius(grid)) - grid

    levels = np.empty(0)
    if env.kind == "sphere":
        # Latitudes whose polyline stays within its share of the chord (like a fillet's).
        r_ends = env.radius(np.array([env.z_lo, env.z_hi]))
        phi = np.arcsin(np.clip(r_ends / env.rho, -1.0, 1.0))
        c = latitude_chord
        dphi = 2.0 * math.acos(1.0 - c / env.rho) if c < env.rho else math.pi / 2
        n = max(1, math.ceil(abs(phi[1] - phi[0]) / dphi))
        levels = env.z0 - env.rho * np.cos(np.linspace(phi[0], phi[1], n + 1)[1:-1])
    return Trim(env, env.side, grid, h, levels, profile)


def meridian_kinks(
    body: ThreadBody, trim: Trim, theta: NDArray[np.float64]
) -> list[tuple[NDArray[np.float64], NDArray[np.int64]]]:
    """Per meridian, the kinks ``(tau, label)`` in ``tau`` order (a kink on a grid point
    appears once per grid interval it closes). The label ``k n + i`` names grid interval
    ``i`` of pitch ``k``: a branch of the kink curve, continuous from meridian to meridian
    as long as no extremum of ``h`` lies between them (those are meridians themselves)."""
    profile = body.profile
    p, lead, hand = profile.pitch, body.lead, body.hand
    grid, hgrid = trim.grid, trim.h
    n = len(grid)
    s = hand * lead * theta / TWO_PI
    tol = KINK_TOL * p
    out: list[tuple[NDArray[np.float64], NDArray[np.int64]]] = [
        (np.empty(0), np.empty(0, dtype=np.int64)) for _ in theta
    ]
    zr = _envelope_height(trim.envelope, np.array([profile.r_lo, profile.r_hi]))
    z_a, z_b = max(float(zr.min()), body.z_min), min(float(zr.max()), body.z_max)
    if z_a > z_b + tol:
        return out
    # Each meridian's kinks lie within tau in [z_a - s, z_b - s]: a window of whole
    # pitches around it (with a pitch to spare each side, so a kink on a grid point is seen
    # from both intervals it closes).
    kk = np.floor((z_a - s) / p)[:, None] - 1.0 + np.arange(math.ceil((z_b - z_a) / p) + 3)
    kk = kk[:, :, None]  # (meridian, pitch, grid interval)
    nxt = (np.arange(n) + 1) % n
    carry = (np.arange(n) + 1) // n
    left = grid + p * kk
    right = grid[nxt] + p * (kk + carry)
    f_l = hgrid - p * kk - s[:, None, None]
    f_r = hgrid[nxt] - p * (kk + carry) - s[:, None, None]
    label = kk.astype(np.int64) * n + np.arange(n)
    at_l, at_r = np.abs(f_l) <= tol, np.abs(f_r) <= tol
    inner = (f_l * f_r < 0) & ~at_l & ~at_r
    j = np.concatenate([np.nonzero(m)[0] for m in (at_l, at_r, inner)])
    s_i = np.broadcast_to(s[:, None, None], inner.shape)[inner]
    roots = _bisect(lambda t: trim.height(t) - t - s_i, left[inner], right[inner])
    tau = np.concatenate([left[at_l], right[at_r], roots])
    lab = np.concatenate([label[at_l], label[at_r], label[inner]])
    lo, hi = body.z_min - s[j], body.z_max - s[j]
    ok = (tau >= lo - 1e-9 * p) & (tau <= hi + 1e-9 * p)
    j, tau, lab = j[ok], np.clip(tau[ok], lo[ok], hi[ok]), lab[ok]
    order = np.lexsort((tau, j))
    j, tau, lab = j[order], tau[order], lab[order]
    cuts = np.searchsorted(j, np.arange(len(theta) + 1))
    for m in range(len(theta)):
        out[m] = (tau[cuts[m] : cuts[m + 1]], lab[cuts[m] : cuts[m + 1]])
    return out


def trimmed_chain(
    trim: Trim,
    s: float,
    ends: tuple[float, float],
    z_ends: tuple[float, float],
    t_ends: tuple[float, float],
    tau: NDArray[np.float64],
    kinks: tuple[NDArray[np.float64], NDArray[np.int64]],
    tol: float,
) -> tuple[
    NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], dict[int, int], NDArray[np.bool_]
]:
    """``(tau, z, r, marks, latitude)`` of a meridian's chain on a trimmed body: stations
    where the thread bounds the material, the kinks, a sphere's latitudes where it bounds
    it, and the two end vertices (radius taken at ``t_ends``); a kink within ``tol`` of
    another vertex becomes it."""
    lat_z = trim.levels[(trim.levels > z_ends[0]) & (trim.levels < z_ends[1])]
    cand = np.concatenate([tau, lat_z - s])
    trimmed = trim.trimmed(cand, cand + s)
    is_lat = np.arange(len(cand)) >= len(tau)
    keep = trimmed == is_lat  # stations on the thread, latitudes on the envelope
    cand, is_lat = cand[keep], is_lat[keep]
    k_tau, k_lab = kinks
    # Vertex kinds, in the order a coincident vertex keeps: end, kink, station, latitude.
    all_tau = np.concatenate([ends, k_tau, cand])
    kind = np.concatenate([[0, 0], np.ones(len(k_tau)), np.where(is_lat, 3, 2)]).astype(np.int64)
    src = np.concatenate([[-1, -1], np.arange(len(k_tau)), np.full(len(cand), -1)])
    order = np.lexsort((kind, all_tau))
    all_tau, kind, src = all_tau[order], kind[order], src[order].astype(np.int64)
    # Groups of vertices within tol; each keeps its first (by kind) member's position.
    head = np.concatenate([[True], np.diff(all_tau) > tol])
    group = np.cumsum(head) - 1
    best = np.full(int(group[-1]) + 1, 99, dtype=np.int64)
    np.minimum.at(best, group, kind)
    chosen = np.flatnonzero(kind == best[group])
    pick = chosen[np.concatenate([[True], np.diff(group[chosen]) > 0])]
    out_tau = all_tau[pick]
    out_kind = kind[pick]
    is_kink = np.flatnonzero(kind == 1)
    marks = dict(zip(k_lab[src[is_kink]].tolist(), group[is_kink].tolist(), strict=True))
    z = out_tau + s
    z[0], z[-1] = z_ends
    at = out_tau.copy()
    at[0], at[-1] = t_ends
    return out_tau, z, trim.lateral(at, z), marks, out_kind == 3
