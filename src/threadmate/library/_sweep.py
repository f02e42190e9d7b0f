"""The sweep: every configuration of a grid through the mechanics (or the thesis's stages),
in chunks, to disk.

Work goes out in chunks of consecutive ``config_id``: for the mechanics one chunk is one
held tilt with all its phases (the continuations of its starts join each other), for the
thesis's model a run of configurations. The chunks run where an executor puts them
(:mod:`._executors`: this process, a process pool or Dask), each in a worker that keeps
its model between chunks (:mod:`._workers`). Each finished chunk is written at once as its
own Parquet part (temporary name, then rename), so an interrupted sweep loses at most the
chunks in flight, and running the same request again computes only the configurations
that no part holds yet; the library's metadata says which request it holds
(:mod:`._metadata`).
"""

from __future__ import annotations

import contextlib
import math
import os
import shutil
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pyarrow as pa

from .._errors import InputError, LibraryError, ThreadmateError
from .._system import cpu_count
from .._validate import check_max_faces, check_starts, check_whole
from ..contact import (
    CONTINUATION_STEP,
    PHASE_TOLERANCE,
    Compliance,
    check_continuation,
)
from ..geometry import ThreadSpec, check_chord
from ._executors import check_execution, lost_errors, open_executor
from ._grid import Values, make_grid
from ._metadata import open_library, record_settings
from ._models import check_model
from ._store import (
    METADATA_FILE,
    done_ids,
    library_schema,
    load,
    next_part_index,
    sweep_lock,
    write_metadata,
    write_part,
)
from ._workers import Job, mesh_files

__all__ = ["sweep", "write_library", "SweepInterrupted", "ProgressCallback"]

#: ``progress(done, total)``: configurations finished (resumed ones included) and the
#: grid's size, called once before any work and after every chunk.
ProgressCallback = Callable[[int, int], None]


class SweepInterrupted(ThreadmateError):
    """A sweep stopped before the end (a worker died, the cluster was lost).

    Every finished chunk is saved: run the same sweep again to resume.
    """


def _chunks(ids: np.ndarray, size: int) -> Iterator[list[int]]:
    for start in range(0, len(ids), size):
        yield [int(i) for i in ids[start : start + size]]


def _tilt_chunks(ids: np.ndarray, n_phase: int) -> Iterator[list[int]]:
    """One chunk per held tilt (ids are roll-major, phase fastest)."""
    tilts = ids // n_phase
    for t in np.unique(tilts):
        yield [int(i) for i in ids[tilts == t]]


