"""The library on disk: a Parquet dataset directory that describes itself.

Layout of a library directory::

    _threadmate.json        metadata (model, spec, grid, parameters, units, version)
    part-00000.parquet      rows of finished configurations, one file per chunk
    part-00001.parquet      ...

Every file appears whole or not at all (written to a temporary name, then renamed), and
every part carries the library's metadata in its Arrow schema (key ``threadmate``; the
grid's values are in ``_threadmate.json`` only, the part names the grid's shape), so the
directory reads directly with ``pyarrow.dataset.dataset(dir)``,
``pandas.read_parquet(dir)`` or DuckDB's ``read_parquet('dir/*.parquet')``: names that
start with ``_`` or ``.`` are skipped by pyarrow. A sweep holds ``.threadmate-sweep.lock``
(its process id and host) while it writes.

Every reader checks, on opening, that the rows fit the grid of ``_threadmate.json``
(each configuration number within the grid, and its held tilt and phase the grid's) and
refuses a library that does not with one :class:`~threadmate.LibraryError`.

Rows follow the record contract of :mod:`threadmate.contact`: for the ``mechanics`` model
(the default) one row per contact state (``STATE_COLUMNS``: the starts, the states passed
on the way and the continuations, each with its passive transition); for the ``thesis``
model one row per configuration (``thesis_schema``).
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import json
import math
import os
import re
import socket
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.dataset as ds
import pyarrow.parquet as pq

from .._angles import phase_difference
from .._errors import InputError, LibraryError
from .._io import atomic_path, atomic_write_text
from .._json import json_text
from ._grid import AnyGrid, read_grid
from ._models import MODELS

__all__ = [
    "METADATA_FILE",
    "FORMAT",
    "library_schema",
    "read_metadata",
    "write_metadata",
    "write_part",
    "part_files",
    "done_ids",
    "load",
    "info",
    "query",
    "compare_metadata",
    "configurations",
    "progress",
    "sweep_lock",
    "lock_holder",
    "LOCK_FILE",
]

#: Name of the metadata file inside a library directory.
METADATA_FILE = "_threadmate.json"
#: Key of the metadata in each part's Arrow schema.
SCHEMA_KEY = b"threadmate"
#: The lock file a sweep holds while it writes (a dot file: pyarrow skips it).
LOCK_FILE = ".threadmate-sweep.lock"
#: Degrees within which a stored configuration is the grid's.
_FIT_TOLERANCE = 1e-6
#: Format tag and version of the metadata.
FORMAT = "threadmate-contact-library"
FORMAT_VERSION = 3
#: The oldest format version a mechanics library is read in: before it, snaps were not
#: proved by screwing in (the ``engaged`` column).
MECHANICS_SINCE = 3
_PART = re.compile(r"^part-(\d{5,})\.parquet$")


def library_schema(metadata: dict[str, Any] | None = None, model: str | None = None) -> pa.Schema:
    """The rows' schema of a library of ``model`` (default: the metadata's, else
    ``mechanics``): the state record, or ``config_id`` + the thesis record + ``error``;
    with ``metadata`` attached under the key ``threadmate``."""
    from ..contact import state_schema, thesis_schema

    if model is None:
        model = (metadata or {}).get("model", "mechanics")
    attached: dict[bytes | str, bytes | str] | None = (
        None
        if metadata is None
        else {SCHEMA_KEY: json_text(part_metadata(metadata), None, sort_keys=True, end="").encode()}
    )
    return state_schema(attached) if model == "mechanics" else thesis_schema(attached)


def part_metadata(metadata: dict[str, Any]) -> dict[str, Any]:
    """The metadata a part carries in its schema: the library's, with the grid's values
    left to :data:`METADATA_FILE` (its shape, size and order stay). A grid of many values
    would otherwise be written into every part."""
    grid = metadata.get("grid")
    if not isinstance(grid, dict) or "roll" not in grid:
        return metadata
    short = {
        "shape": [len(grid.get(a) or ()) for a in ("roll", "pitch", "phase")],
        "values": f"in {METADATA_FILE}",
    }
    short.update({k: grid[k] for k in ("size", "order") if k in grid})
    return {**metadata, "grid": short}


def _check_dir(path: str | os.PathLike[str]) -> Path:
    path = Path(path)
    if not path.exists():
        raise LibraryError(f"no library at {path}: the path does not exist")
    if not path.is_dir():
        raise LibraryError(
            f"{path} is not a library: a library is a directory of Parquet "
            f"parts with {METADATA_FILE}"
        )
    return path


def read_metadata(path: str | os.PathLike[str]) -> dict[str, Any]:
    """The metadata of the library at ``path`` (LibraryError if it is not one)."""
    path = _check_dir(path)
    meta_file = path / METADATA_FILE
    if not meta_file.is_file():
        raise LibraryError(f"{path} is not a threadmate library: it has no {METADATA_FILE}")
    try:
        doc = json.loads(meta_file.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise LibraryError(f"{meta_file} is unreadable or not JSON: {exc}") from None
    if not isinstance(doc, dict) or doc.get("format") != FORMAT:
        raise LibraryError(f"{meta_file} is not threadmate library metadata (no format {FORMAT!r})")
    for key in ("model", "spec", "grid", "mesh", "units", "threadmate_version"):
        if key not in doc:
            raise LibraryError(
                f"{meta_file} lacks the key {key!r} (written by an older "
                "threadmate? sweep it again)"
            )
    if doc["model"] not in MODELS:
        raise LibraryError(f"{meta_file}: unknown model {doc['model']!r}")
    version = doc.get("format_version")
    if not isinstance(version, int) or isinstance(version, bool) or version > FORMAT_VERSION:
        raise LibraryError(
            f"{meta_file}: format version {version!r} is not one this threadmate reads "
            f"(up to {FORMAT_VERSION}; written by a newer threadmate?)"
        )
    if doc["model"] == "mechanics" and version < MECHANICS_SINCE:
        raise LibraryError(
            f"{meta_file}: a mechanics library of format version {version}, written by an "
            "older threadmate whose snaps were not proved by screwing in: sweep it again"
        )
    # The spec and grid every command reads: refuse a hand-edited one here, once.
    from ..contact import Compliance
    from ..geometry import ThreadSpec

    try:
        spec = ThreadSpec.from_dict(doc["spec"])
        grid = read_grid(doc["grid"])
        stated = doc["grid"].get("size")
        if stated is not None and stated != grid.size:
            raise InputError(
                f"key 'grid' lists {grid.size:,} configurations ({grid.describe()}) but "
                f"states a size of {stated!r}: the grid was edited; sweep again into a "
                "new directory"
            )
        mesh = doc["mesh"]
        if not isinstance(mesh, dict) or not isinstance(mesh.get("chord"), int | float):
            raise InputError("key 'mesh' must be a table with the chord")
        if doc["units"] != spec.units:
            raise InputError(f"key 'units' {doc['units']!r} is not the spec's {spec.units!r}")
        if doc["model"] == "mechanics" and "compliance" in doc:
            Compliance.from_dict(doc["compliance"])
    except InputError as exc:
        raise LibraryError(f"{meta_file}: {exc}") from None
    except (KeyError, TypeError, AttributeError, ValueError) as exc:
        raise LibraryError(f"{meta_file}: key 'compliance' is not a compliance ({exc})") from None
    return doc


def write_metadata(path: str | os.PathLike[str], metadata: dict[str, Any]) -> Path:
    """Write the metadata file atomically (creating the directory)."""
    path = Path(path)
    path.mkdir(parents=True, exist_ok=True)
    return atomic_write_text(path / METADATA_FILE, json_text(metadata, sort_keys=True))


def part_files(path: str | os.PathLike[str]) -> list[Path]:
    """The part files of a library, in part order."""
    path = Path(path)
    parts = [p for p in path.iterdir() if _PART.match(p.name)]
    return sorted(parts, key=_part_index)


def _part_index(part: Path) -> int:
    """The number of a part file (one that :func:`part_files` lists)."""
    match = _PART.match(part.name)
    assert match is not None, f"not a part file: {part.name}"
    return int(match.group(1))


def next_part_index(path: str | os.PathLike[str]) -> int:
    """The number of the next part file to write."""
    parts = part_files(path)
    return _part_index(parts[-1]) + 1 if parts else 0


def write_part(path: str | os.PathLike[str], index: int, table: pa.Table) -> Path:
    """Write one chunk of rows as ``part-{index:05d}.parquet``, atomically."""
    target = Path(path) / f"part-{index:05d}.parquet"
    if target.exists():
        raise LibraryError(f"{target} already exists: refusing to overwrite finished rows")
    with atomic_path(target) as tmp:
        pq.write_table(table, tmp, compression="zstd")
    return target


def _check_parts(path: Path, meta: dict[str, Any], parts: list[Path]) -> None:
    """Refuse files that do not belong to the library: Parquet files not named as its
    parts, and parts written for another library (their schema names another id)."""
    strays = sorted(
        p.name for p in path.iterdir() if p.suffix == ".parquet" and not _PART.match(p.name)
    )
    if strays:
        raise LibraryError(
            f"{path / strays[0]} does not belong to the library (its parts "
            "are named part-NNNNN.parquet): move it out of the directory"
        )
    wanted = meta.get("library_id")
    if wanted is None:
        return
    for part in parts:
        try:
            raw = (pq.read_schema(part).metadata or {}).get(SCHEMA_KEY)
            found = json.loads(raw).get("library_id") if raw else None
        except (pa.ArrowInvalid, OSError, ValueError) as exc:
            raise LibraryError(f"{part} is corrupt or not Parquet: {exc}") from None
        if found != wanted:
            raise LibraryError(
                f"{part} does not belong to the library: it was written for "
                "another one (copied in by hand?); move it out of the "
                "directory"
            )


@dataclass(frozen=True)
class _Library:
    """A library opened and checked once: metadata, grid, parts, finished configurations."""

    path: Path
    meta: dict[str, Any]
    grid: AnyGrid
    parts: list[Path]
    dataset: ds.Dataset | None
    done: np.ndarray  # sorted config_ids of the finished configurations


def _open(path: str | os.PathLike[str]) -> _Library:
    """Open a library: its metadata, its parts (each of this library), and the check that
    the rows fit its grid (see :func:`_check_fit`)."""
    path = _check_dir(path)
    meta = read_metadata(path)
    grid = read_grid(meta["grid"])
    parts = part_files(path)
    _check_parts(path, meta, parts)
    dataset = None
    done = np.empty(0, dtype=np.int64)
    if parts:
        try:
            dataset = ds.dataset(
                [str(p) for p in parts], format="parquet", schema=library_schema(meta)
            )
        except (pa.ArrowInvalid, OSError) as exc:
            raise LibraryError(f"{path} holds a corrupt or foreign part: {exc}") from None
        done = _check_fit(path, meta, grid, dataset)
    return _Library(path, meta, grid, parts, dataset, done)


def _table(
    dataset: ds.Dataset,
    path: Path,
    columns: list[str] | None = None,
    filter: ds.Expression | None = None,
) -> pa.Table:
    try:
        return dataset.to_table(columns=columns, filter=filter)
    except (pa.ArrowInvalid, OSError) as exc:
        raise LibraryError(f"{path} holds a corrupt part: {exc}") from None


def _read(
    lib: _Library, columns: list[str] | None = None, filter: ds.Expression | None = None
) -> pa.Table:
    if lib.dataset is None:
        table = library_schema(lib.meta).empty_table()
        return table if columns is None else table.select(columns)
    return _table(lib.dataset, lib.path, columns, filter)


def _corrupt(path: Path, what: str) -> LibraryError:
    return LibraryError(
        f"{path} is corrupt: {what}. Its {METADATA_FILE} or its parts were edited, or "
        "parts were copied in from another library; sweep again into a new directory"
    )


def _check_fit(path: Path, meta: dict[str, Any], grid: AnyGrid, dataset: ds.Dataset) -> np.ndarray:
    """The finished configurations (sorted config_ids), once checked against the grid:
    each number within the grid and held once, its held tilt and phase the grid's, every
    other state of a mechanics library at its start's held tilt."""
    mechanics = meta["model"] == "mechanics"
    names = ["held_roll", "held_pitch"] if mechanics else ["roll", "pitch"]
    columns = ["config_id", *names, "phase"] + (["role"] if mechanics else [])
    rows = _table(dataset, path, columns).to_pandas()
    ids = rows["config_id"].to_numpy(dtype=np.int64)
    outside = (ids < 0) | (ids >= grid.size)
    if outside.any():
        beyond = np.unique(ids[outside])
        raise _corrupt(
            path,
            f"its parts hold {len(beyond)} configuration number(s) beyond the grid "
            f"(first: {int(beyond[0])}), whose {grid.size:,} configurations are "
            f"0..{grid.size - 1} ({grid.describe()})",
        )
    is_start = (rows["role"] == "start").to_numpy() if mechanics else np.ones(len(rows), bool)
    started = ids[is_start]
    done = np.unique(started)
    if len(done) != len(started):
        raise LibraryError(f"{path} holds some configurations twice: it was mixed by hand")
    want = grid.configurations(ids)
    got = rows[[*names, "phase"]].to_numpy(dtype=float)
    tilt_off = np.abs(got[:, :2] - want[:, :2]).max(axis=1) > _FIT_TOLERANCE
    phase_off = np.abs(phase_difference(got[:, 2], want[:, 2])) > _FIT_TOLERANCE
    off = tilt_off | (phase_off & is_start)
    if off.any():
        i = int(np.flatnonzero(off)[0])
        held = "held " if mechanics else ""
        r, p, ph = got[i]
        wr, wp, wph = want[i]
        what = "start" if is_start[i] else "a state"
        at = f"{held}roll {r:g}, pitch {p:g}" + (f", phase {ph:g}" if is_start[i] else "")
        wanted = f"{held}roll {wr:g}, pitch {wp:g}" + (f", phase {wph:g}" if is_start[i] else "")
        raise _corrupt(
            path,
            f"{what} of configuration {int(ids[i])} in its parts is at {at}, where the grid "
            f"of {METADATA_FILE} ({grid.describe()}) puts configuration {int(ids[i])} at "
            f"{wanted}",
        )
    return done


