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
from dataclasses import dataclass

import numpy as np
import trimesh
from numpy.typing import NDArray

from .._errors import InputError
from .._units import MM_PER_UNIT
from .._validate import check_number
from ._body import ThreadBody, bolt_body, nut_body
from ._profile import Profile
from ._spec import ThreadSpec

__all__ = [
    "DEFAULT_CHORD",
    "TessellatedBody",
    "bolt_mesh",
    "check_chord",
    "nut_mesh",
    "thread_meshes",
    "mesh_deviation",
]

TWO_PI = 2.0 * math.pi

#: Default chord tolerance per unit: 5e-6 in (the thesis's CAD models used 1e-4 in).
DEFAULT_CHORD: dict[str, float] = {"in": 5e-6, "mm": 5e-6 * MM_PER_UNIT["in"]}

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
# Finest and coarsest chord, in pitches: finer would make meshes of millions of triangles,
# coarser would no longer resemble a thread.
_FINEST_CHORD = 1e-6
_COARSEST_CHORD = 0.02
SQRT3 = math.sqrt(3.0)
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


def check_chord(spec: ThreadSpec, chord: float | None, name: str = "chord") -> float:
    """The chord tolerance to mesh ``spec`` with: ``chord`` checked (a positive length
    within the finest and coarsest the meshes accept, in pitches), or the default of the
    spec's units. The one check of a chord: the mesh, the sweep and the commands use it;
    messages name the chord ``name`` (an option's name, on the command line).

    Raises
    ------
    InputError
        Naming the chord and the range it must lie in.
    """
    if not isinstance(spec, ThreadSpec):
        raise InputError(f"spec must be a ThreadSpec, got {type(spec).__name__}")
    if chord is None:
        return DEFAULT_CHORD[spec.units]
    chord = check_number(name, chord)
    if chord <= 0:
        raise InputError(f"{name} must be a positive length, got {chord!r}")
    if chord < spec.pitch * _FINEST_CHORD:
        raise InputError(
            f"{name} {chord:g} {spec.units} is too fine (the meshes would have "
            f"many millions of triangles): give at least "
            f"{spec.pitch * _FINEST_CHORD:g}"
        )
    if chord > spec.pitch * _COARSEST_CHORD:
        raise InputError(
            f"{name} {chord:g} {spec.units} is too coarse for a pitch of "
            f"{spec.pitch:g} {spec.units}: give at most "
            f"{spec.pitch * _COARSEST_CHORD:g}"
        )
    return float(chord)


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
    crossings = _crossing_angles(body, stations)
    count = _prime(count, grid.residue)
    for _ in range(_MAX_REFINEMENTS):
        mesh = _build(body, stations, crossings, count, grid.turn, chord)
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
    share = _SAGITTA_SHARE * ((1 - _HI_ARC_SHARE) if profile.fillet_hi > 0 else 1.0)
    step_flat = 2.0 * math.acos(max(-1.0, 1.0 - share * chord / r_hi))
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


def _crossing_angles(body: ThreadBody, stations: NDArray[np.float64]) -> NDArray[np.float64]:
    """Angles in ``[0, 2 pi)`` at which a station's helix meets an end plane."""
    p, lead, hand = body.profile.pitch, body.lead, body.hand
    starts = round(lead / p)
    out = []
    for z_end in (body.z_min, body.z_max):
        for k in range(starts):
            frac = hand * (z_end - stations - k * p) / lead
            out.append(TWO_PI * (frac - np.floor(frac)))
    return np.concatenate(out)


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
) -> trimesh.Trimesh:
    profile = body.profile
    p, lead, hand = profile.pitch, body.lead, body.hand
    z_lo, z_hi = body.z_min, body.z_max
    theta = _meridians(crossings, count, turn)
    n_mer = len(theta)
    tol = 1e-9 * p

    vertices: list[NDArray[np.float64]] = []
    lists: list[tuple[NDArray[np.int64], NDArray[np.float64]]] = []  # (indices, tau)
    n_vert = 0
    for th in theta:
        s = hand * lead * th / TWO_PI
        lo, hi = z_lo - s, z_hi - s
        k = np.arange(math.floor((lo - stations[-1]) / p), math.ceil((hi - stations[0]) / p) + 1)
        tau = (stations[None, :] + p * k[:, None]).ravel()
        tau = np.sort(tau[(tau > lo + tol) & (tau < hi - tol)])
        # End vertices lie exactly on the end planes; on an inserted meridian they take the
        # crossing station's radius (the same helix, within the rounding of the angle).
        ends = np.array([lo, hi])
        near = [_station_at(e, stations, p, tol) for e in ends]
        r_ends = np.array(
            [
                profile.radius(n if n is not None else e).item()
                for e, n in zip(ends, near, strict=True)
            ]
        )
        r = np.concatenate([[r_ends[0]], profile.radius(tau), [r_ends[1]]])
        z = np.concatenate([[z_lo], tau + s, [z_hi]])
        key = np.concatenate([[lo], tau, [hi]])
        vertices.append(np.column_stack([r * math.cos(th), r * math.sin(th), z]))
        lists.append((n_vert + np.arange(len(z)), key))
        n_vert += len(z)

    faces: list[NDArray[np.int64]] = []
    # Lateral strips; the last one joins the last meridian to the first one turned by a
    # full revolution, whose helix labels are shifted by one lead.
    for j in range(n_mer):
        a_idx, a_key = lists[j]
        b_idx, b_key = lists[(j + 1) % n_mer]
        if j + 1 == n_mer:
            b_key = b_key - hand * lead
        faces.append(_zipper(a_idx, a_key, b_idx, b_key))
    lateral = np.concatenate(faces)
    if body.kind == "nut":
        lateral = lateral[:, ::-1]  # the nut's material lies outside the thread surface

    bottom = np.array([idx[0] for idx, _ in lists])
    top = np.array([idx[-1] for idx, _ in lists])
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
