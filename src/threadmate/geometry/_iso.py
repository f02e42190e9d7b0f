"""ISO general purpose metric screw threads: ISO 68-1, ISO 261 and ISO 965-1.

- ISO 68-1 basic profile: ``H = 0.866025 P``; ``d2 = d - 0.649519 P``,
  ``D1 = d - 1.082532 P``.
- ISO 261: the coarse and fine pitches of each nominal diameter from M1 to M64.
- ISO 965-1: fundamental deviations ``es`` (e, f, g, h) and ``EI`` (G, H); tolerances
  ``Td`` (grades 4, 6, 8), ``Td2`` (3 to 9), ``TD1`` and ``TD2`` (4 to 8) for the normal
  length of engagement N. ISO 965-1 gives formulas (e.g. ``Td2(6) = 90 P^0.4 d^0.1``)
  but rounds its tables to preferred numbers and departs from them in places (e.g.
  Td2(6) = 75 um for P = 0.5 in the 2.8-5.6 mm range where the formula gives 78): the
  tables stand, so they are tabulated here, in micrometres.

Limits are rounded to 3 decimals (mm), as in ISO 965-2. Limits the standard does not give
as numbers (documented choices):

- External minor diameter ``d3`` (ISO 965-1 root contour, minimum root radius
  ``R = 0.125 P``): minimum ``d2_min - 0.616025 P`` (the radius R tangent to both flanks at
  the minimum pitch diameter), maximum ``d2_max - H/2 - 2 R (1 - cos(60 deg - arccos(1 -
  Td2 / 4R)))`` (ISO 965-1's maximum root truncation); rounded inward, and kept at least
  0.001 mm below the basic minor diameter D1 so that bolt root and nut crest never meet.
- Internal major diameter: minimum ``D + EI``; maximum ``D2_max + 0.793857 P`` (root flat
  P/24 at the maximum pitch diameter, as ASME B1.13M), rounded inward.
- Root fillet of the external thread: R = 0.125 P at every condition; crests and the
  internal root are flat (fillet 0), as in the basic profile.
"""

from __future__ import annotations

import math
from decimal import ROUND_CEILING, ROUND_FLOOR, ROUND_HALF_EVEN, Decimal
from typing import TypeVar

from .._angles import SQRT3

_T = TypeVar("_T")

__all__ = [
    "ISO_261",
    "coarse_pitch",
    "iso_limits",
    "diameter_range",
    "tolerance_problem",
    "EXTERNAL_POSITIONS",
    "INTERNAL_POSITIONS",
]

# ISO 261 (with ISO 262 choices): nominal diameter -> (coarse pitch or None, fine pitches).
ISO_261: dict[float, tuple[float | None, tuple[float, ...]]] = {
    1: (0.25, (0.2,)),
    1.1: (0.25, (0.2,)),
    1.2: (0.25, (0.2,)),
    1.4: (0.3, (0.2,)),
    1.6: (0.35, (0.2,)),
    1.8: (0.35, (0.2,)),
    2: (0.4, (0.25,)),
    2.2: (0.45, (0.25,)),
    2.5: (0.45, (0.35,)),
    3: (0.5, (0.35,)),
    3.5: (0.6, (0.35,)),
    4: (0.7, (0.5,)),
    4.5: (0.75, (0.5,)),
    5: (0.8, (0.5,)),
    5.5: (None, (0.5,)),
    6: (1, (0.75,)),
    7: (1, (0.75,)),
    8: (1.25, (1, 0.75)),
    9: (1.25, (1, 0.75)),
    10: (1.5, (1.25, 1, 0.75)),
    11: (1.5, (1, 0.75)),
    12: (1.75, (1.5, 1.25, 1)),
    14: (2, (1.5, 1.25, 1)),
    15: (None, (1.5, 1)),
    16: (2, (1.5, 1)),
    17: (None, (1.5, 1)),
    18: (2.5, (2, 1.5, 1)),
    20: (2.5, (2, 1.5, 1)),
    22: (2.5, (2, 1.5, 1)),
    24: (3, (2, 1.5, 1)),
    25: (None, (2, 1.5, 1)),
    26: (None, (1.5,)),
    27: (3, (2, 1.5, 1)),
    28: (None, (2, 1.5, 1)),
    30: (3.5, (3, 2, 1.5, 1)),
    32: (None, (2, 1.5)),
    33: (3.5, (3, 2, 1.5)),
    35: (None, (1.5,)),
    36: (4, (3, 2, 1.5)),
    38: (None, (1.5,)),
    39: (4, (3, 2, 1.5)),
    40: (None, (3, 2, 1.5)),
    42: (4.5, (4, 3, 2, 1.5)),
    45: (4.5, (4, 3, 2, 1.5)),
    48: (5, (4, 3, 2, 1.5)),
    50: (None, (3, 2, 1.5)),
    52: (5, (4, 3, 2, 1.5)),
    55: (None, (4, 3, 2, 1.5)),
    56: (5.5, (4, 3, 2, 1.5)),
    58: (None, (4, 3, 2, 1.5)),
    60: (5.5, (4, 3, 2, 1.5)),
    62: (None, (4, 3, 2, 1.5)),
    64: (6, (4, 3, 2, 1.5)),
}

