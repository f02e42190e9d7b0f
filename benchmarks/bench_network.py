"""Benchmark of the graph stage: build the network and answer every query of the command line.

Two grids: the thesis's (roll and pitch -4..4 by 1, phase 0..355 by 5: 5,832 states) and
the fine one (roll and pitch -4..4 by 0.5, phase 0..359 by 1: 104,040 states). Targets: the
whole set of queries under 5 s and under 60 s.

The libraries are SYNTHETIC: a real library directory (the library stage's Parquet layout,
schema and metadata, every column of the contact record) filled with made-up but
plausible states (an in-phase window near phase 0 for small tilts, unstable bands, resting
orientations, heights and contact points), because sweeping 104,040 configurations takes
far longer than the graph stage itself. The graph stage's cost depends on the number of
states and edges, not on how the rows were computed.

Each query is timed the way the command line runs it (load the library, build the
network, then answer): ``network`` (build, GraphML, node-link JSON), ``path`` (one path and
the 3 best), ``recommend`` (all starts, with the 6-variant sensitivity study).

Run: ``python benchmarks/bench_network.py [--fine-only | --thesis-only]``
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pyarrow as pa

from threadmate.library import Grid
from threadmate.library._store import FORMAT, library_schema, write_metadata, write_part
from threadmate.network import (
    cost_to_snap,
    from_library,
    k_best_paths,
    least_resistance_path,
    recommend_pitch,
    unsafe_starts,
    write_graphml,
    write_node_link,
)

SPEC = {"units": "in", "pitch": 0.05, "hand": "right", "starts": 1,
        "bolt": {"major": 0.24485, "pitch_diameter": 0.21455, "minor": 0.1887},
        "nut": {"major": 0.25, "pitch_diameter": 0.21995, "minor": 0.2015}}


def synthetic_library(path: Path, grid: Grid, seed: int = 0, chunk: int = 20_000) -> Path:
    """Write a library directory with the real schema and made-up states."""
    rng = np.random.default_rng(seed)
    schema = library_schema()
    n_r, n_p, n_ph = grid.shape
    ids = np.arange(grid.size)
    roll, pitch, phase = grid.configurations(ids).T
    tilt = np.hypot(roll, pitch)
    ph = np.radians(phase)
    window = 6.0 + 2.0 * (1.5 - np.minimum(tilt, 1.5))          # in-phase half-width, deg
    dphase = np.abs((phase + 180.0) % 360.0 - 180.0)
    in_phase = (tilt <= 1.5) & (dphase <= window)
    band = np.sin(ph * 2 + np.radians(roll * 20 - pitch * 15)) > 0.55 - 0.05 * tilt
    cls = np.where(in_phase, "in-phase", np.where(band, "unstable", "stable"))
    quasi = (cls == "stable") & (rng.random(grid.size) < 0.05)
    cls = np.where(quasi, "quasi-stable", cls)
    flat = (cls == "stable") & (np.cos(ph + np.radians(pitch * 30)) > 0)
    final_roll = np.where(flat, 0.0, roll + np.where(cls == "unstable", 4.0, 0.8)
                          * np.sin(ph + 0.3))
    final_pitch = np.where(flat, 0.0, pitch + np.where(cls == "unstable", 3.0, 0.8)
                           * np.cos(ph - 0.2))
    z = 0.0025 * tilt / 4.0 * np.cos(ph - np.radians(roll * 10)) + rng.normal(0, 2e-5,
                                                                               grid.size)
    z = np.where(cls == "in-phase", -0.02, np.where(cls == "unstable", z - 0.005, z))
    meta = {"format": FORMAT, "format_version": 1, "spec": SPEC, "grid": grid.to_dict(),
            "mesh": {"chord": 1e-4}, "contact": {"compliance_z": 0.0, "analyzer": "synthetic"},
            "units": "in", "threadmate_version": "synthetic",
            "note": "synthetic library for benchmarks/bench_network.py"}
    write_metadata(path, meta)
    for part, start in enumerate(range(0, grid.size, chunk)):
        s = slice(start, min(start + chunk, grid.size))
        n = s.stop - s.start
        cols = {}
        for field in schema:
            if pa.types.is_floating(field.type):
                cols[field.name] = np.full(n, np.nan)
            elif pa.types.is_integer(field.type):
                cols[field.name] = np.zeros(n, dtype=np.int64)
            elif pa.types.is_boolean(field.type):
                cols[field.name] = np.zeros(n, dtype=bool)
            else:
                cols[field.name] = np.full(n, "", dtype=object)
        cols.update(config_id=ids[s], roll=roll[s], pitch=pitch[s], phase=phase[s],
                    classification=cls[s], n_contacts=np.full(n, 3),
                    region_combination=np.where(flat[s], "base/surface + base/surface + "
                                                "base/surface", "base/surface + -F/+F + "
                                                "base/surface"),
                    interference=np.where(cls[s] == "unstable", 3e-4, 1e-10),
                    origin_drop=np.full(n, 1e-3), pivot_offset=np.full(n, 0.1),
                    final_roll=final_roll[s], final_pitch=final_pitch[s],
                    final_phase=phase[s], final_origin_z=z[s], first_origin_z=z[s] + 0.002,
                    second_origin_z=z[s] + 0.001, third_origin_z=z[s])
        for st in ("first", "second", "third"):
            cols[f"{st}_found"] = np.ones(n, dtype=bool)
            cols[f"{st}_r22"] = np.cos(np.radians(tilt[s]))
            for i in range(1, 4):
                a = ph[s] + 2.0 * math.pi * i / 3
                cols[f"{st}_c{i}_x"] = 0.11 * np.cos(a)
                cols[f"{st}_c{i}_y"] = 0.11 * np.sin(a)
        write_part(path, part, pa.Table.from_pydict(cols, schema=schema))
    return path


def _timed(label: str, func, times: dict[str, float]):
    t0 = time.perf_counter()
    out = func()
    times[label] = time.perf_counter() - t0
    return out


def bench(name: str, grid: Grid, target: float, workdir: Path) -> bool:
    lib = synthetic_library(workdir / f"lib-{name}", grid)
    t: dict[str, float] = {}
    # threadmate network LIBRARY -o FILE.graphml --json-graph FILE
    g = _timed("network: load + build", lambda: from_library(lib), t)
    _timed("network: GraphML", lambda: write_graphml(g, workdir / f"{name}.graphml"), t)
    _timed("network: node-link JSON", lambda: write_node_link(g, workdir / f"{name}.json"), t)
    _timed("network: unsafe starts", lambda: unsafe_starts(g), t)
    # threadmate path LIBRARY --roll 2 --pitch -1.5 --phase 100 --k 3
    g2 = _timed("path: load + build", lambda: from_library(lib), t)
    p = _timed("path: least-resistance path",
               lambda: least_resistance_path(g2, roll=2, pitch=-1.5, phase=100), t)
    _timed("path: 3 best paths", lambda: k_best_paths(g2, 3, roll=2, pitch=-1.5, phase=100), t)
    # threadmate recommend LIBRARY --roll-spread 2
    g3 = _timed("recommend: load + build", lambda: from_library(lib), t)
    costs = _timed("recommend: cost to snap (all states)", lambda: cost_to_snap(g3), t)
    rec = _timed("recommend: recommendation + sensitivity",
                 lambda: recommend_pitch(g3, roll_spread=2.0), t)
    total = sum(t.values())
    print(f"\n{name}: {grid.describe()}")
    print(f"  {g.number_of_nodes()} states, {g.number_of_edges()} edges, "
          f"{sum(math.isfinite(c) for c in costs.values())} reach the snap")
    for label, sec in t.items():
        print(f"  {label:<42} {sec:8.3f} s")
    print(f"  {'total (every CLI query)':<42} {total:8.3f} s   target < {target:g} s: "
          f"{'PASS' if total < target else 'FAIL'}")
    print(f"  sample path: {len(p.path) - 1} steps, {p.cost:.3g} mJ; recommended pitch "
          f"{rec.pitch:g} deg (margin {rec.margin:.3g} mJ, robust {rec.robust})")
    return total < target


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--thesis-only", action="store_true")
    parser.add_argument("--fine-only", action="store_true")
    args = parser.parse_args()
    ok = True
    with tempfile.TemporaryDirectory(prefix="bench-network-") as tmp:
        if not args.fine_only:
            ok &= bench("thesis", Grid.parse(), 5.0, Path(tmp))
        if not args.thesis_only:
            ok &= bench("fine", Grid.parse("-4:4:0.5", "-4:4:0.5", "0:359:1"), 60.0, Path(tmp))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
