"""Unified inch screw threads per ASME B1.1 (UN and UNR thread forms).

Series: UNC, UNF and UNEF (the standard's tables of threads per inch for each size), the
constant-pitch UN series (4, 6, 8, 12, 16, 20, 28 and 32 threads per inch) and UNS
(special pitches); the ``R`` variants (UNRC, UNRF, UNREF, UNR) differ only in the
mandatory rounded root of the external thread. Classes 1A/2A/3A (external) and 1B/2B/3B
(internal).

The limits follow the B1.1 formulas and its own calculation procedure (B1.1 appendix, as
reproduced in Machinery's Handbook): basic major diameter rounded to 4 places, pitch to 8,
the ``k * P`` thread heights and the tolerances to 6, every limit to 4; the internal minor
diameter of classes 1B and 2B is given to 3 places for sizes #6 (0.138 in) and larger.
This reproduces the published tables; the few published values that depart from the
formulas (the 5/8-11 and #12-32 allowances) are tabulated and stand.

- Pitch-diameter tolerance, class 2A: ``0.0015 D^(1/3) + 0.0015 LE^(1/2) + 0.015 P^(2/3)``
  with the standard length of engagement ``LE = D`` for UNC, UNF, 4-, 6- and 8-UN and
  ``LE = 9P`` for UNEF, 12- to 32-UN and UNS. Class multipliers: 1A 1.500, 3A 0.750,
  1B 1.950, 2B 1.300, 3B 0.975.
- Allowance (1A, 2A): 0.300 x the class 2A tolerance; 3A: 0.
- External major-diameter tolerance: ``0.060 P^(2/3)`` (2A, 3A), ``0.090 P^(2/3)`` (1A).
- Internal minor-diameter tolerance: B1.1 5.8.2(c) (see :func:`_minor_tolerance`).

Limits the standard does not give (documented choices that keep a valid geometry):

- External minor diameter: the maximum is B1.1's UNR reference ``d_max - 1.19078493 P``
  for UN and UNR alike (B1.1 allows a rounded root on UN external threads; the flat-root
  UN reference ``d_max - 1.08253175 P`` would leave a 3A bolt no radial clearance to a
  3B nut's minor diameter). The minimum is B1.1's reference ``d2_min - 0.64951905 P``
  (the 0.108P minimum root radius at the minimum pitch diameter), rounded inward.
- Internal major diameter: the minimum is the basic major diameter; the maximum is
  ``D2_max + 0.79385662 P`` (= D + TD2 + H/6: the root flat P/24 at the maximum pitch
  diameter), rounded inward.
- Root fillet of the external thread: the UNR root radius, 0.108P (minimum material) to
  0.144P (maximum material); the mean condition uses their mean 0.126P. Crests and the
  internal root are flat (fillet 0), as in the basic profile.
"""

from __future__ import annotations

import math
from decimal import ROUND_CEILING, ROUND_FLOOR, ROUND_HALF_EVEN, Decimal
from fractions import Fraction

__all__ = [
    "UNIFIED_SERIES",
    "UN_CONSTANT_PITCHES",
    "UNC",
    "UNF",
    "UNEF",
    "numbered_size",
    "series_table",
    "size_value",
    "unified_limits",
    "root_radius_range",
]

#: Series names accepted, mapped to their base series (the R variants share it).
UNIFIED_SERIES = {
    "UNC": "UNC",
    "UNRC": "UNC",
    "UNF": "UNF",
    "UNRF": "UNF",
    "UNEF": "UNEF",
    "UNREF": "UNEF",
    "UN": "UN",
    "UNR": "UN",
    "UNS": "UNS",
    "UNRS": "UNS",
}

#: Threads per inch of the constant-pitch UN series.
UN_CONSTANT_PITCHES = (4, 6, 8, 12, 16, 20, 28, 32)


def numbered_size(number: int) -> float:
    """Basic major diameter (in) of a numbered size: ``0.060 + 0.013 N``."""
    return 0.060 + 0.013 * number


def _fr(text: str) -> Fraction:
    whole, _, frac = text.partition(" ")
    if "/" in whole:
        return Fraction(whole)
    return Fraction(whole) + (Fraction(frac) if frac else 0)


