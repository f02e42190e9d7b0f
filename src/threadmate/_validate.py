"""Input validation shared by the API and the command line: one place for each rule.

Each check returns the value as a plain ``float`` or raises :class:`InputError` (or the
subclass given as ``error``) with one message that names the input and the allowed range.
``name`` is the input's name in the API: a parameter (``"compliance_z"``, ``"phase"``) or a
spec key (``"spec key 'pitch'"``). A message names a parameter first, as the parameter's own
name, and suggests a value as ``name=value``; the command line turns these into its option
names (:mod:`threadmate.cli._options`), so no message here names an option.

Everything here is light to import (numpy alone): the command line quotes these limits in
its help and checks its options with them before any stage loads.
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
    "MAX_TILT",
    "MAX_PHASE",
    "check_configuration",
    "check_number",
    "check_phase",
    "check_roll_spread",
    "check_range",
    "check_length",
    "check_max_faces",
    "check_workers",
    "check_search_steps",
    "check_starts",
    "duration_words",
    "FIGURE_FORMATS",
    "MAX_AXIS_VALUES",
    "MAX_FACES",
    "MAX_K",
    "MAX_STARTS",
    "MAX_STARTS_CEILING",
    "MAX_SEARCH_STEPS",
    "WARN_FACES",
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
#: Largest roll or pitch (degrees) the contact stages and the mechanics accept: beyond it
#: the "bolt comes down on the nut" picture (tip first, compliance centre above the nut)
#: no longer holds.
MAX_TILT = 45.0
#: Largest phase (degrees, either sign) a command or a function takes. A phase counts modulo
#: 360, but past a million degrees (some 2,800 turns) a number is a typo, and the float's
#: own spacing (1e-10 deg at 1e6, 16 deg at 1e18) would move the pose it names.
MAX_PHASE = 1e6

# Limits on the size of a computation, counted before anything is allocated or written
# (one place for all of them). The rates give a refusal's time estimate: threadmate's
# defaults (1/4-20 UNC-2A/2B, its chamfered point and countersink, the default compliance
# and step) on a 2-core machine under load (docs/validation.md, "Cost: the sweep").
#: Most values one grid angle (roll, pitch or phase) may hold: a tilt of +/-45 deg by
#: 0.001 deg, or a turn of phase by 0.0036 deg.
MAX_AXIS_VALUES = 100_000
#: Most starts (grid configurations) a sweep takes unless told otherwise (``max_starts``):
#: 17 times the thesis's grid of 5,832.
MAX_STARTS = 100_000
#: Most starts a sweep takes at all, whatever ``max_starts`` says: a library is read whole by
#: the network, and its configuration numbers are listed in memory.
MAX_STARTS_CEILING = 10_000_000
#: Configurations a sweep computes per second and per worker (mechanics; thesis model).
SWEEP_RATE = {"mechanics": 0.6, "thesis": 20.0}
#: Most continuation steps a search or screw-in takes: turns x 360 / step (one turn at
#: 0.01 deg, the resolution the search locates its events to).
MAX_SEARCH_STEPS = 36_000
#: Continuation steps a search takes per second.
SEARCH_STEP_RATE = 4.0
#: Triangles above which a mesh from CAD is taken with a warning. A 1/4-20 bolt meshed at
#: threadmate's default chord (5e-6 in) has about 53,000 over its default length; the
#: set-up of the contact stages grows in time and memory with the count
#: (docs/validation.md, "Cost: meshes and queries").
WARN_FACES = 500_000
#: Triangles above which a mesh from CAD is refused unless the caller raises the limit
#: (``max_faces``).
MAX_FACES = 2_000_000
#: Most paths :func:`threadmate.network.k_best_paths` returns (Yen's k shortest paths,
#: whose cost grows with k).
MAX_K = 20
#: File suffixes a figure may be written to, and their matplotlib formats.
FIGURE_FORMATS = {".png": "png", ".pdf": "pdf", ".svg": "svg"}


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


def check_phase(name: str, value: Any) -> float:
    """A phase in degrees: a finite number within +/-:data:`MAX_PHASE` (``name``: the
    parameter, ``"phase"``). The one limit of every command and function that takes a
    phase, the grid's phases included."""
    value = check_number(name, value)
    if abs(value) > MAX_PHASE:
        raise InputError(
            f"{name} {value:g} is out of range: give degrees within +/-{MAX_PHASE:g} "
            "(a phase counts modulo 360)"
        )
    return value


