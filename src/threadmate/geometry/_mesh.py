"""Watertight triangle meshes of the exact bolt and nut, within a chord tolerance.

The lateral thread surface is the helical sweep of the profile. It is tessellated on a
grid of *meridians* (half-planes through the axis, at angles ``theta_j``) crossed with the
profile's *stations* (``t`` values whose polyline is within the chord of the profile:
the corners of the flats and flanks and the points that split each fillet arc). On a
meridian the stations sit at heights ``z = t_i + k p + s_j``, ``s_j = hand lead theta_j /
(2 pi)``; the coordinate ``tau = z - s_j`` (the unwrapped profile coordinate) labels the
helix each vertex lies on. Neighbouring meridians are stitched by a zipper that merges
their vertices in ``tau`` order, so every lateral triangle runs along the helices (whose
radius is constant) and the error is only the circumferential sagitta plus the twist of
the helicoid between two meridians. The vertex lists of a meridian run from the lower end
plane to the upper one (each in ``z`` order, which is ``tau`` order).

Meridians are inserted exactly at the angles where a station crosses an end plane, so the
cap outline passes through every profile corner (otherwise it cuts the corners by about
6e-5 in on a 1/4-20). The bolt's end faces are fans from the axis; the nut's end faces
are annuli zipped to the outer circle, which is a regular polygon of its own.

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
meridians depend on each body's own profile and envelope, so the measures below hold as
well.

Why bolt and nut do not share meridian planes: python-fcl's triangle-triangle test can
miss intersecting pairs whose edges are coplanar, which happens when both meshes are built
on the same meridian half-planes (for instance both with a meridian at angle 0, or on
regular grids of the same count, at a round phase). So

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
some phase) are harmless: python-fcl's separating-axis test builds its axes from edge
cross products, which go wrong only when two edges are parallel to rounding precision.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import trimesh
from numpy.typing import ArrayLike, NDArray

from .._angles import SQRT3, TWO_PI
from .._errors import InputError
from ._body import ThreadBody, bolt_body, nut_body
from ._chord import check_chord
from ._ends import Envelope
from ._profile import Profile
from ._spec import ThreadSpec

__all__ = [
    "TessellatedBody",
    "bolt_mesh",
    "nut_mesh",
    "thread_meshes",
    "mesh_deviation",
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
_SAGITTA_SHARE = 0.9
_FLANK_SHARE = 0.95
_MAX_REFINEMENTS = 6
# Least share of the chord left to a round point's latitude polyline (see _shares).
_MIN_LATITUDE_SHARE = 0.2
# Irrational turn of the nut's regular grid, in units of its spacing.
_NUT_GRID_TURN = math.sqrt(2.0) - 1.0


@dataclass(frozen=True)
class TessellatedBody:
    """A body's triangle mesh with the bound of its deviation from the exact surface.

    Attributes
    ----------
    mesh : trimesh.Trimesh
        Watertight, consistently wound, outward normals, float64 vertices in the body's
        own frame and the spec's units. Shared by the cache of :func:`thread_meshes`:
        copy it before changing it.
    body : ThreadBody
        The exact body it tessellates.
    chord : float
        The chord tolerance asked for.
    max_deviation : float
        Largest distance from the mesh to the exact surface found by
        :func:`mesh_deviation` (at most ``chord``).
    """

    mesh: trimesh.Trimesh
    body: ThreadBody
    chord: float
    max_deviation: float

    @property
    def triangles(self) -> int:
        """Number of triangles."""
        return int(len(self.mesh.faces))


# -- public API --------------------------------------------------------------------------
def bolt_mesh(spec: ThreadSpec, chord: float | None = None) -> TessellatedBody:
    """Tessellate the bolt of ``spec`` in its frame (``0 <= z <= bolt.length``).

    Parameters
    ----------
    spec : ThreadSpec
        The thread pair.
    chord : float, optional
        Largest allowed distance from the mesh to the exact surface, in the spec's units
        (default :data:`DEFAULT_CHORD` for the units).

    Returns
    -------
    TessellatedBody
        The mesh and its verified deviation bound.
    """
    chord = check_chord(spec, chord)
    return _tessellate(bolt_body(spec), chord, _BOLT_GRID)


def nut_mesh(spec: ThreadSpec, chord: float | None = None) -> TessellatedBody:
    """Tessellate the nut of ``spec`` in the fixed frame (``-nut.height <= z <= 0``).

    The threaded bore, the flat top face (``surface``) at z = 0, the bottom face and the
    outer cylinder at ``nut.outer_radius``. See :func:`bolt_mesh` for the parameters.
    """
    chord = check_chord(spec, chord)
    return _tessellate(nut_body(spec), chord, _NUT_GRID)


def thread_meshes(
    spec: ThreadSpec, chord: float | None = None
) -> tuple[TessellatedBody, TessellatedBody]:
    """``(bolt, nut)`` meshes of ``spec``, cached per ``(spec, chord)``.

    The contact, sweep and command-line stages call this repeatedly; the meshes are built
    once per process. Do not modify the returned meshes in place (copy them).
    """
    return _cached_pair(spec, check_chord(spec, chord))


def mesh_deviation(mesh: trimesh.Trimesh, body: ThreadBody) -> float:
    """Upper bound on the distance from ``mesh`` to the exact surface of ``body``.

    Samples every triangle at its vertices, edge midpoints, centroid and three more
    barycentric points and takes the largest :meth:`ThreadBody.surface_distance` (itself
    an upper bound on the true distance). Both in the body's frame.
    """
    v = np.asarray(mesh.vertices, dtype=float)
    f = np.asarray(mesh.faces, dtype=np.int64)
    if len(f) == 0:
        return float("inf")
    edges = np.unique(
        np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1), axis=0
    )
    worst = _max_distance(body, v)
    worst = max(worst, _max_distance(body, 0.5 * (v[edges[:, 0]] + v[edges[:, 1]])))
    tri = v[f]
    for w in _BARYCENTRIC:
        worst = max(worst, _max_distance(body, np.einsum("k,nkd->nd", w, tri)))
    return worst


# -- internals ---------------------------------------------------------------------------
_BARYCENTRIC = np.array(
    [
        [1 / 3, 1 / 3, 1 / 3],
        [2 / 3, 1 / 6, 1 / 6],
        [1 / 6, 2 / 3, 1 / 6],
        [1 / 6, 1 / 6, 2 / 3],
    ]
)


@dataclass(frozen=True)
class _Grid:
    """How a body's regular meridian grid is chosen (see the module docstring)."""

    residue: int  # the count is a prime = residue (mod 4)
    turn: float  # turn of the grid, in units of its spacing


