"""Benchmark of the sweep stage: wall time, rate per worker, peak memory, speed-up.

Usage::

    python benchmarks/bench_sweep.py                       # thesis grid, 1 and 2 workers
    python benchmarks/bench_sweep.py --workers 2           # thesis grid, 2 workers only
    python benchmarks/bench_sweep.py --max-configs 1000    # a subset, extrapolated
    python benchmarks/bench_sweep.py --grid fine --max-configs 8000 --workers 2

``--grid thesis`` is the thesis's 9 x 9 x 72 = 5,832 configurations (roll and pitch
-4..4 by 1, phase 0..355 by 5); ``--grid fine`` is roll and pitch by 0.5 and phase by 1
(17 x 17 x 360 = 104,040). The pair is 1/4-20 UNC-2A/2B at mean material, at the default
chord tolerance unless ``--chord`` is given. ``--max-configs`` stops the sweep after about
that many configurations (whole chunks) and extrapolates the full grid's time from the
measured rate, saying so.

Each run happens in a fresh child process so that its peak memory is its own: the peak
resident set of the sweeping process (which holds at most the chunks in flight) and of
its largest worker (one analyser: meshes and BVHs) are reported separately, with their
sum as the footprint bound (main + workers x largest worker). Targets (issue 4): the
thesis grid in at most 60 s on 2 cores, peak memory under 2 GB, the fine grid in bounded
memory (the sweeping process's peak does not grow with the grid).
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
import time
from pathlib import Path

GRIDS = {
    "thesis": ("-4:4:1", "-4:4:1", "0:355:5"),
    "fine": ("-4:4:0.5", "-4:4:0.5", "0:359:1"),
}


def _one(args: argparse.Namespace) -> None:
    """One sweep in this (child) process; prints one JSON line of figures."""
    from threadmate.geometry import spec_from_designation
    from threadmate.library import Grid, info, sweep

    spec = spec_from_designation("1/4-20 UNC-2A/2B")
    roll, pitch, phase = GRIDS[args.grid]
    grid = Grid.parse(roll, pitch, phase)
    chunk = args.chunk_size or min(256, max(4, -(-grid.size // (16 * args.workers))))
    max_chunks = None if not args.max_configs else max(1, args.max_configs // chunk)
    out = Path(args.out)
    start = time.perf_counter()
    sweep(spec, roll, pitch, phase, out=out, workers=args.workers, chunk_size=chunk,
          chord=args.chord, max_chunks=max_chunks)
    wall = time.perf_counter() - start
    doc = info(out)
    size = sum(p.stat().st_size for p in out.iterdir())
    to_mb = 1 / 1024  # ru_maxrss is in KiB on Linux
    main_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * to_mb
    worker_mb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * to_mb
    print(json.dumps({
        "grid": args.grid, "grid_size": grid.size, "workers": args.workers,
        "chunk_size": chunk, "done": doc["done"], "wall_s": wall,
        "configs_per_s": doc["done"] / wall,
        "configs_per_s_per_worker": doc["done"] / wall / args.workers,
        "full_grid_s": wall * grid.size / doc["done"],
        "extrapolated": doc["done"] < grid.size,
        "peak_main_mb": main_mb, "peak_worker_mb": worker_mb if args.workers > 1 else 0.0,
        "footprint_mb": main_mb + (args.workers * worker_mb if args.workers > 1 else 0.0),
        "library_mb": size / 2**20, "parts": doc["parts"],
        "classifications": doc["classifications"],
    }))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--grid", choices=sorted(GRIDS), default="thesis")
    parser.add_argument("--workers", default="1,2",
                        help="comma list of worker counts (default 1,2)")
    parser.add_argument("--max-configs", type=int, default=0,
                        help="stop after about this many configurations and extrapolate")
    parser.add_argument("--chord", type=float, default=None,
                        help="chord tolerance in inches (default: threadmate's default)")
    parser.add_argument("--chunk-size", type=int, default=None)
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
            out = root / f"{args.grid}-w{w}"
            shutil.rmtree(out, ignore_errors=True)
            cmd = [sys.executable, __file__, "--_one", "--grid", args.grid, "--workers",
                   str(w), "--out", str(out), "--max-configs", str(args.max_configs)]
            if args.chord is not None:
                cmd += ["--chord", str(args.chord)]
            if args.chunk_size:
                cmd += ["--chunk-size", str(args.chunk_size)]
            proc = subprocess.run(cmd, capture_output=True, text=True, check=True,
                                  env={**os.environ, "PYTHONUNBUFFERED": "1"})
            r = json.loads(proc.stdout.strip().splitlines()[-1])
            results.append(r)
            note = " (extrapolated from the subset)" if r["extrapolated"] else ""
            print(f"{r['grid']} grid ({r['grid_size']} configurations), {w} worker(s), "
                  f"chunks of {r['chunk_size']}: {r['done']} done in {r['wall_s']:.1f} s; "
                  f"{r['configs_per_s']:.1f} configs/s, "
                  f"{r['configs_per_s_per_worker']:.1f} configs/s per worker; "
                  f"full grid {r['full_grid_s']:.0f} s{note}")
            print(f"  peak memory: sweeping process {r['peak_main_mb']:.0f} MB, largest worker "
                  f"{r['peak_worker_mb']:.0f} MB, footprint <= {r['footprint_mb']:.0f} MB; "
                  f"library {r['library_mb']:.1f} MB in {r['parts']} parts")
            print(f"  states: {r['classifications']}")
        if len(results) >= 2:
            base = results[0]
            for r in results[1:]:
                print(f"speed-up {base['workers']} -> {r['workers']} workers: "
                      f"{r['configs_per_s'] / base['configs_per_s']:.2f}x")
        print(json.dumps(results))
    finally:
        if not args.keep:
            shutil.rmtree(root, ignore_errors=True)


if __name__ == "__main__":
    main()