# -- the sweep ----------------------------------------------------------------------------
def sweep(
    spec: ThreadSpec,
    roll: Values = None,
    pitch: Values = None,
    phase: Values = None,
    *,
    out: str | os.PathLike[str] | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
    chunk_size: int | None = None,
    chord: float | None = None,
    model: str = "mechanics",
    compliance: Compliance | None = None,
    step: float = CONTINUATION_STEP,
    phase_tolerance: float = PHASE_TOLERANCE,
    progress: ProgressCallback | None = None,
    max_chunks: int | None = None,
    analyzer: Callable[..., Any] | None = None,
    bolt_mesh: str | os.PathLike[str] | None = None,
    nut_mesh: str | os.PathLike[str] | None = None,
    mesh_units: str | None = None,
    clockwise: bool = False,
    max_starts: int | None = None,
    max_faces: int | None = None,
    tilt: Values = None,
    direction: Values = None,
) -> Path | pd.DataFrame:
    """Build (or resume) the contact-state library of a thread pair over a grid.

    With the ``mechanics`` model (the default) every configuration is a start: a held tilt
    and a phase where the bolt is dropped. The library holds the rest state each start
    reaches, the unstable states passed on the way, and the counter-clockwise search
    continued from it grid phase by grid phase (jumps and the snap located between grid
    phases), each state with its passive transition (``threadmate.contact.STATE_COLUMNS``).
    With the ``thesis`` model it holds the thesis's fixed-pivot procedure per
    configuration, with the thesis's classes.

    Parameters
    ----------
    spec : ThreadSpec
        The thread pair.
    roll, pitch, phase : str, float, sequence of float or None
        Grid values in degrees (see :func:`parse_range`); None takes the thesis's values
        (roll and pitch -4..4 by 1, phase 0..355 by 5: 5,832 configurations).
    out : path-like, optional
        Library directory. Created if missing; if it already holds a library of the same
        request, the sweep resumes (only configurations no part holds are computed); a
        library of a different spec, grid or setting is refused with :class:`LibraryError`.
        Without ``out`` the sweep runs in a temporary directory and returns the rows.
    workers : int, optional
        Worker processes (default: the CPUs available). ``1`` runs in this process.
    scheduler : str, optional
        ``"local"`` starts a Dask LocalCluster of ``workers``; an address such as
        ``"tcp://host:8786"`` connects to a running Dask scheduler; ``"pool"`` forces the
        process pool. Default: Dask's ``scheduler-address`` setting (env
        ``DASK_SCHEDULER_ADDRESS``) if set, else the process pool. Dask is optional
        (``pip install threadmate[dask]``).
    chunk_size : int, optional
        Thesis model: configurations per chunk (one Parquet part each; default about 16
        chunks per worker, 4 to 256 configurations each). The mechanics' chunk is always
        one held tilt.
    chord : float, optional
        Chord tolerance of the meshes (spec units; default that of
        :mod:`threadmate.geometry`), within the range the meshes accept
        (:func:`threadmate.geometry.check_chord`).
    model : {"mechanics", "thesis"}
        What each configuration runs through (see above).
    compliance : Compliance, optional
        Load, stiffness, lateral stiffness, friction and compliance centre (default
        :class:`~threadmate.contact.Compliance()`); stored in the metadata, and a resumed
        sweep with other values is refused. The thesis's model uses only the centre.
    step, phase_tolerance : float
        Mechanics: the continuation's step and how closely jumps and the snap are located
        (degrees; as :func:`threadmate.contact.search`).
    progress : callable, optional
        ``progress(done, total)`` after each chunk (see :data:`ProgressCallback`).
    max_chunks : int, optional
        Stop after writing this many chunks (the library stays resumable).
    analyzer : callable, optional
        Thesis model: ``analyzer(spec, chord=..., compliance_z=...)`` builds the analyser
        in each worker (default :class:`threadmate.contact.ContactAnalyzer`); it must pickle
        (a module-level class or a :func:`functools.partial` of one). Recorded in the
        metadata.
    bolt_mesh, nut_mesh : path-like, optional
        Mesh files from CAD instead of generated meshes (see
        :class:`~threadmate.contact.ContactAnalyzer`): validated here, then loaded once by
        each worker. Their file names, SHA-256 and units are recorded in the metadata; a
        resumed sweep with other meshes (or none) is refused.
    mesh_units : {"in", "mm"}, optional
        Units of the mesh files (default: a threadmate STL header's, else the spec's).
    clockwise : bool
        Mechanics: also turn every start clockwise directly (:func:`threadmate.contact.
        screw`, one turn) and record what it does on the start's row (``clockwise``:
        engaged, riding or jammed; ``clockwise_phase``: where it is decided).
    max_starts : int, optional
        Most configurations the grid may hold (default
        ``threadmate._validate.MAX_STARTS``, 100,000; at most 10,000,000). A larger grid is
        refused, before anything is allocated or written, with its count and an estimate
        of the time it would take.
    max_faces : int, optional
        Most triangles a mesh from CAD may have (default
        ``threadmate._validate.MAX_FACES``; see :func:`threadmate.geometry.load_mesh`).
    tilt, direction : str, float, sequence of float or None
        A polar grid of misalignment instead of roll and pitch (:class:`PolarGrid`): held
        tilt sizes (degrees, 0 to ``MAX_TILT``) and the directions toward which the bolt
        leans (degrees, azimuth in F from +X toward +Y, modulo 360); either one given makes
        the grid polar (the other takes :data:`DEFAULT_POLAR_RANGES`). Not with ``roll``
        or ``pitch``.

    Returns
    -------
    pathlib.Path or pandas.DataFrame
        The library directory; or, without ``out``, its rows as :func:`load` gives them.

    Raises
    ------
    InputError
        Bad grid, worker count, chord or scheduler, a grid past ``max_starts``, a step
        finer than a search takes (``LibraryError`` for a library that disagrees with the
        request, or that another sweep is writing).
    SweepInterrupted
        A worker or the cluster was lost; finished chunks are saved, run again to resume.
    """
    if not isinstance(spec, ThreadSpec):
        raise InputError(f"spec must be a ThreadSpec, got {type(spec).__name__}")
    model = check_model(model)
    grid = make_grid(roll, pitch, phase, tilt, direction)
    check_execution(workers, scheduler)
    n_workers = workers or cpu_count()
    what = grid.describe(size=False)
    check_starts(grid.size, max_starts, model=model, workers=n_workers, what=what)
    # The meshes' own check, before anything is written.
    chord = check_chord(spec, chord)
    if compliance is None:
        compliance = Compliance()
    if not isinstance(compliance, Compliance):
        raise InputError(f"compliance must be a Compliance, got {type(compliance).__name__}")
    compliance.check_for(spec.pitch)  # here, not first in a worker after the library exists
    # One start's continuation over a turn (its steps counted too).
    check_continuation(step=step, phase_tolerance=phase_tolerance)
    for name, value in (("chunk_size", chunk_size), ("max_chunks", max_chunks)):
        if value is not None:
            check_whole(name, value)
    if model == "mechanics" and analyzer is not None:
        raise InputError("analyzer is for the thesis's model only")
    max_faces = check_max_faces(max_faces)
    bolt_file, nut_file = mesh_files(spec, bolt_mesh, nut_mesh, mesh_units, max_faces)
    job = Job(
        spec,
        grid,
        float(chord),
        model,
        compliance,
        float(step),
        float(phase_tolerance),
        analyzer,
        bolt_file,
        nut_file,
        mesh_units,
        bool(clockwise),
        max_faces=max_faces,
    )

    if out is None:
        tmp = Path(tempfile.mkdtemp(prefix="threadmate-sweep-"))
        try:
            _run(job, tmp / "library", workers, scheduler, chunk_size, progress, max_chunks)
            return load(tmp / "library")
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
    out = Path(out)
    _run(job, out, workers, scheduler, chunk_size, progress, max_chunks)
    return out


