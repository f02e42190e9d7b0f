"""Length units of a spec, their ratios and SI, and energies in mJ: the one module that
owns them.

Lengths in and out are in the spec's ``units`` (``"in"`` or ``"mm"``); the mechanics
works in SI inside (forces in N, stiffness in N m/rad, energies in J and reported in mJ).
"""

from __future__ import annotations

__all__ = ["METRES_PER_UNIT", "MJ_PER_J", "MM_PER_UNIT", "to_metres", "unit_scale"]

#: Millimetres in one length unit of a spec.
MM_PER_UNIT: dict[str, float] = {"in": 25.4, "mm": 1.0}
#: Metres in one length unit of a spec.
METRES_PER_UNIT: dict[str, float] = {u: mm / 1000.0 for u, mm in MM_PER_UNIT.items()}
#: Millijoules in one joule: energies are reported in mJ.
MJ_PER_J = 1e3


def to_metres(value: float, units: str) -> float:
    """``value`` in ``units`` expressed in metres."""
    return value * METRES_PER_UNIT[units]


def unit_scale(units: str, into: str) -> float:
    """How many of the length unit ``into`` make one ``units``: the factor that takes a
    length (or a mesh) from ``units`` into ``into``."""
    return MM_PER_UNIT[units] / MM_PER_UNIT[into]
