"""The sweep: every configuration of a grid through the contact stages, in chunks, to disk.

Work goes out in chunks of consecutive ``config_id``. Each worker process (or Dask
worker thread) builds ONE contact analyser, meshes and python-fcl BVHs included, the
first time it sees a job, and keeps it for every later chunk: fcl objects neither pickle
nor share between threads. Each finished chunk is written at once as its own Parquet part
(temporary name, then rename), so an interrupted sweep loses at most the chunks in
flight, and running the same request again computes only the configurations that no part
holds yet.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import datetime as _dt
import functools
import math
import os
import shutil
import tempfile
import threading
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pyarrow as pa

from .._errors import InputError, LibraryError, ThreadmateError
from .._version import __version__
from ..geometry import ThreadSpec
from ._grid import Grid, Values
from ._store import (
    FORMAT,
    FORMAT_VERSION,
    METADATA_FILE,
    compare_metadata,
    done_ids,
    library_schema,
    load,
    next_part_index,
    read_metadata,
    remove_stale_temporaries,
    write_metadata,
    write_part,
)

__all__ = ["sweep", "SweepInterrupted", "ProgressCallback"]

#: ``progress(done, total)``: configurations finished (resumed ones included) and the
#: grid's size, called once before any work and after every chunk.
ProgressCallback = Callable[[int, int], None]

_DASK_HINT = "pip install threadmate[dask]"


class SweepInterrupted(ThreadmateError):
    """A sweep stopped before the end (a worker died, the cluster was lost).

    Every finished chunk is saved: run the same sweep again to resume.
    """


# -- the work, as run in a worker ---------------------------------------------------------
@dataclass(frozen=True)
class Job:
    """Everything a worker needs to analyse configurations of one sweep (small, picklable)."""

    spec: ThreadSpec
    grid: Grid
    chord: float
    compliance_z: float
    analyzer: Callable[..., Any] | None = None

    @property
    def key(self) -> str:
        return repr((self.spec, self.grid, self.chord, self.compliance_z,
                     _describe_analyzer(self.analyzer)))


_LOCAL = threading.local()


def _analyzer_for(job: Job) -> Any:
    """This worker's analyser for ``job``, built on first use and kept."""
    if getattr(_LOCAL, "key", None) != job.key:
        _LOCAL.analyzer = None  # free the old meshes before building new ones
        factory = job.analyzer
        if factory is None:
            from ..contact import ContactAnalyzer as factory
        _LOCAL.analyzer = factory(job.spec, chord=job.chord, compliance_z=job.compliance_z)
        _LOCAL.key = job.key
    return _LOCAL.analyzer


def _settings(analyzer: Any) -> dict[str, Any]:
    """The mesh and contact settings an analyser actually used (for the metadata)."""
    tolerances = getattr(analyzer, "tolerances", None)
    deviation = getattr(analyzer, "deviation", None)
    return {
        "chord": getattr(analyzer, "chord", None),
        "max_deviation": None if deviation is None else float(deviation),
        "tolerances": None if tolerances is None else {k: float(v)
                                                        for k, v in tolerances.items()},
    }


def _blank_record(schema: pa.Schema) -> dict[str, Any]:
    """Missing values per the record contract: NaN, 0, False, ""."""
    out: dict[str, Any] = {}
    for f in schema:
        if pa.types.is_floating(f.type):
            out[f.name] = math.nan
        elif pa.types.is_integer(f.type):
            out[f.name] = 0
        elif pa.types.is_boolean(f.type):
            out[f.name] = False
        else:
            out[f.name] = ""
    return out


def run_chunk(job: Job, config_ids: list[int]) -> tuple[pa.Table, dict[str, Any]]:
    """Analyse configurations in this process; a configuration that raises becomes a row
    with classification ``error`` and the message in ``error``.

    Returns
    -------
    table : pyarrow.Table
        Rows in the library schema (without metadata), in ``config_ids`` order.
    settings : dict
        The analyser's chord, mesh deviation and tolerances.
    """
    analyzer = _analyzer_for(job)
    schema = library_schema()
    blank = _blank_record(schema)
    rows = []
    for cid, (roll, pitch, phase) in zip(config_ids, job.grid.configurations(config_ids),
                                         strict=True):
        try:
            rec = analyzer.analyze(float(roll), float(pitch), float(phase)).to_record()
            rec["error"] = ""
        except Exception as exc:  # noqa: BLE001 - one bad configuration must not stop a sweep
            rec = dict(blank, roll=float(roll), pitch=float(pitch), phase=float(phase),
                       classification="error", error=f"{type(exc).__name__}: {exc}")
        rec["config_id"] = int(cid)
        rows.append(rec)
    return pa.Table.from_pylist(rows, schema=schema), _settings(analyzer)


