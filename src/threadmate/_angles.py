"""Angles: the turn, phase wrapping and differences, the angle between two axes, and the
flank constant of the 60-degree thread: the one module that owns them.

Angles at every interface are degrees (conventions.md, "Units"); the geometry works in
radians inside (``turn=TWO_PI``). A phase counts modulo one turn: :func:`wrap_phase`
takes it into one turn, :func:`phase_difference` gives the shorter way round from one
phase to another, :func:`axis_angle` the angle between two axes (:data:`Z_AXIS`: the
nut's).
"""

from __future__ import annotations

import math
from typing import Any, overload

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "FULL_TURN",
    "SQRT3",
    "TWO_PI",
    "Z_AXIS",
    "axis_angle",
    "phase_difference",
    "wrap_phase",
]

#: One turn, degrees.
FULL_TURN = 360.0
#: One turn, radians.
TWO_PI = 2.0 * math.pi
#: ``sqrt(3)``: the radial change of a 60-degree thread's flank per unit of axial travel
#: (``1 / tan 30 deg``, the flank half-angle), as in ``R(t) = pd/2 + sqrt(3) (p/4 - |t|)``.
SQRT3 = math.sqrt(3.0)
#: +Z of the fixed frame F, the nut's axis (read-only).
Z_AXIS: NDArray[np.float64] = np.array([0.0, 0.0, 1.0])
Z_AXIS.setflags(write=False)


@overload
def wrap_phase(phase: float, turn: float = FULL_TURN) -> float: ...
@overload
def wrap_phase(phase: NDArray[Any], turn: float = FULL_TURN) -> NDArray[np.float64]: ...
def wrap_phase(phase: Any, turn: float = FULL_TURN) -> Any:
    """``phase`` modulo ``turn``: within ``[0, turn)``, except that a phase a hair below 0
    rounds to ``turn`` itself (degrees; ``turn=TWO_PI`` for radians)."""
    return phase % turn


@overload
def phase_difference(a: float, b: float = 0.0, turn: float = FULL_TURN) -> float: ...
@overload
def phase_difference(
    a: NDArray[Any], b: NDArray[Any] | float = 0.0, turn: float = FULL_TURN
) -> NDArray[np.float64]: ...
@overload
def phase_difference(a: float, b: NDArray[Any], turn: float = FULL_TURN) -> NDArray[np.float64]: ...
def phase_difference(a: Any, b: Any = 0.0, turn: float = FULL_TURN) -> Any:
    """``a - b`` the shorter way round, in ``[-turn/2, turn/2)`` (degrees; ``turn=TWO_PI``
    for radians). With ``b`` left at 0: ``a`` itself brought into that range."""
    half = turn / 2
    return (a - b + half) % turn - half


def axis_angle(a: NDArray[np.float64], b: NDArray[np.float64]) -> float:
    """Angle between two unit axes (degrees); their cosine is clipped to ``[-1, 1]`` against
    rounding."""
    return math.degrees(math.acos(max(-1.0, min(1.0, float(a @ b)))))
