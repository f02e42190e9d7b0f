"""The speed targets of the mechanics, as ratios to their targets, for one or more source
trees side by side in one run.

Usage::

    python benchmarks/bench_targets.py                          # this checkout
    python benchmarks/bench_targets.py --src OLD/src,NEW/src    # before and after
    python benchmarks/bench_targets.py --src OLD/src,NEW/src --run   # and `threadmate run`
    python benchmarks/bench_targets.py --src OLD/src,NEW/src --together [--run]

Each source tree is measured in a child process of its own (``PYTHONPATH`` set to it),
one after the other, with the host's load (``os.getloadavg``) printed beside. On a
shared host whose speed drifts by more than a change moves its figures, ``--together``
runs the children at the same time instead, each on a core of its own
(``os.sched_setaffinity``; at most one source tree per core), so that the codes compared
meet the same host; with ``--run`` they then time ``threadmate run --workers 1``, each on
its core, at the same time (a comparison, not the two-core target). The pair is
1/4-20 UNC-2A/2B at mean material, default chord and compliance: its ``flat`` parts
(no point, no countersink) and its default parts (the chamfered point and the
countersink of the standard nut). Costs are CPU time of this process (one core) divided
by one python-fcl yes/no query of the same meshes (``_reference.py``), timed in the same
child at the run's own rest poses: query equivalents (QE). Each timed part starts from
a collected heap (``gc.collect()``). The CPU milliseconds of a configuration and of a
rest state are printed beside: where the children's reference queries differ (their
cores loaded unevenly by the host), those compare the codes.

Targets (a ratio below 1 meets one):

- a sweep's grid configuration (its drop, rest state and its search continued to the
  next grid phase, events included), on a stretch of the thesis grid (one held tilt,
  all 72 phases of the thesis grid, ``--phases``; timed after three starts of another held
  tilt, which warm the sweep's lazy imports and first-use trees): flat parts <= 45 QE,
  default parts <= 90 QE;
- a rest state (fresh drops, roll and pitch uniform within +/-4 degrees): <= 30 QE;
- one search turn on the default parts (``threadmate search "1/4-20 UNC-2A/2B" --roll 1
  --pitch -1 --phase 100``): <= 5 s CPU;
- 2,600 starts on the default parts: <= 5 min on two cores, estimated from the grid
  configuration's CPU time (cores not shared);
- with ``--run``: ``threadmate run`` on its defaults, from an empty compile cache, wall
  time on this machine's cores: <= 60 s (its CPU time, all processes, printed beside:
  the figure that other load on the host does not change).
"""

from __future__ import annotations

import argparse
import contextlib
import gc
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

TARGETS = {
    "flat_config_qe": 45.0,
    "default_config_qe": 90.0,
    "rest_state_qe": 30.0,
    "search_turn_s": 5.0,
    "starts_2600_min": 5.0,
    "run_s": 60.0,
}
LABELS = {
    "flat_config_qe": "grid configuration, flat parts (QE)",
    "default_config_qe": "grid configuration, default parts (QE)",
    "rest_state_qe": "rest state, default parts (QE)",
    "search_turn_s": "one search turn, default parts (s CPU)",
    "starts_2600_min": "2,600 starts, default parts, 2 cores (min)",
    "run_s": "threadmate run, first run (s wall)",
}


