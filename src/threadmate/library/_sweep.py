"""The sweep: every configuration of a grid through the mechanics (or the thesis's stages),
in chunks, to disk.

Work goes out in chunks of consecutive ``config_id``: for the mechanics one chunk is one
held tilt with all its phases (the continuations of its starts join each other), for the
thesis's model a run of configurations. Each worker process (or Dask worker thread)
builds ONE :class:`~threadmate.contact.Mechanics` (or contact analyser), meshes and
python-fcl BVHs included, the first time it sees a job, and keeps it for every later
chunk: fcl objects neither pickle nor share between threads. Each finished chunk is
written at once as its own Parquet part (temporary name, then rename), so an interrupted
sweep loses at most the chunks in flight, and running the same request again computes
only the configurations that no part holds yet.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import datetime as _dt
import functools
import math
import multiprocessing
import os
import re
import shutil
import signal
import tempfile
import threading
import time
import uuid
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pyarrow as pa

from .._errors import InputError, LibraryError, ThreadmateError
from .._io import remove_stale_temporaries
from .._validate import MAX_FACES, check_max_faces, check_starts, check_whole, check_workers
from .._version import __version__
from ..contact import (
    CONTINUATION_STEP,
    ERROR_CLASS,
    PHASE_TOLERANCE,
    SCREW_IN,
    Compliance,
    blank_row,
    check_continuation,
)
from ..geometry import ThreadSpec, check_chord
from ._grid import Grid, Values
from ._held_tilt import JOIN_DISTANCE, JOIN_TILT, MAX_FOLLOW_TURNS, states_of_held_tilt
from ._models import check_model
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
    release_inherited_locks,
    sweep_lock,
    write_metadata,
    write_part,
)

__all__ = ["sweep", "write_library", "SweepInterrupted", "ProgressCallback"]

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
class MeshFile:
    """A mesh from CAD as a worker receives it: the path (fcl objects do not pickle: each
    worker loads the file once), its units and the SHA-256 the sweep started with (a file
    changed meanwhile is refused)."""

    path: str
    units: str
    sha256: str


@dataclass(frozen=True)
class Job:
    """Everything a worker needs to analyse configurations of one sweep (small, picklable)."""

    spec: ThreadSpec
    grid: Grid
    chord: float
    model: str
    compliance: Compliance
    step: float = CONTINUATION_STEP
    phase_tolerance: float = PHASE_TOLERANCE
    analyzer: Callable[..., Any] | None = None
    bolt_mesh: MeshFile | None = None
    nut_mesh: MeshFile | None = None
    mesh_units: str | None = None
    clockwise: bool = False
    #: Most triangles a mesh from CAD may have (:func:`threadmate.geometry.load_mesh`):
    #: a limit of the run, not of its results (not in :attr:`key` or the metadata).
    max_faces: int = MAX_FACES

    @property
    def key(self) -> str:
        return repr(
            (
                self.spec,
                self.grid,
                self.chord,
                self.model,
                self.compliance,
                _describe_analyzer(self.analyzer),
                self.bolt_mesh,
                self.nut_mesh,
                self.mesh_units,
            )
        )

    def mesh_arguments(self) -> dict[str, Any]:
        """The analyser's keyword arguments for the meshes from CAD (none without)."""
        if self.bolt_mesh is None and self.nut_mesh is None:
            return {}
        limit = {} if self.max_faces == MAX_FACES else {"max_faces": self.max_faces}
        return {
            "bolt_mesh": None if self.bolt_mesh is None else self.bolt_mesh.path,
            "nut_mesh": None if self.nut_mesh is None else self.nut_mesh.path,
            "mesh_units": self.mesh_units,
            **limit,  # a raised or lowered limit only (an analyser factory may not take it)
        }


_LOCAL = threading.local()


def _worker_for(job: Job) -> Any:
    """This worker's Mechanics (or thesis analyser) for ``job``, built on first use and
    kept."""
    if getattr(_LOCAL, "key", None) != job.key:
        _LOCAL.worker = None  # free the old meshes before building new ones
        meshes = job.mesh_arguments()
        if job.model == "mechanics":
            from ..contact import ContactAnalyzer, Mechanics

            analyzer = None
            if meshes:
                analyzer = ContactAnalyzer(
                    job.spec,
                    chord=job.chord,
                    compliance_z=job.compliance.compliance_z,
                    **meshes,
                )
            _LOCAL.worker = Mechanics(job.spec, job.compliance, chord=job.chord, analyzer=analyzer)
        else:
            factory = job.analyzer
            if factory is None:
                from ..contact import ContactAnalyzer

                factory = ContactAnalyzer
            _LOCAL.worker = factory(
                job.spec, chord=job.chord, compliance_z=job.compliance.compliance_z, **meshes
            )
        _check_mesh_files(job, _LOCAL.worker)
        _LOCAL.key = job.key
    return _LOCAL.worker