# Standard series (ASME B1.1 Table 1): size label -> threads per inch.
UNC: dict[str, float] = {
    "#1": 64,
    "#2": 56,
    "#3": 48,
    "#4": 40,
    "#5": 40,
    "#6": 32,
    "#8": 32,
    "#10": 24,
    "#12": 24,
    "1/4": 20,
    "5/16": 18,
    "3/8": 16,
    "7/16": 14,
    "1/2": 13,
    "9/16": 12,
    "5/8": 11,
    "3/4": 10,
    "7/8": 9,
    "1": 8,
    "1 1/8": 7,
    "1 1/4": 7,
    "1 3/8": 6,
    "1 1/2": 6,
    "1 3/4": 5,
    "2": 4.5,
    "2 1/4": 4.5,
    "2 1/2": 4,
    "2 3/4": 4,
    "3": 4,
    "3 1/4": 4,
    "3 1/2": 4,
    "3 3/4": 4,
    "4": 4,
}
UNF: dict[str, float] = {
    "#0": 80,
    "#1": 72,
    "#2": 64,
    "#3": 56,
    "#4": 48,
    "#5": 44,
    "#6": 40,
    "#8": 36,
    "#10": 32,
    "#12": 28,
    "1/4": 28,
    "5/16": 24,
    "3/8": 24,
    "7/16": 20,
    "1/2": 20,
    "9/16": 18,
    "5/8": 18,
    "3/4": 16,
    "7/8": 14,
    "1": 12,
    "1 1/8": 12,
    "1 1/4": 12,
    "1 3/8": 12,
    "1 1/2": 12,
}
UNEF: dict[str, float] = {
    "#12": 32,
    "1/4": 32,
    "5/16": 32,
    "3/8": 32,
    "7/16": 28,
    "1/2": 28,
    "9/16": 24,
    "5/8": 24,
    "11/16": 24,
    "3/4": 20,
    "13/16": 20,
    "7/8": 20,
    "15/16": 20,
    "1": 20,
    "1 1/16": 18,
    "1 1/8": 18,
    "1 3/16": 18,
    "1 1/4": 18,
    "1 5/16": 18,
    "1 3/8": 18,
    "1 7/16": 18,
    "1 1/2": 18,
    "1 9/16": 18,
    "1 5/8": 18,
    "1 11/16": 18,
}
_TABLES = {"UNC": UNC, "UNF": UNF, "UNEF": UNEF}


def series_table(series: str) -> dict[str, float] | None:
    """The size -> threads-per-inch table of a standard series (None for UN, UNS)."""
    return _TABLES.get(UNIFIED_SERIES.get(series, series))


def size_value(label: str) -> float:
    """Basic major diameter (in) of a size label such as ``#10``, ``1/4`` or ``1 1/4``."""
    if label.startswith("#"):
        return numbered_size(int(label[1:]))
    return float(_fr(label))


# -- B1.1 arithmetic ---------------------------------------------------------------------


def _q(x: float | Decimal, places: int, mode: str = ROUND_HALF_EVEN) -> Decimal:
    """Round to ``places`` decimals the way the standard does (ties to even)."""
    return Decimal(repr(float(x)) if isinstance(x, float) else x).quantize(
        Decimal(1).scaleb(-places), rounding=mode
    )


# Allowances (1A, 2A) where the published B1.1 tables depart from 0.3 x Td2(2A) rounded
# (5/8-11: 0.3 x 0.005501 = 0.00165 is tabulated 0.0016; #12-32: 0.0009 for 0.00096).
_PUBLISHED_ALLOWANCE: dict[tuple[Decimal, float], Decimal] = {
    (Decimal("0.6250"), 11): Decimal("0.0016"),
    (Decimal("0.2160"), 32): Decimal("0.0009"),
}

_PD_FACTOR = {"1A": 1.500, "2A": 1.000, "3A": 0.750, "1B": 1.950, "2B": 1.300, "3B": 0.975}


def _length_of_engagement(series: str, tpi: float, major: Decimal, pitch: Decimal) -> Decimal:
    base = UNIFIED_SERIES[series]
    if base in ("UNC", "UNF") or (base == "UN" and tpi in (4, 6, 8)):
        return major
    return 9 * pitch