EXTERNAL_POSITIONS = ("e", "f", "g", "h")
INTERNAL_POSITIONS = ("G", "H")

_P = (
    0.2,
    0.25,
    0.3,
    0.35,
    0.4,
    0.45,
    0.5,
    0.6,
    0.7,
    0.75,
    0.8,
    1,
    1.25,
    1.5,
    1.75,
    2,
    2.5,
    3,
    3.5,
    4,
    4.5,
    5,
    5.5,
    6,
)


#: One value, or one row of grades, per pitch; None where ISO 965-1 gives none.
_Um = int | None
_Row = tuple[_Um, ...]


def _by_pitch(values: tuple[_T, ...]) -> dict[float, _T]:
    return dict(zip(_P, values, strict=True))


def _um_to_mm(value: _Um) -> float:
    """A tabulated value (um) in mm; the caller has checked that the table gives it."""
    assert value is not None
    return value / 1000.0


# ISO 965-1 Table 3: fundamental deviations, um (G: +, e/f/g: -, H and h: 0).
_G: dict[float, int] = _by_pitch(
    (
        17,
        18,
        18,
        19,
        19,
        20,
        20,
        21,
        22,
        22,
        24,
        26,
        28,
        32,
        34,
        38,
        42,
        48,
        53,
        60,
        63,
        71,
        75,
        80,
    )
)
_E: dict[float, _Um] = _by_pitch(
    (
        None,
        None,
        None,
        None,
        None,
        None,
        50,
        53,
        56,
        56,
        60,
        60,
        63,
        67,
        71,
        71,
        80,
        85,
        90,
        95,
        100,
        106,
        112,
        118,
    )
)
_F: dict[float, _Um] = _by_pitch(
    (
        None,
        None,
        None,
        34,
        34,
        35,
        36,
        36,
        38,
        38,
        38,
        40,
        42,
        45,
        48,
        52,
        58,
        63,
        70,
        75,
        80,
        85,
        90,
        95,
    )
)

# ISO 965-1 Table 4: TD1, internal minor diameter, grades 4..8, um.
_TD1: dict[float, _Row] = _by_pitch(
    (
        (38, None, None, None, None),
        (45, 56, None, None, None),
        (53, 67, 85, None, None),
        (63, 80, 100, None, None),
        (71, 90, 112, None, None),
        (80, 100, 125, None, None),
        (90, 112, 140, 180, None),
        (100, 125, 160, 200, None),
        (112, 140, 180, 224, None),
        (118, 150, 190, 236, None),
        (125, 160, 200, 250, 315),
        (150, 190, 236, 300, 375),
        (170, 212, 265, 335, 425),
        (190, 236, 300, 375, 475),
        (212, 265, 335, 425, 530),
        (236, 300, 375, 475, 600),
        (280, 355, 450, 560, 710),
        (315, 400, 500, 630, 800),
        (355, 450, 560, 710, 900),
        (375, 475, 600, 750, 950),
        (425, 530, 670, 850, 1060),
        (450, 560, 710, 900, 1120),
        (475, 600, 750, 950, 1180),
        (500, 630, 800, 1000, 1250),
    )
)