def _child(args: argparse.Namespace) -> None:
    """Measure in this process (the source tree on ``sys.path``); print one JSON line."""
    import numpy as np
    from _reference import ReferenceQuery

    from threadmate.contact import Compliance, Mechanics, search
    from threadmate.geometry import Pose, spec_from_designation
    from threadmate.library import load, sweep

    out: dict[str, float] = {}
    specs = {
        "flat": spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False),
        "default": spec_from_designation("1/4-20 UNC-2A/2B"),
    }
    mechs = {k: Mechanics(s, Compliance()) for k, s in specs.items()}
    # Compile caches and lazy imports warmed outside the timings (the run's figure has them).
    mechs["default"].settle(1.0, -1.0, 100.0)
    mechs["flat"].settle(1.0, -1.0, 100.0)
    queries = {k: ReferenceQuery(s) for k, s in specs.items()}

    def qe(kind: str, poses: list[Pose]) -> float:
        return queries[kind].cpu_time(poses, mechs[kind].tolerance, repeats=10)

    # Rest states. (The set-up's objects collected first: they would bring on a full
    # collection of the heap within the first few drops, a pause that a process's later
    # work meets seldom.)
    gc.collect()
    rng = np.random.default_rng(0)
    times, poses = [], []
    for _ in range(args.rest_states):
        cfg = (rng.uniform(-4, 4), rng.uniform(-4, 4), rng.uniform(0, 360))
        t = time.process_time()
        rest = mechs["default"].settle(*cfg)
        times.append(time.process_time() - t)
        poses.append(rest.state.pose)
    q_default = qe("default", poses)
    out["rest_state_qe"] = float(np.mean(times)) / q_default
    out["rest_state_ms"] = 1e3 * float(np.mean(times))
    out["query_default_us"] = 1e6 * q_default

    # One search turn.
    t = time.process_time()
    search(mechs["default"], 1.0, -1.0, 100.0)
    out["search_turn_s"] = time.process_time() - t

    # A stretch of the thesis grid, in this process (one worker). A sweep's own lazy
    # imports and the trees it builds on first use warmed first, by three starts of
    # another held tilt: a sweep's configurations number in thousands.
    for kind in ("flat", "default"):
        folder = Path(tempfile.mkdtemp(prefix="bench-targets-"))
        sweep(specs[kind], "0", "0", "0:10:5", out=folder / "warm", workers=1)
        gc.collect()
        t = time.process_time()
        sweep(specs[kind], "1", "-1", args.phases, out=folder / "lib", workers=1)
        cpu = time.process_time() - t
        rows = load(folder / "lib")
        n = int(rows["config_id"].nunique())
        rest = rows[(rows["role"] == "start") & (rows["error"] == "")]
        rest_poses = [
            Pose(
                np.reshape(np.asarray(r["rotation"], dtype=float), (3, 3)),
                np.array([r["origin_x"], r["origin_y"], r["origin_z"]]),
            )
            for _, r in rest.iterrows()
        ]
        q = qe(kind, rest_poses)
        out[f"{kind}_config_qe"] = cpu / n / q
        out[f"{kind}_config_ms"] = 1e3 * cpu / n
        out[f"query_{kind}_us"] = 1e6 * q
        if kind == "default":
            out["starts_2600_min"] = cpu / n * 2600 / 2 / 60
    print(json.dumps(out))


def _threadmate_run(src: str) -> tuple[float, float]:
    """Wall time and CPU time (all its processes) of ``threadmate run`` on its defaults,
    with an empty compile cache."""
    with tempfile.TemporaryDirectory(prefix="bench-run-") as folder:
        t = time.perf_counter()
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        proc = subprocess.run(
            _run_command(folder), env=_run_env(src, folder), capture_output=True, text=True
        )
        wall = time.perf_counter() - t
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        if proc.returncode:
            sys.exit(f"threadmate run failed ({src}):\n{proc.stderr[-2000:]}")
        cpu = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
        return wall, cpu


def _run_command(folder: str, *extra: str) -> list[str]:
    code = "import sys; from threadmate.cli import main; sys.exit(main())"
    return [sys.executable, "-c", code, "run", "-o", str(Path(folder) / "out"), *extra]


def _run_env(src: str, folder: str) -> dict[str, str]:
    """``threadmate run``'s environment: the source tree, an empty compile cache."""
    return {**os.environ, "PYTHONPATH": src, "NUMBA_CACHE_DIR": str(Path(folder) / "numba")}


def _on_core(core: int | None) -> Any:
    """A ``preexec_fn`` that pins the child to ``core`` (None: no pinning)."""
    if core is None:
        return None
    return lambda: os.sched_setaffinity(0, {core})


