"""Where a sweep's CPU goes, stage by stage: the figures behind docs/validation.md's
"Where the CPU goes".

Usage::

    python benchmarks/bench_breakdown.py                   # the default run's 25 held tilts
    python benchmarks/bench_breakdown.py --held=0,1.5 --held=-2,1 --workers 1 --json

Each held tilt runs as the sweep runs it (every start phase of ``--phase`` searched, every
snap proved by screwing in), one process per worker, on 1/4-20 UNC-2A/2B at mean material
with its default parts (chamfered point, countersunk nut), default chord and compliance.
The settles (each a descent to a rest state, its first touch included), the
continuation's stages and the collision queries are timed call by call: the methods are
wrapped, not profiled (a profiler's own cost per Python call inflates the Python part
several times). A settle's CPU goes to the stage it serves:

- ``fresh``: a start's rest state, from first contact;
- ``turning``: a continuation step of the search;
- ``bisection``: closing in on a fold or a contact change of the search;
- ``proof``: anything within a snap's proof (the clockwise screw-in), split by the turn
  of the step: ``full`` (the search's step), ``short`` (a step halved where the branch is
  pinched, or closing in on a fold), and whether the descent departed (left the branch);
- ``other``: the snap's window, its click, the tilted settles that look for a branch
  beyond a fold.

A descent of 30 steps or more counts also as ``long`` (the step limit is 60), and the
long ones are told apart by how they end (balanced or arrived at a rest state known
already, at the step limit, or stopped short of it unbalanced: stalled, nothing left to
gain, the trust region spent) and by how many of their steps' trial lowerings were
refused (mostly where, at the step's tilt, the bolt meets the nut above and below at
every height: pinched between the flanks). The proofs' whole cost, their settles and
all else, is printed beside by verdict (engaged, wedged, the torque past its limit,
riding), and so is that of the searches for a rest state at tilts nearby where a turn's
landing climbed (``_tilted``: a wedge is told where none is found). The
collision queries are counted by kind, yes/no (free or colliding) and enumerations (with
the pairs they report), and by the part of
the lowering that asks them (``_lowering``): the bracket, the verification of a kept
lowering, the deepening of a continued one, the nut's material over the bolt.

A diagnostic, not a target: it wraps private methods as they are named today. The host's
load is printed beside the figures (``os.getloadavg``).
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from typing import Any

RUN_HELD = [(float(r), float(p)) for r in range(-2, 3) for p in range(-2, 3)]
LONG = 30


def _verdict(proof: Any) -> str:
    """A proof's verdict in a word: engaged, wedged (no rest state continues its turn),
    torque (the tightening torque passes its limit) or rides."""
    if proof.engaged:
        return "engaged"
    if proof.jammed:
        return "torque" if proof.torque_jam is not None else "wedged"
    return "rides"


def _install(acc: dict[str, Any]) -> None:
    """Wrap the methods whose calls are timed; ``acc`` collects the figures."""
    from threadmate.contact.mechanics import _descent, _lowering, _search, _settle
    from threadmate.contact.scene import _collision

    stack: list[str] = []
    queries = acc["queries"]

    def stage(name: str) -> None:
        cls = _search.Continuation
        inner = getattr(cls, name)

        def wrapped(*args: Any, **kwargs: Any) -> Any:
            # A proof's whole cost (its descents and all else) is timed at the outermost,
            # by its verdict; the search for a rest state beyond a climb, whole.
            outer = name == "prove" and "prove" not in stack
            stack.append(name)
            t = time.process_time()
            out = None
            try:
                out = inner(*args, **kwargs)
                return out
            finally:
                stack.pop()
                cpu = time.process_time() - t
                if outer and out is not None:
                    row = acc["proofs"][_verdict(out)]
                    row[0] += 1
                    row[1] += cpu
                    row[2] += out.turn
                if name == "_tilted":
                    acc["tilted"][0] += 1
                    acc["tilted"][1] += cpu
                    acc["tilted"][2] += out is not None

        setattr(cls, name, wrapped)

    for name in ("prove", "_bisect", "snap_window", "_click", "_tilted"):
        stage(name)

    # Trial lowerings of the descents' steps, and those refused (None).
    trials = [0, 0]
    lowered = _descent._Descent.lowered

    def counted_lowering(self: Any, *args: Any, **kwargs: Any) -> Any:
        out = lowered(self, *args, **kwargs)
        trials[0] += 1
        trials[1] += out is None
        return out

    _descent._Descent.lowered = counted_lowering

    settle = _settle.Mechanics.settle

    def timed_settle(self: Any, *args: Any, **kwargs: Any) -> Any:
        # The whole settle: the first touch is made as the descent is set up.
        t = time.process_time()
        before = list(trials)
        rest = settle(self, *args, **kwargs)
        cpu = time.process_time() - t
        start = kwargs.get("start")
        departed = rest.state.kind == "departed"
        if "prove" in stack:
            turn = abs(rest.phase - start.phase) if start is not None else 0.0
            key = "proof, {} step{}".format(
                "full" if turn >= acc["step"] - 1e-9 else "short",
                ", departed" if departed else "",
            )
        elif start is None:
            key = "fresh"
        elif not stack:
            key = "turning"
        elif stack[-1] == "_bisect":
            key = "bisection"
        else:
            key = "other"
        row = acc["stages"][key]
        row[0] += 1
        row[1] += cpu
        row[2] += rest.iterations
        length = "long" if rest.iterations >= LONG else "short"
        ends = acc["ends"][length]
        if rest.balance.get("converged", 0.0) or rest.balance.get("arrived", 0.0):
            ends[0] += 1
        elif rest.iterations >= _descent.MAX_STEPS:
            ends[1] += 1
        elif rest.state.kind != "departed":
            ends[2] += 1
        ends[3] += trials[0] - before[0]
        ends[4] += trials[1] - before[1]
        if rest.iterations >= LONG:
            row[3] += 1
            row[4] += cpu
        return rest

    _settle.Mechanics.settle = timed_settle

    # Which part of a lowering asks a query (see ``_lowering``): the bracket, the
    # verification of a kept lowering, the deepening of a continued one, the material
    # over the bolt.
    part: list[str] = []

    def lowering(name: str, label: str) -> None:
        inner = getattr(_lowering._Lowering, name)

        def wrapped(*args: Any, **kwargs: Any) -> Any:
            part.append(label)
            try:
                return inner(*args, **kwargs)
            finally:
                part.pop()

        setattr(_lowering._Lowering, name, wrapped)

    for name, label in (
        ("_bracket", "bracket"),
        ("verified", "verification"),
        ("_deepened", "deepening"),
        ("_overhead", "material over"),
    ):
        lowering(name, label)

    pair = _collision.CollisionPair

    def counted(name: str) -> None:
        inner = getattr(pair, name)

        def wrapped(self: Any, *args: Any, **kwargs: Any) -> Any:
            t = time.process_time()
            out = inner(self, *args, **kwargs)
            cpu = time.process_time() - t
            if name == "collides":
                key = "yes/no, colliding" if out else "yes/no, free"
                found = 0
            else:
                key = "enumeration" if name == "pairs" else "enumeration, under material"
                found = len(out)
            row = queries[f"{key} ({part[-1] if part else 'elsewhere'})"]
            row[0] += 1
            row[1] += cpu
            row[2] += found
            return out

        setattr(pair, name, wrapped)

    for name in ("collides", "pairs", "pairs_under_material"):
        counted(name)


#: The worker's own: its mechanics and the figures its wrappers collect.
_WORKER: dict[str, Any] = {}


def _start_worker(step: float) -> None:
    """Set a worker up once: the wrappers, the mechanics, its compile caches warmed."""
    from threadmate.contact import Compliance, Mechanics
    from threadmate.geometry import spec_from_designation

    acc: dict[str, Any] = {
        "step": step,
        "stages": collections.defaultdict(lambda: [0, 0.0, 0, 0, 0.0]),
        "queries": collections.defaultdict(lambda: [0, 0.0, 0]),
        # Per verdict (engaged, wedged, torque, rides): proofs, CPU, degrees turned.
        "proofs": collections.defaultdict(lambda: [0, 0.0, 0.0]),
        # The searches for a rest state beyond a climb: calls, CPU, found.
        "tilted": [0, 0.0, 0],
        # Per length of descent (long, short): balanced (or arrived), at the step limit,
        # stopped short unbalanced; trial lowerings, of which refused.
        "ends": collections.defaultdict(lambda: [0, 0, 0, 0, 0]),
    }
    _install(acc)
    mech = Mechanics(spec_from_designation("1/4-20 UNC-2A/2B"), Compliance())
    mech.settle(1.0, -1.0, 100.0)  # compile caches and lazy set-up outside the figures
    _WORKER.update(acc=acc, mech=mech)


def _held_tilt(held: tuple[float, float], phase: str) -> dict[str, Any]:
    """Run one held tilt in this worker; its figures."""
    from threadmate.contact import PHASE_TOLERANCE
    from threadmate.library import parse_range
    from threadmate.library._held_tilt import states_of_held_tilt

    acc, mech = _WORKER["acc"], _WORKER["mech"]
    for key in ("stages", "queries", "ends", "proofs"):
        acc[key].clear()
    acc["tilted"][:] = [0, 0.0, 0]
    phases = [float(p) for p in parse_range(phase, "phase")]
    roll, pitch = held
    t = time.process_time()
    states_of_held_tilt(
        mech,
        roll,
        pitch,
        phases,
        list(range(len(phases))),
        step=acc["step"],
        phase_tolerance=PHASE_TOLERANCE,
    )
    return {
        "held": {f"{roll:g},{pitch:g}": time.process_time() - t},
        "stages": dict(acc["stages"]),
        "queries": dict(acc["queries"]),
        "ends": dict(acc["ends"]),
        "proofs": dict(acc["proofs"]),
        "tilted": list(acc["tilted"]),
    }


def _merge(parts: list[dict[str, Any]]) -> dict[str, Any]:
    out: dict[str, Any] = {"stages": {}, "queries": {}, "ends": {}, "proofs": {}, "held": {}}
    out["tilted"] = [0, 0.0, 0]
    for part in parts:
        out["held"].update(part["held"])
        out["tilted"] = [a + b for a, b in zip(out["tilted"], part["tilted"], strict=True)]
        for key in ("stages", "queries", "ends", "proofs"):
            for name, row in part[key].items():
                acc = out[key].setdefault(name, [0] * len(row))
                out[key][name] = [a + b for a, b in zip(acc, row, strict=True)]
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--held",
        action="append",
        help="a held tilt, --held=ROLL,PITCH (degrees; repeat for more); "
        "default the run's -2..2 by 1 in both",
    )
    parser.add_argument("--phase", default="0:340:20", help="start phases (default 0:340:20)")
    parser.add_argument("--step", type=float, default=5.0, help="continuation step (degrees)")
    parser.add_argument("--workers", type=int, default=2, help="processes (default 2)")
    parser.add_argument("--json", action="store_true", help="one JSON document")
    args = parser.parse_args()
    held = [tuple(float(v) for v in h.split(",")) for h in args.held] if args.held else RUN_HELD
    load0 = os.getloadavg()
    wall = time.perf_counter()
    # One held tilt at a time to whichever worker is free.
    with ProcessPoolExecutor(
        max(1, args.workers), initializer=_start_worker, initargs=(args.step,)
    ) as pool:
        parts = list(pool.map(_held_tilt, held, [args.phase] * len(held)))
    result = _merge(parts)
    result["wall_s"] = time.perf_counter() - wall
    result["load"] = [list(load0), list(os.getloadavg())]
    result["units"] = {"cpu": "s", "wall_s": "s", "load": "1, 5 and 15 minute averages"}
    total = sum(result["held"].values())
    result["cpu_s"] = total
    if args.json:
        json.dump(result, sys.stdout, indent=1)
        print()
        return
    print(
        f"{len(held)} held tilts, phases {args.phase}: {total:.1f} s of CPU "
        f"({result['wall_s']:.1f} s wall, {args.workers} workers); "
        "load {:.2f} {:.2f} {:.2f} before, {:.2f} {:.2f} {:.2f} after".format(
            *result["load"][0], *result["load"][1]
        )
    )
    print(
        "\nsettles by stage: count, CPU (share of the held tilts' CPU), steps, "
        f"and those of {LONG} steps or more"
    )
    for name, (n, cpu, steps, n_long, cpu_long) in sorted(
        result["stages"].items(), key=lambda kv: -kv[1][1]
    ):
        print(
            f"  {name:30s} {n:6d} {cpu:7.1f} s ({100 * cpu / total:4.1f} %) "
            f"{steps:7d} steps; long {n_long:4d}, {cpu_long:6.1f} s"
        )
    print("  proofs whole (descents and all else), by verdict:")
    for verdict, (n, cpu, turned) in sorted(result["proofs"].items(), key=lambda kv: -kv[1][1]):
        print(
            f"    {verdict:8s} {n:4d} proofs, {cpu:6.1f} s ({100 * cpu / total:4.1f} %), "
            f"{turned / max(n, 1):4.0f} degrees turned on average"
        )
    n, cpu, found = result["tilted"]
    print(
        f"  rest states looked for beyond a climb (tilted settles), whole: {n} times, "
        f"{cpu:.1f} s ({100 * cpu / total:.1f} %), found {found}"
    )
    print(
        f"\nhow descents end (of {LONG} steps or more, and fewer): balanced, at the step "
        "limit, stopped short unbalanced; their trial lowerings, and those refused (pinched)"
    )
    for length in ("long", "short"):
        balanced, limit, stalled, tried, refused = result["ends"].get(length, [0] * 5)
        print(
            f"  {length:6s} {balanced:6d} balanced, {limit:5d} at the limit, {stalled:5d} "
            f"short of it; {tried:7d} trial lowerings, {refused:6d} refused "
            f"({100 * refused / max(tried, 1):.0f} %)"
        )
    print("\ncollision queries: count, CPU (share), pairs reported")
    for name, (n, cpu, pairs) in sorted(result["queries"].items(), key=lambda kv: -kv[1][1]):
        print(f"  {name:46s} {n:7d} {cpu:7.1f} s ({100 * cpu / total:4.1f} %) {pairs:9d} pairs")
    print("\nheld tilts, dearest first (s of CPU)")
    for name, cpu in sorted(result["held"].items(), key=lambda kv: -kv[1]):
        print(f"  ({name}) {cpu:.1f}")


if __name__ == "__main__":
    main()