def done_ids(path: str | os.PathLike[str]) -> np.ndarray:
    """Sorted config_ids that the library's parts already hold (checked against the
    grid: :class:`LibraryError` for a corrupt library)."""
    return _open(path).done


def progress(library: str | os.PathLike[str] | pd.DataFrame) -> dict[str, Any]:
    """How far a library's sweep got: ``done`` (finished configurations, i.e. starts),
    ``configurations`` (the grid's) and ``complete``.

    ``library`` is a library directory or rows as :func:`load` gives them (a mechanics
    library's rows count their starts).
    """
    if isinstance(library, pd.DataFrame):
        meta = library.attrs.get("threadmate") or {}
        if "grid" not in meta:
            raise InputError("rows without library metadata (load them with library.load)")
        total = read_grid(meta["grid"]).size
        rows = library[library["role"] == "start"] if "role" in library.columns else library
        done = int(rows["config_id"].nunique())
    else:
        lib = _open(library)
        total, done = lib.grid.size, len(lib.done)
    return {"done": done, "configurations": total, "complete": done >= total}


def load(path: str | os.PathLike[str], columns: list[str] | None = None) -> pd.DataFrame:
    """Every row of a library, sorted by ``config_id`` (then as written).

    Parameters
    ----------
    path : path-like
        The library directory.
    columns : list of str, optional
        Read only these columns (``config_id`` is always read).

    Returns
    -------
    pandas.DataFrame
        The rows (a mechanics library: one per state, the columns of
        ``threadmate.contact.STATE_COLUMNS``; a thesis library: one per configuration);
        ``df.attrs["threadmate"]`` holds the metadata.

    Raises
    ------
    LibraryError
        ``path`` is missing, not a directory, has no metadata or holds corrupt parts.
    """
    lib = _open(path)
    schema = library_schema(lib.meta)
    if columns is not None:
        unknown = [c for c in columns if c not in schema.names]
        if unknown:
            raise LibraryError(f"no column {unknown[0]!r} in a library")
        columns = ["config_id", *[c for c in columns if c != "config_id"]]
    table = _read(lib, columns)
    df = table.to_pandas().sort_values("config_id", kind="stable").reset_index(drop=True)
    df.attrs["threadmate"] = lib.meta
    return df


