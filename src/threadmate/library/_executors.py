"""Where a sweep's chunks run: this process, a local process pool or a Dask cluster.

Each executor offers the same three calls to the sweep's loop: ``submit(job, ids)`` a
chunk (a future of :func:`~._workers.run_chunk`), ``wait_first(futures)`` the ones that
finished, and ``close(cancel)``. ``slots`` is how many chunks run at once and ``window``
how many the loop keeps in flight. A pool's workers exit with the sweep that started them
(a SIGKILL gives the sweep no chance to stop them), and a cancelled pool stops its
processes with SIGTERM instead of finishing chunks nobody will write.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import multiprocessing
import os
import re
import signal
import threading
import time
from typing import Any

from .._errors import InputError
from .._system import cpu_count
from .._validate import check_workers
from ._store import release_inherited_locks
from ._workers import Job, prepare_inherited, run_chunk, set_worker_rank, with_mesh_contents

__all__ = [
    "check_execution",
    "lost_errors",
    "open_executor",
    "scheduler_from_dask_config",
]

_DASK_HINT = "pip install threadmate[dask]"


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


def _watch_parent(pids: Any, ranks: Any) -> None:
    """Pool-worker initialiser: report this worker's pid, take the next rank (the
    workers' order among themselves, :func:`._workers.set_worker_rank`), and exit when
    the sweep that started it dies (a SIGKILL leaves no chance to stop the pool; without
    this its workers would finish their chunk, minutes of work, for nobody)."""
    pids.put(os.getpid())
    with ranks.get_lock():
        set_worker_rank(ranks.value)
        ranks.value += 1
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
            initargs=(self._pids, context.Value("i", 0)),
        )
        # Forked workers start at the first submit and inherit what this process holds.
        self._forks = context.get_start_method() == "fork"
        self._started = False

    def submit(self, job: Job, ids: list[int]) -> cf.Future:
        if not self._started:
            self._started = True
            if self._forks:
                prepare_inherited(job)
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
                n = workers or cpu_count()
                self.cluster = distributed.LocalCluster(
                    n_workers=n,
                    threads_per_worker=1,
                    processes=True,
                    host="127.0.0.1",
                    dashboard_address=None,
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
        self._job: Job | None = None
        self._job_data: Any = None

    def submit(self, job: Job, ids: list[int]) -> Any:
        # The workers may not share this file system: the job carries its CAD meshes'
        # bytes, and travels to each worker once (scattered), not with every chunk.
        if self._job is not job:
            self._job = job
            self._job_data = self.client.scatter(
                with_mesh_contents(job), broadcast=True, hash=False
            )
        return self.client.submit(run_chunk, self._job_data, ids, pure=False)

    def wait_first(self, futures: set[Any]) -> set[Any]:
        done = self._distributed.wait(list(futures), return_when="FIRST_COMPLETED").done
        return set(done)

    def close(self, cancel: bool) -> None:
        with contextlib.suppress(Exception):
            self.client.close()
        if self.cluster is not None:
            with contextlib.suppress(Exception):
                self.cluster.close()


def scheduler_from_dask_config() -> str | None:
    """The usual Dask setting (``scheduler-address``, env ``DASK_SCHEDULER_ADDRESS``)."""
    try:
        import dask.config
    except ImportError:
        return os.environ.get("DASK_SCHEDULER_ADDRESS") or None
    return dask.config.get("scheduler-address", None) or None


def check_execution(workers: int | None, scheduler: str | None) -> None:
    """Refuse a bad worker count or scheduler (before anything is written)."""
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


def open_executor(workers: int | None, scheduler: str | None) -> Any:
    """The executor for the request: Dask for a scheduler address or ``"local"`` (or
    Dask's own setting), else the process pool (this process for one worker)."""
    if scheduler is None:
        scheduler = scheduler_from_dask_config()
    if scheduler is not None and scheduler.strip() and scheduler.strip() != "pool":
        return _Dask(scheduler.strip(), workers)
    n = workers or cpu_count()
    return _InProcess() if n == 1 else _Pool(n)


def lost_errors() -> tuple[type[BaseException], ...]:
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