def _children(srcs: list[str], args: argparse.Namespace, cores: list[int] | None) -> list[dict]:
    """Each source tree's figures, measured by its own child: one after the other, or all
    at the same time, child ``i`` pinned to ``cores[i]``."""
    here = Path(__file__).resolve().parent
    cmd = [sys.executable, __file__, "--_child", f"--phases={args.phases}"]
    cmd += ["--rest-states", str(args.rest_states)]
    envs = [{**os.environ, "PYTHONPATH": os.pathsep.join([src, str(here)])} for src in srcs]
    if cores is None:
        results = []
        for src, env in zip(srcs, envs, strict=True):
            load0 = os.getloadavg()[0]
            proc = subprocess.run(cmd, env=env, capture_output=True, text=True)
            r = _parsed(src, proc.returncode, proc.stdout, proc.stderr)
            if args.run:
                r["run_s"], r["run_cpu_s"] = _threadmate_run(src)
            r["load"] = [load0, os.getloadavg()[0]]
            results.append(r)
            print(f"{src}: load {r['load'][0]:.2f} -> {r['load'][1]:.2f}", flush=True)
        return results
    load0 = os.getloadavg()[0]
    procs = [
        subprocess.Popen(
            cmd,
            env=env,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            preexec_fn=_on_core(core),
        )
        for env, core in zip(envs, cores, strict=True)
    ]
    outs = [p.communicate() for p in procs]
    results = [
        _parsed(src, p.returncode, out, err)
        for src, p, (out, err) in zip(srcs, procs, outs, strict=True)
    ]
    if args.run:
        for r, wall in zip(results, _runs_together(srcs, cores), strict=True):
            r["run_one_core_s"] = wall
    for r in results:
        r["load"] = [load0, os.getloadavg()[0]]
    print(f"together, one core each: load {load0:.2f} -> {os.getloadavg()[0]:.2f}", flush=True)
    return results


def _runs_together(srcs: list[str], cores: list[int]) -> list[float]:
    """Wall times of ``threadmate run --workers 1`` for each source tree, all started at
    once, each pinned to its core, from empty compile caches."""
    with contextlib.ExitStack() as stack:
        folders = [stack.enter_context(tempfile.TemporaryDirectory()) for _ in srcs]
        logs = [stack.enter_context(open(Path(f) / "stderr", "w+")) for f in folders]
        t = time.perf_counter()
        procs = [
            subprocess.Popen(
                _run_command(folder, "--workers", "1"),
                env=_run_env(src, folder),
                stdout=subprocess.DEVNULL,
                stderr=log,
                preexec_fn=_on_core(core),
            )
            for src, folder, log, core in zip(srcs, folders, logs, cores, strict=True)
        ]
        walls = [0.0] * len(procs)
        while any(p.returncode is None for p in procs):
            for i, p in enumerate(procs):
                if p.returncode is None and p.poll() is not None:
                    walls[i] = time.perf_counter() - t
            time.sleep(0.05)
        for src, p, log in zip(srcs, procs, logs, strict=True):
            if p.returncode:
                log.seek(0)
                sys.exit(f"threadmate run failed ({src}):\n{log.read()[-2000:]}")
        return walls


def _parsed(src: str, code: int, stdout: str, stderr: str) -> dict:
    if code:
        sys.exit(f"benchmark failed ({src}):\n{stderr[-3000:]}")
    return dict(json.loads(stdout.strip().splitlines()[-1]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--src", default=None, help="comma list of source trees (default: ours)")
    parser.add_argument("--phases", default="0:355:5", help="grid phases (default 0:355:5)")
    parser.add_argument("--rest-states", type=int, default=20, help="fresh drops (default 20)")
    parser.add_argument("--run", action="store_true", help="also time `threadmate run`")
    parser.add_argument(
        "--together",
        action="store_true",
        help="measure the source trees at the same time, each on a core of its own",
    )
    parser.add_argument("--_child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args._child:
        _child(args)
        return
    here = Path(__file__).resolve().parent
    srcs = args.src.split(",") if args.src else [str(here.parent / "src")]
    cores = None
    if args.together:
        free = sorted(os.sched_getaffinity(0))
        if len(srcs) > len(free):
            parser.error(f"--together: {len(srcs)} source trees, {len(free)} cores")
        cores = free[: len(srcs)]
    results = _children(srcs, args, cores)
    print()
    head = f"{'target':46s} {'limit':>7s}" + "".join(
        f" {Path(s).resolve().parent.name[-14:]:>22s}" for s in srcs
    )
    print(head)
    for key, limit in TARGETS.items():
        if key not in results[0]:
            continue
        cells = "".join(
            f" {r[key]:10.1f} ({r[key] / limit:5.2f}x)" if key in r else f" {'-':>22s}"
            for r in results
        )
        print(f"{LABELS[key]:46s} {limit:7.0f}{cells}")
    for key in (
        "query_flat_us",
        "query_default_us",
        "flat_config_ms",
        "default_config_ms",
        "rest_state_ms",
        "run_cpu_s",
        "run_one_core_s",
    ):
        if key in results[0]:
            print(f"{key:46s} {'':7s}" + "".join(f" {r[key]:22.0f}" for r in results))
    print(json.dumps(results))


if __name__ == "__main__":
    main()