def _check_mesh_files(job: Job, worker: Any) -> None:
    """Refuse a mesh file whose content changed since the sweep started (the library
    records the SHA-256 it was started with)."""
    analyzer = getattr(worker, "analyzer", worker)
    info = getattr(analyzer, "mesh_info", None)
    for kind, given in (("bolt", job.bolt_mesh), ("nut", job.nut_mesh)):
        if given is None or not isinstance(info, dict):
            continue
        got = (info.get(kind) or {}).get("sha256")
        if got != given.sha256:
            raise LibraryError(
                f"{kind} mesh {given.path} changed while the sweep ran (SHA-256 "
                f"{str(got)[:12]}, started with {given.sha256[:12]}); run the sweep again"
            )


def _settings(analyzer: Any) -> dict[str, Any]:
    """The mesh and contact settings an analyser actually used (for the metadata)."""
    tolerances = getattr(analyzer, "tolerances", None)
    deviation = getattr(analyzer, "deviation", None)
    meshes = getattr(analyzer, "mesh_info", None)
    return {
        "chord": getattr(analyzer, "chord", None),
        "max_deviation": None if deviation is None else float(deviation),
        "tolerances": None if tolerances is None else {k: float(v) for k, v in tolerances.items()},
        "meshes": meshes if isinstance(meshes, dict) else None,
    }


def run_chunk(job: Job, config_ids: list[int]) -> tuple[pa.Table, dict[str, Any]]:
    """Analyse configurations in this process; a configuration that raises becomes a row
    with classification ``error`` and the message in ``error``.

    Returns
    -------
    table : pyarrow.Table
        Rows in the library schema (without metadata).
    settings : dict
        The analyser's chord, mesh deviation and tolerances.
    """
    worker = _worker_for(job)
    schema = library_schema(model=job.model)
    configs = job.grid.configurations(config_ids)
    if job.model == "mechanics":
        # One chunk is one held tilt (see _chunks).
        rows = states_of_held_tilt(
            worker,
            float(configs[0][0]),
            float(configs[0][1]),
            [float(c[2]) for c in configs],
            config_ids,
            step=job.step,
            phase_tolerance=job.phase_tolerance,
            clockwise=job.clockwise,
        )
        return pa.Table.from_pylist(rows, schema=schema), _settings(worker.analyzer)
    blank = blank_row(schema)
    rows = []
    for cid, (roll, pitch, phase) in zip(config_ids, configs, strict=True):
        try:
            rec = worker.analyze(float(roll), float(pitch), float(phase)).to_record()
            rec["error"] = ""
        except Exception as exc:  # noqa: BLE001 - one bad configuration must not stop a sweep
            rec = dict(
                blank,
                roll=float(roll),
                pitch=float(pitch),
                phase=float(phase),
                classification=ERROR_CLASS,
                error=f"{type(exc).__name__}: {exc}",
            )
        rec["config_id"] = int(cid)
        rows.append(rec)
    return pa.Table.from_pylist(rows, schema=schema), _settings(worker)


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


def _watch_parent(pids: Any) -> None:
    """Pool-worker initialiser: report this worker's pid, and exit when the sweep that
    started it dies (a SIGKILL leaves no chance to stop the pool; without this its
    workers would finish their chunk, minutes of work, for nobody)."""
    pids.put(os.getpid())
    release_inherited_locks()  # the library's lock is the sweep's, not this worker's
    parent = os.getppid()

    def watch() -> None:
        while True:
            time.sleep(1.0)
            if os.getppid() != parent:
                os._exit(1)

    threading.Thread(target=watch, name="threadmate-parent-watch", daemon=True).start()


