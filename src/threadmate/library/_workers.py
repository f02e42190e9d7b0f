"""The sweep's work as a worker runs it: the job, the model kept per worker, one chunk.

A :class:`Job` is everything a worker needs (small and picklable: it travels to a pool
process or a Dask worker). Each worker process (or Dask worker thread) builds ONE
:class:`~threadmate.contact.Mechanics` (or thesis analyser), meshes and collision trees
included, the first time it sees a job, and keeps it for every later chunk: building the
meshes and trees is the cost (a forked pool's workers find those their parent built,
:func:`prepare_inherited`), and an analyser's queries reuse buffers of their own, so
threads do not share one. :func:`run_chunk` turns a chunk of ``config_id`` into rows of
the library schema.
"""

from __future__ import annotations

import functools
import hashlib
import os
import tempfile
import threading
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import pyarrow as pa

from .._errors import InputError, LibraryError
from .._validate import MAX_FACES
from ..contact import (
    CONTINUATION_STEP,
    ERROR_CLASS,
    PHASE_TOLERANCE,
    Compliance,
    blank_row,
)
from ..geometry import ThreadSpec, thread_meshes
from ._grid import AnyGrid
from ._held_tilt import states_of_held_tilt, states_over_frictions
from ._store import library_schema

__all__ = [
    "FRICTION_COLUMN",
    "MeshFile",
    "Job",
    "describe_analyzer",
    "local_mesh_path",
    "mesh_files",
    "prepare_inherited",
    "run_chunk",
    "set_worker_rank",
    "with_mesh_contents",
]


@dataclass(frozen=True)
class MeshFile:
    """A mesh from CAD as a worker receives it: the path (each worker loads the file
    once, when it builds its analyser), its units and the SHA-256 the sweep started with
    (a file changed meanwhile is refused).

    ``content``, when given, is the file's bytes, shipped with the job to workers that
    need not share the sweep's file system (a Dask cluster): such a worker writes them
    once to a local copy of the same name (:func:`local_mesh_path`) and loads that. The
    bytes are no part of the job's identity: the SHA-256 is.
    """

    path: str
    units: str
    sha256: str
    content: bytes | None = field(default=None, repr=False, compare=False)


