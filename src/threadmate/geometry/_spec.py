"""Thread specs: the bolt/nut pair as conventions.md defines it, with JSON and TOML I/O.

A spec holds one size of each diameter per body (the designation expansion picks them
at a material condition). Every length is in ``spec.units``.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

import tomli_w

from .._angles import SQRT3
from .._errors import SpecError
from .._io import atomic_write_text, read_utf8
from .._json import json_text, parse_json
from .._units import MM_PER_UNIT
from .._validate import check_length, check_number, check_range
from ._ends import (
    BoltPoint,
    Countersink,
    check_countersink,
    countersink_envelope,
    fill_point,
    point_envelope,
)

__all__ = [
    "BoltSpec",
    "NutSpec",
    "ThreadSpec",
    "load_spec",
    "save_spec",
    "parse_length",
    "UNITS",
]


def filled(value: float | None) -> float:
    """A length that :class:`ThreadSpec` fills in (``bolt.length``, ``nut.height``,
    ``nut.outer_radius``), as a float: on a constructed spec it is never None."""
    assert value is not None, "a constructed ThreadSpec fills in every length"
    return float(value)


#: Length units a spec may declare.
UNITS = tuple(MM_PER_UNIT)

# Bounds on a spec beyond the range of each length (MIN_LENGTH..MAX_LENGTH of the spec's
# units, see threadmate._validate), each with room to spare around every real thread:
#: Most starts of a multi-start thread; lead screws and closures use up to about 8.
MAX_STARTS = 16
#: Longest bolt length or nut height, in pitches. A standard bolt's thread is some 30
#: pitches long (2d + 1/2 in) and a tapped hole deeper than 3d holds nothing more; the
#: analyses concern the start of engagement (one pitch by default, as in the thesis), and
#: 200 pitches already make meshes of over a million triangles.
MAX_PITCHES = 200


@dataclass(frozen=True)
class BoltSpec:
    """External thread (bolt) of a spec; lengths in the spec's units."""

    major: float
    pitch_diameter: float
    minor: float
    crest_fillet: float = 0.0
    root_fillet: float = 0.0
    length: float | None = None  # None: the point's height and one pitch (thesis: one pitch)
    point: BoltPoint = field(default_factory=BoltPoint)


@dataclass(frozen=True)
class NutSpec:
    """Internal thread (nut) of a spec; lengths in the spec's units."""

    major: float
    pitch_diameter: float
    minor: float
    crest_fillet: float = 0.0
    root_fillet: float = 0.0
    height: float | None = None  # None: the countersink's depth and one pitch
    outer_radius: float | None = None  # None: 1.6 x major / 2
    countersink: Countersink | None = None  # None: a flat, sharp-edged bore (the thesis's)