_BOLT_GRID = _Grid(residue=1, turn=0.0)
_NUT_GRID = _Grid(residue=3, turn=_NUT_GRID_TURN)


@functools.lru_cache(maxsize=16)
def _cached_pair(spec: ThreadSpec, chord: float) -> tuple[TessellatedBody, TessellatedBody]:
    return bolt_mesh(spec, chord), nut_mesh(spec, chord)


def _max_distance(body: ThreadBody, points: NDArray[np.float64], chunk: int = 200_000) -> float:
    worst = 0.0
    for start in range(0, len(points), chunk):
        p = points[start : start + chunk]
        # surface_distance measures the end faces and the outer cylinder only from points
        # within the body's extent; a point a hair outside (float32 STL rounding) is first
        # moved onto the extent, and the move added (triangle inequality).
        q = p.copy()
        q[:, 2] = np.clip(q[:, 2], body.z_min, body.z_max)
        if body.outer_radius is not None:
            r = np.hypot(q[:, 0], q[:, 1])
            scale = np.where(r > body.outer_radius, body.outer_radius / np.maximum(r, 1e-300), 1.0)
            q[:, :2] *= scale[:, None]
        moved = np.linalg.norm(p - q, axis=1)
        worst = max(worst, float(np.max(moved + body.surface_distance(q))))
    return worst


