"""Exact helical bodies: the bolt and the nut in their own frames (conventions.md).

A body is its profile swept along a helix: a point at radius ``r``, angle ``theta`` and
height ``z`` of the body's frame sits at profile coordinate
``t = wrap(z - hand * lead * theta / (2 pi))``. The bolt is material where
``r <= R_b(t)`` and ``0 <= z <= length``; the nut where ``R_n(t) <= r <= outer_radius``
and ``-height <= z <= 0``.

A bolt's point and a nut's countersink (:mod:`._ends`) trim the thread by a surface of
revolution ``r = envelope(z)``: the bolt is material where also ``r <= envelope(z)``,
the nut where also ``r >= envelope(z)``. Their regions are ``chamfer`` or ``round``
(bolt) and ``countersink`` (nut).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._angles import TWO_PI
from ._ends import Envelope, countersink_envelope, point_envelope
from ._profile import Profile, bolt_profile, nut_profile, wrap_t
from ._spec import filled

if TYPE_CHECKING:
    from ._spec import ThreadSpec

__all__ = ["ThreadBody", "bolt_body", "nut_body"]


@dataclass(frozen=True)
class ThreadBody:
    """One threaded body in its own frame.

    Attributes
    ----------
    profile : Profile
        The axial-section profile.
    lead : float
        Axial advance per turn (pitch x starts).
    hand : int
        +1 right hand, -1 left hand.
    z_min, z_max : float
        Axial extent in the body's frame (bolt ``[0, length]``, nut ``[-height, 0]``).
    outer_radius : float or None
        The nut's outer radius (None for the bolt).
    envelope : Envelope or None
        The bolt's point or the nut's countersink (None: the thesis's flat end).
    """

    profile: Profile
    lead: float
    hand: int
    z_min: float
    z_max: float
    outer_radius: float | None = None
    envelope: Envelope | None = None

    @property
    def kind(self) -> Literal["bolt", "nut"]:
        """``"bolt"`` or ``"nut"``."""
        return self.profile.body

    @property
    def cap_region(self) -> str:
        """Name of the end face that meets the other body: ``base`` or ``surface``."""
        return "base" if self.kind == "bolt" else "surface"

    @property
    def cap_z(self) -> float:
        """Height of that end face in the body's frame (0 for both bodies)."""
        return 0.0

    @property
    def end_regions(self) -> tuple[str, ...]:
        """Regions of the end that meets the other body: the end face, and the point's or
        countersink's surface when there is one."""
        return (self.cap_region,) + ((self.envelope.region,) if self.envelope else ())

    def thread_outline(self, z: float, samples: int = 2048) -> NDArray[np.float64]:
        """Points ``(samples, 3)`` of the lateral surface's outline at height ``z``."""
        theta = np.linspace(0.0, TWO_PI, samples, endpoint=False)
        r = self.lateral_radius(theta, z)
        return np.column_stack([r * np.cos(theta), r * np.sin(theta), np.full(samples, z)])

    def lateral_radius(self, theta: ArrayLike, z: ArrayLike) -> NDArray[np.float64]:
        """Radius of the lateral surface (thread trimmed by the envelope) at ``theta``
        (radians) and height ``z``."""
        R = self.profile.radius(self.t_of(theta, z))
        if self.envelope is None:
            return R
        e = self.envelope.radius(z)
        return np.minimum(R, e) if self.kind == "bolt" else np.maximum(R, e)

    def _on_envelope(self, R: NDArray[np.float64], z: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Where the envelope, not the thread, bounds the material (radius ``R`` of the
        thread at the same angle and height)."""
        if self.envelope is None:
            return np.zeros(np.shape(R), dtype=bool)
        e = self.envelope.radius(z)
        return e < R if self.kind == "bolt" else e > R

    def t_of(self, theta: ArrayLike, z: ArrayLike) -> NDArray[np.float64]:
        """Profile coordinate of the helix point at angle ``theta`` (radians) and height z."""
        theta = np.asarray(theta, dtype=float)
        return wrap_t(
            np.asarray(z, dtype=float) - self.hand * self.lead * theta / TWO_PI, self.profile.pitch
        )

    def section_radius(self, theta: ArrayLike, z: ArrayLike = 0.0) -> NDArray[np.float64]:
        """Radius of the cross-section at height ``z`` as a function of angle (radians).

        The thesis's eq. 2.5 and 2.9, for every region and fillet at once.
        """
        return self.profile.radius(self.t_of(theta, z))

    def section_slope(self, theta: ArrayLike, z: ArrayLike = 0.0) -> NDArray[np.float64]:
        """``dR/dtheta`` of the cross-section at height ``z`` (length per radian)."""
        return self.profile.slope(self.t_of(theta, z)) * (-self.hand * self.lead / TWO_PI)

    def helical_region(self, theta: ArrayLike, z: ArrayLike) -> NDArray[np.str_]:
        """Thread region (ignoring end faces) at angle ``theta`` (radians) and height z."""
        return self.profile.region(self.t_of(theta, z))

    def region_of(self, points: ArrayLike, face_tol: float | None = None) -> NDArray[np.str_]:
        """Region of surface points given in the body's frame (``(..., 3)``).

        A point within ``face_tol`` of the end face at ``z = 0`` (default: 1e-6 of a pitch)
        and not farther out on the thread surface than it is on the face is on the
        ``base`` (bolt) or ``surface`` (nut); a point nearer the point's or countersink's
        surface than the thread (and not on the face) has its region (``chamfer``,
        ``round``, ``countersink``); otherwise its thread region comes from the exact
        profile.
        """
        p = np.asarray(points, dtype=float)
        r = np.hypot(p[..., 0], p[..., 1])
        theta = np.arctan2(p[..., 1], p[..., 0])
        t = self.t_of(theta, p[..., 2])
        helical = self.profile.region(t)
        tol = face_tol if face_tol is not None else 1e-6 * self.profile.pitch
        d_face = np.abs(p[..., 2] - self.cap_z)
        d_thread = self.profile.distance(t, r)
        outline = self.lateral_radius(theta, self.cap_z)
        if self.envelope is not None:
            d_env = np.abs(self.envelope.signed_distance(r, p[..., 2]))
            env = self._on_envelope(self.profile.radius(t), p[..., 2]) | (d_env < d_thread)
            env &= np.isfinite(self.envelope.radius(p[..., 2]))
            helical = np.where(env, self.envelope.region, helical)
            d_thread = np.where(env, d_env, d_thread)
        on_face = (d_face <= tol) & (d_face <= d_thread)
        if self.kind == "bolt":
            on_face &= r <= outline + tol
        else:
            on_face &= r >= outline - tol
        return np.where(on_face, self.cap_region, helical)

    def surface_distance(self, points: ArrayLike) -> NDArray[np.float64]:
        """Upper bound on the distance from points (body frame) to the body's surface.

        The smaller of the axial-section distance to the lateral surface (the thread
        profile, or the point's or countersink's envelope where that bounds the material)
        and the distance to the end faces' planes (where the point lies over the face).
        """
        p = np.asarray(points, dtype=float)
        r = np.hypot(p[..., 0], p[..., 1])
        theta = np.arctan2(p[..., 1], p[..., 0])
        t = self.t_of(theta, p[..., 2])
        d = self.profile.distance(t, r)
        R = self.profile.radius(t)
        if self.envelope is not None:
            # The lateral surface is the thread or the envelope, whichever bounds the
            # material at this angle and height; from inside the material both distances
            # are upper bounds (the segment to either surface crosses the boundary first).
            z = p[..., 2]
            s_env = self.envelope.signed_distance(r, z)
            on_env = self._on_envelope(R, z)
            thread_in = r <= R if self.kind == "bolt" else r >= R
            inside = thread_in & (s_env <= 0) & np.isfinite(self.envelope.radius(z))
            d_env = np.abs(s_env)
            d = np.where(inside, np.minimum(d, d_env), np.where(on_env, d_env, d))
            R = self.lateral_radius(theta, p[..., 2])
        for zf in (self.z_min, self.z_max):
            over = r <= R if self.kind == "bolt" else (r >= R) & (r <= (self.outer_radius or 0))
            d = np.where(over, np.minimum(d, np.abs(p[..., 2] - zf)), d)
        if self.outer_radius is not None:
            d = np.minimum(
                d,
                np.where(
                    (p[..., 2] >= self.z_min) & (p[..., 2] <= self.z_max),
                    np.abs(r - self.outer_radius),
                    np.inf,
                ),
            )
        return d

    def contains(self, points: ArrayLike) -> NDArray[np.bool_]:
        """Exact material membership of points given in the body's frame."""
        p = np.asarray(points, dtype=float)
        r = np.hypot(p[..., 0], p[..., 1])
        theta = np.arctan2(p[..., 1], p[..., 0])
        R = self.lateral_radius(theta, p[..., 2])
        inside_z = (p[..., 2] >= self.z_min) & (p[..., 2] <= self.z_max)
        if self.kind == "bolt":
            return inside_z & (r <= R)
        return inside_z & (r >= R) & (r <= self.outer_radius)

    def depth(self, points: ArrayLike) -> NDArray[np.float64]:
        """How far points (body frame) lie inside the material (0 outside): an upper bound
        on the distance to the nearest surface, used for interference depth."""
        p = np.asarray(points, dtype=float)
        return np.where(self.contains(p), self.surface_distance(p), 0.0)


def bolt_body(spec: ThreadSpec) -> ThreadBody:
    """The exact bolt of ``spec`` in its frame: ``0 <= z <= bolt.length``, with its point."""
    envelope = point_envelope(spec.bolt.point, spec.bolt.major / 2.0, spec.bolt.minor / 2.0)
    return ThreadBody(
        bolt_profile(spec),
        spec.lead,
        spec.handedness,
        0.0,
        filled(spec.bolt.length),
        envelope=envelope,
    )


def nut_body(spec: ThreadSpec) -> ThreadBody:
    """The exact nut of ``spec`` in the fixed frame: ``-nut.height <= z <= 0``, with its
    countersink."""
    sink = spec.nut.countersink
    return ThreadBody(
        nut_profile(spec),
        spec.lead,
        spec.handedness,
        -filled(spec.nut.height),
        0.0,
        filled(spec.nut.outer_radius),
        envelope=countersink_envelope(sink, spec.nut.minor / 2.0) if sink else None,
    )