# ISO 965-1 Table 5: Td, external major diameter, grades 4, 6, 8, um.
_TD: dict[float, _Row] = _by_pitch(
    (
        (36, 56, None),
        (42, 67, None),
        (48, 75, None),
        (53, 85, None),
        (60, 95, None),
        (63, 100, None),
        (67, 106, None),
        (80, 125, None),
        (90, 140, None),
        (90, 140, None),
        (95, 150, 236),
        (112, 180, 280),
        (132, 212, 335),
        (150, 236, 375),
        (170, 265, 425),
        (180, 280, 450),
        (212, 335, 530),
        (236, 375, 600),
        (265, 425, 670),
        (300, 475, 750),
        (315, 500, 800),
        (335, 530, 850),
        (355, 560, 900),
        (375, 600, 950),
    )
)

#: Basic major diameter ranges of ISO 965-1 Tables 6 and 7: over lower, up to and incl. upper.
_RANGES = ((0.99, 1.4), (1.4, 2.8), (2.8, 5.6), (5.6, 11.2), (11.2, 22.4), (22.4, 45), (45, 90))

# ISO 965-1 Table 6: TD2, internal pitch diameter, grades 4..8, um; [range][pitch].
_TD2: tuple[dict[float, _Row], ...] = (
    {
        0.2: (40, None, None, None, None),
        0.25: (45, 56, None, None, None),
        0.3: (48, 60, 75, None, None),
    },
    {
        0.2: (42, None, None, None, None),
        0.25: (48, 60, None, None, None),
        0.35: (53, 67, 85, None, None),
        0.4: (56, 71, 90, None, None),
        0.45: (60, 75, 95, None, None),
    },
    {
        0.35: (56, 71, 90, None, None),
        0.5: (63, 80, 100, 125, None),
        0.6: (71, 90, 112, 140, None),
        0.7: (75, 95, 118, 150, None),
        0.75: (75, 95, 118, 150, None),
        0.8: (80, 100, 125, 160, 200),
    },
    {
        0.75: (85, 106, 132, 170, None),
        1: (95, 118, 150, 190, 236),
        1.25: (100, 125, 160, 200, 250),
        1.5: (112, 140, 180, 224, 280),
    },
    {
        1: (100, 125, 160, 200, 250),
        1.25: (112, 140, 180, 224, 280),
        1.5: (118, 150, 190, 236, 300),
        1.75: (125, 160, 200, 250, 315),
        2: (132, 170, 212, 265, 335),
        2.5: (140, 180, 224, 280, 355),
    },
    {
        1: (106, 132, 170, 212, None),
        1.5: (125, 160, 200, 250, 315),
        2: (140, 180, 224, 280, 355),
        3: (170, 212, 265, 335, 425),
        3.5: (180, 224, 280, 355, 450),
        4: (190, 236, 300, 375, 475),
        4.5: (200, 250, 315, 400, 500),
    },
    {
        1.5: (132, 170, 212, 265, 335),
        2: (150, 190, 236, 300, 375),
        3: (180, 224, 280, 355, 450),
        4: (200, 250, 315, 400, 500),
        5: (212, 265, 335, 425, 530),
        5.5: (224, 280, 355, 450, 560),
        6: (236, 300, 375, 475, 600),
    },
)

