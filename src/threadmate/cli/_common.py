"""Helpers shared by the commands: spec resolution, JSON output, output paths."""

from __future__ import annotations

import contextlib
import math
import os
import shutil
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import click

from .._errors import InputError
from .._json import json_text, to_jsonable
from ..geometry import ThreadSpec, load_spec

__all__ = [
    "resolve_spec",
    "is_spec_path",
    "emit_json",
    "to_jsonable",
    "SPEC_HELP",
    "check_angle",
    "check_configuration_options",
    "writable_output",
    "writable_directory",
    "write_failed",
]

SPEC_HELP = (
    "DESIGNATION|SPEC is a thread designation such as '1/4-20 UNC-2A/2B', '#10-24 UNC', "
    "'M6x1-6g/6H' or 'M8', or the path of a spec file (.json or .toml, see conventions)."
)


def is_spec_path(text: str) -> bool:
    """Whether ``text`` names a spec file (a .json/.toml name, or anything that exists)
    rather than a designation. Blank text is a (empty) designation, not the folder "."."""
    if not text.strip():
        return False
    path = Path(text)
    return path.suffix.lower() in (".json", ".toml") or path.exists()


def resolve_spec(text: str, condition: str = "mean") -> ThreadSpec:
    """A spec from a designation or a spec-file path (refusing a missing file, a folder or
    an empty designation clearly)."""
    if is_spec_path(text):
        return load_spec(text)
    from ..geometry import spec_from_designation

    return spec_from_designation(text, condition=condition)


def emit_json(doc: Any) -> None:
    """Write exactly one JSON document to stdout."""
    sys.stdout.write(json_text(doc))
    sys.stdout.flush()


def check_angle(name: str, value: float, limit: float = 90.0) -> float:
    """Refuse a non-finite angle or one beyond +/- ``limit`` degrees."""
    if not math.isfinite(value) or abs(value) > limit:
        raise InputError(f"--{name} {value:g} is out of range: give degrees within +/-{limit:g}")
    return value


def echo_err(message: str) -> None:
    """One line on stderr."""
    click.echo(message, err=True)


def check_configuration_options(
    roll: float, pitch: float, phase: float, chord: float | None
) -> None:
    """Refuse a tilt beyond the contact stages' range, a non-finite phase or a chord that
    is not a positive length (before anything is built)."""
    from ..contact import MAX_TILT

    for name, value in (("roll", roll), ("pitch", pitch)):
        if not math.isfinite(value) or abs(value) > MAX_TILT:
            raise InputError(
                f"--{name} {value:g} is out of range: give degrees within +/-{MAX_TILT:g}"
            )
    if not math.isfinite(phase):
        raise InputError(f"--phase {phase:g} is not a finite angle")
    if chord is not None and not (math.isfinite(chord) and chord > 0):
        raise InputError(f"--chord {chord:g} must be a positive length")


# -- output paths ------------------------------------------------------------------------
def _describe(exc: OSError) -> str:
    return exc.strerror or str(exc)


def _probe(folder: Path, what: str) -> None:
    """Create and remove a temporary entry in the existing ``folder``: the one test that
    also holds for root and for file systems such as /proc that refuse every write."""
    try:
        if what == "file":
            fd, tmp = tempfile.mkstemp(prefix=".threadmate-probe-", dir=folder)
            os.close(fd)
            os.unlink(tmp)
        else:
            shutil.rmtree(tempfile.mkdtemp(prefix=".threadmate-probe-", dir=folder))
    except OSError as exc:
        raise InputError(f"{folder} does not accept new files ({_describe(exc)})") from None


def _existing_ancestor(path: Path) -> Path:
    """The nearest ancestor of ``path`` that exists (refusing one that is not a folder)."""
    for parent in path.parents:  # a relative path ends at ".", an absolute one at "/"
        if parent.exists():
            if not parent.is_dir():
                raise InputError(f"cannot create {path}: {parent} is not a directory")
            return parent
    return Path(".")


def writable_directory(path: str | os.PathLike[str], option: str = "-o") -> Path:
    """``path`` as a folder the command can create (if missing) and write into.

    Checked before any work, writing nothing: an existing folder must accept a new file;
    a missing one needs its nearest existing ancestor to be a folder that accepts a new
    folder. Raises :class:`InputError` naming ``option`` and the problem otherwise.
    """
    path = Path(path)
    with _named(option, path):
        if path.exists():
            if not path.is_dir():
                raise InputError(f"{path} exists and is not a directory")
            _probe(path, "file")
        else:
            _probe(_existing_ancestor(path), "dir")
    return path


def writable_output(path: str | os.PathLike[str], option: str = "-o") -> Path:
    """``path`` as a file the command can write (creating missing folders above it).

    Checked before any work, writing nothing: ``path`` must not be a folder, and its folder
    must exist and accept a new file or be creatable. Raises :class:`InputError` naming
    ``option`` and the problem otherwise.
    """
    path = Path(path)
    with _named(option, path):
        if path.is_dir():
            raise InputError(f"{path} is a directory, not a file")
        if path.exists() and not path.is_file():
            raise InputError(f"{path} exists and is not a regular file")
        parent = path.parent
        if parent.exists():
            if not parent.is_dir():
                raise InputError(f"cannot create {path}: {parent} is not a directory")
            _probe(parent, "file")
        else:
            _probe(_existing_ancestor(parent), "dir")
    return path


@contextlib.contextmanager
def _named(option: str, path: Path) -> Iterator[None]:
    """Prefix an InputError raised inside with the option (``-o /x: ...``)."""
    try:
        yield
    except InputError as exc:
        raise InputError(f"{option} {path}: {exc}") from None


def write_failed(path: str | os.PathLike[str], exc: OSError) -> InputError:
    """The :class:`InputError` for an ``OSError`` met while writing ``path`` (a disk that
    filled, a folder removed meanwhile): raise it ``from None`` in place of the OSError."""
    return InputError(f"cannot write {path}: {_describe(exc)}")
