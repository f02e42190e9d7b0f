"""Standard hex nuts: their heights and the diameters of their countersinks.

What a designation's ``nut_height="standard"`` and default countersink
(:func:`threadmate.geometry.spec_from_designation`) take from the nut standards:

- **Heights.** Unified: ASME B18.2.2 hex nuts, the basic thickness, sizes 1/4 to 1 1/2
  in; ASME B18.6.3 hex machine screw nuts, the maximum thickness, sizes #0 to #12. ISO
  metric: ISO 4032 hex nuts style 1, ``m max``, M1.6 to M64 (ISO 8673's fine-pitch nuts
  have the same heights, so a fine pitch takes them too). A height belongs to the size,
  whatever the pitch. A size these tables do not hold has no standard height.
- **Countersink diameter at the face.** The mean of the standard's limits. Unified: ASME
  B18.2.2 (minimum the basic major diameter; maximum that plus 0.030 in for 3/8 in and
  smaller, 1.08 times it above), applied to every Unified size, the numbered sizes and
  those beyond 1 1/2 in included. ISO metric: ISO 4032's ``d_a`` (minimum ``d``; maximum
  tabulated M1.6 to M64); a size outside that table (M1, M1.2, M3.5, M7, ...) takes 1.08
  ``d`` as the maximum, as ASME B18.2.2 does above 3/8 in. The countersink must open
  beyond the nut's major diameter at the material condition: where the mean does not,
  the maximum is taken (and where that does not either, see
  :func:`standard_countersink_diameter`). The countersink's angle is
  :data:`threadmate.geometry._ends.COUNTERSINK_ANGLE` (120 degrees).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .._errors import SpecError

if TYPE_CHECKING:
    from ._designation import Designation

__all__ = [
    "UNIFIED_NUT_HEIGHTS",
    "ISO_NUT_HEIGHTS",
    "ISO_DA_MAX",
    "standard_nut_height",
    "countersink_limits",
    "standard_countersink_diameter",
]

#: Hex nut heights (in) by Unified size label: ASME B18.2.2 hex nuts, basic thickness
#: (1/4 to 1 1/2 in), and ASME B18.6.3 hex machine screw nuts, maximum thickness (#0 to
#: #12).
UNIFIED_NUT_HEIGHTS: dict[str, float] = {
    # ASME B18.6.3, hex machine screw nuts: maximum thickness.
    "#0": 0.050,
    "#1": 0.050,
    "#2": 0.066,
    "#3": 0.066,
    "#4": 0.098,
    "#5": 0.114,
    "#6": 0.114,
    "#8": 0.130,
    "#10": 0.130,
    "#12": 0.161,
    # ASME B18.2.2, hex nuts: basic thickness.
    "1/4": 7 / 32,
    "5/16": 17 / 64,
    "3/8": 21 / 64,
    "7/16": 3 / 8,
    "1/2": 7 / 16,
    "9/16": 31 / 64,
    "5/8": 35 / 64,
    "3/4": 41 / 64,
    "7/8": 3 / 4,
    "1": 55 / 64,
    "1 1/8": 31 / 32,
    "1 1/4": 1 + 1 / 16,
    "1 3/8": 1 + 11 / 64,
    "1 1/2": 1 + 9 / 32,
}

#: Hex nut heights (mm) by ISO size (basic major diameter, mm): ISO 4032 style 1, m max.
ISO_NUT_HEIGHTS: dict[float, float] = {
    1.6: 1.3,
    2.0: 1.6,
    2.5: 2.0,
    3.0: 2.4,
    4.0: 3.2,
    5.0: 4.7,
    6.0: 5.2,
    8.0: 6.8,
    10.0: 8.4,
    12.0: 10.8,
    14.0: 12.8,
    16.0: 14.8,
    18.0: 15.8,
    20.0: 18.0,
    22.0: 19.4,
    24.0: 21.5,
    27.0: 23.8,
    30.0: 25.6,
    33.0: 28.7,
    36.0: 31.0,
    39.0: 33.4,
    42.0: 34.0,
    45.0: 36.0,
    48.0: 38.0,
    52.0: 42.0,
    56.0: 45.0,
    60.0: 48.0,
    64.0: 51.0,
}

#: ISO 4032 ``d_a max`` (mm), the largest diameter of the bearing face's countersink, by
#: ISO size (its minimum is ``d``).
ISO_DA_MAX: dict[float, float] = {
    1.6: 1.84,
    2.0: 2.3,
    2.5: 2.9,
    3.0: 3.45,
    4.0: 4.6,
    5.0: 5.75,
    6.0: 6.75,
    8.0: 8.75,
    10.0: 10.8,
    12.0: 13.0,
    14.0: 15.1,
    16.0: 17.3,
    18.0: 19.5,
    20.0: 21.6,
    22.0: 23.7,
    24.0: 25.9,
    27.0: 29.1,
    30.0: 32.4,
    33.0: 35.6,
    36.0: 38.9,
    39.0: 42.1,
    42.0: 45.4,
    45.0: 48.6,
    48.0: 51.8,
    52.0: 56.2,
    56.0: 60.5,
    60.0: 64.8,
    64.0: 69.1,
}

#: ASME B18.2.2: countersink maximum ``d + 0.030 in`` up to and including 3/8 in ...
_UNIFIED_SMALL = 0.375
_UNIFIED_SMALL_EXTRA = 0.030
#: ... and ``1.08 d`` above (also our maximum for ISO sizes outside ISO 4032's table).
_LARGE_FACTOR = 1.08


def _iso_lookup(table: dict[float, float], size: float) -> float | None:
    for key, value in table.items():
        if abs(key - size) < 1e-9:
            return value
    return None


def standard_nut_height(designation: str | Designation) -> float:
    """Height of the standard hex nut of a designation's size, in its units.

    ASME B18.2.2 (1/4 to 1 1/2 in) and B18.6.3 (#0 to #12) for Unified sizes, ISO 4032
    style 1 (M1.6 to M64) for ISO metric sizes; see the module docstring.

    Raises
    ------
    SpecError
        For a size these tables do not hold, naming it and the sizes they cover.
    """
    from ._designation import parse_designation

    des = parse_designation(designation)
    if des.system == "unified":
        height = UNIFIED_NUT_HEIGHTS.get(des.size)
        covered = ", ".join(UNIFIED_NUT_HEIGHTS)
        where = "ASME B18.6.3 hex machine screw nuts and ASME B18.2.2 hex nuts"
    else:
        height = _iso_lookup(ISO_NUT_HEIGHTS, des.major)
        covered = ", ".join(f"M{d:g}" for d in ISO_NUT_HEIGHTS)
        where = "ISO 4032 hex nuts"
    if height is None:
        raise SpecError(
            f"no standard nut height for size {des.size}: the tables ({where}) cover "
            f"{covered}; give the nut's height as a length or in pitches"
        )
    return float(height)


def countersink_limits(designation: str | Designation) -> tuple[float, float]:
    """``(min, max)`` diameter of the standard nut's countersink at its face, in the
    designation's units (see the module docstring)."""
    from ._designation import parse_designation

    des = parse_designation(designation)
    d = des.major
    if des.system == "unified":
        if d <= _UNIFIED_SMALL + 1e-9:
            return d, d + _UNIFIED_SMALL_EXTRA
        return d, _LARGE_FACTOR * d
    da_max = _iso_lookup(ISO_DA_MAX, d)
    return d, (da_max if da_max is not None else _LARGE_FACTOR * d)


def standard_countersink_diameter(
    designation: str | Designation, nut_major: float | None = None
) -> float:
    """The default countersink diameter of a designation's nut: the mean of
    :func:`countersink_limits`, or their maximum when the mean does not exceed
    ``nut_major`` (the nut's major diameter at the material condition: the countersink
    must open beyond the thread).

    Where even the maximum does not (only M1 and M1.1 at minimum material, sizes below
    ISO 4032's table whose maximum is our 1.08 ``d``), the band of the limits is moved up
    to start at ``nut_major``: the diameter is ``nut_major`` plus half the band.
    """
    lo, hi = countersink_limits(designation)
    mean = (lo + hi) / 2.0
    if nut_major is None or mean > nut_major:
        return mean
    if hi > nut_major:
        return hi
    return nut_major + (hi - lo) / 2.0
