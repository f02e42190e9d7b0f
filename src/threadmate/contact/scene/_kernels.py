"""Compiled kernels of the exact contact geometry: the kink's height, the vertical touch,
the signed distance from a thread body, the feature at a point, where two exact edges
cross, which points can lie deep inside a thread body, the point of an edge closest to
the other body, the bolt's pose applied to a point or to paired triangles, the contacts'
rows of the descent.

The contact code asks these one edge or a few triangle pairs at a time, thousands of
times per rest state, where Python's and numpy's per-call overhead is most of the cost.
They are plain loops over floats, compiled by numba (:mod:`threadmate._compiled`:
once per machine, kept on disk). Without numba the same functions run as Python, slower,
with the same results but for the last bit of ``math.hypot`` (Python's own, not the C
library's) and of a fused multiply-add (:data:`threadmate._compiled.fma`).

The profile and the envelope travel as float arrays (:func:`profile_array`,
:func:`envelope_array`); each kernel repeats the arithmetic of the Python methods it stands
for operation for operation (:meth:`threadmate.geometry.Profile.radius` and ``slope``,
the envelope's ``radius`` and ``signed_distance``, :func:`scipy.optimize.brentq`), so
that its results are those methods' to the last bit, bar the order of rounding in a
library call. The feature at a point (:func:`feature`) goes further: it gives Python's
results to the last bit, Python's ``math.hypot`` and ``** 2`` included (:func:`_hypot`,
:data:`_TWO`), for its normals feed every descent step. The one that stands for no
method, :func:`deep_candidates`, is a filter before the exact tests, with margins far
above rounding: its last bits decide nothing. The bolt's pose is applied to a point as
numpy's BLAS applies it to a few (:func:`placed_in_fixed`, :func:`placed_in_bolt`).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from ..._angles import TWO_PI
from ..._compiled import compiled, fma

if TYPE_CHECKING:
    from ...geometry import ThreadBody

__all__ = [
    "CIRCLE",
    "HELIX",
    "KINK",
    "RIM",
    "SAMPLES",
    "EdgeCurve",
    "FEATURE_KINDS",
    "closest_on_edge",
    "contact_rows",
    "crossing_of_edges",
    "deep_candidates",
    "edge_points",
    "envelope_array",
    "feature",
    "kink_height",
    "least_on_grid",
    "paired_triangles",
    "placed_in_bolt",
    "placed_in_fixed",
    "profile_array",
    "signed_distance",
    "vertical_touch",
    "window_grid",
]

#: Relative tolerance of :func:`scipy.optimize.brentq` by default (four machine epsilons).
_RTOL = 4 * np.finfo(float).eps
#: Iterations of :func:`scipy.optimize.brentq` by default.
_MAXITER = 100
#: Cells of a pitch that bracket a kink's root, and how many each way are tried.
_CELLS = 64
_REACH = 32


def profile_array(body: ThreadBody) -> NDArray[np.float64]:
    """The body's profile as the kernels read it: ``a1..a4`` (breakpoints in ``u = |t|``),
    ``r_hi``, ``r_lo``, the major corner's centre ``(u, r)`` and fillet radius, the minor
    corner's, the pitch radius and the pitch (lengths in the spec's units)."""
    prof = body.profile
    a1, a2, a3, a4 = prof.breakpoints
    (hu, hr), (lu, lr) = prof.centre_hi, prof.centre_lo
    return np.array(
        [
            a1,
            a2,
            a3,
            a4,
            prof.r_hi,
            prof.r_lo,
            hu,
            hr,
            prof.fillet_hi,
            lu,
            lr,
            prof.fillet_lo,
            prof.pitch_diameter / 2,
            prof.pitch,
        ],
        dtype=float,
    )


def envelope_array(body: ThreadBody) -> NDArray[np.float64]:
    """The body's point or countersink as the kernels read it: kind (0 cone, 1 sphere),
    side, ``r0``, ``slope_rz``, ``z0``, ``rho``, ``z_lo``, ``z_hi``."""
    env = body.envelope
    if env is None:
        raise ValueError("the body has no point or countersink")
    return np.array(
        [
            0.0 if env.kind == "cone" else 1.0,
            float(env.side),
            env.r0,
            env.slope_rz,
            env.z0,
            env.rho,
            env.z_lo,
            env.z_hi,
        ],
        dtype=float,
    )


@compiled
def _profile_radius(prof: NDArray[np.float64], t: float) -> float:
    """``Profile.radius(t)`` of one number (:meth:`Profile._radius_at` of ``|wrap(t)|``)."""
    pitch = prof[13]
    u = abs(t - pitch * math.floor(t / pitch + 0.5))
    if u <= prof[0]:
        return prof[4]
    if u <= prof[1]:
        rho = prof[8]
        return prof[7] + math.sqrt(max(rho * rho - (u - prof[6]) ** 2, 0.0))
    if u <= prof[2]:
        return prof[12] + math.sqrt(3.0) * (pitch / 4 - u)
    if u <= prof[3]:
        rho = prof[11]
        return prof[10] - math.sqrt(max(rho * rho - (u - prof[9]) ** 2, 0.0))
    return prof[5]


@compiled
def _envelope_radius(env: NDArray[np.float64], z: float) -> float:
    """The envelope's radius at one height (+inf for the bolt, -inf for the nut beyond
    its span)."""
    if not env[6] <= z <= env[7]:
        return math.inf * env[1]
    if env[0] == 0.0:
        return env[2] + env[3] * z
    rho = env[5]
    return math.sqrt(max(rho * rho - (z - env[4]) ** 2, 0.0))


@compiled
def _gap(
    prof: NDArray[np.float64], env: NDArray[np.float64], rise: float, theta: float, h: float
) -> float:
    return _profile_radius(prof, h - rise * theta) - _envelope_radius(env, h)


@compiled
def _brentq(
    prof: NDArray[np.float64],
    env: NDArray[np.float64],
    rise: float,
    theta: float,
    xa: float,
    xb: float,
    xtol: float,
) -> float:
    """:func:`scipy.optimize.brentq` of :func:`_gap` on ``[xa, xb]`` (scipy's C code,
    step for step, with its default ``rtol`` and ``maxiter``)."""
    xpre, xcur = xa, xb
    xblk, fblk, spre, scur = 0.0, 0.0, 0.0, 0.0
    fpre = _gap(prof, env, rise, theta, xpre)
    fcur = _gap(prof, env, rise, theta, xcur)
    if fpre == 0.0:
        return xpre
    if fcur == 0.0:
        return xcur
    for _ in range(_MAXITER):
        if fpre != 0.0 and fcur != 0.0 and (math.copysign(1.0, fpre) != math.copysign(1.0, fcur)):
            xblk = xpre
            fblk = fpre
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):
            xpre = xcur
            xcur = xblk
            xblk = xpre
            fpre = fcur
            fcur = fblk
            fblk = fpre
        delta = (xtol + _RTOL * abs(xcur)) / 2
        sbis = (xblk - xcur) / 2
        if fcur == 0.0 or abs(sbis) < delta:
            return xcur
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:  # interpolate
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:  # extrapolate
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            if 2 * abs(stry) < min(abs(spre), 3 * abs(sbis) - delta):  # a good short step
                spre = scur
                scur = stry
            else:  # bisect
                spre = sbis
                scur = sbis
        else:  # bisect
            spre = sbis
            scur = sbis
        xpre = xcur
        fpre = fcur
        if abs(scur) > delta:
            xcur += scur
        else:
            xcur += delta if sbis > 0 else -delta
        fcur = _gap(prof, env, rise, theta, xcur)
    raise RuntimeError("the kink's height did not converge")


@compiled
def _kink_height(
    prof: NDArray[np.float64], env: NDArray[np.float64], rise: float, theta: float, z: float
) -> float:
    """The root of ``R(t(theta, h)) - envelope(h)`` nearest ``z``: bracketed on cells of a
    64th of a pitch stepped out from ``z`` (nearest first, the lower first on a tie, up to
    half a pitch each way), found by Brent's method; ``z`` clipped to the envelope's span
    when none is near."""
    z_lo, z_hi = env[6], env[7]
    z0 = min(max(z, z_lo), z_hi)
    step = prof[13] / _CELLS
    xtol = 1e-12 * prof[13]
    # Node k sits at z0 + k step (clipped), k in [-REACH, REACH]; NaN: not evaluated yet.
    heights = np.empty(2 * _REACH + 1)
    values = np.full(2 * _REACH + 1, np.nan)
    for k in range(1, _REACH + 1):
        for side in range(2):
            lo_k = -k if side == 0 else k - 1
            for j in (lo_k, lo_k + 1):
                i = j + _REACH
                if math.isnan(values[i]):
                    h = min(max(z0 + j * step, z_lo), z_hi)
                    heights[i] = h
                    values[i] = _gap(prof, env, rise, theta, h)
            h_lo, f_lo = heights[lo_k + _REACH], values[lo_k + _REACH]
            h_hi, f_hi = heights[lo_k + 1 + _REACH], values[lo_k + 1 + _REACH]
            if h_hi > h_lo and math.copysign(1.0, f_lo) != math.copysign(1.0, f_hi):
                if f_lo == 0.0:
                    return h_lo
                return _brentq(prof, env, rise, theta, h_lo, h_hi, xtol)
    return z0


class _Arrays(NamedTuple):
    """What the kernels read of one body."""

    body: Any  # kept, so that its ``id`` is not reused while the entry lives
    prof: NDArray[np.float64]  # :func:`profile_array`
    env: NDArray[np.float64]  # :func:`envelope_array` (zeros without one)
    rise: float  # the helix's rise per radian
    # :func:`signed_distance`'s and :func:`feature`'s: bolt (1) or nut (0), with an
    # envelope (1), hand times lead, the end face's height, its outline's radius with an
    # envelope, ``hypot(1, slope)`` of a cone's, and 2.0 (:data:`_TWO`).
    shape: NDArray[np.float64]


#: The kernels' arrays of the bodies asked last, by ``id``.
_ARRAYS: dict[int, _Arrays] = {}


def _arrays(body: ThreadBody) -> _Arrays:
    """The kernels' arrays of ``body``, made once."""
    got = _ARRAYS.get(id(body))
    if got is None or got.body is not body:
        if len(_ARRAYS) > 64:
            _ARRAYS.clear()
        env = body.envelope
        shape = np.array(
            [
                1.0 if body.kind == "bolt" else 0.0,
                0.0 if env is None else 1.0,
                float(body.hand * body.lead),
                body.cap_z,
                0.0 if env is None else env.face_radius,
                0.0 if env is None else math.hypot(1.0, env.slope_rz),
                2.0,  # (:data:`_TWO`)
            ]
        )
        got = _Arrays(
            body,
            profile_array(body),
            np.zeros(8) if env is None else envelope_array(body),
            float(body.hand * body.lead / TWO_PI),
            shape,
        )
        _ARRAYS[id(body)] = got
    return got


