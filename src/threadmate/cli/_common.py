"""Helpers shared by the commands: spec resolution, JSON output, progress on stderr."""

from __future__ import annotations

import json
import math
import sys
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any, TypeVar

import click
import numpy as np

from .._errors import InputError
from ..geometry import ThreadSpec, load_spec

__all__ = ["resolve_spec", "emit_json", "to_jsonable", "progress", "SPEC_HELP", "check_angle"]

T = TypeVar("T")

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


def progress(items: Iterable[T], total: int | None, label: str) -> Iterator[T]:
    """Iterate with a progress bar on stderr: items done, rate and time left.

    stdout is never touched, so ``--json`` output stays one clean document.
    """
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        ProgressColumn,
        TextColumn,
        TimeRemainingColumn,
    )
    from rich.text import Text

    class _Rate(ProgressColumn):
        def render(self, task):  # noqa: ANN001, ANN202 - rich's column protocol
            return Text(f"{task.speed:.1f}/s" if task.speed else "-/s")

    console = Console(file=sys.stderr)
    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), _Rate(),
               TimeRemainingColumn())
    with Progress(*columns, console=console, transient=False) as bar:
        task = bar.add_task(label, total=total)
        for item in items:
            yield item
            bar.advance(task)


def echo_err(message: str) -> None:
    """One line on stderr."""
    click.echo(message, err=True)
