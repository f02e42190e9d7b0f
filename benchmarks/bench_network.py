"""Benchmark of the graph stage: build the network and answer every query of the command line.

Two grids: the thesis's (held roll and pitch -4..4 by 1, phase 0..355 by 5: 5,832 starts)
and a fine one (roll and pitch -4..4 by 0.5, phase 0..359 by 1: 104,040 starts). Targets:
the whole set of queries under 5 s and under 60 s, memory bounded.

The libraries are SYNTHETIC: real library directories written by the public
:func:`threadmate.library.write_library` (the Parquet layout, schema and metadata of a
mechanics library, every column of ``threadmate.contact.STATE_COLUMNS``) filled with
states shaped like a real sweep's: per start a first contact, a state passed on the way
and the rest state (about 3 rows per start, as the real sweeps give: 235 rows for 72
starts), turning edges joining each start to the next phase's, one snap per held tilt (at
a phase that depends on the tilt) and a never-snapping cycle for the largest tilts.
Sweeping 104,040 configurations would take days; the graph stage's cost depends on the
number of states and edges, not on how they were computed.

Timed: loading the library and building the network once, then every query of the
command line on it (every start's outcome: its cost to the snap, whether it snaps within a
turn, whether it passes an unstable transition; one path; the recommendation). The
exports (GraphML, node-link JSON) are timed apart: they are file writing, and networkx's
GraphML writer (ElementTree) dominates them.

Run: ``python benchmarks/bench_network.py [--fine-only | --thesis-only]``
"""

from __future__ import annotations

import argparse
import resource
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

from threadmate.contact import Compliance, blank_row, state_id, state_schema
from threadmate.geometry import spec_from_designation
from threadmate.library import Grid, write_library
from threadmate.network import (
    from_library,
    least_resistance_path,
    recommend,
    start_outcomes,
    write_graphml,
    write_node_link,
)


def synthetic_rows(grid: Grid) -> pd.DataFrame:
    """About three states per start (see the module docstring)."""
    blank = blank_row(state_schema())
    rows = []
    n_phase = len(grid.phase)
    cid = 0
    for roll in grid.roll:
        for pitch in grid.pitch:
            tilt = float(np.hypot(roll, pitch))
            snap_at = int((tilt * 37 + 11) % n_phase)
            cycle = tilt > 5.0  # the largest tilts never snap: a cycle
            serial = 0
            ids = []
            for j, phase in enumerate(grid.phase):
                first = state_id(roll, pitch, phase, serial)
                passed = state_id(roll, pitch, phase, serial + 1)
                start = state_id(roll, pitch, phase, serial + 2)
                serial += 3
                ids.append(start)
                z = 0.002 * np.cos(np.radians(phase)) + 1e-4 * tilt
                common = dict(
                    blank,
                    config_id=cid + j,
                    held_roll=roll,
                    held_pitch=pitch,
                    phase=phase,
                    roll=roll * 0.6,
                    pitch=pitch * 0.6,
                    rotation=[1.0, 0, 0, 0, 1.0, 0, 0, 0, 1.0],
                    centre_z=z,
                    origin_z=z,
                    potential=10 * z,
                    n_contacts=2,
                    region_combination="base/surface + +F/surface",
                    contact_regions=["base/surface", "+F/surface"],
                    contact_forces=[6.0, 4.0],
                    contact_points=[0.1, 0, 0, -0.1, 0, 0],
                    contact_normals=[0, 0, 1.0, 0, 0, 1.0],
                )
                settling = dict(
                    classification="unstable",
                    transition="settling",
                    transition_label="unstable",
                    transition_turn=0.0,
                    work_friction=0.0,
                    work_potential=0.0,
                    drop=5e-4,
                )
                for sid, role, nxt, lift in (
                    (first, "first-contact", passed, 1e-3),
                    (passed, "passed", start, 5e-4),
                ):
                    rows.append(
                        dict(
                            common,
                            **settling,
                            state_id=sid,
                            role=role,
                            centre_z=z + lift,
                            next_id=nxt,
                        )
                    )
                rows.append(
                    dict(
                        common,
                        state_id=start,
                        role="start",
                        classification="quasi-stable",
                        driver_torque=0.005,
                        friction_torque=0.004,
                    )
                )
            snap = state_id(roll, pitch, grid.phase[snap_at] + 2.0, serial)
            n_start = len(rows) - 3 * n_phase
            for j in range(n_phase):
                row = rows[n_start + 3 * j + 2]
                if j == snap_at and not cycle:
                    row.update(
                        next_id=snap,
                        transition="snap",
                        transition_label="unstable",
                        transition_turn=2.0,
                        work_friction=0.35,
                        work_potential=0.0,
                        torque_peak=0.005,
                        drop=0.003,
                    )
                else:
                    step = (grid.phase[(j + 1) % n_phase] - grid.phase[j]) % 360.0
                    row.update(
                        next_id=ids[(j + 1) % n_phase],
                        transition="turning",
                        transition_label="quasi-stable",
                        transition_turn=step,
                        work_friction=0.07 * step,
                        work_potential=0.001,
                        torque_peak=0.005,
                        drop=0.0,
                    )
            if not cycle:
                rows.append(
                    dict(
                        blank,
                        config_id=cid + snap_at,
                        state_id=snap,
                        held_roll=roll,
                        held_pitch=pitch,
                        phase=(grid.phase[snap_at] + 2.0) % 360.0,
                        role="after-jump",
                        classification="in-phase",
                        rotation=[1.0, 0, 0, 0, 1.0, 0, 0, 0, 1.0],
                        centre_z=-0.003,
                        n_contacts=1,
                    )
                )
            cid += n_phase
    return pd.DataFrame(rows)


