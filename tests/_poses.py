"""Pose arithmetic the tests recompute from states and library rows themselves."""

from __future__ import annotations

import math
from typing import Any

import numpy as np


def axis_angle(rotation_a: Any, rotation_b: Any) -> float:
    """Angle (degrees) between the bolt axes of two rotations (3 x 3, or 9 row-major)."""
    a = np.reshape(np.asarray(rotation_a, dtype=float), (3, 3))[:, 2]
    b = np.reshape(np.asarray(rotation_b, dtype=float), (3, 3))[:, 2]
    return math.degrees(math.acos(min(1.0, float(a @ b))))


def leaves_branch(fall: float, turned: float, in_phase: bool, thread_pitch: float) -> bool:
    """Whether two states are a jump apart by the continuation's thresholds (mechanics.md):
    the second in phase, or the compliance centre fallen more than thread_pitch / 40, or the
    bolt axis turned more than 0.5 degree."""
    return in_phase or fall > thread_pitch / 40 or turned > 0.5