def _counts(values: pd.Series | np.ndarray) -> dict[str, int]:
    s = pd.Series(values).value_counts()
    return {str(k): int(v) for k, v in s.items()}


def _starts(
    lib: _Library,
    columns: list[str] | None = None,
    filter: ds.Expression | None = None,
) -> pa.Table:
    """One row per finished configuration: the thesis's rows, or the mechanics' starts."""
    if lib.meta["model"] == "mechanics":
        start = ds.field("role") == "start"
        filter = start if filter is None else (start & filter)
    return _read(lib, columns, filter)


def info(path: str | os.PathLike[str]) -> dict[str, Any]:
    """What a library holds, without loading its rows.

    Returns
    -------
    dict
        ``path``, ``model``, ``metadata``, ``configurations`` (grid size), ``done``,
        ``complete``, ``sweeping`` (the process id, host and start time of the sweep that
        holds the library's lock, None when no sweep runs), ``parts``,
        ``classifications`` (counts over the finished configurations: the thesis's rows,
        or the rest states the mechanics' drops reach), ``states`` (mechanics: counts of
        all states by role and by class) and ``grid`` (a one-line description).

    Raises
    ------
    LibraryError
        Not a library, or a corrupt one (rows that do not fit its grid).
    """
    lib = _open(path)
    path, meta, grid = lib.path, lib.meta, lib.grid
    done, classes, states = 0, {}, {}
    if lib.parts:
        table = _starts(lib, ["config_id", "classification"])
        done = table.num_rows
        classes = _counts(table.column("classification").to_numpy(zero_copy_only=False))
        if meta["model"] == "mechanics":
            every = _read(lib, ["role", "classification"]).to_pandas()
            states = {
                "total": len(every),
                "by_role": _counts(every["role"]),
                "by_class": _counts(every["classification"]),
            }
    return {
        "path": str(path),
        "model": meta["model"],
        "units": meta["units"],
        "grid": grid.describe(),
        "configurations": grid.size,
        "done": done,
        "complete": done == grid.size,
        "sweeping": lock_holder(path),
        "parts": len(lib.parts),
        "classifications": classes,
        "states": states,
        "metadata": meta,
    }