def bench(name: str, roll: str, pitch: str, phase: str, workdir: Path) -> None:
    spec = spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False)
    grid = Grid.parse(roll, pitch, phase)
    t = time.perf_counter()
    rows = synthetic_rows(grid)
    lib = write_library(rows, workdir / name, spec, roll, pitch, phase, compliance=Compliance())
    made = time.perf_counter() - t
    print(f"{name}: {grid.size} starts, {len(rows)} states (synthetic, written in {made:.1f} s)")
    del rows
    t = time.perf_counter()
    g = from_library(lib)
    built = time.perf_counter() - t
    t = time.perf_counter()
    out = start_outcomes(g)  # cost to the snap of every start, never-snapping, unstable
    p = least_resistance_path(g, grid.roll[1], grid.pitch[1], grid.phase[3])
    rec = recommend(g, roll_spread=2.0)
    answered = time.perf_counter() - t
    print(
        f"  build {built:.2f} s ({g.number_of_nodes()} nodes, {g.number_of_edges()} "
        f"edges); every start's outcome, one path, the recommendation {answered:.2f} s; "
        f"together {built + answered:.2f} s"
    )
    print(
        f"  ({int(out['snapped'].sum())} starts snap within a turn; path of {len(p.path)} "
        f"states, cost {p.cost:.3g} mJ; pick held pitch {rec.best['held_pitch']:+g})"
    )
    t = time.perf_counter()
    write_graphml(g, workdir / f"{name}.graphml")
    graphml = time.perf_counter() - t
    t = time.perf_counter()
    write_node_link(g, workdir / f"{name}.json")
    print(f"  export: GraphML {graphml:.2f} s, node-link JSON {time.perf_counter() - t:.2f} s")
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"  peak memory of this process {peak:.0f} MB")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--fine-only", action="store_true")
    group.add_argument("--thesis-only", action="store_true")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        if not args.fine_only:
            bench("thesis", "-4:4:1", "-4:4:1", "0:355:5", Path(tmp))
        if not args.thesis_only:
            bench("fine", "-4:4:0.5", "-4:4:0.5", "0:359:1", Path(tmp))


if __name__ == "__main__":
    main()
