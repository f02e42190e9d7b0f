"""Held tilts off any grid, each swept over a grid's phases by the sweep's own machinery.

A search over held tilts (the capture envelope's bisection in tilt size,
:mod:`threadmate.design`) asks for the states of one held tilt at a time, at sizes no grid
holds. :class:`HeldTiltProbe` runs each such held tilt as the sweep runs a chunk (one held
tilt, all its phases, :func:`._held_tilt.states_of_held_tilt` in a worker that keeps its
model between chunks, on this process, a process pool or Dask), and hands back its rows
as :func:`load` would give a library of that one held tilt (the metadata in
``rows.attrs["threadmate"]``), so that every reader of a library reads them. Nothing is
written to disk.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace
from types import TracebackType
from typing import Any

import pandas as pd
import pyarrow as pa

from .._errors import InputError
from ..contact import CONTINUATION_STEP, PHASE_TOLERANCE, Compliance, check_continuation
from ..geometry import ThreadSpec, check_chord
from ._executors import check_execution, open_executor
from ._grid import PolarGrid, Values, parse_range
from ._metadata import request_metadata
from ._workers import FRICTION_COLUMN, Job, MeshFile

__all__ = ["HeldTiltProbe", "ProbeProgress"]

#: ``progress(done, asked)``: held tilts of one call finished, and asked for.
ProbeProgress = Callable[[int, int], None]


class HeldTiltProbe:
    """The states of held tilts at a grid's phases, computed on demand (module docstring).

    Use as a context manager (the workers are started on entry and stopped on exit)::

        with HeldTiltProbe(spec, phase="0:340:20", compliance=c) as probe:
            rows = probe.run([(1.5, 0.0), (1.0, 135.0)])  # {(size, direction): DataFrame}

    Parameters
    ----------
    spec : ThreadSpec
        The thread pair.
    phase : str, float or sequence of float
        The start phases of every held tilt (degrees, as :func:`parse_range`).
    compliance : Compliance, optional
        Default :class:`~threadmate.contact.Compliance()`.
    chord, step, phase_tolerance
        As :func:`sweep`.
    workers, scheduler
        As :func:`sweep`: held tilts run in parallel, one per worker at a time.
    bolt_mesh, nut_mesh, mesh_units
        CAD meshes as a library records them (:class:`._workers.MeshFile`), or None.
    base_metadata : dict, optional
        The metadata the rows carry (a library's, when the probe extends one); default
        that of a sweep of this request. Its grid is replaced by each held tilt's own.
    frictions : sequence of float, optional
        Friction coefficients at which to give each held tilt's rows besides the
        compliance's (:meth:`next_done_each`), the held tilt walked once where every
        proof judges alike at them (:func:`._held_tilt.states_over_frictions`).
    """

    def __init__(
        self,
        spec: ThreadSpec,
        phase: Values,
        *,
        compliance: Compliance | None = None,
        chord: float | None = None,
        step: float = CONTINUATION_STEP,
        phase_tolerance: float = PHASE_TOLERANCE,
        workers: int | None = None,
        scheduler: str | None = None,
        bolt_mesh: MeshFile | None = None,
        nut_mesh: MeshFile | None = None,
        mesh_units: str | None = None,
        base_metadata: dict[str, Any] | None = None,
        frictions: Sequence[float] = (),
    ) -> None:
        if not isinstance(spec, ThreadSpec):
            raise InputError(f"spec must be a ThreadSpec, got {type(spec).__name__}")
        compliance = Compliance() if compliance is None else compliance
        if not isinstance(compliance, Compliance):
            raise InputError(f"compliance must be a Compliance, got {type(compliance).__name__}")
        compliance.check_for(spec.pitch)
        check_continuation(step=step, phase_tolerance=phase_tolerance)
        check_execution(workers, scheduler)
        self.phase = parse_range(phase, "phase")
        self.workers, self.scheduler = workers, scheduler
        others = []
        for mu in frictions:
            checked = replace(compliance, friction=float(mu)).friction  # its range checked
            if checked != compliance.friction and checked not in others:
                others.append(checked)
        #: The friction coefficients of every held tilt's rows, the compliance's first.
        self.frictions = (compliance.friction, *others)
        self._job = Job(
            spec,
            PolarGrid((0.0,), (0.0,), self.phase),
            float(check_chord(spec, chord)),
            "mechanics",
            compliance,
            float(step),
            float(phase_tolerance),
            None,
            bolt_mesh,
            nut_mesh,
            mesh_units,
            frictions=self.frictions if others else (),
        )
        self._meta = dict(base_metadata or request_metadata(self._job))
        self._executor: Any = None
        self._pending: dict[Any, tuple[tuple[float, float], Job]] = {}
        self._done: list[tuple[tuple[float, float], dict[float, pd.DataFrame]]] = []
        #: Held tilts computed so far.
        self.computed = 0

    def __enter__(self) -> HeldTiltProbe:
        self._executor = open_executor(self.workers, self.scheduler)
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        if self._executor is not None:
            self._executor.close(cancel=kind is not None)
            self._executor = None

    @property
    def slots(self) -> int:
        """How many held tilts run at once."""
        return 1 if self._executor is None else int(self._executor.slots)

    def submit(self, size: float, direction: float) -> None:
        """Start the held tilt of ``size`` and ``direction`` (degrees, as a
        :class:`PolarGrid`'s); :meth:`next_done` hands back its rows."""
        if self._executor is None:
            raise RuntimeError("HeldTiltProbe used outside its with-block")
        job = replace(self._job, grid=PolarGrid((size,), (direction,), self.phase))
        self._pending[self._executor.submit(job, list(range(len(self.phase))))] = (
            (size, direction),
            job,
        )

    @property
    def in_flight(self) -> int:
        """Held tilts submitted and not yet handed back."""
        return len(self._pending) + len(self._done)

    def next_done(self) -> tuple[tuple[float, float], pd.DataFrame]:
        """The next held tilt to finish: ``((size, direction), rows)``, rows as
        :func:`load` gives those of a library whose grid is that one held tilt."""
        key, each = self.next_done_each()
        return key, each[self.frictions[0]]

    def next_done_each(self) -> tuple[tuple[float, float], dict[float, pd.DataFrame]]:
        """The next held tilt to finish, at every friction coefficient of
        :attr:`frictions`: ``((size, direction), {friction: rows})``, each as
        :meth:`next_done` gives them, its metadata's compliance with that friction."""
        if not self._done:
            if not self._pending:
                raise RuntimeError("no held tilt in flight")
            for fut in self._executor.wait_first(set(self._pending)):
                key, job = self._pending.pop(fut)
                table, _ = fut.result()
                self._done.append((key, self._split(table, job)))
                self.computed += 1
        return self._done.pop(0)

    def _split(self, table: pa.Table, job: Job) -> dict[float, pd.DataFrame]:
        """A finished chunk's rows by friction coefficient, each with its metadata."""
        meta = {**self._meta, "grid": job.grid.to_dict()}
        if FRICTION_COLUMN not in table.column_names:
            parts = {self.frictions[0]: table}
        else:
            mu = table.column(FRICTION_COLUMN).to_numpy()
            table = table.drop_columns([FRICTION_COLUMN])
            parts = {f: table.filter(pa.array(mu == f)) for f in self.frictions}
        out = {}
        for f, part in parts.items():
            rows = part.to_pandas()
            compliance = {**meta["compliance"], "friction": f}
            rows.attrs["threadmate"] = {**meta, "compliance": compliance}
            out[f] = rows
        return out

    def run(
        self,
        tilts: Sequence[tuple[float, float]],
        progress: ProbeProgress | None = None,
    ) -> dict[tuple[float, float], pd.DataFrame]:
        """The rows of each held tilt, given by its size and direction (degrees), over
        the phases, all at once: ``{(size, direction): rows}`` (:meth:`next_done`)."""
        for size, direction in tilts:
            self.submit(size, direction)
        out: dict[tuple[float, float], pd.DataFrame] = {}
        while len(out) < len(tilts):
            key, rows = self.next_done()
            out[key] = rows
            if progress is not None:
                progress(len(out), len(tilts))
        return out
