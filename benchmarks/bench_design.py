"""Benchmark of the design stage: the default capture envelope and the default design.

Usage::

    python benchmarks/bench_design.py                      # the design (about half an hour)
    python benchmarks/bench_design.py --what envelope      # the envelope (minutes)
    python benchmarks/bench_design.py --what envelope --src /path/to/other/src   # beside it
    python benchmarks/bench_design.py --json

What is timed is what ``threadmate envelope "1/4-20 UNC-2A/2B"`` and ``threadmate design
"1/4-20 UNC-2A/2B" --force 2:40 --stiffness 0.1:10`` compute (issue 29, item 8: the
envelope of one compliance within 5 minutes, a design over a 2-D bound box within 30, on
this 2-core machine), through the public API with ``--workers`` workers (default 2).

Each run happens in a fresh child process, so that its wall time, its CPU time (its own
and its pool workers', once reaped) and its peak memory are its own. ``--src`` runs the
same in a child whose ``threadmate`` is imported from another source tree (a copy of an
earlier commit's ``src``), one after the other, so that two codes are read in one run.

Stages: the child timestamps the design's progress messages (one before each envelope it
computes: a setting, a robustness case, a case of the look for the setting that holds
best), so the wall time splits by what it was spent on.

Query equivalents: in the same child, after the work, one yes/no python-fcl ``collide`` of
the pair's whole meshes (``_reference.py``) is timed at rest poses of the upright bolt,
and the CPU time is also given in those units. The load average (``/proc/loadavg``) is
read before and after each run: the host is shared.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
DESIGNATION = "1/4-20 UNC-2A/2B"
#: The default design's bounds (``threadmate design``'s defaults).
FORCE, STIFFNESS = (2.0, 40.0), (0.1, 10.0)


def _load() -> str:
    try:
        return " ".join(Path("/proc/loadavg").read_text().split()[:3])
    except OSError:
        return "n/a"


def _stage(text: str) -> str:
    """The stage a progress message opens: a setting, the optimum at the envelope's own
    grid, a robustness case, the look."""
    for prefix in ("setting", "the optimum", "robustness", "most robust"):
        if text.startswith(prefix):
            return prefix.removeprefix("the ")
    return "other"


def _one(args: argparse.Namespace) -> None:
    """One run in this (child) process; prints one JSON line."""
    from _reference import ReferenceQuery

    import threadmate
    from threadmate.contact import Compliance, Mechanics
    from threadmate.design import best_compliance, envelope
    from threadmate.geometry import spec_from_designation

    spec = spec_from_designation(DESIGNATION)
    marks: list[tuple[float, str]] = []
    start = time.perf_counter()
    result: dict[str, Any] = {}
    if args.what == "envelope":
        env = envelope(spec, compliance=Compliance(), workers=args.workers)
        result = {"tolerated_tilt": env.tolerated_tilt, "probes": env.probes}
    else:

        def progress(text: str) -> None:
            marks.append((time.perf_counter() - start, text))

        design = best_compliance(
            spec, force=FORCE, stiffness=STIFFNESS, workers=args.workers, progress=progress
        )
        o = design.optimum
        result = {
            "summary": design.summary_line(),
            "force": o["force"],
            "stiffness": o["stiffness"],
            "tolerated_tilt": o["tolerated_tilt"],
            "settings": len(design.settings),
            "robust_setting": None
            if design.robust_setting is None
            else {k: design.robust_setting[k] for k in ("force", "stiffness", "tolerated_tilt")},
        }
    wall = time.perf_counter() - start
    me = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = me.ru_utime + me.ru_stime + children.ru_utime + children.ru_stime
    stages: dict[str, float] = {}
    ends = [t for t, _ in marks[1:]] + ([wall] if marks else [])  # (an envelope has none)
    for (t, text), end in zip(marks, ends, strict=True):
        stages[_stage(text)] = stages.get(_stage(text), 0.0) + end - t
    mech = Mechanics(spec, Compliance())
    poses = [mech.settle(0.0, 0.0, float(p)).state.pose for p in range(0, 360, 40)]
    query = ReferenceQuery(spec).cpu_time(poses, mech.tolerance)
    print(
        json.dumps(
            {
                "what": args.what,
                "threadmate": str(Path(threadmate.__file__).parent),
                "workers": args.workers,
                "wall_s": wall,
                "cpu_s": cpu,
                "peak_mb": max(me.ru_maxrss, children.ru_maxrss) / 1024,
                "stages_wall_s": stages,
                "envelopes": len(marks),
                "query_us": 1e6 * query,
                "cpu_qe": cpu / query,
                "result": result,
            }
        )
    )


def _run(args: argparse.Namespace, src: str | None) -> dict[str, Any]:
    """One run in a fresh child process (importing ``src`` when given)."""
    env = dict(os.environ)
    if src is not None:
        env["PYTHONPATH"] = os.pathsep.join([src, env.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    before = _load()
    cmd = [sys.executable, __file__, "--child", "--what", args.what, "--workers", str(args.workers)]
    out = subprocess.run(cmd, env=env, check=True, capture_output=True, text=True, cwd=HERE)
    doc = json.loads(out.stdout.strip().splitlines()[-1])
    doc.update(load_before=before, load_after=_load())
    return doc


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--what", choices=("design", "envelope"), default="design")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument(
        "--src", action="append", default=[], help="Another source tree to run beside"
    )
    parser.add_argument("--json", action="store_true")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        _one(args)
        return
    docs = []
    for src in (None, *args.src):
        print(f"bench_design: {args.what} with {src or 'threadmate as imported'}", file=sys.stderr)
        docs.append(_run(args, src))
    if args.json:
        print(json.dumps({"units": {"time": "s", "memory": "MB", "query": "us"}, "runs": docs}))
        return
    for d in docs:
        stages = ", ".join(f"{k} {v:.0f} s" for k, v in d["stages_wall_s"].items())
        print(
            f"{d['what']} ({d['threadmate']}): {d['wall_s']:.0f} s wall ({d['wall_s'] / 60:.1f} "
            f"min), {d['cpu_s']:.0f} s CPU ({d['cpu_qe']:.3g} QE at {d['query_us']:.0f} us), "
            f"peak {d['peak_mb']:.0f} MB, load {d['load_before']} -> {d['load_after']}"
        )
        if stages:
            print(f"  by stage (wall): {stages}; {d['envelopes']} envelopes")
        print(f"  {d['result']}")


if __name__ == "__main__":
    main()
