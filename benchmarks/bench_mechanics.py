"""Speed of the mechanics: a rest state, and one simulated turn, in query equivalents.

Run:  python benchmarks/bench_mechanics.py [--n 40] [--starts 6] [--seed 0]

1/4-20 UNC-2A/2B at mean material, default chord (5e-6 in), default compliance, one core.
Costs are reported in python-fcl *query equivalents*: CPU time divided by the CPU time of one
yes/no collision query of the same meshes, whole (``_reference.py``), timed in the same run
at the poses the run produced (each rest pose lifted by the descent's tolerance, where the
bodies are free but close all round, and lowered by it, where they collide: the mean of the
two).

- Rest states: ``--n`` fresh drops with roll and pitch uniform in +/-4 degrees and phase
  uniform in 0..360 (target: at most 60 query equivalents on average).
- One turn: ``--starts`` searches of one turn in continuation steps of 5 degrees (the
  library's grid phase), events located to 0.01 degree (target: at most 100 query
  equivalents per grid phase, events included): the computation of
  :func:`threadmate.contact.search`, its start's rest state and its turn timed apart.
  The turn is charged per grid phase actually turned (to the snap, or the whole turn),
  over all starts together; a start already in phase turns nothing and costs only its
  rest state. The figure with the starts' rest states included is printed beside it.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
from _reference import ReferenceQuery

from threadmate.contact import Compliance, Continuation, Mechanics
from threadmate.geometry import spec_from_designation


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=40, help="rest states (default 40)")
    parser.add_argument("--starts", type=int, default=6, help="one-turn searches (default 6)")
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
        t = time.process_time()
        rest = mech.settle(*cfg)
        times.append(time.process_time() - t)
        queries.append(rest.queries)
        steps.append(rest.iterations)
        classes[rest.classification] = classes.get(rest.classification, 0) + 1
        unconverged += not rest.balance.get("converged", 1.0)
        poses.append(rest.state.pose)

    start_times, turn_times, grid_phases, turn_queries = [], [], [], []
    for k in range(args.starts):
        roll, pitch = rng.uniform(-3, 3), rng.uniform(-3, 3)
        phase = rng.uniform(0, 360)
        t = time.process_time()
        start = mech.settle(roll, pitch, phase).state
        start_times.append(time.process_time() - t)
        q0 = mech.engine.queries
        t = time.process_time()
        legs, events, states = [], [], []
        if start.classification != "in-phase":  # as search() does
            walk = Continuation(mech, roll, pitch, step=5.0, phase_tolerance=0.01)
            legs, events, states = walk.advance(start, phase, 360.0)
        turn_times.append(time.process_time() - t)
        turn_queries.append(mech.engine.queries - q0)
        snap = next((leg for leg in legs if leg.kind == "snap"), None)
        turned = 0.0 if start.classification == "in-phase" else 360.0
        if snap is not None:
            turned = (snap.after.phase - phase) % 360.0
        grid_phases.append(turned / 5.0)
        poses += [s.pose for s in [start, *states][:: max(1, len(states) // 10)]]
        print(
            f"search {k}: start ({roll:.2f}, {pitch:.2f}, {phase:.1f}) {start.classification}; "
            f"turned {turned:.2f} deg, events {len(events)}, {turn_times[-1]:.2f} s"
        )

    q = ReferenceQuery(spec).cpu_time(poses, mech.tolerance, repeats=20)
    qe = np.array(times) / q
    print(f"\none yes/no query: {1e6 * q:.0f} us (mean at the run's poses)")
    print(
        f"rest state: mean {1e3 * np.mean(times):.1f} ms = {qe.mean():.1f} query equivalents "
        f"(median {np.median(qe):.1f}, p90 {np.percentile(qe, 90):.1f}, max {qe.max():.1f});"
        f" queries {statistics.mean(queries):.1f}, descent steps "
        f"{statistics.mean(steps):.1f}; target <= 60"
    )
    print(f"rest-state classes: {classes}; not converged: {unconverged} of {len(configs)}")
    phases_turned = sum(grid_phases)
    per_start = [
        f"{t / g / q:.0f}" if g > 0 else "in phase"
        for t, g in zip(turn_times, grid_phases, strict=True)
    ]
    print(
        f"one turn at 5-degree grid phases: {sum(turn_times) / phases_turned / q:.1f} query "
        f"equivalents per grid phase over {phases_turned:.0f} grid phases turned (per start: "
        f"{', '.join(per_start)}); queries per grid phase "
        f"{sum(turn_queries) / phases_turned:.1f}; target <= 100; with the starts' rest "
        f"states {(sum(turn_times) + sum(start_times)) / phases_turned / q:.1f}"
    )


if __name__ == "__main__":
    main()