def _tessellate(body: ThreadBody, chord: float, grid: _Grid) -> TessellatedBody:
    count, pieces = _plan(body, chord)
    stations = _stations(body.profile, chord, pieces)
    trim = _trim_plan(body, stations, chord)
    crossings = _crossing_angles(body, stations, trim)
    count = _prime(count, grid.residue)
    for _ in range(_MAX_REFINEMENTS):
        mesh = _build(body, stations, crossings, count, grid.turn, chord, trim)
        deviation = mesh_deviation(mesh, body)
        if deviation <= chord:
            return TessellatedBody(mesh, body, chord, deviation)
        # The twist term falls linearly with the meridian spacing, the sagitta as its
        # square: scaling the count by the excess covers both.
        count = _prime(math.ceil(count * deviation / chord * 1.02), grid.residue)
    raise InputError(
        f"could not tessellate the {body.kind} within a chord of {chord:g} "
        f"(reached {deviation:.3g}); give a larger chord"
    )


def _plan(body: ThreadBody, chord: float) -> tuple[int, int]:
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
    share, _ = _shares(body)
    # An envelope's sagitta counts where it reaches beyond the major flat (a countersink).
    r_sag = r_hi if body.envelope is None else max(r_hi, _envelope_reach(body.envelope))
    step_flat = 2.0 * math.acos(max(-1.0, 1.0 - share * chord / r_sag))
    _, a2, a3, _ = profile.breakpoints
    span = max(0.0, (a3 - a2) * SQRT3)  # radial span of the straight flank
    n_r = r_hi / (SQRT3 * math.hypot(r_hi * 2 / SQRT3, c))
    n_theta = c / math.hypot(r_lo * 2 / SQRT3, c)
    base = len(_stations(profile, chord, 1))
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


def _shares(body: ThreadBody) -> tuple[float, float]:
    """Shares of the chord: the circumferential sagitta's at the flats (at ``r_sag`` of
    :func:`_plan`), and a round point's latitude polyline's.

    On a sphere of radius ``rho`` the sagitta between meridians, along its normal, is that
    at the flats scaled by ``r^2 / (rho r_sag)``, and the latitude polyline errs to the
    same side: the polyline takes what the sagitta leaves (a flatter sphere, more), or at
    least :data:`_MIN_LATITUDE_SHARE`, the meridians then closing in.
    """
    share = _SAGITTA_SHARE * ((1 - _HI_ARC_SHARE) if body.profile.fillet_hi > 0 else 1.0)
    env = body.envelope
    if env is None or env.kind != "sphere":
        return share, 0.0
    reach = _envelope_reach(env)
    ratio = reach / max(body.profile.r_hi, reach)
    latitude = _FLANK_SHARE - share * ratio
    if latitude < _MIN_LATITUDE_SHARE:
        latitude = _MIN_LATITUDE_SHARE
        share = (_FLANK_SHARE - latitude) / ratio
    return share, latitude


def _prime(n: int, residue: int) -> int:
    """The smallest prime ``>= max(n, 5)`` that is ``residue`` modulo 4."""
    n = max(n, 5)
    while True:
        if n % 4 == residue and all(n % d for d in range(2, math.isqrt(n) + 1)):
            return n
        n += 1


def _stations(profile: Profile, chord: float, flank_pieces: int) -> NDArray[np.float64]:
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


def _crossing_angles(
    body: ThreadBody, stations: NDArray[np.float64], trim: _Trim | None = None
) -> NDArray[np.float64]:
    """Angles in ``[0, 2 pi)`` at which a station's helix meets an end plane (one that the
    thread reaches: not an end face wholly inside an envelope), and, with an envelope, at
    which the ridge meets a station's helix or an extremum of ``h`` (:class:`_Trim`)."""
    p, lead, hand = body.profile.pitch, body.lead, body.hand
    starts = round(lead / p)
    out = []
    for z_end in (body.z_min, body.z_max):
        if trim is not None and _enveloped(body, z_end):
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