def _kink_arrays(body: ThreadBody) -> tuple[NDArray[np.float64], NDArray[np.float64], float]:
    """The profile's and envelope's arrays and the rise of a body with a kink."""
    if body.envelope is None:
        raise ValueError("the body has no point or countersink")
    got = _arrays(body)
    return got.prof, got.env, got.rise


def kink_height(body: ThreadBody, theta: float, z: float) -> float:
    """Height (body frame) where the thread meets the point or countersink at the polar
    angle ``theta`` (radians): the root of ``R(t(theta, h)) - envelope(h)`` nearest ``z``,
    bracketed on cells of a 64th of a pitch stepped out from ``z`` (nearest first, up to
    half a pitch each way) and found by Brent's method, which, unlike Newton's, the
    profile's corners do not defeat; ``z`` clipped to the envelope's span when no root is
    near."""
    prof, env, rise = _kink_arrays(body)
    return float(_kink_height(prof, env, rise, float(theta), float(z)))


@compiled
def _vertical_touch(
    a: NDArray[np.float64],
    b: NDArray[np.float64],
    drop: NDArray[np.float64],
    point: NDArray[np.float64],
) -> None:
    n = a.shape[0]
    cand = np.empty(15)
    cpts = np.empty((15, 3))
    for m in range(n):
        # Vertices inside the other triangle's projection: bolt vertices over the nut
        # triangle (candidates 0-2), nut vertices under the bolt triangle (3-5).
        for which in range(2):
            tri = b[m] if which == 0 else a[m]
            pts = a[m] if which == 0 else b[m]
            o0, o1, o2 = tri[0, 0], tri[0, 1], tri[0, 2]
            e00, e01, e02 = tri[1, 0] - o0, tri[1, 1] - o1, tri[1, 2] - o2
            e10, e11, e12 = tri[2, 0] - o0, tri[2, 1] - o1, tri[2, 2] - o2
            det = e00 * e11 - e01 * e10
            scale = (e00 * e00 + e01 * e01) + (e10 * e10 + e11 * e11)
            ok = abs(det) > 1e-12 * max(scale, 1e-300)
            safe = det if ok else 1.0
            for k in range(3):
                w0 = pts[k, 0] - o0
                w1 = pts[k, 1] - o1
                u = (w0 * e11 - w1 * e10) / safe
                v = (e00 * w1 - e01 * w0) / safe
                z = o2 + u * e02 + v * e12
                c = 3 * which + k
                if ok and u >= 0 and v >= 0 and u + v <= 1:
                    d = pts[k, 2] - z
                    cand[c] = d if which == 0 else -d
                else:
                    cand[c] = math.inf
                if which == 0:
                    cpts[c, 0], cpts[c, 1], cpts[c, 2] = pts[k, 0], pts[k, 1], z
                else:
                    cpts[c, 0], cpts[c, 1], cpts[c, 2] = pts[k, 0], pts[k, 1], pts[k, 2]
        # Crossings of edge projections, bolt edge (i, i+1) by nut edge (k, k+1),
        # row-major (candidates 6-14).
        for i in range(3):
            i1 = (i + 1) % 3
            p0, p1, p2 = a[m, i, 0], a[m, i, 1], a[m, i, 2]
            r0, r1, r2 = a[m, i1, 0] - p0, a[m, i1, 1] - p1, a[m, i1, 2] - p2
            for k in range(3):
                k1 = (k + 1) % 3
                q0, q1, q2 = b[m, k, 0], b[m, k, 1], b[m, k, 2]
                s0, s1, s2 = b[m, k1, 0] - q0, b[m, k1, 1] - q1, b[m, k1, 2] - q2
                den = r0 * s1 - r1 * s0
                ok = abs(den) > 1e-14 * max(math.hypot(r0, r1) * math.hypot(s0, s1), 1e-300)
                safe = den if ok else 1.0
                w0, w1 = q0 - p0, q1 - p1
                t = (w0 * s1 - w1 * s0) / safe
                u = (w0 * r1 - w1 * r0) / safe
                c = 6 + 3 * i + k
                pz = q2 + u * s2
                cpts[c, 0], cpts[c, 1], cpts[c, 2] = q0 + u * s0, q1 + u * s1, pz
                if ok and t >= 0 and t <= 1 and u >= 0 and u <= 1:
                    cand[c] = (p2 + t * r2) - pz
                else:
                    cand[c] = math.inf
        best = 0
        for c in range(1, 15):
            if cand[c] < cand[best]:
                best = c
        drop[m] = cand[best]
        if math.isfinite(cand[best]):
            point[m, 0], point[m, 1], point[m, 2] = cpts[best, 0], cpts[best, 1], cpts[best, 2]
        else:
            point[m, 0] = point[m, 1] = point[m, 2] = math.nan


