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
node-link JSON export is timed apart.

GraphML, with each state's geometry from the library (``write_graphml(..., library=)``,
as ``threadmate network`` writes it), is written and read back in a fresh process of its
own that loads the library and builds the network first, so that its memory is measured
alone: the resident set before the write, and its peak during the write and during the
read (Linux's ``/proc/self/status``, the peak reset before each through
``/proc/self/clear_refs``; where it cannot be reset the figure is an upper bound, and says
so). Targets (issue 30): the thesis grid written in at most 2 s, the fine grid in at most
30 s and at most 1 GB above the network's own memory. The file is read back with
:func:`threadmate.network.read_graphml` (and, on the thesis grid, with
:func:`networkx.read_graphml` too, which must give the same nodes and edges).

Each time is also given in python-fcl query equivalents (the time over the CPU time of one
yes/no query of the thread pair's meshes, ``_reference.py``, timed in the same run at three
rest states of the mechanics), and beside each figure the host's load (``uptime``'s 1, 5
and 15 minute averages): the machine may be shared.

Run: ``python benchmarks/bench_network.py [--fine-only | --thesis-only]``
"""

from __future__ import annotations

import argparse
import gc
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from _reference import ReferenceQuery

from threadmate.contact import Compliance, Mechanics, blank_row, state_id, state_schema
from threadmate.geometry import spec_from_designation
from threadmate.library import Grid, write_library
from threadmate.network import (
    from_library,
    least_resistance_path,
    read_graphml,
    recommend,
    start_outcomes,
    write_graphml,
    write_node_link,
)

DESIGNATION = "1/4-20 UNC-2A/2B"
#: The grids (held roll, held pitch, phase).
GRIDS = {
    "thesis": ("-4:4:1", "-4:4:1", "0:355:5"),
    "fine": ("-4:4:0.5", "-4:4:0.5", "0:359:1"),
}
#: The GraphML write's targets: seconds, and MB above the network's own memory.
GRAPHML_TARGETS = {"thesis": (2.0, None), "fine": (30.0, 1024.0)}


def spec() -> Any:
    return spec_from_designation(DESIGNATION, point="flat", countersink=False)


def load() -> str:
    """The host's load as ``uptime`` gives it (1, 5 and 15 minute averages)."""
    return "load {:.2f} {:.2f} {:.2f}".format(*os.getloadavg())


class Gauge:
    """The python-fcl yes/no query's CPU time (``_reference.py``) at three rest states."""

    def __init__(self) -> None:
        mech = Mechanics(spec(), Compliance())
        starts = [(0.0, 0.0, 40.0), (2.0, -1.0, 130.0), (-3.0, 2.0, 250.0)]
        self.poses = [mech.settle(*s).state.pose for s in starts]
        self.tolerance = mech.tolerance
        self.query = ReferenceQuery(spec())

    def seconds(self) -> float:
        return self.query.cpu_time(self.poses, self.tolerance, repeats=20)


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
                        engaged=True,  # proved by screwing in, as a sweep's snap is
                        rotation=[1.0, 0, 0, 0, 1.0, 0, 0, 0, 1.0],
                        centre_z=-0.003,
                        n_contacts=1,
                    )
                )
            cid += n_phase
    return pd.DataFrame(rows)


def bench(name: str, workdir: Path) -> Path:
    """The graph stage on the grid ``name``; returns its library."""
    roll, pitch, phase = GRIDS[name]
    grid = Grid.parse(roll, pitch, phase)
    t = time.perf_counter()
    rows = synthetic_rows(grid)
    lib = write_library(rows, workdir / name, spec(), roll, pitch, phase, compliance=Compliance())
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
        f"together {built + answered:.2f} s; {load()}"
    )
    print(
        f"  ({int(out['snapped'].sum())} starts snap within a turn; path of {len(p.path)} "
        f"states, cost {p.cost:.3g} mJ; pick held pitch {rec.best['held_pitch']:+g})"
    )
    t = time.perf_counter()
    write_node_link(g, workdir / f"{name}.json")
    print(f"  export: node-link JSON {time.perf_counter() - t:.2f} s; {load()}")
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"  peak memory of this process {peak:.0f} MB")
    return lib


def _memory(field: str) -> float:
    """A figure of this process's memory from ``/proc/self/status`` (MB): ``VmRSS``
    (resident now) or ``VmHWM`` (its peak)."""
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith(f"{field}:"):
            return int(line.split()[1]) / 1024
    raise RuntimeError(f"no {field} in /proc/self/status")


def _reset_peak() -> bool:
    """Reset this process's peak resident set (``VmHWM``) to its present one."""
    try:
        Path("/proc/self/clear_refs").write_text("5")
    except OSError:
        return False
    return True


