"""Thread specs: the bolt/nut pair as conventions.md defines it, with JSON and TOML I/O.

A spec holds one size of each diameter per body (the designation expansion picks them
at a material condition). Every length is in ``spec.units``.
"""

from __future__ import annotations

import json
import math
import tomllib
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

import tomli_w

from .._errors import SpecError
from .._io import atomic_write_text

__all__ = ["BoltSpec", "NutSpec", "ThreadSpec", "load_spec", "save_spec", "UNITS"]

#: Length units a spec may declare.
UNITS = ("in", "mm")

_SQRT3 = math.sqrt(3.0)


@dataclass(frozen=True)
class BoltSpec:
    """External thread (bolt) of a spec; lengths in the spec's units."""

    major: float
    pitch_diameter: float
    minor: float
    crest_fillet: float = 0.0
    root_fillet: float = 0.0
    length: float | None = None  # None: one pitch, as in the thesis


@dataclass(frozen=True)
class NutSpec:
    """Internal thread (nut) of a spec; lengths in the spec's units."""

    major: float
    pitch_diameter: float
    minor: float
    crest_fillet: float = 0.0
    root_fillet: float = 0.0
    height: float | None = None  # None: one pitch, as in the thesis
    outer_radius: float | None = None  # None: 1.6 x major / 2


@dataclass(frozen=True)
class ThreadSpec:
    """A bolt/nut thread pair (conventions.md, "Thread spec file").

    Construct directly, from a mapping (:meth:`from_dict`), from a file
    (:func:`load_spec`) or from a designation
    (:func:`threadmate.geometry.spec_from_designation`). The constructor validates and
    fills the defaults (bolt length and nut height one pitch, nut outer radius
    1.6 x major / 2), so every attribute of a constructed spec is a number.
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
        if bolt.length is None:
            bolt = replace(bolt, length=self.pitch)
        if nut.height is None:
            nut = replace(nut, height=self.pitch)
        if nut.outer_radius is None:
            nut = replace(nut, outer_radius=1.6 * nut.major / 2.0)
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
    def axial_clearance(self) -> float:
        """Flank-to-flank axial play of the pair: (nut PD - bolt PD) / sqrt(3)."""
        return (self.nut.pitch_diameter - self.bolt.pitch_diameter) / _SQRT3

    # -- mapping form ------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        """The spec as a plain mapping in the spec-file layout of conventions.md."""
        out: dict[str, Any] = {
            "units": self.units,
            "pitch": self.pitch,
            "hand": self.hand,
            "starts": self.starts,
            "bolt": asdict(self.bolt),
            "nut": asdict(self.nut),
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
        starts = data.get("starts", 1)
        if isinstance(starts, bool) or not isinstance(starts, int | float) or starts != int(starts):
            raise SpecError(f"spec key 'starts' must be a whole number, got {starts!r}")
        return cls(
            units=data["units"],
            pitch=_number(data["pitch"], "pitch"),
            bolt=bolt,
            nut=nut,
            hand=data.get("hand", "right"),
            starts=int(starts),
            designation=data.get("designation"),
        )

    def to_json(self) -> str:
        """The spec as a JSON document."""
        return json.dumps(self.to_dict(), indent=2) + "\n"

    def to_toml(self) -> str:
        """The spec as a TOML document."""
        return tomli_w.dumps(self.to_dict())


# -- validation --------------------------------------------------------------------------

def _number(value: Any, key: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise SpecError(f"spec key '{key}' must be a number, got {value!r}")
    value = float(value)
    if not math.isfinite(value):
        raise SpecError(f"spec key '{key}' must be finite, got {value!r}")
    return value


def _no_unknown(data: dict[str, Any], allowed: set[str], prefix: str) -> None:
    unknown = sorted(set(data) - allowed)
    if unknown:
        raise SpecError(f"unknown spec key '{prefix}{unknown[0]}'")


def _body(data: Any, name: str, cls: type) -> Any:
    if not isinstance(data, dict):
        raise SpecError(f"spec key '{name}' must be a table of diameters")
    fields = set(cls.__dataclass_fields__)
    _no_unknown(data, fields, f"{name}.")
    values: dict[str, float | None] = {}
    for key in fields:
        if key in data and data[key] is not None:
            values[key] = _number(data[key], f"{name}.{key}")
        elif key in ("major", "pitch_diameter", "minor"):
            raise SpecError(f"spec key '{name}.{key}' is missing")
    return cls(**values)


def _validate(spec: ThreadSpec) -> None:
    if spec.units not in UNITS:
        raise SpecError(f"spec key 'units' must be one of {', '.join(UNITS)}; got {spec.units!r}")
    if spec.hand not in ("right", "left"):
        raise SpecError(f"spec key 'hand' must be 'right' or 'left'; got {spec.hand!r}")
    if not isinstance(spec.starts, int) or spec.starts < 1:
        raise SpecError(f"spec key 'starts' must be 1 or more; got {spec.starts!r}")
    if not (isinstance(spec.pitch, int | float) and math.isfinite(spec.pitch) and spec.pitch > 0):
        raise SpecError(f"spec key 'pitch' must be a positive length; got {spec.pitch!r}")
    for name, body in (("bolt", spec.bolt), ("nut", spec.nut)):
        for key, value in asdict(body).items():
            if value is None:
                continue
            if not math.isfinite(value):
                raise SpecError(f"spec key '{name}.{key}' must be finite; got {value!r}")
            if value < 0 or (value == 0 and key in ("major", "pitch_diameter", "minor")):
                raise SpecError(f"spec key '{name}.{key}' must be positive; got {value!r}")
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
    # The 60-degree flanks span sqrt(3)/2 * p radially per side; a pitch diameter band
    # wider than the profile allows means the diameters were given for another pitch.
    for name, body in (("bolt", spec.bolt), ("nut", spec.nut)):
        if body.major - body.minor > 2.0 * _SQRT3 * p / 2.0 * 1.0001 + 1e-12:
            raise SpecError(
                f"spec key '{name}.minor' ({body.minor:g}): the thread depth "
                f"{(body.major - body.minor) / 2:g} exceeds the sharp 60-degree profile "
                f"depth {_SQRT3 * p / 2:g} for pitch {p:g}; are bolt and nut of the same "
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


def _validate_extents(spec: ThreadSpec) -> None:
    if spec.bolt.length is not None and spec.bolt.length <= 0:
        raise SpecError(f"spec key 'bolt.length' must be positive; got {spec.bolt.length!r}")
    if spec.nut.height is not None and spec.nut.height <= 0:
        raise SpecError(f"spec key 'nut.height' must be positive; got {spec.nut.height!r}")
    if spec.nut.outer_radius is not None and spec.nut.outer_radius <= spec.nut.major / 2.0:
        raise SpecError(
            f"spec key 'nut.outer_radius' ({spec.nut.outer_radius:g}) must exceed half the "
            f"nut major diameter ({spec.nut.major / 2:g})"
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
    if not path.is_file():
        raise SpecError(f"spec file not found: {path}")
    text = path.read_text(encoding="utf-8", errors="replace")
    suffix = path.suffix.lower()
    try:
        if suffix == ".toml":
            data = tomllib.loads(text)
        elif suffix == ".json":
            data = json.loads(text)
        else:
            raise SpecError(f"spec file {path} must end in .json or .toml")
    except (json.JSONDecodeError, tomllib.TOMLDecodeError) as exc:
        raise SpecError(f"spec file {path} is not valid {suffix[1:].upper()}: {exc}") from None
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
