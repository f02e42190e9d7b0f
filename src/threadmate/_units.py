"""Length units of a spec, their ratios and SI, and energies in mJ: the one module that
owns them.

Lengths in and out are in the spec's ``units`` (``"in"`` or ``"mm"``); the mechanics
works in SI inside (forces in N, stiffness in N m/rad, energies in J and reported in mJ).
"""

from __future__ import annotations

__all__ = [
    "FIGURE_UNITS",
    "METRES_PER_UNIT",
    "MJ_PER_J",
    "MM_PER_UNIT",
    "json_units",
    "to_metres",
    "unit_scale",
]

#: Millimetres in one length unit of a spec.
MM_PER_UNIT: dict[str, float] = {"in": 25.4, "mm": 1.0}
#: Metres in one length unit of a spec.
METRES_PER_UNIT: dict[str, float] = {u: mm / 1000.0 for u, mm in MM_PER_UNIT.items()}
#: Millijoules in one joule: energies are reported in mJ.
MJ_PER_J = 1e3
#: The unit of each kind of figure a JSON document reports (its ``units``), lengths aside.
FIGURE_UNITS: dict[str, str] = {
    "angle": "deg",
    "force": "N",
    "stiffness": "N m/rad",
    "lateral_stiffness": "N/m",
    "work": "mJ",
    "torque": "N m",
    "moment": "N m",
    "share": "1",
    "seconds": "s",
}


def json_units(length: str | None, *kinds: str, **more: str) -> dict[str, str]:
    """The ``units`` of a JSON document: ``length`` (a spec's unit; None: no lengths),
    the unit of each of ``kinds`` (:data:`FIGURE_UNITS`) and ``more`` as given."""
    head = {} if length is None else {"length": length}
    return {**head, **{k: FIGURE_UNITS[k] for k in kinds}, **more}


def to_metres(value: float, units: str) -> float:
    """``value`` in ``units`` expressed in metres."""
    return value * METRES_PER_UNIT[units]


def unit_scale(units: str, into: str) -> float:
    """How many of the length unit ``into`` make one ``units``: the factor that takes a
    length (or a mesh) from ``units`` into ``into``."""
    return MM_PER_UNIT[units] / MM_PER_UNIT[into]