@dataclass(frozen=True)
class ThreadSpec:
    """A bolt/nut thread pair (conventions.md, "Thread spec file").

    Construct directly, from a mapping (:meth:`from_dict`), from a file
    (:func:`load_spec`) or from a designation
    (:func:`threadmate.geometry.spec_from_designation`). The constructor validates and
    fills the defaults (the point's defaults; bolt length one pitch above the point and
    nut height one pitch below the countersink, so one pitch each for the thesis's flat
    ends; nut outer radius 1.6 x major / 2), so every attribute of a constructed spec is
    a number.
    """

    units: str
    pitch: float
    bolt: BoltSpec
    nut: NutSpec
    hand: str = "right"
    starts: int = 1
    designation: str | None = field(default=None, compare=False)

    def __post_init__(self) -> None:
        _validate(self)
        bolt = self.bolt
        nut = self.nut
        bolt = replace(bolt, point=fill_point(bolt.point, self.pitch, bolt.major, bolt.minor))
        if nut.outer_radius is None:
            nut = replace(nut, outer_radius=1.6 * nut.major / 2.0)
        if nut.countersink is not None:
            nut = replace(
                nut,
                countersink=check_countersink(nut.countersink, nut.major, filled(nut.outer_radius)),
            )
        object.__setattr__(self, "bolt", bolt)
        object.__setattr__(self, "nut", nut)
        if bolt.length is None:
            bolt = replace(bolt, length=self.point_height + self.pitch)
        if nut.height is None:
            nut = replace(nut, height=self.countersink_depth + self.pitch)
        object.__setattr__(self, "bolt", bolt)
        object.__setattr__(self, "nut", nut)
        _validate_extents(self)

    # -- derived quantities -------------------------------------------------------------
    @property
    def lead(self) -> float:
        """Axial advance per turn: ``pitch * starts``."""
        return self.pitch * self.starts

    @property
    def handedness(self) -> int:
        """+1 for a right-hand thread, -1 for a left-hand one."""
        return 1 if self.hand == "right" else -1

    @property
    def point_height(self) -> float:
        """Axial height of the bolt's point (chamfer or round) above its tip face; 0 flat."""
        env = point_envelope(self.bolt.point, self.bolt.major / 2.0, self.bolt.minor / 2.0)
        return env.depth if env is not None else 0.0

    @property
    def countersink_depth(self) -> float:
        """Axial depth of the nut's countersink below its entry face; 0 without one."""
        if self.nut.countersink is None:
            return 0.0
        return countersink_envelope(self.nut.countersink, self.nut.minor / 2.0).depth

    @property
    def axial_clearance(self) -> float:
        """Flank-to-flank axial play of the pair: (nut PD - bolt PD) / sqrt(3)."""
        return (self.nut.pitch_diameter - self.bolt.pitch_diameter) / SQRT3

    # -- mapping form ------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        """The spec as a plain mapping in the spec-file layout of conventions.md."""
        out: dict[str, Any] = {
            "units": self.units,
            "pitch": self.pitch,
            "hand": self.hand,
            "starts": self.starts,
            "bolt": _table(self.bolt),
            "nut": _table(self.nut),
        }
        if self.designation:
            out["designation"] = self.designation
        return out

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> ThreadSpec:
        """Build a spec from a mapping in the spec-file layout; unknown keys are refused."""
        if not isinstance(data, dict):
            raise SpecError("a thread spec must be a mapping of keys to values")
        allowed = {"units", "pitch", "hand", "starts", "bolt", "nut", "designation"}
        _no_unknown(data, allowed, "")
        for key in ("units", "pitch", "bolt", "nut"):
            if key not in data:
                raise SpecError(f"spec key '{key}' is missing")
        bolt = _body(data["bolt"], "bolt", BoltSpec)
        nut = _body(data["nut"], "nut", NutSpec)
        pitch = _number(data["pitch"], "pitch")
        units = data["units"]
        if isinstance(bolt.length, str):
            bolt = replace(
                bolt, length=parse_length(bolt.length, pitch, "spec key 'bolt.length'", units)
            )
        if isinstance(nut.height, str):
            nut = replace(
                nut, height=parse_length(nut.height, pitch, "spec key 'nut.height'", units)
            )
        starts = data.get("starts", 1)
        if check_range("spec key 'starts'", starts, 1, MAX_STARTS, error=SpecError) != int(starts):
            raise SpecError(f"spec key 'starts' must be a whole number, got {starts!r}")
        return cls(
            units=data["units"],
            pitch=pitch,
            bolt=bolt,
            nut=nut,
            hand=data.get("hand", "right"),
            starts=int(starts),
            designation=data.get("designation"),
        )

    def to_json(self) -> str:
        """The spec as a JSON document."""
        return json_text(self.to_dict())

    def to_toml(self) -> str:
        """The spec as a TOML document."""
        return tomli_w.dumps(self.to_dict())


