"""Benchmark of the sweep stage: wall time, cost per grid configuration in python-fcl query
equivalents, peak memory.

Usage::

    python benchmarks/bench_sweep.py                           # mechanics, 2 held tilts x 72
    python benchmarks/bench_sweep.py --roll=-4:4:1 --pitch=-4:4:1   # the whole thesis grid
    python benchmarks/bench_sweep.py --workers 1,2             # speed-up from 1 to 2 workers
    python benchmarks/bench_sweep.py --workers 1,2 --scheduler local   # on a Dask LocalCluster
    python benchmarks/bench_sweep.py --model thesis --roll=-4:4:1 --pitch=-4:4:1

The pair is 1/4-20 UNC-2A/2B at mean material, default chord (``--chord`` to change),
default compliance (:class:`threadmate.contact.Compliance`), continuation step ``--step``
(default the sweep's, ``threadmate.contact.CONTINUATION_STEP``) and events located to 0.01
degree. The grid is a subset of
the thesis's 9 x 9 held tilts x 72 phases (phase 0..355 by 5): by default the held tilts
(roll, pitch) = (-3, 1) and (2, 1), each with all 72 phases. The mechanics' library holds,
per configuration, the drop's first contact, the unstable states passed, the rest state,
and the counter-clockwise search continued from it grid phase by grid phase with its jumps
and the snap: everything is in the time measured.

**Query equivalents (QE).** In the same run, after the sweep, one yes/no python-fcl
``collide`` query of the same meshes, each one BVH of the whole mesh (``_reference.py``),
is timed (CPU time) at the library's own rest poses,
lifted and lowered by the descent's tolerance (the bodies free but close all round, and
just colliding: the mean of the two), as in ``bench_mechanics.py``. A shared host's speed
drifts over minutes (the same query has timed 0.66 to 1.08 ms after sweeps a few
minutes apart), so, as a check on that figure, the query is also timed at six rest poses of the
grid every 15 s while the workers run, by a thread of the otherwise idle sweeping
process, and compared with the same six poses timed after the sweep (``drift``: 1 on a
steady host; the QE scaled by it is printed beside, not used, since the gauge itself runs
as a third thread on the workers' cores). Two costs per grid
configuration are reported: the workers' CPU time (user + system of the pool's processes)
divided by the configurations and by the query's CPU time (the cost a core pays,
independent of how many workers share it and of other load on the machine), and the wall
time on the given workers divided the same way. Target
(issue 10): at most 100 QE per grid configuration, all states and events included.

``--model thesis`` runs the thesis's fixed-pivot stages instead (chunks of ``--chunk-size``
configurations), with query times taken at the stages' last poses.

``--scheduler local`` runs the sweep on a Dask distributed LocalCluster of ``--workers``
worker processes on 127.0.0.1 (the sweep's own ``scheduler="local"``), so that its speed-up
at 1 and 2 workers can be read beside the pool's; its workers' CPU time is not gathered
(they are the cluster's processes), so its query equivalents are of wall time only.

Each run happens in a fresh child process so that its peak memory and its workers' CPU time
are its own. Only threadmate's public API is used.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

from _reference import ReferenceQuery

from threadmate.contact import CONTINUATION_STEP

THESIS = ("-4:4:1", "-4:4:1", "0:355:5")
THESIS_CONFIGURATIONS = 81 * 72
#: The query-time gauge while the sweep runs: rest poses, and seconds between samples.
GAUGE_POSES = 6
SAMPLE_EVERY = 15.0


def _poses(rows, model: str, most: int = 40) -> list:
    """Up to ``most`` poses the run produced: the mechanics' rest states, or the thesis's
    last stages."""
    import numpy as np

    from threadmate.geometry import Pose

    poses = []
    if model == "mechanics":
        rest = rows[(rows["role"] == "start") & (rows["error"] == "")]
        for _, r in rest.iloc[:: max(1, len(rest) // most)].iterrows():
            poses.append(
                Pose(
                    np.reshape(np.asarray(r["rotation"], dtype=float), (3, 3)),
                    np.array([r["origin_x"], r["origin_y"], r["origin_z"]]),
                )
            )
        return poses
    for _, r in rows.iloc[:: max(1, len(rows) // most)].iterrows():
        for s in ("third", "second", "first"):
            if r[f"{s}_found"]:
                rot = np.array([[r[f"{s}_r{i}{j}"] for j in range(3)] for i in range(3)])
                poses.append(Pose(rot, np.array([r[f"{s}_origin_{a}"] for a in "xyz"])))
                break
    return poses


def _one(args: argparse.Namespace) -> None:
    """One sweep in this (child) process; prints one JSON line of figures."""
    import numpy as np

    from threadmate.contact import Compliance, Mechanics
    from threadmate.geometry import spec_from_designation
    from threadmate.library import Grid, info, load, sweep

    spec = spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False)
    grid = Grid.parse(args.roll, args.pitch, args.phase)
    # The host's speed drifts over minutes on a shared machine, so a query timed once
    # after the sweep can miss the rate the sweep ran at. As a check, a thread of this
    # process (idle while the workers run) times the query at a few rest poses of the
    # grid every SAMPLE_EVERY seconds, to compare with the same poses timed after the
    # sweep. The gauge is built once the workers have started, so that they do not
    # inherit it.
    gauge: dict[str, Any] = {}
    samples: list[float] = []
    done = threading.Event()

    def build_gauge() -> None:
        mech = Mechanics(spec, Compliance(), chord=args.chord)
        picks = np.linspace(0, grid.size - 1, GAUGE_POSES).round().astype(int).tolist()
        gauge["poses"] = [
            mech.settle(*map(float, c)).state.pose for c in grid.configurations(picks)
        ]
        gauge["tolerance"] = mech.tolerance
        gauge["query"] = ReferenceQuery(spec, args.chord)

    def time_gauge() -> float:
        return gauge["query"].cpu_time(gauge["poses"], gauge["tolerance"], repeats=10)

    def sample() -> None:
        while not done.wait(SAMPLE_EVERY):
            if not gauge:
                build_gauge()
            samples.append(time_gauge())

    sampler = threading.Thread(target=sample, daemon=True)
    sampler.start()
    n_tilts = grid.shape[0] * grid.shape[1]
    out = Path(args.out)
    kwargs: dict[str, Any] = {"model": args.model, "workers": args.workers, "chord": args.chord}
    if args.scheduler != "pool":
        kwargs["scheduler"] = args.scheduler
    if args.model == "mechanics":
        kwargs["step"] = args.step
    else:
        kwargs["chunk_size"] = args.chunk_size or min(
            256, max(4, -(-grid.size // (16 * args.workers)))
        )
    start = time.perf_counter()
    sweep(spec, args.roll, args.pitch, args.phase, out=out, **kwargs)
    wall = time.perf_counter() - start
    done.set()
    sampler.join()
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    me = resource.getrusage(resource.RUSAGE_SELF)
    # workers=1 runs in this process: its CPU time is the work's.
    cpu = children.ru_utime + children.ru_stime if args.workers > 1 else me.ru_utime + me.ru_stime
    if args.scheduler != "pool":
        cpu = float("nan")  # the cluster's worker processes are not this process's children
    doc = info(out)
    size = sum(p.stat().st_size for p in out.iterdir())
    to_mb = 1 / 1024  # ru_maxrss is in KiB on Linux
    main_mb = me.ru_maxrss * to_mb
    worker_mb = children.ru_maxrss * to_mb

    # The query time of the same meshes, in this run, at the run's own poses; and the
    # host's rate while the sweep ran over its rate after (the gauge, timed either side
    # of that query).
    rows = load(out)
    if not gauge:
        build_gauge()
    gauge_after = time_gauge()
    q = gauge["query"].cpu_time(_poses(rows, args.model), gauge["tolerance"])
    gauge_after = 0.5 * (gauge_after + time_gauge())
    drift = float(np.mean(samples)) / gauge_after if samples else 1.0
    n = doc["done"]
    print(
        json.dumps(
            {
                "model": args.model,
                "scheduler": args.scheduler,
                "grid": doc["grid"],
                "configurations": n,
                "held_tilts": n_tilts,
                "workers": args.workers,
                "step": args.step,
                "wall_s": wall,
                "cpu_s": cpu,
                "query_us": 1e6 * q,
                "drift": drift,
                "drift_samples": len(samples),
                "qe_per_config_cpu": cpu / n / q,
                "qe_per_config_cpu_drift_scaled": cpu / n / (q * drift),
                "qe_per_config_wall": wall / n / q,
                "ms_per_config_cpu": 1e3 * cpu / n,
                "thesis_grid_wall_s": wall * THESIS_CONFIGURATIONS / n,
                # What the workers' CPU time gives when the cores are not shared with other work.
                "thesis_grid_cpu_bound_s": cpu * THESIS_CONFIGURATIONS / n / args.workers,
                "states": doc["states"],
                "classifications": doc["classifications"],
                "peak_main_mb": main_mb,
                "peak_worker_mb": worker_mb if args.workers > 1 else 0.0,
                "library_mb": size / 2**20,
                "parts": doc["parts"],
            }
        )
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--model", choices=("mechanics", "thesis"), default="mechanics")
    parser.add_argument("--roll", default="-3,2", help="held roll values (default -3,2)")
    parser.add_argument("--pitch", default="1", help="held pitch values (default 1)")
    parser.add_argument("--phase", default=THESIS[2], help="phases (default 0:355:5)")
    parser.add_argument("--workers", default="2", help="comma list of worker counts (default 2)")
    parser.add_argument(
        "--step",
        type=float,
        default=CONTINUATION_STEP,
        help=f"mechanics: continuation step in degrees (default "
        f"{CONTINUATION_STEP:g}, the sweep's)",
    )
    parser.add_argument(
        "--chord",
        type=float,
        default=None,
        help="chord tolerance in inches (default: threadmate's default)",
    )
    parser.add_argument("--chunk-size", type=int, default=None, help="thesis model only")
    parser.add_argument(
        "--scheduler",
        default="pool",
        choices=("pool", "local"),
        help="pool: the process pool (default); local: a Dask LocalCluster",
    )
    parser.add_argument("--keep", default=None, help="keep the libraries under this folder")
    parser.add_argument("--_one", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--out", default=None, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args._one:
        args.workers = int(args.workers)
        _one(args)
        return

    root = Path(args.keep) if args.keep else Path(tempfile.mkdtemp(prefix="bench-sweep-"))
    results = []
    try:
        for w in (int(x) for x in args.workers.split(",")):
            out = root / f"{args.model}-w{w}"
            shutil.rmtree(out, ignore_errors=True)
            cmd = [
                sys.executable,
                __file__,
                "--_one",
                "--model",
                args.model,
                f"--roll={args.roll}",
                f"--pitch={args.pitch}",
                f"--phase={args.phase}",
                "--workers",
                str(w),
                "--out",
                str(out),
                "--step",
                str(args.step),
                "--scheduler",
                args.scheduler,
            ]
            if args.chord is not None:
                cmd += ["--chord", str(args.chord)]
            if args.chunk_size:
                cmd += ["--chunk-size", str(args.chunk_size)]
            proc = subprocess.run(
                cmd, capture_output=True, text=True, env={**os.environ, "PYTHONUNBUFFERED": "1"}
            )
            if proc.returncode:
                sys.exit(f"benchmark run failed:\n{proc.stderr}")
            r = json.loads(proc.stdout.strip().splitlines()[-1])
            results.append(r)
            print(
                f"{r['model']} ({r['scheduler']}): {r['grid']}, {w} worker(s): "
                f"{r['wall_s']:.1f} s wall, "
                f"{r['cpu_s']:.1f} s worker CPU"
            )
            print(
                f"  one yes/no query {r['query_us']:.0f} us; per grid configuration "
                f"{r['ms_per_config_cpu']:.0f} ms CPU = {r['qe_per_config_cpu']:.0f} query "
                f"equivalents (wall on {w}: {r['qe_per_config_wall']:.0f}); target <= 100"
            )
            print(
                f"  host drift (query time while the sweep ran over after, "
                f"{r['drift_samples']} samples): {r['drift']:.3f}; scaled by it "
                f"{r['qe_per_config_cpu_drift_scaled']:.0f} query equivalents"
            )
            print(
                f"  thesis grid (81 held tilts x 72 phases) on {w} worker(s): about "
                f"{r['thesis_grid_wall_s'] / 60:.1f} min at this run's wall rate, "
                f"{r['thesis_grid_cpu_bound_s'] / 60:.1f} min at its CPU rate (cores not "
                "shared)"
            )
            if r["states"]:
                print(
                    f"  states: {r['states']['total']} ({r['states']['by_role']}); "
                    f"rest states of the starts: {r['classifications']}"
                )
            else:
                print(f"  classes: {r['classifications']}")
            print(
                f"  peak memory: sweeping process {r['peak_main_mb']:.0f} MB, largest worker "
                f"{r['peak_worker_mb']:.0f} MB; library {r['library_mb']:.2f} MB in "
                f"{r['parts']} parts"
            )
        if len(results) >= 2:
            base = results[0]
            for r in results[1:]:
                print(
                    f"speed-up {base['workers']} -> {r['workers']} workers: "
                    f"{base['wall_s'] / r['wall_s']:.2f}x"
                )
        print(json.dumps(results))
    finally:
        if not args.keep:
            shutil.rmtree(root, ignore_errors=True)


if __name__ == "__main__":
    main()