# -- executors ----------------------------------------------------------------------------
class _InProcess:
    """Runs chunks in this process, one at a time (``workers=1``: no pool to start)."""

    slots = 1
    window = 1
    description = "this process"

    def submit(self, job: Job, ids: list[int]) -> cf.Future:
        fut: cf.Future = cf.Future()
        fut.set_result(run_chunk(job, ids))
        return fut

    def wait_first(self, futures: set[Any]) -> set[Any]:
        return set(futures)

    def close(self, cancel: bool) -> None:
        pass


class _Pool:
    """A local process pool; each process keeps its own analyser."""

    def __init__(self, workers: int) -> None:
        self.slots = workers
        self.window = 2 * workers
        self.description = f"process pool of {workers}"
        self.pool = cf.ProcessPoolExecutor(max_workers=workers)

    def submit(self, job: Job, ids: list[int]) -> cf.Future:
        return self.pool.submit(run_chunk, job, ids)

    def wait_first(self, futures: set[Any]) -> set[Any]:
        done, _ = cf.wait(futures, return_when=cf.FIRST_COMPLETED)
        return done

    def close(self, cancel: bool) -> None:
        if cancel:
            # Chunks still running would only be thrown away: stop their processes now
            # (the pool keeps them in a private mapping; without it they finish and exit).
            processes = dict(getattr(self.pool, "_processes", None) or {})
            self.pool.shutdown(wait=False, cancel_futures=True)
            for proc in processes.values():
                with contextlib.suppress(Exception):
                    proc.terminate()
            for proc in processes.values():
                with contextlib.suppress(Exception):
                    proc.join(timeout=5)
        else:
            self.pool.shutdown(wait=True)


class _Dask:
    """A Dask distributed client: an existing scheduler, or a LocalCluster it starts."""

    def __init__(self, address: str, workers: int | None) -> None:
        try:
            import distributed
        except ImportError:
            raise InputError(f"--scheduler {address} needs Dask distributed, which is not "
                             f"installed: {_DASK_HINT}") from None
        self._distributed = distributed
        self.cluster = None
        try:
            if address == "local":
                n = workers or _cpu_count()
                self.cluster = distributed.LocalCluster(
                    n_workers=n, threads_per_worker=1, processes=True,
                    dashboard_address=None)
                self.client = distributed.Client(self.cluster)
                self.description = f"Dask LocalCluster of {n}"
            else:
                self.client = distributed.Client(address, timeout="10s")
                self.description = f"Dask scheduler {address}"
        except (OSError, TimeoutError) as exc:
            if self.cluster is not None:
                self.cluster.close()
            raise InputError(f"cannot reach the Dask scheduler at {address}: {exc}") from None
        threads = sum(self.client.nthreads().values())
        self.slots = max(1, threads)
        self.window = 2 * self.slots

    def submit(self, job: Job, ids: list[int]) -> Any:
        return self.client.submit(run_chunk, job, ids, pure=False)

    def wait_first(self, futures: set[Any]) -> set[Any]:
        done = self._distributed.wait(list(futures), return_when="FIRST_COMPLETED").done
        return set(done)

    def close(self, cancel: bool) -> None:
        with contextlib.suppress(Exception):
            self.client.close()
        if self.cluster is not None:
            with contextlib.suppress(Exception):
                self.cluster.close()


def _cpu_count() -> int:
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:
        return max(1, os.cpu_count() or 1)


def _scheduler_from_dask_config() -> str | None:
    """The usual Dask setting (``scheduler-address``, env ``DASK_SCHEDULER_ADDRESS``)."""
    try:
        import dask.config
    except ImportError:
        return os.environ.get("DASK_SCHEDULER_ADDRESS") or None
    return dask.config.get("scheduler-address", None) or None


def _check_execution(workers: int | None, scheduler: str | None) -> None:
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int)
                                or workers < 1):
        raise InputError(f"--workers must be a whole number >= 1, got {workers!r}")
    if scheduler is not None and not isinstance(scheduler, str):
        raise InputError(f"--scheduler must be an address, 'local' or 'pool', got "
                         f"{scheduler!r}")