def _table(body: BoltSpec | NutSpec) -> dict[str, Any]:
    """A body's spec table: its numbers, then its point or countersink (omitted when flat
    or absent, so that the thesis's specs read as they always have)."""
    out = {k: v for k, v in asdict(body).items() if k not in ("point", "countersink")}
    if isinstance(body, BoltSpec) and body.point.form != "flat":
        out["point"] = body.point.to_dict()
    if isinstance(body, NutSpec) and body.countersink is not None:
        out["countersink"] = body.countersink.to_dict()
    return out


def parse_length(value: Any, pitch: float, name: str, units: str) -> float:
    """A length given in the spec's units (a number) or in pitches (text such as ``"3p"``
    or ``"3 pitches"``), in the spec's units.

    Raises
    ------
    SpecError
        Naming ``name`` when ``value`` is neither.
    """
    if isinstance(value, str):
        text = value.strip().lower()
        for suffix in ("pitches", "pitch", "p"):
            if text.endswith(suffix):
                head = text[: -len(suffix)].strip()
                try:
                    count = float(head)
                except ValueError:
                    break
                if not math.isfinite(count) or count <= 0:
                    break
                return count * pitch
        raise SpecError(
            f"{name} must be a length in {units} or a number of pitches such as '3p'; got {value!r}"
        )
    return check_number(name, value, error=SpecError)


# -- validation --------------------------------------------------------------------------


def _number(value: Any, key: str) -> float:
    return check_number(f"spec key '{key}'", value, error=SpecError)


def _no_unknown(data: dict[str, Any], allowed: set[str], prefix: str) -> None:
    unknown = sorted(set(data) - allowed)
    if unknown:
        raise SpecError(f"unknown spec key '{prefix}{unknown[0]}'")


def _body(data: Any, name: str, cls: type[BoltSpec] | type[NutSpec]) -> Any:
    if not isinstance(data, dict):
        raise SpecError(f"spec key '{name}' must be a table of diameters")
    fields = set(cls.__dataclass_fields__)
    _no_unknown(data, fields, f"{name}.")
    values: dict[str, Any] = {}
    for key in fields:
        if key in ("point", "countersink"):
            if data.get(key) is not None:
                values[key] = _end(data[key], f"{name}.{key}")
        elif key in data and data[key] is not None:
            if key in ("length", "height") and isinstance(data[key], str):
                values[key] = data[key]  # pitches: resolved once the pitch is known
            else:
                values[key] = _number(data[key], f"{name}.{key}")
        elif key in ("major", "pitch_diameter", "minor"):
            raise SpecError(f"spec key '{name}.{key}' is missing")
    return cls(**values)


def _end(data: Any, name: str) -> BoltPoint | Countersink:
    """A ``bolt.point`` or ``nut.countersink`` table (angles in degrees)."""
    cls: type[BoltPoint] | type[Countersink] = BoltPoint if name.endswith("point") else Countersink
    if cls is BoltPoint and isinstance(data, str):
        data = {"form": data}  # point = "chamfer": the form with its defaults
    if not isinstance(data, dict):
        raise SpecError(f"spec key '{name}' must be a table")
    _no_unknown(data, set(cls.__dataclass_fields__), f"{name}.")
    values: dict[str, Any] = {}
    for key, value in data.items():
        if key == "form":
            if not isinstance(value, str):
                raise SpecError(f"spec key '{name}.form' must be text; got {value!r}")
            values[key] = value
        elif value is not None:
            values[key] = _number(value, f"{name}.{key}")
    return cls(**values)


def _length(spec: ThreadSpec, key: str, value: Any, zero_ok: bool = False) -> float:
    return check_length(f"spec key '{key}'", value, spec.units, zero_ok=zero_ok, error=SpecError)


