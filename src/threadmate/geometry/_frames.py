"""Frames and poses (conventions.md, "Frames"): the one module that owns them.

Fixed frame F is the nut's: origin at the centre of its top face, +Z out of the nut toward
the bolt. Bolt frame B: origin at the centre of the bolt's tip face, +Z toward its head.
A bolt pose maps ``x_F = R @ x_B + origin`` with ``R = Rx(roll) @ Ry(pitch) @ Rz(phase)``,
active right-handed rotations, angles in degrees at every interface.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "Pose",
    "rot_x",
    "rot_y",
    "rot_z",
    "bolt_rotation",
    "axis_angle_rotation",
    "held_tilt_from_polar",
    "polar_from_held_tilt",
]


def rot_x(deg: float) -> NDArray[np.float64]:
    """Active right-handed rotation about X by ``deg`` degrees."""
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rot_y(deg: float) -> NDArray[np.float64]:
    """Active right-handed rotation about Y by ``deg`` degrees."""
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rot_z(deg: float) -> NDArray[np.float64]:
    """Active right-handed rotation about Z by ``deg`` degrees."""
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def bolt_rotation(roll: float, pitch: float, phase: float) -> NDArray[np.float64]:
    """``Rx(roll) @ Ry(pitch) @ Rz(phase)``: the bolt's orientation in F (degrees)."""
    return rot_x(roll) @ rot_y(pitch) @ rot_z(phase)


def held_tilt_from_polar(tilt: float, direction: float) -> tuple[float, float]:
    """The held ``(roll, pitch)`` of a tilt given by its size and direction (degrees).

    The polar form of a held tilt: the bolt axis (+Z of B, toward the head) makes the angle
    ``tilt`` with +Z of F and leans toward the azimuth ``direction``, measured in F (the
    nut's frame, fixed to its thread start) from +X toward +Y. With
    ``R = Rx(roll) @ Ry(pitch)`` the axis is ``(sin p, -sin r cos p, cos r cos p)``;
    equated to ``(sin t cos d, sin t sin d, cos t)`` it gives, exactly,

        pitch = asin(sin t cos d),    roll = atan2(-sin t sin d, cos t).

    So direction 0 is a positive pitch, 90 a negative roll, 180 a negative pitch and 270
    a positive roll; a tilt of 0 is upright whatever the direction.

    Parameters
    ----------
    tilt : float
        Angle between the bolt and nut axes, degrees in [0, 90).
    direction : float
        Azimuth toward which the bolt's axis leans, degrees (any value; modulo 360).

    Returns
    -------
    (roll, pitch) : tuple of float
        Degrees.
    """
    t, d = math.radians(tilt), math.radians(direction)
    pitch = math.degrees(math.asin(max(-1.0, min(1.0, math.sin(t) * math.cos(d)))))
    roll = math.degrees(math.atan2(-math.sin(t) * math.sin(d), math.cos(t)))
    return roll + 0.0, pitch + 0.0  # + 0.0 turns -0.0 into 0.0


def polar_from_held_tilt(roll: ArrayLike, pitch: ArrayLike) -> tuple[NDArray[Any], NDArray[Any]]:
    """The size and direction (degrees) of held tilts ``(roll, pitch)``: the inverse of
    :func:`held_tilt_from_polar`.

    The size is the angle between the bolt axis ``Rx(roll) Ry(pitch) e_z`` and +Z of F;
    the direction the azimuth of the axis's horizontal part, from +X toward +Y, in
    [0, 360); NaN for an upright axis (no direction).
    """
    r, p = np.radians(np.asarray(roll, dtype=float)), np.radians(np.asarray(pitch, dtype=float))
    ax, ay, az = np.sin(p), -np.sin(r) * np.cos(p), np.cos(r) * np.cos(p)
    horizontal = np.hypot(ax, ay)
    tilt = np.degrees(np.arctan2(horizontal, az))
    direction = np.where(horizontal > 0, np.degrees(np.arctan2(ay, ax)) % 360.0, np.nan)
    return tilt, direction