# ISO 965-1 Table 7: Td2, external pitch diameter, grades 3..9, um; [range][pitch].
_N = None
_TD2_EXT: tuple[dict[float, _Row], ...] = (
    {
        0.2: (24, 30, 38, 48, _N, _N, _N),
        0.25: (26, 34, 42, 53, _N, _N, _N),
        0.3: (28, 36, 45, 56, _N, _N, _N),
    },
    {
        0.2: (25, 32, 40, 50, _N, _N, _N),
        0.25: (28, 36, 45, 56, _N, _N, _N),
        0.35: (32, 40, 50, 63, 80, _N, _N),
        0.4: (34, 42, 53, 67, 85, _N, _N),
        0.45: (36, 45, 56, 71, 90, _N, _N),
    },
    {
        0.35: (34, 42, 53, 67, 85, _N, _N),
        0.5: (38, 48, 60, 75, 95, _N, _N),
        0.6: (42, 53, 67, 85, 106, _N, _N),
        0.7: (45, 56, 71, 90, 112, _N, _N),
        0.75: (45, 56, 71, 90, 112, _N, _N),
        0.8: (48, 60, 75, 95, 118, 150, 190),
    },
    {
        0.75: (50, 63, 80, 100, 125, _N, _N),
        1: (56, 71, 90, 112, 140, 180, 224),
        1.25: (60, 75, 95, 118, 150, 190, 236),
        1.5: (67, 85, 106, 132, 170, 212, 265),
    },
    {
        1: (60, 75, 95, 118, 150, 190, 236),
        1.25: (67, 85, 106, 132, 170, 212, 265),
        1.5: (71, 90, 112, 140, 180, 224, 280),
        1.75: (75, 95, 118, 150, 190, 236, 300),
        2: (80, 100, 125, 160, 200, 250, 315),
        2.5: (85, 106, 132, 170, 212, 265, 335),
    },
    {
        1: (63, 80, 100, 125, 160, 200, 250),
        1.5: (75, 95, 118, 150, 190, 236, 300),
        2: (85, 106, 132, 170, 212, 265, 335),
        3: (100, 125, 160, 200, 250, 315, 400),
        3.5: (106, 132, 170, 212, 265, 335, 425),
        4: (112, 140, 180, 224, 280, 355, 450),
        4.5: (118, 150, 190, 236, 300, 375, 475),
    },
    {
        1.5: (80, 100, 125, 160, 200, 250, 315),
        2: (90, 112, 140, 180, 224, 280, 355),
        3: (106, 132, 170, 212, 265, 335, 425),
        4: (118, 150, 190, 236, 300, 375, 475),
        5: (125, 160, 200, 250, 315, 400, 500),
        5.5: (132, 170, 212, 265, 335, 425, 530),
        6: (140, 180, 224, 280, 355, 450, 560),
    },
)


def coarse_pitch(diameter: float) -> float | None:
    """ISO 261 coarse pitch of a nominal diameter (None if it has none or is not listed)."""
    entry = ISO_261.get(diameter)
    return entry[0] if entry else None


def diameter_range(diameter: float) -> int | None:
    """Index of the ISO 965-1 basic-major-diameter range holding ``diameter``."""
    for i, (lo, hi) in enumerate(_RANGES):
        if lo < diameter <= hi + 1e-9:
            return i
    return None


def _deviation(position: str, pitch: float) -> int | None:
    """Fundamental deviation in um, signed (es <= 0 for external, EI >= 0 internal)."""
    if position in ("h", "H"):
        return 0
    if position == "G":
        return _G[pitch]
    if position == "g":
        return -_G[pitch]
    value = (_E if position == "e" else _F)[pitch]
    return None if value is None else -value


def tolerance_problem(
    diameter: float, pitch: float, position: str, pd_grade: int, crest_grade: int
) -> str | None:
    """Why ISO 965-1 gives no tolerance for this class (None when it does)."""
    rng = diameter_range(diameter)
    if rng is None:
        return f"ISO 965-1 tolerances cover basic major diameters 1 to 90 mm, not {diameter:g}"
    external = position in EXTERNAL_POSITIONS
    if pitch not in _G:
        return f"ISO 965-1 gives no tolerances for pitch {pitch:g}"
    if _deviation(position, pitch) is None:
        return f"ISO 965-1 defines no fundamental deviation '{position}' for pitch {pitch:g}"
    pd_table = (_TD2_EXT if external else _TD2)[rng]
    if pitch not in pd_table:
        return (
            f"ISO 965-1 gives no pitch-diameter tolerance for pitch {pitch:g} in the "
            f"{_RANGES[rng][0]:g}-{_RANGES[rng][1]:g} mm range"
        )
    pd_grades = range(3, 10) if external else range(4, 9)
    crest_grades = (4, 6, 8) if external else range(4, 9)
    what = "external" if external else "internal"
    if pd_grade not in pd_grades or pd_table[pitch][pd_grade - pd_grades[0]] is None:
        return (
            f"ISO 965-1 has no {what} pitch-diameter tolerance grade {pd_grade} for "
            f"M{diameter:g}x{pitch:g}"
        )
    crest = dict(zip(crest_grades, _TD[pitch] if external else _TD1[pitch], strict=True))
    if crest.get(crest_grade) is None:
        name = "major-diameter (Td)" if external else "minor-diameter (TD1)"
        return f"ISO 965-1 has no {what} {name} tolerance grade {crest_grade} for pitch {pitch:g}"
    return None


