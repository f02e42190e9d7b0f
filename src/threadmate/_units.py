"""Length units of a spec and their conversion to SI: the one module that owns them.

Lengths in and out are in the spec's ``units`` (``"in"`` or ``"mm"``); the mechanics
works in SI inside (forces in N, stiffness in N m/rad, energies in J and reported in mJ).
"""

from __future__ import annotations

__all__ = ["METRES_PER_UNIT", "MM_PER_UNIT", "to_metres"]

#: Metres in one length unit of a spec.
METRES_PER_UNIT: dict[str, float] = {"in": 0.0254, "mm": 0.001}
#: Millimetres in one length unit of a spec.
MM_PER_UNIT: dict[str, float] = {"in": 25.4, "mm": 1.0}


def to_metres(value: float, units: str) -> float:
    """``value`` in ``units`` expressed in metres."""
    return value * METRES_PER_UNIT[units]