def check_configuration(roll: Any, pitch: Any, phase: Any) -> tuple[float, float, float]:
    """A configuration in degrees: ``roll`` and ``pitch`` finite and within
    +/-:data:`MAX_TILT`, ``phase`` within +/-:data:`MAX_PHASE` (:func:`check_phase`). The
    one check of every function and command that takes one start of the bolt."""
    out = []
    for name, value in (("roll", roll), ("pitch", pitch)):
        value = check_number(f"{name} (degrees)", value)
        if abs(value) > MAX_TILT:
            raise InputError(
                f"{name} {value:g} deg is out of range: the contact stages take "
                f"roll and pitch within +/-{MAX_TILT:g} deg"
            )
        out.append(value)
    return out[0], out[1], check_phase("phase", phase)


def check_roll_spread(roll_spread: Any) -> float | None:
    """The roll error a recommendation expects (degrees): None (every roll of the grid) or
    a number from 0 to :data:`MAX_TILT`, the largest held roll a grid holds. The one range
    of :func:`threadmate.network.recommend` and of the pipeline."""
    if roll_spread is None:
        return None
    return check_range("roll_spread (degrees)", roll_spread, 0.0, MAX_TILT)


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
    """``workers``: ``None`` (the default) or a whole number from 1 to ``MAX_WORKERS``."""
    if workers is None:
        return None
    if isinstance(workers, numbers.Integral) and not isinstance(workers, bool | np.bool_):
        if 1 <= workers <= MAX_WORKERS:
            return int(workers)
        if workers < 1:
            raise InputError(f"workers {workers} must be at least 1")
    raise InputError(f"workers must be a whole number from 1 to {MAX_WORKERS}, got {workers!r}")


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
        The input's name in the API (``"compliance_z"``, ``"spec key 'pitch'"``).
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


def duration_words(seconds: float) -> str:
    """A time estimate in words: ``"about 40 s"``, ``"about 3.2 h"``, ``"about 177 days"``."""
    for unit, size in (("years", 365.25 * 86400), ("days", 86400), ("h", 3600), ("min", 60)):
        if seconds >= 2 * size:
            value = seconds / size
            return f"about {value:.3g} {unit}" if value < 1e6 else f"about {value:.1e} {unit}"
    return f"about {max(seconds, 1):.0f} s"


def check_max_faces(max_faces: Any) -> int:
    """``max_faces``, the most triangles a mesh from CAD may have: None (the default,
    :data:`MAX_FACES`) or a whole number of at least 4 (a tetrahedron's)."""
    if max_faces is None:
        return MAX_FACES
    return check_whole("max_faces", max_faces, 4, why=" (triangles)")


def check_search_steps(turns: float, step: float) -> int:
    """The continuation steps of a search over ``turns`` (turns x 360 / ``step`` degrees),
    refused past :data:`MAX_SEARCH_STEPS` with the count and the time it would take."""
    steps = math.ceil(float(turns) * 360.0 / float(step) - 1e-9)
    if steps > MAX_SEARCH_STEPS:
        need = float(turns) * 360.0 / MAX_SEARCH_STEPS
        raise InputError(
            f"step {step:g} deg over {turns:g} turn(s) is {steps:,} continuation steps, "
            f"more than the {MAX_SEARCH_STEPS:,} a search takes (at about "
            f"{SEARCH_STEP_RATE:g} steps/s: {duration_words(steps / SEARCH_STEP_RATE)}); give "
            f"step={need:.3g} or coarser, or fewer turns"
        )
    return steps


def check_starts(
    count: int, max_starts: int | None, *, model: str, workers: int, what: str = ""
) -> int:
    """Refuse a sweep of ``count`` starts past ``max_starts`` (default :data:`MAX_STARTS`;
    at most :data:`MAX_STARTS_CEILING`), naming the count, the time it would take on
    ``workers`` workers at :data:`SWEEP_RATE` and how to raise the limit."""
    if max_starts is None:
        limit = MAX_STARTS
    else:
        limit = check_whole("max_starts", max_starts, 1, MAX_STARTS_CEILING)
    if count <= limit:
        return limit
    rate = SWEEP_RATE.get(model, SWEEP_RATE["mechanics"])
    eta = duration_words(count / (rate * max(1, workers)))
    grid = f" ({what})" if what else ""
    head = (
        f"the grid{grid} has {count:,} configurations: at about {rate:g} per second per "
        f"worker ({model} model) that is {eta} on {workers} worker(s)"
    )
    if count > MAX_STARTS_CEILING:
        raise InputError(
            f"{head}; a library holds at most {MAX_STARTS_CEILING:,} starts, whatever "
            "max_starts says: use a coarser grid"
        )
    raise InputError(
        f"{head}, past the limit of {limit:,} starts; use a coarser grid, or pass "
        f"max_starts={count} to run it"
    )
