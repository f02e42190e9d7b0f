"""The refinement of an edge-on-face contact as numpy computed it: the tests' reference for
the compiled search along an edge (``contact.scene._kernels.closest_on_edge``), which must
give these results to the last bit where numpy's ``cos``, ``sin`` and ``arctan2`` are the C
library's and its BLAS multiplies small matrices by chains of fused multiply-adds (as
OpenBLAS does on every x86-64 processor since 2013). Edge-on-edge contacts, which the
package refines by another kernel, are returned unmoved here."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from threadmate._angles import SQRT3, TWO_PI
from threadmate.contact.scene import Feature
from threadmate.contact.scene._exact import _sharp_corners
from threadmate.contact.scene._kernels import kink_height, signed_distance
from threadmate.geometry import Pose, ThreadBody


def _wrap(t: NDArray[np.float64], thread_pitch: float) -> NDArray[np.float64]:
    """``geometry``'s ``wrap_t``: an axial coordinate wrapped into ``[-p/2, p/2)``."""
    return t - thread_pitch * np.floor(t / thread_pitch + 0.5)


def _radius(body: ThreadBody, t: NDArray[np.float64]) -> NDArray[np.float64]:
    """``body.profile.radius(t)`` of an array: the same pieces and the same choice among
    them, by a chain of ``where`` (``np.select`` costs several times more on the short
    arrays of the contact code)."""
    prof = body.profile
    u = np.abs(_wrap(t, prof.pitch))
    a1, a2, a3, a4 = prof.breakpoints
    (hu, hr), (lu, lr) = prof.centre_hi, prof.centre_lo
    rh, rl = prof.fillet_hi, prof.fillet_lo
    # The contact code asks short runs of points close together, mostly on one piece of
    # the profile: that piece alone then, by the same formula as the chain below.
    lo, hi = (float(u.min()), float(u.max())) if u.size else (0.0, 0.0)
    if a2 < lo and hi <= a3:
        return prof.pitch_diameter / 2 + SQRT3 * (prof.pitch / 4 - u)
    if hi <= a1:
        return np.full_like(u, prof.r_hi)
    if a4 < lo:
        return np.full_like(u, prof.r_lo)
    out = np.where(u <= a4, lr - np.sqrt(np.maximum(rl * rl - (u - lu) ** 2, 0.0)), prof.r_lo)
    out = np.where(u <= a3, prof.pitch_diameter / 2 + SQRT3 * (prof.pitch / 4 - u), out)
    out = np.where(u <= a2, hr + np.sqrt(np.maximum(rh * rh - (u - hu) ** 2, 0.0)), out)
    return np.where(u <= a1, prof.r_hi, out)


def _t_array(
    body: ThreadBody, theta: NDArray[np.float64], z: NDArray[np.float64] | float
) -> NDArray[np.float64]:
    """:meth:`ThreadBody.t_of` without its argument conversions."""
    return _wrap(z - body.hand * body.lead * theta / TWO_PI, body.profile.pitch)


def signed_distance_at(body: ThreadBody, points_b: NDArray[np.float64]) -> NDArray[np.float64]:
    """Signed distance (negative inside the material) of points in the body's frame.

    Within the slab of the body, the thread surface's radial offset along its normal
    (first-order exact, exact on the surface), intersected with the end face's half-space
    and trimmed by the point or countersink where it spans. Beyond the end face that meets
    the other body (above the nut's top face, below the bolt's tip) the thread surface
    does not continue: there the distance is to the face's outline, radially, combined
    with the height off its plane. Computed by a compiled kernel
    (:func:`._kernels.signed_distance`).
    """
    p = np.ascontiguousarray(points_b, dtype=float).reshape(-1, 3)
    return signed_distance(body, p, np.arctan2(p[:, 1], p[:, 0]))


#: The sample numbers of a refinement's grid along an edge (:func:`_grid`).
_SAMPLES = np.arange(17.0)


def _grid(half: float) -> NDArray[np.float64]:
    """``np.linspace(-half, half, 17)`` by numpy's own arithmetic (its argument handling
    costs more than the grid, asked three times per edge refined)."""
    y = _SAMPLES * ((half - -half) / 16) + -half
    y[-1] = half
    return y


def _edge_points(
    body: ThreadBody, feature: Feature, anchor: NDArray[np.float64], angles: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Points of the exact edge through ``anchor`` (body frame) at polar ``angles``."""
    if feature.kind == "rim":
        if body.envelope is not None:
            r_rim = np.full_like(angles, body.envelope.face_radius)
        else:
            r_rim = _radius(body, _t_array(body, angles, body.cap_z))
        return np.column_stack(
            [r_rim * np.cos(angles), r_rim * np.sin(angles), np.full_like(angles, body.cap_z)]
        )
    if feature.kind == "kink":
        assert body.envelope is not None  # only a point or countersink has a kink
        z, h = np.empty(len(angles)), float(anchor[2])
        for i, angle in enumerate(angles):  # each root followed from the one before
            z[i] = h = kink_height(body, float(angle), h)
        r_k = body.envelope.radius(z)
        return np.column_stack([r_k * np.cos(angles), r_k * np.sin(angles), z])
    theta0 = math.atan2(anchor[1], anchor[0])
    r = math.hypot(anchor[0], anchor[1])
    prof = body.profile
    t0 = float(body.t_of(theta0, anchor[2]))
    # The corner's radius, exactly: the sharp corner nearest the anchor's profile point.
    corners = _sharp_corners(body)
    if corners:
        uc = min(corners, key=lambda u: abs(abs(t0) - u))
        r = float(prof.radius(uc))
    z = anchor[2] + body.hand * body.lead * (angles - theta0) / TWO_PI
    return np.column_stack([r * np.cos(angles), r * np.sin(angles), z])


def refine_on_edge(
    nut: ThreadBody,
    bolt: ThreadBody,
    pose: Pose,
    p: NDArray[np.float64],
    window: float,
    fn: Feature,
    fb: Feature,
) -> NDArray[np.float64]:
    """The exact point of an edge touching an exact face near ``p`` (fixed frame), the
    features there ``fn`` (the nut's) and ``fb`` (the bolt's); ``p`` where the contact is
    not one edge on one face."""
    if fn.is_edge == fb.is_edge:
        return p
    if fn.is_edge:
        edge_body, edge, anchor = nut, fn, p

        def gap(pts: NDArray[np.float64]) -> NDArray[np.float64]:
            return signed_distance_at(bolt, pose.to_bolt(pts))

        def to_f(pts: NDArray[np.float64]) -> NDArray[np.float64]:
            return pts
    else:
        edge_body, edge, anchor = bolt, fb, pose.to_bolt(p)

        def gap(pts: NDArray[np.float64]) -> NDArray[np.float64]:
            return signed_distance_at(nut, pose.to_fixed(pts))

        def to_f(pts: NDArray[np.float64]) -> NDArray[np.float64]:
            return pose.to_fixed(pts)

    theta0 = math.atan2(anchor[1], anchor[0])
    half = window / max(math.hypot(anchor[0], anchor[1]), 1e-300)
    best = theta0
    for _ in range(3):
        angles = best + _grid(half)
        values = gap(_edge_points(edge_body, edge, anchor, angles))
        j = int(np.argmin(values))
        best = float(angles[j])
        if 0 < j < 16:  # the parabola through the least value and its neighbours
            a, b, c = values[j - 1 : j + 2]
            den = a - 2 * b + c
            if den > 0:
                best += 0.5 * (a - c) / den * (angles[1] - angles[0])
        half /= 8
    return to_f(_edge_points(edge_body, edge, anchor, np.array([best])))[0]