class _Pool:
    """A local process pool; each process keeps its own worker state and exits with the
    sweep."""

    def __init__(self, workers: int) -> None:
        self.slots = workers
        self.window = 2 * workers
        self.description = f"process pool of {workers}"
        context = multiprocessing.get_context()
        self._pids = context.SimpleQueue()
        self.pool = cf.ProcessPoolExecutor(
            max_workers=workers,
            mp_context=context,
            initializer=_watch_parent,
            initargs=(self._pids,),
        )

    def submit(self, job: Job, ids: list[int]) -> cf.Future:
        return self.pool.submit(run_chunk, job, ids)

    def wait_first(self, futures: set[Any]) -> set[Any]:
        done, _ = cf.wait(futures, return_when=cf.FIRST_COMPLETED)
        return done

    def close(self, cancel: bool) -> None:
        if not cancel:
            self.pool.shutdown(wait=True)
            return
        # Chunks still running would only be thrown away: stop their processes now.
        pids = []
        while not self._pids.empty():
            pids.append(self._pids.get())
        self.pool.shutdown(wait=False, cancel_futures=True)
        for pid in pids:
            with contextlib.suppress(OSError):
                os.kill(pid, signal.SIGTERM)
        deadline = time.monotonic() + 5.0
        for pid in pids:
            while time.monotonic() < deadline:
                try:
                    os.kill(pid, 0)
                except OSError:
                    break
                time.sleep(0.05)


class _Dask:
    """A Dask distributed client: an existing scheduler, or a LocalCluster it starts."""

    def __init__(self, address: str, workers: int | None) -> None:
        try:
            import distributed
        except ImportError:
            raise InputError(
                f"scheduler={address!r} needs Dask distributed, which is not "
                f"installed: {_DASK_HINT}"
            ) from None
        self._distributed = distributed
        self.cluster = None
        try:
            if address == "local":
                n = workers or _cpu_count()
                self.cluster = distributed.LocalCluster(
                    n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None
                )
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
    if workers is not None:
        check_workers(workers)
    if scheduler is not None and not isinstance(scheduler, str):
        raise InputError(f"scheduler must be an address, 'local' or 'pool', got {scheduler!r}")
    if scheduler is not None and scheduler.strip():
        _check_scheduler(scheduler)


#: A Dask scheduler address: ``tcp://host:port`` (or another protocol), or ``host:port``.
_ADDRESS = re.compile(r"^([a-z][a-z0-9+.-]*://)?[A-Za-z0-9_.\-\[\]:]+:\d+$")


def _check_scheduler(scheduler: str) -> str:
    text = scheduler.strip()
    if text in ("local", "pool") or _ADDRESS.match(text):
        return text
    raise InputError(
        f"scheduler {scheduler!r} is not 'pool', 'local' or a Dask scheduler "
        "address such as tcp://host:8786"
    )


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
        args = ", ".join(
            [repr(a) for a in factory.args]
            + [f"{k}={v!r}" for k, v in sorted(factory.keywords.items())]
        )
        return f"{_describe_analyzer(factory.func)}({args})"
    module = getattr(factory, "__module__", "")
    name = getattr(factory, "__qualname__", repr(factory))
    return f"{module}.{name}" if module else name


def _request_metadata(job: Job) -> dict[str, Any]:
    meta: dict[str, Any] = {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "threadmate_version": __version__,
        "model": job.model,
        "units": job.spec.units,
        "angles": "degrees",
        "conventions": "conventions.md: x_F = Rx(roll) Ry(pitch) Rz(phase) x_B + origin",
        "spec": job.spec.to_dict(),
        "grid": job.grid.to_dict(),
        "mesh": {
            "chord": job.chord,
            "max_deviation": None,
            "bolt": _mesh_metadata(job.bolt_mesh),
            "nut": _mesh_metadata(job.nut_mesh),
        },
        "created": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        # Every part carries this id in its schema: a part of another library is told.
        "library_id": uuid.uuid4().hex,
    }
    if job.model == "mechanics":
        meta["compliance"] = job.compliance.to_dict()
        meta["continuation"] = {
            "step": job.step,
            "phase_tolerance": job.phase_tolerance,
            "screw_in": SCREW_IN,
            "clockwise": job.clockwise,
            "max_turns": MAX_FOLLOW_TURNS,
            "join_tilt": JOIN_TILT,
            "join_distance_pitches": JOIN_DISTANCE,
            "units": "degrees; turns; pitches",
        }
        meta["contact"] = {"tolerances": None}
        meta["columns"] = (
            "one row per contact state: threadmate.contact.STATE_COLUMNS (docs/architecture.md)"
        )
    else:
        meta["compliance"] = {"compliance_z": job.compliance.compliance_z}
        meta["contact"] = {
            "compliance_z": job.compliance.compliance_z,
            "tolerances": None,
            "analyzer": _describe_analyzer(job.analyzer),
        }
        meta["columns"] = "config_id, the contact record of docs/architecture.md, error"
    return meta


