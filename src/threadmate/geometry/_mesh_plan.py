"""Planning a body's mesh: the profile stations, the meridian grid and the angles of
the meridians inserted at crossings, sized to the chord.

A station is a profile coordinate ``t`` whose polyline is within the chord of the profile
(the corners of the flats and flanks and the points that split each fillet arc); the
chord is shared between that polyline, the circumferential sagitta between meridians and
the helicoid's twist (:func:`plan_grid`, :func:`shares`). Meridians are inserted exactly
at the angles where a station crosses an end plane, so the cap outline passes through
every profile corner (otherwise it cuts the corners by about 6e-5 in on a 1/4-20), and,
on a trimmed body, where the ridge crosses a station's helix (:mod:`._mesh_trim`).

Why bolt and nut do not share meridian planes: the collision query's triangle-triangle
test (FCL's, see :mod:`threadmate.contact.scene._obb`) can miss intersecting pairs whose
edges are coplanar, which happens when both meshes are built on the same meridian
half-planes (for instance both with a meridian at angle 0, or on regular grids of the
same count, at a round phase). So

* the regular grids have different, co-prime counts: the bolt's count is a prime ``= 1
  (mod 4)``, the nut's a prime ``= 3 (mod 4)``, so they never coincide and at any phase at
  most one bolt meridian can line up with a nut meridian;
* the nut's grid is turned by an irrational angle (``(sqrt 2 - 1)`` of its spacing), so
  at no rational phase in degrees (0, 5, 10, ...) does a regular bolt meridian fall on a
  regular nut meridian;
* the flat centres (``t = 0`` and ``t = p/2``, the same for both bodies) are not stations
  (a flat needs only its ends), so the inserted meridians sit at angles set by each body's
  own corners, which involve ``sqrt 3`` and the body's diameters and differ between bolt
  and nut for any pair with clearance.

These measures are the same at every chord. Near coincidences (meridians 1e-8 rad apart at
some phase) are harmless: that test builds its separating axes from edge cross products,
which go wrong only when two edges are parallel to rounding precision.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .._angles import SQRT3, TWO_PI
from ._body import ThreadBody
from ._mesh_trim import Trim, envelope_reach, enveloped
from ._profile import Profile

__all__ = [
    "BOLT_GRID",
    "NUT_GRID",
    "SAGITTA_SHARE",
    "NUT_GRID_TURN",
    "MeridianGrid",
    "crossing_angles",
    "meridians",
    "plan_grid",
    "prime",
    "profile_stations",
    "shares",
]

# Share of the chord given to the profile polyline of a fillet arc at the major-diameter
# corner (bolt crest fillet, nut root fillet). There the polyline and the circumferential
# sagitta both err toward the air, so their errors add; at the minor-diameter corner they
# err to opposite sides and each may take (nearly) the whole chord.
_HI_ARC_SHARE = 0.3
_LO_ARC_SHARE = 0.95
# Share of the chord given to the circumferential sagitta on the flats (which bound the
# meridian spacing), and to sagitta plus helicoid twist on the flanks; the margin covers
# what the error model leaves out, and refinement whatever it still misses.
SAGITTA_SHARE = 0.9
_FLANK_SHARE = 0.95
# Least share of the chord left to a round point's latitude polyline (see shares).
_MIN_LATITUDE_SHARE = 0.2
# Irrational turn of the nut's regular grid, in units of its spacing.
NUT_GRID_TURN = math.sqrt(2.0) - 1.0


@dataclass(frozen=True)
class MeridianGrid:
    """How a body's regular meridian grid is chosen (see the module docstring)."""

    residue: int  # the count is a prime = residue (mod 4)
    turn: float  # turn of the grid, in units of its spacing


BOLT_GRID = MeridianGrid(residue=1, turn=0.0)
NUT_GRID = MeridianGrid(residue=3, turn=NUT_GRID_TURN)


def plan_grid(body: ThreadBody, chord: float) -> tuple[int, int]:
    """Regular meridian count and flank subdivision that meet ``chord`` at least cost.

    Error model of a lateral triangle between meridians ``dtheta`` apart: the
    circumferential sagitta ``n_r r dtheta^2 / 8`` plus the helicoid twist
    ``n_theta dr dtheta / 4`` (``dr`` the radial span of the triangle along the profile,
    ``n_r``, ``n_theta`` the radial and circumferential components of the unit normal).
    Flats have no twist and ``n_r = 1``: they bound ``dtheta``. Flanks (``dz/dr =
    1/sqrt 3``) are split into ``m`` equal pieces to tame the twist; the pair
    ``(dtheta, m)`` minimising meridians x stations is chosen.
    """
    profile = body.profile
    r_hi, r_lo = profile.r_hi, profile.r_lo
    c = body.lead / TWO_PI
    share, _ = shares(body)
    # An envelope's sagitta counts where it reaches beyond the major flat (a countersink).
    r_sag = r_hi if body.envelope is None else max(r_hi, envelope_reach(body.envelope))
    step_flat = 2.0 * math.acos(max(-1.0, 1.0 - share * chord / r_sag))
    _, a2, a3, _ = profile.breakpoints
    span = max(0.0, (a3 - a2) * SQRT3)  # radial span of the straight flank
    n_r = r_hi / (SQRT3 * math.hypot(r_hi * 2 / SQRT3, c))
    n_theta = c / math.hypot(r_lo * 2 / SQRT3, c)
    base = len(profile_stations(profile, chord, 1))
    best = (math.inf, math.ceil(TWO_PI / step_flat), 1)
    for f in np.linspace(1.0, 0.3, 36):
        step = step_flat * f
        twist = _FLANK_SHARE * chord - n_r * r_hi * step * step / 8
        if twist <= 0:
            continue
        m = max(1, math.ceil(span * n_theta * step / (4 * twist)))
        stations = base + 2 * (m - 1)
        cost = (TWO_PI / step + 2 * stations * round(body.lead / profile.pitch)) * stations
        if cost < best[0]:
            best = (cost, math.ceil(TWO_PI / step), m)
    return best[1], best[2]