def vertical_touch(
    bolt_tris: NDArray[np.float64], nut_tris: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Drop at which each bolt triangle first meets its nut triangle, and where (see
    :func:`threadmate.contact.scene.vertical_touch`, which this computes)."""
    a = np.ascontiguousarray(bolt_tris, dtype=float).reshape(-1, 3, 3)
    b = np.ascontiguousarray(nut_tris, dtype=float).reshape(-1, 3, 3)
    drop = np.empty(len(a))
    point = np.empty((len(a), 3))
    _vertical_touch(a, b, drop, point)
    return drop, point


@compiled
def _profile_slope(prof: NDArray[np.float64], t: float) -> float:
    """``Profile.slope(t)`` of one number: ``d radius / d t``."""
    pitch = prof[13]
    t = t - pitch * math.floor(t / pitch + 0.5)
    u = abs(t)
    if u <= prof[0]:
        out = 0.0
    elif u <= prof[1]:
        rho = prof[8]
        out = -(u - prof[6]) / math.sqrt(max(rho * rho - (u - prof[6]) ** 2, 1e-300))
    elif u <= prof[2]:
        out = -math.sqrt(3.0)
    elif u <= prof[3]:
        rho = prof[11]
        out = (u - prof[9]) / math.sqrt(max(rho * rho - (u - prof[9]) ** 2, 1e-300))
    else:
        out = 0.0
    return (-1.0 if t < 0 else 1.0) * out


@compiled
def _signed_distance(
    prof: NDArray[np.float64],
    env: NDArray[np.float64],
    shape: NDArray[np.float64],
    points: NDArray[np.float64],
    theta: NDArray[np.float64],
    out: NDArray[np.float64],
) -> None:
    is_bolt, with_env, hand_lead, cap_z, face, k_cone = (
        shape[0] > 0,
        shape[1] > 0,
        shape[2],
        shape[3],
        shape[4],
        shape[5],
    )
    pitch = prof[13]
    for i in range(points.shape[0]):
        x, y, z = points[i, 0], points[i, 1], points[i, 2]
        r = math.hypot(x, y)
        t = z - hand_lead * theta[i] / TWO_PI
        t = t - pitch * math.floor(t / pitch + 0.5)
        radial = (r - _profile_radius(prof, t)) / math.hypot(1.0, _profile_slope(prof, t))
        thread = radial if is_bolt else -radial
        off = z - cap_z
        side = -off if is_bolt else off
        d = thread if thread >= side else side
        if with_env and env[6] <= z <= env[7]:
            if env[0] == 0.0:
                bevel = env[1] * ((r - env[2] - env[3] * z) / k_cone)
            else:
                bevel = env[1] * (math.hypot(r, z - env[4]) - env[5])
            d = d if d >= bevel else bevel
        if (off < 0) if is_bolt else (off > 0):
            if with_env:
                outline = face
            else:
                tc = cap_z - hand_lead * theta[i] / TWO_PI
                outline = _profile_radius(prof, tc - pitch * math.floor(tc / pitch + 0.5))
            gap = r - outline if is_bolt else outline - r
            d = math.hypot(off, gap if gap >= 0.0 else 0.0)
        out[i] = d


def signed_distance(
    body: ThreadBody, points: NDArray[np.float64], theta: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Signed distance (negative inside the material) of ``points`` (``(n, 3)``, body
    frame) from the body: the thread's radial offset along its normal, cut by the end
    face and the point or countersink; beyond the end face, the distance to its outline.
    ``theta``, each point's polar angle, is numpy's ``arctan2``, which differs in the last
    bit from the C library's where numpy has SIMD code for it."""
    got = _arrays(body)
    out = np.empty(len(points))
    _signed_distance(got.prof, got.env, got.shape, points, theta, out)
    return out


@compiled
def _deep_candidates(
    prof: NDArray[np.float64],
    env: NDArray[np.float64],
    shape: NDArray[np.float64],
    points: NDArray[np.float64],
    rotation: NDArray[np.float64],
    origin: NDArray[np.float64],
    inverse: bool,
    z_lo: float,
    z_hi: float,
    gap: float,
    out: NDArray[np.int64],
) -> int:
    is_bolt, with_env, hand_lead = shape[0] > 0, shape[1] > 0, shape[2]
    r_hi, r_lo = prof[4], prof[5]
    rot, o = rotation, origin
    n = 0
    for i in range(points.shape[0]):
        px, py, pz = points[i, 0], points[i, 1], points[i, 2]
        if inverse:  # into the body's frame: (p - origin) @ rotation
            px, py, pz = px - o[0], py - o[1], pz - o[2]
            z = px * rot[0, 2] + py * rot[1, 2] + pz * rot[2, 2]
            if z < z_lo or z > z_hi:
                continue
            x = px * rot[0, 0] + py * rot[1, 0] + pz * rot[2, 0]
            y = px * rot[0, 1] + py * rot[1, 1] + pz * rot[2, 1]
        else:  # out of the moved body's frame: rotation @ p + origin
            z = rot[2, 0] * px + rot[2, 1] * py + rot[2, 2] * pz + o[2]
            if z < z_lo or z > z_hi:
                continue
            x = rot[0, 0] * px + rot[0, 1] * py + rot[0, 2] * pz + o[0]
            y = rot[1, 0] * px + rot[1, 1] * py + rot[1, 2] * pz + o[1]
        r = math.hypot(x, y)
        # The lateral radius lies within [r_lo, r_hi]: most points are decided here.
        if (r > r_hi - gap) if is_bolt else (r < r_lo + gap):
            continue
        lateral = _profile_radius(prof, z - hand_lead * math.atan2(y, x) / TWO_PI)
        if with_env:
            e = _envelope_radius(env, z)
            if (e < lateral) if is_bolt else (e > lateral):
                lateral = e
        if (lateral - r if is_bolt else r - lateral) > gap:
            out[n] = i
            n += 1
    return n


def deep_candidates(
    body: ThreadBody,
    points: NDArray[np.float64],
    rotation: NDArray[np.float64],
    origin: NDArray[np.float64],
    *,
    inverse: bool,
    depth: float,
    margin: float,
) -> NDArray[np.int64]:
    """Which of ``points`` can lie deeper than ``depth`` inside ``body``: their indices.

    ``points`` are moved into the body's frame first: by ``(p - origin) @ rotation``
    with ``inverse`` (fixed-frame points into a moved body's frame), else by
    ``rotation @ p + origin``. A point deeper than ``depth`` lies within the body's
    heights and at least ``depth`` inside its lateral radius at its angle and height
    (:meth:`ThreadBody.lateral_radius`; :meth:`ThreadBody.surface_distance` is no more
    than that radial gap): the points kept pass both tests with ``margin`` (heights)
    and half of ``depth`` to spare, so that rounding keeps every point the exact tests
    (:meth:`ThreadBody.contains`, ``surface_distance``) can find deep, and most others
    are left out at a few operations each.
    """
    got = _arrays(body)
    out = np.empty(len(points), dtype=np.int64)
    n = _deep_candidates(
        got.prof,
        got.env,
        got.shape,
        np.ascontiguousarray(points, dtype=float),
        np.ascontiguousarray(rotation, dtype=float),
        np.ascontiguousarray(origin, dtype=float),
        bool(inverse),
        float(body.z_min - margin),
        float(body.z_max + margin),
        0.5 * float(depth),
        out,
    )
    return out[:n]


#: The exact edges :func:`crossing_of_edges` follows, by how a point at a polar angle is found
#: on them: the kink (its height by root finding, then the envelope's radius), the circle
#: where an envelope meets the end face, the rim of a flat end (the profile's radius at
#: the end face), a helix (a sharp corner of the profile).
KINK, CIRCLE, RIM, HELIX = 0, 1, 2, 3


class EdgeCurve(NamedTuple):
    """An exact edge as :func:`crossing_of_edges` reads it."""

    kind: int  # :data:`KINK`, :data:`CIRCLE`, :data:`RIM` or :data:`HELIX`
    prof: NDArray[np.float64]  # :func:`profile_array`
    env: NDArray[np.float64]  # :func:`envelope_array` (zeros without one)
    rise: float  # the helix's rise per radian (the kink's root finding reads it)
    hand_lead: float  # the thread's hand times its lead
    radius: float  # the circle's or the helix's radius
    height: float  # the end face's height, or the helix's at ``angle``; the kink's start
    angle: float  # the helix's polar angle at ``height``


@compiled
def _on_curve(curve: EdgeCurve, angle: float, last: float) -> tuple[float, float, float, float]:
    """The point of ``curve`` at a polar angle, in its body's frame, and the kink's height
    to follow it from next (``last``: the one before)."""
    c, s = math.cos(angle), math.sin(angle)
    if curve.kind == KINK:
        z = _kink_height(curve.prof, curve.env, curve.rise, angle, last)
        r = _envelope_radius(curve.env, z)
        return r * c, r * s, z, z
    if curve.kind == CIRCLE:
        return curve.radius * c, curve.radius * s, curve.height, last
    if curve.kind == RIM:
        pitch = curve.prof[13]
        t = curve.height - curve.hand_lead * angle / TWO_PI
        r = _profile_radius(curve.prof, t - pitch * math.floor(t / pitch + 0.5))
        return r * c, r * s, curve.height, last
    rise = curve.hand_lead * (angle - curve.angle) / TWO_PI
    return curve.radius * c, curve.radius * s, curve.height + rise, last


@compiled
def _edge_crossing(
    nut: EdgeCurve,
    bolt: EdgeCurve,
    rotation: NDArray[np.float64],
    origin: NDArray[np.float64],
    a: float,
    b: float,
    out: NDArray[np.float64],
) -> bool:
    r00, r01, r02 = rotation[0, 0], rotation[0, 1], rotation[0, 2]
    r10, r11, r12 = rotation[1, 0], rotation[1, 1], rotation[1, 2]
    r20, r21, r22 = rotation[2, 0], rotation[2, 1], rotation[2, 2]
    o0, o1, o2 = origin[0], origin[1], origin[2]
    # Each kink is followed from its last root, in the order the points are asked.
    n_last, b_last = nut.height, bolt.height
    h = 1e-7
    gaps = np.empty(6)
    for _ in range(8):
        for k in range(3):
            q0, q1, _q2, n_last = _on_curve(nut, a + h if k == 1 else a, n_last)
            x, y, z, b_last = _on_curve(bolt, b + h if k == 2 else b, b_last)
            gaps[2 * k] = q0 - (r00 * x + r01 * y + r02 * z + o0)
            gaps[2 * k + 1] = q1 - (r10 * x + r11 * y + r12 * z + o1)
        g0, g1 = gaps[0], gaps[1]
        j00, j01 = (gaps[2] - g0) / h, (gaps[4] - g0) / h
        j10, j11 = (gaps[3] - g1) / h, (gaps[5] - g1) / h
        det = j00 * j11 - j01 * j10
        if det == 0.0 or not math.isfinite(det):
            return False
        da = (j01 * g1 - j11 * g0) / det
        db = (j10 * g0 - j00 * g1) / det
        a, b = a + da, b + db
        if not (math.isfinite(a) and math.isfinite(b)):
            return False
        if max(abs(da), abs(db)) < 1e-12:
            break
    out[0], out[1], out[2], n_last = _on_curve(nut, a, n_last)
    x, y, z, b_last = _on_curve(bolt, b, b_last)
    out[3] = r00 * x + r01 * y + r02 * z + o0
    out[4] = r10 * x + r11 * y + r12 * z + o1
    out[5] = r20 * x + r21 * y + r22 * z + o2
    return True


def crossing_of_edges(
    nut: EdgeCurve,
    bolt: EdgeCurve,
    rotation: NDArray[np.float64],
    origin: NDArray[np.float64],
    a: float,
    b: float,
) -> NDArray[np.float64] | None:
    """Where the nut's edge and the bolt's (at the pose ``(rotation, origin)``) cross seen
    along Z: Gauss-Newton on their polar angles from ``a`` and ``b`` (radians), with
    forward differences of 1e-7 rad, up to eight steps or until a step is below 1e-12
    rad. The nut edge's point and the bolt edge's above or below it (fixed frame),
    ``(2, 3)``; None where the Jacobian is singular or the angles leave the numbers."""
    out = np.empty(6)
    if not _edge_crossing(
        nut, bolt, np.ascontiguousarray(rotation), np.ascontiguousarray(origin), a, b, out
    ):
        return None
    return out.reshape(2, 3)


# -- the bolt's pose applied as numpy applies it ------------------------------------------
# numpy multiplies a few points by a 3 x 3 matrix through its BLAS; OpenBLAS, on processors
# with fused multiply-add, sums each coordinate as a chain of them, in the order below
# (:data:`threadmate._compiled.fma`). These reproduce ``Pose.to_fixed`` and
# ``Pose.to_bolt`` of two points or more (or of stacked triangles) to the last bit.


@compiled
def placed_in_fixed(
    x: float, y: float, z: float, rotation: NDArray[np.float64], origin: NDArray[np.float64]
) -> tuple[float, float, float]:
    """The point ``(x, y, z)`` of the bolt's frame in the fixed frame: ``p @ rotation.T +
    origin``."""
    r = rotation
    return (
        fma(z, r[0, 2], fma(y, r[0, 1], x * r[0, 0])) + origin[0],
        fma(z, r[1, 2], fma(y, r[1, 1], x * r[1, 0])) + origin[1],
        fma(z, r[2, 2], fma(y, r[2, 1], x * r[2, 0])) + origin[2],
    )


@compiled
def placed_in_bolt(
    x: float, y: float, z: float, rotation: NDArray[np.float64], origin: NDArray[np.float64]
) -> tuple[float, float, float]:
    """The point ``(x, y, z)`` of the fixed frame in the bolt's frame: ``(p - origin) @
    rotation``."""
    r = rotation
    dx, dy, dz = x - origin[0], y - origin[1], z - origin[2]
    return (
        fma(dz, r[2, 0], fma(dy, r[1, 0], dx * r[0, 0])),
        fma(dz, r[2, 1], fma(dy, r[1, 1], dx * r[0, 1])),
        fma(dz, r[2, 2], fma(dy, r[1, 2], dx * r[0, 2])),
    )


# -- the feature at a point ---------------------------------------------------------------
#: :func:`feature`'s ``shape`` slot holding 2.0, the exponent of Python's ``x ** 2``: read at
#: run time, it keeps the compiler from turning ``math.pow(x, 2.0)`` into ``x * x``, which
#: differs from the C library's ``pow`` (Python's ``**``) in the last bit of about one
#: result in a thousand.
_TWO = 6


@compiled
def _radius_as_python(prof: NDArray[np.float64], t: float, two: float) -> float:
    """:func:`_profile_radius` with Python's ``** 2`` (see :data:`_TWO`)."""
    pitch = prof[13]
    u = abs(t - pitch * math.floor(t / pitch + 0.5))
    if u <= prof[0]:
        return prof[4]
    if u <= prof[1]:
        rho = prof[8]
        return prof[7] + math.sqrt(max(rho * rho - math.pow(u - prof[6], two), 0.0))
    if u <= prof[2]:
        return prof[12] + math.sqrt(3.0) * (pitch / 4 - u)
    if u <= prof[3]:
        rho = prof[11]
        return prof[10] - math.sqrt(max(rho * rho - math.pow(u - prof[9], two), 0.0))
    return prof[5]


@compiled
def _envelope_radius_as_python(env: NDArray[np.float64], z: float, two: float) -> float:
    """:func:`_envelope_radius` with Python's ``** 2`` (see :data:`_TWO`)."""
    if not env[6] <= z <= env[7]:
        return math.inf * env[1]
    if env[0] == 0.0:
        return env[2] + env[3] * z
    rho = env[5]
    return math.sqrt(max(rho * rho - math.pow(z - env[4], two), 0.0))


@compiled
def _slope_as_python(prof: NDArray[np.float64], t: float, two: float) -> float:
    """:func:`_profile_slope` with Python's ``** 2`` (see :data:`_TWO`)."""
    pitch = prof[13]
    t = t - pitch * math.floor(t / pitch + 0.5)
    u = abs(t)
    if u <= prof[0]:
        out = 0.0
    elif u <= prof[1]:
        rho = prof[8]
        out = -(u - prof[6]) / math.sqrt(max(rho * rho - math.pow(u - prof[6], two), 1e-300))
    elif u <= prof[2]:
        out = -math.sqrt(3.0)
    elif u <= prof[3]:
        rho = prof[11]
        out = (u - prof[9]) / math.sqrt(max(rho * rho - math.pow(u - prof[9], two), 1e-300))
    else:
        out = 0.0
    return (-1.0 if t < 0 else 1.0) * out


@compiled
def _two_product(x: float, y: float) -> tuple[float, float]:
    """``x * y`` as ``hi + lo`` exactly (Dekker's product of Veltkamp's halves)."""
    t = x * 134217729.0
    xh = t - (t - x)
    xl = x - xh
    t = y * 134217729.0
    yh = t - (t - y)
    yl = y - yh
    p = xh * yh
    q = xh * yl + xl * yh
    hi = p + q
    return hi, p - hi + q + xl * yl


@compiled
def _hypot(x: float, y: float) -> float:
    """Python's own ``math.hypot(x, y)`` (CPython's ``vector_norm`` of two numbers: a sum
    of squares kept exact in two parts, its root corrected once), not the C library's,
    which differs from it in the last bit of one result in about two hundred: the exact
    geometry's Python methods use Python's, and this kernel gives their results to the
    last bit."""
    x = abs(x)
    y = abs(y)
    top = max(x, y)
    if math.isinf(top):
        return top
    if math.isnan(x) or math.isnan(y):
        return math.nan
    if top == 0.0:
        return top
    e = math.frexp(top)[1]
    if e < -1021:  # subnormal: far below any length here; the C library's is as good
        return math.hypot(x, y)
    scale = math.ldexp(1.0, -e)
    csum, frac1, frac2 = 1.0, 0.0, 0.0
    for v in (x * scale, y * scale):
        hi, lo = _two_product(v, v)
        s = csum + hi
        frac2 += (csum - s) + hi
        csum = s
        frac1 += lo
    h = math.sqrt(csum - 1.0 + (frac1 + frac2))
    hi, lo = _two_product(-h, h)
    s = csum + hi
    frac2 += (csum - s) + hi
    csum = s
    frac1 += lo
    h += (csum - 1.0 + (frac1 + frac2)) / (2.0 * h)
    return h / scale


#: :func:`feature` kinds, by the code the kernel returns.
FEATURE_KINDS = ("rim", "cap", "kink", "bevel", "corner", "thread")


@compiled
def _unit3(x: float, y: float, z: float) -> tuple[float, float, float]:
    n = math.sqrt(x * x + y * y + z * z)  # (numpy's ``v @ v`` of three: the same sum)
    if n > 0:
        return x / n, y / n, z / n
    return x, y, z


@compiled
def _helical_normal3(
    prof: NDArray[np.float64],
    is_bolt: bool,
    hand_lead: float,
    x: float,
    y: float,
    t: float,
    two: float,
) -> tuple[float, float, float]:
    r = max(_hypot(x, y), 1e-300)
    c, s = x / r, y / r
    slope = _slope_as_python(prof, t, two)
    g = slope * hand_lead / (TWO_PI * r)
    if is_bolt:
        return _unit3(c - g * s, s + g * c, -slope)
    return _unit3(-(c - g * s), -(s + g * c), slope)  # (the bolt's, reversed)


@compiled
def _bevel_normal3(
    env: NDArray[np.float64], k_cone: float, x: float, y: float, z: float
) -> tuple[float, float, float]:
    r = max(_hypot(x, y), 1e-300)
    if env[0] == 0.0:
        n_r, n_z = env[1] / k_cone, -env[1] * env[3] / k_cone
    else:
        h = _hypot(r, z - env[4])
        if h == 0.0:
            h = 1.0
        n_r, n_z = env[1] * r / h, env[1] * (z - env[4]) / h
    return n_r * x / r, n_r * y / r, n_z


@compiled
def _rim_tangent3(
    prof: NDArray[np.float64],
    with_env: bool,
    hand_lead: float,
    cap_z: float,
    x: float,
    y: float,
    two: float,
) -> tuple[float, float, float]:
    theta = math.atan2(y, x)
    if with_env:
        return -math.sin(theta), math.cos(theta), 0.0
    pitch = prof[13]
    t = cap_z - hand_lead * theta / TWO_PI
    t = t - pitch * math.floor(t / pitch + 0.5)
    radius = _radius_as_python(prof, t, two)
    d_radius = _slope_as_python(prof, t, two) * (-hand_lead / TWO_PI)
    c, s = math.cos(theta), math.sin(theta)
    return _unit3(d_radius * c - radius * s, d_radius * s + radius * c, 0.0)


@compiled
def _feature(
    prof: NDArray[np.float64],
    env: NDArray[np.float64],
    shape: NDArray[np.float64],
    x: float,
    y: float,
    z: float,
    tol: float,
    out: NDArray[np.float64],
) -> int:
    """The feature of a thread body at ``(x, y, z)`` (its frame): the code of its kind
    in :data:`FEATURE_KINDS`, and in ``out`` its face normal, edge tangent and side
    (:class:`._exact.Feature`). Python's arithmetic of the profile's, the envelope's and
    the helix's formulas, operation for operation, to the last bit (a test compares the
    two).
    """
    is_bolt, with_env, hand_lead, cap_z = shape[0] > 0, shape[1] > 0, shape[2], shape[3]
    face, k_cone, two = shape[4], shape[5], shape[_TWO]
    pitch = prof[13]
    cap_nz = -1.0 if is_bolt else 1.0
    r = _hypot(x, y)
    # The helix coordinate, the profile radius there and the distance to the thread.
    t = z - hand_lead * math.atan2(y, x) / TWO_PI
    t = t - pitch * math.floor(t / pitch + 0.5)
    R = _radius_as_python(prof, t, two)
    d_thread = abs(_hypot(x, y) - R) / _hypot(1.0, _slope_as_python(prof, t, two))
    d_cap = abs(z - cap_z)
    out[:] = np.nan
    if with_env:
        e = _envelope_radius_as_python(env, z, two)
        # The distance to the whole cone or sphere, also just beyond the span where it
        # trims the thread: the kink where a countersink meets the nut's crest lies on the
        # span's end.
        if env[0] == 0.0:
            at = (r - env[2] - env[3] * z) / _hypot(1.0, env[3])
        else:
            at = math.hypot(r, z - env[4]) - env[5]  # (numpy's hypot: the C library's)
        d_env = abs(env[1] * at)
        over = r <= face + tol if is_bolt else r >= face - tol
        near_cap = d_cap <= tol and over
        near_env = d_env <= tol
        if near_cap and near_env:
            b0, b1, b2 = _bevel_normal3(env, k_cone, x, y, z)
            out[3], out[4], out[5] = _rim_tangent3(prof, with_env, hand_lead, cap_z, x, y, two)
            out[6], out[7], out[8] = _unit3(0.0 + b0, 0.0 + b1, cap_nz + b2)
            return 0
        if near_cap or (over and d_cap < min(d_thread, d_env)):
            out[0], out[1], out[2] = 0.0, 0.0, cap_nz
            return 1
        bounds = math.isfinite(e) and (e < R if is_bolt else e > R)
        if near_env and d_thread <= tol:
            b0, b1, b2 = _bevel_normal3(env, k_cone, x, y, z)
            h0, h1, h2 = _helical_normal3(prof, is_bolt, hand_lead, x, y, t, two)
            out[3], out[4], out[5] = _unit3(b1 * h2 - b2 * h1, b2 * h0 - b0 * h2, b0 * h1 - b1 * h0)
            out[6], out[7], out[8] = _unit3(b0 + h0, b1 + h1, b2 + h2)
            return 2
        if near_env or (bounds and d_env < d_thread):
            out[0], out[1], out[2] = _bevel_normal3(env, k_cone, x, y, z)
            return 3
    over = r <= R + tol if is_bolt else r >= R - tol
    near_cap = d_cap <= tol and over
    if near_cap and d_thread <= tol:
        h0, h1, h2 = _helical_normal3(prof, is_bolt, hand_lead, x, y, t, two)
        out[3], out[4], out[5] = _rim_tangent3(prof, with_env, hand_lead, cap_z, x, y, two)
        out[6], out[7], out[8] = _unit3(0.0 + h0, 0.0 + h1, cap_nz + h2)
        return 0
    if near_cap or (over and d_cap < d_thread):
        out[0], out[1], out[2] = 0.0, 0.0, cap_nz
        return 1
    # A sharp corner: the profile point nearest to (t, r) within ``tol`` of one.
    u = abs(t)
    for k in range(2):
        if (prof[8] if k == 0 else prof[11]) > 0:
            continue  # a fillet: no corner
        uc = prof[0] if k == 0 else prof[3]
        if _hypot(u - uc, r - _radius_as_python(prof, uc, two)) <= tol:
            h = 1e-4 * pitch
            sign = 1.0 if t >= 0 else -1.0
            i0, i1, i2 = _helical_normal3(
                prof, is_bolt, hand_lead, x, y, sign * max(uc - h, 0.0), two
            )
            o0, o1, o2 = _helical_normal3(
                prof, is_bolt, hand_lead, x, y, sign * min(uc + h, pitch / 2), two
            )
            theta = math.atan2(y, x)
            out[3], out[4], out[5] = _unit3(
                -r * math.sin(theta), r * math.cos(theta), hand_lead / TWO_PI
            )
            out[6], out[7], out[8] = _unit3(i0 + o0, i1 + o1, i2 + o2)
            return 4
    out[0], out[1], out[2] = _helical_normal3(prof, is_bolt, hand_lead, x, y, t, two)
    return 5


def feature(body: ThreadBody, x: float, y: float, z: float, tol: float) -> tuple[str, Any]:
    """The feature of ``body`` at the point ``(x, y, z)`` (its frame) within ``tol``: its
    kind (:data:`FEATURE_KINDS`) and a (9,) array of its face normal, edge tangent and side
    (NaN where it has none; a face's side is its normal)."""
    got = _arrays(body)
    out = np.empty(9)
    return FEATURE_KINDS[_feature(got.prof, got.env, got.shape, x, y, z, tol, out)], out


# -- the search along an edge ------------------------------------------------------------
# Where an exact edge touches the other body's face, the contact point is refined along
# the edge (:func:`threadmate.contact.scene.refine_on_edge`): 17 polar angles about the
# best so far, the other body's signed distance at each, the least taken and moved to the
# vertex of the parabola through it and its neighbours, the window narrowed eightfold,
# three times. The kernel keeps numpy's results to the last bit: the points by
# :func:`_on_curve`, the pose by :func:`placed_in_fixed` and :func:`placed_in_bolt`, the
# distances by :func:`_signed_distance`, the angles by the C library's ``atan2``.

#: Angles sampled per window, the window's ends included.
SAMPLES = 17


@compiled
def _grid(best: float, half: float, out: NDArray[np.float64]) -> None:
    """``best + np.linspace(-half, half, SAMPLES)`` by numpy's arithmetic: the sample's
    number times the spacing, minus ``half``, the last sample ``half`` itself."""
    step = (half - -half) / (SAMPLES - 1)
    for i in range(SAMPLES - 1):
        out[i] = best + (float(i) * step + -half)
    out[SAMPLES - 1] = best + half


@compiled
def _points(curve: EdgeCurve, angles: NDArray[np.float64], out: NDArray[np.float64]) -> None:
    """The points of ``curve`` at ``angles`` (a kink followed from ``curve.height``, each
    root from the one before)."""
    last = curve.height
    for i in range(len(angles)):
        out[i, 0], out[i, 1], out[i, 2], last = _on_curve(curve, angles[i], last)


@compiled
def _least(angles: NDArray[np.float64], values: NDArray[np.float64]) -> float:
    """The angle of the least value (numpy's ``argmin``: the first, or the first NaN),
    moved to the vertex of the parabola through it and its neighbours where one opens
    upward."""
    j = 0
    for i in range(len(values)):
        if math.isnan(values[i]):
            j = i
            break
        if values[i] < values[j]:
            j = i
    best = angles[j]
    if 0 < j < len(values) - 1:
        a, b, c = values[j - 1], values[j], values[j + 1]
        den = a - 2 * b + c
        if den > 0:
            best += 0.5 * (a - c) / den * (angles[1] - angles[0])
    return best


@compiled
def _closest(
    curve: EdgeCurve,
    prof: NDArray[np.float64],
    env: NDArray[np.float64],
    shape: NDArray[np.float64],
    rotation: NDArray[np.float64],
    origin: NDArray[np.float64],
    into_bolt: bool,
    best: float,
    half: float,
    out: NDArray[np.float64],
) -> None:
    angles = np.empty(SAMPLES)
    points = np.empty((SAMPLES, 3))
    moved = np.empty((SAMPLES, 3))
    theta = np.empty(SAMPLES)
    values = np.empty(SAMPLES)
    for _ in range(3):
        _grid(best, half, angles)
        _points(curve, angles, points)
        for i in range(SAMPLES):
            x, y, z = points[i, 0], points[i, 1], points[i, 2]
            if into_bolt:  # the nut's edge, the bolt's face
                moved[i, 0], moved[i, 1], moved[i, 2] = placed_in_bolt(x, y, z, rotation, origin)
            else:  # the bolt's edge, the nut's face
                moved[i, 0], moved[i, 1], moved[i, 2] = placed_in_fixed(x, y, z, rotation, origin)
            theta[i] = math.atan2(moved[i, 1], moved[i, 0])
        _signed_distance(prof, env, shape, moved, theta, values)
        best = _least(angles, values)
        half /= 8
    out[0], out[1], out[2], _ = _on_curve(curve, best, curve.height)


def window_grid(best: float, half: float) -> NDArray[np.float64]:
    """The :data:`SAMPLES` polar angles (radians) of a window of half-width ``half``
    about ``best``."""
    out = np.empty(SAMPLES)
    _grid(float(best), float(half), out)
    return out


def edge_points(curve: EdgeCurve, angles: NDArray[np.float64]) -> NDArray[np.float64]:
    """The points of ``curve`` at polar ``angles`` (radians, in order; its body's frame),
    ``(n, 3)``."""
    angles = np.ascontiguousarray(angles, dtype=float)
    out = np.empty((len(angles), 3))
    _points(curve, angles, out)
    return out


def least_on_grid(angles: NDArray[np.float64], values: NDArray[np.float64]) -> float:
    """The angle of a window's least value, refined by the parabola through its
    neighbours (see the module docstring)."""
    return float(_least(angles, np.ascontiguousarray(values, dtype=float)))


def closest_on_edge(
    curve: EdgeCurve,
    face: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]],
    rotation: NDArray[np.float64],
    origin: NDArray[np.float64],
    into_bolt: bool,
    angle: float,
    half: float,
) -> NDArray[np.float64]:
    """The point of ``curve`` (its body's frame) where it comes closest to, or deepest
    into, the other body's exact surface, searched from the polar ``angle`` in a window of
    half-width ``half`` (radians); ``face``: the other body's profile, envelope and shape
    arrays (:func:`._kernels._arrays`); ``into_bolt``: the edge is the nut's and the face
    the bolt's (else the reverse), the bolt at ``(rotation, origin)``."""
    out = np.empty(3)
    _closest(
        curve,
        *face,
        np.ascontiguousarray(rotation, dtype=float),
        np.ascontiguousarray(origin, dtype=float),
        into_bolt,
        float(angle),
        float(half),
        out,
    )
    return out


