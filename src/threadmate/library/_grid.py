"""The configuration grid: roll, pitch and phase values and the fixed configuration order.

A grid holds three sorted tuples of degrees. Configurations are numbered roll-major,
phase fastest::

    config_id = (i_roll * n_pitch + i_pitch) * n_phase + i_phase

so a chunk of consecutive ids is a run of phases of one orientation, and the number of a
configuration never changes for a given grid.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any, cast

import numpy as np

from .._angles import phase_difference, wrap_phase
from .._errors import InputError
from .._validate import MAX_AXIS_VALUES, check_number, check_phase
from ..contact import MAX_TILT as _CONTACT_MAX_TILT

__all__ = ["Grid", "parse_range", "DEFAULT_GRID", "DEFAULT_RANGES", "MAX_TILT"]

#: Largest roll or pitch a grid may hold (degrees): the contact package's limit.
MAX_TILT = _CONTACT_MAX_TILT
#: Values closer than this (degrees) are one grid value; STOP within it of the last step
#: is included.
ANGLE_TOLERANCE = 1e-9
#: Decimals kept for every grid value, so that 0.1 * 3 is stored as 0.3.
_DECIMALS = 9

Values = str | float | int | Sequence[float] | None


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
    option : {"roll", "pitch", "phase"}
        The angle they are for. Roll and pitch must lie within +/-:data:`MAX_TILT`
        degrees; phases within +/-``threadmate._validate.MAX_PHASE`` (the one limit of a
        phase) are taken modulo 360 with repeats dropped (``0:360:5`` is 72 phases).

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
    if option not in ("roll", "pitch", "phase"):
        raise InputError(f"unknown grid angle {option!r}: expected roll, pitch or phase")
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
    if option == "phase":
        raw = [wrap_phase(check_phase(option, v)) for v in raw]  # the one phase limit
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
    if option == "phase" and len(out) > 1 and out[0] + 360.0 - out[-1] <= ANGLE_TOLERANCE:
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
        """Inverse of :meth:`to_dict`."""
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


#: The thesis's ranges (chapter 4): roll and pitch -4..4 deg by 1, phase 0..355 by 5.
DEFAULT_RANGES = {"roll": "-4:4:1", "pitch": "-4:4:1", "phase": "0:355:5"}
#: The thesis's grid: 9 x 9 x 72 = 5,832 configurations.
DEFAULT_GRID = Grid.parse()