def _executor(workers: int | None, scheduler: str | None) -> Any:
    if scheduler is None:
        scheduler = _scheduler_from_dask_config()
    if scheduler is not None and scheduler.strip() and scheduler.strip() != "pool":
        return _Dask(scheduler.strip(), workers)
    n = workers or _cpu_count()
    return _InProcess() if n == 1 else _Pool(n)


# -- metadata -----------------------------------------------------------------------------
def _describe_analyzer(factory: Callable[..., Any] | None) -> str:
    if factory is None:
        return "threadmate.contact.ContactAnalyzer"
    if isinstance(factory, functools.partial):
        args = ", ".join([repr(a) for a in factory.args]
                         + [f"{k}={v!r}" for k, v in sorted(factory.keywords.items())])
        return f"{_describe_analyzer(factory.func)}({args})"
    module = getattr(factory, "__module__", "")
    name = getattr(factory, "__qualname__", repr(factory))
    return f"{module}.{name}" if module else name


def _default_chord(units: str) -> float:
    from ..geometry import DEFAULT_CHORD

    return float(DEFAULT_CHORD[units])


def _request_metadata(job: Job) -> dict[str, Any]:
    spec = job.spec.to_dict()
    return {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "threadmate_version": __version__,
        "units": job.spec.units,
        "angles": "degrees",
        "conventions": "conventions.md: x_F = Rx(roll) Ry(pitch) Rz(phase) x_B + origin",
        "spec": spec,
        "grid": job.grid.to_dict(),
        "mesh": {"chord": job.chord, "max_deviation": None},
        "contact": {"compliance_z": job.compliance_z, "tolerances": None,
                    "analyzer": _describe_analyzer(job.analyzer)},
        "columns": "config_id, the contact record of docs/architecture.md, error",
        "created": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
    }


def _open_library(out: Path, job: Job) -> dict[str, Any]:
    """Create the library directory, or check that an existing one holds this request."""
    wanted = _request_metadata(job)
    if out.exists() and not out.is_dir():
        raise LibraryError(f"{out} exists and is not a directory: give a library directory")
    if out.is_dir() and (out / METADATA_FILE).exists():
        meta = read_metadata(out)
        diff = compare_metadata(meta, wanted)
        if diff:
            raise LibraryError(f"{out} holds a different sweep; refusing to mix it with this "
                               f"request. It differs in: {'; '.join(diff)}. Use another "
                               "output directory.")
        remove_stale_temporaries(out)
        return meta
    if out.is_dir() and any(not p.name.startswith(".") for p in out.iterdir()):
        raise LibraryError(f"{out} exists, is not empty and is not a threadmate library: "
                           "give a new or empty directory")
    write_metadata(out, wanted)
    return wanted


def _chunks(ids: np.ndarray, size: int) -> Iterator[list[int]]:
    for start in range(0, len(ids), size):
        yield [int(i) for i in ids[start:start + size]]