def _validate(spec: ThreadSpec) -> None:
    if spec.units not in UNITS:
        raise SpecError(f"spec key 'units' must be one of {', '.join(UNITS)}; got {spec.units!r}")
    if spec.designation is not None and not isinstance(spec.designation, str):
        raise SpecError(f"spec key 'designation' must be text; got {spec.designation!r}")
    if spec.hand not in ("right", "left"):
        raise SpecError(f"spec key 'hand' must be 'right' or 'left'; got {spec.hand!r}")
    if (
        isinstance(spec.starts, bool)
        or not isinstance(spec.starts, int)
        or not 1 <= spec.starts <= MAX_STARTS
    ):
        raise SpecError(
            f"spec key 'starts' must be a whole number from 1 to {MAX_STARTS}; got {spec.starts!r}"
        )
    # Every length within [MIN_LENGTH, MAX_LENGTH] of the spec's units (see _validate for
    # why that covers every real thread); a fillet may also be 0 (a sharp corner).
    _length(spec, "pitch", spec.pitch)
    for name, body in (("bolt", spec.bolt), ("nut", spec.nut)):
        for key, value in asdict(body).items():
            if value is not None and key not in ("point", "countersink"):
                _length(spec, f"{name}.{key}", value, zero_ok=key.endswith("fillet"))
        for key in ("diameter", "radius"):
            value = getattr(spec.bolt.point, key) if name == "bolt" else None
            if value is not None:
                _length(spec, f"bolt.point.{key}", value)
        sink = spec.nut.countersink if name == "nut" else None
        if sink is not None and sink.diameter is not None:
            _length(spec, "nut.countersink.diameter", sink.diameter)
        if not body.minor < body.pitch_diameter:
            raise SpecError(
                f"spec key '{name}.minor' ({body.minor:g}) must be less than "
                f"'{name}.pitch_diameter' ({body.pitch_diameter:g})"
            )
        if not body.pitch_diameter < body.major:
            raise SpecError(
                f"spec key '{name}.pitch_diameter' ({body.pitch_diameter:g}) must be less "
                f"than '{name}.major' ({body.major:g})"
            )
    p = spec.pitch
    # The coarsest standard threads have a pitch of a quarter of their diameter (M1 x 0.25);
    # a pitch beyond the diameter is no screw thread (and a unit or digit slip).
    if p > spec.nut.major:
        raise SpecError(
            f"spec key 'pitch' ({p:g} {spec.units}) exceeds 'nut.major' "
            f"({spec.nut.major:g} {spec.units}): a thread's pitch is a fraction of its "
            f"diameter"
        )
    # The 60-degree flanks span sqrt(3)/2 * p radially per side; a pitch diameter band
    # wider than the profile allows means the diameters were given for another pitch.
    for name, body in (("bolt", spec.bolt), ("nut", spec.nut)):
        if body.major - body.minor > 2.0 * SQRT3 * p / 2.0 * 1.0001 + 1e-12:
            raise SpecError(
                f"spec key '{name}.minor' ({body.minor:g}): the thread depth "
                f"{(body.major - body.minor) / 2:g} exceeds the sharp 60-degree profile "
                f"depth {SQRT3 * p / 2:g} for pitch {p:g}; are bolt and nut of the same "
                f"pitch?"
            )
    if spec.bolt.pitch_diameter > spec.nut.pitch_diameter:
        raise SpecError(
            f"spec key 'bolt.pitch_diameter' ({spec.bolt.pitch_diameter:g}) exceeds "
            f"'nut.pitch_diameter' ({spec.nut.pitch_diameter:g}): the bolt cannot enter "
            f"the nut at any phase"
        )
    if spec.bolt.major > spec.nut.major:
        raise SpecError(
            f"spec key 'bolt.major' ({spec.bolt.major:g}) exceeds 'nut.major' "
            f"({spec.nut.major:g}): the bolt cannot enter the nut at any phase"
        )
    if spec.bolt.minor > spec.nut.minor:
        raise SpecError(
            f"spec key 'bolt.minor' ({spec.bolt.minor:g}) exceeds 'nut.minor' "
            f"({spec.nut.minor:g}): the bolt cannot enter the nut at any phase"
        )
    if spec.nut.minor >= spec.bolt.major:
        u = spec.units
        raise SpecError(
            f"spec key 'nut.minor' ({spec.nut.minor:g} {u}) is not below 'bolt.major' "
            f"({spec.bolt.major:g} {u}): the threads do not overlap, so the nut holds "
            "nothing (the bolt passes through it)"
        )


