"""The configuration grid: held tilts and phases, and the fixed configuration order.

Two kinds of grid, one interface (:data:`AnyGrid`):

- :class:`Grid`, the square grid: roll, pitch and phase values (three sorted tuples of
  degrees). Configurations are numbered roll-major, phase fastest::

      config_id = (i_roll * n_pitch + i_pitch) * n_phase + i_phase

- :class:`PolarGrid`, the polar grid of misalignment: tilt sizes, directions (the azimuth
  in F, from +X toward +Y, toward which the bolt's axis leans:
  :func:`threadmate.geometry.held_tilt_from_polar`) and phases. Its held tilts are the
  upright one (tilt 0, once, whatever the directions) and then every size above 0 in every
  direction, size-major::

      config_id = i_held * n_phase + i_phase

Either way a chunk of consecutive ids is a run of phases of one held tilt, and the number
of a configuration never changes for a given grid. :func:`make_grid` owns the rule that a
request is one kind or the other; :func:`read_grid` reads either from a library's metadata.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any, cast

import numpy as np

from .._angles import phase_difference, wrap_phase
from .._errors import InputError
from .._validate import MAX_AXIS_VALUES, check_number, check_phase
from ..contact import MAX_TILT as _CONTACT_MAX_TILT
from ..geometry._frames import held_tilt_from_polar, polar_from_held_tilt

__all__ = [
    "AnyGrid",
    "Grid",
    "PolarGrid",
    "make_grid",
    "read_grid",
    "parse_range",
    "DEFAULT_GRID",
    "DEFAULT_RANGES",
    "DEFAULT_POLAR_RANGES",
    "DIRECTION_DEFINITION",
    "MAX_TILT",
]

#: Largest roll or pitch a grid may hold (degrees): the contact package's limit.
MAX_TILT = _CONTACT_MAX_TILT
#: Values closer than this (degrees) are one grid value; STOP within it of the last step
#: is included.
ANGLE_TOLERANCE = 1e-9
#: Decimals kept for every grid value, so that 0.1 * 3 is stored as 0.3.
_DECIMALS = 9

Values = str | float | int | Sequence[float] | None
#: The angles a grid may have; the phase and the direction are taken modulo 360.
_AXES = ("roll", "pitch", "phase", "tilt", "direction")
_TURNING = ("phase", "direction")


def _number(text: str, option: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"{option}: {text.strip()!r} is not a number of degrees") from None
    if not math.isfinite(value):
        raise InputError(f"{option}: {text.strip()!r} is not a finite angle")
    return value


def _span(text: str, option: str) -> list[float]:
    """``START:STOP:STEP`` by integer step counting (STOP kept when it falls on the grid)."""
    parts = text.split(":")
    if len(parts) != 3:
        raise InputError(
            f"{option}: {text!r} is not START:STOP:STEP (nor a number or a comma list)"
        )
    start, stop, step = (_number(p, option) for p in parts)
    if step <= 0:
        raise InputError(f"{option}: step {step:g} in {text!r} must be positive")
    if stop < start:
        raise InputError(f"{option}: stop {stop:g} is below start {start:g} in {text!r}")
    n = math.floor((stop - start) / step + 1e-9)
    if n + 1 > MAX_AXIS_VALUES:  # counted before a value is made
        raise InputError(
            f"{option}: {text!r} gives {n + 1:,} values, more than the "
            f"{MAX_AXIS_VALUES:,} a grid angle holds; use a coarser step"
        )
    return [start + k * step for k in range(n + 1)]


def parse_range(values: Values, option: str) -> tuple[float, ...]:
    """Grid values of one angle from text, a number or a sequence of numbers.

    Text is ``START:STOP:STEP`` (STOP included when it falls on the grid: ``-4:4:1`` is
    nine values; counted in whole steps, never by adding floats), a single value, or a
    comma list whose items are values or ranges (``0,90:180:45``).

    Parameters
    ----------
    values : str, float or sequence of float
        The values.
    option : {"roll", "pitch", "phase", "tilt", "direction"}
        The angle they are for. Roll and pitch must lie within +/-:data:`MAX_TILT`
        degrees, a tilt size within 0 and :data:`MAX_TILT`; phases and directions within
        +/-``threadmate._validate.MAX_PHASE`` (the one limit of a phase) are taken modulo
        360 with repeats dropped (``0:360:5`` is 72 phases).

    Returns
    -------
    tuple of float
        Sorted, distinct values in degrees.

    Raises
    ------
    InputError
        A malformed range, a zero or negative step, a non-number, an empty set, a tilt or
        a phase out of range, or more than ``threadmate._validate.MAX_AXIS_VALUES``
        values; the message names ``option``.
    """
    if option not in _AXES:
        raise InputError(
            f"unknown grid angle {option!r}: expected roll, pitch, phase, tilt or direction"
        )
    raw: list[float] = []
    if isinstance(values, str):
        items = [s.strip() for s in values.split(",")]
        if not any(items):
            raise InputError(f"{option}: no values given")
        for item in items:
            if not item:
                raise InputError(f"{option}: empty item in {values!r}")
            raw += _span(item, option) if ":" in item else [_number(item, option)]
    elif isinstance(values, Iterable):
        for v in values:
            raw.append(check_number(f"{option} (degrees)", v))
        if not raw:
            raise InputError(f"{option}: no values given")
    elif isinstance(values, numbers.Real):
        raw = [check_number(f"{option} (degrees)", values)]
    else:
        raise InputError(
            f"{option}: expected START:STOP:STEP, a number or a list, got {type(values).__name__}"
        )
    if option in _TURNING:
        raw = [wrap_phase(check_phase(option, v)) for v in raw]  # the one phase limit
    elif option == "tilt":
        low, high = min(raw), max(raw)
        if low < 0 or high > MAX_TILT + ANGLE_TOLERANCE:
            bad = low if low < 0 else high
            raise InputError(
                f"tilt: {bad:g} deg is out of range: a tilt size lies within 0 and "
                f"{MAX_TILT:g} deg (its direction is given apart)"
            )
    else:
        worst = max(raw, key=abs)
        if abs(worst) > MAX_TILT + ANGLE_TOLERANCE:
            raise InputError(
                f"{option}: {worst:g} deg is out of range: roll and pitch "
                f"must lie within +/-{MAX_TILT:g} deg"
            )
    out: list[float] = []
    for v in sorted(round(v, _DECIMALS) + 0.0 for v in raw):  # + 0.0 turns -0.0 into 0.0
        if not out or v - out[-1] > ANGLE_TOLERANCE:
            out.append(v)
    if option in _TURNING and len(out) > 1 and out[0] + 360.0 - out[-1] <= ANGLE_TOLERANCE:
        out.pop()  # 359.9999999999 is phase 0 again
    if len(out) > MAX_AXIS_VALUES:
        raise InputError(
            f"{option}: {len(out):,} values, more than the {MAX_AXIS_VALUES:,} a grid "
            "angle holds; use a coarser step"
        )
    return tuple(out)


@dataclass(frozen=True)
class Grid:
    """Roll, pitch and phase values of a sweep (degrees) and the order of its configurations.

    Construct with :meth:`parse` (text, numbers or None for the thesis's values) or
    directly from sequences (validated and normalised the same way).

    Attributes
    ----------
    roll, pitch, phase : tuple of float
        Sorted distinct values; phases in ``[0, 360)``.
    """

    roll: tuple[float, ...]
    pitch: tuple[float, ...]
    phase: tuple[float, ...]

    def __post_init__(self) -> None:
        for name in ("roll", "pitch", "phase"):
            object.__setattr__(self, name, parse_range(getattr(self, name), name))

    @classmethod
    def parse(cls, roll: Values = None, pitch: Values = None, phase: Values = None) -> Grid:
        """A grid from text, numbers or sequences; None takes the thesis's values
        (roll and pitch -4..4 by 1, phase 0..355 by 5)."""
        # The constructor takes any Values: __post_init__ parses them into the tuples.
        given = (
            DEFAULT_RANGES["roll"] if roll is None else roll,
            DEFAULT_RANGES["pitch"] if pitch is None else pitch,
            DEFAULT_RANGES["phase"] if phase is None else phase,
        )
        return cls(*cast("tuple[tuple[float, ...], ...]", given))

    @property
    def shape(self) -> tuple[int, int, int]:
        """``(n_roll, n_pitch, n_phase)``."""
        return len(self.roll), len(self.pitch), len(self.phase)

    @property
    def size(self) -> int:
        """Number of configurations."""
        a, b, c = self.shape
        return a * b * c

    def __len__(self) -> int:
        return self.size

    def indices(self, config_id: int | np.ndarray) -> tuple[Any, Any, Any]:
        """``(i_roll, i_pitch, i_phase)`` of configuration number(s)."""
        _, n_pitch, n_phase = self.shape
        ids = np.asarray(config_id)
        if np.any((ids < 0) | (ids >= self.size)):
            raise InputError(f"config_id out of range 0..{self.size - 1}")
        i_roll, rest = np.divmod(ids, n_pitch * n_phase)
        i_pitch, i_phase = np.divmod(rest, n_phase)
        return i_roll, i_pitch, i_phase

    def configuration(self, config_id: int) -> tuple[float, float, float]:
        """``(roll, pitch, phase)`` in degrees of one configuration number."""
        i, j, k = (int(x) for x in self.indices(int(config_id)))
        return self.roll[i], self.pitch[j], self.phase[k]

    def configurations(self, config_ids: Sequence[int] | np.ndarray) -> np.ndarray:
        """``(n, 3)`` array of roll, pitch, phase for configuration numbers."""
        i, j, k = self.indices(np.asarray(config_ids, dtype=np.int64))
        return np.column_stack(
            [np.asarray(self.roll)[i], np.asarray(self.pitch)[j], np.asarray(self.phase)[k]]
        )

    def config_id(self, i_roll: int, i_pitch: int, i_phase: int) -> int:
        """The configuration number of grid indices."""
        _, n_pitch, n_phase = self.shape
        return (int(i_roll) * n_pitch + int(i_pitch)) * n_phase + int(i_phase)

    def nearest(
        self, roll: float, pitch: float, phase: float
    ) -> tuple[int, tuple[float, float, float]]:
        """The grid configuration nearest an arbitrary one (phase compared modulo 360).

        Returns
        -------
        config_id : int
        (roll, pitch, phase) : tuple of float
            The grid values.
        """
        for name, v in (("roll", roll), ("pitch", pitch)):
            check_number(f"{name} (degrees)", v)
        check_phase("phase", phase)
        i = int(np.argmin(np.abs(np.asarray(self.roll) - roll)))
        j = int(np.argmin(np.abs(np.asarray(self.pitch) - pitch)))
        d = np.abs(phase_difference(np.asarray(self.phase), phase))
        k = int(np.argmin(d))
        return self.config_id(i, j, k), (self.roll[i], self.pitch[j], self.phase[k])

    def locate(
        self, roll: float, pitch: float, phase: float, *, nearest: bool = False
    ) -> tuple[int, tuple[float, float, float], bool]:
        """The grid configuration of a request: ``(config_id, grid values, moved_to_grid)``.

        A request on the grid (phase modulo 360) is itself. One off the grid is refused
        with the nearest configuration named, unless ``nearest`` is True: then the nearest
        is taken and ``moved_to_grid`` is True. The one rule of ``library query`` and ``path``.
        """
        cid, on_grid = self.nearest(roll, pitch, phase)
        moved = not (
            math.isclose(on_grid[0], roll, abs_tol=ANGLE_TOLERANCE)
            and math.isclose(on_grid[1], pitch, abs_tol=ANGLE_TOLERANCE)
            and abs(phase_difference(on_grid[2], phase)) <= ANGLE_TOLERANCE
        )
        if moved and not nearest:
            raise InputError(
                f"the configuration roll {roll:g}, pitch {pitch:g}, phase {phase:g} is not on "
                f"the library's grid ({self.describe()}); the nearest configuration is roll "
                f"{on_grid[0]:g}, pitch {on_grid[1]:g}, phase {on_grid[2]:g}: ask for it, or "
                "pass nearest=True"
            )
        return cid, on_grid, moved

    kind = "roll-pitch"

    @property
    def held_tilts(self) -> tuple[tuple[float, float], ...]:
        """``(roll, pitch)`` of each held tilt, in configuration order."""
        return tuple((r, p) for r in self.roll for p in self.pitch)

    def neighbours(self) -> list[tuple[tuple[float, float], tuple[float, float]]]:
        """Pairs of held tilts one grid step apart (in roll or in pitch), each pair both
        ways: the active tilt steps of the network."""
        out = []
        for values, axis in ((self.roll, 0), (self.pitch, 1)):
            for a, b in zip(values, values[1:], strict=False):
                for other in self.pitch if axis == 0 else self.roll:
                    u, v = ((a, other), (b, other)) if axis == 0 else ((other, a), (other, b))
                    out += [(u, v), (v, u)]
        return out

    def to_dict(self) -> dict[str, Any]:
        """Plain mapping (lists of degrees, the shape and the order rule)."""
        return {
            "roll": list(self.roll),
            "pitch": list(self.pitch),
            "phase": list(self.phase),
            "size": self.size,
            "order": "config_id = (i_roll * n_pitch + i_pitch) * n_phase + i_phase",
        }

    @classmethod
    def from_dict(cls, doc: dict[str, Any]) -> Grid:
        """Inverse of :meth:`to_dict` (a polar grid's document: :func:`read_grid`)."""
        if isinstance(doc, dict) and doc.get("kind", "roll-pitch") != "roll-pitch":
            raise InputError(f"not a roll/pitch grid: kind {doc.get('kind')!r}")
        try:
            return cls(tuple(doc["roll"]), tuple(doc["pitch"]), tuple(doc["phase"]))
        except (KeyError, TypeError) as exc:
            raise InputError(f"not a grid description: {exc}") from None

    def describe(self, size: bool = True) -> str:
        """One line such as ``roll -4..4 (9) x pitch -4..4 (9) x phase 0..355 (72) = 5832
        configurations`` (without the count when ``size`` is False)."""

        def one(name: str, v: tuple[float, ...]) -> str:
            return f"{name} {v[0]:g}..{v[-1]:g} ({len(v)})" if len(v) > 1 else f"{name} {v[0]:g}"

        axes = f"{one('roll', self.roll)} x {one('pitch', self.pitch)} x {one('phase', self.phase)}"
        return f"{axes} = {self.size} configurations" if size else axes


@dataclass(frozen=True)
class PolarGrid:
    """Held tilts by size and direction, and phases (degrees): the polar grid of
    misalignment, and the order of its configurations (module docstring).

    The direction is the azimuth in F (the nut's frame, fixed to its thread start), from
    +X toward +Y, toward which the bolt's axis leans; each held tilt's roll and pitch are
    :func:`threadmate.geometry.held_tilt_from_polar` of its size and direction, rounded to
    1e-9 degree as every grid value is. A size of 0 is one held tilt (upright), however
    many directions.

    Construct with :meth:`parse` (text, numbers or None for :data:`DEFAULT_POLAR_RANGES`)
    or directly from sequences (validated and normalised the same way).

    Attributes
    ----------
    tilt : tuple of float
        Sorted distinct sizes, within 0 and :data:`MAX_TILT`.
    direction : tuple of float
        Sorted distinct directions in ``[0, 360)``.
    phase : tuple of float
        Sorted distinct phases in ``[0, 360)``.
    """

    tilt: tuple[float, ...]
    direction: tuple[float, ...]
    phase: tuple[float, ...]
    _polar: tuple[tuple[float, float], ...] = field(init=False, repr=False, compare=False)
    _held: tuple[tuple[float, float], ...] = field(init=False, repr=False, compare=False)

    kind = "polar"

    def __post_init__(self) -> None:
        for name in ("tilt", "direction", "phase"):
            object.__setattr__(self, name, parse_range(getattr(self, name), name))
        polar: list[tuple[float, float]] = []
        for t in self.tilt:
            polar += [(t, math.nan)] if t == 0 else [(t, d) for d in self.direction]
        held = []
        for t, d in polar:
            r, p = (0.0, 0.0) if t == 0 else held_tilt_from_polar(t, d)
            held.append((round(r, _DECIMALS) + 0.0, round(p, _DECIMALS) + 0.0))
        object.__setattr__(self, "_polar", tuple(polar))
        object.__setattr__(self, "_held", tuple(held))

    @classmethod
    def parse(
        cls, tilt: Values = None, direction: Values = None, phase: Values = None
    ) -> PolarGrid:
        """A polar grid from text, numbers or sequences; None takes
        :data:`DEFAULT_POLAR_RANGES`."""
        given = (
            DEFAULT_POLAR_RANGES["tilt"] if tilt is None else tilt,
            DEFAULT_POLAR_RANGES["direction"] if direction is None else direction,
            DEFAULT_RANGES["phase"] if phase is None else phase,
        )
        return cls(*cast("tuple[tuple[float, ...], ...]", given))

    @property
    def held_tilts(self) -> tuple[tuple[float, float], ...]:
        """``(roll, pitch)`` of each held tilt, in configuration order."""
        return self._held

    @property
    def polar_tilts(self) -> tuple[tuple[float, float], ...]:
        """``(size, direction)`` of each held tilt, in configuration order (direction NaN
        for the upright one)."""
        return self._polar

    @property
    def shape(self) -> tuple[int, int]:
        """``(n_held_tilts, n_phase)``."""
        return len(self.held_tilts), len(self.phase)

    @property
    def size(self) -> int:
        """Number of configurations."""
        a, b = self.shape
        return a * b

    def __len__(self) -> int:
        return self.size

    def indices(self, config_id: int | np.ndarray) -> tuple[Any, Any]:
        """``(i_held, i_phase)`` of configuration number(s)."""
        ids = np.asarray(config_id)
        if np.any((ids < 0) | (ids >= self.size)):
            raise InputError(f"config_id out of range 0..{self.size - 1}")
        return np.divmod(ids, len(self.phase))

    def configuration(self, config_id: int) -> tuple[float, float, float]:
        """``(roll, pitch, phase)`` in degrees of one configuration number."""
        i, k = (int(x) for x in self.indices(int(config_id)))
        r, p = self.held_tilts[i]
        return r, p, self.phase[k]

    def configurations(self, config_ids: Sequence[int] | np.ndarray) -> np.ndarray:
        """``(n, 3)`` array of roll, pitch, phase for configuration numbers."""
        i, k = self.indices(np.asarray(config_ids, dtype=np.int64))
        held = np.asarray(self.held_tilts, dtype=float).reshape(-1, 2)
        return np.column_stack([held[i, 0], held[i, 1], np.asarray(self.phase)[k]])

    def nearest(
        self, roll: float, pitch: float, phase: float
    ) -> tuple[int, tuple[float, float, float]]:
        """The grid configuration nearest an arbitrary one: the held tilt whose bolt axis
        makes the smallest angle with the requested one's, the phase nearest modulo 360.

        Returns
        -------
        config_id : int
        (roll, pitch, phase) : tuple of float
            The grid values.
        """
        for name, v in (("roll", roll), ("pitch", pitch)):
            check_number(f"{name} (degrees)", v)
        check_phase("phase", phase)
        held = np.radians(np.asarray(self.held_tilts, dtype=float).reshape(-1, 2))

        def axis(r: np.ndarray, p: np.ndarray) -> np.ndarray:
            return np.stack([np.sin(p), -np.sin(r) * np.cos(p), np.cos(r) * np.cos(p)], -1)

        want = axis(np.radians(np.array([roll])), np.radians(np.array([pitch])))[0]
        i = int(np.argmax(axis(held[:, 0], held[:, 1]) @ want))
        k = int(np.argmin(np.abs(phase_difference(np.asarray(self.phase), phase))))
        r, p = self.held_tilts[i]
        return i * len(self.phase) + k, (r, p, self.phase[k])

    def locate(
        self, roll: float, pitch: float, phase: float, *, nearest: bool = False
    ) -> tuple[int, tuple[float, float, float], bool]:
        """As :meth:`Grid.locate`: the grid configuration of a request given by its held
        roll and pitch (:func:`threadmate.geometry.held_tilt_from_polar` turns a size and
        direction into them)."""
        cid, on_grid = self.nearest(roll, pitch, phase)
        moved = not (
            math.isclose(on_grid[0], roll, abs_tol=1e-6)
            and math.isclose(on_grid[1], pitch, abs_tol=1e-6)
            and abs(phase_difference(on_grid[2], phase)) <= ANGLE_TOLERANCE
        )
        if moved and not nearest:
            t, d = self.polar_tilts[cid // len(self.phase)]
            where = "upright" if t == 0 else f"tilt {t:g} toward {d:g}"
            raise InputError(
                f"the configuration roll {roll:g}, pitch {pitch:g}, phase {phase:g} is not on "
                f"the library's grid ({self.describe()}); the nearest configuration is "
                f"{where} (roll {on_grid[0]:.6g}, pitch {on_grid[1]:.6g}), phase "
                f"{on_grid[2]:g}: ask for it, or pass nearest=True"
            )
        return cid, on_grid, moved

    def neighbours(self) -> list[tuple[tuple[float, float], tuple[float, float]]]:
        """Pairs of held tilts one grid step apart (the next size in the same direction,
        the next direction at the same size, round the circle), each pair both ways: the
        active tilt steps of the network. The upright tilt neighbours the smallest size
        above 0 in every direction."""
        index = {pt: i for i, pt in enumerate(self.polar_tilts)}
        held = self.held_tilts
        sizes = [t for t in self.tilt if t > 0]
        pairs: set[tuple[int, int]] = set()
        for n, t in enumerate(sizes):
            for m, d in enumerate(self.direction):
                here = index[(t, d)]
                if n > 0:
                    pairs.add((index[(sizes[n - 1], d)], here))
                elif 0.0 in self.tilt:
                    pairs.add((0, here))
                if len(self.direction) > 1:
                    other = index[(t, self.direction[(m + 1) % len(self.direction)])]
                    if other != here:
                        pairs.add((min(here, other), max(here, other)))
        out = []
        for a, b in sorted(pairs):
            out += [(held[a], held[b]), (held[b], held[a])]
        return out

    def to_dict(self) -> dict[str, Any]:
        """Plain mapping: the kind, lists of degrees, the held tilts, the size and the order
        rule."""
        return {
            "kind": "polar",
            "tilt": list(self.tilt),
            "direction": list(self.direction),
            "phase": list(self.phase),
            "held_tilts": [list(h) for h in self.held_tilts],
            "size": self.size,
            "direction_definition": DIRECTION_DEFINITION,
            "order": "config_id = i_held * n_phase + i_phase; held tilts: upright once, then "
            "each tilt above 0 (ascending) in each direction (ascending)",
        }

    @classmethod
    def from_dict(cls, doc: dict[str, Any]) -> PolarGrid:
        """Inverse of :meth:`to_dict`."""
        try:
            if doc.get("kind") != "polar":
                raise InputError(f"not a polar grid: kind {doc.get('kind')!r}")
            return cls(tuple(doc["tilt"]), tuple(doc["direction"]), tuple(doc["phase"]))
        except (KeyError, TypeError, AttributeError) as exc:
            raise InputError(f"not a grid description: {exc}") from None

    def describe(self, size: bool = True) -> str:
        """One line such as ``tilt 0..4 (9) x direction 0..337.5 (16) x phase 0..340 (18)
        = 2286 configurations`` (without the count when ``size`` is False)."""

        def one(name: str, v: tuple[float, ...]) -> str:
            return f"{name} {v[0]:g}..{v[-1]:g} ({len(v)})" if len(v) > 1 else f"{name} {v[0]:g}"

        axes = (
            f"{one('tilt', self.tilt)} x {one('direction', self.direction)} x "
            f"{one('phase', self.phase)}"
        )
        held = f" ({len(self.held_tilts)} held tilts)"
        return f"{axes}{held} = {self.size} configurations" if size else axes

    def polar(self, roll: Any, pitch: Any) -> tuple[np.ndarray, np.ndarray]:
        """Size and direction of held tilts (:func:`threadmate.geometry.polar_from_held_tilt`)."""
        return polar_from_held_tilt(roll, pitch)


#: A grid of either kind.
AnyGrid = Grid | PolarGrid

#: The definition of a polar grid's direction, in the metadata and the docs' words.
DIRECTION_DEFINITION = (
    "azimuth in F (the nut's frame, fixed to its thread start), from +X toward +Y, toward "
    "which the bolt's axis (+Z of B, toward the head) leans; roll = atan2(-sin t sin d, "
    "cos t), pitch = asin(sin t cos d)"
)


def make_grid(
    roll: Values = None,
    pitch: Values = None,
    phase: Values = None,
    tilt: Values = None,
    direction: Values = None,
) -> AnyGrid:
    """The grid a request names: a polar grid when a tilt size or a direction is given,
    else a roll/pitch grid (None takes each kind's defaults).

    Raises
    ------
    InputError
        Roll or pitch given with tilt or direction (a grid is one kind or the other), or a
        bad range.
    """
    square = [n for n, v in (("roll", roll), ("pitch", pitch)) if v is not None]
    polar = [n for n, v in (("tilt", tilt), ("direction", direction)) if v is not None]
    if square and polar:
        raise InputError(
            f"{square[0]} and {polar[0]} are two kinds of grid: give roll and pitch (a "
            "square grid) or tilt and direction (a polar grid), not both"
        )
    if polar:
        return PolarGrid.parse(tilt, direction, phase)
    return Grid.parse(roll, pitch, phase)


def read_grid(doc: dict[str, Any]) -> AnyGrid:
    """A grid of either kind from its :meth:`to_dict` document (a library's metadata)."""
    if isinstance(doc, dict) and doc.get("kind") == "polar":
        return PolarGrid.from_dict(doc)
    return Grid.from_dict(doc)


#: The thesis's ranges (chapter 4): roll and pitch -4..4 deg by 1, phase 0..355 by 5.
DEFAULT_RANGES = {"roll": "-4:4:1", "pitch": "-4:4:1", "phase": "0:355:5"}
#: The polar grid's default sizes and directions: 0 to 4 deg by 0.5, every 22.5 deg (the
#: phases are :data:`DEFAULT_RANGES`'s).
DEFAULT_POLAR_RANGES = {"tilt": "0:4:0.5", "direction": "0:360:22.5"}
#: The thesis's grid: 9 x 9 x 72 = 5,832 configurations.
DEFAULT_GRID = Grid.parse()