def write_library(
    records: pd.DataFrame | list[dict[str, Any]],
    out: str | os.PathLike[str],
    spec: ThreadSpec,
    roll: Values = None,
    pitch: Values = None,
    phase: Values = None,
    *,
    model: str = "mechanics",
    compliance: Compliance | None = None,
    chord: float | None = None,
    step: float = CONTINUATION_STEP,
    phase_tolerance: float = PHASE_TOLERANCE,
    rows_per_part: int = 500_000,
    tilt: Values = None,
    direction: Values = None,
) -> Path:
    """Write a library from rows computed elsewhere (a study, a benchmark, a test).

    The library is what :func:`sweep` with the same arguments would write around the same
    rows: metadata for the request, the rows in the model's schema (the record contract of
    :mod:`threadmate.contact`) as Parquet parts. Rows are not checked against the
    mechanics; they must carry every column of the schema.

    Parameters
    ----------
    records : pandas.DataFrame or list of dict
        Rows with the columns of ``STATE_COLUMNS`` (mechanics) or of ``thesis_schema``.
    out : path-like
        A new or empty directory (or a library of the same request, to add parts to).
    spec, roll, pitch, phase, tilt, direction, model, compliance, chord, step, phase_tolerance
        As :func:`sweep`: they go into the metadata.
    rows_per_part : int
        Rows per Parquet part.

    Returns
    -------
    pathlib.Path
        The library directory.
    """
    if not isinstance(spec, ThreadSpec):
        raise InputError(f"spec must be a ThreadSpec, got {type(spec).__name__}")
    model = check_model(model)
    job = Job(
        spec,
        make_grid(roll, pitch, phase, tilt, direction),
        check_chord(spec, chord),
        model,
        compliance or Compliance(),
        float(step),
        float(phase_tolerance),
    )
    schema = library_schema(model=model)
    frame = pd.DataFrame(records) if not isinstance(records, pd.DataFrame) else records
    missing = [n for n in schema.names if n not in frame.columns]
    if missing:
        raise InputError(f"records lack the column {missing[0]!r} of the {model} schema")
    try:
        table = pa.Table.from_pandas(frame[schema.names], schema=schema, preserve_index=False)
    except (pa.ArrowInvalid, pa.ArrowTypeError) as exc:
        raise InputError(f"records do not fit the {model} schema: {exc}") from None
    out = Path(out)
    with _locked(out):
        meta = open_library(out, job)
        part = next_part_index(out)
        with_meta = table.replace_schema_metadata(library_schema(meta).metadata)
        for start in range(0, max(table.num_rows, 1), rows_per_part):
            write_part(out, part, with_meta.slice(start, rows_per_part))
            part += 1
    return out


