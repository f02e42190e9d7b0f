"""Speed of the contact stages: ms per configuration per stage and collision queries.

Run:  python benchmarks/bench_contact.py [--n 50] [--seed 0]

1/4-20 UNC-2A/2B at mean material, default chord (5e-6 in), one core. Configurations:
roll and pitch uniform in +/-4 degrees, phase uniform in 0..360. The analyser (meshes and
BVHs) is built once, outside the timing. Target: the three stages of one configuration in
at most 20 ms and 100 collision queries. Each stage's search is timed where the analyser
calls it; the rest of a configuration (exact normals and regions of the contacts, the
interference depth, the classification) is listed apart and included in the total.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from threadmate.contact import ContactAnalyzer, _analyzer
from threadmate.geometry import BoltSpec, NutSpec, ThreadSpec

SPEC = ThreadSpec(
    units="in",
    pitch=0.05,
    bolt=BoltSpec(major=0.24485, pitch_diameter=0.21455, minor=0.1887, root_fillet=0.00625),
    nut=NutSpec(major=0.2500, pitch_diameter=0.21995, minor=0.2015),
)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=50, help="configurations (default 50)")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()

    t0 = time.perf_counter()
    analyzer = ContactAnalyzer(SPEC)
    build = time.perf_counter() - t0
    eng = analyzer.engine
    print(
        f"analyser built in {build:.2f} s: bolt {len(eng.bolt_faces)} triangles, "
        f"nut {len(eng.nut_faces)} triangles"
    )

    rng = np.random.default_rng(args.seed)
    configs = [(rng.uniform(-4, 4), rng.uniform(-4, 4), rng.uniform(0, 360)) for _ in range(args.n)]
    analyzer.analyze(*configs[0])  # warm caches (numpy, the profile's pieces)

    # Each stage's search is timed where the analyser calls it (a turn from one contact is
    # the second stage, from two the third). What is left (exact normals and regions, the
    # interference depth, the classification) is reported apart.
    spent = np.zeros(3)

    def timed(search, stage):
        def run(*args, **kwargs):
            t = time.perf_counter()
            try:
                return search(*args, **kwargs)
            finally:
                spent[stage(args)] += 1e3 * (time.perf_counter() - t)

        return run

    _analyzer.first_contact = timed(_analyzer.first_contact, lambda args: 0)
    _analyzer.turn_to_new_contact = timed(_analyzer.turn_to_new_contact, lambda args: len(args[4]))
    total, stage_ms, queries, stage_q, classes = [], [], [], [], {}
    for cfg in configs:
        spent[:] = 0.0
        t = time.perf_counter()
        result = analyzer.analyze(*cfg)
        total.append(1e3 * (time.perf_counter() - t))
        stage_ms.append(spent.copy())
        queries.append(result.queries)
        stage_q.append([s.queries for s in result.stages])
        classes[result.classification] = classes.get(result.classification, 0) + 1
    total_a, q = np.array(total), np.array(queries)
    sq, sm = np.array(stage_q, dtype=float), np.array(stage_ms)
    print(f"{args.n} configurations (roll, pitch in +/-4 deg, phase 0..360):")
    print(
        f"  total ms/config: mean {total_a.mean():.1f}  median {np.median(total_a):.1f}  "
        f"p90 {np.percentile(total_a, 90):.1f}  max {total_a.max():.1f}  (target <= 20)"
    )
    for k, name in enumerate(("first", "second", "third")):
        print(
            f"  {name:6s} stage search: {sm[:, k].mean():5.1f} ms, "
            f"{sq[:, k].mean():5.1f} queries per configuration"
        )
    print(
        f"  contacts, normals, interference, classification: "
        f"{(total_a - sm.sum(1)).mean():5.1f} ms per configuration"
    )
    print(f"  collision queries/config: mean {q.mean():.1f}  max {q.max()}  (target <= 100)")
    print(f"  classifications: {classes}")


if __name__ == "__main__":
    main()
