"""The scene's compiled kernels warmed: each compiled, or loaded from numba's on-disk
cache, by one small call, the processes that warm them taking turns.

On a machine whose cache is empty, every process that asks the kernels compiles them:
a pool's workers would each do the same seconds of work at once. numba looks in its
on-disk cache at a kernel's first call, so a kernel one process has compiled and saved,
another loads. The processes that warm the kernels therefore take turns (a lock file per
step, where the platform has ``fcntl``): each first compiles the steps no other is
compiling, in its own order, then waits for the others' and loads them. Each step is
compiled once between them. With the cache warm, each call only loads what the work
would load anyway. :func:`warm_kernels_aside` starts one more such process at once, to
compile while its caller imports and prepares (a command's first seconds use one core).

Each call passes arguments of the types the work passes (C-ordered float64 and int64
arrays), so that it compiles the very signature the work asks for
(``tests/test_compiled.py`` checks that the work compiles no second one).
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import tempfile
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np

from ..._compiled import COMPILED
from ..._system import cpu_count
from ...geometry import ThreadBody, bolt_body, spec_from_designation
from ._kernels import (
    KINK,
    EdgeCurve,
    _arrays,
    closest_on_edge,
    contact_rows,
    crossing_of_edges,
    deep_candidates,
    edge_points,
    feature,
    kink_height,
    least_on_grid,
    paired_triangles,
    signed_distance,
    vertical_touch,
    window_grid,
)
from ._linkage import EVERY_PAIR, single_linkage
from ._obb import ALL, ANY, CrossingQuery, ObbForest, obb_forest, unique_face_pairs

__all__ = ["warm_kernels", "warm_kernels_aside"]


def _triangles() -> tuple[np.ndarray, np.ndarray]:
    """Two small triangles, one above the other."""
    low = np.array([[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]])
    return low + [0.0, 0.0, 0.5], low


def _leaf() -> ObbForest:
    """A forest of one tree of one leaf, made here (not by the trees' build, which the
    other order warms first)."""
    tri = _triangles()[1]
    return ObbForest(
        centre=np.array([[0.5, 0.5, 0.0]]),
        axes=np.eye(3)[None].copy(),
        extent=np.array([[0.5, 0.5, 0.0]]),
        left=np.full(1, -1, dtype=np.int64),
        right=np.full(1, -1, dtype=np.int64),
        leaf=np.zeros(1, dtype=np.int64),
        size=np.ones(1, dtype=np.int64),
        triangles=tri,
        faces=np.zeros(1, dtype=np.int64),
        roots=np.zeros(1, dtype=np.int64),
    )


def _trees() -> None:
    top, low = _triangles()
    vertices = np.concatenate([top, low]).reshape(-1, 3)
    obb_forest(vertices, np.arange(6, dtype=np.int64).reshape(2, 3), [np.arange(2)])


def _walks() -> None:
    forest = _leaf()
    query = CrossingQuery(forest)
    trees, rotation = np.zeros(1, dtype=np.int64), np.eye(3)
    unique_face_pairs(query(forest, 0, trees, rotation, np.zeros(3), ANY))
    query.below(forest, 0, trees, rotation, np.zeros(3), np.array([0.0, 0.0, 1.0]))
    query.among(forest, np.zeros((1, 3), dtype=np.int64), rotation, np.zeros(3), ALL)


def _touch() -> None:
    vertical_touch(*_triangles())
    vertices, faces = np.eye(3), np.arange(3, dtype=np.int64).reshape(1, 3)
    pairs = np.zeros((1, 2), dtype=np.int64)
    paired_triangles(vertices, faces, vertices, faces, pairs, np.eye(3), np.zeros(3))
    one = np.ones(1)
    contact_rows(np.eye(3)[:1], np.zeros((1, 3)), one, one, np.zeros(3), 1.0, np.eye(3)[1], 3)
    # (The contact set's grouping, of few points and of many.)
    single_linkage(np.zeros((2, 3)), 1.0)
    single_linkage(np.zeros((EVERY_PAIR + 1, 3)), 1.0)


def _body() -> ThreadBody:
    """The default bolt's exact body, whose arrays the exact geometry's kernels take."""
    return bolt_body(spec_from_designation("1/4-20 UNC-2A/2B"))


def _features() -> None:
    body = _body()
    body.profile.distance(np.zeros(1), np.zeros(1))  # (the meshes' accuracy)
    kink_height(body, 0.0, 0.0)
    feature(body, 0.0, 0.0, 0.0, 1e-7)


def _edges() -> None:
    body = _body()
    p = np.zeros((1, 3))
    signed_distance(body, p, np.arctan2(p[:, 1], p[:, 0]))
    deep_candidates(body, p, np.eye(3), p[0], inverse=True, depth=1.0, margin=0.0)
    got = _arrays(body)
    kink = EdgeCurve(KINK, got.prof, got.env, got.rise, float(body.lead), 0.0, 0.0, 0.0)
    crossing_of_edges(kink, kink, np.eye(3), np.zeros(3), 0.0, 1.0)
    face = (got.prof, got.env, got.shape)
    closest_on_edge(kink, face, np.eye(3), np.zeros(3), True, 0.0, 0.1)
    least_on_grid(window_grid(0.0, 0.1), np.zeros(17))
    edge_points(kink, np.zeros(1))


#: The kernels' calls, in the forward order: the trees' build and the walk, the two
#: dearest to compile, at either end, and steps small enough between that two processes,
#: one from each end, finish about together.
_STEPS: tuple[Callable[[], None], ...] = (_trees, _touch, _features, _edges, _walks)
#: Longest wait for another process's turn at a step (seconds): beyond it (that process
#: stalled, or numba cannot save to its cache) this one compiles the step itself.
_WAIT = 60.0


def _lock_folder() -> Path | None:
    """Where the steps' lock files live (None: no ``fcntl`` here, the processes do not
    take turns)."""
    try:
        import fcntl  # noqa: F401
    except ImportError:  # pragma: no cover - not on Linux or macOS
        return None
    owner = os.getuid() if hasattr(os, "getuid") else 0
    return Path(tempfile.gettempdir()) / f"threadmate-warm-{owner}"


@contextlib.contextmanager
def _turn(folder: Path | None, name: str, wait: float) -> Iterator[bool]:
    """Hold the turn at step ``name`` while inside: True once held; waiting up to ``wait``
    seconds for another process that holds it (False when it still does, or where there
    are no turns to take, no lock file to make: the step is then run anyway)."""
    if folder is None:
        yield False
        return
    import fcntl

    try:
        folder.mkdir(parents=True, exist_ok=True)
        handle = open(folder / f"{name}.lock", "a")  # closed by the with below
    except OSError:  # no writable temporary folder: no turns
        yield False
        return
    with handle:
        deadline = time.monotonic() + wait
        while True:
            try:
                fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                if time.monotonic() >= deadline:
                    yield False
                    return
                time.sleep(0.02)
                continue
            try:
                yield True
            finally:
                fcntl.flock(handle, fcntl.LOCK_UN)
            return


def warm_kernels(reverse: bool = False) -> None:
    """Compile (or load from numba's cache) the scene's kernels, taking turns with the
    other processes that warm them (module docstring): first the steps no other process
    is at, in the forward order or ``reverse`` (give the workers of a pool alternate
    orders), then, waiting for each, the others."""
    folder = _lock_folder()
    later = []
    for step in reversed(_STEPS) if reverse else _STEPS:
        with _turn(folder, step.__name__, 0.0) as held:
            if held or folder is None:
                step()
                continue
        later.append(step)  # another process is at it (or no lock file: run it below)
    for step in later:
        with _turn(folder, step.__name__, _WAIT):
            step()


def _warm_aside(parent: int) -> None:
    """A process of :func:`warm_kernels_aside`: warm, unless its parent is gone."""
    if os.getppid() == parent:
        warm_kernels(reverse=True)


#: The process :func:`warm_kernels_aside` started last, by the process of that pid (a
#: forked child holds its parent's entry, not its own child).
_ASIDE: dict[int, multiprocessing.process.BaseProcess] = {}


def warm_kernels_aside() -> multiprocessing.process.BaseProcess | None:
    """Start warming the kernels (:func:`warm_kernels`) in a forked process beside this one,
    and return it: a caller about to start a process pool on a machine whose numba cache
    may be empty calls this first, so that one core compiles while the caller imports
    and prepares. The one it started already while that one still runs; None where it
    would not help (numba missing, one CPU, no ``fork``). The process is a daemon: it
    ends with its caller at the latest."""
    if not COMPILED or "fork" not in multiprocessing.get_all_start_methods():
        return None
    if cpu_count() < 2:
        return None
    running = _ASIDE.get(os.getpid())
    if running is not None and running.is_alive():
        return running
    process = multiprocessing.get_context("fork").Process(
        target=_warm_aside, args=(os.getpid(),), name="threadmate-warm", daemon=True
    )
    process.start()
    _ASIDE.clear()
    _ASIDE[os.getpid()] = process
    return process
