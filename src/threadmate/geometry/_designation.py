"""Thread designations: parsing, limits of size, and expansion into a :class:`ThreadSpec`.

Accepted forms (case and spacing are free; ``LH``/``RH`` may follow a space or a dash):

- Unified (ASME B1.1): ``1/4-20 UNC-2A/2B``, ``1/4-20 UNC-2A`` (the nut takes the same
  class number, 2B), ``1/4-20 UNC`` (2A/2B), ``#10-24 UNC``, ``10-24 UNC``,
  ``0.250-20 UNC-2A``, ``1 1/4-7 UNC`` or ``1-1/4-7 UNC``, ``1/2-28 UN-2A``,
  ``1/2-13 UNRC-2A/2B LH``; series UNC, UNF, UNEF, UN, UNS and their UNR forms.
  A bare integer size is a numbered size when the series table says so (``10-24 UNC``
  is #10, ``1-8 UNC`` is 1 in); for UN and UNS, 0 and 5 to 12 are numbered sizes, and
  1 to 4 are numbered only with more than 32 threads per inch (finer than any UN series).
- ISO metric: ``M6x1-6g/6H``, ``M6x1``, ``M8`` (coarse pitch), ``M10x1.25-6g``,
  ``M6x1-5g6g/6H``, ``M6x1-6g/6H-LH``. Default class 6g/6H (5H/6h up to M1.4, as ISO
  965-1 prescribes; the nearest finer grade where ISO 965-1 has none for the pitch, e.g.
  4H for M1x0.2). A lower-case letter is an external (bolt) position, an upper-case
  one internal (nut); in a pair written all in capitals the first class is the bolt's.

Material conditions (:data:`MATERIAL_CONDITIONS`): ``max`` (maximum material: largest bolt,
smallest nut), ``min`` (minimum material: smallest bolt, largest nut) and ``mean`` (the
midpoint of every limit, the default). The standards' limits and the documented choices for
the limits they leave open are in :mod:`._unified` and :mod:`._iso`.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from .._angles import SQRT3
from .._errors import DesignationError, InputError, SpecError
from . import _iso, _unified
from ._ends import BoltPoint, Countersink
from ._nuts import standard_countersink_diameter, standard_nut_height
from ._spec import BoltSpec, NutSpec, ThreadSpec, parse_length

__all__ = [
    "Designation",
    "BodyLimits",
    "ThreadLimits",
    "MATERIAL_CONDITIONS",
    "parse_designation",
    "thread_limits",
    "spec_from_designation",
    "material_condition",
]

#: Material conditions a designation expands at (aliases: maximum/mmc, minimum/lmc).
MATERIAL_CONDITIONS = ("max", "mean", "min")
_CONDITION_ALIASES = {
    "max": "max",
    "maximum": "max",
    "mmc": "max",
    "min": "min",
    "minimum": "min",
    "lmc": "min",
    "mean": "mean",
    "mid": "mean",
    "middle": "mean",
}

_EXAMPLES = "e.g. '1/4-20 UNC-2A/2B', '#10-24 UNC', 'M6x1-6g/6H' or 'M8'"


@dataclass(frozen=True)
class Designation:
    """A parsed thread designation.

    Attributes
    ----------
    text : str
        Canonical form, e.g. ``1/4-20 UNC-2A/2B`` or ``M6x1-6g/6H``.
    system : {"unified", "iso"}
    units : {"in", "mm"}
    size : str
        Size label: ``#10``, ``1/4``, ``1 1/4``, ``M6``.
    major : float
        Basic major diameter, in ``units``.
    pitch : float
        Pitch, in ``units``.
    series : str
        ``UNC``, ``UNRC``, ... ``UNS`` or ``M``.
    bolt_class, nut_class : str
        Tolerance classes: ``2A``/``2B`` or ``6g``/``6H`` (``5g6g`` style for ISO).
    hand : {"right", "left"}
    tpi : float or None
        Threads per inch (Unified only).
    """

    text: str
    system: str
    units: str
    size: str
    major: float
    pitch: float
    series: str
    bolt_class: str
    nut_class: str
    hand: str = "right"
    tpi: float | None = None

    def __str__(self) -> str:
        return self.text


@dataclass(frozen=True)
class BodyLimits:
    """Limits of size of one body; every field but the class is a ``(min, max)`` pair."""

    major: tuple[float, float]
    pitch_diameter: tuple[float, float]
    minor: tuple[float, float]
    crest_fillet: tuple[float, float] = (0.0, 0.0)
    root_fillet: tuple[float, float] = (0.0, 0.0)
    tolerance_class: str = ""

    def to_dict(self) -> dict[str, Any]:
        """Plain mapping: ``{"major": [min, max], ...}``."""
        out: dict[str, Any] = {
            k: list(getattr(self, k))
            for k in ("major", "pitch_diameter", "minor", "crest_fillet", "root_fillet")
        }
        if self.tolerance_class:
            out["tolerance_class"] = self.tolerance_class
        return out


@dataclass(frozen=True)
class ThreadLimits:
    """Limits of size of a bolt/nut pair (lengths in ``units``)."""

    units: str
    pitch: float
    designation: str
    bolt: BodyLimits
    nut: BodyLimits
    hand: str = "right"
    starts: int = field(default=1)

    def to_dict(self) -> dict[str, Any]:
        """Plain mapping in the layout of ``threadmate thread --json``."""
        return {
            "units": self.units,
            "pitch": self.pitch,
            "designation": self.designation,
            "hand": self.hand,
            "bolt": self.bolt.to_dict(),
            "nut": self.nut.to_dict(),
        }


# -- parsing -----------------------------------------------------------------------------


def parse_designation(text: str | Designation) -> Designation:
    """Parse a Unified or ISO metric thread designation.

    Raises
    ------
    DesignationError
        Naming what is wrong: an unknown size or series, a pitch that is not in the
        series, an unknown tolerance class, or text that is no designation at all.
    """
    if isinstance(text, Designation):
        return text
    if not isinstance(text, str):
        raise DesignationError(f"a thread designation must be text, got {text!r}")
    raw = " ".join(text.split())
    if not raw:
        raise DesignationError(f"empty thread designation; give one, {_EXAMPLES}")
    if re.match(r"^[Mm]\s*\d", raw):
        return _parse_iso(raw)
    return _parse_unified(raw)


_UNIFIED_RE = re.compile(
    r"^(?P<size>#\s*\d+|\d+\s*[ -]\s*\d+/\d+|\d+/\d+|\d*\.\d+|\d+)\s*-\s*"
    r"(?P<tpi>\d+(?:\.\d+)?)\s*(?P<series>[A-Z]+)?\s*(?P<rest>.*)$"
)
_UNIFIED_REST_RE = re.compile(
    r"^(?:-?\s*(?P<c1>\d[A-Z])(?:\s*/\s*(?P<c2>\d[A-Z]))?)?\s*(?:-?\s*(?P<hand>LH|RH))?$"
)
_UNIFIED_CLASSES = ("1A", "2A", "3A", "1B", "2B", "3B")


def _fraction_label(value: Fraction) -> str:
    whole, rem = divmod(value, 1)
    if rem == 0:
        return str(int(whole))
    frac = f"{rem.numerator}/{rem.denominator}"
    return f"{int(whole)} {frac}" if whole else frac


def _parse_unified(raw: str) -> Designation:
    up = raw.upper()
    m = _UNIFIED_RE.match(up)
    if not m:
        raise DesignationError(f"cannot read thread designation '{raw}'; expected {_EXAMPLES}")
    series = m["series"]
    if not series:
        raise DesignationError(
            f"thread designation '{raw}' names no series; add UNC, UNF, UNEF, UN or UNS"
        )
    if series not in _unified.UNIFIED_SERIES:
        raise DesignationError(
            f"unknown thread series '{series}' in '{raw}': Unified series are UNC, UNF, "
            f"UNEF, UN and UNS (UNRC, UNRF, UNREF, UNR, UNRS for the rounded root)"
        )
    base = _unified.UNIFIED_SERIES[series]
    tpi = float(m["tpi"])
    if tpi <= 0:
        raise DesignationError(f"threads per inch must be positive in '{raw}'")
    label, major = _unified_size(m["size"], tpi, base, raw)
    table = _unified.series_table(base)
    if table is not None:
        if label not in table:
            raise DesignationError(
                f"unknown size '{label}' for the {base} series in '{raw}' "
                f"({base} sizes: {', '.join(table)})"
            )
        if table[label] != tpi:
            raise DesignationError(
                f"{tpi:g} threads per inch is not in the {base} series for size {label} "
                f"in '{raw}' ({base} pitch: {label}-{table[label]:g})"
            )
    elif base == "UN" and tpi not in _unified.UN_CONSTANT_PITCHES:
        raise DesignationError(
            f"{tpi:g} threads per inch is not a UN constant-pitch series in '{raw}' "
            f"(UN: {', '.join(map(str, _unified.UN_CONSTANT_PITCHES))} tpi; use UNS for a "
            f"special pitch)"
        )
    pitch = 1.0 / tpi
    if major - 1.082532 * pitch <= 0.2 * major:
        raise DesignationError(
            f"thread pitch 1/{tpi:g} in is too coarse for size {label} in '{raw}'"
        )

    rest = _UNIFIED_REST_RE.match(m["rest"].strip())
    if not rest:
        raise DesignationError(
            f"cannot read the class part '{m['rest'].strip()}' of '{raw}': expected a class "
            f"such as 2A, 2B or 2A/2B, optionally followed by LH"
        )
    bolt_cls, nut_cls = _unified_classes(rest["c1"], rest["c2"], raw)
    if "1" in (bolt_cls[0], nut_cls[0]) and not (
        base in ("UNC", "UNF") or (base == "UN" and tpi == 8)
    ):
        raise DesignationError(
            f"classes 1A and 1B apply only to UNC, UNF and 8-UN threads, not '{raw}'"
        )
    hand = "left" if rest["hand"] == "LH" else "right"
    text = f"{label}-{tpi:g} {series}-{bolt_cls}/{nut_cls}" + (" LH" if hand == "left" else "")
    return Designation(
        text=text,
        system="unified",
        units="in",
        size=label,
        major=major,
        pitch=pitch,
        series=series,
        bolt_class=bolt_cls,
        nut_class=nut_cls,
        hand=hand,
        tpi=tpi,
    )


def _unified_size(token: str, tpi: float, base: str, raw: str) -> tuple[str, float]:
    token = token.replace(" ", "") if token.startswith("#") else token
    table = _unified.series_table(base)
    if token.startswith("#"):
        number = int(token[1:])
        if number > 12:
            raise DesignationError(
                f"unknown numbered size '{token}' in '{raw}': numbered sizes are #0 to #12"
            )
        return f"#{number}", _unified.numbered_size(number)
    if "/" in token:
        whole, _, frac = re.sub(r"\s*[ -]\s*", " ", token).rpartition(" ")
        try:
            fraction = Fraction(frac) + (int(whole) if whole else 0)
        except (ValueError, ZeroDivisionError):
            raise DesignationError(f"unknown size '{token}' in '{raw}'") from None
        return _inch_size(fraction, raw)
    if "." in token:
        value = float(token)
        for label in table or {}:
            if abs(_unified.size_value(label) - value) < 5e-5:
                return label, _unified.size_value(label)
        as_fraction = Fraction(value).limit_denominator(64)
        if abs(float(as_fraction) - value) < 5e-5:
            return _inch_size(as_fraction, raw)
        return _inch_size_checked(f"{value:.4f}", value, raw)
    number = int(token)
    numbered, inch = f"#{number}", str(number)
    if table is not None:
        for label in (numbered, inch):
            if table.get(label) == tpi:
                return label, _unified.size_value(label)
        for label in (numbered, inch):
            if label in table:
                return label, _unified.size_value(label)
        if number <= 12:
            return numbered, _unified.numbered_size(number)
        return _inch_size(Fraction(number), raw)
    if number == 0 or 5 <= number <= 12 or (number <= 4 and tpi > 32):
        return numbered, _unified.numbered_size(number)
    return _inch_size(Fraction(number), raw)


def _inch_size(value: Fraction, raw: str) -> tuple[str, float]:
    return _inch_size_checked(_fraction_label(value), float(value), raw)


def _inch_size_checked(label: str, value: float, raw: str) -> tuple[str, float]:
    if not 0.06 <= value <= 6.0:
        raise DesignationError(f"unknown size '{label}' in '{raw}': ASME B1.1 covers 0.060 to 6 in")
    return label, value


def _unified_classes(c1: str | None, c2: str | None, raw: str) -> tuple[str, str]:
    given = [c for c in (c1, c2) if c]
    for c in given:
        if c not in _UNIFIED_CLASSES:
            raise DesignationError(
                f"unknown thread class '{c}' in '{raw}': Unified classes are 1A, 2A, 3A "
                f"(external) and 1B, 2B, 3B (internal)"
            )
    external = [c for c in given if c.endswith("A")]
    internal = [c for c in given if c.endswith("B")]
    if len(external) > 1 or len(internal) > 1:
        raise DesignationError(
            f"'{raw}' gives two {'external' if len(external) > 1 else 'internal'} classes; "
            f"a pair is one external (A) and one internal (B) class, e.g. 2A/2B"
        )
    bolt = external[0] if external else (internal[0][0] + "A" if internal else "2A")
    nut = internal[0] if internal else bolt[0] + "B"
    return bolt, nut


_ISO_RE = re.compile(
    r"^[Mm]\s*(?P<d>\d+(?:[.,]\d+)?)\s*(?:[xX×*]\s*(?P<p>\d+(?:[.,]\d+)?))?\s*(?P<rest>.*)$"
)
_ISO_CLASS = r"\d[A-Za-z](?:\d[A-Za-z])?"
_ISO_REST_RE = re.compile(
    rf"^(?:-?\s*(?P<c1>{_ISO_CLASS})(?:\s*/\s*(?P<c2>{_ISO_CLASS}))?)?"
    r"\s*(?:-?\s*(?P<hand>[LlRr][Hh]))?$"
)


def _parse_iso(raw: str) -> Designation:
    m = _ISO_RE.match(raw)
    if not m:
        raise DesignationError(f"cannot read thread designation '{raw}'; expected {_EXAMPLES}")
    d = float(m["d"].replace(",", "."))
    size = min(_iso.ISO_261, key=lambda k: abs(k - d))
    if abs(size - d) > 1e-6:
        raise DesignationError(
            f"unknown ISO 261 size 'M{d:g}' in '{raw}' (ISO 261 sizes: M1 to M64, e.g. "
            f"M1.6, M2.5, M6, M8, M10, M12)"
        )
    coarse, fine = _iso.ISO_261[size]
    if m["p"] is None:
        if coarse is None:
            raise DesignationError(
                f"M{size:g} has no coarse pitch in ISO 261; give the pitch, e.g. "
                f"M{size:g}x{fine[0]:g}"
            )
        pitch = coarse
    else:
        pitch = float(m["p"].replace(",", "."))
        allowed = ((coarse,) if coarse else ()) + fine
        if not any(abs(pitch - a) < 1e-9 for a in allowed):
            raise DesignationError(
                f"thread pitch {pitch:g} is not an ISO 261 pitch for M{size:g} in '{raw}' "
                f"(coarse: {coarse if coarse else 'none'}; fine: "
                f"{', '.join(f'{f:g}' for f in fine)})"
            )
    rest = _ISO_REST_RE.match(m["rest"].strip())
    if not rest:
        raise DesignationError(
            f"cannot read the tolerance part '{m['rest'].strip()}' of '{raw}': expected a "
            f"class such as 6g, 6H or 6g/6H (ISO 965-1), optionally followed by LH"
        )
    bolt, nut = _iso_classes(rest["c1"], rest["c2"], size, pitch, raw)
    for cls in (bolt, nut):
        problem = _iso.tolerance_problem(size, pitch, *cls)
        if problem:
            raise DesignationError(f"{problem} (in '{raw}')")
    hand = "left" if (rest["hand"] or "").upper() == "LH" else "right"
    bolt_s, nut_s = _iso_class_text(bolt), _iso_class_text(nut)
    text = f"M{size:g}x{pitch:g}-{bolt_s}/{nut_s}" + ("-LH" if hand == "left" else "")
    return Designation(
        text=text,
        system="iso",
        units="mm",
        size=f"M{size:g}",
        major=float(size),
        pitch=pitch,
        series="M",
        bolt_class=bolt_s,
        nut_class=nut_s,
        hand=hand,
    )


def _iso_class_text(cls: tuple[str, int, int]) -> str:
    position, pd_grade, crest_grade = cls
    if pd_grade == crest_grade:
        return f"{pd_grade}{position}"
    return f"{pd_grade}{position}{crest_grade}{position}"


def _read_iso_class(token: str, raw: str) -> tuple[str, int, int]:
    m = re.fullmatch(r"(\d)([A-Za-z])(?:(\d)([A-Za-z]))?", token)
    assert m is not None
    pd_grade, position = int(m[1]), m[2]
    crest_grade = int(m[3]) if m[3] else pd_grade
    if m[4] and m[4] != position:
        raise DesignationError(
            f"tolerance class '{token}' in '{raw}' mixes positions '{position}' and '{m[4]}'"
        )
    if position not in _iso.EXTERNAL_POSITIONS + _iso.INTERNAL_POSITIONS:
        raise DesignationError(
            f"unknown tolerance position '{position}' in '{raw}': ISO 965-1 positions are "
            f"e, f, g, h (external) and G, H (internal)"
        )
    return position, pd_grade, crest_grade


def _default_class(position: str, grade: int, size: float, pitch: float) -> tuple[str, int, int]:
    # ISO 965-1 tabulates no coarse grades for the finest pitches (e.g. only 4H for
    # P = 0.2): take the nearest finer grade it does give.
    for g in range(grade, 3, -1):
        if _iso.tolerance_problem(size, pitch, position, g, g) is None:
            return (position, g, g)
    return (position, grade, grade)


def _iso_classes(
    c1: str | None, c2: str | None, size: float, pitch: float, raw: str
) -> tuple[tuple[str, int, int], tuple[str, int, int]]:
    small = size <= 1.4
    default_bolt = _default_class("h" if small else "g", 6, size, pitch)
    default_nut = _default_class("H", 5 if small else 6, size, pitch)
    if c1 and c2 and not any(ch.islower() for ch in c1 + c2):
        c1 = c1.lower()  # an all-capitals pair: the first class is the bolt's
    given = [_read_iso_class(c, raw) for c in (c1, c2) if c]
    external = [c for c in given if c[0] in _iso.EXTERNAL_POSITIONS]
    internal = [c for c in given if c[0] in _iso.INTERNAL_POSITIONS]
    if len(external) > 1 or len(internal) > 1:
        raise DesignationError(
            f"'{raw}' gives two {'external' if len(external) > 1 else 'internal'} tolerance "
            f"classes; a pair is one external (lower case) and one internal (upper case), "
            f"e.g. 6g/6H"
        )
    return (external[0] if external else default_bolt, internal[0] if internal else default_nut)


# -- limits and specs ----------------------------------------------------------------------


def thread_limits(designation: str | Designation) -> ThreadLimits:
    """Limits of size of the bolt and nut of a designation (see module docstring)."""
    des = parse_designation(designation)
    if des.system == "unified":
        raw = _unified.unified_limits(
            des.major, des.tpi or 1.0 / des.pitch, des.series, des.bolt_class, des.nut_class
        )
    else:
        try:
            raw = _iso.iso_limits(
                des.major,
                des.pitch,
                _read_iso_class(des.bolt_class, des.text),
                _read_iso_class(des.nut_class, des.text),
            )
        except ValueError as exc:
            raise DesignationError(f"{exc} (in '{des.text}')") from None
    return ThreadLimits(
        units=des.units,
        pitch=des.pitch,
        designation=des.text,
        bolt=BodyLimits(**raw["bolt"], tolerance_class=des.bolt_class),
        nut=BodyLimits(**raw["nut"], tolerance_class=des.nut_class),
        hand=des.hand,
    )


def material_condition(condition: str) -> str:
    """Normalise a material condition to ``max``, ``mean`` or ``min``."""
    key = str(condition).strip().lower()
    if key not in _CONDITION_ALIASES:
        raise InputError(
            f"unknown material condition '{condition}': use max (maximum material), "
            f"mean or min (minimum material)"
        )
    return _CONDITION_ALIASES[key]


def _pick(limits: tuple[float, float], condition: str, largest: bool) -> float:
    lo, hi = limits
    if condition == "mean":
        return (lo + hi) / 2.0
    return hi if (condition == "max") == largest else lo


def spec_from_designation(
    designation: str | Designation,
    condition: str = "mean",
    *,
    point: str | BoltPoint = "chamfer",
    countersink: bool | Countersink | None = True,
    bolt_length: float | str | None = None,
    nut_height: float | str | None = None,
) -> ThreadSpec:
    """Expand a designation into a :class:`ThreadSpec` at a material condition.

    Parameters
    ----------
    designation : str or Designation
        E.g. ``"1/4-20 UNC-2A/2B"`` or ``"M6x1-6g/6H"``.
    condition : {"mean", "max", "min"}
        ``max``/``maximum``: maximum material (every bolt diameter at its largest, every
        nut diameter at its smallest); ``min``/``minimum``: minimum material; ``mean``:
        the midpoint of every limit.
    point : {"chamfer", "flat", "round"} or BoltPoint
        The bolt's point: a form with its defaults, or a :class:`BoltPoint` whose unset
        values take them. ``"flat"`` is the thesis's bolt.
    countersink : bool, None or Countersink
        ``True``: the standard nut's countersink; ``False`` or ``None``: a flat,
        sharp-edged bore (the thesis's nut); a :class:`Countersink` (its diameter, if
        unset, the standard's).
    bolt_length, nut_height : float, str or None
        A length in the designation's units, or text in pitches such as ``"3p"``; for
        ``nut_height`` also ``"standard"``, the standard hex nut's height. None: the
        spec's defaults (the point's height and one pitch; the countersink's depth and
        one pitch).

    Raises
    ------
    DesignationError
        For a designation that names no standard thread.
    SpecError
        For parts that do not fit the thread (naming the spec key), or
        ``nut_height="standard"`` for a size the nut tables do not hold.

    Notes
    -----
    The bolt's root fillet is the standard's root radius at the condition (ASME B1.1
    UNR: 0.144P at max, 0.108P at min, 0.126P at mean; ISO: 0.125P), reduced where the
    rounded limits leave a full-round root smaller than that (the arc must fit its
    corner). Crests and the nut's root are flat.

    The defaults of the ends come from the fastener standards (``conventions.md``,
    "Ends"):

    - point: a 45-degree chamfer (from the axis) down to a tip diameter 0.1 pitch below
      the bolt's minor diameter (ASME B18.2.1 hex bolts and cap screws; ISO 4753 end
      "CH"); a round point's radius is 1.4 times the major diameter (ISO 4753 "RN");
    - countersink: 120 degrees included (ASME B18.2.2, ISO 4032: 90 to 120), the
      diameter at the face the mean of the standard's limits (ASME B18.2.2: the basic
      major diameter to that plus 0.030 in up to 3/8 in, to 1.08 times it above; ISO
      4032: ``d`` to ``d_a max``, and 1.08 ``d`` for a size outside its table), or their
      maximum where the mean does not clear the nut's major diameter at the condition
      (where that does not either, M1 and M1.1 at minimum material: the nut's major
      diameter plus half the band);
    - ``nut_height="standard"``: ASME B18.2.2 hex nuts (1/4 to 1 1/2 in), ASME B18.6.3
      hex machine screw nuts (#0 to #12), ISO 4032 style-1 hex nuts (M1.6 to M64).

    The tables are in :mod:`threadmate.geometry._nuts`. With ``point="flat",
    countersink=False`` and the default lengths the spec is the thesis's: one pitch of
    bolt and of nut.
    """
    des = parse_designation(designation)
    cond = material_condition(condition)
    lim = thread_limits(des)
    b, n = lim.bolt, lim.nut
    bolt_vals = {
        k: _pick(getattr(b, k), cond, largest=True) for k in ("major", "pitch_diameter", "minor")
    }
    nut_vals = {
        k: _pick(getattr(n, k), cond, largest=False) for k in ("major", "pitch_diameter", "minor")
    }
    # The radius of an arc tangent to both flanks at the minor diameter: a larger root
    # fillet would not fit its corner.
    h = SQRT3 / 2.0 * des.pitch
    full_round = (bolt_vals["minor"] - bolt_vals["pitch_diameter"] + h) / 2.0
    root = min(_pick(b.root_fillet, cond, largest=True), full_round * (1.0 - 1e-9))
    return ThreadSpec(
        units=des.units,
        pitch=des.pitch,
        bolt=BoltSpec(
            **bolt_vals,
            crest_fillet=_pick(b.crest_fillet, cond, True),
            root_fillet=max(root, 0.0),
            length=_part_length(bolt_length, des, "bolt_length"),
            point=_point(point),
        ),
        nut=NutSpec(
            **nut_vals,
            crest_fillet=_pick(n.crest_fillet, cond, True),
            root_fillet=_pick(n.root_fillet, cond, True),
            height=_part_length(nut_height, des, "nut_height"),
            countersink=_countersink(countersink, des, nut_vals["major"]),
        ),
        hand=des.hand,
        designation=des.text,
    )


def _point(point: str | BoltPoint) -> BoltPoint:
    """``point`` as a :class:`BoltPoint` (its form and values are checked by the spec)."""
    if isinstance(point, BoltPoint):
        return point
    if isinstance(point, str):
        return BoltPoint(point.strip().lower())
    raise SpecError(f"point must be 'flat', 'chamfer', 'round' or a BoltPoint; got {point!r}")


def _countersink(
    countersink: bool | Countersink | None, des: Designation, nut_major: float
) -> Countersink | None:
    """The nut's countersink: the standard one, none, or the one given (its diameter, if
    unset, the standard's)."""
    if countersink is None or countersink is False:
        return None
    if countersink is True:
        countersink = Countersink()
    if not isinstance(countersink, Countersink):
        raise SpecError(
            f"countersink must be True, False, None or a Countersink; got {countersink!r}"
        )
    if countersink.diameter is not None:
        return countersink
    return Countersink(countersink.angle, standard_countersink_diameter(des, nut_major))


def _part_length(value: float | str | None, des: Designation, name: str) -> float | None:
    """A bolt length or nut height given in units, in pitches or (nut) as "standard"."""
    if value is None:
        return None
    if name == "nut_height" and isinstance(value, str) and value.strip().lower() == "standard":
        try:
            return standard_nut_height(des)
        except SpecError as exc:
            raise SpecError(f"nut_height='standard': {exc}") from None
    return parse_length(value, des.pitch, name, des.units)