def shares(body: ThreadBody) -> tuple[float, float]:
    """Shares of the chord: the circumferential sagitta's at the flats (at ``r_sag`` of
    :func:`plan_grid`), and a round point's latitude polyline's.

    On a sphere of radius ``rho`` the sagitta between meridians, along its normal, is that
    at the flats scaled by ``r^2 / (rho r_sag)``, and the latitude polyline errs to the
    same side: the polyline takes what the sagitta leaves (a flatter sphere, more), or at
    least :data:`_MIN_LATITUDE_SHARE`, the meridians then closing in.
    """
    share = SAGITTA_SHARE * ((1 - _HI_ARC_SHARE) if body.profile.fillet_hi > 0 else 1.0)
    env = body.envelope
    if env is None or env.kind != "sphere":
        return share, 0.0
    reach = envelope_reach(env)
    ratio = reach / max(body.profile.r_hi, reach)
    latitude = _FLANK_SHARE - share * ratio
    if latitude < _MIN_LATITUDE_SHARE:
        latitude = _MIN_LATITUDE_SHARE
        share = (_FLANK_SHARE - latitude) / ratio
    return share, latitude


def prime(n: int, residue: int) -> int:
    """The smallest prime ``>= max(n, 5)`` that is ``residue`` modulo 4."""
    n = max(n, 5)
    while True:
        if n % 4 == residue and all(n % d for d in range(2, math.isqrt(n) + 1)):
            return n
        n += 1


def profile_stations(profile: Profile, chord: float, flank_pieces: int) -> NDArray[np.float64]:
    """Profile stations over one pitch, ``[-p/2, p/2)``, distinct modulo the pitch.

    The corners of the flats and flanks and, on each fillet arc, points at equal angles
    whose sagitta stays within its share of the chord. The flat centres are left out (a
    flat is straight), which keeps bolt and nut stations apart. Each straight flank is
    split into ``flank_pieces`` equal pieces (which bounds the helicoid twist).
    """
    a1, a2, a3, a4 = profile.breakpoints
    u = [a1, a4, *np.linspace(a2, a3, flank_pieces + 1)]
    for rho, (uc, _), lo, hi, share in (
        (profile.fillet_hi, profile.centre_hi, a1, a2, _HI_ARC_SHARE),
        (profile.fillet_lo, profile.centre_lo, a3, a4, _LO_ARC_SHARE),
    ):
        if rho <= 0 or hi <= lo:
            continue
        phi0 = math.asin(min(1.0, max(-1.0, (lo - uc) / rho)))
        phi1 = math.asin(min(1.0, max(-1.0, (hi - uc) / rho)))
        c = share * chord
        dphi = 2.0 * math.acos(1.0 - c / rho) if c < rho else math.pi / 2
        n = max(1, math.ceil(abs(phi1 - phi0) / dphi))
        u.extend(uc + rho * np.sin(np.linspace(phi0, phi1, n + 1)))
    p = profile.pitch
    t = np.concatenate([np.asarray(u), -np.asarray(u)])
    t = np.sort(t - p * np.floor(t / p + 0.5))
    # Drop stations that coincide (a corner with no fillet, a flat of zero width).
    tol = 1e-9 * p
    keep = np.concatenate([[True], np.diff(t) > tol])
    t = t[keep]
    if len(t) > 1 and t[0] + p - t[-1] <= tol:
        t = t[:-1]
    return t


def crossing_angles(
    body: ThreadBody, stations: NDArray[np.float64], trim: Trim | None = None
) -> NDArray[np.float64]:
    """Angles in ``[0, 2 pi)`` at which a station's helix meets an end plane (one that the
    thread reaches: not an end face wholly inside an envelope), and, with an envelope, at
    which the ridge meets a station's helix or an extremum of ``h`` (:class:`Trim`)."""
    p, lead, hand = body.profile.pitch, body.lead, body.hand
    starts = round(lead / p)
    out = []
    for z_end in (body.z_min, body.z_max):
        if trim is not None and enveloped(body, z_end):
            continue
        for k in range(starts):
            frac = hand * (z_end - stations - k * p) / lead
            out.append(TWO_PI * (frac - np.floor(frac)))
    if trim is not None:
        # The kink on the helix tau sits at height Z(R(tau)).
        tau = trim.grid
        z = trim.height(tau)
        ok = (z >= body.z_min) & (z <= body.z_max)
        for k in range(starts):
            frac = hand * (z[ok] - tau[ok] - k * p) / lead
            out.append(TWO_PI * (frac - np.floor(frac)))
    return np.concatenate(out)


def meridians(crossings: NDArray[np.float64], count: int, turn: float) -> NDArray[np.float64]:
    """Sorted meridian angles in ``[0, 2 pi)``: the crossings and the regular grid."""
    step = TWO_PI / count
    regular = step * (np.arange(count) + turn)
    cross = np.unique(crossings)
    tol = 1e-9
    cross = cross[np.concatenate([[True], np.diff(cross) > tol])]
    if len(cross) > 1 and cross[0] + TWO_PI - cross[-1] <= tol:
        cross = cross[:-1]
    # A regular meridian within a hair of a crossing would only make sliver triangles.
    gap = np.abs(regular[:, None] - cross[None, :])
    gap = np.minimum(gap, TWO_PI - gap)
    regular = regular[np.all(gap > 1e-4 * step, axis=1)] if len(cross) else regular
    return np.sort(np.concatenate([cross, regular]))
