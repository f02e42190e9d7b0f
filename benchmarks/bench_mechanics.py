"""Speed of the mechanics: a rest state, and one simulated turn, in query equivalents.

Run:  python benchmarks/bench_mechanics.py [--n 40] [--starts 3] [--seed 0]

1/4-20 UNC-2A/2B at mean material, default chord (5e-6 in), default compliance, one core.
Costs are reported in python-fcl *query equivalents*: wall time divided by the time of one
yes/no collision query of the same meshes, timed in the same run at the poses the run
produced (each rest pose lifted by the descent's tolerance, where the bodies are free but
close all round, and lowered by it, where they collide: the mean of the two).

- Rest states: ``--n`` fresh drops with roll and pitch uniform in +/-4 degrees and phase
  uniform in 0..360 (target: at most 60 query equivalents on average).
- One turn: ``--starts`` searches of one turn in continuation steps of 5 degrees (the
  library's grid phase), events located to 0.01 degree (target: at most 100 query
  equivalents per grid phase, events included). A search that snaps early is charged
  per grid phase actually turned.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from threadmate.contact import Compliance, Mechanics, search
from threadmate.geometry import Pose, spec_from_designation


def _query_time(mech: Mechanics, poses: list[Pose], repeats: int = 20) -> float:
    """Mean time of one yes/no query at ``poses`` lifted and lowered by the tolerance."""
    eng = mech.engine
    times = []
    for pose in poses:
        for dz in (mech.tolerance, -mech.tolerance):
            moved = pose.translated([0.0, 0.0, dz])
            t = time.perf_counter()
            for _ in range(repeats):
                eng.collides(moved)
            times.append((time.perf_counter() - t) / repeats)
    return float(np.mean(times))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=40, help="rest states (default 40)")
    parser.add_argument("--starts", type=int, default=3, help="one-turn searches (default 3)")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()

    spec = spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False)
    t0 = time.perf_counter()
    mech = Mechanics(spec, Compliance())
    print(f"built in {time.perf_counter() - t0:.2f} s; compliance {mech.compliance}")
    rng = np.random.default_rng(args.seed)
    configs = [(rng.uniform(-4, 4), rng.uniform(-4, 4), rng.uniform(0, 360)) for _ in range(args.n)]
    mech.settle(*configs[0])  # warm caches

    times, queries, steps, classes, poses = [], [], [], {}, []
    unconverged = 0
    for cfg in configs:
        t = time.perf_counter()
        rest = mech.settle(*cfg)
        times.append(time.perf_counter() - t)
        queries.append(rest.queries)
        steps.append(rest.iterations)
        classes[rest.classification] = classes.get(rest.classification, 0) + 1
        unconverged += not rest.balance.get("converged", 1.0)
        poses.append(rest.state.pose)

    turn_times, grid_phases, turn_queries, snaps = [], [], [], []
    for k in range(args.starts):
        roll, pitch = rng.uniform(-3, 3), rng.uniform(-3, 3)
        phase = rng.uniform(0, 360)
        q0 = mech.engine.queries
        t = time.perf_counter()
        run = search(mech, roll, pitch, phase, turns=1.0, step=5.0)
        turn_times.append(time.perf_counter() - t)
        turned = run.snap_turn if run.snap is not None else 360.0
        grid_phases.append(max(turned / 5.0, 1.0))
        turn_queries.append(mech.engine.queries - q0)
        snaps.append(run.snap_turn)
        poses += [s.pose for s in run.states[:: max(1, len(run.states) // 10)]]
        print(
            f"search {k}: start ({roll:.2f}, {pitch:.2f}, {phase:.1f}) "
            f"snap turn {run.snap_turn} events {len(run.events)} "
            f"{turn_times[-1]:.2f} s"
        )

    q = _query_time(mech, poses)
    qe = np.array(times) / q
    print(f"\none yes/no query: {1e6 * q:.0f} us (mean at the run's poses)")
    print(
        f"rest state: mean {1e3 * np.mean(times):.1f} ms = {qe.mean():.1f} query equivalents "
        f"(median {np.median(qe):.1f}, p90 {np.percentile(qe, 90):.1f}, max {qe.max():.1f});"
        f" queries {statistics.mean(queries):.1f}, descent steps "
        f"{statistics.mean(steps):.1f}; target <= 60"
    )
    print(f"rest-state classes: {classes}; not converged: {unconverged} of {len(configs)}")
    per_grid = np.array(turn_times) / np.array(grid_phases) / q
    print(
        f"one turn at 5-degree grid phases: {per_grid.mean():.1f} query equivalents per grid "
        f"phase (per start: {', '.join(f'{v:.0f}' for v in per_grid)}); queries per grid "
        f"phase {np.mean(np.array(turn_queries) / np.array(grid_phases)):.1f}; "
        f"target <= 100"
    )


if __name__ == "__main__":
    main()