def configurations(library: str | os.PathLike[str] | pd.DataFrame) -> pd.DataFrame:
    """One row per finished configuration, in either model: ``config_id``, ``roll``,
    ``pitch``, ``phase`` (the configuration: held tilt and start phase, degrees),
    ``classification``, ``n_contacts``, ``region_combination`` (of the thesis's last stage,
    or of the rest state the mechanics' drop reaches).

    ``library`` is a library directory or rows as :func:`load` gives them.
    """
    df = library if isinstance(library, pd.DataFrame) else load(library)
    if "role" in df.columns:
        meta = df.attrs.get("threadmate")
        df = (
            df[df["role"] == "start"]
            .drop(columns=["roll", "pitch"], errors="ignore")
            .rename(columns={"held_roll": "roll", "held_pitch": "pitch"})
        )
        df.attrs["threadmate"] = meta
    cols = [
        "config_id",
        "roll",
        "pitch",
        "phase",
        "classification",
        "n_contacts",
        "region_combination",
    ]
    out = df[[c for c in cols if c in df.columns]].reset_index(drop=True)
    out.attrs = dict(df.attrs)
    return out


def query(
    path: str | os.PathLike[str], roll: float, pitch: float, phase: float, *, nearest: bool = False
) -> dict[str, Any]:
    """The stored contact state of a configuration, without recomputing.

    Parameters
    ----------
    path : path-like
        The library directory.
    roll, pitch, phase : float
        The configuration asked for (degrees; phase modulo 360).
    nearest : bool
        Take the nearest grid configuration when the request is off the grid (else
        :class:`~threadmate.InputError` naming the nearest).

    Returns
    -------
    dict
        ``requested`` and ``grid`` (roll, pitch, phase), ``moved_to_grid`` (True when the
        grid state differs from the request), ``config_id``, ``units``, ``model``, ``computed``
        (False when an unfinished sweep has not reached it yet) and ``record`` (the
        thesis's row, or the rest state the mechanics' drop reaches; None if not computed).
    """
    lib = _open(path)
    meta = lib.meta
    cid, on_grid, moved = lib.grid.locate(roll, pitch, phase, nearest=nearest)
    record = None
    if lib.parts:
        rows = _starts(lib, filter=ds.field("config_id") == cid).to_pylist()
        record = rows[0] if rows else None
    return {
        "requested": {"roll": float(roll), "pitch": float(pitch), "phase": float(phase)},
        "grid": {"roll": on_grid[0], "pitch": on_grid[1], "phase": on_grid[2]},
        "moved_to_grid": moved,
        "config_id": cid,
        "units": meta["units"],
        "model": meta["model"],
        "computed": record is not None,
        "record": record,
    }