@contextlib.contextmanager
def _locked(out: Path) -> Iterator[None]:
    """Create the library directory if it is missing and hold its lock (one sweep writes a
    library at a time); a directory created here that is left empty (a request refused
    before its first write) is removed."""
    if out.exists() and not out.is_dir():
        raise LibraryError(f"{out} exists and is not a directory: give a library directory")
    created = not out.exists()
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise LibraryError(f"cannot create the library at {out}: {exc.strerror or exc}") from None
    try:
        with sweep_lock(out):
            yield
    finally:
        if created:
            with contextlib.suppress(OSError):
                out.rmdir()  # only if empty


def _run(
    job: Job,
    out: Path,
    workers: int | None,
    scheduler: str | None,
    chunk_size: int | None,
    progress: ProgressCallback | None,
    max_chunks: int | None,
) -> None:
    existed = out.exists()
    with _locked(out):
        _run_locked(job, out, existed, workers, scheduler, chunk_size, progress, max_chunks)


def _run_locked(
    job: Job,
    out: Path,
    existed: bool,
    workers: int | None,
    scheduler: str | None,
    chunk_size: int | None,
    progress: ProgressCallback | None,
    max_chunks: int | None,
) -> None:
    meta = open_library(out, job)
    total = job.grid.size
    done = done_ids(out)
    todo = np.setdiff1d(np.arange(total, dtype=np.int64), done, assume_unique=True)
    n_done = total - len(todo)
    if len(todo) == 0:
        if progress is not None:
            progress(n_done, total)
        return
    try:
        executor = open_executor(workers, scheduler)
    except BaseException:
        if not existed:  # leave nothing behind for a request that never started
            (out / METADATA_FILE).unlink(missing_ok=True)  # the directory goes with the lock
        raise
    if progress is not None:
        progress(n_done, total)
    if job.model == "mechanics":
        chunks = _tilt_chunks(todo, len(job.grid.phase))
    else:
        if chunk_size is None:
            chunk_size = int(min(256, max(4, math.ceil(len(todo) / (16 * executor.slots)))))
        chunks = _chunks(todo, chunk_size)
    part = next_part_index(out)
    cancel = True
    try:
        cancel = not _loop(
            job, out, executor, chunks, meta, part, n_done, total, progress, max_chunks
        )
    except lost_errors() as exc:
        n_saved = len(done_ids(out))
        raise SweepInterrupted(
            f"the sweep stopped: a worker or the cluster was lost ({type(exc).__name__}: "
            f"{exc}). {n_saved} of {total} configurations are saved in {out}; run the same "
            "sweep again to resume."
        ) from exc
    finally:
        executor.close(cancel=cancel)


def _loop(
    job: Job,
    out: Path,
    executor: Any,
    chunks: Iterator[list[int]],
    meta: dict[str, Any],
    part: int,
    n_done: int,
    total: int,
    progress: ProgressCallback | None,
    max_chunks: int | None,
) -> bool:
    """Keep a bounded window of chunks in flight (results stream to disk, memory stays
    flat) and write each chunk as it completes; False if stopped at ``max_chunks``."""
    in_flight: set[Any] = set()
    for ids in chunks:
        in_flight.add(executor.submit(job, ids))
        if len(in_flight) >= executor.window:
            break
    written = 0

    def save(fut: Any) -> None:
        nonlocal part, written, n_done
        table, settings = fut.result()
        if record_settings(meta, settings, job.chord):
            # The first result tells what the workers' models actually used.
            write_metadata(out, meta)
        write_part(out, part, table.replace_schema_metadata(library_schema(meta).metadata))
        part += 1
        written += 1
        n_done += len(np.unique(table.column("config_id").to_numpy()))
        if progress is not None:
            progress(n_done, total)

    while in_flight:
        finished = executor.wait_first(in_flight)
        in_flight -= finished
        failed = [f for f in finished if f.exception() is not None]
        for fut in (f for f in finished if f.exception() is None):
            save(fut)
            if max_chunks is not None and written >= max_chunks:
                return False
        if failed:
            # Save every chunk that did finish before reporting a lost worker or cluster.
            for fut in [f for f in in_flight if f.done() and f.exception() is None]:
                save(fut)
            failed[0].result()  # raises the worker's or the cluster's error
        for _ in range(len(finished)):
            nxt = next(chunks, None)
            if nxt is not None:
                in_flight.add(executor.submit(job, nxt))
    return True
