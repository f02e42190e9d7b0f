"""The feature of an exact thread body at a point, computed in Python (Python's
``math.hypot`` and ``** 2``, the exact bodies' own methods): the tests' reference for the
compiled ``contact.scene.feature_at`` (``contact.scene._kernels.feature``), which must give
these results to the last bit. The helpers that the package still computes in Python it
shares."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from threadmate._angles import TWO_PI
from threadmate._vectors import cross3
from threadmate.contact.scene import Feature
from threadmate.contact.scene._exact import (
    _helix_tangent,
    _sharp_corners,
    _t_of,
    _thread_distance,
    _unit,
)
from threadmate.geometry import ThreadBody


def _helical_normal(body: ThreadBody, p: NDArray[np.float64], t: float) -> NDArray[np.float64]:
    """Outward unit normal of the body's thread surface at ``p`` using the slope at ``t``."""
    r = max(math.hypot(p[0], p[1]), 1e-300)
    c, s = p[0] / r, p[1] / r
    slope = float(body.profile.slope(t))
    g_theta = slope * body.hand * body.lead / (TWO_PI * r)
    grad = np.array([c - g_theta * s, s + g_theta * c, -slope])
    return _unit(grad if body.kind == "bolt" else -grad)


def _rim_tangent(body: ThreadBody, p: NDArray[np.float64]) -> NDArray[np.float64]:
    theta = math.atan2(p[1], p[0])
    if body.envelope is not None:  # the end face's outline is a circle
        return np.array([-math.sin(theta), math.cos(theta), 0.0])
    t = _t_of(body, theta, body.cap_z)
    radius = float(body.profile.radius(t))
    d_radius = float(body.profile.slope(t)) * (-body.hand * body.lead / TWO_PI)
    c, s = math.cos(theta), math.sin(theta)
    return _unit(np.array([d_radius * c - radius * s, d_radius * s + radius * c, 0.0]))


def _cap_normal(body: ThreadBody) -> NDArray[np.float64]:
    """Outward unit normal of the body's end face (a new array: callers keep it)."""
    return np.array([0.0, 0.0, -1.0 if body.kind == "bolt" else 1.0])


def _bevel_normal(body: ThreadBody, p: NDArray[np.float64]) -> NDArray[np.float64]:
    """Outward unit normal of the body's point or countersink surface at ``p``."""
    assert body.envelope is not None
    r = max(math.hypot(p[0], p[1]), 1e-300)
    n_r, n_z = body.envelope.normal(r, float(p[2]))
    return np.array([n_r * p[0] / r, n_r * p[1] / r, n_z])


def _bevel_feature(
    body: ThreadBody,
    p: NDArray[np.float64],
    tol: float,
    t: float,
    R: float,
    d_thread: float,
    d_cap: float,
) -> Feature | None:
    """The feature at ``p`` of a body with a point or countersink, or None where the thread
    alone bounds it (then the thread's features apply)."""
    env = body.envelope
    assert env is not None
    r = math.hypot(p[0], p[1])
    z = float(p[2])
    e = float(env.radius(z))
    # The distance to the whole cone or sphere, also just beyond the span where it trims
    # the thread: the kink where a countersink meets the nut's crest lies on the span's end.
    d_env = abs(float(env.signed_distance(r, z)))
    face = env.face_radius
    over_cap = r <= face + tol if body.kind == "bolt" else r >= face - tol
    near_cap = d_cap <= tol and over_cap
    near_env = d_env <= tol
    if near_cap and near_env:
        side = _cap_normal(body) + _bevel_normal(body, p)
        return Feature("rim", None, _rim_tangent(body, p), _unit(side))
    if near_cap or (over_cap and d_cap < min(d_thread, d_env)):
        cap_normal = _cap_normal(body)
        return Feature("cap", cap_normal, None, cap_normal)
    bounds = math.isfinite(e) and (e < R if body.kind == "bolt" else e > R)
    if near_env and d_thread <= tol:
        n_env, n_thr = _bevel_normal(body, p), _helical_normal(body, p, t)
        return Feature("kink", None, _unit(cross3(n_env, n_thr)), _unit(n_env + n_thr))
    if near_env or (bounds and d_env < d_thread):
        n = _bevel_normal(body, p)
        return Feature("bevel", n, None, n)
    return None


def feature_at(body: ThreadBody, point: NDArray[np.float64], tol: float) -> Feature:
    """The feature of ``body`` at ``point`` (body frame) within ``tol``."""
    p = np.asarray(point, dtype=float)
    prof = body.profile
    r = math.hypot(p[0], p[1])
    t, R, d_thread = _thread_distance(body, p)
    d_cap = abs(p[2] - body.cap_z)
    if body.envelope is not None:
        found = _bevel_feature(body, p, tol, t, R, d_thread, d_cap)
        if found is not None:
            return found
    over_cap = r <= R + tol if body.kind == "bolt" else r >= R - tol
    near_cap = d_cap <= tol and over_cap
    near_thread = d_thread <= tol
    if near_cap and near_thread:
        side = _cap_normal(body) + _helical_normal(body, p, t)
        return Feature("rim", None, _rim_tangent(body, p), _unit(side))
    if near_cap or (over_cap and d_cap < d_thread):
        cap_normal = _cap_normal(body)
        return Feature("cap", cap_normal, None, cap_normal)
    # A sharp corner: the profile point nearest to (t, r) is within tol of a corner.
    u = abs(t)
    for uc in _sharp_corners(body):
        rc = float(prof.radius(uc))
        if math.hypot(u - uc, r - rc) <= tol:
            h = 1e-4 * prof.pitch
            sign = 1.0 if t >= 0 else -1.0
            n_in = _helical_normal(body, p, sign * max(uc - h, 0.0))
            n_out = _helical_normal(body, p, sign * min(uc + h, prof.pitch / 2))
            return Feature("corner", None, _helix_tangent(body, p), _unit(n_in + n_out))
    n = _helical_normal(body, p, t)
    return Feature("thread", n, None, n)