# -- envelopes -----------------------------------------------------------------------------
# Two kink roots (or a kink and a vertex) closer than this, in pitches, are one vertex; an
# inserted meridian's rounding stays far below it.
_KINK_TOL = 1e-10


@dataclass(frozen=True)
class _Trim:
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


def _envelope_reach(env: Envelope) -> float:
    """Largest ``radius x |n_r|`` over the envelope's span (its circumferential sagitta
    per unit of ``dtheta^2 / 8``, measured along its normal)."""
    r = float(np.max(np.abs(env.radius(np.array([env.z_lo, env.z_hi])))))
    if env.kind == "cone":
        return r / math.hypot(1.0, env.slope_rz)
    return r * r / env.rho


def _enveloped(body: ThreadBody, z: float) -> bool:
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


def _trim_plan(body: ThreadBody, stations: NDArray[np.float64], chord: float) -> _Trim | None:
    """The envelope's trim of ``body`` (None without one): see :class:`_Trim`."""
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
        c = _shares(body)[1] * chord
        dphi = 2.0 * math.acos(1.0 - c / env.rho) if c < env.rho else math.pi / 2
        n = max(1, math.ceil(abs(phi[1] - phi[0]) / dphi))
        levels = env.z0 - env.rho * np.cos(np.linspace(phi[0], phi[1], n + 1)[1:-1])
    return _Trim(env, env.side, grid, h, levels, profile)