#: Metadata entries that must agree for two libraries (or a library and a request) to
#: hold comparable rows, with the words used to name a difference.
_IDENTITY = (
    (("model",), "model"),
    (("spec",), "spec"),
    (("grid", "kind"), "grid kind (roll/pitch or polar)"),
    (("grid", "roll"), "grid roll values"),
    (("grid", "pitch"), "grid pitch values"),
    (("grid", "tilt"), "grid tilt sizes"),
    (("grid", "direction"), "grid directions"),
    (("grid", "phase"), "grid phase values"),
    (("mesh", "chord"), "mesh chord tolerance"),
    (("mesh", "bolt"), "bolt mesh"),
    (("mesh", "nut"), "nut mesh"),
    (("contact", "compliance_z"), "compliance centre (compliance_z)"),
    (("contact", "analyzer"), "contact analyser"),
    (("compliance",), "compliance (force, stiffness, lateral stiffness, friction, centre)"),
    (("continuation",), "continuation settings"),
    (("threadmate_version",), "threadmate version"),
)


def _get(doc: dict[str, Any], keys: tuple[str, ...]) -> Any:
    for k in keys:
        if not isinstance(doc, dict) or k not in doc:
            return None
        doc = doc[k]
    return doc


def _same(a: Any, b: Any) -> bool:
    if (
        isinstance(a, float | int)
        and isinstance(b, float | int)
        and not isinstance(a, bool)
        and not isinstance(b, bool)
    ):
        return math.isclose(a, b, rel_tol=1e-12, abs_tol=1e-15)
    if isinstance(a, list | tuple) and isinstance(b, list | tuple):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    return a == b


