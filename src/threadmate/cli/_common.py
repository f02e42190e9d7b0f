"""Helpers shared by the commands: spec resolution, JSON output."""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path
from typing import Any

import click
import numpy as np

from .._errors import InputError
from ..geometry import ThreadSpec, load_spec

__all__ = ["resolve_spec", "emit_json", "to_jsonable", "SPEC_HELP", "check_angle",
           "check_configuration_options"]

SPEC_HELP = (
    "DESIGNATION|SPEC is a thread designation such as '1/4-20 UNC-2A/2B', '#10-24 UNC', "
    "'M6x1-6g/6H' or 'M8', or the path of a spec file (.json or .toml, see conventions)."
)


def resolve_spec(text: str, condition: str = "mean") -> ThreadSpec:
    """A spec from a designation or a spec-file path (refusing a missing file clearly)."""
    path = Path(text)
    if path.suffix.lower() in (".json", ".toml") or path.exists():
        if not path.is_file():
            raise InputError(f"spec file not found: {text}")
        return load_spec(path)
    from ..geometry import spec_from_designation

    return spec_from_designation(text, condition=condition)


def to_jsonable(obj: Any) -> Any:
    """Convert numpy scalars/arrays, tuples and paths into plain JSON types."""
    if isinstance(obj, dict):
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [to_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return to_jsonable(obj.tolist())
    if isinstance(obj, np.bool_):
        return bool(obj)
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, np.floating | float):
        value = float(obj)
        return value if math.isfinite(value) else None
    if isinstance(obj, Path):
        return str(obj)
    return obj


def emit_json(doc: Any) -> None:
    """Write exactly one JSON document to stdout."""
    sys.stdout.write(json.dumps(to_jsonable(doc), indent=2) + "\n")
    sys.stdout.flush()


def check_angle(name: str, value: float, limit: float = 90.0) -> float:
    """Refuse a non-finite angle or one beyond +/- ``limit`` degrees."""
    if not math.isfinite(value) or abs(value) > limit:
        raise InputError(f"--{name} {value:g} is out of range: give degrees within +/-{limit:g}")
    return value


def echo_err(message: str) -> None:
    """One line on stderr."""
    click.echo(message, err=True)


def check_configuration_options(roll: float, pitch: float, phase: float,
                                chord: float | None) -> None:
    """Refuse a tilt beyond the contact stages' range, a non-finite phase or a chord that
    is not a positive length (before anything is built)."""
    from ..contact import MAX_TILT

    for name, value in (("roll", roll), ("pitch", pitch)):
        if not math.isfinite(value) or abs(value) > MAX_TILT:
            raise InputError(f"--{name} {value:g} is out of range: give degrees within "
                             f"+/-{MAX_TILT:g}")
    if not math.isfinite(phase):
        raise InputError(f"--phase {phase:g} is not a finite angle")
    if chord is not None and not (math.isfinite(chord) and chord > 0):
        raise InputError(f"--chord {chord:g} must be a positive length")
