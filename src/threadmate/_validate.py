"""Input validation shared by the API and the command line: one place for each rule.

Each check returns the value as a plain ``float`` or raises :class:`InputError` (or the
subclass given as ``error``) with one message that names the input and the allowed range.
``name`` is how the user wrote the input: ``"spec key 'pitch'"``, ``"--compliance-z"``.
"""

from __future__ import annotations

import math
import numbers
from typing import Any

import numpy as np

from ._errors import InputError

__all__ = [
    "MIN_LENGTH",
    "MAX_LENGTH",
    "MAX_WORKERS",
    "check_number",
    "check_range",
    "check_length",
    "check_workers",
]

# The range of a length, in the spec's own units (in or mm). Real screw threads lie far
# inside it in either unit: the smallest standard threads (watch and instrument screws,
# M0.3 x 0.08, 0.003 in of pitch) sit 30 times above the floor in inches and 800 times in
# mm, and the largest (M1000 in mm, the 6 in UN sizes and pipe threads to some 24 in) below
# the ceiling of 1 m or 25 m. Outside it a number is a typo or a unit mix-up, not a thread,
# and the geometry would fail in floating point (1e308 overflows a wrap into one pitch,
# 1e300 a chord count) instead of with a message.
#: Smallest length (pitch, diameter, bolt length, nut height, radius), spec units.
MIN_LENGTH = 1e-4
#: Largest length, spec units.
MAX_LENGTH = 1e3
#: Most worker processes a sweep starts (far above any one machine's cores; beyond it the
#: number is a typo, and past the C int range the process pool fails with a traceback).
MAX_WORKERS = 1024


def check_number(name: str, value: Any, *, error: type[InputError] = InputError) -> float:
    """``value`` as a float if it is a finite real number (not a bool), else ``error``."""
    # numbers.Real covers int, float and the numpy scalars; bool is a number only to Python.
    if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Real):
        raise error(f"{name} must be a number, got {value!r}")
    try:
        value = float(value)
    except OverflowError:  # an integer beyond the float range (JSON/TOML allow any size)
        raise error(f"{name} must be a finite number, got an integer too large for one") from None
    if not math.isfinite(value):
        raise error(f"{name} must be a finite number, got {value!r}")
    return value


def check_range(
    name: str,
    value: Any,
    lo: float,
    hi: float,
    *,
    units: str = "",
    error: type[InputError] = InputError,
) -> float:
    """``value`` as a float if it is a finite number within ``[lo, hi]``, else ``error``."""
    value = check_number(name, value, error=error)
    if not lo <= value <= hi:
        unit = f" {units}" if units else ""
        raise error(
            f"{name} is out of range: {value:g}{unit}; give a value from {lo:g} to {hi:g}{unit}"
        )
    return value


def check_whole(name: str, value: Any, lo: int = 1, hi: int | None = None, *, why: str = "") -> int:
    """``value`` as an int if it is a whole number (not a bool) within ``[lo, hi]``."""
    whole = (
        int(value)
        if isinstance(value, numbers.Integral) and not isinstance(value, bool | np.bool_)
        else None
    )
    if whole is None or whole < lo or (hi is not None and whole > hi):
        span = f"from {lo} to {hi}" if hi is not None else f">= {lo}"
        raise InputError(f"{name} must be a whole number {span}{why}, got {value!r}")
    return whole


def check_workers(workers: int | None) -> int | None:
    """``--workers``: ``None`` (the default) or a whole number from 1 to ``MAX_WORKERS``."""
    if workers is None:
        return None
    if isinstance(workers, numbers.Integral) and not isinstance(workers, bool | np.bool_):
        if 1 <= workers <= MAX_WORKERS:
            return int(workers)
        if workers < 1:
            raise InputError(f"--workers {workers} must be at least 1")
    raise InputError(f"--workers must be a whole number from 1 to {MAX_WORKERS}, got {workers!r}")


def check_open_range(name: str, value: Any, lo: float, hi: float, *, units: str = "") -> float:
    """``value`` as a float if it is a finite number within ``(lo, hi]``."""
    value = check_number(name, value)
    if not lo < value <= hi:
        unit = f" {units}" if units else ""
        raise InputError(f"{name} must be within ({lo:g}, {hi:g}]{unit}, got {value!r}")
    return value


def check_length(
    name: str,
    value: Any,
    units: str,
    *,
    signed: bool = False,
    zero_ok: bool = False,
    error: type[InputError] = InputError,
) -> float:
    """A finite length in ``units`` within the range every real thread fits.

    Parameters
    ----------
    name : str
        The input as the user wrote it (``"--compliance-z"``, ``"spec key 'pitch'"``).
    value
        The number to check.
    units : {"in", "mm"}
        The spec's units; the message gives the range in them.
    signed : bool
        A coordinate rather than a size: any value with ``|value| <= MAX_LENGTH``
        (zero included).
    zero_ok : bool
        A size that may be 0 (a sharp corner's fillet): ``0`` or from ``MIN_LENGTH`` up.
    error : type
        The :class:`InputError` subclass to raise (``SpecError`` for spec keys).

    Returns
    -------
    float
        ``value``.
    """
    value = check_number(name, value, error=error)
    if signed:
        return check_range(name, value, -MAX_LENGTH, MAX_LENGTH, units=units, error=error)
    if zero_ok and value == 0:
        return 0.0
    if value <= 0:
        what = "0 or a positive length" if zero_ok else "a positive length"
        raise error(f"{name} must be {what}; got {value:g} {units}")
    if zero_ok:
        # A fillet may be as small as it likes: it only rounds a corner.
        return check_range(name, value, 0.0, MAX_LENGTH, units=units, error=error)
    return check_range(name, value, MIN_LENGTH, MAX_LENGTH, units=units, error=error)
