"""Helpers shared by the commands: spec resolution, JSON output, output paths."""

from __future__ import annotations

import contextlib
import os
import shutil
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import click

from .._angles import FULL_TURN, wrap_phase
from .._errors import InputError
from .._json import json_text
from ..geometry import SpecParts, ThreadSpec, with_parts

__all__ = [
    "parts_document",
    "resolve_spec",
    "is_spec_path",
    "emit_json",
    "SPEC_HELP",
    "writable_output",
    "writable_directory",
    "write_failed",
    "NewFolders",
    "new_folders",
    "shown_phase",
    "turn_words",
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


def resolve_spec(text: str, condition: str = "mean", parts: SpecParts | None = None) -> ThreadSpec:
    """A spec from a designation or a spec-file path (refusing a missing file, a folder or
    an empty designation clearly), with the bolt's point, the nut's countersink and their
    lengths as ``parts`` gives them (the options of
    :func:`threadmate.cli._options.parts_option`, applied by
    :func:`threadmate.geometry.with_parts`: a designation takes a chamfered point and the
    standard countersink unless told otherwise, a spec file its own)."""
    spec: str | Path = Path(text) if is_spec_path(text) else text
    return with_parts(spec, condition=condition, **(parts or SpecParts()).arguments())


def parts_document(spec: ThreadSpec) -> dict[str, Any]:
    """The bolt's point and the nut's countersink of a spec, with the point's height, the
    countersink's depth and the two lengths (angles in degrees, lengths in the spec's
    units): the ``parts`` entry of ``threadmate thread --json``."""
    sink = spec.nut.countersink
    return {
        "point": {**spec.bolt.point.to_dict(), "height": spec.point_height},
        "countersink": (
            None if sink is None else {**sink.to_dict(), "depth": spec.countersink_depth}
        ),
        "bolt_length": spec.bolt.length,
        "nut_height": spec.nut.height,
    }


def emit_json(doc: Any) -> None:
    """Write exactly one JSON document to stdout."""
    sys.stdout.write(json_text(doc))
    sys.stdout.flush()


def echo_err(message: str) -> None:
    """One line on stderr."""
    click.echo(message, err=True)


def shown_phase(phase: float) -> float:
    """A phase as every command prints it: wrapped into [0, 360) degrees. (A search's
    phases run on past 360 as it turns; how far it turned is said as the turn,
    :func:`turn_words`.)"""
    wrapped = wrap_phase(phase)
    return 0.0 if wrapped >= FULL_TURN - 1e-9 else wrapped + 0.0  # no 360.0000, no -0


def turn_words(turn: float, fmt: str = ".4f") -> str:
    """A turn in degrees and in turns: ``372.5400 deg (1.03 turns)``."""
    return f"{turn:{fmt}} deg ({abs(turn) / FULL_TURN:.2f} turns)"


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


class NewFolders:
    """The folders that the checked output paths of one run need and that did not exist:
    :func:`writable_directory` and :func:`writable_output` note them. A run that fails
    removes those left empty (and the empty folders it made inside them)."""

    def __init__(self) -> None:
        self.folders: list[Path] = []

    def note(self, folder: Path) -> None:
        """Note ``folder`` and each missing folder above it, if ``folder`` is missing."""
        for f in (folder, *folder.parents):
            if f.exists():
                break
            if f not in self.folders:
                self.folders.append(f)

    def remove_empty(self) -> list[Path]:
        """Remove the noted folders that hold no file (deepest first); return them."""
        removed = []
        for top in sorted(self.folders, key=lambda f: len(f.parts), reverse=True):
            if not top.is_dir():
                continue
            inner = [Path(d) for d, _, _ in os.walk(top, topdown=False)]
            for folder in inner:  # the run made everything inside a folder it made
                with contextlib.suppress(OSError):  # not empty: it keeps what it holds
                    folder.rmdir()
                    removed.append(folder)
        return removed


_NEW_FOLDERS: NewFolders | None = None


@contextlib.contextmanager
def new_folders() -> Iterator[NewFolders]:
    """Collect the output folders a run will create (see :class:`NewFolders`)."""
    global _NEW_FOLDERS
    previous, _NEW_FOLDERS = _NEW_FOLDERS, NewFolders()
    try:
        yield _NEW_FOLDERS
    finally:
        _NEW_FOLDERS = previous


def _note_new(folder: Path) -> None:
    if _NEW_FOLDERS is not None:
        _NEW_FOLDERS.note(folder)


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
        if path.exists() and not path.is_dir():
            raise InputError(f"{path} exists and is not a directory")
        _check_folder(path)
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
        if parent.exists() and not parent.is_dir():
            raise InputError(f"cannot create {path}: {parent} is not a directory")
        _check_folder(parent)
    return path


def _check_folder(folder: Path) -> None:
    """A folder to write into: an existing one must accept a new file; a missing one (noted,
    to be removed again if the command fails) needs its nearest existing ancestor to
    accept a new folder."""
    if folder.exists():
        _probe(folder, "file")
    else:
        _probe(_existing_ancestor(folder), "dir")
        _note_new(folder)


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