def _mm(x: float, mode: str = ROUND_HALF_EVEN) -> float:
    return float(Decimal(repr(x)).quantize(Decimal("0.001"), rounding=mode))


def iso_limits(
    diameter: float,
    pitch: float,
    bolt_class: tuple[str, int, int],
    nut_class: tuple[str, int, int],
) -> dict[str, dict[str, tuple[float, float]]]:
    """Limits of size (mm) of an ISO metric pair.

    Parameters
    ----------
    diameter, pitch : float
        Basic major diameter and pitch, mm.
    bolt_class, nut_class : tuple
        ``(position, pitch-diameter grade, crest grade)``, e.g. ``("g", 6, 6)`` for 6g
        and ``("H", 6, 6)`` for 6H (the crest is the bolt's major, the nut's minor).

    Returns
    -------
    dict
        ``{"bolt": {...}, "nut": {...}}`` of ``(min, max)`` tuples, as
        :func:`threadmate.geometry._unified.unified_limits`.

    Raises
    ------
    ValueError
        If ISO 965-1 gives no tolerance for a class (see :func:`tolerance_problem`).
    """
    for position, pd_grade, crest_grade in (bolt_class, nut_class):
        problem = tolerance_problem(diameter, pitch, position, pd_grade, crest_grade)
        if problem:
            raise ValueError(problem)
    rng = diameter_range(diameter)
    assert rng is not None
    h = SQRT3 / 2 * pitch
    d2 = diameter - 0.649519 * pitch
    d1 = diameter - 1.082532 * pitch

    position, pd_grade, crest_grade = bolt_class
    es = _um_to_mm(_deviation(position, pitch))
    td2 = _um_to_mm(_TD2_EXT[rng][pitch][pd_grade - 3])
    td = _um_to_mm(_TD[pitch][(4, 6, 8).index(crest_grade)])
    d_max, d2_max = diameter + es, d2 + es
    d2_min = d2_max - td2
    r = 0.125 * pitch
    # ISO 965-1 maximum root truncation below the sharp-V root at the maximum pitch dia.
    trunc = h / 4 - r * (1 - math.cos(math.pi / 3 - math.acos(1 - td2 / (4 * r))))
    bolt = {
        "major": (_mm(d_max - td), _mm(d_max)),
        "pitch_diameter": (_mm(d2_min), _mm(d2_max)),
        # Kept 0.001 below the nut's smallest minor diameter: for position h at fine
        # pitches the maximum root sits within microns of D1 and would round onto it.
        "minor": (
            _mm(_mm(d2_min) - 0.616025 * pitch, ROUND_CEILING),
            min(_mm(_mm(d2_max) - h + 2 * trunc, ROUND_FLOOR), _mm(_mm(d1) - 0.001)),
        ),
        "crest_fillet": (0.0, 0.0),
        "root_fillet": (r, r),
    }

    position, pd_grade, crest_grade = nut_class
    ei = _um_to_mm(_deviation(position, pitch))
    td2n = _um_to_mm(_TD2[rng][pitch][pd_grade - 4])
    td1 = _um_to_mm(_TD1[pitch][crest_grade - 4])
    nut_d2_max = d2 + ei + td2n
    nut = {
        "major": (_mm(diameter + ei), _mm(_mm(nut_d2_max) + 0.793857 * pitch, ROUND_FLOOR)),
        "pitch_diameter": (_mm(d2 + ei), _mm(nut_d2_max)),
        "minor": (_mm(d1 + ei), _mm(d1 + ei + td1)),
        "crest_fillet": (0.0, 0.0),
        "root_fillet": (0.0, 0.0),
    }
    return {"bolt": bolt, "nut": nut}