@dataclass(frozen=True)
class Job:
    """Everything a worker needs to analyse configurations of one sweep (small, picklable)."""

    spec: ThreadSpec
    grid: AnyGrid
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
    #: Friction coefficients at which to give the rows besides (a mechanics chunk without
    #: ``clockwise`` only, :func:`run_chunk`); empty: the compliance's alone.
    frictions: tuple[float, ...] = ()
    #: Most triangles a mesh from CAD may have (:func:`threadmate.geometry.load_mesh`):
    #: a limit of the run, not of its results (not in :attr:`key` or the metadata).
    max_faces: int = MAX_FACES

    @property
    def key(self) -> str:
        """What decides the model a worker builds and keeps (not the grid: a worker keeps
        its model for jobs of other grids, such as the envelope's probes)."""
        return repr(
            (
                self.spec,
                self.chord,
                self.model,
                self.compliance,
                describe_analyzer(self.analyzer),
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
            "bolt_mesh": None if self.bolt_mesh is None else local_mesh_path(self.bolt_mesh),
            "nut_mesh": None if self.nut_mesh is None else local_mesh_path(self.nut_mesh),
            "mesh_units": self.mesh_units,
            **limit,  # a raised or lowered limit only (an analyser factory may not take it)
        }


def with_mesh_contents(job: Job) -> Job:
    """``job`` with its CAD mesh files' bytes inside, for workers that may not see the
    sweep's file system. A file changed since the sweep started is refused, as a worker
    would refuse it."""

    def shipped(kind: str, mesh: MeshFile | None) -> MeshFile | None:
        if mesh is None or mesh.content is not None:
            return mesh
        content = Path(mesh.path).read_bytes()
        if hashlib.sha256(content).hexdigest() != mesh.sha256:
            raise LibraryError(
                f"{kind} mesh {mesh.path} changed while the sweep ran; run the sweep again"
            )
        return replace(mesh, content=content)

    if job.bolt_mesh is None and job.nut_mesh is None:
        return job
    return replace(
        job, bolt_mesh=shipped("bolt", job.bolt_mesh), nut_mesh=shipped("nut", job.nut_mesh)
    )


def local_mesh_path(mesh: MeshFile) -> str:
    """Where this worker reads ``mesh``: its path, or, for a mesh shipped with its bytes,
    a copy of the same file name under this host's temporary directory (by SHA-256,
    written once and atomically: workers on one host share it)."""
    if mesh.content is None:
        return mesh.path
    folder = Path(tempfile.gettempdir()) / "threadmate-meshes" / mesh.sha256
    target = folder / Path(mesh.path).name
    if target.is_file() and target.stat().st_size == len(mesh.content):
        return str(target)
    folder.mkdir(parents=True, exist_ok=True)
    part = folder / f".{target.name}.{os.getpid()}.{threading.get_ident()}.part"
    part.write_bytes(mesh.content)
    os.replace(part, target)
    return str(target)


#: The column that tells apart the rows of each friction coefficient of a job with
#: :attr:`Job.frictions`.
FRICTION_COLUMN = "friction"

_LOCAL = threading.local()
#: This process's rank among a pool's workers (None: not a pool's worker, or not yet
#: warmed, see :func:`_worker_for`).
_RANK: list[int | None] = [None]


def set_worker_rank(rank: int) -> None:
    """Record this pool worker's rank (0, 1, ...): its first job warms the compiled
    kernels in the order of its rank's parity."""
    _RANK[0] = rank


def prepare_inherited(job: Job) -> None:
    """Build in this process, before it forks a pool's workers, what they would each
    build alike: they inherit it, and so does this process's report after the sweep.

    ``job``'s generated meshes (:func:`threadmate.geometry.thread_meshes` keeps them per
    process; none where they all come from CAD or the analyser is the caller's own),
    and, for the mechanics, the compiled kernels and the contact scene, its collision
    trees included (:func:`threadmate.contact.contact_scene` keeps it). On a machine
    whose numba cache is empty the kernels are compiled here, taking turns with a
    process that warms them beside this one (:func:`threadmate.contact.warm_kernels_aside`,
    started here unless one runs): each is compiled once, on the two cores, before the
    workers exist, not by the workers and that process three at a time."""
    mechanics = job.model == "mechanics" and job.analyzer is None
    if mechanics:
        from ..contact import contact_scene, warm_kernels, warm_kernels_aside

        warm_kernels_aside()
    if job.analyzer is None and (job.bolt_mesh is None or job.nut_mesh is None):
        thread_meshes(job.spec, job.chord)
    if mechanics:
        warm_kernels()
        contact_scene(job.spec, chord=job.chord, **job.mesh_arguments())


def _worker_for(job: Job) -> Any:
    """This worker's Mechanics (or thesis analyser) for ``job``, built on first use and
    kept.

    A pool's worker first warms the compiled kernels, odd ranks in the reverse order
    (:func:`threadmate.contact.warm_kernels`): where the workers are not forked from a
    process that warmed them (:func:`prepare_inherited`), on a machine whose numba cache
    is empty, they then compile each kernel about once between them, not once each;
    forked, each call finds its kernel compiled."""
    if _RANK[0] is not None:
        from ..contact import warm_kernels

        warm_kernels(reverse=_RANK[0] % 2 == 1)
        _RANK[0] = None
    if getattr(_LOCAL, "key", None) != job.key:
        _LOCAL.worker = None  # free the old meshes before building new ones
        meshes = job.mesh_arguments()
        if job.model == "mechanics":
            from ..contact import Mechanics, contact_scene

            scene = contact_scene(job.spec, chord=job.chord, **meshes)
            _LOCAL.worker = Mechanics(job.spec, job.compliance, scene=scene)
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
    info = getattr(getattr(worker, "scene", None), "mesh_info", None)
    for kind, given in (("bolt", job.bolt_mesh), ("nut", job.nut_mesh)):
        if given is None or not isinstance(info, dict):
            continue
        got = (info.get(kind) or {}).get("sha256")
        if got != given.sha256:
            raise LibraryError(
                f"{kind} mesh {given.path} changed while the sweep ran (SHA-256 "
                f"{str(got)[:12]}, started with {given.sha256[:12]}); run the sweep again"
            )


def _settings(worker: Any) -> dict[str, Any]:
    """The mesh and contact settings a model actually used (for the metadata)."""
    scene = getattr(worker, "scene", None)
    tolerances = getattr(worker, "tolerances", None)
    deviation = getattr(scene, "deviation", None)
    meshes = getattr(scene, "mesh_info", None)
    return {
        "chord": getattr(scene, "chord", None),
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
        Rows in the library schema (without metadata). With :attr:`Job.frictions`, the
        rows at each of them (:func:`._held_tilt.states_over_frictions`), one after the
        other, told apart by a last column ``friction`` that no library stores.
    settings : dict
        The analyser's chord, mesh deviation and tolerances.
    """
    worker = _worker_for(job)
    schema = library_schema(model=job.model)
    configs = job.grid.configurations(config_ids)
    if job.model == "mechanics":
        # One chunk is one held tilt (see _chunks).
        held = (
            worker,
            float(configs[0][0]),
            float(configs[0][1]),
            [float(c[2]) for c in configs],
            config_ids,
        )
        step, tolerance = job.step, job.phase_tolerance
        if not job.frictions:
            rows = states_of_held_tilt(
                *held, step=step, phase_tolerance=tolerance, clockwise=job.clockwise
            )
        else:
            each = states_over_frictions(*held, job.frictions, step=step, phase_tolerance=tolerance)
            schema = schema.append(pa.field(FRICTION_COLUMN, pa.float64()))
            rows = [{**row, FRICTION_COLUMN: mu} for mu, part in each.items() for row in part]
        return pa.Table.from_pylist(rows, schema=schema), _settings(worker)
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


def describe_analyzer(factory: Callable[..., Any] | None) -> str:
    """The thesis analyser's factory as text (its module and name, a partial's arguments):
    part of a job's identity and of the library's metadata."""
    if factory is None:
        return "threadmate.contact.ContactAnalyzer"
    if isinstance(factory, functools.partial):
        args = ", ".join(
            [repr(a) for a in factory.args]
            + [f"{k}={v!r}" for k, v in sorted(factory.keywords.items())]
        )
        return f"{describe_analyzer(factory.func)}({args})"
    module = getattr(factory, "__module__", "")
    name = getattr(factory, "__qualname__", repr(factory))
    return f"{module}.{name}" if module else name


def mesh_files(
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