# -- the sweep ----------------------------------------------------------------------------
def sweep(spec: ThreadSpec, roll: Values = None, pitch: Values = None, phase: Values = None,
          *, out: str | os.PathLike[str] | None = None, workers: int | None = None,
          scheduler: str | None = None, chunk_size: int | None = None,
          chord: float | None = None, compliance_z: float = 0.0,
          progress: ProgressCallback | None = None, max_chunks: int | None = None,
          analyzer: Callable[..., Any] | None = None) -> Path | pd.DataFrame:
    """Build (or resume) the contact-state library of a thread pair over a grid.

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
        Configurations per chunk (one Parquet part each). Default: about 16 chunks per
        worker, 4 to 256 configurations each.
    chord : float, optional
        Chord tolerance of the meshes (spec units; default that of
        :mod:`threadmate.geometry`). At most a tenth of the pitch.
    compliance_z : float
        Compliance centre on the bolt axis, bolt frame (default 0: the tip centre).
    progress : callable, optional
        ``progress(done, total)`` after each chunk (see :data:`ProgressCallback`).
    max_chunks : int, optional
        Stop after writing this many chunks (the library stays resumable).
    analyzer : callable, optional
        ``analyzer(spec, chord=..., compliance_z=...)`` builds the analyser in each
        worker (default :class:`threadmate.contact.ContactAnalyzer`); it must pickle
        (a module-level class or a :func:`functools.partial` of one). Recorded in the
        metadata.

    Returns
    -------
    pathlib.Path or pandas.DataFrame
        The library directory; or, without ``out``, its rows as :func:`load` gives them.

    Raises
    ------
    InputError
        Bad grid, worker count, chord or scheduler (``LibraryError`` for a library that
        disagrees with the request).
    SweepInterrupted
        A worker or the cluster was lost; finished chunks are saved, run again to resume.
    """
    if not isinstance(spec, ThreadSpec):
        raise InputError(f"spec must be a ThreadSpec, got {type(spec).__name__}")
    grid = Grid.parse(roll, pitch, phase)
    if chord is None:
        chord = _default_chord(spec.units)
    if isinstance(chord, bool) or not isinstance(chord, int | float) \
            or not math.isfinite(chord) or chord <= 0:
        raise InputError(f"--chord must be a positive length, got {chord!r}")
    if chord > spec.pitch / 10:
        raise InputError(f"--chord {chord:g} is too coarse for pitch {spec.pitch:g} "
                         f"{spec.units}: give at most a tenth of the pitch")
    if isinstance(compliance_z, bool) or not isinstance(compliance_z, int | float) \
            or not math.isfinite(compliance_z):
        raise InputError(f"--compliance-z must be a finite length, got {compliance_z!r}")
    for name, value in (("chunk_size", chunk_size), ("max_chunks", max_chunks)):
        if value is not None and (isinstance(value, bool) or not isinstance(value, int)
                                  or value < 1):
            raise InputError(f"{name} must be a whole number >= 1, got {value!r}")
    _check_execution(workers, scheduler)
    job = Job(spec, grid, float(chord), float(compliance_z), analyzer)

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


def _run(job: Job, out: Path, workers: int | None, scheduler: str | None,
         chunk_size: int | None, progress: ProgressCallback | None,
         max_chunks: int | None) -> None:
    existed = out.exists()
    meta = _open_library(out, job)
    total = job.grid.size
    done = done_ids(out)
    todo = np.setdiff1d(np.arange(total, dtype=np.int64), done, assume_unique=True)
    n_done = total - len(todo)
    if len(todo) == 0:
        if progress is not None:
            progress(n_done, total)
        return
    try:
        executor = _executor(workers, scheduler)
    except BaseException:
        if not existed:  # leave nothing behind for a request that never started
            (out / METADATA_FILE).unlink(missing_ok=True)
            with contextlib.suppress(OSError):
                out.rmdir()
        raise
    if progress is not None:
        progress(n_done, total)
    if chunk_size is None:
        chunk_size = int(min(256, max(4, math.ceil(len(todo) / (16 * executor.slots)))))
    chunks = _chunks(todo, chunk_size)
    part = next_part_index(out)
    cancel = True
    try:
        cancel = not _loop(job, out, executor, chunks, meta, part, n_done, total, progress,
                           max_chunks)
    except _lost_errors() as exc:
        n_saved = len(done_ids(out))
        raise SweepInterrupted(
            f"the sweep stopped: a worker or the cluster was lost ({type(exc).__name__}: "
            f"{exc}). {n_saved} of {total} configurations are saved in {out}; run the same "
            "sweep again to resume.") from exc
    finally:
        executor.close(cancel=cancel)


def _loop(job: Job, out: Path, executor: Any, chunks: Iterator[list[int]],
          meta: dict[str, Any], part: int, n_done: int, total: int,
          progress: ProgressCallback | None, max_chunks: int | None) -> bool:
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
        if meta["mesh"].get("max_deviation") is None:
            # The first result tells what the workers' analysers actually used.
            meta["mesh"].update(chord=settings["chord"] or job.chord,
                                max_deviation=settings["max_deviation"])
            meta["contact"]["tolerances"] = settings["tolerances"]
            write_metadata(out, meta)
        write_part(out, part, table.replace_schema_metadata(library_schema(meta).metadata))
        part += 1
        written += 1
        n_done += table.num_rows
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


def _lost_errors() -> tuple[type[BaseException], ...]:
    """Exceptions that mean a worker or the cluster was lost (not a bug in the work)."""
    from concurrent.futures.process import BrokenProcessPool

    lost: tuple[type[BaseException], ...] = (BrokenProcessPool, cf.CancelledError)
    try:
        from distributed import KilledWorker
        from distributed.client import FutureCancelledError
        from distributed.comm.core import CommClosedError

        lost += (KilledWorker, CommClosedError, FutureCancelledError)
    except ImportError:
        pass
    return lost
