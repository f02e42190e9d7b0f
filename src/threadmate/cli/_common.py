"""Helpers shared by the commands: spec resolution, JSON output, output paths."""

from __future__ import annotations

import contextlib
import math
import os
import shutil
import sys
import tempfile
from collections.abc import Callable, Iterator
from dataclasses import dataclass, fields, replace
from pathlib import Path
from typing import Any

import click

from .._errors import InputError, SpecError
from .._json import json_text, to_jsonable
from .._validate import MAX_TILT, check_phase
from ..geometry import (
    BoltPoint,
    Countersink,
    Designation,
    ThreadSpec,
    load_spec,
    parse_designation,
    parse_length,
    spec_from_designation,
    standard_countersink_diameter,
    standard_nut_height,
)

__all__ = [
    "Parts",
    "parts_document",
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


@dataclass(frozen=True)
class Parts:
    """The bolt's point, the nut's countersink and the two lengths as the options
    (:func:`threadmate.cli._options.parts_option`) give them; None: not given.

    Applied by :func:`resolve_spec`: to a designation through
    :func:`threadmate.geometry.spec_from_designation` (a chamfered point and the standard
    countersink unless told otherwise), to a spec file by replacing its fields.
    """

    point: str | None = None
    chamfer_angle: float | None = None
    point_diameter: float | None = None
    round_radius: float | None = None
    countersink: bool | None = None
    countersink_angle: float | None = None
    countersink_diameter: float | None = None
    bolt_length: str | None = None
    nut_height: str | None = None

    @property
    def given(self) -> bool:
        """Whether any option was given."""
        return any(getattr(self, f.name) is not None for f in fields(self))


#: The option of each :class:`Parts` field.
PART_OPTIONS = {
    "point": "--point",
    "chamfer_angle": "--chamfer-angle",
    "point_diameter": "--point-diameter",
    "round_radius": "--round-radius",
    "countersink": "--countersink",
    "countersink_angle": "--countersink-angle",
    "countersink_diameter": "--countersink-diameter",
    "bolt_length": "--bolt-length",
    "nut_height": "--nut-height",
}
#: The spec key each option sets (to name the option in the spec's refusals).
_PART_KEYS = {
    "bolt.point.form": "point",
    "bolt.point.angle": "chamfer_angle",
    "bolt.point.diameter": "point_diameter",
    "bolt.point.radius": "round_radius",
    "nut.countersink.angle": "countersink_angle",
    "nut.countersink.diameter": "countersink_diameter",
    "bolt.length": "bolt_length",
    "nut.height": "nut_height",
}


def resolve_spec(text: str, condition: str = "mean", parts: Parts | None = None) -> ThreadSpec:
    """A spec from a designation or a spec-file path (refusing a missing file, a folder or
    an empty designation clearly), with the bolt's point, the nut's countersink and their
    lengths as ``parts`` gives them (a designation: a chamfered point and the standard
    countersink unless told otherwise; a spec file: its own unless told otherwise)."""
    parts = parts or Parts()
    if is_spec_path(text):
        spec = load_spec(text)
        if not parts.given:
            return spec
        return _naming_options(parts, lambda: _parts_of_spec(spec, parts))
    if not parts.given:
        return spec_from_designation(text, condition=condition)
    des = parse_designation(text)
    return _naming_options(parts, lambda: _parts_of_designation(des, condition, parts))


def _naming_options(parts: Parts, build: Callable[[], ThreadSpec]) -> ThreadSpec:
    """``build()``, a refusal of a spec key that an option set prefixed with the option."""
    try:
        return build()
    except SpecError as exc:
        message = str(exc)
        for key, name in _PART_KEYS.items():
            if getattr(parts, name) is not None and f"'{key}'" in message:
                raise SpecError(f"{PART_OPTIONS[name]}: {message}") from None
        raise


def _check_part_options(parts: Parts, form: str, countersink: bool) -> None:
    """Refuse an option that does not apply to the point's form or to no countersink."""
    for name, forms in (
        ("chamfer_angle", ("chamfer",)),
        ("round_radius", ("round",)),
        ("point_diameter", ("chamfer", "round")),
    ):
        if getattr(parts, name) is not None and form not in forms:
            raise InputError(
                f"{PART_OPTIONS[name]} applies to --point {' or '.join(forms)}, not to a "
                f"{form} point"
            )
    if not countersink:
        for name in ("countersink_angle", "countersink_diameter"):
            if getattr(parts, name) is not None:
                raise InputError(
                    f"{PART_OPTIONS[name]} applies to a countersink, not --no-countersink"
                )


def _length_option(
    text: str | None, name: str, pitch: float, units: str, des: str | Designation | None
) -> float | None:
    """``--bolt-length`` or ``--nut-height`` in the spec's units (None: not given)."""
    if text is None:
        return None
    option = PART_OPTIONS[name]
    if name == "nut_height" and text.strip().lower() == "standard":
        if des is None:
            raise InputError(
                f"{option} standard needs a designation and the spec file names none; give "
                f"the height in {units} or in pitches (e.g. 3p)"
            )
        try:
            return standard_nut_height(des)
        except InputError as exc:  # a size the tables lack, a spec's unreadable designation
            raise SpecError(f"{option} standard: {exc}") from None
    try:
        value: float | str = float(text)
    except ValueError:
        value = text
    return parse_length(value, pitch, option, units)


def _parts_of_designation(des: Designation, condition: str, parts: Parts) -> ThreadSpec:
    form = parts.point or "chamfer"
    countersink = True if parts.countersink is None else parts.countersink
    _check_part_options(parts, form, countersink)
    sink: Countersink | bool = False
    if countersink:
        angle = {} if parts.countersink_angle is None else {"angle": parts.countersink_angle}
        sink = Countersink(**angle, diameter=parts.countersink_diameter)
    return spec_from_designation(
        des,
        condition,
        point=BoltPoint(form, parts.chamfer_angle, parts.point_diameter, parts.round_radius),
        countersink=sink,
        bolt_length=_length_option(parts.bolt_length, "bolt_length", des.pitch, des.units, des),
        nut_height=_length_option(parts.nut_height, "nut_height", des.pitch, des.units, des),
    )


def _parts_of_spec(spec: ThreadSpec, parts: Parts) -> ThreadSpec:
    """``spec`` with the fields the options give replaced. A length that is the spec's
    default (the point's height or countersink's depth and one pitch) stays the default:
    it follows new ends."""
    des = spec.designation  # read only if a standard value is asked for
    old_point, old_sink = spec.bolt.point, spec.nut.countersink
    form = parts.point or old_point.form
    countersink = parts.countersink
    if countersink is None:  # a countersink's angle or diameter asks for one
        countersink = old_sink is not None or (
            parts.countersink_angle is not None or parts.countersink_diameter is not None
        )
    _check_part_options(parts, form, countersink)
    keep = old_point if form == old_point.form else BoltPoint(form)
    point = BoltPoint(
        form,
        keep.angle if parts.chamfer_angle is None else parts.chamfer_angle,
        keep.diameter if parts.point_diameter is None else parts.point_diameter,
        keep.radius if parts.round_radius is None else parts.round_radius,
    )
    sink: Countersink | None = None
    if countersink:
        angle = parts.countersink_angle
        diameter = parts.countersink_diameter
        if old_sink is not None:
            angle = old_sink.angle if angle is None else angle
            diameter = old_sink.diameter if diameter is None else diameter
        if diameter is None:
            if des is None:
                raise InputError(
                    "--countersink: the spec file has no countersink and names no "
                    "designation to take the standard's from; give --countersink-diameter"
                )
            try:
                diameter = standard_countersink_diameter(des, spec.nut.major)
            except InputError as exc:  # the spec's designation is unreadable
                raise InputError(f"--countersink: {exc}") from None
        sink = Countersink(diameter=diameter) if angle is None else Countersink(angle, diameter)
    length = _length_option(parts.bolt_length, "bolt_length", spec.pitch, spec.units, des)
    height = _length_option(parts.nut_height, "nut_height", spec.pitch, spec.units, des)
    old_length, old_height = spec.bolt.length, spec.nut.height
    assert old_length is not None and old_height is not None  # filled in by the spec
    tol = 1e-9 * spec.pitch
    if length is None and abs(old_length - spec.point_height - spec.pitch) > tol:
        length = old_length  # its own length; the default follows the new point
    if height is None and abs(old_height - spec.countersink_depth - spec.pitch) > tol:
        height = old_height
    return replace(
        spec,
        bolt=replace(spec.bolt, point=point, length=length),
        nut=replace(spec.nut, countersink=sink, height=height),
    )


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


def check_angle(name: str, value: float, limit: float = 90.0) -> float:
    """Refuse a non-finite angle or one beyond +/- ``limit`` degrees."""
    if not math.isfinite(value) or abs(value) > limit:
        raise InputError(f"--{name} {value:g} is out of range: give degrees within +/-{limit:g}")
    return value


def echo_err(message: str) -> None:
    """One line on stderr."""
    click.echo(message, err=True)


def shown_phase(phase: float) -> float:
    """A phase as every command prints it: wrapped into [0, 360) degrees. (A search's
    phases run on past 360 as it turns; how far it turned is said as the turn,
    :func:`turn_words`.)"""
    wrapped = phase % 360.0
    return 0.0 if wrapped >= 360.0 - 1e-9 else wrapped + 0.0  # no 360.0000, no -0


def turn_words(turn: float, fmt: str = ".4f") -> str:
    """A turn in degrees and in turns: ``372.5400 deg (1.03 turns)``."""
    return f"{turn:{fmt}} deg ({abs(turn) / 360.0:.2f} turns)"


def check_configuration_options(
    roll: float, pitch: float, phase: float, chord: float | None
) -> None:
    """Refuse a tilt beyond the contact stages' range, a phase beyond
    :data:`~threadmate._validate.MAX_PHASE` or a chord that is not a positive length
    (before anything is built)."""
    for name, value in (("roll", roll), ("pitch", pitch)):
        if not math.isfinite(value) or abs(value) > MAX_TILT:
            raise InputError(
                f"--{name} {value:g} is out of range: give degrees within +/-{MAX_TILT:g}"
            )
    check_phase("--phase", phase)
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
        if path.exists():
            if not path.is_dir():
                raise InputError(f"{path} exists and is not a directory")
            _probe(path, "file")
        else:
            _probe(_existing_ancestor(path), "dir")
            _note_new(path)
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
            _note_new(parent)
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