def _kinks(
    body: ThreadBody, trim: _Trim, theta: NDArray[np.float64]
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
    tol = _KINK_TOL * p
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


@dataclass
class _Chain:
    """A meridian's vertices from the lower end plane to the upper one: indices, helix
    coordinates, heights, kink labels (label -> position), latitude-station flags."""

    idx: NDArray[np.int64]
    tau: NDArray[np.float64]
    z: NDArray[np.float64]
    marks: dict[int, int]
    lat: NDArray[np.bool_] | None = None


def _trimmed_chain(
    trim: _Trim,
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


def _meridians(crossings: NDArray[np.float64], count: int, turn: float) -> NDArray[np.float64]:
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


def _build(
    body: ThreadBody,
    stations: NDArray[np.float64],
    crossings: NDArray[np.float64],
    count: int,
    turn: float,
    chord: float,
    trim: _Trim | None = None,
) -> trimesh.Trimesh:
    profile = body.profile
    p, lead, hand = profile.pitch, body.lead, body.hand
    z_lo, z_hi = body.z_min, body.z_max
    theta = _meridians(crossings, count, turn)
    n_mer = len(theta)
    tol = 1e-9 * p
    kinks = _kinks(body, trim, theta) if trim is not None else None

    vertices: list[NDArray[np.float64]] = []
    chains: list[_Chain] = []
    n_vert = 0
    for j, th in enumerate(theta):
        s = hand * lead * th / TWO_PI
        lo, hi = z_lo - s, z_hi - s
        k = np.arange(math.floor((lo - stations[-1]) / p), math.ceil((hi - stations[0]) / p) + 1)
        tau = (stations[None, :] + p * k[:, None]).ravel()
        tau = np.sort(tau[(tau > lo + tol) & (tau < hi - tol)])
        # End vertices lie exactly on the end planes; on an inserted meridian they take the
        # crossing station's radius (the same helix, within the rounding of the angle).
        ends = np.array([lo, hi])
        near = [_station_at(e, stations, p, tol) for e in ends]
        if trim is None or kinks is None:
            r_ends = np.array(
                [
                    profile.radius(n if n is not None else e).item()
                    for e, n in zip(ends, near, strict=True)
                ]
            )
            r = np.concatenate([[r_ends[0]], profile.radius(tau), [r_ends[1]]])
            z = np.concatenate([[z_lo], tau + s, [z_hi]])
            key = np.concatenate([[lo], tau, [hi]])
            chain = _Chain(n_vert + np.arange(len(z)), key, z, {})
        else:
            t_ends = (lo if near[0] is None else near[0], hi if near[1] is None else near[1])
            key, z, r, marks, lat = _trimmed_chain(
                trim, s, (lo, hi), (z_lo, z_hi), t_ends, tau, kinks[j], _KINK_TOL * p
            )
            chain = _Chain(n_vert + np.arange(len(z)), key, z, marks, lat)
        vertices.append(np.column_stack([r * math.cos(th), r * math.sin(th), z]))
        chains.append(chain)
        n_vert += len(z)

    faces: list[NDArray[np.int64]] = []
    # Lateral strips; the last one joins the last meridian to the first one turned by a
    # full revolution, whose helix labels are shifted by one lead.
    starts = round(lead / p)
    n_grid = len(trim.grid) if trim is not None else 0
    for j in range(n_mer):
        last = j + 1 == n_mer
        faces.append(
            _strip(
                chains[j],
                chains[(j + 1) % n_mer],
                hand * lead if last else 0.0,
                hand * starts * n_grid if last else 0,
            )
        )
    lateral = np.concatenate(faces)
    if body.kind == "nut":
        lateral = lateral[:, ::-1]  # the nut's material lies outside the thread surface

    bottom = np.array([c.idx[0] for c in chains])
    top = np.array([c.idx[-1] for c in chains])
    caps: list[NDArray[np.int64]] = []
    if body.kind == "bolt":
        centres = np.array([[0.0, 0.0, z_lo], [0.0, 0.0, z_hi]])
        c_lo, c_hi = n_vert, n_vert + 1
        vertices.append(centres)
        nxt = np.roll(np.arange(n_mer), -1)
        caps.append(np.column_stack([np.full(n_mer, c_lo), bottom[nxt], bottom]))
        caps.append(np.column_stack([np.full(n_mer, c_hi), top, top[nxt]]))
    else:
        assert body.outer_radius is not None  # a nut body has its outer cylinder
        r_out = float(body.outer_radius)
        sag = 2.0 * math.acos(max(-1.0, 1.0 - _SAGITTA_SHARE * chord / r_out))
        n_out = _prime(math.ceil(TWO_PI / sag), 3)
        phi = TWO_PI / n_out * (np.arange(n_out, dtype=np.float64) + _NUT_GRID_TURN)
        ring = np.column_stack([r_out * np.cos(phi), r_out * np.sin(phi)])
        o_lo = n_vert + np.arange(n_out)
        o_hi = o_lo + n_out
        vertices.append(np.column_stack([ring, np.full(n_out, z_lo)]))
        vertices.append(np.column_stack([ring, np.full(n_out, z_hi)]))
        top_faces = _annulus(top, theta, o_hi, phi)
        caps.append(top_faces)
        caps.append(_annulus(bottom, theta, o_lo, phi)[:, ::-1])
        nxt = np.roll(np.arange(n_out), -1)
        caps.append(np.column_stack([o_lo, o_lo[nxt], o_hi]))
        caps.append(np.column_stack([o_lo[nxt], o_hi[nxt], o_hi]))
    mesh = trimesh.Trimesh(
        np.concatenate(vertices), np.concatenate([lateral, *caps]), process=False
    )
    return mesh


def _strip(a: _Chain, b: _Chain, shift: float, label_shift: int) -> NDArray[np.int64]:
    """Triangles between neighbouring meridians' chains (``b`` turned by ``shift`` of
    helix coordinate and ``label_shift`` of kink labels when it closes the revolution).

    Without kinks, one zipper in ``tau`` order. With them, the kinks of one branch on both
    chains are joined by an edge (so no triangle cuts across the ridge where thread and
    envelope meet), and the pieces between are zipped in ``tau`` order on the thread, in
    height order on a sphere (along its latitudes).
    """
    b_tau = b.tau - shift
    if not a.marks or not b.marks:
        return _zipper(a.idx, a.tau, b.idx, b_tau)
    pairs = sorted(
        {
            (pa, b.marks[lab + label_shift])
            for lab, pa in a.marks.items()
            if lab + label_shift in b.marks
        }
    )
    path = [(0, 0)]
    for pa, pb in pairs:
        if pa >= path[-1][0] and pb >= path[-1][1] and (pa, pb) != path[-1]:
            path.append((pa, pb))
    end = (len(a.idx) - 1, len(b.idx) - 1)
    if path[-1] != end:
        path.append(end)
    faces = []
    for (a0, b0), (a1, b1) in zip(path[:-1], path[1:], strict=True):
        sa, sb = slice(a0, a1 + 1), slice(b0, b1 + 1)
        inner = (
            np.concatenate([a.lat[a0 + 1 : a1], b.lat[b0 + 1 : b1]])
            if a.lat is not None and b.lat is not None
            else np.empty(0, bool)
        )
        if len(inner) and inner.all():
            faces.append(_zipper(a.idx[sa], a.z[sa], b.idx[sb], b.z[sb]))
        else:
            faces.append(_zipper(a.idx[sa], a.tau[sa], b.idx[sb], b_tau[sb]))
    return np.concatenate(faces)


def _station_at(tau: float, stations: NDArray[np.float64], p: float, tol: float) -> float | None:
    """The station (as a ``tau`` on the same helix) within ``tol`` of ``tau``, if any."""
    k = np.round((tau - stations) / p)
    cand = stations + k * p
    i = int(np.argmin(np.abs(cand - tau)))
    return float(cand[i]) if abs(cand[i] - tau) <= tol else None


def _zipper(
    a_idx: NDArray[np.int64],
    a_key: NDArray[np.float64],
    b_idx: NDArray[np.int64],
    b_key: NDArray[np.float64],
) -> NDArray[np.int64]:
    """Triangles stitching two vertex chains merged in ``key`` order.

    Each step advances the chain whose next vertex has the smaller key and makes the
    triangle ``(a, b, new)``; for chains on meridians ``theta_a < theta_b`` ordered upward
    this winds counter-clockwise seen from outside (+r).
    """
    keys = np.concatenate([a_key[1:], b_key[1:]])
    from_a = np.concatenate([np.ones(len(a_key) - 1, bool), np.zeros(len(b_key) - 1, bool)])
    from_a = from_a[np.argsort(keys, kind="stable")]
    ia = np.cumsum(from_a)
    ib = np.cumsum(~from_a)
    a_prev = a_idx[ia - from_a]
    b_prev = b_idx[ib - ~from_a]
    new = np.where(from_a, a_idx[ia], b_idx[ib])
    return np.column_stack([a_prev, b_prev, new])


def _annulus(
    inner: NDArray[np.int64],
    inner_angle: NDArray[np.float64],
    outer: NDArray[np.int64],
    outer_angle: NDArray[np.float64],
) -> NDArray[np.int64]:
    """Triangles of a flat ring between two closed chains, wound to face +z."""
    start = inner_angle[0]
    o_ang = start + np.mod(outer_angle - start, TWO_PI)
    order = np.argsort(o_ang)
    o_idx, o_ang = outer[order], o_ang[order]
    # Close both chains by repeating their first vertex one revolution on.
    i_idx = np.concatenate([inner, inner[:1]])
    i_ang = np.concatenate([inner_angle, [start + TWO_PI]])
    o_idx = np.concatenate([o_idx, o_idx[:1]])
    o_ang = np.concatenate([o_ang, o_ang[:1] + TWO_PI])
    # (inner, outer, new) turns from the radial direction to the circumferential: +z.
    return _zipper(i_idx, i_ang, o_idx, o_ang)