def _mesh_metadata(mesh: MeshFile | None) -> dict[str, Any] | None:
    """A CAD mesh in the metadata: file name, SHA-256 and units (None: generated); its
    deviation and off-spec shares are added from the first finished chunk."""
    if mesh is None:
        return None
    return {"file": Path(mesh.path).name, "sha256": mesh.sha256, "units": mesh.units}


def _mesh_files(
    spec: ThreadSpec, bolt_mesh: Any, nut_mesh: Any, mesh_units: str | None, max_faces: int
) -> tuple[MeshFile | None, MeshFile | None]:
    """The CAD meshes of a sweep, validated here (before any library is written) as the
    workers will load them."""
    from ..contact import check_mesh_file

    out: list[MeshFile | None] = []
    for kind, given in (("bolt", bolt_mesh), ("nut", nut_mesh)):
        if given is None:
            out.append(None)
            continue
        if not isinstance(given, str | os.PathLike):
            raise InputError(
                f"{kind}_mesh must be a mesh file path for a sweep (its workers load it), "
                f"got {type(given).__name__}"
            )
        doc = check_mesh_file(
            os.fspath(given),
            kind,  # type: ignore[arg-type]
            spec,
            mesh_units,
            max_faces=max_faces,
        )
        out.append(MeshFile(str(Path(given).absolute()), doc["units"], doc["sha256"]))
    return out[0], out[1]


def _open_library(out: Path, job: Job) -> dict[str, Any]:
    """Create the library directory, or check that an existing one holds this request."""
    wanted = _request_metadata(job)
    if out.exists() and not out.is_dir():
        raise LibraryError(f"{out} exists and is not a directory: give a library directory")
    if out.is_dir() and (out / METADATA_FILE).exists():
        meta = read_metadata(out)
        diff = compare_metadata(meta, wanted)
        if diff:
            raise LibraryError(
                f"{out} holds a different sweep; refusing to mix it with this "
                f"request. It differs in: {'; '.join(diff)}. Use another "
                "output directory."
            )
        remove_stale_temporaries(out)
        return meta
    if out.is_dir() and any(not p.name.startswith(".") for p in out.iterdir()):
        raise LibraryError(
            f"{out} exists, is not empty and is not a threadmate library: "
            "give a new or empty directory"
        )
    try:
        write_metadata(out, wanted)
    except OSError as exc:
        raise LibraryError(f"cannot create the library at {out}: {exc.strerror or exc}") from None
    return wanted


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
    grid = Grid.parse(roll, pitch, phase)
    _check_execution(workers, scheduler)
    n_workers = workers or _cpu_count()
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
    bolt_file, nut_file = _mesh_files(spec, bolt_mesh, nut_mesh, mesh_units, max_faces)
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
        max_faces,
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
    spec, roll, pitch, phase, model, compliance, chord, step, phase_tolerance
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
        Grid.parse(roll, pitch, phase),
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
        meta = _open_library(out, job)
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
    except _lost_errors() as exc:
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
        if meta["mesh"].get("max_deviation") is None:
            # The first result tells what the workers' analysers actually used.
            meta["mesh"].update(
                chord=settings["chord"] or job.chord, max_deviation=settings["max_deviation"]
            )
            meshes = settings.get("meshes") or {}
            for kind in ("bolt", "nut"):
                if isinstance(meta["mesh"].get(kind), dict) and meshes.get(kind):
                    # How the CAD mesh follows the spec (deviation, off-spec shares).
                    extra = {k: v for k, v in meshes[kind].items() if k != "path"}
                    meta["mesh"][kind] = {**extra, **meta["mesh"][kind]}
            if meshes.get("off_spec_tolerance") is not None:
                meta["mesh"]["off_spec_tolerance"] = meshes["off_spec_tolerance"]
            meta["contact"]["tolerances"] = settings["tolerances"]
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