def _validate_extents(spec: ThreadSpec) -> None:
    # With the defaults filled in, every extent is a number: check the ones derived from
    # the pitch or the major diameter too (a default from an in-range pitch is in range).
    _length(spec, "bolt.length", spec.bolt.length)
    _length(spec, "nut.height", spec.nut.height)
    _length(spec, "nut.outer_radius", spec.nut.outer_radius)
    for key, value in (("bolt.length", spec.bolt.length), ("nut.height", spec.nut.height)):
        assert value is not None
        if value > MAX_PITCHES * spec.pitch:
            raise SpecError(
                f"spec key '{key}' ({value:g} {spec.units}) is out of range: give at most "
                f"{MAX_PITCHES} pitches ({MAX_PITCHES * spec.pitch:g} {spec.units})"
            )
    if spec.nut.outer_radius is not None and spec.nut.outer_radius <= spec.nut.major / 2.0:
        raise SpecError(
            f"spec key 'nut.outer_radius' ({spec.nut.outer_radius:g}) must exceed half the "
            f"nut major diameter ({spec.nut.major / 2:g})"
        )
    for key, value, end, what in (
        ("bolt.length", spec.bolt.length, spec.point_height, "the point's height"),
        ("nut.height", spec.nut.height, spec.countersink_depth, "the countersink's depth"),
    ):
        assert value is not None
        if end > 0 and value <= end + 1e-9 * spec.pitch:
            raise SpecError(
                f"spec key '{key}' ({value:g} {spec.units}) must exceed {what} "
                f"({end:g} {spec.units})"
            )
    # Fillets must fit their corners; the profile module knows the corner geometry.
    from ._profile import check_fillets

    check_fillets(spec)


# -- files -------------------------------------------------------------------------------


def load_spec(path: str | Path) -> ThreadSpec:
    """Load a spec from a ``.json`` or ``.toml`` file.

    Raises
    ------
    SpecError
        If the file is missing, unreadable, not JSON/TOML, or not a valid spec.
    """
    path = Path(path)
    if path.is_dir():
        raise SpecError(f"{path} is a directory, not a spec file")
    if not path.exists():
        raise SpecError(f"spec file not found: {path}")
    if not path.is_file():
        raise SpecError(f"{path} is not a regular file, so not a spec file")
    try:
        text = read_utf8(path, SpecError)  # a byte-order mark is fine, Latin-1 is not
    except OSError as exc:
        raise SpecError(f"cannot read spec file {path}: {exc.strerror or exc}") from None
    suffix = path.suffix.lower()
    try:
        if suffix == ".toml":
            data = tomllib.loads(text)
        elif suffix == ".json":
            data = parse_json(text)  # a key given twice is refused (TOML refuses it itself)
        else:
            raise SpecError(f"spec file {path} must end in .json or .toml")
    except (ValueError, RecursionError) as exc:
        # ValueError: the decode errors, and a number of over 4300 digits; RecursionError:
        # thousands of nested brackets.
        why = str(exc) if isinstance(exc, ValueError) else "nested too deeply"
        raise SpecError(f"spec file {path} is not valid {suffix[1:].upper()}: {why}") from None
    try:
        return ThreadSpec.from_dict(data)
    except SpecError as exc:
        raise SpecError(f"{path}: {exc}") from None


def save_spec(spec: ThreadSpec, path: str | Path) -> Path:
    """Write ``spec`` to ``path`` (JSON or TOML by suffix) atomically."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".toml":
        text = spec.to_toml()
    elif suffix == ".json":
        text = spec.to_json()
    else:
        raise SpecError(f"spec file {path} must end in .json or .toml")
    return atomic_write_text(path, text)