# -- the paired triangles of a lowering --------------------------------------------------


@compiled
def _paired_triangles(
    bolt_vertices: NDArray[np.float64],
    bolt_faces: NDArray[np.int64],
    nut_vertices: NDArray[np.float64],
    nut_faces: NDArray[np.int64],
    pairs: NDArray[np.int64],
    rotation: NDArray[np.float64],
    origin: NDArray[np.float64],
    bolt: NDArray[np.float64],
    nut: NDArray[np.float64],
) -> None:
    for k in range(len(pairs)):
        b, n = pairs[k, 0], pairs[k, 1]
        for v in range(3):
            p = bolt_vertices[bolt_faces[b, v]]
            bolt[k, v, 0], bolt[k, v, 1], bolt[k, v, 2] = placed_in_fixed(
                p[0], p[1], p[2], rotation, origin
            )
            q = nut_vertices[nut_faces[n, v]]
            nut[k, v, 0], nut[k, v, 1], nut[k, v, 2] = q[0], q[1], q[2]


def paired_triangles(
    bolt_vertices: NDArray[np.float64],
    bolt_faces: NDArray[np.int64],
    nut_vertices: NDArray[np.float64],
    nut_faces: NDArray[np.int64],
    pairs: NDArray[np.int64],
    rotation: NDArray[np.float64],
    origin: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The vertices of the paired bolt and nut faces (``pairs`` of face numbers), each
    ``(n, 3, 3)``: the bolt's moved by the pose ``(rotation, origin)`` as
    ``Pose.to_fixed`` moves them (:func:`placed_in_fixed`), the nut's as they are. Asked
    at every lowering, of a few hundred pairs, where numpy's gathers and product cost most
    of the work."""
    bolt, nut = np.empty((len(pairs), 3, 3)), np.empty((len(pairs), 3, 3))
    _paired_triangles(
        bolt_vertices,
        bolt_faces,
        nut_vertices,
        nut_faces,
        np.ascontiguousarray(pairs, dtype=np.int64),
        np.ascontiguousarray(rotation, dtype=float),
        np.ascontiguousarray(origin, dtype=float),
        bolt,
        nut,
    )
    return bolt, nut


# -- the contacts' rows of the descent ----------------------------------------------------


@compiled
def _contact_rows(
    normal: NDArray[np.float64],
    point: NDArray[np.float64],
    gap: NDArray[np.float64],
    rate: NDArray[np.float64],
    centre: NDArray[np.float64],
    metres: float,
    pitch_axis: NDArray[np.float64],
    rows: NDArray[np.float64],
    gaps: NDArray[np.float64],
) -> None:
    n = len(gap)
    v0, v1, v2 = pitch_axis[0], pitch_axis[1], pitch_axis[2]
    for i in range(n):
        n0, n1, n2 = normal[i, 0], normal[i, 1], normal[i, 2]
        r0 = (point[i, 0] - centre[0]) * metres
        r1 = (point[i, 1] - centre[1]) * metres
        r2 = (point[i, 2] - centre[2]) * metres
        m0, m1, m2 = r1 * n2 - r2 * n1, r2 * n0 - r0 * n2, r0 * n1 - r1 * n0
        rows[i, 0], rows[i, 1] = n2, m0
        # The moment about the pitch axis as numpy's BLAS sums a matrix by a vector.
        if n == 1:
            rows[i, 2] = m0 * v0 + m1 * v1 + m2 * v2
        else:
            rows[i, 2] = fma(m2, v2, fma(m0, v0, m1 * v1))
        if rows.shape[1] == 5:
            rows[i, 3], rows[i, 4] = n0, n1
        gaps[i] = gap[i] * metres * rate[i]


def contact_rows(
    normal: NDArray[np.float64],
    point: NDArray[np.float64],
    gap: NDArray[np.float64],
    rate: NDArray[np.float64],
    centre: NDArray[np.float64],
    metres: float,
    pitch_axis: NDArray[np.float64],
    width: int,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Each contact's rate of opening per unit of the held bolt's coordinates (a row of
    ``width`` 3 or 5: the normal's Z part, its moment about the roll axis X and about
    ``pitch_axis`` (per metre of arm), then its X and Y parts), and its normal gap (the
    vertical ``gap`` in metres times its ``rate``): ``normal``, ``point`` (spec units, the
    arm from ``centre``, ``metres`` per unit), one row each. The numbers numpy gave: the
    moment about the pitch axis summed as the BLAS numpy calls sums a matrix by a vector
    (one row left to right; more, fused multiply-adds in its order). Asked several times
    per descent step, of one or two contacts, where numpy's per-call cost was all of it
    (:class:`threadmate.contact.Mechanics`)."""
    rows, gaps = np.empty((len(gap), width)), np.empty(len(gap))
    _contact_rows(
        np.ascontiguousarray(normal, dtype=float),
        np.ascontiguousarray(point, dtype=float),
        np.ascontiguousarray(gap, dtype=float),
        np.ascontiguousarray(rate, dtype=float),
        np.ascontiguousarray(centre, dtype=float),
        float(metres),
        np.ascontiguousarray(pitch_axis, dtype=float),
        rows,
        gaps,
    )
    return rows, gaps