def graphml_child(lib: Path, path: Path, compare: bool) -> dict[str, Any]:
    """Build the network of ``lib``, write it to ``path`` and read it back, measuring each
    step's time and memory (run in a process of its own)."""
    g = from_library(lib)
    gc.collect()
    doc: dict[str, Any] = {"nodes": g.number_of_nodes(), "edges": g.number_of_edges()}
    doc["network_mb"] = _memory("VmRSS")
    peaks = [_memory("VmHWM")]  # the build's; ru_maxrss would count the parent's fork too
    doc["reset"] = _reset_peak()
    t, cpu = time.perf_counter(), time.process_time()
    write_graphml(g, path, library=lib)
    doc["write_s"], doc["write_cpu_s"] = time.perf_counter() - t, time.process_time() - cpu
    peaks.append(_memory("VmHWM"))
    doc["write_mb"] = peaks[-1] - doc["network_mb"]
    doc["file_mb"] = path.stat().st_size / 2**20
    del g
    gc.collect()
    before = _memory("VmRSS")
    _reset_peak()
    t = time.perf_counter()
    back = read_graphml(path)
    doc["read_s"] = time.perf_counter() - t
    peaks.append(_memory("VmHWM"))
    doc["read_mb"] = peaks[-1] - before  # the network read included
    doc["read_back"] = [back.number_of_nodes(), back.number_of_edges()]
    del back
    if compare:  # networkx's own reader: the whole document as a tree
        import networkx as nx

        gc.collect()
        before = _memory("VmRSS")
        _reset_peak()
        t = time.perf_counter()
        plain = nx.read_graphml(path)
        doc["nx_read_s"] = time.perf_counter() - t
        peaks.append(_memory("VmHWM"))
        doc["nx_read_mb"] = peaks[-1] - before
        doc["nx_read_back"] = [plain.number_of_nodes(), plain.number_of_edges()]
    doc["peak_mb"] = max(peaks)
    return doc


def bench_graphml(name: str, lib: Path, workdir: Path, gauge: Gauge) -> None:
    """The GraphML write and read of grid ``name``'s network, in a fresh process."""
    command = [sys.executable, __file__, "--graphml-child", str(lib), str(workdir / "n.graphml")]
    if name == "thesis":
        command.append("--compare-nx")
    run = subprocess.run(command, capture_output=True, text=True, check=False)
    if run.returncode:
        raise RuntimeError(f"the GraphML process failed:\n{run.stderr}")
    doc = json.loads(run.stdout.strip().splitlines()[-1])
    after = load()
    q = gauge.seconds()
    seconds, megabytes = GRAPHML_TARGETS[name]
    bound = "" if doc["reset"] else " (an upper bound: the peak could not be reset)"
    mb_target = f", target <= {megabytes:.0f} MB" if megabytes else ""
    print(
        f"  GraphML ({doc['nodes']} nodes, {doc['edges']} edges, geometry included; "
        f"{doc['file_mb']:.0f} MB): one yes/no python-fcl query {1e6 * q:.0f} us CPU"
    )
    print(
        f"    write {doc['write_s']:.2f} s = {doc['write_s'] / q:,.0f} query equivalents "
        f"(CPU {doc['write_cpu_s']:.2f} s), target <= {seconds:g} s; {after}"
    )
    print(
        f"    write's memory above the network's {doc['network_mb']:.0f} MB: "
        f"{doc['write_mb']:.0f} MB{bound}{mb_target}; process peak {doc['peak_mb']:.0f} MB"
    )
    print(
        f"    read back (threadmate.network.read_graphml, a stream) {doc['read_s']:.2f} s = "
        f"{doc['read_s'] / q:,.0f} query equivalents, {doc['read_mb']:.0f} MB with the "
        f"network read; {doc['read_back'][0]} nodes, {doc['read_back'][1]} edges; {after}"
    )
    if "nx_read_s" in doc:
        print(
            f"    networkx.read_graphml {doc['nx_read_s']:.2f} s = "
            f"{doc['nx_read_s'] / q:,.0f} query equivalents, {doc['nx_read_mb']:.0f} MB; "
            f"{doc['nx_read_back'][0]} nodes, {doc['nx_read_back'][1]} edges"
        )
    if (
        doc["read_back"] != [doc["nodes"], doc["edges"]]
        or doc.get("nx_read_back", doc["read_back"]) != doc["read_back"]
    ):
        raise RuntimeError("the GraphML read back is not the network written")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--fine-only", action="store_true")
    group.add_argument("--thesis-only", action="store_true")
    group.add_argument(
        "--graphml-child", nargs=2, metavar=("LIBRARY", "FILE"), help=argparse.SUPPRESS
    )
    parser.add_argument("--compare-nx", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.graphml_child:
        lib, path = map(Path, args.graphml_child)
        print(json.dumps(graphml_child(lib, path, args.compare_nx)))
        return
    gauge = Gauge()
    with tempfile.TemporaryDirectory() as tmp:
        for name in ("thesis", "fine"):
            if (name == "thesis" and args.fine_only) or (name == "fine" and args.thesis_only):
                continue
            lib = bench(name, Path(tmp))
            bench_graphml(name, lib, Path(tmp), gauge)


if __name__ == "__main__":
    main()