def _minor_tolerance(cls: str, major: float, pitch: float, tpi: float) -> float:
    """Internal minor-diameter tolerance, ASME B1.1 5.8.2(c)."""
    p, d = pitch, major
    formula = 0.05 * p ** (2 / 3) + 0.03 * p / d - 0.002
    if cls in ("1B", "2B"):
        if d < 0.25:
            return min(max(formula, 0.25 * p - 0.4 * p * p), 0.394 * p)
        return 0.25 * p - 0.4 * p * p if tpi >= 4 else 0.15 * p
    # Class 3B: the formula, not above 0.394P nor below 0.23P - 1.5P^2 (13 tpi and
    # finer) or 0.120P (coarser).
    floor = 0.23 * p - 1.5 * p * p if tpi >= 13 else 0.120 * p
    return min(max(formula, floor), 0.394 * p)


def root_radius_range(pitch: float) -> tuple[float, float]:
    """UNR external root radius: 0.108P (min) to 0.144P (max)."""
    return (0.108 * pitch, 0.144 * pitch)


def unified_limits(
    major: float, tpi: float, series: str, bolt_class: str, nut_class: str
) -> dict[str, dict[str, tuple[float, float]]]:
    """Limits of size of a Unified pair, in inches.

    Parameters
    ----------
    major : float
        Basic major diameter (in).
    tpi : float
        Threads per inch.
    series : str
        A key of :data:`UNIFIED_SERIES` (decides the length of engagement).
    bolt_class, nut_class : str
        ``1A``/``2A``/``3A`` and ``1B``/``2B``/``3B``.

    Returns
    -------
    dict
        ``{"bolt": {...}, "nut": {...}}``, each mapping ``major``, ``pitch_diameter``,
        ``minor``, ``crest_fillet`` and ``root_fillet`` to ``(min, max)``.
    """
    d_bsc = _q(major, 4)
    p = _q(1.0 / tpi, 8)
    pf = float(p)
    le = _length_of_engagement(series, tpi, d_bsc, p)
    td2_2a = 0.0015 * float(d_bsc) ** (1 / 3) + 0.0015 * math.sqrt(le) + 0.015 * pf ** (2 / 3)
    h_pitch = _q(0.64951905 * pf, 6)  # twice the external addendum: major - pitch dia.

    # External thread (bolt).
    if bolt_class == "3A":
        allowance = Decimal(0)
    else:
        allowance = _PUBLISHED_ALLOWANCE.get((d_bsc, tpi)) or _q(0.3 * td2_2a, 4)
    td = _q((0.090 if bolt_class == "1A" else 0.060) * pf ** (2 / 3), 6)
    d_max = _q(d_bsc - allowance, 4)
    d_min = _q(d_max - td, 4)
    d2_max = _q(d_max - h_pitch, 4)
    d2_min = _q(d2_max - _q(_PD_FACTOR[bolt_class] * td2_2a, 6), 4)
    # UNR reference maximum minor: d_max - 1.19078493 P, computed as the published tables
    # do, from the rounded maximum pitch diameter (1.19078493 - 0.64951905 = 0.54126588).
    d3_max = _q(d2_max - _q(0.54126588 * pf, 6), 4)
    d3_min = _q(d2_min - _q(0.64951905 * pf, 6), 4, ROUND_CEILING)

    # Internal thread (nut).
    d1_min4 = _q(d_bsc - _q(1.08253175 * pf, 6), 4)
    d1_max4 = _q(d1_min4 + _q(_minor_tolerance(nut_class, float(d_bsc), pf, tpi), 4), 4)
    if nut_class in ("1B", "2B") and d_bsc >= Decimal("0.138"):
        d1_min4, d1_max4 = _q(d1_min4, 3), _q(d1_max4, 3)
    D2_min = _q(d_bsc - h_pitch, 4)
    D2_max = _q(D2_min + _q(_PD_FACTOR[nut_class] * td2_2a, 6), 4)
    D_max = _q(D2_max + Decimal(repr(0.79385662 * pf)), 4, ROUND_FLOOR)

    root = root_radius_range(pf)
    return {
        "bolt": {
            "major": (float(d_min), float(d_max)),
            "pitch_diameter": (float(d2_min), float(d2_max)),
            "minor": (float(d3_min), float(d3_max)),
            "crest_fillet": (0.0, 0.0),
            "root_fillet": root,
        },
        "nut": {
            "major": (float(d_bsc), float(D_max)),
            "pitch_diameter": (float(D2_min), float(D2_max)),
            "minor": (float(d1_min4), float(d1_max4)),
            "crest_fillet": (0.0, 0.0),
            "root_fillet": (0.0, 0.0),
        },
    }