def compare_metadata(a: dict[str, Any], b: dict[str, Any]) -> list[str]:
    """What differs between two libraries' metadata in the entries that decide their rows
    (spec values, grid, chord, compliance centre, analyser, version); empty when they
    agree."""
    out = []
    for keys, words in _IDENTITY:
        va, vb = _get(a, keys), _get(b, keys)
        if keys == ("spec",) and isinstance(va, dict) and isinstance(vb, dict):
            # The designation text names a spec; the values decide the rows.
            va = {k: v for k, v in va.items() if k != "designation"}
            vb = {k: v for k, v in vb.items() if k != "designation"}
        if keys in (("mesh", "bolt"), ("mesh", "nut")):
            # A mesh from CAD is its content and units (a renamed file is the same mesh);
            # an older library, or a generated mesh, has none.
            ma, mb = _mesh_identity(va), _mesh_identity(vb)
            if (ma and ma[:2]) != (mb and mb[:2]):
                out.append(f"{words} ({_mesh_words(ma)} vs {_mesh_words(mb)})")
            continue
        if not _same(va, vb):
            if keys == ("spec",) and isinstance(va, dict) and isinstance(vb, dict):
                diff = sorted(_flat_diff(va, vb))
                out.append(f"spec ({', '.join(diff)})")
            elif keys[0] == "grid":
                out.append(f"{words} ({_short(va)} vs {_short(vb)})")
            else:
                out.append(f"{words} ({va!r} vs {vb!r})")
    return out


def _mesh_identity(v: Any) -> tuple[Any, Any, Any] | None:
    """What decides a CAD mesh's rows: its SHA-256 and units (and its name, to say so)."""
    if not isinstance(v, dict) or not v.get("sha256"):
        return None
    return (v.get("sha256"), v.get("units"), v.get("file"))


def _mesh_words(v: tuple[Any, Any, Any] | None) -> str:
    if v is None:
        return "generated"
    sha, units, name = v
    return f"{name}, sha256 {str(sha)[:12]}, units {units}"


def _short(v: Any) -> str:
    if isinstance(v, list) and len(v) > 4:
        return f"{len(v)} values {v[0]:g}..{v[-1]:g}"
    return repr(v)


