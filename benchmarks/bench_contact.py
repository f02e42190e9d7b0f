"""Speed of the contact stages: ms per configuration per stage and collision queries.

Run:  python benchmarks/bench_contact.py [--n 50] [--seed 0]

1/4-20 UNC-2A/2B at mean material, default chord (5e-6 in), one core. Configurations:
roll and pitch uniform in +/-4 degrees, phase uniform in 0..360. The analyser (meshes and
BVHs) is built once, outside the timing. Target: the three stages of one configuration in
at most 20 ms and 100 collision queries.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from threadmate.contact import ContactAnalyzer
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
    print(f"analyser built in {build:.2f} s: bolt {len(eng.bolt_faces)} triangles, "
          f"nut {len(eng.nut_faces)} triangles")

    rng = np.random.default_rng(args.seed)
    configs = [(rng.uniform(-4, 4), rng.uniform(-4, 4), rng.uniform(0, 360))
               for _ in range(args.n)]
    analyzer.analyze(*configs[0])  # warm caches (sector managers, numpy)
    total, queries, stage_q, classes = [], [], [], {}
    for cfg in configs:
        t = time.perf_counter()
        result = analyzer.analyze(*cfg)
        total.append(1e3 * (time.perf_counter() - t))
        queries.append(result.queries)
        stage_q.append([s.queries for s in result.stages])
        classes[result.classification] = classes.get(result.classification, 0) + 1
    total_a, q = np.array(total), np.array(queries)
    sq = np.array(stage_q, dtype=float)
    # Stage time is apportioned by its share of the queries (each stage is almost all
    # collision queries); the rest (contacts, normals, interference) is listed apart.
    per_query = total_a / np.maximum(q, 1)
    stage_ms = sq * per_query[:, None]
    print(f"{args.n} configurations (roll, pitch in +/-4 deg, phase 0..360):")
    print(f"  total ms/config: mean {total_a.mean():.1f}  median {np.median(total_a):.1f}  "
          f"p90 {np.percentile(total_a, 90):.1f}  max {total_a.max():.1f}")
    for k, name in enumerate(("first", "second", "third")):
        print(f"  {name:6s} stage: ~{stage_ms[:, k].mean():5.1f} ms, "
              f"{sq[:, k].mean():5.1f} queries per configuration")
    print(f"  collision queries/config: mean {q.mean():.1f}  max {q.max()}  "
          f"(target <= 100; ms target <= 20)")
    print(f"  classifications: {classes}")


if __name__ == "__main__":
    main()