def axis_angle_rotation(axis: ArrayLike, deg: float) -> NDArray[np.float64]:
    """Active rotation by ``deg`` degrees about the unit direction ``axis`` (right hand)."""
    axis = np.asarray(axis, dtype=float)
    n = np.linalg.norm(axis)
    if n == 0:
        raise ValueError("rotation axis has zero length")
    # Rodrigues' formula: the searches build a pose per collision query, and scipy's
    # Rotation costs several times more per call than the query's own bookkeeping.
    x, y, z = axis / n
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    t = 1.0 - c
    return np.array(
        [
            [c + x * x * t, x * y * t - z * s, x * z * t + y * s],
            [y * x * t + z * s, c + y * y * t, y * z * t - x * s],
            [z * x * t - y * s, z * y * t + x * s, c + z * z * t],
        ]
    )


@dataclass(frozen=True)
class Pose:
    """A rigid placement of the bolt in the fixed frame: ``x_F = rotation @ x_B + origin``."""

    rotation: NDArray[np.float64]
    origin: NDArray[np.float64]

    @classmethod
    def from_angles(
        cls,
        roll: float,
        pitch: float,
        phase: float,
        h: float = 0.0,
        x: float = 0.0,
        y: float = 0.0,
    ) -> Pose:
        """The conventions' bolt pose: orientation from degrees, origin ``(x, y, h)``."""
        return cls(bolt_rotation(roll, pitch, phase), np.array([x, y, h], dtype=float))

    @classmethod
    def identity(cls) -> Pose:
        """The pose that leaves B on F."""
        return cls(np.eye(3), np.zeros(3))

    @property
    def matrix(self) -> NDArray[np.float64]:
        """The 4 x 4 homogeneous transform B -> F."""
        m = np.eye(4)
        m[:3, :3] = self.rotation
        m[:3, 3] = self.origin
        return m

    @property
    def axis(self) -> NDArray[np.float64]:
        """The bolt axis (+Z of B) in F."""
        return self.rotation[:, 2].copy()

    def to_fixed(self, points_b: ArrayLike) -> NDArray[np.float64]:
        """Map points (``(..., 3)``) from the bolt frame to the fixed frame."""
        return np.asarray(points_b, dtype=float) @ self.rotation.T + self.origin

    def to_bolt(self, points_f: ArrayLike) -> NDArray[np.float64]:
        """Map points (``(..., 3)``) from the fixed frame to the bolt frame."""
        return (np.asarray(points_f, dtype=float) - self.origin) @ self.rotation

    def vector_to_fixed(self, vectors_b: ArrayLike) -> NDArray[np.float64]:
        """Rotate direction vectors from B to F."""
        return np.asarray(vectors_b, dtype=float) @ self.rotation.T

    def vector_to_bolt(self, vectors_f: ArrayLike) -> NDArray[np.float64]:
        """Rotate direction vectors from F to B."""
        return np.asarray(vectors_f, dtype=float) @ self.rotation

    def translated(self, delta: ArrayLike) -> Pose:
        """This pose moved by ``delta`` (in F)."""
        return Pose(self.rotation, self.origin + np.asarray(delta, dtype=float))

    def rotated_about(self, point: ArrayLike, axis: ArrayLike, deg: float) -> Pose:
        """This pose turned by ``deg`` degrees about the line through ``point`` along ``axis``
        (both in F, right-hand rule)."""
        q = axis_angle_rotation(axis, deg)
        point = np.asarray(point, dtype=float)
        return Pose(q @ self.rotation, q @ (self.origin - point) + point)

    def angles(self) -> tuple[float, float, float]:
        """``(roll, pitch, phase)`` in degrees with ``R = Rx Ry Rz`` (extrinsic x-y-z read
        as intrinsic X-Y-Z)."""
        from scipy.spatial.transform import Rotation  # on demand: this module stays light

        roll, pitch, phase = Rotation.from_matrix(self.rotation).as_euler("XYZ", degrees=True)
        return float(roll), float(pitch), float(phase)