def _flat_diff(a: dict[str, Any], b: dict[str, Any], prefix: str = "") -> list[str]:
    out = []
    for k in sorted(set(a) | set(b)):
        va, vb = a.get(k), b.get(k)
        if isinstance(va, dict) and isinstance(vb, dict):
            out += _flat_diff(va, vb, f"{prefix}{k}.")
        elif not _same(va, vb):
            out.append(f"{prefix}{k}: {va!r} vs {vb!r}")
    return out


# -- the sweep's lock ---------------------------------------------------------------------
#: Lock file descriptors this process holds (a forked pool worker closes its copies).
_HELD: set[int] = set()


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's process: it exists
        return True
    except OSError:
        return False
    return True


def lock_holder(path: str | os.PathLike[str]) -> dict[str, Any] | None:
    """The sweep that holds the library's lock: ``pid``, ``host`` and ``started`` (None
    when the lock file is absent, unreadable, or names a process of this host that no
    longer runs: a sweep that was killed)."""
    try:
        doc = json.loads((Path(path) / LOCK_FILE).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError):
        return None
    if not isinstance(doc, dict) or not isinstance(doc.get("pid"), int):
        return None
    if doc.get("host") == socket.gethostname() and not _alive(doc["pid"]):
        return None
    return {k: doc.get(k) for k in ("pid", "host", "started")}


def _holder_words(path: Path) -> str:
    doc = lock_holder(path)
    if doc is None:
        return "another process"
    return f"process {doc['pid']} on {doc['host']} (since {doc['started']})"


def _refuse_locked(path: Path) -> LibraryError:
    return LibraryError(
        f"{path} is being swept by {_holder_words(path)}: one sweep writes a library at a "
        "time. Wait for it to finish (or stop it), then run this sweep again to resume"
    )


@contextlib.contextmanager
def sweep_lock(path: str | os.PathLike[str]) -> Iterator[Path]:
    """Hold the library's lock while a sweep writes it (the directory must exist).

    The lock is :data:`LOCK_FILE` in the library, locked with ``fcntl.flock`` and holding
    this process's id, host and start time. The operating system releases it when the
    process ends, however it ends: the file a killed sweep leaves does not block the next.
    A second sweep is refused at once with :class:`LibraryError` naming the holder.
    """
    path = Path(path)
    lock = path / LOCK_FILE
    try:
        import fcntl
    except ImportError:  # not POSIX: a file created exclusively, stale if its process died
        fcntl = None  # type: ignore[assignment]
    for _ in range(10):
        if fcntl is None:
            try:
                fd = os.open(lock, os.O_RDWR | os.O_CREAT | os.O_EXCL, 0o644)
            except FileExistsError:
                if lock_holder(path) is not None:
                    raise _refuse_locked(path) from None
                with contextlib.suppress(FileNotFoundError):
                    lock.unlink()  # left by a sweep that was killed
                continue
            except OSError as exc:
                raise LibraryError(
                    f"cannot lock the library at {path}: {exc.strerror or exc}"
                ) from None
        else:
            try:
                fd = os.open(lock, os.O_RDWR | os.O_CREAT | getattr(os, "O_CLOEXEC", 0), 0o644)
            except OSError as exc:
                raise LibraryError(
                    f"cannot lock the library at {path}: {exc.strerror or exc}"
                ) from None
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                os.close(fd)
                raise _refuse_locked(path) from None
            # The holder before us removes the file as it lets go: lock the file that is
            # there now, not one already unlinked.
            try:
                same = os.path.samestat(os.fstat(fd), os.stat(lock))
            except FileNotFoundError:
                same = False
            if not same:
                os.close(fd)
                continue
        break
    else:
        raise LibraryError(f"cannot take the lock {lock}: it keeps changing hands")
    _HELD.add(fd)
    try:
        doc = {
            "pid": os.getpid(),
            "host": socket.gethostname(),
            "started": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        }
        os.ftruncate(fd, 0)
        os.pwrite(fd, json_text(doc, None).encode(), 0)
        yield lock
    finally:
        _HELD.discard(fd)
        with contextlib.suppress(FileNotFoundError):
            lock.unlink()  # before letting go, so that no one locks a removed file
        os.close(fd)


def release_inherited_locks() -> None:
    """In a process forked from a sweep: close the copies of its lock files (the lock
    stays the sweep's, and ends with it rather than with this process)."""
    for fd in list(_HELD):
        with contextlib.suppress(OSError):
            os.close(fd)
    _HELD.clear()
